#!/usr/bin/env python3
"""Reference axial stiffness of a simple straight 1+m strand (Costello's linear theory).

A straight core wire of radius R1 and m helical wires of radius R2 laid on it (helix radius
r2 = R1 + R2, lay angle theta between wire tangent and strand axis), linear elastic (E, nu).
Under a small strand strain eps with the strand ends held against rotation (Costello's beta = 0),
the axial force and torque are F = K_eps eps and M = K_m eps. The derivation follows Costello,
Theory of Wire Rope (2nd ed., Springer 1997), ch. 3 "simple straight strand", and Costello &
Phillips (1976), and is written out in docs/theory/bundles.md, "Reference: Costello's strand
theory", whose symbols this file uses:

    alpha = pi/2 - theta      Costello's helix angle (wire tangent against the cross-section
                              plane); s = sin(alpha) = cos(theta), c = cos(alpha) = sin(theta)
    kappa0 = c^2 / r2         curvature of the helical wire (about its binormal)
    tau0   = s c / r2         torsion of the helical wire (twist of its Frenet frame)

    kinematics (linear): eps      = xi + cot(alpha) d_alpha                       (K1)
                         r2 tau_s = cot(alpha) (xi - d_r / r2) - d_alpha          (K2)
                         d_r      = -nu (R1 eps + R2 xi) - C_c p                  (K3)
    wire curvature and twist changes (per deformed length, Love/Costello):
                         d_kappa = -2 s c d_alpha / r2 - c^2 d_r / r2^2
                         d_tau   = (c^2 - s^2) d_alpha / r2 - s c d_r / r2^2
    wire loads:          T = E A2 xi,  G' = E I2 d_kappa,  H = G J2 d_tau = E I2 d_tau / (1 + nu)
                         N' = H kappa0 - G' tau0
                         p = -X = T kappa0 - N' tau0    (line load of a wire on the core)
    strand resultants:   F = E A1 eps + m (T s + N' c)
                         M = G J1 tau_s + m (H s + G' c + r2 (T c - N' s))

with xi the wire strain, d_alpha the change of the helix angle, d_r of the helix radius, tau_s
the strand's twist per unit length (0 with rotation held) and C_c an optional radial contact
compliance (m^2/N, 0 in Costello). Variants (keyword arguments) switch off the Poisson term of
(K3), the wire bending and torsion, or measure the curvature changes per reference length (the
Cosserat-rod strains of rodsolve); `simple_axial_stiffness` is E (A1 + m A2 cos^3 theta).

Importable:  costello_axial_stiffness(R1, R2, alpha, E, nu, rotation_fixed=True) -> dict
             (alpha is the LAY angle theta in radians; K_eps in N, K_m in N m per unit strain).
Command line: python3 scripts/costello_strand.py [--R1 ..] [--R2 ..] [--lay-angle DEG] [--E ..]
             [--nu ..] [--wires 6] [--penalty K --strain EPS] [--sweep] prints the variants.
Only numpy; no rodsolve imports.
"""

import argparse
import math
import sys

import numpy as np


def _geometry(R1, R2, alpha, E, nu, n_wires):
    """The constants of one strand; alpha is the lay angle (rad)."""
    if not (R1 > 0.0 and R2 > 0.0 and E > 0.0 and -1.0 < nu <= 0.5 and n_wires >= 1):
        raise ValueError('need R1, R2, E > 0, -1 < nu <= 0.5 and at least one helical wire')
    if not 0.0 <= alpha < 0.5 * math.pi:
        raise ValueError('the lay angle must lie in [0, pi/2)')
    helix = 0.5 * math.pi - alpha
    s, c = math.sin(helix), math.cos(helix)
    r2 = R1 + R2
    A1, A2 = math.pi * R1**2, math.pi * R2**2
    I1, I2 = 0.25 * math.pi * R1**4, 0.25 * math.pi * R2**4
    G = E / (2.0 * (1.0 + nu))
    return dict(R1=R1, R2=R2, r2=r2, lay=alpha, helix=helix, s=s, c=c, E=E, nu=nu, G=G,
                m=n_wires, EA1=E * A1, EA2=E * A2, EI2=E * I2, GJ1=G * 2.0 * I1,
                GJ2=G * 2.0 * I2, kappa0=c**2 / r2, tau0=s * c / r2)


