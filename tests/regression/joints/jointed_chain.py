"""Four free ph_director rods joined end to end by a rigid, a spherical and a revolute joint,
thrown spinning without supports or loads: input/jointed_chain.nml (issue 10; the module
headers of src/system/tie_coupling.F90 and src/formulations/ph_director/ph_director_tie.f90;
docs/theory/bundles.md "Joints and strands: validation").

    jointed_chain.py conservation   energy, momenta, the joints' geometry and forces
    jointed_chain.py se3_pg         the same chain of se3_pg rods (input/se3_pg_jointed_chain.nml,
                                    issue 22 item 5: joints through the system layer on
                                    se3_pg's own tie rows): linear momentum to round-off, the
                                    joints' geometry and forces
    jointed_chain.py se3_pg_two_ranks  the se3_pg chain's first 50 steps on 1 and 2 ranks
    jointed_chain.py two_ranks      the first 50 steps on 1 and 2 ranks agree (the rods are
                                    split over the ranks, so joints tie nodes of different
                                    ranks): positions, directors and tie forces to 1e-10 of
                                    their largest values, as in the strand's acceptance test
                                    (DESIGN.md §5: a small multiple of the Newton tolerance
                                    1e-12 for coupled runs with parallel MUMPS)

What the theory says holds, and how exactly:
- Every tie row is imposed at the endpoint, g(z_{n+1}) = 0, like the nodal orthonormality rows,
  so a joint holds at every record to what Newton leaves of that step's rows, without drift over
  the steps. The position rows (phi_a - phi_b: the reference ends coincide) are linear, so
  every Newton update satisfies them exactly: joined end positions coincide to round-off
  (bound 1e-14, a few ulps of coordinates up to 4). The rotation rows are quadratic
  (bilinear in the directors of the two nodes), as are the orthonormality rows: they hold to
  the last residual of each step, below newton_atol, and do not accumulate over the steps
  (bound newton_atol at every record): the rigid joint keeps the relative rotation of its two
  sections (R_rel = I below), the revolute joint keeps its axis fixed in both sections
  (e_a = sum_i alpha_i d_a^i equals e_b = sum_j beta_j d_b^j, alpha and beta the axis in the
  two reference sections) and turns about it only (R_rel e = e).
- The tie force on a node is minus the position part of G^T lambda; a joint's position rows
  enter its two nodes with +I and -I, so the forces on the two sides are equal and opposite to
  round-off (bound 1e-14 of the largest tie force). An end that nothing ties has zero force.
- Energy, linear and angular momentum: every joint force is an exact discrete gradient of
  time-independent constraints, without net force or torque, so the discrete energy and momenta
  change per step only by the Newton residual of the step (momentum rows M (v_{n+1} - v_n) +
  h f, in momentum units; their sum over the nodes is the change of p, their moment that of l,
  their product with v_mid that of H; H also takes once what the previous step left in its
  non-rate stress rows). The Newton stop is newton_atol on the Euclidean norm of
  the residual; the bounds are stated multiples of it (below, at each check).
What the checks guard against: a joint that does net work or exerts a net force or torque, a
tie that is not exactly imposed, forces booked on the wrong end, a revolute or spherical joint
that locks (the joints must let the sections turn), rods that do not interact (every rod's own
energy changes: the joints move energy between them).
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

RODS = ("a", "b", "c", "d")
# (rod_a, index of end_a, rod_b, index of end_b, kind): node -1 is the end, 0 the start.
JOINTS = (("a", -1, "b", 0, "rigid"), ("b", -1, "c", 0, "spherical"),
          ("c", -1, "d", 0, "revolute"))
AXIS = np.array([0.36, -0.64, 0.48]) / np.linalg.norm([0.36, -0.64, 0.48])
# Round-off bounds (module docstring).
POSITION_ROUNDOFF = 1e-14
FORCE_ROUNDOFF = 1e-14


def newton_atol(text):
    return float(re.search(r"newton_atol\s*=\s*([0-9.eEdD+-]+)", text).group(1).replace("d", "e"))


def relative_rotation(da, db):
    """R_rel(t) = A_0 A(t)^T B(t) B_0^T, A = [d_a^1 d_a^2 d_a^3] and B the directors of the two
    end sections as columns (directors[t, node, i, :] is d_i): the turn of section b relative
    to section a since t = 0, in the reference frame. I for a rigid joint; a rotation about the
    reference axis e for a revolute joint (A(t) A_0^T e = B(t) B_0^T e gives R_rel e = e)."""
    return np.einsum("ki,tij,jl->tkl", da[0].T, np.einsum("tik,tjk->tij", da, db), db[0])


def check_joints(checks, r, prefix, rotation_bound):
    """Every joint of the chain at every record: the joined positions coincide to round-off,
    the rigid joint keeps the relative rotation and the revolute joint its axis in both
    sections to `rotation_bound`, the spherical and revolute joints let the sections turn,
    and the two sides' forces are equal and opposite and not zero."""
    largest_force = max(np.max(np.abs(r[name]["series/ties/force"])) for name in RODS)
    for rod_a, end_a, rod_b, end_b, kind in JOINTS:
        label = f"{prefix}{kind} joint {rod_a}.{'end' if end_a else 'start'}-{rod_b}.start"
        xa, xb = r[rod_a]["position"][:, end_a], r[rod_b]["position"][:, end_b]
        checks.check(f"{label}: max |phi_a - phi_b| over the records", np.max(np.abs(xa - xb)),
                     POSITION_ROUNDOFF)
        da, db = r[rod_a]["directors"][:, end_a], r[rod_b]["directors"][:, end_b]
        rotation = relative_rotation(da, db)
        angle = np.arccos(np.clip((np.trace(rotation, axis1=1, axis2=2) - 1) / 2, -1.0, 1.0))
        if kind == "rigid":
            checks.check(f"{label}: max |R_rel - I| (relative rotation kept)",
                         np.max(np.abs(rotation - np.eye(3))), rotation_bound)
        elif kind == "spherical":
            checks.check(f"{label}: the sections turn relative to each other (max angle of R_rel"
                         " > 0.5 rad)", -np.max(angle), -0.5)
        else:
            alpha = da[0] @ AXIS
            beta = db[0] @ AXIS
            ea = np.einsum("i,tik->tk", alpha, da)
            eb = np.einsum("j,tjk->tk", beta, db)
            checks.check(f"{label}: max |e_a - e_b| (the axis fixed in both sections)",
                         np.max(np.abs(ea - eb)), rotation_bound)
            checks.check(f"{label}: max |R_rel e - e| (a relative turn about the axis only)",
                         np.max(np.abs(rotation @ AXIS - AXIS)), rotation_bound)
            checks.check(f"{label}: the sections turn about the axis (max angle of R_rel "
                         "> 0.5 rad)",
                         -np.max(angle), -0.5)
            print(f"info: {label}: the axis turned by up to "
                  f"{np.degrees(np.arccos(np.clip(ea @ AXIS, -1, 1))).max():.1f} degrees in space")
        print(f"info: {label}: largest relative rotation angle {np.max(angle):.4f} rad")
        fa = r[rod_a]["series/ties/force"][:, 1 if end_a else 0]
        fb = r[rod_b]["series/ties/force"][:, 1 if end_b else 0]
        checks.check(f"{label}: max |F_a + F_b| / max |F| (equal and opposite)",
                     np.max(np.abs(fa + fb)) / largest_force, FORCE_ROUNDOFF)
        checks.check(f"{label}: the joint carries force (max |F| > 0.1)",
                     -np.max(np.linalg.norm(fa, axis=1)), -0.1)
    checks.check(f"{prefix}free ends (a.start, d.end): tie force exactly 0",
                 float(np.max(np.abs(r["a"]["series/ties/force"][:, 0])) +
                       np.max(np.abs(r["d"]["series/ties/force"][:, 1]))), 0.0)


