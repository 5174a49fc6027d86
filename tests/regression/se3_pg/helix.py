"""SE(3) helix: a straight rod bent into a two-coil helix by a follower end moment with constant
K components, the locking test with an exactly representable constant-strain solution of seed
002 §4.2 (Table 2; methods/se3_petrov_galerkin.md §10.2, §14.2), input/se3_helix.nml.

    helix.py rho10     slenderness 10, Table 2: Newton tolerance 1e-8, 70 increments
    helix.py rho1e2    slenderness 1e2: 1e-9, 100 increments
    helix.py rho1e3    slenderness 1e3: 1e-10, 200 increments
    helix.py rho1e4    slenderness 1e4: 1e-11, 500 increments
    helix.py rho1e3_tight, rho1e4_tight
                       the same with a STRICTER Newton tolerance than Table 2's (1e-13 and
                       1e-16): at these slendernesses the tangent's smallest stiffness is so
                       small (EI / L^3 = 7e-12 and 7e-16) that a residual of Table 2's size
                       allows tip errors far above 1e-8 (rho = 1e3: 2.2e-7 at 1e-10; methods
                       §14.2 saw 3.3e-7, "limited by the tolerance"), and at rho = 1e4 an
                       increment's load (3e-13) is below 1e-11, so Newton skips increments
                       until the lag fails (input/se3_helix.nml header)

Each case checks (issue 7, methods §10.2 "Expected result"): the run reaches the full load (a
failing increment is halved by the stepper, up to &solver max_cutbacks times; the cut-backs are
reported), the residual 2-norm at the end of every increment is within the tolerance, the tip
at r*(1) = (0, -10, 50) per component; the nodes at r*(i/5) per component and their frames at
the Serret-Frenet frame (e_x^K, e_y^K, e_z^K) = (d3, d1, d2) (the angle of A^T A*); every
element's strains K gamma = (1, 0, 0) and K kappa = (c, 0, 1) R0 alpha'^2 / L^2 = (0.0343506,
0, 0.0863324) per component (a rotation error delta of the nodes changes the strain by about
delta / l_e, l_e = 27). Issue 7 asks for 1e-8 in each; the bounds here are tighter, per case
(BOUNDS).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import se3_field  # noqa: E402
import se3_scene  # noqa: E402
from se3_scene import rs  # noqa: E402

ROD = "helix"
R0, COILS, HEIGHT = 10.0, 2, 50.0
C = HEIGHT / (R0 * 2 * np.pi * COILS)
S0 = np.sqrt(1 + C**2)
LENGTH = S0 * R0 * 2 * np.pi * COILS
ALPHA_PRIME = 2 * np.pi * COILS
X = R0 * ALPHA_PRIME**2 / LENGTH**2
N_ELEMENTS = 5
# Table 2: slenderness -> (Newton tolerance, load increments).
TABLE_2 = {10: (1e-8, 70), 100: (1e-9, 100), 1000: (1e-10, 200), 10000: (1e-11, 500)}
#: Issue 7's acceptance (1e-8 per component) is far above what the exactly representable
#: solution gives, so each case has its own bounds, about 10 to 50 times the Release build's
#: errors (in brackets): (positions of the tip and nodes, nodal frame angles, strains).
#: rho = 10 and 1e2 sit at round-off of positions of size 50 (eps 50 = 1e-14): 1e-12 (2.9e-14)
#: and 1e-11 (4.3e-13); angles 1e-13 (2.6e-15) and 1e-12 (4.8e-14). The two slender cases are
#: limited by their tight Newton tolerances (module header): 2e-10 (1.0e-11, 9e-12), angles
#: 2e-11 (1.2e-12, 1.0e-12). Strains are constant per element and exact at any load: 1e-14
#: (4.8e-16, 5.6e-16) and 2e-13 (1.2e-14, 1.1e-14). The cases at Table 2's own tolerances,
#: not run by ctest, keep the issue's 1e-8 (which they miss, module header).
BOUNDS = {(10, 1e-8): (1e-12, 1e-13, 1e-14), (100, 1e-9): (1e-11, 1e-12, 1e-14),
          (1000, 1e-13): (2e-10, 2e-11, 2e-13), (10000, 1e-16): (2e-10, 2e-11, 2e-13)}
ISSUE_7 = (1e-8, 1e-8, 1e-8)


def exact(xi):
    """r*(xi) and the frame A*(xi) = (e_x^K, e_y^K, e_z^K) of methods §10.2 (eqs. 54-56)."""
    alpha = ALPHA_PRIME * xi
    r = R0 * np.array([np.sin(alpha), -np.cos(alpha), C * alpha])
    e_x = np.array([np.cos(alpha), np.sin(alpha), C]) / S0
    e_y = np.array([-np.sin(alpha), np.cos(alpha), 0.0])
    e_z = np.array([-C * np.cos(alpha), -C * np.sin(alpha), 1.0]) / S0
    return r, np.column_stack([e_x, e_y, e_z])


def scene(args, rho, atol=None):
    atol = TABLE_2[rho][0] if atol is None else atol
    increments = TABLE_2[rho][1]
    radius = LENGTH / (2 * rho)
    k_b = np.pi * radius**4 / 4          # E I, E = 1
    k_t = 2 * 0.5 * np.pi * radius**4 / 4   # G I_polar, G = 0.5: k_t = k_b
    # K c = (k_t c, 0, k_b) X in K = (d3, d1, d2), i.e. (d1, d2, d3) = (0, k_b X, k_t c X).
    return se3_scene.edit(rs.read_example(args.source, "se3_helix.nml"), [
        ("rod", "radius", repr(radius)), ("solver", "newton_atol", repr(atol)),
        ("time", "dt", repr(1.0 / increments)),
        ("load", "moment", rs.vector((0.0, k_b * X, k_t * C * X)))])


def helix(args, checks, rho, atol=None):
    atol = TABLE_2[rho][0] if atol is None else atol
    increments = TABLE_2[rho][1]
    r = se3_scene.run(args, scene(args, rho, atol), f"rho{rho}_atol{atol:g}", ROD,
                      allow_failure=True)
    residual = r["series/newton/residual"][1:]
    iterations = r["series/newton/iterations"][1:]
    print(f"info: rho = {rho}, atol {atol:g}, {increments} increments: {r.summary()}; "
          f"Newton iterations per increment min {iterations.min()}, mean "
          f"{iterations.mean():.2f}, max {iterations.max()}; largest final residual "
          f"{np.max(residual):.3e}, last {residual[-1]:.3e}")
    checks.check(f"rho = {rho}: exit status of rodsolve", r.status, 0)
    checks.check(f"rho = {rho}: 1 - final load factor", 1.0 - r["time"][-1], 0)
    checks.check(f"rho = {rho}: largest residual 2-norm at the end of an increment",
                 float(np.max(residual)), atol)
    bound_position, bound_angle, bound_strain = BOUNDS.get((rho, atol), ISSUE_7)
    position, directors = r["position"][-1], r["directors"][-1]
    tip = position[-1]
    print(f"info: rho = {rho}: tip ({tip[0]:.3e}, {tip[1]:.12f}, {tip[2]:.12f}); error "
          f"{np.array2string(tip - [0.0, -10.0, 50.0], precision=3)}")
    for c, expected in enumerate((0.0, -10.0, 50.0)):
        checks.check(f"rho = {rho}: |tip component {c} - ({expected})|", abs(tip[c] - expected),
                     bound_position)
    frames = se3_field.frames(directors)
    node_error, angle_error = 0.0, 0.0
    for i in range(N_ELEMENTS + 1):
        r_star, a_star = exact(i / N_ELEMENTS)
        node_error = max(node_error, float(np.max(np.abs(position[i] - r_star))))
        angle_error = max(angle_error,
                          float(np.linalg.norm(se3_field.log_so3(frames[i].T @ a_star))))
    checks.check(f"rho = {rho}: nodes: largest |r_i - r*(i/5)| component", node_error,
                 bound_position)
    checks.check(f"rho = {rho}: nodes: largest angle of A_i^T A*(i/5)", angle_error,
                 bound_angle)
    # Strains in director components (Gamma1, Gamma2, Gamma3, K1, K2, K3) = (gamma_y, gamma_z,
    # gamma_x, kappa_y, kappa_z, kappa_x).
    strain = r["strain"][-1]
    expected = np.array([0.0, 0.0, 1.0, 0.0, X, C * X])
    print(f"info: rho = {rho}: element strains K gamma, K kappa: "
          f"{np.array2string(strain[:, [2, 0, 1]], precision=9)} | "
          f"{np.array2string(strain[:, [5, 3, 4]], precision=9)} (exact (1, 0, 0) | "
          f"({C * X:.7f}, 0, {X:.7f}))")
    checks.check(f"rho = {rho}: strains: largest |gamma - (1, 0, 0)| component",
                 float(np.max(np.abs(strain[:, :3] - expected[:3]))), bound_strain)
    checks.check(f"rho = {rho}: strains: largest |kappa - (0.0343506, 0, 0.0863324)| component",
                 float(np.max(np.abs(strain[:, 3:] - expected[3:]))), bound_strain)


def main():
    cases = {"rho10": (10, None), "rho1e2": (100, None), "rho1e3": (1000, None),
             "rho1e4": (10000, None), "rho1e3_tight": (1000, 1e-13),
             "rho1e4_tight": (10000, 1e-16)}
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=sorted(cases))
    args = parser.parse_args()
    checks = rs.Checks()
    helix(args, checks, *cases[args.case])
    checks.finish()


if __name__ == "__main__":
    main()
