"""Quasistatic cantilever under a dead tip force and moment (seed 000 §6.3;
methods/ph_director_3d.md §6.3 and §10 V8): input/elastica_inextensible.nml and
input/elastica_extensible.nml against the references of elastica_reference.py.

    elastica.py inextensible       tip against the analytic elastica; order in n_e
    elastica.py extensible_order   tip against the Reissner-rod reference for n_e = 4..32
    elastica.py locking            EA, GA x 1e4 without the constraint: no locking (p = 1, 2)
    elastica.py endpoint           the last record is the endpoint equilibrium (independent of dt)

Expected order in n_e: the unknowns are C0 quadratic (p = 2) with discontinuous linear
stresses and 2-point Gauss quadrature. In one dimension the Galerkin/mixed solution is
superconvergent at the nodes, so the tip (a node) converges with order 2p = 4 (2 for p = 1),
not with the O(h^2) of the stresses or the O(h^3) of the positions between nodes. An
independent planar implementation of the same discretization (for choosing these bounds)
gives order 4.0 and tip errors 2.0e-3 (n_e = 8), 1.2e-4 (16), 7.6e-6 (32) for the
inextensible rod, which this solver reproduces to all printed digits. The paper's 8 elements
therefore do not reach 1e-4; that needs n_e = 32. Bounds on errors below are centres with a
band (DESIGN.md §8), orders are checked against 4 +- 0.3.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_scene as rs  # noqa: E402
import elastica_reference as reference  # noqa: E402

ROD = "cantilever"
GAMMA_0 = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
#: The §6.3 stiffnesses (N1 N2 N3 M1 M2 M3 order: GA1, GA2, EA, EI1, EI2, GJ).
STIFFNESS = np.array([reference.GA, reference.GA, reference.EA, reference.EI, reference.EI,
                      reference.GJ])


def tip_run(args, scene, name, **variables):
    """Run `scene` with variables changed ({'rod__n_elements': '16'}); return the rod's fields
    and the tip (x, y) of the last record, after checking it is the load factor t = 1."""
    text = rs.read_example(args.source, scene)
    for key, value in variables.items():
        group, variable = key.split("__")
        text = rs.set_variable(text, group, variable, value)
    r = rs.rod(rs.run(args, text, name), ROD)
    assert abs(r["time"][-1] - 1.0) < 1e-12, f"{name}: last record at t = {r['time'][-1]}"
    return r, r["position"][-1, -1, :2]


def orders(n_elements, errors):
    return [math.log2(errors[a] / errors[b]) / math.log2(b / a)
            for a, b in zip(n_elements[:-1], n_elements[1:])]


def planar_checks(checks, r, label):
    """The motion stays in the e1-e2 plane and the constraints hold at the last record."""
    checks.check(label + ": max |z| and |d3 . e3| (planar)",
                 max(np.max(np.abs(r["position"][:, :, 2])),
                     np.max(np.abs(r["directors"][:, :, 2, 2]))), 1e-10)
    checks.check(label + ": max nodal |g(d)|", np.max(r["series/constraint_residual"]), 1e-12)


def inextensible(args, checks):
    exact = reference.solve()["tip"]
    print(f"info: analytic tip (x, y) = ({exact[0]:.12f}, {exact[1]:.12f})")
    n_elements = (8, 16, 32)
    errors = {}
    for n in n_elements:
        r, tip = tip_run(args, "elastica_inextensible.nml", f"inextensible_n{n}",
                         rod__n_elements=str(n))
        errors[n] = np.max(np.abs(tip - exact))
        print(f"info: n_e = {n}: tip ({tip[0]:.10f}, {tip[1]:.10f}), error per component "
              f"({tip[0] - exact[0]:.3e}, {tip[1] - exact[1]:.3e})")
        checks.check(f"n_e = {n}: max |Gamma - Gamma0| at the stress points, last record",
                     np.max(np.abs(r["strain"][-1, :, :3] - GAMMA_0[:3])), 1e-10)
        checks.check(f"n_e = {n}: max |C_M M - K(q)| at the stress points, last record",
                     np.max(np.abs(r["stress"][-1, :, 3:] / STIFFNESS[3:]
                                   - r["strain"][-1, :, 3:])), 1e-10)
        if n == 8:
            planar_checks(checks, r, "n_e = 8")
    observed = orders(n_elements, errors)
    print(f"info: observed orders {['%.3f' % p for p in observed]}")
    for (a, b), p in zip(zip(n_elements[:-1], n_elements[1:]), observed):
        checks.check(f"|order {a} -> {b} - 4|", abs(p - 4.0), 0.3)
    checks.check("n_e = 8 (the paper's mesh): max component tip error (discretization, 2.0e-3)",
                 errors[8], 2.5e-3)
    checks.check("n_e = 32: max component tip error", errors[32], 1e-5)


def extensible_order(args, checks):
    exact = reference.solve(ea=reference.EA, ga=reference.GA)["tip"]
    print(f"info: Reissner-rod reference tip (x, y) = ({exact[0]:.12f}, {exact[1]:.12f})")
    n_elements = (4, 8, 16, 32)
    errors, tips = {}, {}
    for n in n_elements:
        r, tip = tip_run(args, "elastica_extensible.nml", f"extensible_n{n}",
                         rod__n_elements=str(n))
        tips[n] = tip
        errors[n] = np.max(np.abs(tip - exact))
        print(f"info: n_e = {n}: tip ({tip[0]:.10f}, {tip[1]:.10f}), max component error "
              f"{errors[n]:.3e}")
        consistency = np.abs(r["stress"] / STIFFNESS - (r["strain"] - GAMMA_0))
        checks.check(f"n_e = {n}: strain consistency max |C sigma - (eps(q) - eps0)|, all records",
                     np.max(consistency), 1e-10)
    planar_checks(checks, r, "n_e = 32")
    observed = orders(n_elements, errors)
    print(f"info: observed orders {['%.3f' % p for p in observed]}")
    for (a, b), p in zip(zip(n_elements[:-1], n_elements[1:]), observed):
        checks.check(f"|order {a} -> {b} - 4|", abs(p - 4.0), 0.3)
    richardson = tips[32] + (tips[32] - tips[16]) / 15
    print(f"info: Richardson tip from n_e = 16, 32 differs from the reference by "
          f"{np.max(np.abs(richardson - exact)):.3e}")
    checks.check("n_e = 32: max component tip error", errors[32], 1e-5)


def locking(args, checks):
    """EA and GA times 1e4 without the constraint. The stiff rod is a different problem from the
    inextensible one: their exact tips differ by 1.4e-4 (elastica_reference.py (e)), more than
    the discretization error at n_e = 32, so each rod is compared with its own exact solution
    (the Reissner-rod reference with the stiff EA, GA). Locking would show as a stiff-rod error
    far above that of the constrained rod on the same mesh; the bound is the constrained
    error times 2 plus 1e-6, for p = 2 (n_e = 8) and p = 1 (n_e = 16, the same nodes)."""
    factor = 1e4
    exact_inextensible = reference.solve()["tip"]
    exact_stiff = reference.solve(ea=reference.EA * factor, ga=reference.GA * factor)["tip"]
    print(f"info: exact tips: inextensible {exact_inextensible}, EA, GA x 1e4 {exact_stiff} "
          f"(differ by {np.max(np.abs(exact_stiff - exact_inextensible)):.3e})")
    stiff_values = {"rod__EA": repr(reference.EA * factor),
                    "rod__GA1": repr(reference.GA * factor),
                    "rod__GA2": repr(reference.GA * factor)}
    errors = {}
    for degree, n in ((2, 8), (1, 16)):
        _, constrained = tip_run(args, "elastica_inextensible.nml",
                                 f"locking_constrained_p{degree}", rod__degree=str(degree),
                                 rod__n_elements=str(n))
        _, stiff = tip_run(args, "elastica_extensible.nml", f"locking_stiff_p{degree}",
                           rod__degree=str(degree), rod__n_elements=str(n), **stiff_values)
        e_constrained = np.max(np.abs(constrained - exact_inextensible))
        e_stiff = np.max(np.abs(stiff - exact_stiff))
        errors[degree] = e_stiff
        print(f"info: p = {degree}, n_e = {n}: constrained error {e_constrained:.4e}, stiff error "
              f"{e_stiff:.4e}, stiff against the inextensible solution "
              f"{np.max(np.abs(stiff - exact_inextensible)):.4e}")
        checks.check(f"p = {degree}: stiff-rod error / (2 constrained error + 1e-6)",
                     e_stiff / (2 * e_constrained + 1e-6), 1.0)
    # p = 2 on the same nodes is far more accurate than p = 1 (order 4 against 2); a locking
    # p = 2 element would lose that.
    print(f"info: stiff-rod error p = 1 / p = 2 on the same 17 nodes: {errors[1] / errors[2]:.1f}")
    checks.check("stiff rod: error(p = 2) / error(p = 1) on the same nodes", errors[2] / errors[1],
                 0.2)


def endpoint(args, checks):
    """Quasistatic runs with dt = 0.1 and 0.05: the last record is the endpoint equilibrium at
    t = 1 and must not depend on dt beyond Newton accuracy, while the states along the path
    are midpoint-step states, which differ by O(dt^2)."""
    runs = {}
    for dt in (0.1, 0.05):
        runs[dt], _ = tip_run(args, "elastica_inextensible.nml", f"endpoint_dt{dt}",
                              time__dt=repr(dt))
    a, b = runs[0.1], runs[0.05]
    final = max(np.max(np.abs(a["position"][-1] - b["position"][-1])),
                np.max(np.abs(a["directors"][-1] - b["directors"][-1])))
    checks.check("last record (t = 1), dt = 0.1 against 0.05: max |position|, |directors|",
                 final, 1e-9)
    checks.check("last record: max |stress(dt = 0.1) - stress(dt = 0.05)|",
                 np.max(np.abs(a["stress"][-1] - b["stress"][-1])), 1e-9)
    i, j = int(np.argmin(np.abs(a["time"] - 0.5))), int(np.argmin(np.abs(b["time"] - 0.5)))
    path = np.max(np.abs(a["position"][i] - b["position"][j]))
    print(f"info: at t = 0.5 the path states differ by {path:.3e} (midpoint steps, O(dt^2)); "
          f"at t = 1 by {final:.3e}")
    checks.check("the path states differ (the comparison can tell them apart): "
                 "-difference at t = 0.5", -path, -1e-6)
    # The endpoint equilibrium of the constrained rod also matches the analytic solution to the
    # discretization error of n_e = 8 (see inextensible).
    exact = reference.solve()["tip"]
    checks.check("last record: max component tip error against the analytic elastica",
                 np.max(np.abs(b["position"][-1, -1, :2] - exact)), 2.5e-3)


def main():
    cases = {"inextensible": inextensible, "extensible_order": extensible_order,
             "locking": locking, "endpoint": endpoint}
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=sorted(cases))
    args = parser.parse_args()
    checks = rs.Checks()
    cases[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
