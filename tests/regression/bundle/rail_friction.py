"""Friction between rods (issue 24 item 2; docs/theory/bundles.md, "Friction"): a rod lying
along a rail (a thicker rod clamped at both ends) on a slope, the two in line contact.

    rail_friction.py stick   tan(alpha) = 0.2 < mu = 0.3: the rod sticks (creeps below the
                             slip velocity of the regularization)
    rail_friction.py slide   tan(alpha) = 0.5 > mu: it slides along the rail with Coulomb's
                             acceleration g (sin(alpha) - mu cos(alpha)) (1 %, the acceptance
                             of the incline on a plane); also on 2 ranks
    rail_friction.py se3_pg_slide   the slide with both rods on se3_pg

The slope is gravity tilted by alpha about y: both rods lie along x, the rod on top of the rail
(contact radii 5 mm and 10 mm), gravity acts on the rod only, so the rail carries nothing but
the rod. What the theory says (src/contact/contact_potential.f90, Friction): a line contact
whose points slip along the axis carries the friction mu times its normal force whatever the
quadrature, and the balance H + E_contact + D - W_gravity is constant with D the booked
dissipation; the test computes gravity's work from the stored positions of the rod.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                "scripts"))
from costello_strand import line_contact_penetration  # noqa: E402
from slope_friction import check_slope, slope_books  # noqa: E402

RADIUS = 0.005
RAIL_RADIUS = 0.01
LENGTH = 0.2
RAIL_LENGTH = 0.5
MU = 0.3
SLIP_VELOCITY = 1e-4
G = 9.81
RHO_A = 1000.0 * math.pi * RADIUS**2
# Soft enough that the rod sinks about 5 % of the contact distance into the rail, where the
# default contact points resolve the contact patch (rs_contact_element, sliding ripple).
K = 5e5
# se3_pg's residual of the steel rail rounds at 1.5e-7 (its rows are not scaled by h), more
# than 1000 newton_atol = 1e-12 above, where Newton's stagnation test looks.
NEWTON_ATOL = {"ph_director": "1e-12", "se3_pg": "1e-9"}


def scene(tan_alpha, t_end, formulation="ph_director"):
    """The rod centred on the rail at its static distance under the normal weight
    w = rho A g cos(alpha), at rest, both rods on `formulation`."""
    alpha = math.atan(tan_alpha)
    # The line law of the contact potential (scripts/costello_strand.py, rs_contact_element).
    rc = RADIUS + RAIL_RADIUS
    d = rc - line_contact_penetration(RHO_A * G * math.cos(alpha), K, rc)
    return f"""&run
    title = 'a rod sliding along a rail with friction'
/
&time
    t_end = {t_end!r}, dt = 1e-4
/
&solver
    newton_atol = NEWTON_ATOL
/
&output
    path = 'placeholder.h5', stride = 10
/
&rod
    name = 'rail', formulation = 'FORMULATION', n_elements = 16, degree = 2,
    start = {-RAIL_LENGTH / 2!r}, 0, 0, direction = 1, 0, 0, length = {RAIL_LENGTH!r},
    section = 'circle', radius = {RAIL_RADIUS!r}, E = 2e11, nu = 0.3, density = 7800.0
/
&bc rod = 'rail', end = 'start', kind = 'clamped' /
&bc rod = 'rail', end = 'end', kind = 'clamped' /
&rod
    name = 'a', formulation = 'FORMULATION', n_elements = 8, degree = 2,
    start = {-LENGTH / 2!r}, 0, {d!r}, direction = 1, 0, 0, length = {LENGTH!r},
    section = 'circle', radius = {RADIUS!r}, E = 1e8, nu = 0.3, density = 1000.0
/
&load
    rod = 'a', where = 'gravity', acceleration = {G * math.sin(alpha)!r}, 0, {-G * math.cos(alpha)!r}
/
&contact
    stiffness = {K!r}, self_contact = .false., mu = {MU!r}, slip_velocity = {SLIP_VELOCITY!r}
/
""".replace("FORMULATION", formulation).replace("NEWTON_ATOL", NEWTON_ATOL[formulation]), alpha


def run_case(args, checks, case):
    tan_alpha = 0.2 if case == "stick" else 0.5
    t_end = 0.1
    text, alpha = scene(tan_alpha, t_end, "se3_pg" if case == "se3_pg_slide" else "ph_director")
    path = rs.run(args, text, case)
    rod = rs.rod(path, "a")
    rail = rs.rod(path, "rail")
    print(f"info: {case}: tan(alpha) = {tan_alpha}, mu = {MU}")
    t, travel, dissipated = slope_books(checks, case, rod, {"rod": rod, "rail": rail}, alpha,
                                        RHO_A * LENGTH * G, 8, "along the rail")
    # The rail is clamped at both ends and barely moves (its sag under the rod is 1e-8 m).
    checks.check(f"{case}: the rail's largest displacement (m)",
                 float(np.max(np.abs(rail["position"] - rail["position"][0]))), 1e-6)
    if case == "slide":
        # The same run on 2 ranks (the rod and the rail on one rank each, one shared system):
        # the friction's terms and its dissipation from the pairs across the ranks. The two
        # differ by the order of sums only (measured 4.4e-16 m and 5e-14 relative).
        parallel = rs.rod(rs.run(args, text, case + "_2", ranks=2), "a")
        checks.check(f"{case}: max |x (2 ranks) - x (1 rank)| (m)",
                     float(np.max(np.abs(parallel["position"] - rod["position"]))), 1e-14)
        checks.check(f"{case}: |D (2 ranks) / D (1 rank) - 1|",
                     abs(np.sum(parallel["series/energy/dissipated"]) /
                         np.sum(rod["series/energy/dissipated"]) - 1.0), 1e-12)
    check_slope(checks, case, case != "stick", alpha, MU, SLIP_VELOCITY, RHO_A * LENGTH * G,
                t[-1], travel, dissipated, 1e-2, t, rod["series/contact/friction"],
                rod["series/contact/slip_speed"])


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["stick", "slide", "se3_pg_slide"])
    args = parser.parse_args()
    checks = rs.Checks()
    run_case(args, checks, args.case)
    checks.finish()


if __name__ == "__main__":
    main()
