"""A 1+6 strand pulled by its end plates: input/bundle_seven_wire.nml (issue 10 acceptance;
docs/theory/bundles.md "Reference: Costello's strand theory" and "Joints and strands:
validation").

    seven_wire_strand.py two_ranks           the same run on 1 and 2 ranks (METIS partition,
                                             distributed assembly, parallel MUMPS) gives the
                                             same positions and directors to 1e-10 relative
    seven_wire_strand.py stiffness           axial stiffness under small tension against
                                             Costello's linear theory, the scene as it is (the
                                             default contact points)
    seven_wire_strand.py se3_pg_stiffness    the same strand of se3_pg wires (issue 22 item 5):
                                             Costello as for ph_director, and ph_director's
                                             stiffness within the discretization difference
    seven_wire_strand.py block_jacobi        the strand dynamic (the bench's scene: dt = 1e-5 s,
                                             its pull ramped): the linear solver is then GMRES
                                             with block Jacobi over the rods (issue 23; the
                                             default for dynamic systems of 7 or more rods
                                             without joints); against the direct LU (MUMPS)
                                             of the whole system, and on 2 ranks
    seven_wire_strand.py stiffness_resolved  the same with the contact patch resolved
                                             (points_per_element = 100): against the rod
                                             model's own reference to 0.2 % (label slow)

The axial force on the strand is the force of the top plate on the rods: the sum over the rods
of the z component of series/ties/force[:, 1] (index 1 is a rod's end, tied to the plate
'top'; the force ON the rod, so positive in tension). Only the last record of a quasistatic run
is an equilibrium (the endpoint solve at t_end; earlier records are midpoint-path states), so
each load level is its own run: the scene at eps = pull / L = 1e-3 and the same with the pull
raised to eps = 1.1e-3. The stiffness is the slope (F(1.1e-3) - F(1e-3)) / (1e-4) (a tangent
at 1.05e-3: the penalty's secant is softer than its tangent, docs/theory/bundles.md) and the
secant F / eps at 1e-3 is reported too.

The torque the held top plate exerts (the twist coupling with the rotation held) is the
torque carried through the strand (section_torque: from the wires' stress resultants); its
slope K_m between the same two runs is checked too.

References (scripts/costello_strand.py with the scene's radii, lay angle, E and nu, ends held
against rotation, beta = 0):
- K_C: Costello's linear theory (Poisson contraction, wire bending and torsion);
- K_rod: the same kinematics as the rod model (no Poisson contraction, strains per reference
  length, rigid contact): K_rod / K_C - 1 = +1.11 % (the model has no Poisson contraction);
- K_pen: K_rod with the helical wires sinking into the core by the continuous penalty line
  contact law (penalty_secant_stiffness), the tangent taken between the same two strains as
  in the runs. This is the rod model's own prediction; K_pen / K_rod - 1 = -0.55 % at k = 1e17;
- K_m,pen: the torque of the same model (linear_response with the penalty approach); Costello's
  K_m is 5.4 % below it (Poisson contraction and curvature measure), so it is printed, not
  checked.
Tolerances (docs/theory/bundles.md, "Costello's theory and the rodsolve model", items 3-7):
- stiffness (the scene): K / K_C - 1 must lie in (K_pen / K_C - 1) +- 1 %, i.e. K within 1 %
  of the model's own K_pen. The model differences are known in sign and size (+1.11 % Poisson,
  -0.53 % penalty tangent). The scene's default contact points (spacing 0.29 mm) do not resolve
  the contact patch (half-width a = sqrt(2 r_c delta) = 54 um): the load concentrates on few
  point pairs and the wires sink deeper than the continuous law says (1.6 times; both are
  printed). The penalty's tangent deficit scales with the penetration, so this may add up to
  one more deficit, 0.55 % (at twice the penetration); with end effects (< 0.1 %: clamped
  ends, one pitch; doubling the length changed K by 2e-4), the discrete helix reference
  (< 0.1 % at 16 elements per pitch) and geometric nonlinearity (5e-5) the sum is 0.76 %.
  A strand missing a wire (-14 %), straight wires (+7 %) or wires that do not press on the
  core would fail.
- stiffness_resolved: |K / K_pen - 1| <= 0.2 %: with 100 contact points per element (spacing
  0.72 a) the sampling error is what 100 -> 150 points changes (4.5e-4 measured), plus end
  effects (2e-4 measured), mesh (16 -> 32 elements per pitch changes K by 7e-5) and
  nonlinearity (5e-5): 0.08 %, with the contact law's remaining departure from the continuous
  one (the deepest penetration is 1.09 times the law's, printed) for the rest.
- torque: |K_m / K_m,pen - 1| <= 1.5 % (scene) and 1 % (resolved). The torque is 1.3 times as
  sensitive to the penalty approach as the force (dM/M = -1.75 %, dF/F = -1.36 % for the same
  delta), so the unresolved patch's allowance becomes 0.7 % (0.06 % resolved); the exact helix
  kinematics (costello_strand.exact_response) lower the tangent K_m by 0.3 % at these strains
  (the force by 0.02 %); the clamped ends lower K_m of a one-pitch strand by about 0.3 %
  (doubling the length raised it by 0.16 %; the force changed by 2e-4). Sums: 1.3 % and 0.66 %.
  The torque itself is exact by equilibrium (its spread along the wires, about 1e-4, is
  printed).
- equilibrium: the rods carry no load but the plates' and contact is internal, so the forces
  of the two plates on the strand sum to zero to the Newton residual (1e-10 N) per record:
  bound 1e-9 of the axial force. The transverse force of the top plate vanishes by the
  six-fold symmetry to the same bound.
- two ranks: issue 10 acceptance, 1e-10 of the largest |position| (positions) and absolute
  (directors); DESIGN.md §5 allows a small multiple of the Newton tolerance for coupled runs
  with parallel MUMPS. The tie forces (the plates' multipliers) to 1e-10 of the largest: they
  are forces, the residual rows they balance are forces and the Newton stop is 1e-10 N, so
  1e-10 relative (4e-7 N) leaves a factor 4000 over that stop. Rods must sit on rank 1 (the
  partition lines of the log), so that ties and contact pairs cross ranks.
"""
import math
import os
import re
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import run_scene as rs  # noqa: E402