def _wire_loads(g, xi, d_kappa, d_tau, kappa, tau, wire_bending):
    """T, G', H, N' of a helical wire from its strain and curvature changes."""
    T = g['EA2'] * xi
    if wire_bending:
        Gp = g['EI2'] * d_kappa
        H = g['GJ2'] * d_tau
    else:
        Gp = H = 0.0
    Np = H * kappa - Gp * tau
    return T, Gp, H, Np


def linear_response(g, eps, tau_s, *, poisson_contraction=True, wire_bending=True,
                    curvature_measure='deformed', radial_compliance=0.0, extra_approach=0.0):
    """The linearized state of a right-handed strand at strand strain eps and twist tau_s.

    Solves (K1)-(K3) for xi, d_alpha, d_r (all linear, p included through radial_compliance);
    extra_approach is a fixed additional inward radial displacement of the helical wires (m),
    used by penalty_secant_stiffness. Returns the dict of intermediate quantities and F, M.
    """
    if curvature_measure not in ('deformed', 'reference'):
        raise ValueError("curvature_measure is 'deformed' or 'reference'")
    s, c, r = g['s'], g['c'], g['r2']
    nu_k = g['nu'] if poisson_contraction else 0.0
    ref = 1.0 if curvature_measure == 'reference' else 0.0
    # Coefficient rows (on x = [xi, d_alpha, d_r]) of the curvature and twist changes.
    dk_row = np.array([ref * c**2 / r, -2.0 * s * c / r, -c**2 / r**2])
    dt_row = np.array([ref * s * c / r, (c**2 - s**2) / r, -s * c / r**2])
    if wire_bending:
        Gp_row, H_row = g['EI2'] * dk_row, g['GJ2'] * dt_row
    else:
        Gp_row, H_row = np.zeros(3), np.zeros(3)
    T_row = np.array([g['EA2'], 0.0, 0.0])
    Np_row = H_row * g['kappa0'] - Gp_row * g['tau0']
    p_row = T_row * g['kappa0'] - Np_row * g['tau0']
    cot = c / s
    A = np.array([[1.0, cot, 0.0],
                  [cot, -1.0, -cot / r],
                  [nu_k * g['R2'], 0.0, 1.0]])
    A[2] += radial_compliance * p_row
    b = np.array([eps, r * tau_s, -nu_k * g['R1'] * eps - extra_approach])
    x = np.linalg.solve(A, b)
    xi, d_alpha, d_r = x
    T, Gp, H, Np = T_row @ x, Gp_row @ x, H_row @ x, Np_row @ x
    F = g['EA1'] * eps + g['m'] * (T * s + Np * c)
    M = g['GJ1'] * tau_s + g['m'] * (H * s + Gp * c + r * (T * c - Np * s))
    return dict(xi=xi, d_alpha=d_alpha, d_r=d_r, d_kappa=dk_row @ x, d_tau=dt_row @ x,
                T=T, G_prime=Gp, H=H, N_prime=Np, X=-(p_row @ x), p=p_row @ x, F=F, M=M)


