"""The 45-degree bend of seed 004 (methods/se3_strands.md §4.3, Tables 3-4), input/
bend45_strand.nml: an arc of radius 100 and 45 degrees, 80 segments (81 nodes), clamped at
s = 0, dead vertical tip load, statics by damped dynamics (&time relaxation).

    bend45.py load300           tip within 0.15 per component of the paper's (58.86, 22.23,
    bend45.py load600           40.11) at 300 N and (47.25, 15.64, 53.43) at 600 N (Table 3,
                                "present method", issue 8); relaxed within 100 steps; the
                                methods' prototype at N = 80 (a centre with a band of 2e-3:
                                its 3 printed decimals) and its steps (23, 28)
    bend45.py path_independence the relaxed state does not depend on the path: dt = 5 s and
                                twice the damping land on the same tip (1e-7 relative; the
                                kinetic-energy stop leaves that much motion)
    bend45.py saint_venant      the torsion-constant remark (methods §4.3, §7): with the
                                Saint-Venant J = 0.1406 instead of the polar I3 = 1/6 (and
                                dt = 5 s, see below) the 600 N
                                tip misses the paper's x by more than the band (0.15), so the
                                paper used G I3; the methods' prototype at N = 320: (46.89,
                                15.56, 53.61), centre with a band of 0.02

The two bands. The prototype at the same N = 80 is the tight reference: measured 6e-5 ...
3.8e-4, within its printed half unit 5e-4, band 2e-3. The paper's values differ from it (and
from the converged N = 320 answer, methods §4.3) by 0.015 ... 0.097 per component: the paper's
own digits, not this code's error, so the band 0.15 (1.5 to 10 times the measured deviation)
cannot be narrower; it checks that the scene is the paper's problem.

The scene is the benchmark turned by -90 degrees about e_z: a point (x, y, z) of the result is
(y, -x, z) in the benchmark's coordinates. The load cases print the time to solution (the time
loop of rodsolve's summary line, and the whole run) next to Table 4's 0.8 s (the paper's Python
on a laptop) and 4 s (Abaqus).
"""
import sys

import numpy as np

from strand_scene import rs, se3_scene, relaxed_steps

ROD = "bend"
PAPER = {300: (58.86, 22.23, 40.11), 600: (47.25, 15.64, 53.43)}
PROTOTYPE_N80 = {300: (58.781, 22.245, 40.190), 600: (47.153, 15.686, 53.472)}
PROTOTYPE_STEPS = {300: 23, 600: 28}
SAINT_VENANT_N320 = (46.89, 15.56, 53.61)


def benchmark(point):
    """Scene coordinates to the benchmark's: (x, y, z) -> (y, -x, z)."""
    return np.array([point[1], -point[0], point[2]])


def solve(args, name, load, extra=()):
    text = se3_scene.edit(rs.read_example(args.source, "bend45_strand.nml"),
                          [("load", "force", rs.vector((0.0, 0.0, float(load)))), *extra])
    r = se3_scene.run(args, text, name, ROD)
    return r, benchmark(r["position"][-1, -1]), relaxed_steps(r, ROD)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["load300", "load600", "path_independence",
                                         "saint_venant"])
    args = parser.parse_args()
    checks = rs.Checks()
    if args.case.startswith("load"):
        load = int(args.case[4:])
        r, tip, steps = solve(args, args.case, load)
        print(f"info: {load} N: tip (benchmark coordinates) ({tip[0]:.4f}, {tip[1]:.4f}, "
              f"{tip[2]:.4f}) after {steps} steps; paper {PAPER[load]}, prototype N = 80 "
              f"{PROTOTYPE_N80[load]} in {PROTOTYPE_STEPS[load]} steps")
        checks.check(f"{load} N: relaxed", 0 if steps else 1, 0)
        checks.check(f"{load} N: steps to relax (paper: within 100)", steps or 1e9, 100)
        checks.check(f"{load} N: |steps - prototype's {PROTOTYPE_STEPS[load]}|",
                     abs((steps or 1e9) - PROTOTYPE_STEPS[load]), 0)
        for c, label in enumerate("xyz"):
            checks.check(f"{load} N: |tip {label} - paper {PAPER[load][c]}|",
                         abs(tip[c] - PAPER[load][c]), 0.15)
            checks.check(f"{load} N: |tip {label} - prototype {PROTOTYPE_N80[load][c]}|",
                         abs(tip[c] - PROTOTYPE_N80[load][c]), 2e-3)
        print(f"info: {load} N: time to solution: time loop {r.seconds:.4g} s, whole run (setup, "
              f"time loop, output) {r.wall_seconds:.4g} s; seed 004 Table 4 (600 N, 81 nodes): "
              "present method 0.8 s, Abaqus 4 s (other machines)")
    elif args.case == "path_independence":
        _, tip, steps = solve(args, "reference", 600)
        _, other, other_steps = solve(args, "other_path", 600,
                                      [("time", "dt", "5.0"), ("rod", "external_damping", "0.2")])
        print(f"info: 600 N: tip {tip} ({steps} steps of 10 s, damping 0.1), {other} "
              f"({other_steps} steps of 5 s, damping 0.2)")
        checks.check("relaxed on both paths", 0 if steps and other_steps else 1, 0)
        checks.check("largest |tip difference| / |tip|",
                     float(np.max(np.abs(tip - other)) / np.linalg.norm(tip)), 1e-7)
    else:
        # dt = 5 s: with the paper's free end this case sat on the edge of stability at the
        # scene's 10 s (it relaxed or ran away depending on round-off); with the free end fixed
        # it relaxes at 10 s too (energy.py saint_venant, N = 320). The fixed point does not
        # depend on dt.
        _, tip, steps = solve(args, "saint_venant", 600,
                              [("rod", "torsion_constant", "'saint_venant'"), ("time", "dt", "5.0")])
        print(f"info: 600 N, Saint-Venant J: tip ({tip[0]:.4f}, {tip[1]:.4f}, {tip[2]:.4f}) "
              f"after {steps} steps; paper {PAPER[600]}; prototype N = 320 {SAINT_VENANT_N320}")
        checks.check("relaxed", 0 if steps else 1, 0)
        checks.check("0.15 - |tip x - paper x| (< 0: the paper did not use J)",
                     0.15 - abs(tip[0] - PAPER[600][0]), 0.0)
        for c, label in enumerate("xyz"):
            checks.check(f"|tip {label} - prototype (J, N = 320) {SAINT_VENANT_N320[c]}|",
                         abs(tip[c] - SAINT_VENANT_N320[c]), 0.02)
    checks.finish()


if __name__ == "__main__":
    sys.exit(main())
