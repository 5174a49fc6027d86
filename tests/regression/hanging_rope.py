"""Prestretched starts (issue 26 item 3; docs/theory/prestretched_starts.md): a rope placed
stretched between two pins (&rod prestrain), started in its static equilibrium under gravity
(&time initial_equilibrium) and released from one pin (&bc release_time), built from
input/hanging_rope.nml (stress-free length L0 = 1 m, prestrain 1e-3, rhoA = 0.1 kg/m, EA = 1000
N, EI / (rhoA g L0^3) = 1e-6, g = 9.81; the closed forms are computed here).

    hanging_<formulation>  both pins kept, at one height, 1.001 m apart: the rope hangs as the
                           elastic (extensible) catenary. The test's own closed form, in the
                           stress-free arc length S, with H the horizontal force and V = w L0 / 2
                           the vertical reaction (w = rhoA g per stress-free length):
                             x(S) = H S / EA + (H / w) [asinh((w S - V) / H) + asinh(V / H)],
                             y(S) = (w S^2 / 2 - V S) / EA + [sqrt(H^2 + (w S - V)^2)
                                    - sqrt(H^2 + V^2)] / w,
                           H from x(L0) = span: sag 32.41 mm, H = 3.782 N (the stretch under the
                           rope's own weight raises the prestrain's tension EA eps = 1 N almost
                           fourfold). Nodes are compared at S = s / (1 + eps). Checks: the
                           largest nodal distance from the closed form relative to the sag, and
                           its fall between two meshes (second order: the ratio of the errors
                           4 +- 1); each element's tension against |T(S)| = sqrt(H^2 + (w S -
                           V)^2) at its midpoint (relative); and, started in that equilibrium,
                           the largest nodal speed over 100 steps (h = 0.001) below 1e-10 m/s
                           (the velocity scale of the rope's swing, omega1 times the sag, is
                           0.1 m/s). ph_planar at 20 and 40 elements: measured 5.0e-3 and
                           1.26e-3 of the sag (ratio 3.97; bound 2e-3), tension 7e-6 (bound
                           1e-4), speed 0 (Newton's first residual is below newton_atol).
                           se3_pg, whose two-node SE(3) elements converge more slowly on this
                           nearly bending-free rope, at 80 and 160: 1.17e-2 and 3.5e-3 (ratio
                           3.3; bound 5e-3), tension 4.0e-3 (bound 6e-3, converging as the
                           shape), speed 5e-11 (Newton at its rounding floor); its start is
                           clamped, because a rope pinned at both ends can spin about the line
                           through the pins, a zero-stiffness mode of the statics (the clamp's
                           bending boundary layer, sqrt(EI / H) = 0.5 mm, is below the element
                           length and does not move the sag).
    swing_<formulation>    the example: the lower pin 5 cm to the side of the vertical through
                           the upper one, held until t = 0.1 s. The horizontal displacement u
                           from the vertical through the upper pin is projected on the first mode
                           of the hanging chain, u1(X) = J0(j01 sqrt(X / L0)) (X = L0 - S from
                           the free end; trapezoidal weights in S: the mass weight under which
                           the chain's modes are orthogonal), and the period of that modal
                           coordinate is 2 (t_2 - t_1) from its first two zero crossings (linear
                           interpolation, exact to O(h^3) at a crossing). Closed form: omega1 =
                           (j01 / 2) sqrt(g / L) with L = L0 (1 + rhoA g L0 / (2 EA)) the hanging
                           length under the rope's own weight (its extensibility alone moves the
                           period by 2.5e-4 from that of L0): T1 = 1.668777 s.
                           What separates the rod from the chain besides: the bending stiffness
                           (measured with cl_em_planar at 160 elements: the period moves by 1e-5
                           between EI ratios 1e-6 and 1.6e-5 with the top pinned; a clamped top
                           would shorten it by 1.5 sqrt(EI / (rhoA g L^3)), 1.5e-3, and is
                           avoided), the finite amplitude (5 % of L: of order 1e-4) and the
                           discretization: the midpoint rule's (omega1 h)^2 / 12 = 1.2e-4 at
                           h = 0.01, and the mesh. Checks, at three levels of mesh and step
                           halved together: the period at the finest within 1e-3 of the closed
                           form; convergence: the change from the middle to the finest level
                           at most half the change from the coarsest to the middle (second
                           order gives a quarter; measured 0.31 to 0.35); at rest while both
                           pins hold (largest speed up to the release below 1e-10 m/s); the
                           released end swings across the vertical; and for the
                           energy-consistent planar schemes the energy balance through the
                           release, |H_{n+1} - H_n - W_n| per step below 1e-10 of max H
                           (round-off: a held coordinate does not move, so its reaction does no
                           work; measured below 5e-12).
                           Measured period errors: cl_em_planar (EI ratio 1e-6; 20/40/80
                           elements, h = 0.02/0.01/0.005) 5.0e-4, 1.8e-4, 7.5e-5; ph_planar (EI
                           ratio 1e-4; 40/80/160, h = 0.01/0.005/0.0025) 1.7e-4, 3.8e-5,
                           -2.1e-6; se3_pg (EI ratio 1e-6, generalized-alpha rho_inf = 0.5;
                           20/40/80) 7.0e-4, 2.9e-4, 1.4e-4.
                           ph_planar needs the larger EI: PH-EM's rate-form strains drift from
                           the compatible ones where the nodal rotations are nearly free
                           (methods/ph_planar.md §4.5), and at EI ratio 1e-6 (or 1e-4 with 20
                           elements) the released rope's top element stretches to metres
                           without force, which its energy balance, exact in the mixed strains,
                           does not see (the same without any of the new input: a rope released
                           from a straight slanted start). se3_pg's lower end is clamped until
                           the release (a pinned top and pinned lower end have the spin mode
                           above) and it runs generalized-alpha: its midpoint rule is not
                           energy-conserving for this element (methods/se3_petrov_galerkin.md
                           §7.4), and the rope's unresolved stiff modes make its Newton fail
                           after the release; generalized-alpha needs their damping (rho_inf =
                           0.9 fails at 20 and 40 elements, 0.8 and 0.5 pass at all three).
"""
import numpy as np
from scipy.optimize import brentq
from scipy.special import j0

