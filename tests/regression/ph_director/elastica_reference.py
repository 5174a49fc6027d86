"""Reference solutions of the planar cantilever of seed 000 §6.3 (methods/ph_director_3d.md
§6.3).

A straight rod along e1, clamped at s = 0, with a dead tip force F = (Fx, Fy) and a tip moment
M e3 at s = L, bent in the e1-e2 plane. With θ the angle of d3 = (cos θ, sin θ) from e1 (and
d1 = (-sin θ, cos θ), d2 = e3 for the directors of the scenes), statics gives

    n(s) = F                                   (no distributed load: n' = 0)
    m3(s) = M + [(φ(L) - φ(s)) x F]_3          (moment balance m' + φ' x n = 0)
    EI θ'(s) = m3(s)                           (K2 = θ', bending about d2 = e3)
    =>  EI θ'' = -[φ' x F]_3 = -(φ'_1 Fy - φ'_2 Fx),   θ(0) = 0,  EI θ'(L) = M.

Inextensible and shear-rigid (Euler's elastica): φ' = d3. Extensible and shear-deformable
(Reissner's planar rod, the 'unconstrained' scene): the material force N1 = F·d1, N3 = F·d3
gives Γ1 = N1/GA, Γ3 = 1 + N3/EA and φ' = Γ1 d1 + Γ3 d3.

The two-point boundary-value problem is solved by shooting on κ0 = θ'(0) with Newton (the
derivative from the variational equations), classical RK4 in s, and continuation in the load
factor from 0 to 1 so that the solution is the one on the loading path (the quasistatic path of
the solver). The RK4 step count is doubled until the tip moves by less than 1e-13 L, then the
last two are Richardson-extrapolated (RK4 error ~ N^-4).

Run as a script, it validates itself and prints the §6.3 tips:
  (a) step convergence: the observed RK4 order is 4 and the last doubling changes the tip by
      less than 1e-12;
  (b) small loads: the tip agrees with linear beam theory (deflection F L^3/(3 EI) + M L^2/(2 EI),
      plus F L/GA and the axial F L/EA for the extensible rod) to the size of the neglected
      nonlinear terms;
  (c) a pure tip moment gives a circle of radius EI/M;
  (d) the inextensible §6.3 tip agrees with an independent evaluation through incomplete
      elliptic integrals (Carlson's R_F and R_D) of the first integral EI θ'^2/2 = P sin θ + C;
  (e) stiff extensible rods tend to the inextensible solution as 1/stiffness.
Exit status 1 if a check fails.
"""
import math
import sys

import numpy as np

#: §6.3 parameters (methods/ph_director_3d.md §6.3, cardillo's scripts of refs [19]/[78]).
LENGTH = 2 * math.pi
EA, GA, GJ, EI = 5.0, 1.0, 0.5, 2.0
P = 10 * EI / LENGTH**2          # 0.5066059182116889
TIP_FORCE = (0.0, -P)
TIP_MOMENT = 2.5 * P


def _director_tangent(theta, force, ea, ga):
    """φ'(θ) and dφ'/dθ for the material law of the rod (ea = ga = None: inextensible)."""
    c, s = math.cos(theta), math.sin(theta)
    if ea is None:
        return c, s, -s, c                         # φ' = d3, dφ'/dθ = d1
    n1 = -force[0] * s + force[1] * c              # N1 = F·d1, d1 = (-s, c)
    n3 = force[0] * c + force[1] * s               # N3 = F·d3, d3 = (c, s)
    g1, g3 = n1 / ga, 1.0 + n3 / ea
    # φ' = Γ1 d1 + Γ3 d3 with dd1/dθ = -d3, dd3/dθ = d1, dN1/dθ = -N3, dN3/dθ = N1
    a1 = g3 - n3 / ga                              # coefficient of d1 in dφ'/dθ
    a3 = n1 / ea - g1                              # coefficient of d3 in dφ'/dθ
    return (-g1 * s + g3 * c, g1 * c + g3 * s, -a1 * s + a3 * c, a1 * c + a3 * s)


