"""A sliding end (a prismatic support, issue 26 item 3) on se3_pg: input/se3_pg_sliding_shaft.nml,
a straight shaft (L = 1 m, EA = 1e4 N, GJ = 1 N m^2, 16 elements) whose start is driven through
Theta = 25 rad about its axis x while its end slides along x under a dead tension F = 1 N; statics.
The references are closed forms computed here.

    sliding.py tension   at every load step: the axial force N3 of every element equals F to
                         1e-9 relative (the guide takes no axial force; measured 2e-11, the
                         Newton tolerance: a clamped end would take all of it and leave
                         N3 = 0), the torsion moment M3 is GJ Theta(t) / L to 1e-13 (measured
                         4e-15; Theta(t) = 25 t, the ramp), the end has moved by F L / EA along
                         x (1e-11 relative, measured 1e-13) and not across (1e-14 m), its
                         directors are the reference ones (1e-14)
    sliding.py axis      a sliding end whose axis is not a coordinate axis is refused by se3_pg
                         (it eliminates coordinates of r), naming the rod and the axis
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

ROD = "shaft"
F, L, EA, GJ, THETA = 1.0, 1.0, 1e4, 1.0, 25.0


def tension(args, checks):
    text = rs.read_example(args.source, "se3_pg_sliding_shaft.nml")
    r = rs.rod(rs.run(args, text, "sliding"), ROD)
    t = r["time"]
    stress = r["stress"]
    axial = stress[1:, :, 2]
    torsion = stress[1:, :, 5]
    expected_torsion = GJ * THETA * t[1:, None] / L
    end = r["position"][:, -1, :]
    print(f"info: {t.size - 1} load steps; N3 in [{axial.min():.15g}, {axial.max():.15g}] N, "
          f"|M3| at t = 1: {abs(torsion[-1, 0]):.15g} N m, end at x = {end[-1, 0]:.15g} m")
    checks.check("max |N3 / F - 1| over elements and steps", float(np.max(np.abs(axial / F - 1))),
                 1e-9)
    checks.check("max ||M3| / (GJ Theta(t) / L) - 1|",
                 float(np.max(np.abs(np.abs(torsion) / expected_torsion - 1))), 1e-13)
    checks.check("|end x - L - F L / EA| / (F L / EA)",
                 abs(end[-1, 0] - L - F * L / EA) / (F * L / EA), 1e-11)
    checks.check("max |end y|, |end z| [m] (held across the axis)",
                 float(np.max(np.abs(end[:, 1:]))), 1e-14)
    directors = r["directors"][:, -1]
    checks.check("max |end directors - reference| (rotation held)",
                 float(np.max(np.abs(directors - directors[0]))), 1e-14)


def axis(args, checks):
    text = rs.read_example(args.source, "se3_pg_sliding_shaft.nml")
    text = text.replace("kind = 'sliding', axis = 1.0, 0.0, 0.0", "kind = 'sliding', axis = 1.0, 1.0, 0.0")
    status, log = rs.run_failing(args, text, "oblique")
    message = ("rod 'shaft': se3_pg holds the coordinates of r, so a sliding end's axis must be a "
               "coordinate axis (x, y or z); axis = (1.0, 1.0, 0.0)")
    checks.check("exit status is not 0", float(status == 0), 0.0)
    checks.check("the message names the rod and the axis", float(message not in log), 0.0)


def main():
    return rs.run_cases(__doc__, {"tension": tension, "axis": axis})


if __name__ == "__main__":
    sys.exit(main())
