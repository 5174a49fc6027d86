"""Soft robotic arm with three pneumatic chambers (seed 000 §6.4; methods/ph_director_3d.md §6.4
and §10 V9): input/soft_arm_circle.nml and input/soft_arm_heart.nml.

    soft_arm.py circle
    soft_arm.py heart

Both: the scene's &actuator groups are exactly the output of scripts/soft_arm_tables.py; the
run reaches T = 4 with 81 records; the energy balance with the actuator port,
|H_{n+1} - H_n - W_ext,n - W_act,n + D_n| <= 2e-10 max H at every step (exact up to Newton at
1e-11; measured 7.8e-12 circle, 1.1e-11 heart), once with the program's balance_error and
once with the chambers' work computed in the test from the paper's forces and the stored
strains (actuator_work; against the program's work per step 1e-12 of the largest, measured
2e-14 and 5e-14; over the run 1e-10 of max H, measured 3.5e-12 and 3.8e-13);
the actuators do work; scripts/rodplot.py tip writes the tip-path PNG.
The paper states no numbers, only the shapes (Fig. 16), so the shape checks are bands:
circle: during [t1, t2] = [0.5, 3.5] the tip turns once round the e3 axis (unwrapped angle
covered >= 2 pi - 0.15), in the direction phi(t) + pi (the arm bends away from the most
pressurized chamber; see the scene header) to 0.15 rad, at a roughly constant height
(max - min <= 0.15 L; there is no damping, so the start of the manoeuvre leaves a small
oscillation);
heart: while r/max r >= 0.3 the tip's direction from the e3 axis is that of -(x, y)(2 pi t/T)
of eq. (75) to 0.15 rad, and the path closes (|tip(T) - tip(0)| <= 0.02 L).
"""
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import run_scene as rs  # noqa: E402

ROD = "arm"
LENGTH = 0.1755
T1, T2, T_END = 0.5, 3.5, 4.0
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def tables_script(source):
    sys.path.insert(0, os.path.join(source, "scripts"))
    import soft_arm_tables
    return soft_arm_tables


def wrap(angle):
    """An angle difference in (-pi, pi]."""
    return np.angle(np.exp(1j * angle))


def actuator_work(r, tables, kind):
    """Work W_act,n of the three chambers over each step, computed from the paper's chamber
    forces (scripts/soft_arm_tables.py: pressure area value_k(t), eqs. 73-74) and the stored
    strains, not from the program's actuator_work.

    A chamber of force tau = -pressure area value_k(t) along d3 at the offset rho = rho^1 d1 +
    rho^2 d2 adds the material stress tau (0, 0, 1, rho^2, -rho^1, 0) (the moment rho x tau d3),
    the same along the whole rod, whose power is W_act = -h int dsigma_act . eps_dot(q_mid,
    v_mid) ds (methods §3.2 eq. 66). The strains are bilinear in q and h v_mid = q_n+1 - q_n,
    so h eps_dot(q_mid, v_mid) = eps(q_n+1) - eps(q_n) exactly at every point (methods §5.3
    item 3). The stress points are the 2-point Gauss points (docs/user/output.md), so
    W_act,n = -dsigma_act(t_mid) . sum_points l_e/2 (eps_n+1 - eps_n)."""
    t = rs.one_step_per_record(r)
    t_mid = 0.5 * (t[1:] + t[:-1])
    stress = np.zeros((t_mid.size, 6))
    for alpha in tables.ALPHAS:
        rho1, rho2 = tables.offset(alpha)
        tau = np.array([-tables.PRESSURE * tables.AREA * tables.VALUES[kind](s, alpha)
                        for s in t_mid])
        stress += tau[:, None] * np.array([0.0, 0.0, 1.0, rho2, -rho1, 0.0])
    nodes = r["mesh"]
    weight = np.repeat(nodes[2::2] - nodes[:-2:2], 2) / 2    # two Gauss points per element
    integral = np.einsum("p,spc->sc", weight, r["strain"])    # int eps ds at every record
    return -np.sum(stress * np.diff(integral, axis=0), axis=1)


