"""Every bundle code path under the run-time checks of the Debug build (label `unit`, which CI
runs with -fcheck=all, floating-point traps and the C sanitizers): a small scene with all three
joint kinds, a fixed and a driven end plate, contact and gravity, a few dynamic steps on 1 and
2 ranks (the distributed assembly and stepper). It checks what holds at any step size:

    checked.py run      each rod's energy balance (the coupling work booked as external work,
                        docs/theory/bundles.md) at the Newton tolerance, joined ends together,
                        and the same result on 1 and 2 ranks to 1e-10 (issue 10)

Bounds. The balance error of a step is at most a small multiple of the Newton residual times
the step's motion; with newton_atol = 1e-10 and motions below 1e-2 the bound 1e-9 J is wide
(measured about 1e-13 J). Joined positions are linear tie rows: round-off (1e-14 m).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

SCENE = """
&time t_end = 0.004, dt = 1e-3 /
&solver newton_atol = 1e-10 /
&output
    stride = 1
/
&rod name = 'a', formulation = 'ph_director', n_elements = 4, start = 0, 0, 0,
     direction = 1, 0, 0, length = 0.5, section = 'circle', radius = 0.01, E = 1e9, nu = 0.3,
     density = 1000 /
&rod name = 'b', formulation = 'ph_director', n_elements = 4, start = 0.5, 0, 0,
     direction = 0, 1, 0, length = 0.5, section = 'circle', radius = 0.01, E = 1e9, nu = 0.3,
     density = 1000 /
&rod name = 'c', formulation = 'ph_director', n_elements = 4, start = 0.5, 0.5, 0,
     direction = 0, 0, 1, length = 0.5, section = 'circle', radius = 0.01, E = 1e9, nu = 0.3,
     density = 1000 /
&rod name = 'd', formulation = 'ph_director', n_elements = 4, start = 0.5, 0.5, 0.5,
     direction = -1, 0, 0, length = 0.5, section = 'circle', radius = 0.01, E = 1e9, nu = 0.3,
     density = 1000 /
&rod name = 'e', formulation = 'ph_director', n_elements = 4, start = 0.25, -0.1, 0.021,
     direction = 0, 1, 0, length = 0.2, section = 'circle', radius = 0.01, E = 1e9, nu = 0.3,
     density = 1000 /
&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = 'rigid' /
&joint rod_a = 'b', end_a = 'end', rod_b = 'c', end_b = 'start', kind = 'spherical' /
&joint rod_a = 'c', end_a = 'end', rod_b = 'd', end_b = 'start', kind = 'revolute',
       axis = 0, 1, 0 /
&plate name = 'ground', rods = 'a', end = 'start' /
&plate name = 'driver', rods = 'd', end = 'end', displacement = 0, 0, 0.01,
       rotation = 0, 0, 0.1, time_function = 'ramp', t_off = 0.004 /
&load where = 'gravity', acceleration = 0, 0, -9.81 /
&load rod = 'e', where = 'distributed', force = 0, 0, -50 /
&contact stiffness = 1e12 /
"""

RODS = ("a", "b", "c", "d", "e")
JOINTS = (("a", -1, "b", 0), ("b", -1, "c", 0), ("c", -1, "d", 0))


def run(args, checks):
    one = rs.run(args, SCENE, "one_rank")
    two = rs.run(args, SCENE, "two_ranks", ranks=2)
    first = {name: rs.rod(one, name) for name in RODS}
    second = {name: rs.rod(two, name) for name in RODS}
    for name in RODS:
        checks.check(f"rod {name}: largest |energy balance error| of a step (J)",
                     float(np.max(np.abs(first[name]["series/energy/balance_error"]))), 1e-9)
    for a, end_a, b, end_b in JOINTS:
        gap = np.max(np.abs(first[a]["position"][:, end_a] - first[b]["position"][:, end_b]))
        checks.check(f"joint {a}-{b}: largest distance of the joined ends (m)", float(gap), 1e-14)
    moved = max(float(np.max(np.abs(first[n]["position"][-1] - first[n]["position"][0])))
                for n in RODS)
    checks.check("the bundle moved (the checks can fail): -max |phi(t_end) - phi(0)|", -moved,
                 -1e-6)
    contact = max(float(np.max(first[n]["series/contact/energy"])) for n in RODS)
    checks.check("contact acted: -max contact energy share (J)", -contact, -1e-12)
    for name in RODS:
        difference = np.max(np.abs(first[name]["position"] - second[name]["position"]))
        checks.check(f"rod {name}: max |position(1 rank) - position(2 ranks)| (m)",
                     float(difference), 1e-10)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["run"])
    args = parser.parse_args()
    checks = rs.Checks()
    run(args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
