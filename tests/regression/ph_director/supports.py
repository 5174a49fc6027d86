"""Supports and loads of ph_director (issue 26 item 2; docs/theory/ph_director.md "Supports
and loads").

    supports.py pinned    the pinned-pinned column (input/pinned_column.nml): the frequency of
                          its free vibration against the Euler-Bernoulli (pi/L)^2 sqrt(EI/rhoA),
                          the pinned positions held exactly, the energy balance at round-off
    supports.py follower  the follower cantilever of seed 002 §4.1 (input/se3_cantilever.nml at
                          slenderness 10) on ph_director at 4, 8, 16 quadratic elements against
                          se3_pg at 32, 64, 128 elements (Richardson-extrapolated): the tip
                          agrees within discretization and the difference falls with the mesh
    supports.py follower_balance  the flying spaghetti (methods §6.1) with its tip loads as
                          follower loads: H_{n+1} - H_n = W_n at round-off with W_n computed
                          here from the stored directors
    supports.py rigid     &rod rigid = 'EA' (inextensible but shearable): a short cantilever's
                          tip deflection under a small tip force against Timoshenko's
                          P L^3/(3 EI) + P L/(k GA); 'kirchhoff' + rigid = 'EA' drops the shear
                          term; the plan names the multipliers

Every closed form is computed here from the scene's parameters, never read from the program.
"""
import math
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402


# ---- pinned ----------------------------------------------------------------------------------

def section_constants(text):
    """EI and rhoA of a scene's circular section (radius, E, density)."""
    radius = rs.number(text, "rod", "radius")
    young = rs.number(text, "rod", "E")
    density = rs.number(text, "rod", "density")
    return young * math.pi * radius**4 / 4, density * math.pi * radius**2


def mean_period(t, y, after):
    """The mean period of y(t) after `after`: the upward zero crossings (linear interpolation
    between the samples), first to last, over their count. A component of the third mode
    (1/243 of the first) shifts each crossing by a bounded amount, so the error of the mean
    falls as 1 / (number of periods)."""
    k = np.nonzero((y[:-1] < 0) & (y[1:] >= 0) & (t[:-1] > after))[0]
    crossings = t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k])
    return (crossings[-1] - crossings[0]) / (crossings.size - 1), crossings.size - 1


def pinned(args, checks):
    """The pinned-pinned column vibrates at omega_1 = (pi/L)^2 sqrt(EI/rhoA) (Euler-Bernoulli;
    rotary inertia and shear lower it by 2e-5 at r/L = 2e-3). The midpoint rule's own frequency
    for a linear oscillator is (2/h) atan(omega h/2), 3.3e-4 below omega at h = T/100; the
    measured one is compared with both (acceptance: 0.5 % of omega_1). Measured on the Release
    build: 2.4e-4 below omega_1, 9.0e-5 above the midpoint rule's (the third mode's share and
    the mesh); bounds 2e-3 and 1e-3. The pinned positions are held exactly, the end directors
    turn (directors free), and the energy balance holds at round-off: after the pulse, H stays
    constant (no work: the held positions do none). H is tiny (8e-12 J for this linear motion)
    and its rounding is that of the positions (1 m) times the forces: measured 3.5e-10 of max H
    (3e-21 J) for the balance error and 3.7e-10 for the drift of H after the pulse; bound 1e-8."""
    text = rs.read_example(args.source, "pinned_column.nml")
    bending, line_mass = section_constants(text)
    length = rs.number(text, "rod", "length")
    h = rs.number(text, "time", "dt")
    t_off = rs.number(text, "load", "t_off")
    omega = (math.pi / length)**2 * math.sqrt(bending / line_mass)
    omega_h = 2 / h * math.atan(omega * h / 2)
    r = rs.rod(rs.run(args, text, "pinned"), "column")
    t = r["time"]
    middle = r["position"].shape[1] // 2
    y = r["position"][:, middle, 1]
    period, count = mean_period(t, y, t_off)
    measured = 2 * math.pi / period
    print(f"info: omega_1 = {omega:.6f} rad/s (midpoint rule: {omega_h:.6f}); measured "
          f"{measured:.6f} over {count} periods, amplitude {np.max(np.abs(y)):.3e} m")
    checks.check("|omega - omega_1| / omega_1 (Euler-Bernoulli, pinned-pinned)",
                 abs(measured - omega) / omega, 2e-3)
    checks.check("|omega - (2/h) atan(omega_1 h/2)| / omega_1 (the midpoint rule's frequency)",
                 abs(measured - omega_h) / omega, 1e-3)
    held = max(np.max(np.abs(r["position"][:, 0, :] - r["position"][0, 0, :])),
               np.max(np.abs(r["position"][:, -1, :] - r["position"][0, -1, :])))
    checks.check("pinned positions: max |phi - phi(0)| at both ends", held, 0.0)
    turn = np.max(np.abs(r["directors"][:, 0, :, :] - r["directors"][0, 0, :, :]))
    print(f"info: largest change of a start director: {turn:.3e}")
    checks.check("the start directors turn: 1e-9 / max |d - d(0)|", 1e-9 / turn, 1.0)
    total = r["series/energy/total"]
    checks.check("max_n |balance_error_n| / max H",
                 np.max(np.abs(r["series/energy/balance_error"])) / np.max(total), 1e-8)
    free = total[t > t_off + h]
    checks.check("after the pulse: max |H_n - H_last| / H_last", np.max(np.abs(free - free[-1]))
                 / free[-1], 1e-8)


