"""Independent references for the contact tests (numpy only): the continuous line-contact law
and crossing law of the penalty potential, the Gauss-point double sum the solver evaluates for
two aligned parallel rods, and the clamp reaction of a beam on the contact foundation.

The potential (src/contact/contact_potential.f90, docs/theory/bundles.md "Contact"): two
centreline points at squared distance d2 carry psi(d2) = k (r_c^2 - d2)^3 / (3 r_c^4) for
d2 < r_c^2 (else 0), integrated over both arc lengths. Everything below is derived from that
formula alone, not from the solver's code or output.
"""
import math

import numpy as np


def line_force(k, rc, delta):
    """Force per length between two parallel infinite straight lines at the penetration delta =
    r_c - d (continuous double integral): f = (32/15) k d (r_c^2 - d^2)^(5/2) / r_c^4."""
    delta = np.asarray(delta, dtype=float)
    s = np.clip(delta * (2 * rc - delta), 0.0, None)
    return 32.0 / 15.0 * k * (rc - delta) * s**2 * np.sqrt(s) / rc**4


def line_penetration(k, rc, force):
    """The penetration at which the line law carries `force` (N/m), on its rising branch
    0 < delta < (1 - 1/sqrt(6)) r_c (bisection to round-off)."""
    lo, hi = 0.0, rc * (1 - 1 / math.sqrt(6))
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if line_force(k, rc, mid) > force:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def gauss_sum_force(k, rc, delta, le, m):
    """Force per length between two straight parallel rods at the penetration delta whose
    elements (length le) carry m Gauss-Legendre contact points each, the elements of the two
    rods aligned (the same mesh, as in the pressed-rods scene): the double sum
    sum_g sum_h w_g w_h psi(d^2 + (s_g - s_h)^2) per length, differentiated in d. The mean over
    one element of an infinite pair of rods (neighbouring elements to the reach of the support)."""
    x, w = np.polynomial.legendre.leggauss(m)
    s_a = 0.5 * (x + 1) * le
    w_a = 0.5 * w * le
    d = rc - delta
    reach = int(math.ceil(rc / le)) + 1
    s_b = np.concatenate([s_a + j * le for j in range(-reach, reach + 1)])
    w_b = np.tile(w_a, 2 * reach + 1)
    s = rc**2 - d**2 - (s_a[:, None] - s_b[None, :])**2
    # -d/dd psi(d^2 + u^2) = -2 d psi' = 2 d k s^2 / r_c^4 on the support.
    pair = np.where(s > 0, 2 * d * k * s**2 / rc**4, 0.0)
    return float(np.sum(w_a[:, None] * w_b[None, :] * pair) / le)


def gauss_sum_penetration(k, rc, force, le, m):
    """The penetration at which the Gauss-point sum of `gauss_sum_force` carries `force`."""
    lo, hi = 0.0, rc * (1 - 1 / math.sqrt(6))
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if gauss_sum_force(k, rc, mid, le, m) > force:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def crossing_energy(k, rc, delta):
    """Contact energy of two straight lines crossing at right angles at the penetration delta
    (continuous double integral over the disc u^2 + v^2 < s, s = r_c^2 - d^2):
    E = k / (3 r_c^4) * pi s^4 / 4, ~ (4 pi / 3) k delta^4 for delta << r_c."""
    s = max(delta * (2 * rc - delta), 0.0)
    return k / (3 * rc**4) * math.pi * s**4 / 4


def crossing_penetration(k, rc, energy):
    """The penetration of two right-angle crossing lines holding the contact energy `energy`
    (inverse of crossing_energy on 0 <= delta <= r_c)."""
    s = (12 * rc**4 * energy / (math.pi * k))**0.25
    return rc - math.sqrt(max(rc**2 - s, 0.0))


def clamp_reaction(ei, q, k, rc, length, n=1000):
    """Two equal Euler-Bernoulli beams along x, clamped at x = 0 touching (zero penetration),
    free at x = L, pressed together by the line load q each and held apart by the line law: by
    symmetry each deflects by w(x) towards the other, delta = 2 w and
    EI w'''' = q - f(2 w), w(0) = w'(0) = 0, w''(L) = w'''(L) = 0.
    Finite differences on n intervals (ghost points for the boundary conditions), Newton to
    1e-13 relative. Returns the clamp reaction R = q L - integral f (trapezoid) and the largest
    penetration 2 max w. The linearized problem (foundation modulus K = 2 f'(delta_inf)) has
    R = q / beta, beta = (K / (4 EI))^(1/4), and the overshoot exp(-pi) = 4.3 %; the line law
    stiffens with delta, so near the clamp the foundation is softer and R larger."""
    h = length / n
    a = np.zeros((n, n))
    stencil = (1.0, -4.0, 6.0, -4.0, 1.0)

    def ghost(j):
        """w_j as a combination of the unknowns w_1..w_n (index 0..n-1)."""
        if j == 0:
            return []
        if j == -1:                      # w'(0) = 0
            return [(0, 1.0)]
        if 1 <= j <= n:
            return [(j - 1, 1.0)]
        if j == n + 1:                   # w''(L) = 0
            return [(n - 1, 2.0), (n - 2, -1.0)]
        # w'''(L) = 0: w_{n+2} = 2 w_{n+1} - 2 w_{n-1} + w_{n-2}
        return [(n - 1, 4.0), (n - 2, -4.0), (n - 3, 1.0)]

    for i in range(1, n + 1):
        for offset, c in zip(range(-2, 3), stencil):
            for col, weight in ghost(i + offset):
                a[i - 1, col] += c * weight
    a *= ei / h**4
    w = np.full(n, 0.5 * line_penetration(k, rc, q))
    for _ in range(30):
        f = line_force(k, rc, 2 * w)
        eps = 1e-7 * rc
        slope = (line_force(k, rc, 2 * w + eps) - line_force(k, rc, 2 * w - eps)) / (2 * eps)
        residual = a @ w - q + f
        dw = np.linalg.solve(a + np.diag(2 * slope), -residual)
        w += dw
        if np.max(np.abs(dw)) <= 1e-13 * np.max(np.abs(w)):
            break
    f = line_force(k, rc, 2 * w)
    carried = h * (np.sum(f[:-1]) + 0.5 * f[-1])
    return q * length - carried, 2 * float(np.max(w))