def conservation(args, checks):
    text = rs.read_example(args.source, "jointed_chain.nml")
    atol = newton_atol(text)
    path = rs.run(args, text, "conservation")
    r = {name: rs.rod(path, name) for name in RODS}
    steps = r["a"]["time"].size - 1
    n_nodes = sum(r[name]["position"].shape[1] for name in RODS)
    print(f"info: {steps} steps, {n_nodes} nodes, newton_atol {atol:g}, Newton iterations "
          f"{r['a']['series/newton/iterations'].sum()}, largest final residual "
          f"{r['a']['series/newton/residual'].max():.3e}")

    # --- Energy: H = sum of the rods' totals. Per step, the change is the residual of the
    # momentum rows times v_mid (and of the other rows times their conjugates), plus what the
    # previous step left in its stress rows (they are non-rate, so the next step imposes them
    # afresh; docs/theory/bundles.md "Joints and strands: validation"). Both are bounded by
    # newton_atol times the velocity and force scales of the scene, O(10) here (rods of unit
    # length and mass spinning at 2-4 rad/s); the bound is 10 newton_atol per step and its sum
    # over the run for the drift. Measured: 0.25 newton_atol per step.
    total = sum(r[name]["series/energy/total"] for name in RODS)
    checks.check("max per-step |H_{n+1} - H_n| (sum over rods)", np.max(np.abs(np.diff(total))),
                 10 * atol)
    checks.check("max |H_n - H_0| (sum over rods)", np.max(np.abs(total - total[0])),
                 10 * atol * steps)
    # The joints' work on the rods, booked as each rod's external work, sums to zero per step:
    # -lambda^T (g(z_{n+1}) - g(z_n)) with both g at the Newton residual.
    work = sum(r[name]["series/energy/external_work"] for name in RODS)
    checks.check("max per-step |sum over rods of the joints' work|", np.max(np.abs(work)),
                 10 * atol)
    for name in RODS:
        checks.check(f"rod {name}: per-record energy balance error",
                     np.max(np.abs(r[name]["series/energy/balance_error"])), 10 * atol)
    exchanged = min(np.max(np.abs(r[name]["series/energy/total"] -
                               r[name]["series/energy/total"][0])) for name in RODS)
    checks.check("the joints move energy between the rods (min over rods of max |H_rod - H_rod(0)|"
                 " > 1e-2 H(0))", -exchanged, -1e-2 * total[0])

    # --- Momenta: per step, the change of p is the sum over the nodes of the position rows of
    # the momentum residual R_M = M (v_{n+1} - v_n) + h [...] (momentum units; the joint terms
    # have zero net force), |.| <= sqrt(n_nodes) |R| (Cauchy-Schwarz); that of l is the sum of
    # phi_mid x R_phi + d_mid^i x R_d^i over the nodes, |.| <= max(|phi|, 1) sqrt(4 n_nodes)
    # |R| (|d^i| = 1). Bounds: these with |R| <= newton_atol.
    p = sum(r[name]["series/momentum/linear"] for name in RODS)
    l = sum(r[name]["series/momentum/angular"] for name in RODS)
    lever = max(1.0, max(np.max(np.linalg.norm(r[name]["position"], axis=2)) for name in RODS))
    checks.check("max per-step |p_{n+1} - p_n| (sum over rods)",
                 np.max(np.linalg.norm(np.diff(p, axis=0), axis=1)), np.sqrt(n_nodes) * atol)
    checks.check("max |p_n - p_0|", np.max(np.linalg.norm(p - p[0], axis=1)),
                 np.sqrt(n_nodes) * atol * steps)
    checks.check("max per-step |l_{n+1} - l_n| (sum over rods)",
                 np.max(np.linalg.norm(np.diff(l, axis=0), axis=1)),
                 lever * np.sqrt(4 * n_nodes) * atol)
    checks.check("max |l_n - l_0|", np.max(np.linalg.norm(l - l[0], axis=1)),
                 lever * np.sqrt(4 * n_nodes) * atol * steps)
    print(f"info: H(0) = {total[0]:.10g}, p(0) = {p[0]}, l(0) = {l[0]}, lever {lever:.3f}")
    for name in RODS:
        checks.check(f"rod {name}: max nodal |g(d)| (orthonormality)",
                     np.max(r[name]["series/constraint_residual"]), atol)

    # --- The joints hold at every record: positions to round-off, rotations to newton_atol.
    check_joints(checks, r, "", atol)


