"""Rigid bodies on rod ends (issue 24 item 4, &bc kind = 'body'; src/formulations/ph_director/
ph_director_body.f90), against closed forms computed here.

    tip_body.py cantilever   input/tip_mass_cantilever.nml: the Euler-Bernoulli end-mass period
                             (acceptance 0.5 % at a fine mesh), with the mesh convergence shown,
                             and the condensed step against the full one
    tip_body.py pendulum     input/body_pendulum.nml: the rigid compound pendulum's period
    tip_body.py static       the tip-mass cantilever in statics under gravity, the body's weight
                             off the end: Euler-Bernoulli's tip deflection
    tip_body.py free         a free rod with a body off its end (centre offset, a full inertia
                             tensor), thrown spinning: energy and momenta kept to round-off, and
                             the momenta and the body's kinetic energy recomputed here from the
                             stored states (the rod's by Gauss quadrature of its interpolated
                             fields, the body's as 1/2 m |v_c|^2 + 1/2 omega . J omega)
"""
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402


def value(text, name):
    return float(re.search(r"\b" + name + r" = ([-0-9.eE+]+)", text).group(1))


def crossings(t, s, both=False):
    """Times where s crosses 0 upwards (and downwards with `both`), linearly interpolated."""
    out = []
    for i in range(1, s.size):
        if (s[i - 1] < 0.0 <= s[i]) or (both and s[i - 1] > 0.0 >= s[i]):
            out.append(t[i - 1] + (t[i] - t[i - 1]) * (-s[i - 1]) / (s[i] - s[i - 1]))
    return np.array(out)


def cantilever(args, checks):
    text = rs.read_example(args.source, "tip_mass_cantilever.nml")
    radius, length, young, density = (value(text, n) for n in ("radius", "length", "E", "density"))
    mass = value(text, "mass")
    rho_a = density * math.pi * radius**2
    ei = young * math.pi * radius**4 / 4.0
    mu = mass / (rho_a * length)
    from scipy.optimize import brentq
    lam = brentq(lambda l: 1.0 + math.cos(l) * math.cosh(l) + mu * l * (
        math.cos(l) * math.sinh(l) - math.sin(l) * math.cosh(l)), 0.5, 1.875104068711961)
    period = 2.0 * math.pi / (lam**2 * math.sqrt(ei / (rho_a * length**4)))
    print(f"info: mu = {mu:.6f}, lambda = {lam:.9f}, Euler-Bernoulli period {period:.9f} s")
    errors = {}
    for n in (4, 8, 16):
        r = rs.rod(rs.run(args, rs.set_variable(text, "rod", "n_elements", str(n)),
                          f"cantilever_{n}"), "beam")
        t, y = r["time"], r["position"][:, -1, 1]
        up = crossings(t, y - y.mean())
        measured = (up[-1] - up[0]) / (up.size - 1)
        errors[n] = measured / period - 1.0
        print(f"info: {n} elements: period {measured:.9f} s over {up.size - 1} periods, "
              f"relative error {errors[n]:+.3e}")
        if n == 16:
            # The end force's work is booked; the balance closes per step to the Newton
            # tolerance's share (measured 2e-15 of max H).
            checks.check("cantilever: largest |balance error| / max H per record",
                         float(np.max(np.abs(r["series/energy/balance_error"])) /
                               np.max(r["series/energy/total"])), 1e-13)
    # At 16 quadratic elements the period is the end-mass period to 8.8e-5 (the midpoint
    # rule's (omega h)^2 / 12 = 2e-5 and the rod's shear and rotary inertia, (r / L)^2).
    checks.check("cantilever: |T / T_Euler-Bernoulli - 1|, 16 elements (acceptance 0.5 %)",
                 abs(errors[16]), 1e-3)
    # The condensed step (velocities and stresses eliminated, methods §5.5) takes the body's
    # mass through d/dq = 2/h d/dv: it solves the same equations (measured 2.5e-14 m on a tip
    # deflection of 6.8e-5 m, the Newton tolerance's share).
    condensed = rs.set_variable(text, "solver", "condense_stresses", ".true.")
    tip = rs.rod(rs.run(args, condensed, "cantilever_condensed"), "beam")["position"][:, -1]
    reference = rs.rod(os.path.join(args.workdir, "cantilever_16.h5"), "beam")["position"][:, -1]
    checks.check("cantilever: max |tip (condensed) - tip| / max |tip deflection|",
                 float(np.max(np.abs(tip - reference)) / np.max(np.abs(reference[:, 1]))), 1e-8)
    # The mesh no longer matters at 16 elements: 8 and 16 agree to 2e-6 (4 elements differ by
    # 5e-5 from 16); what remains is the time step's and the rod's Timoshenko effects.
    checks.check("cantilever: |T(16 elements) / T(8 elements) - 1| (mesh converged)",
                 abs((1.0 + errors[16]) / (1.0 + errors[8]) - 1.0), 5e-5)


