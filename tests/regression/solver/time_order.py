"""Order 4 in time by Suzuki's composition of midpoint steps (&time order = 4; issue 25 item 1,
docs/theory/time_integration.md), for every formulation that composes.

    time_order.py ph_director    flying spaghetti (3D): slope 4, and its invariants at order 4
    time_order.py ph_planar      planar flying spaghetti: slope 4, invariants
    time_order.py cl_em_planar   the same with the classical energy-momentum beam
    time_order.py kirchhoff      Kirchhoff cantilever (inextensible): slope 4, constraints, balance
    time_order.py se3_pg         soft flexible heavy top: slope 4

The observed order is log2 of the ratio of successive refinement changes |x(h) - x(h/2)| of
the tip position at a fixed time (no reference run needed: for an order-p scheme the ratio is
2^p). The acceptance of issue 25 is 4 +- 0.3. Three conditions make the order visible, and each
case states how it meets them:
- the steps resolve the mesh's stiffest modes (omega_max h below about 1): an unresolved mode,
  excited by a load's onset, leaves an error that does not converge with h at any order (the
  midpoint rule turns it by a wrong angle); so the meshes are coarse and the steps fine;
- the Newton tolerance sits well below the refinement changes;
- the loads are smooth inside every step (Suzuki's sub-steps stay inside the step, so a kink at
  a step boundary is harmless).
Every sub-step is a midpoint step with its own exact balance, so the invariants hold at order 4
as at order 2: the bounds below are the order-2 tests' own where those sit within 100 times
what order 4 achieves (tests/regression/ph_director/), tighter where they do not (planar).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

#: Issue 25's acceptance: the observed order of the composition is 4 within 0.3.
ORDER, ORDER_TOLERANCE = 4.0, 0.3


def tip_at_end(args, text, rod, h, name):
    """The free end's position at t_end, run at order 4 with step h (one record at the end)."""
    t_end = rs.number(text, "time", "t_end")
    text = rs.set_variable(text, "time", "dt", repr(h))
    text = rs.set_variable(text, "time", "order", "4")
    text = rs.set_variable(text, "output", "stride", str(round(t_end / h)))
    r = rs.rod(rs.run(args, text, f"{name}_h{h:g}"), rod)
    if abs(r["time"][-1] - t_end) > 1e-12:
        raise SystemExit(f"the run ended at {r['time'][-1]}, not at t_end = {t_end}")
    return r["position"][-1, -1, :]


def observed_order(args, checks, text, rod, steps, name):
    """Refinement changes of the tip over `steps` (each half the last) and their slopes; the
    finest slope is checked, the coarser ones are printed (they show the approach)."""
    tips = [tip_at_end(args, text, rod, h, name) for h in steps]
    changes = [np.linalg.norm(a - b) for a, b in zip(tips, tips[1:])]
    slopes = [np.log2(a / b) for a, b in zip(changes, changes[1:])]
    for h, change in zip(steps, changes):
        print(f"info: h = {h:g}: |x(h) - x(h/2)| = {change:.3e}")
    print("info: slopes " + ", ".join(f"{s:.3f}" for s in slopes))
    checks.check(f"{name}: |observed order - 4| (h = {steps[-3]:g}, {steps[-2]:g}, {steps[-1]:g})",
                 abs(slopes[-1] - ORDER), ORDER_TOLERANCE)
    return changes


def balance(checks, r, bound):
    """The program's per-step energy balance at order 4 (the sum of its sub-steps')."""
    checks.check("order 4: max_n |balance_error_n| / max H",
                 np.max(np.abs(r["series/energy/balance_error"])) / np.max(r["series/energy/total"]),
                 bound)


def study(text, t_end, edits):
    """The order study's scene: `text` to t_end with the (group, variable, value) edits, and
    Newton's relative test off (the absolute tolerance of the edits decides)."""
    text = rs.set_variable(text, "time", "t_end", t_end)
    for group, variable, value in edits + (("solver", "newton_rtol", "0"),):
        text = rs.set_variable(text, group, variable, value)
    return text


def at_order_4(args, text, name, rod):
    """The scene as given, run at order 4: its records, their times, stored energies and the
    largest energy."""
    r = rs.rod(rs.run(args, rs.set_variable(text, "time", "order", "4"), name), rod)
    return r, r["time"], r["series/energy/total"], np.max(r["series/energy/total"])


def ph_director(args, checks):
    """Flying spaghetti. Order: 4 elements (the stiffest axial and shear modes near 400 rad/s
    are resolved by h <= 2.5e-3), t = 1 (on the hat's rising flank, a linear load), Newton at
    1e-13; slopes 0.41 (h = 5e-3 does not resolve them yet), 4.00 measured. Invariants: the
    scene as given (h = 0.1) at order 4."""
    text = rs.read_example(args.source, "flying_spaghetti.nml")
    edits = (("rod", "n_elements", "4"), ("solver", "newton_atol", "1e-13"))
    observed_order(args, checks, study(text, "1.0", edits), "spaghetti",
                   (5e-3, 2.5e-3, 1.25e-3, 6.25e-4), "spaghetti")

    r, t, total, top = at_order_4(args, text, "spaghetti_invariants", "spaghetti")
    balance(checks, r, 1e-13)
    free = t >= 5.0 - 1e-12
    # No work after t = 5: the stored energy is constant, read from the stored totals.
    checks.check("order 4: (max H - min H) / max H for t >= 5", np.ptp(total[free]) / top, 1e-13)
    # The impulse of the hat's force 20 f(t) e1 is 500 * (1/10): every sub-step's midpoint rule
    # integrates the linear flanks exactly, and no sub-step crosses the kinks at 2.5 and 5.
    p, l = r["series/momentum/linear"], r["series/momentum/angular"]
    checks.check("order 4: |p(t >= 5) - (50, 0, 0)| / 50", np.max(np.abs(p[free] - [50.0, 0.0, 0.0])) / 50,
                 1e-13)
    checks.check("order 4: |l(t >= 5) - l(5)| / |l(5)|",
                 np.max(np.linalg.norm(l[free] - l[free][0], axis=1)) / np.linalg.norm(l[free][0]), 1e-13)
    checks.check("order 4: max nodal |g(d)|", np.max(r["series/constraint_residual"]), 1e-12)