def se3_pg(args, checks):
    """The se3_pg chain. Its rows are force balances (I dr) and virtual rotations (K dphi) of
    the midpoint rule (methods/se3_petrov_galerkin.md eqs. 49-51); the joint forces enter the
    position rows of the two joined nodes as +lambda and -lambda and the rods' internal forces
    have no net force (objectivity), so the sum of the position rows is (p_{n+1} - p_n) / h
    exactly up to the round-off of summing forces of O(10) N: linear momentum is kept to
    round-off whatever the Newton residual. Measured (2 s, 200 steps): per step 4.5e-14, over
    the run 2.0e-13, at |p| = 5.1. Bounds: 500 eps |p| per step (13 times the measured), and
    500 eps |p| sqrt(steps) over the run (a random walk of per-step round-offs; 40 times).
    The joints: the position rows are linear in the positions (the pivot offset s is zero for
    coinciding reference ends), so every Newton update keeps them to round-off; the rotation
    rows (bilinear in Exp(psi_a), Exp(psi_b)) converge quadratically with the step and end at
    round-off too: measured |R_rel - I| 1.3e-15 (rigid) and |R_rel e - e| 7e-15 (revolute);
    bound 1e-13 for both (the 3 x 3 products of unit-size directors, 100 eps per entry, 15
    to 75 times the measured). se3_pg's midpoint rule keeps neither energy nor angular momentum
    exactly: reported, not checked."""
    text = rs.read_example(args.source, "se3_pg_jointed_chain.nml")
    path = rs.run(args, text, "se3_pg")
    r = {name: rs.rod(path, name) for name in RODS}
    steps = r["a"]["time"].size - 1
    p = sum(r[name]["series/momentum/linear"] for name in RODS)
    scale = 500 * np.finfo(float).eps * np.linalg.norm(p[0])
    checks.check("se3_pg: max per-step |p_{n+1} - p_n| (sum over rods)",
                 np.max(np.linalg.norm(np.diff(p, axis=0), axis=1)), scale)
    checks.check("se3_pg: max |p_n - p_0|", np.max(np.linalg.norm(p - p[0], axis=1)),
                 scale * np.sqrt(steps))
    check_joints(checks, r, "se3_pg ", 1e-13)
    total = sum(r[name]["series/energy/total"] for name in RODS)
    l = sum(r[name]["series/momentum/angular"] for name in RODS)
    print(f"info: se3_pg chain: H drift {np.max(np.abs(total - total[0])):.3e} of H(0) = "
          f"{total[0]:.4f}, |l_n - l_0| up to {np.max(np.linalg.norm(l - l[0], axis=1)):.3e} of "
          f"|l(0)| = {np.linalg.norm(l[0]):.4f} (not kept by the scheme)")


