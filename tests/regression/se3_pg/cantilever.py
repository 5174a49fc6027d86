"""SE(3) cantilever with follower tip loads, the locking test of seed 002 §4.1 (Table 1, Fig. 4c;
methods/se3_petrov_galerkin.md §10.1, §13 items 7-8, §14.1), input/se3_cantilever.nml.

    cantilever.py rho10      one element at slenderness 10 (atol 1e-8) against a 256-element
                             run at the same slenderness: e_r and e_psi of Table 1's rho = 10 row
                             (6.789, 1.628) within half a unit of the last printed digit (5e-4),
                             so also 6.792 and 1.629 to 3 significant digits (6.79, 1.63)
    cantilever.py rho1e3     one element at slenderness 1e3 (atol 1e-10): e_r = 6.792 and
                             e_psi = 1.629 within 5e-4 (Table 1; methods §14.1 6.79218, 1.62858)
    cantilever.py mesh64     64 elements at 1e3 against 256 elements: e_r and e_psi within 5 %
                             of 1.43e-3 and 3.60e-4 (issue 7; methods §14.1 1.43184e-3,
                             3.59901e-4, the paper's own 1.397e-3, 3.357e-4 come from a director
                             reference, methods §14.1)
    cantilever.py order      n_el = 1, 2, ..., 64 at 1e3 against 256 elements: e(n) / e(2n)
                             within [3.5, 4.5] for n = 2 .. 32, both fields (order 2, Fig. 4c)
    cantilever.py rho1e4     slenderness 1e4 converges with the analytic tangent to 1e-11 (Table
                             1): 1 element in the 20 increments without a cut-back, 64 elements
                             to t = 1 (cut-backs reported); e_r and e_psi at 1 element against a
                             256-element run at atol 1e-14: Table 1's 6.792, 1.629 within 5e-4

e_r is eq. (52), e_psi eq. (53) without its 1/k (methods §13 item 7), both at k = 100 points of
the SE(3) pose field (se3_field.py). The Newton tolerance is on the 2-norm of the residual (the
paper's max-norm tolerance is at most as strict).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import se3_field  # noqa: E402
import se3_scene  # noqa: E402
from se3_scene import rs  # noqa: E402

ROD = "cantilever"
LENGTH = 1000.0
ATOL = {10: 1e-8, 100: 1e-9, 1000: 1e-10, 10000: 1e-11}
TABLE_1 = {10: (6.789, 1.628), 1000: (6.792, 1.629), 10000: (6.792, 1.629)}


def scene(args, rho, n_elements, atol):
    """The example with w = L / rho (square section), its loads 0.5 pi EI / L and
    0.5 pi EI / L^2 (follower, along d2 of the tip), n_elements and newton_atol."""
    w = LENGTH / rho
    ei = w**4 / 12.0
    moment = 0.5 * math.pi * ei / LENGTH
    force = moment / LENGTH
    return se3_scene.edit(rs.read_example(args.source, "se3_cantilever.nml"), [
        ("rod", "n_elements", str(n_elements)), ("rod", "width", repr(w)),
        ("rod", "height", repr(w)), ("solver", "newton_atol", repr(atol)),
        ("load", "force", rs.vector((0.0, force, 0.0))),
        ("load", "moment", rs.vector((0.0, moment, 0.0)))])


def solve(args, rho, n_elements, atol=None):
    atol = ATOL[rho] if atol is None else atol
    name = f"rho{rho}_n{n_elements}_atol{atol:g}"
    r = se3_scene.run(args, scene(args, rho, n_elements, atol), name, ROD)
    residual = r["series/newton/residual"][1:]
    print(f"info: rho = {rho}, {n_elements} element(s), atol {atol:g}: {r.summary()}; tip "
          f"{np.array2string(r['position'][-1, -1], precision=6)}; largest final residual of an "
          f"increment {np.max(residual):.2e}")
    return r


def errors(r, ref):
    return se3_field.errors(r["position"][-1], r["directors"][-1], ref["position"][-1],
                            ref["directors"][-1])


def three_significant(x):
    return float(f"{x:.3g}")


def one_element(args, checks, rho):
    ref = solve(args, rho, 256)
    r = solve(args, rho, 1)
    e_r, e_psi = errors(r, ref)
    print(f"info: rho = {rho}, 1 element: e_r = {e_r:.6f}, e_psi = {e_psi:.6f} (Table 1 "
          f"{TABLE_1[rho]}; methods §14.1 " +
          ("6.78864, 1.62812)" if rho == 10 else "6.79218, 1.62858)"))
    checks.check(f"rho = {rho}: |e_r - {TABLE_1[rho][0]}| (1 element)", abs(e_r - TABLE_1[rho][0]),
                 5e-4)
    checks.check(f"rho = {rho}: |e_psi - {TABLE_1[rho][1]}| (1 element)",
                 abs(e_psi - TABLE_1[rho][1]), 5e-4)
    checks.check(f"rho = {rho}: e_r to 3 significant digits minus 6.79",
                 abs(three_significant(e_r) - 6.79), 1e-12)
    checks.check(f"rho = {rho}: e_psi to 3 significant digits minus 1.63",
                 abs(three_significant(e_psi) - 1.63), 1e-12)
    return e_r, e_psi


def rho10(args, checks):
    one_element(args, checks, 10)


def rho1e3(args, checks):
    one_element(args, checks, 1000)


def mesh64(args, checks):
    ref = solve(args, 1000, 256)
    e_r, e_psi = errors(solve(args, 1000, 64), ref)
    print(f"info: 64 elements: e_r = {e_r:.6e}, e_psi = {e_psi:.6e} (methods §14.1 1.43184e-3, "
          "3.59901e-4; paper 1.397e-3, 3.357e-4 against a director reference)")
    checks.check("64 elements: |e_r / 1.43e-3 - 1|", abs(e_r / 1.43e-3 - 1), 0.05)
    checks.check("64 elements: |e_psi / 3.60e-4 - 1|", abs(e_psi / 3.60e-4 - 1), 0.05)


def order(args, checks):
    ref = solve(args, 1000, 256)
    meshes = [1, 2, 4, 8, 16, 32, 64]
    e = np.array([errors(solve(args, 1000, n), ref) for n in meshes])
    for n, (e_r, e_psi) in zip(meshes, e):
        print(f"info: n_el = {n:3d}: e_r = {e_r:.6e}, e_psi = {e_psi:.6e}")
    for i, n in enumerate(meshes[:-1]):
        ratio = e[i] / e[i + 1]
        print(f"info: e({n}) / e({2 * n}) = {ratio[0]:.4f} (e_r), {ratio[1]:.4f} (e_psi)")
        if n < 2:
            continue
        for j, field in enumerate(("e_r", "e_psi")):
            checks.check(f"|{field}({n}) / {field}({2 * n}) - 4| (order 2: within [3.5, 4.5])",
                         abs(ratio[j] - 4.0), 0.5)


def rho1e4(args, checks):
    r = solve(args, 10000, 1)
    print(f"info: rho = 1e4, 1 element: Newton iterations per increment "
          f"{r['series/newton/iterations'][1:].tolist()}")
    checks.check("rho = 1e4, 1 element: 1 - final load factor", 1.0 - r["time"][-1], 0)
    checks.check("rho = 1e4, 1 element: cut-backs of the 20 increments", r.cutbacks, 0)
    checks.check("rho = 1e4, 1 element: largest residual 2-norm at the end of an increment",
                 float(np.max(r["series/newton/residual"][1:])), 1e-11)
    r64 = solve(args, 10000, 64)
    print(f"info: rho = 1e4, 64 elements: Newton iterations per increment "
          f"{r64['series/newton/iterations'][1:].tolist()}, {r64.cutbacks} cut-back(s) (the "
          "stepper halves a failing increment and continues with the rest of the step)")
    checks.check("rho = 1e4, 64 elements: 1 - final load factor", 1.0 - r64["time"][-1], 0)
    checks.check("rho = 1e4, 64 elements: largest residual 2-norm at the end of an increment",
                 float(np.max(r64["series/newton/residual"][1:])), 1e-11)
    # The tolerance 1e-11 is loose against loads of that size (F_tip = 1.309e-11), so the
    # reference is solved to 1e-14, the smallest tolerance 256 elements reach (at 1e-15 the
    # first increment stalls at the round-off floor: DIVERGED_MAX_IT after 6 halvings).
    ref = solve(args, 10000, 256, atol=1e-14)
    e_r, e_psi = errors(r, ref)
    e64 = errors(r64, ref)
    print(f"info: rho = 1e4 against 256 elements (atol 1e-14): 1 element (atol 1e-11) "
          f"e_r = {e_r:.6f}, e_psi = {e_psi:.6f} (Table 1 6.792, 1.629); 64 elements (atol "
          f"1e-11) e_r = {e64[0]:.6e}, e_psi = {e64[1]:.6e} (Table 1 1.397e-3, 3.356e-4; "
          "above rho = 1e3's 1.432e-3, 3.599e-4 because atol 1e-11 leaves an error of the "
          "order of the loads; 1.43184e-3 at atol 1e-14)")
    checks.check("rho = 1e4: |e_r - 6.792| (1 element)", abs(e_r - 6.792), 5e-4)
    checks.check("rho = 1e4: |e_psi - 1.629| (1 element)", abs(e_psi - 1.629), 5e-4)


def main():
    cases = {"rho10": rho10, "rho1e3": rho1e3, "mesh64": mesh64, "order": order,
             "rho1e4": rho1e4}
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=sorted(cases))
    args = parser.parse_args()
    checks = rs.Checks()
    cases[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