def pendulum(args, checks):
    from scipy.special import ellipk
    text = rs.read_example(args.source, "body_pendulum.nml")
    path = rs.run(args, text, "pendulum")
    r = rs.rod(path, "arm")
    t, end = r["time"], r["position"][:, -1]
    angle = np.arctan2(end[:, 0], -end[:, 2])
    zeros = crossings(t, angle, both=True)
    measured = 2.0 * (zeros[-1] - zeros[0]) / (zeros.size - 1)
    arm = text[text.index("name = 'arm'"):]
    radius, length, density = (value(arm, n) for n in ("radius", "length", "density"))
    body = text[text.index("kind = 'body'"):]
    mass = value(body, "mass")
    inertia = float(re.search(r"inertia = ([-0-9.eE+]+)", body).group(1))
    g = 9.81
    m_arm = density * math.pi * radius**2 * length
    pivot_inertia = (m_arm * length**2 / 3.0 + density * math.pi * radius**4 / 4.0 * length
                     + mass * length**2 + inertia)
    theta0 = float(angle[0])
    period = 4.0 * math.sqrt(pivot_inertia / (g * (m_arm * length / 2.0 + mass * length))) * \
        ellipk(math.sin(theta0 / 2.0)**2)
    print(f"info: theta_0 = {theta0:.6f} rad; compound pendulum period {period:.9f} s, "
          f"measured {measured:.9f} s over {(zeros.size - 1) / 2:.1f} periods")
    # The rod's flexibility (steel, E I / (M g L^2) ~ 1e3) and the midpoint rule's
    # (omega h)^2 / 12 = 4e-6: measured 1.3e-5. The books close to the Newton tolerance's share
    # (measured 1.1e-13 of max H).
    checks.check("pendulum: |T / T_compound - 1|", abs(measured / period - 1.0), 1e-3)
    both = [rs.rod(path, name) for name in ("stub", "arm")]
    total = sum(b["series/energy/total"] for b in both)
    booked = sum(np.cumsum(b["series/energy/external_work"]) for b in both)
    checks.check("pendulum: |H - W_gravity - H(0)| / max H (the books, gravity's work)",
                 float(np.max(np.abs(total - booked - total[0])) / np.max(np.abs(total))), 1e-11)


def static(args, checks):
    """The tip-mass cantilever in statics (quasistatic, gravity along -z, ramped): the body's
    weight acts at its centre of mass, a distance c beyond the end, so the tip deflects by
    q L^4 / (8 EI) + P L^3 / (3 EI) + P c L^2 / (2 EI) (the rod's weight q, the body's P,
    Euler-Bernoulli; the deflection is 1e-4 L, so the geometric terms are 1e-8)."""
    text = rs.read_example(args.source, "tip_mass_cantilever.nml")
    radius, length, young, density = (value(text, n) for n in ("radius", "length", "E", "density"))
    mass, offset, g = value(text, "mass"), 0.1, 0.05
    text = rs.set_variable(text, "time", "t_end", "1.0")
    text = rs.set_variable(text, "time", "dt", "0.5")
    text = rs.set_variable(text, "time", "quasistatic", ".true.")
    text = re.sub(r"&load .*?/", f"&load where = 'gravity', acceleration = 0, 0, {-g!r}, "
                  "time_function = 'ramp', t_off = 1 /", text, flags=re.S)
    text = text.replace("mass = ", f"centre = {offset!r}, 0, 0, mass = ", 1)
    r = rs.rod(rs.run(args, text, "static"), "beam")
    ei = young * math.pi * radius**4 / 4.0
    q = density * math.pi * radius**2 * g
    p = mass * g
    expected = -(q * length**4 / (8.0 * ei) + p * length**3 / (3.0 * ei) +
                 p * offset * length**2 / (2.0 * ei))
    tip = float(r["position"][-1, -1, 2])
    print(f"info: tip deflection {tip:.9e} m, Euler-Bernoulli {expected:.9e} m")
    # Shear (P L / (k G A) against P L^3 / (3 EI): 3 (r / L)^2 / (k G / E) ~ 2e-5 here) and
    # the geometric terms: measured 4.8e-5; without the body's offset moment it would be 10 %
    # off, without its weight 75 %.
    checks.check("static: |tip deflection / Euler-Bernoulli - 1|", abs(tip / expected - 1.0),
                 1e-3)


