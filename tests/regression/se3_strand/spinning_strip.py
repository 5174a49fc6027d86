"""Howcroft et al.'s curved flat strip spun about the vertical through its driven clamp (seed 004
§3.3, Table 5, Fig. 7; methods/se3_strands.md §4.4), input/strand_spinning_strip.nml: 32
segments, the spin ramped up over 4 s and held to 8 s, a Kelvin-Voigt stress to settle the
transient (it vanishes in the steady spin).

    spinning_strip.py f1 | f2 | f8   the steady tip radius and height at 1, 2 and 8 Hz against
                                     the methods' rotating-frame statics (0.46693, -0.08998),
                                     (0.47457, -0.05112), (0.47875, -0.00792) (issue 8), with
                                     the bounds of BOUNDS below; steady: the tip moves over the
                                     last second less than STILL; the relaxed start at t = 0 is
                                     the 30-degree arc's tip (R sin 30°, -R (1 - cos 30°)) to
                                     1e-9; at 8 Hz the steady tip does not depend on the step
                                     (dt = 1 ms lands on the 2 ms tip to 1e-11)

    spinning_strip.py resonance      Fig. 8 (methods §4.5), input/strand_strip_resonance.nml: the
                                     clamp oscillating vertically (the drive spans 0.04 m to
                                     1e-3 relative) while the spin ramps from 0 to 8 Hz over
                                     t = 12 ... 20 s: the tip's vertical oscillation (peak to
                                     peak per 0.5 s window) grows to more than twice its
                                     amplitude before the ramp and falls to below 70 % of its
                                     peak by the end (the paper prints no numbers)
    spinning_strip.py restart        the 8 Hz run stopped at t = 1 s and continued with
                                     restart_from to 2 s ends in the uninterrupted run's state
                                     (bitwise: the checkpoint holds the whole state, the clamp's
                                     pose included)
    spinning_strip.py two_ranks      two strips (1 and 8 Hz) on 2 ranks give the 1-rank results
                                     bitwise (DESIGN.md §5)

The scene is rotated (see its header): radius sqrt(y^2 + z^2), height -x.
"""
import math
import sys

import numpy as np

from strand_scene import rs, se3_scene

ROD = "strip"
LENGTH = 0.479
RADIUS = LENGTH / (math.pi / 6)
STEADY = {1: (0.46693, -0.08998), 2: (0.47457, -0.05112), 8: (0.47875, -0.00792)}
# Bounds on |radius - reference| and |height - reference| (m). The references are the methods'
# N = 32 statics (methods/se3_strands.md §4.4), the same N as the scene, printed to 5 decimals
# (half unit 5e-6); measured on the Release build: radius 1.5e-6, 2.1e-6, 2.3e-6 and height
# 8.7e-7, 5.1e-6 at 1 and 2 Hz, all within the printing: bound 5e-5. The 8 Hz height misses by
# 6.4e-5 although the dynamic steady state does not depend on the step (case f8 checks dt =
# 1 ms against 2 ms; 0.5 ms agrees as well): the methods' explicit 8 Hz relaxation "converged
# only with dt = 0.5 ms and a long ramp" (methods §4.4, §7 item 4), so its last digit is the
# reference's, and the bound is 10 times that miss, 7e-4 (the old 1e-3 was 13 % of the height).
BOUNDS = {1: (5e-5, 5e-5), 2: (5e-5, 5e-5), 8: (5e-5, 7e-4)}
# Tip motion over the last second (m): the Kelvin-Voigt time of 0.05 s damps the spin-up over
# the 4 s hold; measured 1.7e-7, 1.1e-7 and 2.1e-10, bounds 12, 18 and 24 times that.
STILL = {1: 2e-6, 2: 2e-6, 8: 5e-9}


def restart(args, checks):
    text = rs.set_variable(rs.read_example(args.source, "strand_spinning_strip.nml"), "time",
                           "t_end", "2.0")
    whole = rs.rod(rs.run(args, text, "whole"), ROD)
    first = rs.run(args, rs.set_variable(text, "time", "t_end", "1.0"), "first_half")
    r = se3_scene.run(args, rs.set_variable(text, "run", "restart_from", f"'{first}'"),
                      "continued", ROD)
    checks.check("restart: steps the continued run took - 500 (it starts at t = 1)",
                 abs((r.steps or 0) - 500), 0)
    again = r.fields
    for field in ("position", "directors", "velocity", "stress"):
        checks.check(f"restart: largest |{field} - uninterrupted| at t = 2",
                     float(np.max(np.abs(again[field][-1] - whole[field][-1]))), 0.0)