def _rhs(y, force, ei, ea, ga):
    """State y = (θ, κ, x, y, δθ, δκ): the rod ODE and its variation with respect to κ0."""
    theta, kappa, _, _, dtheta, dkappa = y
    t1, t2, dt1, dt2 = _director_tangent(theta, force, ea, ga)
    cross = t1 * force[1] - t2 * force[0]
    dcross = dt1 * force[1] - dt2 * force[0]
    return (kappa, -cross / ei, t1, t2, dkappa, -dcross * dtheta / ei)


def _integrate(kappa0, length, force, ei, ea, ga, n_steps, keep=False):
    y = (0.0, kappa0, 0.0, 0.0, 0.0, 1.0)
    h = length / n_steps
    path = [y] if keep else None
    for _ in range(n_steps):
        k1 = _rhs(y, force, ei, ea, ga)
        k2 = _rhs(tuple(a + 0.5 * h * b for a, b in zip(y, k1)), force, ei, ea, ga)
        k3 = _rhs(tuple(a + 0.5 * h * b for a, b in zip(y, k2)), force, ei, ea, ga)
        k4 = _rhs(tuple(a + h * b for a, b in zip(y, k3)), force, ei, ea, ga)
        y = tuple(a + (h / 6.0) * (b1 + 2 * b2 + 2 * b3 + b4)
                  for a, b1, b2, b3, b4 in zip(y, k1, k2, k3, k4))
        if keep:
            path.append(y)
    return (y, np.array(path)) if keep else y


def _newton(kappa0, length, force, moment, ei, ea, ga, n_steps):
    """Newton on EI κ(L) - M for κ0 = θ'(0); returns the converged κ0 and the end state."""
    for _ in range(50):
        y = _integrate(kappa0, length, force, ei, ea, ga, n_steps)
        correction = (ei * y[1] - moment) / (ei * y[5])
        kappa0 -= correction
        if abs(correction) < 1e-15 * max(1.0, abs(kappa0)):
            return kappa0, _integrate(kappa0, length, force, ei, ea, ga, n_steps)
    raise RuntimeError("shooting did not converge")


def shoot(length, force, moment, ei, ea=None, ga=None, n_steps=512, n_load=50, kappa0=None):
    """The solution for a fixed RK4 step count: (tip (x, y), θ(L), κ0). Without a start value
    kappa0 it is followed from load factor 0 to 1 in n_load increments, so that it is the
    equilibrium on the loading path (the §6.3 loads have others: Newton at the full load from
    the straight rod, or in 5 increments, ends on another branch)."""
    if kappa0 is None:
        kappa0 = 0.0
        for step in range(1, n_load):
            lam = step / n_load
            kappa0, _ = _newton(kappa0, length, (lam * force[0], lam * force[1]), lam * moment,
                                ei, ea, ga, n_steps)
    kappa0, y = _newton(kappa0, length, force, moment, ei, ea, ga, n_steps)
    return np.array([y[2], y[3]]), y[0], kappa0


def solve(length=LENGTH, force=TIP_FORCE, moment=TIP_MOMENT, ei=EI, ea=None, ga=None,
          tolerance=1e-13, verbose=False):
    """Tip position (x, y), tip angle and θ'(0), converged in the RK4 step count: doubled from
    64 until the tip changes by less than tolerance * length, then Richardson-extrapolated.
    ea = ga = None: inextensible and shear-rigid. Returns a dict with 'tip', 'theta_L',
    'kappa0', 'steps' and the 'history' of (n_steps, tip)."""
    n_steps = 64
    tip, theta, kappa0 = shoot(length, force, moment, ei, ea, ga, n_steps, n_load=50)
    history = [(n_steps, tip, theta, kappa0)]
    while True:
        n_steps *= 2
        tip, theta, kappa0 = shoot(length, force, moment, ei, ea, ga, n_steps, kappa0=kappa0)
        history.append((n_steps, tip, theta, kappa0))
        change = np.max(np.abs(history[-1][1] - history[-2][1]))
        if verbose:
            print("  RK4 %6d steps: tip (%.15f, %.15f), change %.2e"
                  % (n_steps, tip[0], tip[1], change))
        if change < tolerance * length or n_steps > 2**16:
            break
    (_, tip1, th1, k1), (_, tip2, th2, k2) = history[-2], history[-1]
    return {"tip": tip2 + (tip2 - tip1) / 15.0, "theta_L": th2 + (th2 - th1) / 15.0,
            "kappa0": k2 + (k2 - k1) / 15.0, "steps": n_steps, "history": history,
            "change": change}