from run_scene import run_cases, run, rod, read_example, set_variable, number

J01 = 2.404825557695773
EXAMPLE = "hanging_rope.nml"
RELEASE_TIME = 0.1
RELEASED_END = f"kind = 'pinned', release_time = {RELEASE_TIME}"
# EI / (rhoA g L0^3) of each formulation's swing (the docstring says why ph_planar's is larger).
SWING_EI_RATIO = {"ph_planar": 1e-4, "cl_em_planar": 1e-6, "se3_pg": 1e-6}
# (elements, h) of the swings' convergence study; ph_planar's coarsest mesh at EI ratio 1e-4
# drifts away like its 1e-6 (the bending stiffness per element, EI / h_e, is what holds the
# nodal rotations), so its levels start at 40 elements.
SWING_LEVELS = {"ph_planar": ((40, 0.01), (80, 0.005), (160, 0.0025)),
                "cl_em_planar": ((20, 0.02), (40, 0.01), (80, 0.005)),
                "se3_pg": ((20, 0.02), (40, 0.01), (80, 0.005))}


def rope_data(text):
    eps = number(text, "rod", "prestrain")
    length = number(text, "rod", "length")
    return dict(eps=eps, L0=length / (1 + eps), EA=number(text, "rod", "EA"),
                rhoA=number(text, "rod", "rhoA"), g=-numbers_y(text))


def numbers_y(text):
    from run_scene import numbers
    return numbers(text, "load", "acceleration")[1]


def variant(text, formulation, n, dt, t_end, ei=None, horizontal=False, keep_end=False,
            clamped_start=False, scheme=None):
    """The example with another formulation, mesh, step and span, or its ends changed."""
    text = set_variable(text, "rod", "formulation", f"'{formulation}'")
    text = set_variable(text, "rod", "n_elements", str(n))
    text = set_variable(text, "time", "dt", repr(dt))
    text = set_variable(text, "time", "t_end", repr(t_end))
    if ei is not None:
        for name in ("EI1", "EI2", "GJ"):
            text = set_variable(text, "rod", name, repr(ei))
    if horizontal:
        text = set_variable(text, "rod", "direction", "1.0, 0.0, 0.0")
    if keep_end:
        text = text.replace(RELEASED_END, "kind = 'pinned'")
    if clamped_start:
        text = text.replace("end = 'start', kind = 'pinned'", "end = 'start', kind = 'clamped'")
    if scheme is not None:
        text = set_variable(text, "time", "scheme", f"'{scheme[0]}'")
        text = set_variable(text, "time", "rho_inf", repr(scheme[1]))
    return text


def catenary(d, span):
    """The elastic catenary through two pins at one height `span` apart: x(S), y(S), |T(S)|."""
    w = d["rhoA"] * d["g"]
    ea, l0 = d["EA"], d["L0"]
    v = 0.5 * w * l0

    def x_of(s, h):
        return h * s / ea + h / w * (np.arcsinh((w * s - v) / h) + np.arcsinh(v / h))

    h = brentq(lambda h: x_of(l0, h) - span, 1e-6 * w * l0, 1e6 * w * l0, xtol=1e-15)

    def y_of(s):
        return (0.5 * w * s**2 - v * s) / ea + (np.hypot(h, w * s - v) - np.hypot(h, v)) / w
    return (lambda s: x_of(s, h)), y_of, (lambda s: np.hypot(h, w * s - v)), h


