"""Damping of ph_director (issue 26 item 1; docs/theory/ph_director.md "Damping",
docs/theory/damping.md): Kelvin-Voigt viscosity as a Maxwell branch of zero compliance
(seed 000 Remark 5.2), condensed per element, and the drags on the centreline and the sections.

    damping.py decrement  Kelvin-Voigt cantilever (input/damped_cantilever.nml): the logarithmic
                          decrement of its free vibration against the damped Euler-Bernoulli
                          mode, at h and h/2, and inextensible (constrained components carry no
                          viscous stress)
    damping.py balance    the flying spaghetti (methods §6.1) with Kelvin-Voigt, drag, angular
                          drag, each alone and all together: H_{n+1} - H_n - W_n + D_n at
                          round-off with W_n and D_n computed here from the stored motion, and
                          D_n > 0 in every step
    damping.py terminal   a free rod falling under gravity against drag: v(t) = v_t (1 -
                          exp(-c t / rhoA)), v_t = rhoA g / c (1 %), and the midpoint rule's own
                          recursion to round-off; its Kelvin-Voigt viscosity does not act on the
                          rigid fall
    damping.py spin       a free rod spinning about its own axis against angular drag: w(t) =
                          w0 exp(-c_w t / (rhoI1 + rhoI2)); Kelvin-Voigt and drag do not act on
                          the rigid spin

Every closed form is computed here from the scene's parameters, never read from the program.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

#: beta_1 L of the first clamped-free Euler-Bernoulli mode.
BETA_1 = 1.875104068711961
#: 2-point Gauss points on [-1, 1] and the quadratic Lagrange shape functions there (nodes at
#: xi = -1, 0, 1): the stress points of p = 2 (docs/user/output.md `stress_mesh`).
GAUSS = np.array([-1.0, 1.0]) / math.sqrt(3.0)
SHAPE = np.array([[0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)] for x in GAUSS])


# ---- decrement -------------------------------------------------------------------------------

def cantilever_constants(text):
    """omega_1 and zeta of input/damped_cantilever.nml's first mode, from its section and
    material: circle of `radius`, E, density; zeta = tau omega_1 / 2 (docs/theory/damping.md)."""
    radius = rs.number(text, "rod", "radius")
    young = rs.number(text, "rod", "E")
    density = rs.number(text, "rod", "density")
    length = rs.number(text, "rod", "length")
    tau = rs.number(text, "rod", "kelvin_voigt_time")
    area, inertia = math.pi * radius**2, math.pi * radius**4 / 4
    omega = (BETA_1 / length)**2 * math.sqrt(young * inertia / (density * area))
    return omega, tau * omega / 2


def tip_decrement(r, period):
    """The logarithmic decrement of the tip's transverse (y) motion: the maxima after 1.5
    periods (the pulse over, the higher modes gone: zeta_2 = 6.27 zeta_1), each from the
    parabola through its three samples, and the slope of log(maximum) against its count.
    For one damped mode A exp(-zeta w t) cos(w_d t + phi) the maxima are a damped period
    apart and in the ratio exp(delta) exactly."""
    t, y = r["time"], r["position"][:, -1, 1]
    k = np.arange(1, y.size - 1)
    k = k[(y[k] > y[k - 1]) & (y[k] >= y[k + 1]) & (t[k] > 1.5 * period)]
    a, b, c = y[k - 1], y[k], y[k + 1]
    peaks = b - 0.125 * (a - c)**2 / (a - 2 * b + c)
    slope = np.polyfit(np.arange(peaks.size), np.log(peaks), 1)[0]
    return -slope, peaks.size


def decrement(args, checks):
    """The damped first mode of input/damped_cantilever.nml (8 quadratic elements, one
    Kelvin-Voigt time for all six components, zeta = 0.05): delta = 2 pi zeta / sqrt(1 -
    zeta^2) from the Euler-Bernoulli omega_1. Measured on the Release build (in brackets):
    h = T/100 (-6.6e-4), h = T/200 (-1.7e-4): the midpoint rule's (omega h)^2 error, so order 2
    in h (the ratio of the errors 4.005), and the mesh and the Timoshenko terms (r/L = 2e-3)
    are below that; the inextensible rod (shear and dilatation rigid: no viscous stress there,
    docs/theory/ph_director.md) the same mode (-6.5e-4). Bounds: 2e-3 at h = T/100
    (acceptance: 2 %), 5e-4 at T/200, the ratio of the two errors 4 within 0.5 (order 2).

    The energy balance of this small motion (H ~ 4e-6 J) is bounded by the Newton tolerance
    (1e-10: the condensed viscous stress puts V = tau EA = 5e3 N s between the rounding of the
    positions and the residual, docs/theory/ph_director.md "Damping"): 1e-7 of max H
    (1.6e-8, 8.9e-9 at h/2; inextensible, V on bending and torsion only, 1.0e-10); D_n > 0 in
    every step. The exact balance of a large motion is the case `balance`."""
    text = rs.read_example(args.source, "damped_cantilever.nml")
    omega, zeta = cantilever_constants(text)
    expected = 2 * math.pi * zeta / math.sqrt(1 - zeta**2)
    period = 2 * math.pi / omega
    dt = rs.number(text, "time", "dt")
    print(f"info: omega_1 = {omega:.6f} rad/s, zeta = {zeta:.6f}, delta = {expected:.6f}")
    errors = {}
    for label, scene in (("h", text),
                         ("h/2", rs.set_variable(text, "time", "dt", repr(dt / 2))),
                         ("inextensible", rs.set_variable(text, "rod", "constraint",
                                                          "'inextensible'"))):
        r = rs.rod(rs.run(args, scene, "decrement_" + label.replace("/", "_")), "cantilever")
        measured, count = tip_decrement(r, period)
        errors[label] = (measured - expected) / expected
        print(f"info: {label}: delta = {measured:.6f} from {count} maxima, relative error "
              f"{errors[label]:.3e}")
        total = r["series/energy/total"]
        dissipated = r["series/energy/dissipated"][1:]
        checks.check(f"{label}: max_n |balance_error_n| / max H",
                     np.max(np.abs(r["series/energy/balance_error"])) / np.max(total), 1e-7)
        checks.check(f"{label}: steps with D_n <= 0", float(np.sum(dissipated <= 0.0)), 0.0)
    checks.check("|delta - delta_EB| / delta_EB, h = T/100", abs(errors["h"]), 2e-3)
    checks.check("|delta - delta_EB| / delta_EB, h = T/200", abs(errors["h/2"]), 5e-4)
    checks.check("|error(h) / error(h/2) - 4| (order 2 in h)",
                 abs(errors["h"] / errors["h/2"] - 4.0), 0.5)
    checks.check("|delta - delta_EB| / delta_EB, inextensible, h = T/100",
                 abs(errors["inextensible"]), 2e-3)


# ---- balance ---------------------------------------------------------------------------------

#: Damping of the spaghetti variants: Kelvin-Voigt time for every component, drag, angular drag.
SPAGHETTI_DAMPING = {"kelvin_voigt": (0.05, 0.0, 0.0), "drag": (0.0, 0.2, 0.0),
                     "angular_drag": (0.0, 0.0, 2.0), "all": (0.05, 0.2, 2.0)}
#: The least share of the loads' work each variant dissipates by t = 15 (measured: 1.5 %,
#: 81 %, 81 %, 98 %): Kelvin-Voigt takes only the vibration's energy, not the rigid motion's.
SPAGHETTI_SHARE = {"kelvin_voigt": 0.01, "drag": 0.5, "angular_drag": 0.5, "all": 0.5}
#: input/flying_spaghetti.nml: stiffnesses in the strain order (Gamma1, Gamma2, Gamma3, K1, K2,
#: K3) = (GA1, GA2, EA, EI1, EI2, GJ).
SPAGHETTI_STIFFNESS = np.array([1e4, 1e4, 1e4, 1e3, 1e3, 1e3])


def viscous_dissipation(r, tau):
    """D_n of the Kelvin-Voigt stress from the stored strains (docs/theory/ph_director.md
    "Damping"): with p = 2 and 2-point Gauss the stress points are the Gauss points and the
    stress basis interpolates there, so s_v = V Delta eps / h at each point and
    D_n = h sum w s_v . V^-1 s_v = sum (le/2) Delta eps . V Delta eps / h, V = tau k."""
    t = rs.one_step_per_record(r)
    viscosity = tau * SPAGHETTI_STIFFNESS
    increment = np.diff(r["strain"], axis=0)              # (steps, points, 6)
    nodes = r["mesh"]
    weight = np.repeat(0.5 * (nodes[2::2] - nodes[:-2:2]), 2)
    return np.sum(weight * np.sum(viscosity * increment**2, axis=2), axis=1) / np.diff(t)


def drag_dissipation(r, drag, angular_drag):
    """D_n of the drags from the stored nodal velocities: h int u . diag(c I, c_w/2 I9) u ds
    with u the interpolated midpoint velocity (v_n + v_{n+1})/2 of the centreline and the three
    directors, integrated with the scheme's 2-point Gauss rule on each quadratic element."""
    t = rs.one_step_per_record(r)
    v = np.concatenate([r["velocity"], r["director_velocity"].reshape(t.size, -1, 9)], axis=2)
    mid = 0.5 * (v[1:] + v[:-1])                           # (steps, nodes, 12)
    nodes = r["mesh"]
    damp = np.array([drag] * 3 + [0.5 * angular_drag] * 9)
    total = np.zeros(t.size - 1)
    for e in range(nodes.size // 2):
        le = nodes[2 * e + 2] - nodes[2 * e]
        for g in range(2):
            u = np.einsum("a,nac->nc", SHAPE[g], mid[:, 2 * e:2 * e + 3, :])
            total += 0.5 * le * np.sum(damp * u**2, axis=1)
    return np.diff(t) * total


def balance(args, checks):
    """The flying spaghetti (methods §6.1, 10 quadratic elements, h = 0.1, 150 steps) with each
    law alone and all together. W_n of the end loads (run_scene.end_load_work) and D_n
    (viscous_dissipation, drag_dissipation) are computed here from the paper's loads, the
    damping coefficients and the stored states. Bounds, measured on the Release build in
    brackets: the balance 1e-13 of max H (KV 7e-15, drag 5e-15, angular 5e-15, all 1.9e-14;
    the condensed viscous stress puts Newton at its rounding floor, 2e-11 to 5e-11 in the
    residual, which shows here); the stored D_n against the test's 1e-12 of max D_n (5e-15 to
    2.7e-14: the strain increments from the stored strains against the program's B(q_mid)
    (q_{n+1} - q_n)); D_n > 0 in every step; each law dissipates a share of the loads' work
    (SPAGHETTI_SHARE), so that the balance tests the dissipation and not only the work."""
    base = rs.read_example(args.source, "flying_spaghetti.nml")
    for label, (tau, drag, angular_drag) in SPAGHETTI_DAMPING.items():
        text = base
        for name, value in (("kelvin_voigt_time", tau), ("drag", drag),
                            ("angular_drag", angular_drag)):
            if value > 0.0:
                text = rs.set_variable(text, "rod", name, repr(value))
        r = rs.rod(rs.run(args, text, "balance_" + label), "spaghetti")
        total = r["series/energy/total"]
        top = np.max(total)
        work = rs.end_load_work(r, -1, (0.1, 0.0, 0.0), (0.0, 1.0, 0.5),
                                lambda s: 200.0 * rs.time_function("hat", s, 0.0, 5.0))
        dissipation = np.zeros(work.size)
        if tau > 0.0:
            dissipation += viscous_dissipation(r, tau)
        if drag > 0.0 or angular_drag > 0.0:
            dissipation += drag_dissipation(r, drag, angular_drag)
        stored = r["series/energy/dissipated"][1:]
        checks.check(f"{label}: max_n |H_{{n+1}} - H_n - W_n + D_n| / max H (W, D: test)",
                     np.max(np.abs(np.diff(total) - work + dissipation)) / top, 1e-13)
        checks.check(f"{label}: max_n |balance_error_n| / max H (the program's)",
                     np.max(np.abs(r["series/energy/balance_error"])) / top, 1e-13)
        checks.check(f"{label}: max_n |D_n (test) - dissipated_n| / max D_n",
                     np.max(np.abs(dissipation - stored)) / np.max(dissipation), 1e-12)
        checks.check(f"{label}: steps with D_n (test) <= 0", float(np.sum(dissipation <= 0.0)),
                     0.0)
        checks.check(f"{label}: the damping matters: -(sum D_n) / (sum W_n)",
                     -np.sum(dissipation) / np.sum(work), -SPAGHETTI_SHARE[label])
        print(f"info: {label}: sum W_n = {np.sum(work):.6e}, sum D_n = {np.sum(dissipation):.6e}, "
              f"H(15) = {total[-1]:.6e}, smallest D_n = {np.min(dissipation):.3e}, Newton "
              f"residual at most {np.max(r['series/newton/residual']):.2e}")


# ---- terminal velocity and spin --------------------------------------------------------------

def free_rod(t_end, dt, extra, atol):
    """A free straight rod along e1 (L = 1, 4 quadratic elements, rhoA = 1, rhoI = 0.01 each,
    EA = GA = 1e4, EI = GJ = 10), with `extra` lines in its &rod and the groups after it, and
    the Newton tolerance `atol`."""
    return f"""&run
    title = 'damped free rod'
/
&time
    t_end = {t_end}
    dt = {dt}
/
&solver
    newton_atol = {atol}
/
&output
    path = 'out/free_rod.h5'
/
&rod
    name = 'rod'
    formulation = 'ph_director'
    n_elements = 4, degree = 2, n_gauss = 2
    start = 0.0, 0.0, 0.0
    direction = 1.0, 0.0, 0.0
    d1 = 0.0, 1.0, 0.0
    length = 1.0
    EA = 1e4, GA1 = 1e4, GA2 = 1e4, EI1 = 10.0, EI2 = 10.0, GJ = 10.0
    rhoA = 1.0, rhoI1 = 0.01, rhoI2 = 0.01
{extra}"""


def terminal(args, checks):
    """A free rod (rhoA = 1) falls under g = 9.81 against drag c = 2 (a = c / rhoA = 2 1/s),
    h = 0.025 for t = 4 (exp(-a t) = 3.4e-4): v(t) = v_t (1 - exp(-a t)), v_t = rhoA g / c.
    The fall is a rigid translation, so the rod's Kelvin-Voigt viscosity (given) must not act.
    Newton tolerance 1e-10: tau = 0.1 s makes V = tau EA = 1e3 N s, which turns the rounding of
    positions 20 m from the origin into residuals of 5e-11 (docs/theory/ph_director.md
    "Damping"); 1e-12 is below that floor.
    The centre-of-mass velocity is p_z / (rhoA L). The midpoint rule's recursion for this
    linear law is v_{n+1} = ((1 - a h/2) v_n - h g) / (1 + a h/2), whose limit is exactly v_t:
    checked to 1e-12 (measured 1.8e-13 relative to v_t, the Newton tolerance); the closed form
    to its O((a h)^2) accuracy, 2e-4 of v_t (measured 7.7e-5; (a h)^2/12 = 2.1e-4); the end
    velocity against v_t, 1 % (3.3e-4, the remaining exp(-a t)); the energy balance with the
    weight's work and the drag's dissipation computed here, 1e-12 of max |H| (1.2e-14)."""
    g, c, rho_a, length, h, t_end = 9.81, 2.0, 1.0, 1.0, 0.025, 4.0
    extra = f"""    drag = {c}, kelvin_voigt_time = 0.1
/
&load
    where = 'gravity', acceleration = 0.0, 0.0, -{g}
/
"""
    r = rs.rod(rs.run(args, free_rod(t_end, h, extra, 1e-10), "terminal"), "rod")
    t = rs.one_step_per_record(r)
    v = r["series/momentum/linear"][:, 2] / (rho_a * length)
    a = c / rho_a
    v_t = -rho_a * g / c
    closed = v_t * (1 - np.exp(-a * t))
    recursion = np.zeros(t.size)
    for n in range(t.size - 1):
        recursion[n + 1] = ((1 - a * h / 2) * recursion[n] - h * g) / (1 + a * h / 2)
    checks.check("|v(4) - v_t| / |v_t| (terminal velocity)", abs(v[-1] - v_t) / abs(v_t), 1e-2)
    checks.check("max_n |v_n - v_t (1 - exp(-a t_n))| / |v_t|",
                 np.max(np.abs(v - closed)) / abs(v_t), 2e-4)
    checks.check("max_n |v_n - midpoint recursion| / |v_t|",
                 np.max(np.abs(v - recursion)) / abs(v_t), 1e-12)
    horizontal = r["series/momentum/linear"][:, :2]
    checks.check("no horizontal motion: max |p_x|, |p_y|", np.max(np.abs(horizontal)), 1e-12)
    total = r["series/energy/total"]
    checks.check("max_n |balance_error_n| / max |H|",
                 np.max(np.abs(r["series/energy/balance_error"])) / np.max(np.abs(total)), 1e-12)
    # The weight's work is rhoA L g times the fall of the centre of mass; with no motion
    # relative to the rigid fall, the drag dissipates c L |v_mid|^2 h per step.
    fall = np.diff(r["series/center_of_mass"][:, 2])
    work = -rho_a * length * g * fall
    dissipation = c * length * fall**2 / np.diff(t)
    checks.check("max_n |H_{n+1} - H_n - W_n + D_n| / max |H| (W, D: test)",
                 np.max(np.abs(np.diff(total) - work + dissipation)) / np.max(np.abs(total)), 1e-12)
    print(f"info: v(4) = {v[-1]:.10f}, v_t = {v_t:.10f}; closed form error "
          f"{np.max(np.abs(v - closed)) / abs(v_t):.2e}, recursion error "
          f"{np.max(np.abs(v - recursion)) / abs(v_t):.2e}, balance "
          f"{np.max(np.abs(r['series/energy/balance_error'])) / np.max(np.abs(total)):.2e}")


def spin(args, checks):
    """The free rod spinning about its own axis (d3 = e1) at w0 = 2 rad/s against angular drag
    c_w = 0.04 N s: the moment -c_w w on the axial inertia rhoI1 + rhoI2 = 0.02 kg m gives
    w(t) = w0 exp(-a t), a = c_w / (rhoI1 + rhoI2) = 2 1/s, so the angle turned is
    theta(t) = w0 (1 - exp(-a t)) / a. The rod also has drag and Kelvin-Voigt viscosity:
    neither may act on a rigid spin about the centreline. theta from d1 at the tip (atan2 of
    its e3 and e2 components, unwrapped), t = 2, h = 0.02 and 0.01. Bounds, measured in
    brackets: theta against the closed form 3e-4 of w0/a at h = 0.02 (1.0e-4: the midpoint
    rule's O((a h)^2), (a h)^2/12 = 1.3e-4), the error's ratio between h and h/2 4 within 0.05
    (1e-4: order 2); the midpoint spin rate (theta_{n+1} - theta_n)/h against w(t_{n+1/2}) 5e-4 of
    w0 (1.4e-4); d3 and the centreline at rest 1e-13 (0: the spin is exact about the axis);
    the energy balance 1e-11 of H(0) (1.0e-12, Newton tolerance 1e-10)."""
    w0, c_w, rho_i, t_end = 2.0, 0.04, 0.01, 2.0
    a = c_w / (2 * rho_i)
    extra = f"""    angular_velocity = {w0}, 0.0, 0.0
    rotation_center = 0.5, 0.0, 0.0
    angular_drag = {c_w}, drag = 0.5, kelvin_voigt_time = 0.1
/
"""
    errors = []
    for h in (0.02, 0.01):
        r = rs.rod(rs.run(args, free_rod(t_end, h, extra, 1e-12), f"spin_h{h:g}"), "rod")
        t = rs.one_step_per_record(r)
        d1 = r["directors"][:, -1, 0, :]
        theta = np.unwrap(np.arctan2(d1[:, 2], d1[:, 1]))
        theta -= theta[0]
        closed = w0 * (1 - np.exp(-a * t)) / a
        errors.append(np.max(np.abs(theta - closed)) / (w0 / a))
        total = r["series/energy/total"]
        print(f"info: h = {h:g}: theta(2) = {theta[-1]:.8f}, closed form {closed[-1]:.8f}; "
              f"H(2)/H(0) = {total[-1] / total[0]:.6f} against exp(-2 a t) = "
              f"{math.exp(-2 * a * t_end):.6f}")
        if h < 0.02:
            continue
        checks.check("h = 0.02: max_n |theta_n - w0 (1 - exp(-a t_n)) / a| / (w0 / a)",
                     errors[0], 3e-4)
        rate = np.diff(theta) / np.diff(t)
        t_mid = 0.5 * (t[1:] + t[:-1])
        checks.check("h = 0.02: max_n |(theta_{n+1} - theta_n) / h - w0 exp(-a t_{n+1/2})| / w0",
                     np.max(np.abs(rate - w0 * np.exp(-a * t_mid))) / w0, 5e-4)
        still = max(np.max(np.abs(r["directors"][:, :, 2, :] - [1.0, 0.0, 0.0])),
                    np.max(np.abs(r["position"] - r["position"][0])))
        checks.check("d3 and the centreline stay put: max |d3 - e1|, |phi - phi(0)|", still, 1e-13)
        checks.check("max_n |balance_error_n| / H(0)",
                     np.max(np.abs(r["series/energy/balance_error"])) / total[0], 1e-11)
    checks.check("|error(h) / error(h/2) - 4| (order 2 against the closed form)",
                 abs(errors[0] / errors[1] - 4.0), 0.05)


def main():
    rs.run_cases(__doc__, {"decrement": decrement, "balance": balance, "terminal": terminal,
                           "spin": spin})


if __name__ == "__main__":
    main()