def planar(args, checks, formulation):
    """Planar flying spaghetti (the force and moment held until 2.5). Order: 4 elements, t = 1,
    Newton at 1e-10 (the planar residual's round-off floor is near 1e-11, grows as 1/h; its
    tests' own setting); slopes 3.97, 3.99 (ph_planar), 3.95, 3.99 (cl_em_planar).
    Invariants: the scene to t = 5 at its h = 0.1, order 4."""
    text = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    text = rs.set_variable(text, "rod", "formulation", f"'{formulation}'")
    text = rs.set_variable(text, "solver", "newton_atol", "1e-10")
    observed_order(args, checks, study(text, "1.0", (("rod", "n_elements", "4"),)), "spaghetti",
                   (5e-3, 2.5e-3, 1.25e-3, 6.25e-4), formulation)

    r, t, total, top = at_order_4(args, rs.set_variable(text, "time", "t_end", "5.0"),
                                  f"{formulation}_invariants", "spaghetti")
    # Newton at 1e-10 on stresses of O(1e3) leaves the balances at 2e-14 to 3e-14 (measured, all
    # four below): bounds 1e-12.
    balance(checks, r, 1e-12)
    free = t >= 2.5 - 1e-12
    checks.check("order 4: (max H - min H) / max H for t >= 2.5", np.ptp(total[free]) / top, 1e-12)
    if formulation == "ph_planar":
        # cl_em_planar keeps energy and linear momentum, not angular momentum (its algebraic
        # strain's variation; docs/theory/ph_planar.md), at either order.
        l = r["series/momentum/angular"][:, 2]
        checks.check("order 4: |l_z(t >= 2.5) - l_z(2.5)| / |l_z(2.5)|",
                     np.max(np.abs(l[free] - l[free][0])) / abs(l[free][0]), 1e-12)
    p = r["series/momentum/linear"][:, :2]
    checks.check("order 4: |p(t >= 2.5) - p(2.5)| / |p(2.5)|",
                 np.max(np.linalg.norm(p[free] - p[free][0], axis=1)) / np.linalg.norm(p[free][0]), 1e-12)


def kirchhoff(args, checks):
    """Kirchhoff cantilever, its pulse. Order: 2 elements (the stiffest bending mode resolved by
    h <= 1.25e-4; the torsion mode, near 1e5 rad/s at any mesh, is excited only weakly by the
    smooth pulse), t = 0.04 (inside the pulse), Newton at 1e-13; slopes 3.67, 3.94 measured, the
    first still on the way (h = 2.5e-4). Invariants: the scene as given at order 4."""
    text = rs.read_example(args.source, "kirchhoff_cantilever.nml")
    edits = (("rod", "n_elements", "2"), ("solver", "newton_atol", "1e-13"))
    observed_order(args, checks, study(text, "0.04", edits), "cantilever",
                   (2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5), "kirchhoff")

    r, t, total, top = at_order_4(args, text, "kirchhoff_invariants", "cantilever")
    checks.check("order 4: max nodal |g(d)|", np.max(r["series/constraint_residual"]), 1e-12)
    checks.check("order 4: max |Gamma - (0, 0, 1)| (stress points)",
                 np.max(np.abs(r["strain"][:, :, :3] - [0.0, 0.0, 1.0])), 5e-12)
    balance(checks, r, 1e-11)
    free = t >= 0.05 - 1e-12
    checks.check("order 4: (max H - min H) / max H for t >= 0.05", np.ptp(total[free]) / top, 1e-11)


def se3_pg(args, checks):
    """Soft flexible heavy top (one element; se3_pg's midpoint rule is symmetric, not energy
    conserving). Order: t = 0.1, Newton at 1e-7 on forces of O(1e4) (below, it stalls at its
    round-off floor on the shortest sub-steps); slope 4.00 measured."""
    text = rs.read_example(args.source, "se3_heavy_top_soft.nml")
    observed_order(args, checks, study(text, "0.1", (("solver", "newton_atol", "1e-7"),)), "top",
                   (8e-4, 4e-4, 2e-4, 1e-4), "heavy top")


if __name__ == "__main__":
    rs.run_cases(__doc__, {"ph_director": ph_director, "kirchhoff": kirchhoff, "se3_pg": se3_pg,
                           "ph_planar": lambda args, checks: planar(args, checks, "ph_planar"),
                           "cl_em_planar": lambda args, checks: planar(args, checks, "cl_em_planar")})