def hanging_case(formulation, meshes, clamped_start, shape_bound, tension_bound):
    def case(args, checks):
        example = read_example(args.source, EXAMPLE)
        d = rope_data(example)
        span = number(example, "rod", "length")
        x_of, y_of, tension_of, h_force = catenary(d, span)
        sag = -y_of(0.5 * d["L0"])
        errors = []
        for n in meshes:
            text = variant(example, formulation, n, 0.001, 0.1, horizontal=True, keep_end=True,
                           clamped_start=clamped_start)
            r = rod(run(args, text, f"hanging_{n}"), "rope")
            s = r["mesh"] / (1 + d["eps"])
            p = r["position"]
            errors.append(np.max(np.hypot(p[0, :, 0] - x_of(s), p[0, :, 1] - y_of(s))) / sag)
            s_mid = r["stress_mesh"] / (1 + d["eps"])
            tension = np.max(np.abs(r["stress"][0, :, 2] / tension_of(s_mid) - 1))
            speed = np.max(np.linalg.norm(r["velocity"], axis=2))
            print(f"info: {formulation}, {n} elements: sag {-p[0, n // 2, 1]:.6e} m (closed "
                  f"form {sag:.6e} m, H = {h_force:.6f} N); shape error {errors[-1]:.3e} of "
                  f"the sag; tension {tension:.3e}; largest speed {speed:.3e} m/s")
        checks.check(f"shape at {meshes[-1]} elements: largest distance from the elastic "
                     "catenary / sag", errors[-1], shape_bound)
        checks.check("second order: |error ratio between the meshes - 4|",
                     abs(errors[0] / errors[1] - 4), 1.0)
        checks.check("element tension against the catenary's (relative)", tension,
                     tension_bound)
        checks.check("largest nodal speed over 100 steps from the equilibrium (m/s)", speed,
                     1e-10)
    return case


def swing_period(r, d):
    """The period of the first hanging-chain mode's coordinate, from its first two zero
    crossings."""
    t = r["time"]
    p = r["position"]
    big_x = d["L0"] - r["mesh"] / (1 + d["eps"])
    weights = np.full(big_x.size, abs(big_x[1] - big_x[0]))
    weights[[0, -1]] *= 0.5
    mode = j0(J01 * np.sqrt(np.maximum(big_x, 0.0) / d["L0"]))
    u = p[:, :, 0] - p[:, :1, 0]
    q1 = (u * weights * mode).sum(axis=1) / (weights * mode**2).sum()
    k = np.where(np.sign(q1[1:]) != np.sign(q1[:-1]))[0]
    crossings = t[k] - q1[k] * (t[k + 1] - t[k]) / (q1[k + 1] - q1[k])
    if crossings.size < 2:
        return np.inf
    return 2 * (crossings[1] - crossings[0])


def swing_case(formulation, scheme=None, clamped_end=False, energy=True):
    def case(args, checks):
        example = read_example(args.source, EXAMPLE)
        d = rope_data(example)
        hanging = d["L0"] * (1 + d["rhoA"] * d["g"] * d["L0"] / (2 * d["EA"]))
        exact = 2 * np.pi / (0.5 * J01 * np.sqrt(d["g"] / hanging))
        ei = SWING_EI_RATIO[formulation] * d["rhoA"] * d["g"] * d["L0"]**3
        errors = []
        levels = SWING_LEVELS[formulation]
        if clamped_end:
            example = example.replace("end = 'end', " + RELEASED_END,
                                      "end = 'end', kind = 'clamped', release_time = "
                                      f"{RELEASE_TIME}")
        for n, h in levels:
            text = variant(example, formulation, n, h, 2.0, ei=ei, scheme=scheme)
            r = rod(run(args, text, f"swing_{n}"), "rope")
            errors.append(swing_period(r, d) / exact - 1)
            balance = np.max(np.abs(r["series/energy/balance_error"])) / \
                np.max(np.abs(r["series/energy/total"]))
            tip = r["position"][:, -1, 0] - r["position"][:, 0, 0]
            held = r["time"] <= RELEASE_TIME + 1e-12
            speed = np.max(np.linalg.norm(r["velocity"][held], axis=2))
            print(f"info: {formulation}, {n} elements, h = {h}: period error {errors[-1]:.3e} "
                  f"(closed form {exact:.6f} s); energy balance {balance:.3e} of max H")
        checks.check(f"period at {levels[-1][0]} elements, h = {levels[-1][1]} "
                     "(relative error)", abs(errors[-1]), 1e-3)
        checks.check("convergence: |e_fine - e_mid| / |e_mid - e_coarse|",
                     abs(errors[2] - errors[1]) / abs(errors[1] - errors[0]), 0.5)
        checks.check("at rest while both pins hold: largest nodal speed (m/s)", speed, 1e-10)
        checks.check("the released end swings across the vertical (min tip offset, m)",
                     np.min(tip), 0.0 - 1e-3)
        if energy:
            checks.check("energy balance through the release / max H", balance, 1e-10)
    return case


CASES = {
    "hanging_ph_planar": hanging_case("ph_planar", (20, 40), False, 2e-3, 1e-4),
    "hanging_se3_pg": hanging_case("se3_pg", (80, 160), True, 5e-3, 6e-3),
    "swing_ph_planar": swing_case("ph_planar"),
    "swing_cl_em_planar": swing_case("cl_em_planar"),
    "swing_se3_pg": swing_case("se3_pg", scheme=("generalized_alpha", 0.5), clamped_end=True,
                               energy=False),
}

if __name__ == "__main__":
    run_cases(__doc__.splitlines()[0], CASES)
