"""Quasistatic ph_director runs end on the equilibrium branch connected to the unloaded state
(issue 21 item 11; DESIGN.md §3 "Quasistatics", docs/theory/ph_director.md "Quasistatics").

    statics_increments.py unramped      the cantilever of seed 000 §6.3 (input/elastica_
                                        inextensible.nml) under twice its loads, applied at once
                                        (time_function = 'constant'): one load step and 100 load
                                        steps end on the same equilibrium, the one of the
                                        elastica followed from the unloaded rod
    statics_increments.py hanging_rope  a rope clamped at both ends, given as a V-shaped
                                        polyline, under its weight from t = 0: the states do not
                                        alternate from step to step, the shape is the catenary
                                        and the tension at the clamps the catenary's

Before the fix (midpoint load steps from the unloaded state, one Newton solve at the end):
the unramped cantilever in one step ended on a folded state with the tip at (2.80, -4.72)
instead of (4.38, -3.52) and twice the strain energy, and with dt = 0.01 the run failed at
t = 0; the rope with dt = 0.1 failed at t = 0 (and from a polyline through a parabola its load
steps alternated between the weightless shape and one with four times the strain energy, 0.0060
and 0, until Newton failed at t = 0.2).

Why: with no inertia the midpoint steps balance the loads at the mid state, so a state not in
equilibrium with the loads at t_n is reflected, x_{n+1} = 2 x_mid - x_n, at every step. A
quasistatic run now starts with the equilibrium at the loads of t = 0, continued from the
initial shape in a pseudo-time, with increments halved when Newton fails or a cross-section
turns by more than a quarter radian (rod_run.F90, continue_equilibrium).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_scene as rs  # noqa: E402
import elastica_reference as reference  # noqa: E402

#: The loads of seed 000 §6.3 scaled by 2: the tip rotates by 0.75 rad and the rod by more than
#: a radian along its length, and Newton from the straight rod at the full load converges to
#: another equilibrium (measured before the fix).
LOAD_FACTOR = 2.0


def last_state(r):
    return np.concatenate([r["position"][-1].ravel(), r["directors"][-1].ravel()])


def elastica_run(args, name, dt, n_elements=8):
    text = rs.read_example(args.source, "elastica_inextensible.nml")
    force = (0.0, -LOAD_FACTOR * reference.P, 0.0)
    text = rs.set_variable(text, "load", "force", rs.vector(force))
    text = rs.set_variable(text, "load", "moment",
                           rs.vector((0.0, 0.0, LOAD_FACTOR * reference.TIP_MOMENT)))
    text = text.replace("time_function = 'ramp', t_on = 0.0, t_off = 1.0",
                        "time_function = 'constant'")
    text = rs.set_variable(text, "time", "dt", repr(dt))
    text = rs.set_variable(text, "rod", "n_elements", str(n_elements))
    return rs.rod(rs.run(args, text, name), "cantilever")


def unramped(args, checks):
    one = elastica_run(args, "unramped_1_step", 1.0)
    many = elastica_run(args, "unramped_100_steps", 0.01)
    for r, label in ((one, "1 step"), (many, "100 steps")):
        assert abs(r["time"][-1] - 1.0) < 1e-12, f"{label}: last record at {r['time'][-1]}"
    checks.check("last record, 1 step against 100 steps: max |position|, |directors|",
                 float(np.max(np.abs(last_state(one) - last_state(many)))), 1e-8)
    checks.check("last record, 1 step against 100 steps: max |stress|",
                 float(np.max(np.abs(one["stress"][-1] - many["stress"][-1]))), 1e-8)
    # The load is constant: every record, t = 0 included, is the same equilibrium (no
    # alternation of the midpoint steps).
    states = np.array([np.concatenate([p.ravel(), d.ravel()])
                       for p, d in zip(many["position"], many["directors"])])
    checks.check("100 steps: max over the records of |state - last state|",
                 float(np.max(np.abs(states - states[-1]))), 1e-8)
    exact = reference.solve(force=(0.0, -LOAD_FACTOR * reference.P),
                            moment=LOAD_FACTOR * reference.TIP_MOMENT)
    tip = one["position"][-1, -1, :2]
    error8 = float(np.max(np.abs(tip - exact["tip"])))
    print(f"info: tip (1 step, n_e = 8) ({tip[0]:.6f}, {tip[1]:.6f}); elastica followed from "
          f"the unloaded rod ({exact['tip'][0]:.6f}, {exact['tip'][1]:.6f}); the other "
          f"branch that one Newton solve found before the fix: (2.796, -4.721)")
    # The discretization error of 8 quadratic elements (order 4 at the tip, elastica.py): the
    # other branch is 1.6 away.
    checks.check("n_e = 8: max component |tip - elastica| (discretization error)", error8, 2e-2)
    fine = elastica_run(args, "unramped_1_step_ne16", 1.0, n_elements=16)
    error16 = float(np.max(np.abs(fine["position"][-1, -1, :2] - exact["tip"])))
    order = math.log2(error8 / error16)
    print(f"info: tip error n_e = 8: {error8:.3e}, n_e = 16: {error16:.3e}, order {order:.2f}")
    checks.check("observed order of the tip in n_e (4 for degree 2): |order - 4|",
                 abs(order - 4.0), 0.5)


# The rope: span 1.6 between two clamps at the same height, length 2, weight w = rhoA g = 1 per
# length; stiff axially (EA = GA = 1e4: strains of 1e-4) and soft in bending (EI = 1e-3).
SPAN, LENGTH, WEIGHT, EI = 1.6, 2.0, 1.0, 1e-3


def rope_points():
    """The V of length LENGTH between the clamps (two segments of length 1, depth 0.6): a shape
    that does not hang that way (0.11 from the catenary), stress-free (prestressed = .false.),
    so its kink stays in the reference."""
    return np.array([[0.0, 0.0, 0.0], [SPAN / 2, 0.0, -0.6], [SPAN, 0.0, 0.0]])


def catenary_parameter():
    """a of the inextensible catenary z = a cosh((x - SPAN/2)/a) + c through both clamps with
    arc length LENGTH: 2 a sinh(SPAN / (2 a)) = LENGTH, by Newton."""
    a, b, s = 0.5, SPAN / 2, LENGTH / 2
    for _ in range(100):
        f = a * math.sinh(b / a) - s
        a -= f / (math.sinh(b / a) - (b / a) * math.cosh(b / a))
    return a


def rope_scene(dt):
    points = rope_points()
    return f"""&run
    title = 'hanging rope'