def lagrange2(xi):
    """Quadratic Lagrange shape values on [-1, 1] (nodes -1, 0, 1)."""
    return np.array([0.5 * xi * (xi - 1.0), 1.0 - xi * xi, 0.5 * xi * (xi + 1.0)])


def rod_momenta_and_energy(r, record, rho_a, rho_i, n_elements):
    """The rod's own kinetic energy, linear and angular momentum at a record, from its stored
    nodes (quadratic elements) with the rod's Gauss rule (n_gauss = 2, the default: its
    consistent mass is integrated with it, methods/ph_director_3d.md §4.3 eq. 112)."""
    x, v = r["position"][record], r["velocity"][record]
    d, w = r["directors"][record], r["director_velocity"][record]
    mesh = r["mesh"]
    points, weights = np.polynomial.legendre.leggauss(2)
    kinetic, linear, angular = 0.0, np.zeros(3), np.zeros(3)
    for e in range(n_elements):
        nodes = slice(2 * e, 2 * e + 3)
        half = 0.5 * (mesh[2 * e + 2] - mesh[2 * e])
        for xi, weight in zip(points, weights):
            n = lagrange2(xi)
            xg, vg = n @ x[nodes], n @ v[nodes]
            # Stored as [node, i, component]: row i is d_i.
            dg, wg = np.einsum("a,aij->ij", n, d[nodes]), np.einsum("a,aij->ij", n, w[nodes])
            ds = weight * half
            kinetic += ds * 0.5 * (rho_a * vg @ vg + rho_i * (wg[0] @ wg[0] + wg[1] @ wg[1]))
            linear += ds * rho_a * vg
            angular += ds * (rho_a * np.cross(xg, vg) + rho_i * (np.cross(dg[0], wg[0]) +
                                                               np.cross(dg[1], wg[1])))
    return kinetic, linear, angular