SCENE = "bundle_seven_wire.nml"
RODS = ("core", "w1_1", "w1_2", "w1_3", "w1_4", "w1_5", "w1_6")
RAISED = 1.1   # the second load level, in units of the scene's pull
N_ELEMENTS = 16  # elements of every rod in the scene (--elements-per-pitch 16, one pitch)


def scene_value(text, name):
    return float(re.search(name + r"\s*=\s*([-0-9.eE+]+)", text).group(1))


def rod_group(text, name):
    start = text.index(f"name = '{name}'")
    return text[start:text.index("\n/", start)]


def strand_parameters(text):
    """Core radius R1, wire radius R2, lay angle (tan = 2 pi r / pitch of wire w1_1), E, nu."""
    core, wire = rod_group(text, "core"), rod_group(text, "w1_1")
    r1 = scene_value(core, r"\bradius")
    r2 = scene_value(wire, r"\bradius")
    lay = math.atan2(2 * math.pi * scene_value(wire, "helix_radius"),
                     scene_value(wire, "helix_pitch"))
    return r1, r2, lay, scene_value(wire, r"\bE"), scene_value(wire, r"\bnu")


def pulled(text, factor):
    """The scene with the top plate's pull multiplied by factor."""
    match = re.search(r"(displacement = 0\.0, 0\.0, )([-0-9.eE+]+)", text)
    return text[:match.start(2)] + repr(factor * float(match.group(2))) + text[match.end(2):]


def costello():
    sys.path.insert(0, os.path.join(ARGS.source, "scripts"))
    import costello_strand  # noqa: E402
    return costello_strand


def plate_moments(path):
    """The moments about the origin of the top and the bottom plate on the strand at the last
    record, from the ties' forces and moments on the rods' ends (series/ties/force, moment)."""
    top, bottom = np.zeros(3), np.zeros(3)
    for name in RODS:
        fields = rs.rod(path, name)
        x, force, moment = (fields["position"][-1], fields["series/ties/force"][-1],
                            fields["series/ties/moment"][-1])
        bottom += np.cross(x[0], force[0]) + moment[0]
        top += np.cross(x[-1], force[1]) + moment[1]
    return top, bottom


