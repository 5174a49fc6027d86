"""Checks shared by the friction regressions of a rod on a slope (obstacles.py incline_*, a rod
on a tilted plane; rail_friction.py, a rod on a tilted rail): Coulomb's sliding and the
regularized law's stick branch, in closed form (docs/theory/bundles.md, Obstacles and
Friction)."""
import math

import numpy as np


def centre_of_mass(position, n_elements):
    """The centre of mass of a uniform rod from its nodes [records, nodes, 3]: Simpson's
    weights per quadratic element, the trapezoid's per linear one (se3_pg), exact for the
    interpolated centreline."""
    degree = (position.shape[1] - 1) // n_elements
    element = np.array([1.0, 4.0, 1.0]) / 6.0 if degree == 2 else np.array([0.5, 0.5])
    weights = np.zeros(position.shape[1])
    for e in range(n_elements):
        weights[degree * e:degree * e + degree + 1] += element
    weights /= weights.sum()
    return np.einsum("n,rnk->rk", weights, position)


def slope_books(checks, case, slider, rods, alpha, weight, n_elements, where):
    """The run of a rod (`slider`, a rod's fields) released on a slope of angle alpha with the
    weight `weight` (N), in contact with whatever `rods` (name: fields of every rod, the
    slider's included) lie on: its travel down the slope from its centre of mass, and the energy books
    from the stored states: the rods' H and contact energy + the dissipation booked so far -
    gravity's work on the slider (computed here) is constant, to the Newton residual's work
    (10 newton_atol per step times the step's motion: far below the bound 1e-11 J over 1000
    steps, against the energy scale m g travel of 1e-3 J; measured 1e-13 J); the code's own
    balance per record of each rod too. Returns the times, the travel and the dissipation."""
    t = slider["time"]
    c = centre_of_mass(slider["position"], n_elements)
    travel = c[-1, 0] - c[0, 0]
    print(f"info: {case}: Newton iterations {slider['series/newton/iterations'][1:].mean() / 10:.2f} "
          f"per step (records every 10 steps); travel {where} {travel * 1e3:.6f} mm in "
          f"{t[-1]:.3f} s, across {np.ptp(c[:, 1]):.2e} m, normal {np.ptp(c[:, 2]):.2e} m")
    gravity_work = (c - c[0]) @ (weight * np.array([math.sin(alpha), 0.0, -math.cos(alpha)]))
    dissipated = np.cumsum(sum(r["series/energy/dissipated"] for r in rods.values()))
    books = sum(r["series/energy/total"] + r["series/contact/energy"] for r in rods.values()) + \
        dissipated - gravity_work
    print(f"info: dissipated {dissipated[-1]:.6e} J, gravity's work {gravity_work[-1]:.6e} J")
    checks.check(f"{case}: max |H + E_contact + D - W_gravity - (its start)| (J)",
                 float(np.max(np.abs(books - books[0]))), 1e-11)
    for name, r in rods.items():
        checks.check(f"{case}: the code's balance error per record of {name} (J)",
                     float(np.max(np.abs(r["series/energy/balance_error"]))), 1e-11)
    return t, travel, dissipated[-1]


def check_slope(checks, case, sliding, alpha, mu, slip_velocity, weight, t_end, travel,
                dissipated, dissipation_rtol, t, friction, slip):
    """A rod of weight `weight` (N) on a slope of angle alpha with friction mu, released at
    rest, travelled `travel` (m) down it in t_end and dissipated `dissipated` (J).
    Sliding: a = g (sin(alpha) - mu cos(alpha)) once the slip exceeds the slip velocity (the
    regularization's share of the force is (v_s / v)^2 / 2 < 1e-5 after 1 ms), and D = mu N
    travel (to `dissipation_rtol`, the scene's normal bounce). Stuck: the regularized law
    balances the slope's pull at the creep velocity v = v_s beta / sqrt(1 - beta^2),
    beta = tan(alpha) / mu, reached within a step, and creeping at a steady speed the rod keeps
    its kinetic energy: friction takes all the work of the pull (gravity's component along the
    slope; the normal one's work is the rod settling). The recorded friction of each step
    (series/contact/friction and slip_speed at the times t, averaged over the late half) is
    -mu N along the slope and the points slip at the rod's speed a t when sliding; stuck, the
    friction balances the pull and the points creep at v."""
    late = t > 0.5 * t[-1]
    g = 9.81
    if sliding:
        a = g * (math.sin(alpha) - mu * math.cos(alpha))
        expected = 0.5 * a * t_end**2
        print(f"info: expected travel {expected * 1e3:.6f} mm")
        checks.check(f"{case}: |travel / (a t^2 / 2) - 1| (acceptance 1 %)",
                     abs(travel / expected - 1.0), 0.01)
        checks.check(f"{case}: dissipation = mu N travel, relative",
                     abs(dissipated / (mu * weight * math.cos(alpha) * travel) - 1.0),
                     dissipation_rtol)
        # (measured 9e-4 on the rail, where the normal bounce modulates N; 3e-7 on the plane)
        checks.check(f"{case}: mean recorded friction / (-mu N) - 1 (late half)",
                     abs(float(np.mean(friction[late, 0])) / (-mu * weight * math.cos(alpha))
                         - 1.0), 1e-2)
        # (measured 4.5e-4 on the rail, 1.4e-5 on the plane)
        checks.check(f"{case}: largest slip speed / (a t) - 1 at the end",
                     abs(float(slip[-1]) / (a * t[-1]) - 1.0), 5e-3)
    else:
        beta = math.tan(alpha) / mu
        creep = slip_velocity * beta / math.sqrt(1.0 - beta**2)
        print(f"info: creep v t = {creep * t_end * 1e3:.6f} mm")
        checks.check(f"{case}: |dissipated / the pull's work - 1| (stuck)",
                     abs(dissipated / (weight * math.sin(alpha) * travel) - 1.0), 1e-2)
        checks.check(f"{case}: |travel / (creep t) - 1| (the stick branch's creep)",
                     abs(travel / (creep * t_end) - 1.0), 0.01)
        # (measured 5e-5 and 4.6e-4 on the rail, 2e-7 and 3e-7 on the plane)
        checks.check(f"{case}: mean recorded friction / (-pull) - 1 (late half)",
                     abs(float(np.mean(friction[late, 0])) / (-weight * math.sin(alpha)) - 1.0),
                     1e-3)
        checks.check(f"{case}: mean largest slip speed / creep speed - 1 (late half)",
                     abs(float(np.mean(slip[late])) / creep - 1.0), 5e-3)
        # Frictionless the rod would slide g sin(alpha) t^2 / 2 (9.6 mm at tan(alpha) = 0.2).
        checks.check(f"{case}: travel / frictionless slide (stuck)",
                     travel / (0.5 * g * math.sin(alpha) * t_end**2), 1e-2)