def two_ranks(args, checks, example="jointed_chain.nml"):
    text = rs.set_variable(rs.read_example(args.source, example), "time", "t_end",
                           "0.5")
    one = {name: rs.rod(rs.run(args, text, "one_rank"), name) for name in RODS}
    two_path, log = rs.run(args, text, "two_ranks", ranks=2, want_log=True)
    partition = [line for line in log.splitlines()
                 if "rank 1:" in line]
    print("info: " + "\ninfo: ".join(partition))
    checks.check("the 2-rank run puts rods on rank 1 (log lines naming rank 1)",
                 -float(len(partition)), -1.0)
    two = {name: rs.rod(two_path, name) for name in RODS}
    for field in ("position", "directors", "series/ties/force", "series/energy/total"):
        scale = max(np.max(np.abs(one[name][field])) for name in RODS)
        difference = max(np.max(np.abs(one[name][field] - two[name][field])) for name in RODS)
        checks.check(f"max |{field}(1 rank) - {field}(2 ranks)| / max |{field}|",
                     difference / scale, 1e-10)
    checks.check("records on 1 and 2 ranks differ in number",
                 float(sum(abs(one[n]["time"].size - two[n]["time"].size) for n in RODS)), 0.0)
    moved = np.max(np.abs(one["d"]["position"][-1] - one["d"]["position"][0]))
    checks.check("the chain moved (the comparison can fail): max |phi(0.5) - phi(0)| of rod d "
                 "> 0.1",
                 -moved, -0.1)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["conservation", "two_ranks", "se3_pg",
                                         "se3_pg_two_ranks"])
    args = parser.parse_args()
    checks = rs.Checks()
    {"conservation": conservation, "two_ranks": two_ranks, "se3_pg": se3_pg,
     "se3_pg_two_ranks": lambda a, c: two_ranks(a, c, "se3_pg_jointed_chain.nml")
     }[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