def common(args, checks, kind):
    text = rs.read_example(args.source, f"soft_arm_{kind}.nml")
    tables = tables_script(args.source)
    block = tables.generated_block(text)
    checks.check("the scene's &actuator groups are the output of scripts/soft_arm_tables.py",
                 float(block != tables.actuator_groups(kind)), 0.0)
    path = rs.run(args, text, f"soft_arm_{kind}")
    r = rs.rod(path, ROD)
    t = r["time"]
    checks.check("|t_last - 4| (the run reaches T)", abs(t[-1] - T_END), 1e-12)
    checks.check("records - 81", abs(float(t.size - 81)), 0.0)
    total = r["series/energy/total"]
    top = np.max(total)
    balance = np.abs(r["series/energy/balance_error"])
    checks.check("max_n |H_{n+1} - H_n - W_n - W_act,n + D_n| / max H", np.max(balance) / top,
                 2e-10)
    work = r["series/energy/actuator_work"]
    checks.check("the chambers do work: -max_n |W_act,n| / max H", -np.max(np.abs(work)) / top,
                 -1e-3)
    # The balance again with the chambers' work computed here (actuator_work), so that a sign
    # error made consistently in the actuation and its work cannot pass; the scene has no
    # external loads and no damping: H_{n+1} - H_n = W_act,n.
    test_work = actuator_work(r, tables, kind)
    checks.check("max_n |W_act,n (test) - actuator_work_n| / max |W_act,n|",
                 np.max(np.abs(test_work - work[1:])) / np.max(np.abs(test_work)), 1e-12)
    checks.check("max_n |H_{n+1} - H_n - W_act,n (test)| / max H",
                 np.max(np.abs(np.diff(total) - test_work)) / top, 2e-10)
    checks.check("|H(T) - H(0) - sum W_act,n (test)| / max H",
                 abs(total[-1] - total[0] - np.sum(test_work)) / top, 1e-10)
    print(f"info: max H = {top:.6e} J, largest |W_act,n| = {np.max(np.abs(work)):.4e} J, "
          f"largest |balance error| = {np.max(balance):.3e} J; "
          f"steps cut back: {int(np.sum(r['series/dt'][1:] < 0.05 - 1e-12))}, "
          f"max Newton iterations {int(np.max(r['series/newton/iterations']))}")
    tip = r["position"][:, -1, :]
    checks.check("the tip path is finite and moves: -max |tip - tip(0)| / L",
                 -np.max(np.linalg.norm(tip - tip[0], axis=1)) / LENGTH
                 if np.all(np.isfinite(tip)) else 1.0, -0.1)
    image = os.path.join(args.workdir, f"soft_arm_{kind}_tip.png")
    if os.path.exists(image):
        os.remove(image)
    rodplot = os.path.join(args.source, "scripts", "rodplot.py")
    plot = subprocess.run([sys.executable, rodplot, "tip", path, "--plane", "xy", "-o", image],
                          capture_output=True, text=True)
    print(plot.stdout + plot.stderr, end="")
    checks.check("rodplot.py tip: exit status", float(plot.returncode), 0.0)
    head, size = b"", 0
    if os.path.exists(image):
        with open(image, "rb") as f:
            head = f.read(8)
        size = os.path.getsize(image)
    checks.check("tip plot is a PNG of more than 10 kB: -size / 10 kB",
                 -size / 1e4 if head == PNG_SIGNATURE else 0.0, -1.0)
    return r, t, tip


def circle(args, checks):
    r, t, tip = common(args, checks, "circle")
    tables = tables_script(args.source)
    turning = (t >= T1 - 1e-9) & (t <= T2 + 1e-9)
    angle = np.arctan2(tip[:, 1], tip[:, 0])
    covered = np.ptp(np.unwrap(angle[turning]))
    phase = np.array([tables.circle_amplitude_phase(s)[1] for s in t])
    lag = np.abs(wrap(angle - (phase + math.pi)))[turning]
    height = tip[turning, 2]
    radius = np.hypot(tip[turning, 0], tip[turning, 1])
    print(f"info: t in [0.5, 3.5]: tip height {np.min(height):.5f} .. {np.max(height):.5f} m "
          f"(spread {np.ptp(height):.5f} m = {np.ptp(height) / LENGTH:.3f} L), distance from the "
          f"axis {np.min(radius):.5f} .. {np.max(radius):.5f} m, angle covered {covered:.4f} rad, "
          f"largest deviation from phi + pi {np.max(lag):.4f} rad")
    checks.check("one revolution during [0.5, 3.5]: 2 pi - 0.15 - angle covered",
                 2 * math.pi - 0.15 - covered, 0.0)
    checks.check("tip direction - (phi(t) + pi) during [0.5, 3.5], rad", np.max(lag), 0.15)
    checks.check("roughly constant height during [0.5, 3.5]: (max - min) / L",
                 np.ptp(height) / LENGTH, 0.15)


def heart(args, checks):
    _, t, tip = common(args, checks, "heart")
    theta = 2 * math.pi * t / T_END
    x, y = np.sin(theta)**3, np.cos(theta) - np.cos(2 * theta)
    big = np.hypot(x, y) / 2.0 >= 0.3
    deviation = np.abs(wrap(np.arctan2(tip[:, 1], tip[:, 0]) - np.arctan2(-y, -x)))[big]
    closing = np.linalg.norm(tip[-1] - tip[0])
    print(f"info: tip x {np.min(tip[:, 0]):.5f} .. {np.max(tip[:, 0]):.5f} m, y "
          f"{np.min(tip[:, 1]):.5f} .. {np.max(tip[:, 1]):.5f} m; largest deviation from the "
          f"direction of -(x, y) {np.max(deviation):.4f} rad over {int(np.sum(big))} records; "
          f"|tip(T) - tip(0)| = {closing:.3e} m")
    checks.check("tip direction - direction of -(x, y)(theta) where r/max r >= 0.3, rad",
                 np.max(deviation), 0.15)
    checks.check("the path closes: |tip(T) - tip(0)| / L", closing / LENGTH, 0.02)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["circle", "heart"])
    args = parser.parse_args()
    checks = rs.Checks()
    {"circle": circle, "heart": heart}[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