# ---- follower ------------------------------------------------------------------------------

#: input/se3_cantilever.nml at slenderness 10: L = 1000, square section of side 100.
CANTILEVER_LENGTH, CANTILEVER_SIDE = 1000.0, 100.0


def follower_cantilever(args, formulation, n_elements):
    """The tip position (t = 1) of input/se3_cantilever.nml at slenderness 10 (its follower
    tip moment 0.5 pi EI / L about d2 and force 0.5 pi EI / L^2 along d2) on `formulation`
    with n_elements (ph_director: degree 2, 2-point Gauss), Newton tolerance 1e-8."""
    bending = CANTILEVER_SIDE**4 / 12.0
    moment = 0.5 * math.pi * bending / CANTILEVER_LENGTH
    text = rs.read_example(args.source, "se3_cantilever.nml")
    edits = [("rod", "width", repr(CANTILEVER_SIDE)), ("rod", "height", repr(CANTILEVER_SIDE)),
             ("rod", "n_elements", str(n_elements)), ("solver", "newton_atol", "1e-8"),
             ("load", "force", rs.vector((0.0, moment / CANTILEVER_LENGTH, 0.0))),
             ("load", "moment", rs.vector((0.0, moment, 0.0)))]
    if formulation == "ph_director":
        edits += [("rod", "formulation", "'ph_director'"), ("rod", "degree", "2"),
                  ("rod", "n_gauss", "2")]
    for group, variable, value in edits:
        text = rs.set_variable(text, group, variable, value)
    r = rs.rod(rs.run(args, text, f"follower_{formulation}_{n_elements}"), "cantilever")
    return r["position"][-1, -1]


def follower(args, checks):
    """A follower end force (and moment) on a cantilever: ph_director against se3_pg on the
    locking test of seed 002 §4.1 (both statics; the tip turns out of plane by about 90
    degrees). se3_pg converges with order 2 (checked here: the ratio of its successive tip
    differences, 32/64/128 elements, measured 4.000), so its Richardson extrapolation
    x_se3 = x_128 + (x_128 - x_64)/3 is the reference; ph_director (p = 2) at 4, 8, 16 elements
    differs from it by 5.8e-4 L, 3.5e-5 L, 2.2e-6 L (measured on the Release build; a factor
    16 per halving, order 4 as the elastica's, tests/regression/ph_director/elastica.py), and
    from se3_pg's own 128-element tip by 8.0e-6 L, which is mostly se3_pg's discretization
    error (its 64-to-128 change is 1.4e-5 L). Bounds: the difference falls by a factor 8 or
    more per mesh halving, 2e-5 L at 16 elements, 1e-4 L from se3_pg at 128."""
    se3 = {n: follower_cantilever(args, "se3_pg", n) for n in (32, 64, 128)}
    ratio = np.linalg.norm(se3[32] - se3[64]) / np.linalg.norm(se3[64] - se3[128])
    reference = se3[128] + (se3[128] - se3[64]) / 3.0
    print(f"info: se3_pg tip at 128 elements {se3[128]}, extrapolated {reference}; "
          f"successive difference ratio {ratio:.3f}")
    checks.check("se3_pg order 2: |ratio of successive tip differences - 4|", abs(ratio - 4.0),
                 0.5)
    errors = {}
    for n in (4, 8, 16):
        tip = follower_cantilever(args, "ph_director", n)
        errors[n] = np.linalg.norm(tip - reference) / CANTILEVER_LENGTH
        print(f"info: ph_director, {n} elements: tip {tip}, |tip - se3_pg extrapolated| / L = "
              f"{errors[n]:.3e}, |tip - se3_pg(128)| / L = "
              f"{np.linalg.norm(tip - se3[128]) / CANTILEVER_LENGTH:.3e}")
    checks.check("|tip_ph(16) - tip_se3 (extrapolated)| / L", errors[16], 2e-5)
    checks.check("|tip_ph(16) - tip_se3(128)| / L", np.linalg.norm(tip - se3[128])
                 / CANTILEVER_LENGTH, 1e-4)
    checks.check("the difference falls with the mesh: 8 e(8) / e(4)", 8 * errors[8] / errors[4],
                 1.0)
    checks.check("the difference falls with the mesh: 8 e(16) / e(8)", 8 * errors[16] / errors[8],
                 1.0)


