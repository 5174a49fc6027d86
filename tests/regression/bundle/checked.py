"""Every bundle code path under the run-time checks of the Debug build (label `unit`, which CI
runs with -fcheck=all, floating-point traps and the C sanitizers): a small scene with all three
joint kinds, a fixed and a driven end plate, contact and gravity, a few dynamic steps on 1 and
2 ranks (the distributed assembly and stepper). It checks what holds at any step size:

    checked.py run      each rod's energy balance (the coupling work booked as external work,
                        docs/theory/bundles.md) at the Newton tolerance, joined ends together,
                        and the same result on 1 and 2 ranks to 1e-10 (issue 10); the scene
                        with the driving plate held still: the system's energy balance with
                        the work of gravity and of the distributed load computed in the test
                        (load_work), and the booked external work against it

Bounds. The balance error of a step is at most a small multiple of the Newton residual times
the step's motion; with newton_atol = 1e-10 and motions below 1e-2 that is 1e-12 J, and
measured 1.7e-12 J at most (rod d, driven by the plate; 5e-17 ... 5e-13 J on the others):
bound 2e-11 J. Joined positions are linear tie rows: round-off (1e-14 m; measured 0).
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
#: The scene's section and loads: rho A = 1000 kg/m^3 pi (0.01 m)^2, gravity -9.81 e_z on every
#: rod, 50 N/m along -e_z on rod 'e'.
RHO_A = 1000.0 * np.pi * 0.01**2
GRAVITY = np.array([0.0, 0.0, -9.81])
DISTRIBUTED = {"e": np.array([0.0, 0.0, -50.0])}
#: The scene with the driving plate held still (no displacement, no rotation): then the plates
#: and joints do no work on the system, and what enters it is the work of the loads alone.
HELD = SCENE.replace("""displacement = 0, 0, 0.01,
       rotation = 0, 0, 0.1, time_function = 'ramp', t_off = 0.004 /""", "/")
JOINTS = (("a", -1, "b", 0), ("b", -1, "c", 0), ("c", -1, "d", 0))


def line_integral(r):
    """int phi^h ds at every record for the quadratic elements (the default degree 2): Simpson's
    rule l_e/6 (phi_0 + 4 phi_1 + phi_2) per element is exact for them."""
    phi, s = r["position"], r["mesh"]
    length = s[2::2] - s[:-2:2]
    return np.einsum("e,sec->sc", length / 6,
                     phi[:, :-2:2] + 4 * phi[:, 1::2] + phi[:, 2::2])


def load_work(r, name):
    """Work of the dead distributed loads on rod `name` over each step, computed in the test:
    a force per unit length n (gravity rho A g, the distributed load) enters the momentum rows
    as M_phi n (methods/ph_director_3d.md §4.3), whose work over a step is
    h v_mid . M_phi n = n . int (phi_{n+1} - phi_n) ds (h v_mid = phi_{n+1} - phi_n, methods
    §5.2; sum_b M_ab = int N_a ds exactly under 2-point Gauss)."""
    load = RHO_A * GRAVITY + DISTRIBUTED.get(name, 0.0)
    return np.diff(line_integral(r), axis=0) @ load


def held_plate(args, checks):
    """The system's energy balance without the program's balance_error: sum over the rods of
    H_{n+1} - H_n, plus the change of the contact energy, equals the loads' work computed in
    the test (joints and held plates do no work: their tie rows are linear in the positions);
    the external work the program books on the rods (loads plus coupling forces) sums to the
    loads' work minus the change of the contact energy (the contact forces are the discrete
    gradient of the contact energy). Both exact up to the Newton residual and round-off, with
    step works of 1e-3 ... 6e-3 J: measured 1.1e-13 J and 7.7e-17 J, bounds 2e-12 J and
    2e-15 J."""
    r = {name: rs.rod(rs.run(args, HELD, "held_plate"), name) for name in RODS}
    work = sum(load_work(r[name], name) for name in RODS)
    contact = sum(r[name]["series/contact/energy"] for name in RODS)
    total = sum(r[name]["series/energy/total"] for name in RODS)
    booked = sum(r[name]["series/energy/external_work"][1:] for name in RODS)
    print(f"info: held plate: work of the loads per step (test) "
          f"{np.array2string(work, precision=4)} J; contact energy "
          f"{np.array2string(contact, precision=4)} J")
    checks.check("held plate: max_n |sum H_{n+1} - H_n + Delta E_c - W_n (test)| (J)",
                 float(np.max(np.abs(np.diff(total) + np.diff(contact) - work))), 2e-12)
    checks.check("held plate: max_n |sum external_work_n - (W_n (test) - Delta E_c)| (J)",
                 float(np.max(np.abs(booked - work + np.diff(contact)))), 2e-15)
    checks.check("held plate: the loads do work: -min_n |W_n (test)| (J)",
                 -float(np.min(np.abs(work))), -1e-6)


def run(args, checks):
    one = rs.run(args, SCENE, "one_rank")
    two = rs.run(args, SCENE, "two_ranks", ranks=2)
    first = {name: rs.rod(one, name) for name in RODS}
    second = {name: rs.rod(two, name) for name in RODS}
    for name in RODS:
        checks.check(f"rod {name}: largest |energy balance error| of a step (J)",
                     float(np.max(np.abs(first[name]["series/energy/balance_error"]))), 2e-11)
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
    held_plate(args, checks)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["run"])
    args = parser.parse_args()
    checks = rs.Checks()
    run(args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
