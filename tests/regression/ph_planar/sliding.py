"""A sliding end (a prismatic support, issue 26 item 3) on the planar formulations: a rod along x
(input/planar_sliding_beam.nml: L = 1 m, EA = 1e4 N, EI = 1 N m^2, 20 elements), clamped at its
start, whose end slides along x (theta and y held, x free). References are closed forms computed
here.

    sliding.py stretch    statics (ph_planar and cl_em_planar) under a dead end force F = 5 N
                          along x: the end moves by F L / EA (1e-11 relative; measured 1e-13 at the
                          Newton tolerance) and the axial force of every element is F (1e-10)
    sliding.py guide      dynamics (ph_planar): the end force ramped up and a transverse load
                          pulse make the beam swing between its clamp and the guide; at every
                          record the end's y and its directors are the held ones (exactly, by
                          elimination) while its x moves, and the energy balance stays at
                          round-off (1e-13 of max H; measured 8e-15)
    sliding.py axis       an axis that is not along a planar coordinate axis is refused, naming
                          the rod, the plane's axes and the given axis
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

ROD = "beam"
F, L, EA = 5.0, 1.0, 1e4


def scene(args):
    return rs.read_example(args.source, "planar_sliding_beam.nml")


def stretch(args, checks):
    for formulation in ("ph_planar", "cl_em_planar"):
        text = rs.set_variable(scene(args), "rod", "formulation", f"'{formulation}'")
        text = rs.set_variable(text, "time", "quasistatic", ".true.")
        text = rs.set_variable(rs.set_variable(text, "time", "t_end", "1.0"), "time", "dt", "0.1")
        # Only the end force: the transverse pulse's group removed.
        text = text[:text.rindex("&load")]
        r = rs.rod(rs.run(args, text, f"stretch_{formulation}"), ROD)
        end = r["position"][-1, -1, 0]
        axial = r["stress"][-1, :, 2]
        print(f"info: {formulation}: end at x = {end:.15g} m, N3 in [{axial.min():.15g}, "
              f"{axial.max():.15g}] N")
        checks.check(f"{formulation}: |end x - L - F L / EA| / (F L / EA)",
                     abs(end - L - F * L / EA) / (F * L / EA), 1e-11)
        checks.check(f"{formulation}: max |N3 / F - 1|", float(np.max(np.abs(axial / F - 1))), 1e-10)


def guide(args, checks):
    r = rs.rod(rs.run(args, scene(args), "guide"), ROD)
    end = r["position"][:, -1, :]
    directors = r["directors"][:, -1]
    balance = r["series/energy/balance_error"]
    total = r["series/energy/total"]
    print(f"info: end x from {end[0, 0]:.6g} to {end[-1, 0]:.6g} m (range "
          f"{np.ptp(end[:, 0]):.3g}), mid-span y up to {np.max(np.abs(r['position'][:, 10, 1])):.3g} m")
    checks.check("max |end y| [m]", float(np.max(np.abs(end[:, 1]))), 1e-14)
    checks.check("max |end directors - reference|", float(np.max(np.abs(directors - directors[0]))), 1e-14)
    checks.check("the end slides: -(range of end x) [m]", -float(np.ptp(end[:, 0])), -1e-4)
    checks.check("max |balance_error| / max H", float(np.max(np.abs(balance)) / np.max(np.abs(total))),
                 1e-13)


def axis(args, checks):
    text = scene(args).replace("axis = 1.0, 0.0, 0.0", "axis = 1.0, 1.0, 0.0")
    text = rs.set_variable(text, "output", "path", f"'{os.path.join(args.workdir, 'oblique.h5')}'")
    status, log = rs.run_failing(args, text, "oblique")
    message = ("rod 'beam': ph_planar holds the planar coordinates x, y (along e1 = (1.0, 0.0, 0.0), "
               "e2 = (0.0, 1.0, 0.0)), so a sliding end's axis must be one of them; "
               "axis = (1.0, 1.0, 0.0)")
    checks.check("exit status is not 0", float(status == 0), 0.0)
    checks.check("the message names the rod, the plane's axes and the axis", float(message not in log), 0.0)


def main():
    return rs.run_cases(__doc__, {"stretch": stretch, "guide": guide, "axis": axis})


if __name__ == "__main__":
    sys.exit(main())
