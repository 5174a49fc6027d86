"""A floating plate: rods tied at their ends to a rigid plate with mass and inertia that nothing
else holds (issue 24 item 4; input/floating_plate.nml; docs/theory/ph_director.md, "Rigid
bodies on ends").

    floating_plate.py free_flight   three rods on the plate, pushed for 2 ms at one rod's free
                                    end, then flying: energy and momenta of rods and plate
                                    constant after the push, the linear momentum equal to the
                                    push's impulse (the midpoint sum of its time function,
                                    computed here), the tied ends' distances constant (a rigid
                                    plate)
    floating_plate.py axial         three steel rods standing on the ground (clamped), the plate
                                    on top, gravity switched on at t = 0: the plate rings on the
                                    rods at the frequency of a mass on n bars in parallel,
                                    beta tan(beta) = n rho A L / M, omega = beta c / L (exact for
                                    axial waves in the bars), and about the static sag M g L /
                                    (n E A)

What the theory says (src/formulations/ph_director/ph_director_body.f90, src/system/
tie_coupling.F90 float_plate): the plate is a body in director form on the first rod's tied
end, and the other ends are tied to that end by rigid joints that keep their reference offsets;
the joints do no work and keep linear and angular momentum, the body's energy and momenta are
exact in the midpoint step, so without loads the bundle keeps all of them to the Newton
residual.
"""
import math
import os
import sys

import numpy as np
from scipy.optimize import brentq

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

RODS = ("r1", "r2", "r3")


def free_flight(args, checks):
    text = rs.read_example(args.source, "floating_plate.nml")
    path = rs.run(args, text, "free_flight")
    r = {name: rs.rod(path, name) for name in RODS}
    t = r["r1"]["time"]
    dt = rs.number(text, "time", "dt")
    force = np.array(rs.numbers(text, "load", "force"))
    t_off = rs.number(text, "load", "t_off")
    after = int(np.searchsorted(t, t_off + 0.5 * dt))
    # The push's impulse as the midpoint rule takes it: h sum f(t_mid) F over the steps.
    mids = np.arange(0.0, t_off - 0.5 * dt, dt) + 0.5 * dt
    impulse = dt * float(np.sum(rs.time_function("pulse", mids, 0.0, t_off))) * force
    energy = sum(r[n]["series/energy/total"] for n in RODS)
    linear = sum(r[n]["series/momentum/linear"] for n in RODS)
    angular = sum(r[n]["series/momentum/angular"] for n in RODS)
    ends = [r[n]["position"][:, -1, :] for n in RODS]
    distances = np.array([np.linalg.norm(ends[i] - ends[j], axis=1)
                          for i, j in ((0, 1), (0, 2), (1, 2))])
    drift = float(np.max(np.abs(energy[after:] - energy[after])) / energy[after])
    p_error = float(np.max(np.abs(linear[after:] - impulse)))
    l_drift = float(np.max(np.abs(angular[after:] - angular[after])))
    rigid = float(np.max(np.abs(distances - distances[:, :1])))
    print(f"info: after the push (t = {t[after]:.4f} s): H = {energy[after]:.9e} J, drift "
          f"{drift:.2e}; p = {linear[-1]} against the impulse {impulse}; |l| = "
          f"{np.linalg.norm(angular[after]):.3e}, drift {l_drift:.2e}; tied ends' distances "
          f"kept to {rigid:.2e} m")
    # The energy after the push: the Newton tolerance's share (measured 2e-12 at 1e-12).
    checks.check("free flight: relative energy drift after the push", drift, 1e-10)
    # p = the impulse, to the Newton residual (measured 4e-18 against p = 1e-3).
    checks.check("free flight: max |p - impulse| (kg m/s)", p_error, 1e-16)
    # l after the push (measured 2e-18 against |l| = 9e-6).
    checks.check("free flight: max |l - l(after the push)| (kg m^2/s)", l_drift, 1e-16)
    # The plate is rigid: the ends tied to it keep their distances (measured 7e-18 m).
    checks.check("free flight: tied ends' distances, largest change (m)", rigid, 1e-16)
    checks.check("free flight: it moved (-kinetic energy at the end, J)",
                 -float(sum(r[n]["series/energy/kinetic"][-1] for n in RODS)), -1e-3)


