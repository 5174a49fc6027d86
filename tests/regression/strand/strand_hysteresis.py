"""A seven-wire strand under tension bent back and forth with friction between the wires
(issue 24 acceptance: friction in a seven-wire strand under cyclic bending;
input/strand_bending_friction.nml, docs/theory/bundles.md "Friction between rods").

The bottom plate pulls the strand to the strain 1e-3 (a ramp over 10 ms), which presses the
helical wires onto the core; then the top plate turns about e_x by theta(t) = 0.05 sin(2 pi
(t - 10 ms) / 40 ms) rad for two cycles, with its position held. The wires slide on the core
and friction (mu = 0.3) makes the moment of the top plate against its rotation a hysteresis
loop, drawn to strand_hysteresis.png in the work directory.

What is checked, from the stored states (not from the code's books):
- the work of the plates in each cycle, computed here from the tie forces and moments on the
  rods' ends (series/ties/force, series/ties/moment: the multipliers of each step) and the
  plates' motions, equals the friction dissipation plus the change of H and of the contact
  energy over the cycle (to 1e-5: the stored moment's directors are the record's, not the
  step's midpoint values); the work the rods' books hold equals D + dH to 1e-8 relative (the
  acceptance);
- the loop is open: the dissipation per cycle is a few percent of the work of the half cycle
  (its area against the elastic energy), the same in both cycles (steady), and the moment
  at theta = 0 is not zero (the wires stuck in their slipped positions).
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

SCENE = "strand_bending_friction.nml"
RODS = ["core"] + [f"w1_{j}" for j in range(1, 7)]


def plate_motion(text, name):
    """A plate's displacement, rotation, centre and time function (t_on, t_off) from the scene."""
    body = re.search(r"&plate\s+name = '" + name + r"'(.*?)\n/", text, flags=re.S).group(1)

    def vector(key, default):
        match = re.search(key + r" = ([^\n]*)", body)
        return np.array([float(v) for v in match.group(1).split(",")]) if match else default
    kind = re.search(r"time_function = '(\w+)'", body).group(1)
    t_on, t_off = (float(v) for v in re.search(r"t_on = ([^,]*), t_off = ([^\n]*)", body).groups())
    return dict(displacement=vector("displacement", np.zeros(3)),
                rotation=vector("rotation", np.zeros(3)), centre=vector("centre", None),
                kind=kind, t_on=t_on, t_off=t_off)


def time_function(plate, t):
    """f(t) of a plate's time function (run_scene.time_function, docs/user/input.md)."""
    return rs.time_function(plate["kind"], t, plate["t_on"], plate["t_off"])