def resonance(args, checks):
    r = se3_scene.run(args, rs.read_example(args.source, "strand_strip_resonance.nml"),
                      "resonance", ROD)
    t = r["time"]
    height = -r["position"][:, :, 0]
    windows = np.arange(8.0, 20.0, 0.5)

    def spans(node):
        return np.array([np.ptp(height[(t >= a) & (t < a + 0.5), node]) for a in windows])
    tip, clamp = spans(-1), spans(0)
    before = float(np.max(tip[windows < 12.0]))
    peak = int(np.argmax(tip))
    print(f"info: tip vertical peak to peak per 0.5 s from t = 8: {np.round(tip, 4).tolist()}; "
          f"largest {tip[peak]:.4f} m at t = {windows[peak]:.1f} s (spin "
          f"{windows[peak] - 12.0:.1f} ... {windows[peak] - 11.5:.1f} Hz); before the ramp "
          f"{before:.4f} m; clamp {np.min(clamp):.6f} ... {np.max(clamp):.6f} m; {r.summary()}")
    checks.check("largest |clamp peak to peak / 0.04 - 1|",
                 float(np.max(np.abs(clamp / 0.04 - 1))), 1e-3)
    checks.check("2 - (largest tip peak to peak in the ramp) / (largest before it)",
                 2.0 - float(np.max(tip[windows >= 12.0])) / before, 0.0)
    checks.check("tip peak to peak at the end / its largest - 0.7",
                 float(tip[-1] / tip[peak]) - 0.7, 0.0)
    checks.check("the peak lies inside the ramp: (12 - t_peak)+ + (t_peak - 19.5)+",
                 max(0.0, 12.0 - windows[peak]) + max(0.0, windows[peak] - 19.5), 0.0)


def two_ranks(args, checks):
    text = rs.set_variable(rs.read_example(args.source, "strand_spinning_strip.nml"), "time",
                           "t_end", "1.0")
    rod = text[text.index("&rod"):text.index("\n/", text.index("&rod")) + 2]
    bc = text[text.index("&bc"):text.index("\n/", text.index("&bc")) + 2]
    slow = bc.replace("'strip'", "'slow'").replace("50.26548245743669", repr(2 * math.pi))
    text = text + "\n" + rod.replace("'strip'", "'slow'") + "\n" + slow + "\n"
    one = rs.run(args, text, "one_rank")
    two = rs.run(args, text.replace("one_rank", "two_ranks"), "two_ranks", ranks=2)
    for name in ("strip", "slow"):
        a, b = rs.rod(one, name), rs.rod(two, name)
        checks.check(f"{name}: largest |position(1 rank) - position(2 ranks)|",
                     float(np.max(np.abs(a["position"] - b["position"]))), 0.0)
        checks.check(f"{name}: records on 1 and 2 ranks differ in number",
                     abs(len(a["time"]) - len(b["time"])), 0)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["f1", "f2", "f8", "resonance", "restart", "two_ranks"])
    args = parser.parse_args()
    checks = rs.Checks()
    special = {"resonance": resonance, "restart": restart, "two_ranks": two_ranks}
    if args.case in special:
        special[args.case](args, checks)
        checks.finish()
    f = int(args.case[1:])
    text = se3_scene.edit(rs.read_example(args.source, "strand_spinning_strip.nml"),
                          [("bc", "angular_velocity", rs.vector((2 * math.pi * f, 0.0, 0.0)))])
    r = se3_scene.run(args, text, args.case, ROD)
    t = r["time"]
    tip = r["position"][:, -1, :]
    radius = np.hypot(tip[:, 1], tip[:, 2])
    height = -tip[:, 0]
    relaxed = (RADIUS * math.sin(math.pi / 6), -RADIUS * (1 - math.cos(math.pi / 6)))
    checks.check("relaxed tip at t = 0: largest |(r, z) - (R sin 30°, -R (1 - cos 30°))|",
                 max(abs(radius[0] - relaxed[0]), abs(height[0] - relaxed[1])), 1e-9)
    last = t >= t[-1] - 1.0
    drift = max(np.ptp(radius[last]), np.ptp(height[last]))
    print(f"info: {f} Hz: tip radius {radius[-1]:.6f} m, height {height[-1]:.6f} m at t = "
          f"{t[-1]:.3g} s (methods' rotating-frame statics {STEADY[f]}); motion over the last "
          f"second {drift:.2e} m; {r.summary()}")
    checks.check(f"{f} Hz: tip motion over the last second (steady)", drift, STILL[f])
    checks.check(f"{f} Hz: |tip radius - {STEADY[f][0]}|", abs(radius[-1] - STEADY[f][0]),
                 BOUNDS[f][0])
    checks.check(f"{f} Hz: |tip height - {STEADY[f][1]}|", abs(height[-1] - STEADY[f][1]),
                 BOUNDS[f][1])
    if f == 8:
        # The steady spin's shape (radius and height: the strip's shape in the rotating frame)
        # does not depend on the step: dt = 1 ms lands on the 2 ms tip radius and height to
        # 1e-11 (measured 3e-13 m), so the 6.4e-5 miss of the height above is not this run's
        # time error.
        finer = se3_scene.run(args, se3_scene.edit(text, [("time", "dt", "1.0e-3"),
                                                          ("output", "stride", "50")]),
                              "f8_dt1ms", ROD)
        other = finer["position"][-1, -1]
        change = max(abs(np.hypot(other[1], other[2]) - radius[-1]), abs(-other[0] - height[-1]))
        checks.check("8 Hz: tip radius and height, |dt = 1 ms - dt = 2 ms| (m)", change, 1e-11)
    checks.finish()


if __name__ == "__main__":
    sys.exit(main())