def free(args, checks):
    radius, density, n_elements = 0.01, 1000.0, 8
    mass, centre = 0.2, np.array([0.02, 0.01, -0.015])
    inertia = np.array([[2e-4, 3e-5, -1e-5], [3e-5, 3e-4, 2e-5], [-1e-5, 2e-5, 4e-4]])
    text = f"""&run title = 'a free rod with a body off its end' /
&time t_end = 0.2, dt = 1e-3 /
&solver newton_atol = 1e-12 /
&output path = 'placeholder.h5', stride = 1 /
&rod
    name = 'beam', formulation = 'ph_director', n_elements = {n_elements}, degree = 2,
    length = 0.5, start = 0, 0, 0, direction = 1, 0, 0, section = 'circle',
    radius = {radius!r}, E = 1e7, nu = 0.3, density = {density!r},
    velocity = 0.3, -0.2, 0.5, angular_velocity = 1.0, 4.0, -2.0
/
&bc
    rod = 'beam', end = 'end', kind = 'body', mass = {mass!r}, centre = {rs.vector(centre)},
    inertia = {rs.vector(np.diag(inertia))},
    inertia_products = {rs.vector([inertia[1, 2], inertia[0, 2], inertia[0, 1]])}
/
"""
    r = rs.rod(rs.run(args, text, "free"), "beam")
    total = r["series/energy/total"]
    p, l = r["series/momentum/linear"], r["series/momentum/angular"]
    steps = total.size - 1
    print(f"info: H = {total[0]:.9e} J, p = {p[0]}, l = {l[0]}")
    # (measured 2.2e-15, 2.2e-16 and 3.3e-16: round-off)
    checks.check("free: max |H - H(0)| / H(0)", float(np.max(np.abs(total - total[0])) / total[0]),
                 1e-13)
    checks.check("free: max |p - p(0)| (kg m/s)", float(np.max(np.abs(p - p[0]))), 1e-14)
    checks.check("free: max |l - l(0)| (kg m^2/s)", float(np.max(np.abs(l - l[0]))), 1e-14)
    checks.check("free: largest nodal orthonormality residual",
                 float(np.max(r["series/constraint_residual"])), 1e-14)
    # Recomputed here: the rod's part by quadrature, the body's in rigid-body form.
    rho_a = density * math.pi * radius**2
    rho_i = density * math.pi * radius**4 / 4.0
    # Directors as columns: the stored arrays hold d_i as row i.
    reference = r["directors"][0, -1].T
    body_centre = reference.T @ centre
    # The body in director form (rs_ph_director_body), written here from its definition:
    # E_ij = (tr(J_b)/2 I - J_b)_ij + m c_i c_j in the reference director basis.
    j_body = reference.T @ inertia @ reference
    second = 0.5 * np.trace(j_body) * np.eye(3) - j_body + mass * np.outer(body_centre, body_centre)
    worst = {"energy": 0.0, "linear": 0.0, "angular": 0.0}
    rigid = 0.0
    for record in range(0, steps + 1, 20):
        kinetic, linear, angular = rod_momenta_and_energy(r, record, rho_a, rho_i, n_elements)
        x, v = r["position"][record, -1], r["velocity"][record, -1]
        d, w = r["directors"][record, -1].T, r["director_velocity"][record, -1].T
        p_point = mass * (v + w @ body_centre)
        p_directors = mass * np.outer(v, body_centre) + w @ second
        kinetic += 0.5 * (v @ p_point + np.sum(w * p_directors))
        linear = linear + p_point
        angular = angular + np.cross(x, p_point) + sum(np.cross(d[:, i], p_directors[:, i])
                                                       for i in range(3))
        worst["energy"] = max(worst["energy"], abs(kinetic / r["series/energy/kinetic"][record] - 1.0))
        worst["linear"] = max(worst["linear"], float(np.linalg.norm(linear - p[record]) /
                                                     np.linalg.norm(p[record])))
        worst["angular"] = max(worst["angular"], float(np.linalg.norm(angular - l[record]) /
                                                       np.linalg.norm(l[record])))
        # The same body in rigid-body form, 1/2 m |v_c|^2 + 1/2 omega . J omega with
        # omega = 1/2 sum_i d_i x w_i: equal when the director rates are rigid, w_i = omega x
        # d_i. The midpoint scheme keeps the directors orthonormal at every step, but its
        # endpoint velocities v_{n+1} = 2 (q_{n+1} - q_n) / h - v_n are rigid only to O(h^2).
        v_c = v + w @ body_centre
        omega = 0.5 * sum(np.cross(d[:, i], w[:, i]) for i in range(3))
        rotation = d @ reference.T
        j_now = rotation @ inertia @ rotation.T
        rigid_form = 0.5 * mass * v_c @ v_c + 0.5 * omega @ j_now @ omega
        director_form = 0.5 * (v @ p_point + np.sum(w * p_directors))
        rigid = max(rigid, abs(rigid_form / director_form - 1.0))
    for name, error in worst.items():
        checks.check(f"free: {name} from the stored states (director form) against the code's, "
                     "relative (measured 2e-16 to 4e-16)", error, 1e-14)
    print(f"info: the body's kinetic energy in rigid form against the director form: {rigid:.2e}")
    checks.check("free: the body's rigid-body kinetic energy against its director form "
                 "(O(h^2): measured 7.6e-9)", rigid, 1e-7)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["cantilever", "pendulum", "free", "static"])
    args = parser.parse_args()
    checks = rs.Checks()
    {"cantilever": cantilever, "pendulum": pendulum, "free": free,
     "static": static}[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