def plate_forces(path):
    """Axial force of the top plate on the strand, the transverse force and the sum of both
    plates' forces, at the last record (the endpoint equilibrium), and the deepest penetration."""
    fields = {name: rs.rod(path, name) for name in RODS}
    top = sum(fields[name]["series/ties/force"][-1, 1] for name in RODS)
    bottom = sum(fields[name]["series/ties/force"][-1, 0] for name in RODS)
    penetration = max(fields[name]["series/contact/penetration"][-1] for name in RODS)
    core = fields["core"]["position"]
    strain = (core[-1, -1, 2] - core[-1, 0, 2]) / (core[0, -1, 2] - core[0, 0, 2]) - 1.0
    return top, bottom, penetration, strain


def section_torque(path, n_elements=N_ELEMENTS):
    """Torque about e_z carried through the strand at its last record: per rod, the median over
    its stress points of (x x n)_z + m_z, n = N_i d_i and m = M_i d_i the stress resultants
    (material components, docs/user/output.md) with the position and directors interpolated
    at the point (Lagrange, the element's nodes); summed over the rods. By equilibrium it is
    the torque of the top plate on the strand: frictionless contact with the straight core
    pushes a wire towards the axis, so it has no moment about it, and each wire's torque is
    constant along it (the median leaves out the few points next to the clamped ends, where
    the pointwise stresses of the discretization deviate). Also the largest relative spread
    of the middle half of a helical wire's points (the core carries no torque)."""
    total, spread = 0.0, 0.0
    for name in RODS:
        fields = rs.rod(path, name)
        x, d = fields["position"][-1], fields["directors"][-1]
        stress, points, mesh = fields["stress"][-1], fields["stress_mesh"], fields["mesh"]
        degree = (x.shape[0] - 1) // n_elements
        per_element = points.size // n_elements
        torque = np.empty(points.size)
        for k, s_point in enumerate(points):
            e = k // per_element
            nodes = slice(e * degree, e * degree + degree + 1)
            local = mesh[nodes]
            shape = np.array([np.prod([(s_point - local[j]) / (local[i] - local[j])
                                       for j in range(degree + 1) if j != i])
                              for i in range(degree + 1)])
            position = shape @ x[nodes]
            directors = np.einsum("a,aij->ij", shape, d[nodes])
            force, moment = stress[k, :3] @ directors, stress[k, 3:] @ directors
            torque[k] = np.cross(position, force)[2] + moment[2]
        median = np.median(torque)
        total += median
        middle = torque[points.size // 4: 3 * points.size // 4]
        if name != "core":
            spread = max(spread, np.max(np.abs(middle - median)) / abs(median))
    return total, spread


def stiffness(args, checks, points=None, tolerance=0.01, torque_tolerance=0.015, scene=SCENE,
              n_elements=N_ELEMENTS, tag="stiffness"):
    """The tangent stiffness and torque of the scene against the references; returns the
    tangent K."""
    cs = costello()
    text = rs.read_example(args.source, scene)
    if points is not None:
        text = rs.set_variable(text, "contact", "points_per_element", str(points))
        tag = f"{tag}_p{points}"
    r1, r2, lay, young, nu = strand_parameters(text)
    k = scene_value(text, "stiffness")
    paths = [rs.run(args, text, f"{tag}_eps1"), rs.run(args, pulled(text, RAISED), f"{tag}_eps2")]
    (f1, b1, pen1, eps1), (f2, b2, pen2, eps2) = [plate_forces(path) for path in paths]
    (m1, spread1), (m2, spread2) = [section_torque(path, n_elements) for path in paths]
    # The plates' moments from the ties (series/ties/moment): in equilibrium they cancel, and
    # the top plate's torque about the axis is the torque carried through the strand, which
    # section_torque takes from the wires' stresses instead (its spread along the wires,
    # about 1e-4, bounds the agreement: measured 7e-5 on ph_director, 6.5e-4 on se3_pg).
    # Equilibrium holds to the Newton tolerance's share (measured 2e-15 to 7e-15).
    for label, path, torque in (("eps1", paths[0], m1), ("eps2", paths[1], m2)):
        top_moment, bottom_moment = plate_moments(path)
        print(f"info: {label}: the plates' moments about the origin from the ties: top "
              f"{top_moment}, bottom {bottom_moment} N m; section torque {torque:.6f} N m")
        checks.check(f"{label}: |M_top + M_bottom| / |M_top,z| (static equilibrium, from the "
                     "ties' moments)", np.linalg.norm(top_moment + bottom_moment) /
                     abs(top_moment[2]), 1e-13)
        checks.check(f"{label}: |M_top,z (ties) / section torque (stresses) - 1|",
                     abs(top_moment[2] / torque - 1.0), 1e-2)
    length = scene_value(text[text.index("name = 'core'"):], "length")
    pull = float(re.search(r"displacement = 0\.0, 0\.0, ([-0-9.eE+]+)", text).group(1))
    checks.check("strain of the run |eps - pull / L| (the plate moved the core's end)",
                 abs(eps1 - pull / length), 1e-12)
    for label, top, bottom in (("eps1", f1, b1), ("eps2", f2, b2)):
        checks.check(f"{label}: |F_top + F_bottom| / F_z (static equilibrium of the strand)",
                     np.linalg.norm(top + bottom) / top[2], 1e-9)
        checks.check(f"{label}: |transverse F_top| / F_z (six-fold symmetry)",
                     np.linalg.norm(top[:2]) / top[2], 1e-9)
    tangent = (f2[2] - f1[2]) / (eps2 - eps1)
    secant = f1[2] / eps1
    k_c = cs.costello_axial_stiffness(r1, r2, lay, young, nu)["K_eps"]
    k_rod = cs.costello_axial_stiffness(r1, r2, lay, young, nu, poisson_contraction=False,
                                        curvature_measure="reference")["K_eps"]
    s1, delta1, p1 = cs.penalty_secant_stiffness(r1, r2, lay, young, nu, k, eps1)
    s2, delta2, _ = cs.penalty_secant_stiffness(r1, r2, lay, young, nu, k, eps2)
    k_pen = (s2 * eps2 - s1 * eps1) / (eps2 - eps1)
    print(f"info: R1 = {r1:.6e} m, R2 = {r2:.6e} m, lay angle {math.degrees(lay):.6f} deg, "
          f"E = {young:g} Pa, nu = {nu:g}, k = {k:g} N/m^3, L = {length:.6e} m, eps = {eps1:.4e}, "
          f"{eps2:.4e}")
    print(f"info: F_z = {f1[2]:.6f} N, {f2[2]:.6f} N; tangent K = {tangent:.6e} N, secant "
          f"F / eps = {secant:.6e} N")
    print(f"info: Costello K_C = {k_c:.6e} N (K / K_C - 1 = {tangent / k_c - 1:+.4%}); rod "
          f"kinematics K_rod = {k_rod:.6e} N ({tangent / k_rod - 1:+.4%}); with the penalty "
          f"K_pen = {k_pen:.6e} N ({tangent / k_pen - 1:+.4%}; K_pen / K_C - 1 = "
          f"{k_pen / k_c - 1:+.4%}); secant {secant:.6e} N against the penalty secant "
          f"{s1:.6e} N ({secant / s1 - 1:+.4%})")
    print(f"info: deepest penetration {pen1:.4e} m, {pen2:.4e} m; continuous line contact "
          f"{delta1:.4e} m, {delta2:.4e} m (line load {p1:.1f} N/m)")
    # Torque with the rotation held: the model's own reference (K_m of the linear theory with
    # the penalty approach delta, as for the force); Costello's K_m is 6.5 % lower (Poisson
    # contraction and curvature measure, docs/theory/bundles.md), so it is not the reference.
    geometry = cs._geometry(r1, r2, lay, young, nu, 6)
    model = dict(poisson_contraction=False, curvature_measure="reference")
    torque_pen = [cs.linear_response(geometry, eps, 0.0, extra_approach=delta, **model)["M"]
                  for eps, delta in ((eps1, delta1), (eps2, delta2))]
    km = (m2 - m1) / (eps2 - eps1)
    km_pen = (torque_pen[1] - torque_pen[0]) / (eps2 - eps1)
    km_c = cs.costello_axial_stiffness(r1, r2, lay, young, nu)["K_m"]
    print(f"info: torque {m1:.6f} N m, {m2:.6f} N m (spread along the wires {spread1:.1e}, "
          f"{spread2:.1e}); tangent K_m = {km:.2f} N m against K_m,pen = {km_pen:.2f} N m "
          f"({km / km_pen - 1:+.3%}) and Costello {km_c:.2f} N m ({km / km_c - 1:+.3%}); secant "
          f"M / eps = {m1 / eps1:.2f} N m against {torque_pen[0] / eps1:.2f} N m")
    checks.check(f"|K_m / K_m,pen - 1| (torque of the held plate; tolerance "
                 f"{torque_tolerance:.1%})",
                 abs(km / km_pen - 1), torque_tolerance)
    if points is None:
        expected = k_pen / k_c - 1
        checks.check(f"|(K / K_C - 1) - ({expected:+.3%})|: Costello, after the model's known "
                     f"differences (no Poisson contraction {k_rod / k_c - 1:+.2%}, penalty "
                     f"{k_pen / k_rod - 1:+.2%})", abs(tangent / k_c - 1 - expected), tolerance)
    else:
        checks.check(f"|K / K_pen - 1| (the rod model's own reference, tolerance {tolerance:.1%})",
                     abs(tangent / k_pen - 1), tolerance)
    return tangent


def se3_pg_stiffness(args, checks):
    """The se3_pg strand (input/se3_pg_seven_wire.nml: 64 two-node elements per wire; its
    header says why not 32) against the same references and tolerances
    (stiffness's docstring: the model's departures from Costello are the rod model's, not the
    formulation's), and against ph_director's strand: both discretize the same rod model (shear
    and extension, stress-free helical references, the same contact law and points), so their
    stiffnesses differ by their discretization errors only: se3_pg's helix is exact (constant
    strains per element) where ph_director's quadratic elements interpolate it (< 0.1 % at 16
    per pitch), and the contact points sit on se3_pg's chords rather than on ph_director's
    parabolas, which moves the penetration the tangent depends on; tolerance 0.5 %."""
    k_se3 = stiffness(args, checks, scene="se3_pg_seven_wire.nml", n_elements=64,
                      tag="se3_pg_stiffness")
    k_ph = stiffness(args, checks, tag="ph_director_stiffness")
    print(f"info: tangent K: se3_pg {k_se3:.6e} N, ph_director {k_ph:.6e} N "
          f"({k_se3 / k_ph - 1:+.4%})")
    checks.check("|K(se3_pg) / K(ph_director) - 1| (discretization difference, tolerance 0.5 %)",
                 abs(k_se3 / k_ph - 1), 0.005)


def two_ranks(args, checks):
    text = rs.read_example(args.source, SCENE)
    one = rs.run(args, text, "one_rank")
    two_path, log = rs.run(args, text, "two_ranks", ranks=2, want_log=True)
    partition = [line for line in log.splitlines()
                 if "rank 1:" in line]
    print("info: " + "\ninfo: ".join(partition[:8]))
    checks.check("the 2-rank run puts rods on rank 1 (log lines naming rank 1)",
                 -float(len(partition)), -1.0)
    first = {name: rs.rod(one, name) for name in RODS}
    scale = max(np.max(np.abs(first[name]["position"])) for name in RODS)
    force_scale = max(np.max(np.abs(first[name]["series/ties/force"])) for name in RODS)
    for name in RODS:
        a, b = first[name], rs.rod(two_path, name)
        checks.check(f"{name}: records on 1 and 2 ranks differ in number",
                     abs(a["time"].size - b["time"].size), 0)
        checks.check(f"{name}: max |position(1 rank) - position(2 ranks)| / max |position|",
                     np.max(np.abs(a["position"] - b["position"])) / scale, 1e-10)
        checks.check(f"{name}: max |directors(1 rank) - directors(2 ranks)|",
                     np.max(np.abs(a["directors"] - b["directors"])), 1e-10)
        checks.check(f"{name}: max |tie force(1 rank) - tie force(2 ranks)| / max |tie force|",
                     np.max(np.abs(a["series/ties/force"] - b["series/ties/force"])) / force_scale,
                     1e-10)
    moved = np.max(np.abs(first["w1_1"]["position"][-1] - first["w1_1"]["position"][0]))
    checks.check("the wires moved (the comparison can fail): max |phi(1) - phi(0)| > 1e-6 m",
                 -moved, -1e-6)


def block_jacobi(args, checks):
    """The dynamic strand of tests/bench/bundle_bench.py (scripts/make_strand.py --layers 1
    --core-radius auto, dt = 1e-5 s, 5 steps of the ramp): block Jacobi (the default here,
    the log names it) against the direct LU of the whole Jacobian (MUMPS, the options that
    restore it) and on 2 ranks. GMRES stops at a tenth of newton_atol (1e-10 N), so every
    Newton iterate, and the solution where Newton stops, is the LU's to that tolerance over
    the stiffness (1e-10 N over a wire stiffness of 1e9 N/m: 1e-19 m), so the positions differ
    by round-off only: measured 2.3e-16 (direct) and 1.1e-16 (2 ranks) relative; bound 1e-14
    (43 and 87 times; the issue's bound for 1 against 2 ranks is 1e-10), with the same Newton
    iterations per step (bound: equal; the issue allows 10 %)."""
    path = os.path.join(args.workdir, "dynamic_strand.nml")
    os.makedirs(args.workdir, exist_ok=True)
    subprocess.run([sys.executable, os.path.join(args.source, "scripts", "make_strand.py"), path,
                    "--layers", "1", "--core-radius", "auto", "--dt", "1e-5", "--t-end", "5e-5",
                    "--t-off", "2e-4", "--stride", "1"], check=True, capture_output=True)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    direct = ("-ksp_type", "preonly", "-pc_type", "lu", "-pc_factor_mat_solver_type", "mumps")
    runs = {}
    for label, ranks, extra in (("block", 1, ("-ksp_view",)), ("direct", 1, direct),
                                ("block_2", 2, ())):
        result, log = rs.run(args, text, f"dynamic_{label}", ranks=ranks, extra=extra,
                             want_log=True)
        runs[label] = ({name: rs.rod(result, name) for name in RODS}, log)
    log = runs["block"][1]
    checks.check("the default solver is block Jacobi over the 7 rods (-ksp_view: 'number of "
                  "blocks = 7')", 0 if re.search(r"number of blocks = 7\b", log) else 1, 0)
    scale = max(np.max(np.abs(runs["block"][0][name]["position"])) for name in RODS)
    for other in ("direct", "block_2"):
        difference = max(np.max(np.abs(runs["block"][0][name]["position"] -
                                       runs[other][0][name]["position"])) for name in RODS)
        checks.check(f"max |position(block Jacobi) - position({other})| / max |position|",
                     difference / scale, 1e-14)
        iterations = runs["block"][0]["core"]["series/newton/iterations"]
        checks.check(f"Newton iterations per record, block Jacobi against {other}",
                     float(np.max(np.abs(iterations -
                                         runs[other][0]["core"]["series/newton/iterations"]))),
                     0.0)
    moved = np.max(np.abs(runs["block"][0]["w1_1"]["position"][-1] -
                          runs["block"][0]["w1_1"]["position"][0]))
    checks.check("the wires moved (the comparison can fail): max |phi(end) - phi(0)| > 1e-9 m",
                 -moved, -1e-9)


ARGS = None


def main():
    global ARGS
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["two_ranks", "stiffness", "stiffness_resolved",
                                         "se3_pg_stiffness", "block_jacobi"])
    args = parser.parse_args()
    ARGS = args
    checks = rs.Checks()
    if args.case == "two_ranks":
        two_ranks(args, checks)
    elif args.case == "stiffness":
        stiffness(args, checks)
    elif args.case == "se3_pg_stiffness":
        se3_pg_stiffness(args, checks)
    elif args.case == "block_jacobi":
        block_jacobi(args, checks)
    else:
        stiffness(args, checks, points=100, tolerance=0.002, torque_tolerance=0.01)
    checks.finish()


if __name__ == "__main__":
    main()