def axial(args, checks):
    text = rs.read_example(args.source, "floating_plate.nml")
    mass, length, radius, modulus, density = 0.5, 0.3, 0.001, 2e11, 7800.0
    text = text.replace("E = 2e9, nu = 0.3, density = 1000.0",
                        f"E = {modulus:g}, nu = 0.3, density = {density:g}")
    text = rs.set_variable(text, "plate", "mass", str(mass))
    text = rs.set_variable(text, "plate", "centre", "0.0066666666666667, 0.0066666666666667, 0.3")
    text = rs.set_variable(text, "plate", "inertia_products", "0, 0, 0")
    text = text[:text.index("&load")] + """&load where = 'gravity', acceleration = 0, 0, -9.81 /
"""
    for n in RODS:
        text += f"&bc rod = '{n}', end = 'start', kind = 'clamped' /\n"
    text = rs.set_variable(text, "time", "t_end", "0.01")
    text = rs.set_variable(text, "time", "dt", "1e-5")
    text = rs.set_variable(text, "solver", "newton_atol", "1e-13")
    path = rs.run(args, text, "axial")
    r = rs.rod(path, "r1")
    t = r["time"]
    z = r["position"][:, -1, 2] - length
    area = math.pi * radius**2
    rod_mass = density * area * length
    beta = brentq(lambda b: b * math.tan(b) - len(RODS) * rod_mass / mass, 1e-6, math.pi / 2 - 1e-9)
    omega = beta * math.sqrt(modulus / density) / length
    sag = (mass + len(RODS) * rod_mass / 2) * 9.81 * length / (len(RODS) * modulus * area)
    # The period from the upward crossings of the mean over whole periods.
    mean = 0.5 * (z.max() + z.min())
    rising = np.where((z[:-1] < mean) & (z[1:] >= mean))[0]
    crossings = t[rising] + (mean - z[rising]) / (z[rising + 1] - z[rising]) * (t[rising + 1] - t[rising])
    period = float(np.mean(np.diff(crossings)))
    measured = 2 * math.pi / period
    print(f"info: {len(crossings)} upward crossings; omega {measured:.3f} rad/s against "
          f"beta c / L = {omega:.3f} rad/s (beta = {beta:.6f}); mean sag {-mean * 1e9:.2f} nm "
          f"against (M + n m_rod / 2) g L / (n E A) = {sag * 1e9:.2f} nm")
    checks.check("axial: crossings seen - 4 (at least 5 periods)", -(len(crossings) - 4), 0)
    # Against the exact frequency of a mass on bars: the midpoint rule's period error
    # (omega h)^2 / 12 = 1.0e-4 (measured 1.02e-4).
    checks.check("axial: |omega / (beta c / L) - 1|", abs(measured / omega - 1), 2e-3)
    # Against the midpoint rule's own frequency of that oscillator, (2 / h) atan(omega h / 2):
    # what is left is the quadratic elements' axial error and the crossings' interpolation
    # (measured 1.4e-6).
    discrete = 2.0 / 1e-5 * math.atan(omega * 1e-5 / 2.0)
    print(f"info: the midpoint rule's frequency {discrete:.3f} rad/s")
    checks.check("axial: |omega / ((2 / h) atan(omega_exact h / 2)) - 1|",
                 abs(measured / discrete - 1), 5e-5)
    # The mean deflection: the static sag of the mass and half the rods' own weight (measured
    # 6.6e-6; the higher axial modes ring about it).
    checks.check("axial: |mean sag / static sag - 1|", abs(-mean / sag - 1), 1e-4)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["free_flight", "axial"])
    args = parser.parse_args()
    checks = rs.Checks()
    {"free_flight": free_flight, "axial": axial}[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