def profile(length=LENGTH, force=TIP_FORCE, moment=TIP_MOMENT, ei=EI, ea=None, ga=None,
            n_steps=4096):
    """The centreline (s, x, y, θ) at n_steps + 1 equally spaced points (RK4 with n_steps)."""
    _, _, kappa0 = shoot(length, force, moment, ei, ea, ga, 64)
    _, _, kappa0 = shoot(length, force, moment, ei, ea, ga, n_steps, kappa0=kappa0)
    _, path = _integrate(kappa0, length, force, ei, ea, ga, n_steps, keep=True)
    s = np.linspace(0.0, length, n_steps + 1)
    return s, path[:, 2], path[:, 3], path[:, 0]


# Carlson's symmetric elliptic integrals (Carlson 1995, Numer. Algorithms 10; DLMF §19.36).
def carlson_rf(x, y, z):
    for _ in range(200):
        lam = math.sqrt(x * y) + math.sqrt(y * z) + math.sqrt(z * x)
        x, y, z = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam)
        mu = (x + y + z) / 3.0
        dx, dy, dz = 1 - x / mu, 1 - y / mu, 1 - z / mu
        if max(abs(dx), abs(dy), abs(dz)) < 1e-4:
            break
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    return (1 - e2 / 10 + e3 / 14 + e2 * e2 / 24 - 3 * e2 * e3 / 44) / math.sqrt(mu)


def carlson_rd(x, y, z):
    total, factor = 0.0, 1.0
    for _ in range(200):
        lam = math.sqrt(x * y) + math.sqrt(y * z) + math.sqrt(z * x)
        total += factor / (math.sqrt(z) * (z + lam))
        factor *= 0.25
        x, y, z = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam)
        mu = (x + y + 3 * z) / 5.0
        dx, dy, dz = 1 - x / mu, 1 - y / mu, 1 - z / mu
        if max(abs(dx), abs(dy), abs(dz)) < 1e-4:
            break
    ea = dx * dy
    eb = dz * dz
    ec = ea - eb
    ed = ea - 6 * eb
    ee = ed + ec + ec
    series = (1 + ed * (-3 / 14 + 9 / 88 * ed - 4.5 / 26 * dz * ee)
              + dz * (ee / 6 + dz * (-9 / 22 * ec + 3 / 26 * dz * ea)))
    return 3 * total + factor * series / (mu * math.sqrt(mu))


def elliptic_f_e(phi, m):
    """Incomplete elliptic integrals F(φ|m) and E(φ|m) for any real φ and 0 <= m < 1
    (F(φ + jπ) = F(φ) + 2jK, likewise E)."""
    j = math.floor(phi / math.pi + 0.5)
    phi0 = phi - j * math.pi                  # in [-π/2, π/2]
    s, c = math.sin(phi0), math.cos(phi0)
    q = 1 - m * s * s
    rf = carlson_rf(c * c, q, 1.0)
    rd = carlson_rd(c * c, q, 1.0)
    f = s * rf
    e = s * rf - m * s**3 * rd / 3
    if j:
        kk = carlson_rf(0.0, 1 - m, 1.0)
        ek = kk - m * carlson_rd(0.0, 1 - m, 1.0) / 3
        f += 2 * j * kk
        e += 2 * j * ek
    return f, e


