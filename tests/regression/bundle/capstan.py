"""The capstan (issue 24 acceptance): a rope wrapped by the angle theta over a fixed drum with
friction mu (&obstacle 'cylinder'), one end held by the tension T1 (a dead end force along
its tangent), the other pulled slowly along its tangent by a driven &plate. While the rope
slides, Euler-Eytelwein's capstan equation gives the tension at the pulled end:

    T2 / T1 = exp(mu theta cos(psi)),

psi the lay angle of the wrap (a helix of rise p per turn: tan(psi) = p / (2 pi R); 0 for the
plane wraps of theta < 2 pi; for theta = 2 pi the rope rises by 8 mm so that its ends pass).
Acceptance: within 2 % for mu = 0.1 and 0.3, theta = pi/2, pi and 2 pi.

    capstan.py run      all six cases (about 2 s each)

The rope: EA = 1e4 N, so it stretches by well under 0.1 %; EI = 2e-5 N m^2, so that the
bending of the rope that leaves the drum (EI / (2 R^2) = 4e-3 N of tension) stays below 0.2 %
of T1 (a stiffer rope, EI = 1.3e-3, pulled 10 % above the capstan value); contact radius 2 mm on
a drum of radius 50 mm, stiffness 1e10 N/m^3 (penetration about 1e-4 m). The dead load T1 = 1 N
is ramped over 20 ms; then the plate pulls 2 mm over 80 ms (25 mm/s, 25 times the friction's
slip velocity of 1e-3 m/s, so the regularization takes 0.1 % of the friction). The tension T2
is the plate's force on the rope along the end's tangent (series/ties/force), averaged over the
second half of the pull, when the rope slides steadily (the undamped longitudinal waves of the
rope make it oscillate by a few percent about the mean; averaged from 15 ms after the pull
starts, while the rope still passes from sticking to sliding, it lies up to 0.6 % lower).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

DRUM = 0.05
ROPE = 0.002
T1 = 1.0
PULL_ON, T_END = 0.02, 0.1


def scene(theta, mu):
    rise = 0.008 if theta > 1.5 * math.pi else 0.0
    radius = DRUM + ROPE
    psi = math.atan(rise / (2 * math.pi * radius))
    start_tangent = np.array([0.0, math.cos(psi), math.sin(psi)])
    end_tangent = np.array([-math.sin(theta) * math.cos(psi), math.cos(theta) * math.cos(psi),
                            math.sin(psi)])
    elements = int(round(32 * theta / math.pi))
    load = rs.vector(-T1 * start_tangent)
    pull = rs.vector(0.002 * end_tangent)
    text = f"""&run
    title = 'capstan: theta = {theta!r}, mu = {mu!r}'
/
&time
    t_end = {T_END!r}, dt = 1e-4
/
&solver
    newton_atol = 1e-10
/
&output
    path = 'placeholder.h5', stride = 10
/
&rod
    name = 'rope', formulation = 'ph_director', n_elements = {elements}, degree = 2
    geometry = 'helix', start = {radius!r}, 0, 0, direction = 0, 0, 1
    helix_radius = {radius!r}, helix_pitch = {rise!r}, helix_turns = {theta / (2 * math.pi)!r}
    EA = 1e4, GA1 = 1e4, GA2 = 1e4, EI1 = 2e-5, EI2 = 2e-5, GJ = 2e-5
    rhoA = 0.0126, rhoI1 = 1e-8, rhoI2 = 1e-8, contact_radius = {ROPE!r}
/
&load
    rod = 'rope', where = 'start', force = {load}
    time_function = 'ramp', t_on = 0, t_off = {PULL_ON!r}
/
&plate
    name = 'pull', rods = 'rope', end = 'end', displacement = {pull}
    time_function = 'ramp', t_on = {PULL_ON!r}, t_off = {T_END!r}
/
&obstacle
    name = 'drum', kind = 'cylinder', point = 0, 0, 0, normal = 0, 0, 1, radius = {DRUM!r}
    stiffness = 1e10, mu = {mu!r}, slip_velocity = 1e-3
/
"""
    return text, psi, end_tangent


def run(args, checks):
    for mu in (0.1, 0.3):
        for label, theta in (("pi/2", math.pi / 2), ("pi", math.pi), ("2 pi", 2 * math.pi)):
            text, psi, end_tangent = scene(theta, mu)
            name = f"capstan_mu{mu}_theta{theta:.3f}"
            r = rs.rod(rs.run(args, text, name), "rope")
            t = r["time"]
            t2 = r["series/ties/force"][:, 1, :] @ end_tangent
            sliding = t >= 0.5 * (PULL_ON + T_END)
            mean = float(t2[sliding].mean())
            expected = T1 * math.exp(mu * theta * math.cos(psi))
            # How far the held end slid along the drum: the rope really slips.
            slid = float(np.linalg.norm(r["position"][-1, 0] - r["position"][0, 0]))
            print(f"info: mu = {mu}, theta = {label}: T2 / T1 = {mean / T1:.4f} (sliding mean; "
                  f"oscillating by {t2[sliding].std() / mean:.1%}), capstan "
                  f"{expected / T1:.4f}; the held end slid {slid * 1e3:.2f} mm; Newton "
                  f"iterations {r['series/newton/iterations'][1:].mean() / 10:.2f} per step")
            checks.check(f"mu = {mu}, theta = {label}: |T2 / (T1 exp(mu theta cos psi)) - 1| "
                         "(acceptance 2 %)", abs(mean / expected - 1.0), 0.02)
            checks.check(f"mu = {mu}, theta = {label}: the rope slides (-held end's travel, "
                         "mm; at least 1 of the plate's 2)", -slid * 1e3, -1.0)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["run"])
    args = parser.parse_args()
    checks = rs.Checks()
    run(args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