def plate_work(fields, plate, end, t):
    """The work of a plate on the strand in each step, from the stored ties: the wrench of the
    step (the multipliers of its midpoint solve, with the ends' midpoint positions as levers)
    on the plate's motion of the step, a translation by the change of f displacement and a
    turn by the change of f rotation about its centre (one fixed axis)."""
    f = time_function(plate, t)
    centre = plate["centre"] + f[:, None] * plate["displacement"]
    centre_mid = 0.5 * (centre[1:] + centre[:-1])
    force = np.zeros((t.size - 1, 3))
    moment = np.zeros((t.size - 1, 3))
    for name in RODS:
        x = fields[name]["position"][:, -1 if end == 1 else 0]
        x_mid = 0.5 * (x[1:] + x[:-1])
        tie_force = fields[name]["series/ties/force"][1:, end]
        force += tie_force
        moment += np.cross(x_mid - centre_mid, tie_force) + fields[name]["series/ties/moment"][1:, end]
    df = np.diff(f)
    # A turn by the angle phi about the fixed axis e moves a tied point or director by
    # tan(phi / 2) e x (its two positions' sum) (Rodrigues, with Cayley's parameter), so its
    # work is 2 tan(phi / 2) e . (the wrench's moment with the midpoint levers).
    angle = np.linalg.norm(plate["rotation"])
    turn = 2.0 * np.tan(0.5 * df * angle) / angle if angle > 0.0 else df
    return df * (force @ plate["displacement"]) + turn * (moment @ plate["rotation"]), moment


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["run"])
    args = parser.parse_args()
    checks = rs.Checks()
    text = rs.read_example(args.source, SCENE)
    path = rs.run(args, text, "hysteresis")
    fields = {name: rs.rod(path, name) for name in RODS}
    t = fields["core"]["time"]
    bottom, top = plate_motion(text, "bottom"), plate_motion(text, "top")
    work_bottom, _ = plate_work(fields, bottom, 0, t)
    work_top, moment_top = plate_work(fields, top, 1, t)
    work = work_bottom + work_top
    dissipated = sum(fields[name]["series/energy/dissipated"][1:] for name in RODS)
    energy = sum(fields[name]["series/energy/total"] + fields[name]["series/contact/energy"]
                 for name in RODS)
    external = sum(fields[name]["series/energy/external_work"][1:] for name in RODS)
    internal = sum(fields[name]["series/energy/total"] for name in RODS)
    theta = top["rotation"][0] * time_function(top, t)
    m_x = moment_top[:, 0]
    period = top["t_off"] - top["t_on"]
    cycles = int(round((t[-1] - top["t_on"]) / period))
    iterations = fields["core"]["series/newton/iterations"]
    print(f"info: {t.size - 1} steps, {iterations[1:].mean():.2f} Newton iterations per step, "
          f"{cycles} cycles of {period * 1e3:.1f} ms; largest moment {np.max(np.abs(m_x)):.4f} N m")
    losses = []
    for c in range(cycles):
        first = int(np.searchsorted(t, top["t_on"] + c * period - 1e-12))
        last = int(np.searchsorted(t, top["t_on"] + (c + 1) * period - 1e-12))
        steps = slice(first, last)
        w, d = float(np.sum(work[steps])), float(np.sum(dissipated[steps]))
        change = float(energy[last] - energy[first])
        gross = float(np.sum(np.abs(work[steps])))
        losses.append(d)
        print(f"info: cycle {c + 1}: plates' work {w:.9e} J (gross {gross:.4e} J), friction "
              f"dissipation {d:.9e} J, change of H + E_contact {change:.3e} J")
        # The work recomputed here from the stored wrench: the stored moment takes the
        # directors of the record, the step works on their midpoint values, a second-order
        # difference per step (measured 4.3e-7 relative over a cycle; the lever part alone,
        # with midpoint positions, is exact).
        checks.check(f"cycle {c + 1}: |W_plates (from the ties) - D - dH| / W_plates",
                     abs(w - d - change) / abs(w), 1e-5)
        # The acceptance, on the rods' books: the couplings' work booked on the rods (the
        # plates', and minus the change of the contact energy) equals D + dH to 1e-8
        # (measured 9e-10: the Newton tolerance's share).
        booked = float(np.sum(external[steps]))
        checks.check(f"cycle {c + 1}: |W_booked - D - dH| / W_booked (acceptance 1e-8)",
                     abs(booked - d - float(internal[last] - internal[first])) / abs(booked), 1e-8)
        # The loop is open: the friction takes a few percent of the elastic energy of the half
        # cycle (measured 4 %; frictionless it would be 0).
        checks.check(f"cycle {c + 1}: -D / (gross work / 2) (the loop is open)",
                     -d / (0.5 * gross), -0.01)
    if cycles >= 2:
        checks.check("|D (cycle 2) / D (cycle 1) - 1| (a steady loop)",
                     abs(losses[1] / losses[0] - 1.0), 0.05)
    # The loop's width at theta = 0: the moment of the steps (its multipliers, acting over the
    # step, so at the step's midpoint rotation) interpolated to theta = 0 where the rotation
    # rises and where it falls; frictionless both would be 0.
    theta_mid = 0.5 * (theta[1:] + theta[:-1])
    at_zero = {1: [], -1: []}
    for k in range(1, theta_mid.size):
        if t[k] > top["t_on"] and theta_mid[k - 1] * theta_mid[k] < 0.0:
            share = theta_mid[k - 1] / (theta_mid[k - 1] - theta_mid[k])
            at_zero[int(np.sign(theta_mid[k] - theta_mid[k - 1]))].append(
                m_x[k - 1] + share * (m_x[k] - m_x[k - 1]))
    width = 0.5 * abs(np.mean(at_zero[-1]) - np.mean(at_zero[1]))
    print(f"info: the loop at theta = 0: {np.mean(at_zero[1]):.4f} N m rising, "
          f"{np.mean(at_zero[-1]):.4f} N m falling")
    # (measured 3.3 % of the largest moment)
    checks.check("-(half the loop's width at theta = 0) / max |M| (the loop is open)",
                 -width / float(np.max(np.abs(m_x))), -0.003)
    # The moment of a step (its multipliers) acts over the step: drawn at the step's midpoint.
    draw(args.workdir, theta_mid, m_x, t[1:] > top["t_on"])
    checks.finish()


def draw(workdir, theta, moment, cycling):
    """The loop: the top plate's moment about e_x against its rotation."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(5, 4))
    axes.plot(theta[cycling] * 1e3, moment[cycling], lw=1)
    axes.set_xlabel("rotation of the top plate about e_x (mrad)")
    axes.set_ylabel("moment of the top plate (N m)")
    axes.set_title("seven-wire strand, mu = 0.3: bending hysteresis")
    axes.grid(True, lw=0.3)
    figure.tight_layout()
    out = os.path.join(workdir, "strand_hysteresis.png")
    figure.savefig(out, dpi=120)
    print(f"info: the loop is drawn in {out}")


if __name__ == "__main__":
    main()