def exact_response(g, eps, tau_s, *, poisson_contraction=True, wire_bending=True,
                   curvature_measure='deformed', radial_compliance=0.0):
    """The same state with the exact (nonlinear) helix kinematics, for checking the algebra.

    Unknowns xi, alpha_f, r_f of the deformed helix:
      (1 + xi) sin(alpha_f) = (1 + eps) sin(alpha)
      (1 + xi) cos(alpha_f) / r_f = cos(alpha) / r2 + tau_s sin(alpha)
      r_f = r2 - nu (R1 eps + R2 xi) - C_c p
    with curvature cos^2(alpha_f)/r_f and torsion sin cos/r_f of the deformed helix (per
    deformed length; times 1 + xi per reference length). Solved by Newton with a
    finite-difference Jacobian.
    """
    a0, r0 = g['helix'], g['r2']
    nu_k = g['nu'] if poisson_contraction else 0.0
    per_ref = curvature_measure == 'reference'

    def state(y):
        xi, af, rf = y
        stretch = (1.0 + xi) if per_ref else 1.0
        kf, tf = math.cos(af)**2 / rf, math.sin(af) * math.cos(af) / rf
        d_kappa = stretch * kf - g['kappa0']
        d_tau = stretch * tf - g['tau0']
        T, Gp, H, Np = _wire_loads(g, xi, d_kappa, d_tau, kf, tf, wire_bending)
        p = T * kf - Np * tf
        return T, Gp, H, Np, p, af, rf

    def residual(y):
        xi, af, rf = y
        p = state(y)[4]
        return np.array([
            (1.0 + xi) * math.sin(af) - (1.0 + eps) * math.sin(a0),
            (1.0 + xi) * math.cos(af) / rf - math.cos(a0) / r0 - tau_s * math.sin(a0),
            (rf - r0 + nu_k * (g['R1'] * eps + g['R2'] * xi) + radial_compliance * p) / r0])

    y = np.array([eps, a0, r0])
    for _ in range(50):
        f = residual(y)
        if np.max(np.abs(f)) < 1e-15:
            break
        J = np.empty((3, 3))
        for j in range(3):
            h = 1e-7 * max(1.0, abs(y[j]))
            yp, ym = y.copy(), y.copy()
            yp[j] += h
            ym[j] -= h
            J[:, j] = (residual(yp) - residual(ym)) / (2.0 * h)
        y = y - np.linalg.solve(J, f)
    T, Gp, H, Np, p, af, rf = state(y)
    F = g['EA1'] * eps + g['m'] * (T * math.sin(af) + Np * math.cos(af))
    M = g['GJ1'] * tau_s + g['m'] * (H * math.sin(af) + Gp * math.cos(af)
                                     + rf * (T * math.cos(af) - Np * math.sin(af)))
    return dict(xi=y[0], alpha_f=af, r_f=rf, F=F, M=M, p=p)


def simple_axial_stiffness(R1, R2, alpha, E, n_wires=6):
    """E (A1 + m A2 cos^3(theta)): wires as axially loaded bars, no Poisson term, no bending."""
    return E * math.pi * (R1**2 + n_wires * R2**2 * math.cos(alpha)**3)


def helical_wire_clearance(R1, R2, alpha, n_wires=6):
    """Costello's condition whether the helical wires touch each other.

    In the plane normal to the strand axis a helical wire's section is (nearly) an ellipse
    with semi-axes R2 (radial) and R2 / sin(alpha_h) (alpha_h = pi/2 - theta); neighbours,
    2 pi / m apart, touch when the ray at pi/m from the strand centre is tangent to it:
        r2_touch = R2 sqrt(1 + tan^2(pi/2 - pi/m) / sin^2(alpha_h)).
    Returns (r2 / r2_touch, touch): r2 / r2_touch > 1 means the wires of the layer are apart.
    """
    helix = 0.5 * math.pi - alpha
    r_touch = R2 * math.sqrt(1.0 + math.tan(0.5 * math.pi - math.pi / n_wires)**2
                             / math.sin(helix)**2)
    ratio = (R1 + R2) / r_touch
    return ratio, ratio <= 1.0