/
&time
    t_end = 1.0
    dt = {dt}
    quasistatic = .true.
/
&solver
    newton_atol = 1e-10
/
&output
    path = 'out/hanging_rope.h5'
/
&rod
    name = 'rope'
    formulation = 'ph_director'
    n_elements = 16, degree = 2, n_gauss = 2
    geometry = 'polyline'
    points = {rs.vector(points.ravel())}
    EA = 1e4, GA1 = 1e4, GA2 = 1e4
    EI1 = {EI}, EI2 = {EI}, GJ = {EI}
    rhoA = {WEIGHT}, rhoI1 = 1.0, rhoI2 = 1.0
/
&bc
    rod = 'rope', end = 'start', kind = 'clamped'
/
&bc
    rod = 'rope', end = 'end', kind = 'clamped'
/
&load
    where = 'gravity'
    acceleration = 0.0, 0.0, -1.0
/
"""


def hanging_rope(args, checks):
    runs = {dt: rs.rod(rs.run(args, rope_scene(dt), f"rope_dt{dt}"), "rope") for dt in (1.0, 0.1)}
    a, b = runs[1.0], runs[0.1]
    checks.check("last record, dt = 1 against dt = 0.1: max |position|, |directors|",
                 float(np.max(np.abs(last_state(a) - last_state(b)))), 1e-8)
    energy = b["series/energy/strain"]
    print(f"info: strain energy of the records (dt = 0.1): {np.array2string(energy, precision=6)}")
    checks.check("dt = 0.1: max over the records of |strain energy - last| (no alternation)",
                 float(np.max(np.abs(energy - energy[-1]))), 1e-10)
    ca = catenary_parameter()
    # Statics alone: the tension at a clamp is the catenary's w a cosh(SPAN / (2 a)) whatever
    # the bending near it, up to the shift of the shape (below) over the rope's length.
    clamp_tension = WEIGHT * ca * math.cosh(SPAN / (2 * ca))
    axial = b["stress"][-1][:, 2]
    print(f"info: axial force N3 from {axial.min():.6f} to {axial.max():.6f}; catenary: "
          f"H = w a = {WEIGHT * ca:.6f} at the bottom, {clamp_tension:.6f} at the clamps")
    checks.check("|largest axial force / catenary's tension at the clamps - 1|",
                 abs(axial.max() / clamp_tension - 1), 5e-3)
    x, z = b["position"][-1, :, 0], b["position"][-1, :, 2]
    catenary = ca * np.cosh((x - SPAN / 2) / ca) - ca * math.cosh(SPAN / (2 * ca))
    deviation = float(np.max(np.abs(z - catenary)))
    # The rod is not a rope: at each clamp its end keeps the slope of the polyline's first
    # segment, 36.9 degrees, where the catenary's is atan(sinh(SPAN / (2a))) = 56.5 degrees, and
    # bending turns it over the boundary-layer length sqrt(EI / H) with H = w a the horizontal
    # tension (0.038); the stress-free kink of the V relaxes over the same length. The
    # centreline is off the catenary by about that length times the slope difference; the axial
    # strain (1e-4) and the mesh add less.
    tension = WEIGHT * ca
    slope_gap = math.atan(math.sinh(SPAN / (2 * ca))) - math.atan2(
        -rope_points()[1, 2], rope_points()[1, 0])
    estimate = math.sqrt(EI / tension) * abs(slope_gap)
    print(f"info: catenary a = {ca:.6f}, sag {ca * (math.cosh(SPAN / (2 * ca)) - 1):.6f}; rope "
          f"sag {-z.min():.6f}; max |z - catenary| {deviation:.3e}; boundary-layer estimate "
          f"sqrt(EI/H) |slope gap| = {estimate:.3e}")
    checks.check("max |z - catenary| / (boundary-layer estimate sqrt(EI/H) |slope gap|)",
                 deviation / estimate, 2.0)
    checks.check("the test can tell the polyline from the catenary: -max |z_polyline - "
                 "catenary| / estimate", -float(np.max(np.abs(
                     rope_points()[:, 2] - (ca * np.cosh((rope_points()[:, 0] - SPAN / 2) / ca)
                                            - ca * math.cosh(SPAN / (2 * ca)))))) / estimate,
                 -4.0)


def main():
    cases = {"unramped": unramped, "hanging_rope": hanging_rope}
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=sorted(cases))
    args = parser.parse_args()
    checks = rs.Checks()
    cases[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
