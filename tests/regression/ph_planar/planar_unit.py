"""The planar element test of the authors' code (methods/ph_planar.md §6.4; moofeKIT
tests/testBeamElements.m, not in the paper's text), input/planar_unit.nml.

    planar_unit.py tip   tip displacement (dx, dy, dtheta) at t = 0.2 of PH-EM (ph_planar)
                         = (-0.091077, 0.28976, 0.74456) within 2e-6 per component (methods §10
                         acceptance test 1; the expected values are the authors' code's, given
                         to 5-6 digits, so the band covers their rounding)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import planar  # noqa: E402
from planar import rs  # noqa: E402

EXPECTED = (-0.091077, 0.28976, 0.74456)   # methods §6.4, PH-EM (mixedPH Midpoint)


def tip(args, checks):
    r = rs.rod(rs.run(args, rs.read_example(args.source, "planar_unit.nml"), "tip"), "beam")
    k = planar.record(r, 0.2)
    th = planar.theta(r["directors"])
    got = (r["position"][k, -1, 0] - r["position"][0, -1, 0],
           r["position"][k, -1, 1] - r["position"][0, -1, 1],
           th[k, -1] - th[0, -1])
    print(f"info: tip (dx, dy, dtheta) at t = 0.2: ({got[0]:.8f}, {got[1]:.8f}, {got[2]:.8f})"
          " (prototype (-0.09107714, 0.28976133, 0.7445605))")
    for label, value, expected in zip(("dx", "dy", "dtheta"), got, EXPECTED):
        checks.check(f"|tip {label} - ({expected})|", abs(value - expected), 2e-6)
    checks.check("|tip z| and out-of-plane director components",
                 max(np.max(np.abs(r["position"][:, :, 2])),
                     np.max(np.abs(r["directors"][:, :, 1, :] - [0.0, 0.0, 1.0]))), 1e-14)
    iterations = r["series/newton/iterations"][1:]
    print(f"info: Newton linear solves per step {iterations.tolist()} (methods §6.4: 4 per step)")


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["tip"])
    args = parser.parse_args()
    checks = rs.Checks()
    tip(args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