def follower_balance(args, checks):
    """The flying spaghetti (input/flying_spaghetti.nml, 150 steps) with its end force
    (20, 0, 0) and moment (0, 200, 100) f(t) as follower loads: components in the tip's director
    basis. The step applies n_mid = sum_i n_i d_i,mid (and m_mid) and books their work at that
    value (docs/theory/ph_director.md), so with W_n computed here from the stored motion,
    W_n = f(t_mid) [n_mid . (phi_{n+1} - phi_n) + m_mid . 1/2 sum_i d_i,n x d_i,n+1]
    (run_scene.end_load_work's identity), H_{n+1} - H_n - W_n is the scheme's balance. Measured
    on the Release build: 9.5e-16 of max H (the program's balance_error 9.3e-16, its
    external_work 7e-16 of max |W_n| from the test's; Newton residual at most 7e-12); bound
    1e-13.
    The loads must turn: W differs from the dead loads' work computed the same way."""
    text = rs.set_variable(rs.read_example(args.source, "flying_spaghetti.nml"), "load", "frame",
                           "'follower'")
    r = rs.rod(rs.run(args, text, "follower_balance"), "spaghetti")
    t = rs.one_step_per_record(r)
    t_mid = 0.5 * (t[1:] + t[:-1])
    factor = rs.time_function("hat", t_mid, 0.0, 5.0)
    d = r["directors"][:, -1, :, :]                       # (records, director i, component)
    d_mid = 0.5 * (d[1:] + d[:-1])
    force = np.einsum("i,nic->nc", [20.0, 0.0, 0.0], d_mid)
    moment = np.einsum("i,nic->nc", [0.0, 200.0, 100.0], d_mid)
    turn = 0.5 * np.sum(np.cross(d[:-1], d[1:]), axis=1)
    work = factor * (np.sum(force * np.diff(r["position"][:, -1, :], axis=0), axis=1)
                     + np.sum(moment * turn, axis=1))
    dead = rs.end_load_work(r, -1, (20.0, 0.0, 0.0), (0.0, 200.0, 100.0),
                            lambda s: rs.time_function("hat", s, 0.0, 5.0))
    total = r["series/energy/total"]
    top = np.max(total)
    print(f"info: sum W_n = {np.sum(work):.6e} (the same loads dead: {np.sum(dead):.6e}), "
          f"H(15) = {total[-1]:.6e}, Newton residual at most "
          f"{np.max(r['series/newton/residual']):.2e}")
    checks.check("max_n |H_{n+1} - H_n - W_n| / max H (W_n: test)",
                 np.max(np.abs(np.diff(total) - work)) / top, 1e-13)
    checks.check("max_n |balance_error_n| / max H (the program's)",
                 np.max(np.abs(r["series/energy/balance_error"])) / top, 1e-13)
    checks.check("max_n |W_n (test) - external_work_n| / max |W_n|",
                 np.max(np.abs(work - r["series/energy/external_work"][1:]))
                 / np.max(np.abs(work)), 1e-13)
    checks.check("the loads follow: 0.1 max |W_n| / max_n |W_n - W_n (dead)|",
                 0.1 * np.max(np.abs(work)) / np.max(np.abs(work - dead)), 1.0)


# ---- rigid -----------------------------------------------------------------------------------