def costello_axial_stiffness(R1, R2, alpha, E, nu, rotation_fixed=True, *, n_wires=6,
                             poisson_contraction=True, wire_bending=True,
                             curvature_measure='deformed', radial_compliance=0.0,
                             handedness=1):
    """Costello's linear axial stiffness of a 1+m strand.

    R1, R2: core and helical wire radii (m); alpha: lay angle theta (rad, wire tangent against
    the strand axis); E (Pa), nu. rotation_fixed: ends held against rotation (beta = 0);
    otherwise the strand turns freely (M = 0). handedness +1 (right) or -1 (left) sets the
    sign of the torque and of the twist coupling. Returns a dict:
      K_eps      F / eps (N)
      K_m        M / eps (N m) with rotation held; 0 when rotation is free
      twist_per_strain  tau_s / eps (rad/m) when rotation is free, else 0
      stiffness_matrix  [[dF/deps, dF/dtau_s], [dM/deps, dM/dtau_s]] (tau_s in rad/m)
      K_simple   E (A1 + m A2 cos^3 theta);  K_straight  E (A1 + m A2)
      per_strain the intermediate quantities per unit strain at the state used for K_eps
                 (xi, d_alpha, d_r, d_kappa, d_tau, T, G_prime, H, N_prime, X)
      clearance  r2 / r2_touch of helical_wire_clearance; helical_wires_touch
    """
    if handedness not in (1, -1):
        raise ValueError('handedness is +1 (right) or -1 (left)')
    g = _geometry(R1, R2, alpha, E, nu, n_wires)
    opts = dict(poisson_contraction=poisson_contraction, wire_bending=wire_bending,
                curvature_measure=curvature_measure, radial_compliance=radial_compliance)
    unit_eps = linear_response(g, 1.0, 0.0, **opts)
    unit_tau = linear_response(g, 0.0, 1.0, **opts)
    h = float(handedness)
    matrix = np.array([[unit_eps['F'], h * unit_tau['F']],
                       [h * unit_eps['M'], unit_tau['M']]])
    if rotation_fixed:
        state, twist = unit_eps, 0.0
        K_eps, K_m = matrix[0, 0], matrix[1, 0]
    else:
        twist = -matrix[1, 0] / matrix[1, 1]
        state = linear_response(g, 1.0, h * twist, **opts)
        K_eps, K_m = matrix[0, 0] + matrix[0, 1] * twist, 0.0
    ratio, touch = helical_wire_clearance(R1, R2, alpha, n_wires)
    keys = ('xi', 'd_alpha', 'd_r', 'd_kappa', 'd_tau', 'T', 'G_prime', 'H', 'N_prime', 'X')
    per_strain = {k: state[k] for k in keys}
    per_strain['H'] *= h
    per_strain['d_tau'] *= h
    return dict(K_eps=K_eps, K_m=K_m, twist_per_strain=twist, stiffness_matrix=matrix,
                K_simple=simple_axial_stiffness(R1, R2, alpha, E, n_wires),
                K_straight=E * math.pi * (R1**2 + n_wires * R2**2),
                per_strain=per_strain, clearance=ratio, helical_wires_touch=touch)


def line_contact_load(delta, k, r_c):
    """Line load (N/m of helical wire) of rodsolve's contact potential on a straight core.

    The potential psi(d2) = k (r_c^2 - d2)^3 / (3 r_c^4) (J/m^2, k in N/m^3) integrated over the
    arc lengths of both rods (src/contact/contact_potential.f90, &contact stiffness): a point of
    the helical wire at distance r_f = r_c - delta from the core's centreline has the energy
    per unit wire length e = (32/35) k a^7 / (3 r_c^4), a^2 = r_c^2 - r_f^2, so it is pushed
    out by p = -de/dr_f = (32/15) k r_f a^5 / r_c^4 ~ 12.07 k delta^(5/2) / sqrt(r_c).
    (The exact continuous integral; Gauss quadrature resolves it only if the support 2a spans
    several Gauss points of the core.)
    """
    if delta <= 0.0:
        return 0.0
    r_f = r_c - delta
    a2 = r_c**2 - r_f**2
    return 32.0 / 15.0 * k * r_f * a2**2.5 / r_c**4