def elliptic_tip(length, p, moment, ei, theta_guess, kappa0_sign):
    """Inextensible tip under F = (0, -p) and tip moment M > 0 through elliptic integrals.

    From EI θ'' = p cos θ: EI θ'^2/2 = p sin θ + C with C = M^2/(2EI) - p sin θ_L, so
    θ'^2 = a + b sin θ (a = 2C/EI, b = 2p/EI). With sin θ = 1 - 2 sin^2 u, u = (θ - π/2)/2:
    θ'^2 = (a + b)(1 - m sin^2 u), m = 2b/(a + b).
    - m < 1: θ' keeps its sign; with θ' > 0,
        L = 2/sqrt(a+b) [F(u|m)],  y_L = 2/sqrt(a+b) [(1 - 2/m) F(u|m) + (2/m) E(u|m)]
      between u0 = -π/4 and uL = (θ_L - π/2)/2.
    - m > 1: θ' may change sign. With sin w = sqrt(m) sin u and θ' = sqrt(a+b) cos w, w grows
      monotonically with s (dw/ds = sqrt(b/2) cos u > 0) through the zeros of θ', and
        ds = sqrt(2/b) dw / sqrt(1 - sin^2 w/m),  sin θ = 1 - (2/m) sin^2 w, so
        L = sqrt(2/b) [F(w|1/m)],  y_L = sqrt(2/b) [2 E(w|1/m) - F(w|1/m)]
      from w0 (sin w0 = -sqrt(m/2), cos w0 of the sign of θ'(0)) to the first wL > w0 with
      sin wL = sqrt(m) sin uL and cos wL > 0 (θ'(L) = M/EI > 0).
    In both cases x_L = ∫ cos θ ds = (EI/p)(θ'(L) - θ'(0)). θ_L solves the length equation by
    the secant method from theta_guess, which (with the sign of θ'(0)) only selects the branch."""
    b = 2 * p / ei
    kappa_l = moment / ei

    def parts(theta_l):
        a = kappa_l**2 - b * math.sin(theta_l)
        m = 2 * b / (a + b)
        u0, ul = -math.pi / 4, (theta_l - math.pi / 2) / 2
        if 0 < m < 1:
            if kappa0_sign < 0:
                raise ValueError("m < 1 but θ'(0) < 0")
            f0, e0 = elliptic_f_e(u0, m)
            fl, el = elliptic_f_e(ul, m)
            scale = 2 / math.sqrt(a + b)
            arc = scale * (fl - f0)
            y = scale * ((1 - 2 / m) * (fl - f0) + (2 / m) * (el - e0))
            kappa0 = math.sqrt(a)
        else:
            s0 = math.asin(math.sqrt(m) * math.sin(u0))
            w0 = s0 if kappa0_sign > 0 else math.pi - s0
            sl = math.asin(math.sqrt(m) * math.sin(ul))
            wl = sl
            while wl <= w0:
                wl += 2 * math.pi
            f0, e0 = elliptic_f_e(w0, 1 / m)
            fl, el = elliptic_f_e(wl, 1 / m)
            scale = math.sqrt(2 / b)
            arc = scale * (fl - f0)
            y = scale * (2 * (el - e0) - (fl - f0))
            kappa0 = math.sqrt(a + b) * math.cos(w0)
        x = ei / p * (kappa_l - kappa0)
        return arc, x, y, m

    t0, t1 = theta_guess, theta_guess + 1e-6
    r0, r1 = parts(t0)[0] - length, parts(t1)[0] - length
    for _ in range(100):
        if r1 == r0:
            break
        t2 = t1 - r1 * (t1 - t0) / (r1 - r0)
        t0, r0 = t1, r1
        t1, r1 = t2, parts(t2)[0] - length
        if abs(r1) < 1e-15 * length:
            break
    _, x, y, m = parts(t1)
    return np.array([x, y]), t1, m


def _report(name, measured, bound, failures):
    ok = measured <= bound
    print("%s %s: %.3e (bound %.1e)" % ("ok  " if ok else "FAIL", name, measured, bound))
    if not ok:
        failures.append(name)