#: A short cantilever (L = 1, EI = 1, GA = 10 so the shear term is 30 % of the bending one) in
#: statics, a small tip force P = 1e-6 along d1 (deflection 4e-7 L: the geometric
#: nonlinearity is (P L^2 / EI)^2 ~ 1e-12 of it).
TIMOSHENKO = """&run
    title = 'Timoshenko cantilever, inextensible but shearable'
/
&time
    t_end = 1.0
    dt = 0.5
    quasistatic = .true.
/
&solver
    newton_atol = 1e-14
/
&output
    path = 'out/timoshenko.h5'
/
&rod
    name = 'beam'
    formulation = 'ph_director'
    n_elements = 4, degree = 2, n_gauss = 2
    start = 0.0, 0.0, 0.0
    direction = 1.0, 0.0, 0.0
    d1 = 0.0, 1.0, 0.0
    length = 1.0
    EA = 100.0, GA1 = 10.0, GA2 = 10.0, EI1 = 1.0, EI2 = 1.0, GJ = 0.8
    rhoA = 1.0, rhoI1 = 0.01, rhoI2 = 0.01
    rigid = 'EA'
/
&bc
    rod = 'beam', end = 'start', kind = 'clamped'
/
&load
    rod = 'beam', where = 'end'
    force = 0.0, 1e-6, 0.0
    frame = 'spatial'
    time_function = 'ramp', t_on = 0.0, t_off = 1.0
/
"""


def rigid(args, checks):
    """&rod rigid = 'EA' makes the rod inextensible but shearable (methods §2.3: C with a zero
    N3 entry, N3 a multiplier). Its tip deflection under the small tip force P (d1 = e2) is
    Timoshenko's P L^3/(3 EI) + P L/(GA) (shear_factor 1: GA as given); with p = 2 the mixed
    element holds the linear moment and the constant shear force exactly, so only the
    geometric nonlinearity (1e-12) and the Newton tolerance separate them: measured 1.5e-13
    relative, bound 1e-9 (acceptance: within discretization at a fine mesh). Pulled by P
    along its axis, the rod does not stretch (measured 0 against P L / EA = 1e-8 of an
    extensible one; bound 1e-4 of that), and 'kirchhoff' with rigid = 'EA' (shear and
    dilatation rigid, as 'inextensible') loses the shear term: P L^3/(3 EI) (measured 1.1e-13), bound 1e-9. The
    plan names N3 as the multiplier."""
    force, length, bending, shear = 1e-6, 1.0, 1.0, 10.0
    bending_only = force * length**3 / (3 * bending)
    expected = bending_only + force * length / shear
    r = rs.rod(rs.run(args, TIMOSHENKO, "rigid_ea"), "beam")
    tip = r["position"][-1, -1] - r["position"][0, -1]
    print(f"info: rigid = 'EA': tip deflection {tip[1]:.12e}, Timoshenko {expected:.12e}; "
          f"axial {tip[0]:.3e}")
    checks.check("rigid EA: |delta - (P L^3/(3 EI) + P L/GA)| / delta", abs(tip[1] - expected)
                 / expected, 1e-9)
    pull = rs.set_variable(TIMOSHENKO, "load", "force", rs.vector((force, 0.0, 0.0)))
    r = rs.rod(rs.run(args, pull, "rigid_ea_pull"), "beam")
    stretch = r["position"][-1, -1, 0] - r["position"][0, -1, 0]
    print(f"info: rigid = 'EA' pulled by P along the axis: tip moves {stretch:.3e} (extensible: "
          f"P L / EA = {force * length / 100.0:.3e})")
    checks.check("rigid EA pulled: |u_axial| / (P L / EA)", abs(stretch) / (force * length / 100.0),
                 1e-4)
    text = rs.set_variable(TIMOSHENKO, "rod", "constraint", "'kirchhoff'")
    r = rs.rod(rs.run(args, text, "rigid_ea_kirchhoff"), "beam")
    tip = r["position"][-1, -1] - r["position"][0, -1]
    print(f"info: kirchhoff + rigid = 'EA': tip deflection {tip[1]:.12e}, Euler-Bernoulli "
          f"{bending_only:.12e}")
    checks.check("kirchhoff + rigid EA: |delta - P L^3/(3 EI)| / delta",
                 abs(tip[1] - bending_only) / bending_only, 1e-9)
    plan = subprocess.run([args.rodsolve, "--check-input", os.path.join(args.workdir,
                                                                          "rigid_ea.nml")],
                          capture_output=True, text=True).stdout
    line = next((x for x in plan.splitlines() if "constraint multipliers" in x), "")
    print("info: plan:" + line)
    checks.check("the plan names N3 a multiplier and EA infinite",
                 0.0 if ("N3" in line and "EA infinite" in line and "N1" not in line) else 1.0,
                 0.0)


def main():
    rs.run_cases(__doc__, {"pinned": pinned, "follower": follower,
                           "follower_balance": follower_balance, "rigid": rigid})


if __name__ == "__main__":
    main()