def line_contact_penetration(p, k, r_c):
    """delta with line_contact_load(delta) = p (bisection; delta < 0.4 r_c, below the peak)."""
    if p <= 0.0:
        return 0.0
    lo, hi = 0.0, 0.4 * r_c
    if line_contact_load(hi, k, r_c) < p:
        raise ValueError('line load beyond what the penalty can carry')
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if line_contact_load(mid, k, r_c) < p:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def penalty_secant_stiffness(R1, R2, alpha, E, nu, k, eps, *, n_wires=6,
                             poisson_contraction=False, wire_bending=True,
                             curvature_measure='reference'):
    """F / eps at strand strain eps, rotation held, with the helical wires sinking into the
    core by the penalty penetration delta(p) of line_contact_load (the rodsolve model: no
    Poisson contraction by default, Cosserat strains per reference length).

    delta enters (K3) as an extra inward approach; it is found by bisection on
    g(delta) = delta - delta_pen(p(delta)), which increases in delta. Returns
    (K_secant, delta, p).
    """
    g = _geometry(R1, R2, alpha, E, nu, n_wires)
    opts = dict(poisson_contraction=poisson_contraction, wire_bending=wire_bending,
                curvature_measure=curvature_measure)
    r_c = R1 + R2

    def mismatch(delta):
        state = linear_response(g, eps, 0.0, extra_approach=delta, **opts)
        return delta - line_contact_penetration(max(state['p'], 0.0), k, r_c), state

    lo, hi = 0.0, 0.0
    hi_state = linear_response(g, eps, 0.0, **opts)
    # The approach at which the wires no longer press on the core bounds delta from above.
    hi = max(hi_state['p'], 0.0) / max(-(linear_response(g, 0.0, 0.0, extra_approach=1.0,
                                                         **opts)['p']), 1e-300)
    hi = min(hi, 0.39 * r_c)
    if mismatch(hi)[0] <= 0.0:
        return hi_state['F'] / eps, 0.0, hi_state['p']
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mismatch(mid)[0] < 0.0:
            lo = mid
        else:
            hi = mid
    delta = 0.5 * (lo + hi)
    state = mismatch(delta)[1]
    return state['F'] / eps, delta, state['p']


def variants(R1, R2, alpha, E, nu, n_wires=6):
    """(label, K_eps, K_m) of the simple formula and the Costello variants, rotation held."""
    rows = [('E (A1 + m A2 cos^3 theta)', simple_axial_stiffness(R1, R2, alpha, E, n_wires),
             float('nan'))]
    cases = [
        ('no Poisson, no wire bending', dict(poisson_contraction=False, wire_bending=False)),
        ('Poisson, no wire bending', dict(wire_bending=False)),
        ('Costello (Poisson, bending, torsion)', dict()),
        ('no Poisson, bending, per reference length',
         dict(poisson_contraction=False, curvature_measure='reference')),
        ('Poisson, bending, per reference length', dict(curvature_measure='reference')),
    ]
    for label, opts in cases:
        res = costello_axial_stiffness(R1, R2, alpha, E, nu, n_wires=n_wires, **opts)
        rows.append((label, res['K_eps'], res['K_m']))
    return rows