def main():
    failures = []
    print("Elastica of seed 000 §6.3: L = 2π, EI = %g, P = 10 EI/L^2 = %.16g, M = 2.5 P"
          % (EI, P))

    print("(a) RK4 step convergence, inextensible:")
    ref = solve(verbose=True)
    hist = ref["history"]
    e1 = np.max(np.abs(hist[-3][1] - hist[-2][1]))
    e2 = np.max(np.abs(hist[-2][1] - hist[-1][1]))
    if len(hist) >= 4:
        e0 = np.max(np.abs(hist[-4][1] - hist[-3][1]))
        print("  observed RK4 order %.2f" % math.log2(e0 / e1))
        _report("|observed RK4 order - 4|", abs(math.log2(e0 / e1) - 4), 0.2, failures)
    _report("tip change at the last step doubling", e2, 1e-12, failures)
    tip = ref["tip"]
    print("  tip (Richardson) x = %.12f, y = %.12f, θ(L) = %.12f, θ'(0) = %.12f"
          % (tip[0], tip[1], ref["theta_L"], ref["kappa0"]))

    print("(b) small loads against linear beam theory (factor 1e-4 on the §6.3 loads):")
    eps = 1e-4
    f, m = (0.0, -eps * P), eps * TIP_MOMENT
    small = solve(force=f, moment=m)["tip"]
    y_lin = f[1] * LENGTH**3 / (3 * EI) + m * LENGTH**2 / (2 * EI)
    _report("inextensible |y - (F L^3/(3EI) + M L^2/(2EI))| / |y|",
            abs(small[1] - y_lin) / abs(y_lin), 1e-6, failures)
    _report("inextensible |x - L| / |y| (second order)", abs(small[0] - LENGTH) / abs(y_lin), 1e-3,
            failures)
    small = solve(force=f, moment=m, ea=EA, ga=GA)["tip"]
    y_lin = f[1] * LENGTH**3 / (3 * EI) + f[1] * LENGTH / GA + m * LENGTH**2 / (2 * EI)
    _report("extensible |y - (F L^3/(3EI) + F L/GA + M L^2/(2EI))| / |y|",
            abs(small[1] - y_lin) / abs(y_lin), 1e-6, failures)
    axial = 0.3
    stretched = solve(force=(axial, 0.0), moment=0.0, ea=EA, ga=GA)["tip"]
    _report("extensible, axial tip force only: |tip - (L (1 + F/EA), 0)| (exact)",
            max(abs(stretched[0] - LENGTH * (1 + axial / EA)), abs(stretched[1])), 1e-12, failures)
    print("(c) pure tip moment M = 2.5 P: a circle of radius EI/M:")
    radius = EI / TIP_MOMENT
    circle = np.array([radius * math.sin(LENGTH / radius),
                       radius * (1 - math.cos(LENGTH / radius))])
    moment_only = solve(force=(0.0, 0.0), moment=TIP_MOMENT)["tip"]
    _report("|tip - circle|", np.max(np.abs(moment_only - circle)), 1e-12, failures)

    print("(d) independent evaluation through elliptic integrals:")
    elliptic, theta_l, mod = elliptic_tip(LENGTH, P, TIP_MOMENT, EI, ref["theta_L"],
                                           math.copysign(1.0, ref["kappa0"]))
    print("  elliptic: x = %.12f, y = %.12f, θ(L) = %.12f (parameter m = %.6f)"
          % (elliptic[0], elliptic[1], theta_l, mod))
    _report("|tip(RK4) - tip(elliptic)|", np.max(np.abs(tip - elliptic)), 1e-10, failures)
    _report("|θ_L(RK4) - θ_L(elliptic)|", abs(ref["theta_L"] - theta_l), 1e-10, failures)

    print("(e) extensible §6.3 rod, and stiff rods tending to the inextensible one:")
    ext = solve(ea=EA, ga=GA)
    print("  extensible (EA = 5, GA = 1): x = %.12f, y = %.12f" % tuple(ext["tip"]))
    gaps = []
    for factor in (1e2, 1e3, 1e4):
        stiff = solve(ea=EA * factor, ga=GA * factor)["tip"]
        gaps.append(np.max(np.abs(stiff - tip)))
        print("  EA, GA x %g: |tip - inextensible| = %.3e" % (factor, gaps[-1]))
    rate = math.log10(gaps[0] / gaps[-1]) / 2
    _report("|order of the stiff -> inextensible limit - 1|", abs(rate - 1), 0.05, failures)

    print("\nreference tip, inextensible §6.3: x = %.12f, y = %.12f" % tuple(tip))
    print("reference tip, extensible §6.3:   x = %.12f, y = %.12f" % tuple(ext["tip"]))
    print("%d check(s) failed" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
