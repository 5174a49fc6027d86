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