def _main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--R1', type=float, default=1.05e-3, help='core wire radius (m)')
    parser.add_argument('--R2', type=float, default=1.0e-3, help='helical wire radius (m)')
    parser.add_argument('--lay-angle', type=float, default=12.0,
                        help='lay angle theta between wire and strand axis (deg)')
    parser.add_argument('--E', type=float, default=200e9, help="Young's modulus (Pa)")
    parser.add_argument('--nu', type=float, default=0.3, help="Poisson's ratio")
    parser.add_argument('--wires', type=int, default=6, help='number of helical wires m')
    parser.add_argument('--penalty', type=float, default=None,
                        help='rodsolve &contact stiffness k (N/m^3): also the secant stiffness '
                             'with the penalty penetration at --strain')
    parser.add_argument('--strain', type=float, default=1e-3, help='strand strain for --penalty')
    parser.add_argument('--sweep', action='store_true',
                        help='table over lay angles 0..30 deg instead of one geometry')
    args = parser.parse_args(argv)
    theta = math.radians(args.lay_angle)
    if args.sweep:
        print('theta_deg  K_simple/K_straight  K_costello/K_straight  K_costello/K_simple - 1'
              '  clearance')
        for deg in range(0, 31, 2):
            t = math.radians(deg)
            res = costello_axial_stiffness(args.R1, args.R2, t, args.E, args.nu,
                                           n_wires=args.wires)
            print(f"{deg:9d}  {res['K_simple'] / res['K_straight']:19.6f}  "
                  f"{res['K_eps'] / res['K_straight']:21.6f}  "
                  f"{res['K_eps'] / res['K_simple'] - 1.0:+23.3e}  {res['clearance']:9.4f}")
        return 0
    res = costello_axial_stiffness(args.R1, args.R2, theta, args.E, args.nu, n_wires=args.wires)
    free = costello_axial_stiffness(args.R1, args.R2, theta, args.E, args.nu,
                                    rotation_fixed=False, n_wires=args.wires)
    r2 = args.R1 + args.R2
    pitch = 2.0 * math.pi * r2 / math.tan(theta) if theta > 0 else float('inf')
    print(f'1+{args.wires} strand: R1 = {args.R1:g} m, R2 = {args.R2:g} m, r2 = {r2:g} m, '
          f'lay angle {args.lay_angle:g} deg (Costello helix angle '
          f'{90.0 - args.lay_angle:g} deg), pitch {pitch:g} m, E = {args.E:g} Pa, '
          f'nu = {args.nu:g}')
    print(f"helical wires {'TOUCH' if res['helical_wires_touch'] else 'do not touch'} each "
          f"other: r2 / r2_touch = {res['clearance']:.5f} (Costello's condition)")
    print(f"{'model (rotation held)':48s} {'K_eps (N)':>14s} {'/K_costello-1':>14s} "
          f"{'K_m (N m)':>12s}")
    for label, K, Km in variants(args.R1, args.R2, theta, args.E, args.nu, args.wires):
        print(f"{label:48s} {K:14.6e} {K / res['K_eps'] - 1.0:+14.3e} {Km:12.4e}")
    print(f"{'E (A1 + m A2), straight wires':48s} {res['K_straight']:14.6e} "
          f"{res['K_straight'] / res['K_eps'] - 1.0:+14.3e}")
    print(f"rotation free: K_eps = {free['K_eps']:.6e} N, twist {free['twist_per_strain']:.4e} "
          f"rad/m per unit strain")
    print('per unit strain (Costello, rotation held):')
    for key, value in res['per_strain'].items():
        print(f'  {key:8s} {value:+.6e}')
    print('stiffness matrix [[F/eps, F/tau_s], [M/eps, M/tau_s]] (tau_s in rad/m):')
    for row in res['stiffness_matrix']:
        print('  ' + '  '.join(f'{v:+.6e}' for v in row))
    if args.penalty is not None:
        K, delta, p = penalty_secant_stiffness(args.R1, args.R2, theta, args.E, args.nu,
                                               args.penalty, args.strain, n_wires=args.wires)
        ref = costello_axial_stiffness(args.R1, args.R2, theta, args.E, args.nu,
                                       n_wires=args.wires, poisson_contraction=False,
                                       curvature_measure='reference')['K_eps']
        forces = [penalty_secant_stiffness(args.R1, args.R2, theta, args.E, args.nu,
                                           args.penalty, f * args.strain,
                                           n_wires=args.wires)[0] * f * args.strain
                  for f in (0.99, 1.01)]
        tangent = (forces[1] - forces[0]) / (0.02 * args.strain)
        print(f'penalty k = {args.penalty:g} N/m^3 at strain {args.strain:g}: penetration '
              f'{delta:.4e} m ({delta / args.R2:.3e} R2), line load {p:.4e} N/m, contact '
              f'patch half-length a = {math.sqrt(2.0 * (args.R1 + args.R2) * delta):.3e} m')
        print(f'  secant K = {K:.6e} N ({K / ref - 1.0:+.3e}), tangent dF/deps = '
              f'{tangent:.6e} N ({tangent / ref - 1.0:+.3e}) against the rigid-contact model '
              f'value {ref:.6e} N')
    return 0


if __name__ == '__main__':
    sys.exit(_main())
