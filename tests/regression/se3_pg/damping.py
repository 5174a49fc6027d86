"""Damping of se3_pg rods (issue 26 item 1; docs/theory/damping.md, docs/theory/se3_pg.md
"Damping"): Kelvin-Voigt viscosity (&rod kelvin_voigt_time), drag and angular drag, with the
midpoint rule and generalized-alpha (rho_inf = 0.9). Every closed form is computed here.

    damping.py decrement  input/se3_pg_damped_cantilever.nml (16 elements, T_1 / 100, 7 periods;
                          tau = 2 zeta_1 / omega_1 on every component, zeta_1 = 0.02, omega_1 the
                          Euler-Bernoulli first frequency, beta_1 L = 1.875104068711961): the
                          logarithmic decrement of the tip's peaks (parabolic peaks after 1.2
                          T_1, a line fitted to their logarithms) within 2 % of delta = 2 pi
                          zeta_1 / sqrt(1 - zeta_1^2) (measured 0.04 %), the damped period
                          within 0.5 % of 2 pi / (omega_1 sqrt(1 - zeta_1^2)); D_n > 0 at every
                          step; both schemes
    damping.py rigid      a free rod (4 elements, h = 0.01) translating and spinning about its
                          own axis: with drag under gravity, v(t) = v_t (1 - exp(-c t / rhoA)),
                          v_t = rhoA g / c (reached within 1 %), the horizontal velocity decays as
                          exp(-c t / rhoA); with angular drag the spin decays as w0 exp(-c_w t /
                          (rho (I1 + I2))); each equals the scheme's own solution of these linear
                          equations (the midpoint rule's and generalized-alpha's recursions,
                          computed here) to 1e-8 and the closed form to the scheme's accuracy
                          ((c h / rhoA)^2 / 8); with all three laws D_n = L (c |dr|^2 + c_w
                          dalpha^2) / h from the stored positions and directors (Kelvin-Voigt
                          adds nothing); Kelvin-Voigt alone dissipates nothing (1e-20 of H_0):
                          a rigid motion is not damped; D_n > 0 at every step; the balance
                          error to round-off (1e-12 of the energy scale) with the midpoint rule
                          (the rod stays straight: no Petrov-Galerkin defect), and second order
                          in h with generalized-alpha (its numerical dissipation)
    damping.py axial      a clamped rod in free axial vibration with Kelvin-Voigt (8 elements):
                          the midpoint rule keeps H_{n+1} - H_n - W_n + D_n = 0 to round-off
                          (1e-11 of max H; the element's strains are linear in the positions
                          when nothing rotates), D_n > 0 at every step, the energy decays
    damping.py balance    the flying spaghetti (input/flying_spaghetti.nml, seed 000 §6.1) as an
                          se3_pg rod, h = 0.05: undamped, Kelvin-Voigt (tau 0.5), drag (0.3),
                          angular drag (3) and all three, both schemes. se3_pg's schemes do not
                          keep this element's energy (docs/theory/se3_pg.md), so the balance
                          error is not round-off: the check is that with damping it is no
                          larger than without (the largest |b_n| and sum |b_n|, both printed),
                          with D_n > 0 at every step
    damping.py restart    the damped cantilever with generalized-alpha stopped after T_1 and
                          continued from its checkpoint ends as the uninterrupted run (2 T_1):
                          the checkpoint state (24 numbers per node and the strain rates, 6 per
                          element), each part within 1e-8 of its largest value (measured 3e-11
                          at most: the runs agree to Newton's tolerance, not bit for bit, as
                          without damping; a history lost at the restart would be an O(1) error)
"""
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import se3_scene  # noqa: E402
from se3_scene import rs  # noqa: E402

SCHEMES = ("midpoint", "generalized_alpha")
RHO_INF = 0.9                         # &time rho_inf's default
BETA_1 = 1.875104068711961            # first root of 1 + cos(b) cosh(b) = 0
GRAVITY = 9.81


def edited(text, changes):
    return se3_scene.edit(text, changes)


def scheme_of(text, scheme):
    return rs.set_variable(text, "time", "scheme", f"'{scheme}'")


def run(args, text, name, rod):
    result = se3_scene.run(args, text, name, rod)
    print(f"info: {name}: {result.summary()}, wall {result.wall_seconds:.3g} s")
    return result


def series(result, key):
    return result[f"series/energy/{key}"]


def positive_dissipation(checks, label, result):
    """D_n > 0 at every step (every step is a record)."""
    d = series(result, "dissipated")[1:]
    checks.check(f"{label}: steps with D_n <= 0 (of {d.size}; smallest D_n {np.min(d):.3e})",
                 float(np.sum(d <= 0.0)), 0.0)


# ---- decrement ---------------------------------------------------------------------------------

def tip_peaks(t, z, after):
    """Maxima of z after `after`, refined by the parabola through each and its neighbours."""
    times, values = [], []
    for i in range(1, z.size - 1):
        if t[i] > after and z[i] > 0.0 and z[i] > z[i - 1] and z[i] >= z[i + 1]:
            a, b, c = z[i - 1], z[i], z[i + 1]
            shift = 0.5 * (a - c) / (a - 2.0 * b + c)
            values.append(b - 0.25 * (a - c) * shift)
            times.append(t[i] + shift * (t[1] - t[0]))
    return np.array(times), np.array(values)


def decrement(args, checks):
    text = rs.read_example(args.source, "se3_pg_damped_cantilever.nml")
    ei, rho_a, length = (rs.number(text, "rod", v) for v in ("EI1", "rhoA", "length"))
    tau = rs.number(text, "rod", "kelvin_voigt_time")
    omega_1 = BETA_1**2 * math.sqrt(ei / (rho_a * length**4))
    zeta = tau * omega_1 / 2.0
    delta = 2.0 * math.pi * zeta / math.sqrt(1.0 - zeta**2)
    period = 2.0 * math.pi / (omega_1 * math.sqrt(1.0 - zeta**2))
    print(f"info: omega_1 = {omega_1:.6f}, zeta_1 = {zeta:.5f}, delta = {delta:.7f}, "
          f"damped period {period:.6f}")
    for scheme in SCHEMES:
        r = run(args, edited(scheme_of(text, scheme), [
            ("output", "fields", "'position'"), ("output", "xdmf", ".false.")]),
            f"decrement_{scheme}", "cantilever")
        t, z = r["time"], r["position"][:, -1, 2]
        times, peaks = tip_peaks(t, z, 1.2 * 2.0 * math.pi / omega_1)
        slope = np.polyfit(np.arange(peaks.size), np.log(peaks), 1)[0]
        measured_period = float(np.mean(np.diff(times)))
        print(f"info: {scheme}: {peaks.size} peaks, decrement {-slope:.7f} "
              f"({-slope / delta - 1.0:+.2e}), period {measured_period:.6f} "
              f"({measured_period / period - 1.0:+.2e})")
        checks.check(f"{scheme}: peaks measured (of 5)", float(peaks.size < 5), 0.0)
        checks.check(f"{scheme}: |decrement / delta - 1| (2 %)", abs(-slope / delta - 1.0), 0.02)
        checks.check(f"{scheme}: |damped period / 2 pi/(omega_1 sqrt(1 - zeta^2)) - 1|",
                     abs(measured_period / period - 1.0), 0.005)
        positive_dissipation(checks, scheme, r)


# ---- rigid motions -----------------------------------------------------------------------------

def straight_rod(t_end, dt, newton_atol, fields, n_elements, more):
    """A straight rod of length 1 along x (EA = GA = 100, EI = GJ = 1) and `more` of its &rod."""
    return f"""&time
    t_end = {t_end}, dt = {dt}
/
&solver
    newton_atol = {newton_atol}
/
&output
    path = 'x.h5', xdmf = .false., fields = '{fields}'
/
&rod
    name = 'rod', formulation = 'se3_pg', n_elements = {n_elements}
    start = 0, 0, 0, direction = 1, 0, 0, d1 = 0, 1, 0, length = 1
    EA = 100, GA1 = 100, GA2 = 100, EI1 = 1, EI2 = 1, GJ = 1
    {more}
/
"""


FREE_ROD = straight_rod(5.0, 0.01, "1e-11", "position,directors,velocity,director_velocity", 4,
                        "rhoA = 2, rhoI1 = 0.05, rhoI2 = 0.05\n    velocity = 0.5, 0.2, 0, "
                        "angular_velocity = 10, 0, 0, rotation_center = 0, 0, 0")
GRAVITY_LOAD = """&load
    where = 'gravity', acceleration = 0, 0, -9.81
/
"""


def scheme_solution(scheme, h, rate, y0, steps):
    """The step's own solution of y' = -rate y, y(0) = y0: the midpoint rule's y_{n+1} = y_n
    (1 - x/2) / (1 + x/2), x = rate h; generalized-alpha's (JWH 2000) from y_n, y'_n with the
    consistent y'_0 = -rate y0: y_{n+1} = y_n + h y'_n + h gamma (y'_{n+1} - y'_n), y'_n +
    alpha_m (y'_{n+1} - y'_n) = -rate (y_n + alpha_f (y_{n+1} - y_n))."""
    y = np.empty(steps + 1)
    y[0] = y0
    if scheme == "midpoint":
        x = rate * h
        y[1:] = y0 * ((1.0 - 0.5 * x) / (1.0 + 0.5 * x)) ** np.arange(1, steps + 1)
        return y
    alpha_m = 0.5 * (3.0 - RHO_INF) / (1.0 + RHO_INF)
    alpha_f = 1.0 / (1.0 + RHO_INF)
    gamma = 0.5 + alpha_m - alpha_f
    lam = -rate
    dy = lam * y0
    for n in range(steps):
        # dy_1 = dy + (y_1 - y - h dy) / (h gamma); the stage equation is linear in y_1.
        a = alpha_m / (h * gamma) - lam * alpha_f
        rhs = lam * (1.0 - alpha_f) * y[n] - dy + alpha_m * (y[n] + h * dy) / (h * gamma)
        y[n + 1] = rhs / a
        dy = dy + (y[n + 1] - y[n] - h * dy) / (h * gamma)
    return y


def rod_motion(r):
    """Mean node velocity, spin (angular velocity about d3, from the directors and their rates:
    w = (1/2) sum_i d_i x d_i'), and per step the mean |dr| and the turn angle of the sections."""
    v = r["velocity"].mean(axis=1)
    d = r["directors"]              # (records, nodes, director i, component)
    dd = r["director_velocity"]
    w = 0.5 * sum(np.cross(d[:, :, i, :], dd[:, :, i, :]) for i in range(3))
    spin = np.einsum("rnc,rnc->rn", w, d[:, :, 2, :]).mean(axis=1)
    dr = np.diff(r["position"], axis=0)
    turn = np.einsum("rnic,rnie->rnce", d[1:], d[:-1])          # R_{n+1} R_n^T per node
    sine = 0.5 * np.linalg.norm(np.stack([turn[..., 2, 1] - turn[..., 1, 2],
                                          turn[..., 0, 2] - turn[..., 2, 0],
                                          turn[..., 1, 0] - turn[..., 0, 1]], axis=-1), axis=-1)
    cosine = 0.5 * (np.trace(turn, axis1=-2, axis2=-1) - 1.0)
    return v, spin, dr, np.arctan2(sine, cosine)


def rigid(args, checks):
    base = FREE_ROD
    rho_a, length = rs.number(base, "rod", "rhoA"), rs.number(base, "rod", "length")
    inertia = rs.number(base, "rod", "rhoI1") + rs.number(base, "rod", "rhoI2")
    h, t_end = rs.number(base, "time", "dt"), rs.number(base, "time", "t_end")
    v0 = rs.numbers(base, "rod", "velocity")
    w0 = rs.numbers(base, "rod", "angular_velocity")[0]
    c, c_w, tau = 4.0, 0.2, 0.05
    k, k_w = c / rho_a, c_w / inertia
    v_t = rho_a * GRAVITY / c
    steps = round(t_end / h)
    cases = {"drag": ([("drag", repr(c))], True),
             "angular_drag": ([("angular_drag", repr(c_w))], False),
             "all": ([("drag", repr(c)), ("angular_drag", repr(c_w)),
                      ("kelvin_voigt_time", repr(tau))], True),
             "kelvin_voigt": ([("kelvin_voigt_time", repr(tau))], False)}
    for scheme in SCHEMES:
        for label, (damping, falls) in cases.items():
            text = scheme_of(base + (GRAVITY_LOAD if falls else ""), scheme)
            text = edited(text, [("rod", name, value) for name, value in damping])
            r = run(args, text, f"rigid_{scheme}_{label}", "rod")
            t = r["time"]
            v, spin, dr, turn = rod_motion(r)
            dragged = label in ("drag", "all")
            spun = label in ("angular_drag", "all")
            tag = f"{scheme}, {label}"
            # Velocity and spin: the scheme's solution, the closed form.
            expected = {"v_x": (v[:, 0], v0[0], k if dragged else 0.0, 0.0),
                        "v_z": (v[:, 2], 0.0, k if dragged else 0.0, -v_t if falls else 0.0),
                        "spin": (spin, w0, k_w if spun else 0.0, 0.0)}
            speed = max(float(np.linalg.norm(v0)), v_t if falls else 0.0)
            for name, (measured, start, rate, limit) in expected.items():
                scale = abs(w0) if name == "spin" else speed
                if rate == 0.0:
                    if name == "v_z" and falls:
                        continue
                    checks.check(f"{tag}: {name} constant (relative)",
                                 float(np.max(np.abs(measured - start))) / scale, 1e-10)
                    continue
                own = limit + scheme_solution(scheme, h, rate, start - limit, steps)
                closed = limit + (start - limit) * np.exp(-rate * t)
                to_own = float(np.max(np.abs(measured - own))) / scale
                to_closed = float(np.max(np.abs(measured - closed))) / scale
                print(f"info: {tag}: {name}: rate {rate} 1/s, max |run - scheme's solution| "
                      f"{to_own:.2e}, max |run - closed form| {to_closed:.2e} (relative)")
                checks.check(f"{tag}: {name} = the scheme's solution of y' = -{rate:g} y",
                             to_own, 1e-8)
                checks.check(f"{tag}: {name} = the closed form to (rate h)^2 / 8",
                             to_closed, (rate * h) ** 2 / 8.0)
            if falls and dragged:
                checks.check(f"{tag}: |v_z(t_end) / (-rhoA g / c) - 1| (1 %)",
                             abs(v[-1, 2] / -v_t - 1.0), 0.01)
            # The dissipation: the drag laws' closed form, nothing from Kelvin-Voigt.
            d = series(r, "dissipated")[1:]
            if label == "kelvin_voigt":
                h0 = series(r, "total")[0]
                print(f"info: {tag}: sum D = {np.sum(d):.3e} (H_0 = {h0:.3f})")
                checks.check(f"{tag}: sum D / H_0 (a rigid motion is not damped)",
                             float(np.sum(np.abs(d))) / h0, 1e-20)
            else:
                drag_d = length * ((c if dragged else 0.0) * np.sum(dr.mean(axis=1) ** 2, axis=1)
                                   + (c_w if spun else 0.0) * turn.mean(axis=1) ** 2) / h
                checks.check(f"{tag}: max |D_n - L (c |dr|^2 + c_w dalpha^2) / h| / max D_n",
                             float(np.max(np.abs(d - drag_d)) / np.max(d)), 1e-9)
                positive_dissipation(checks, tag, r)
            b = series(r, "balance_error")[1:]
            scale = float(np.max(series(r, "total")) + np.max(np.abs(series(r, "external_work"))))
            print(f"info: {tag}: max |b_n| / energy scale {np.max(np.abs(b)) / scale:.2e}")
            bound = 1e-12 if scheme == "midpoint" else 3e-6
            checks.check(f"{tag}: max |H_n+1 - H_n - W_n + D_n| / (max H + max |W_n|)",
                         float(np.max(np.abs(b))) / scale, bound)


# ---- axial vibration ---------------------------------------------------------------------------

AXIAL = straight_rod(2.0, 0.002, "1e-12", "position", 8,
                     "rhoA = 1, rhoI1 = 0.01, rhoI2 = 0.01, kelvin_voigt_time = 0.01") + """&bc
    rod = 'rod', end = 'start', kind = 'clamped'
/
&load
    rod = 'rod', where = 'end', force = 1, 0, 0, time_function = 'pulse', t_on = 0, t_off = 0.4
/
"""


def axial(args, checks):
    for scheme in SCHEMES:
        r = run(args, scheme_of(AXIAL, scheme), f"axial_{scheme}", "rod")
        total, b = series(r, "total"), series(r, "balance_error")[1:]
        relative = float(np.max(np.abs(b)) / np.max(total))
        print(f"info: {scheme}: max |b_n| / max H = {relative:.2e}, sum D = "
              f"{np.sum(series(r, 'dissipated')):.4e}, H at the end {total[-1] / np.max(total):.2e}"
              f" of max H")
        positive_dissipation(checks, scheme, r)
        checks.check(f"{scheme}: H(t_end) / max H (the vibration decays)",
                     float(total[-1] / np.max(total)), 0.05)
        if scheme == "midpoint":
            checks.check("midpoint: max |H_n+1 - H_n - W_n + D_n| / max H (round-off)",
                         relative, 1e-11)


# ---- large motion: the flying spaghetti --------------------------------------------------------

def balance(args, checks):
    base = edited(rs.read_example(args.source, "flying_spaghetti.nml"), [
        ("rod", "formulation", "'se3_pg'"), ("time", "dt", "0.05"),
        ("solver", "newton_atol", "1e-9"), ("output", "fields", "'position'"),
        ("output", "xdmf", ".false.")])
    variants = {"undamped": [], "kelvin_voigt": [("kelvin_voigt_time", "0.5")],
                "drag": [("drag", "0.3")], "angular_drag": [("angular_drag", "3.0")],
                "all": [("kelvin_voigt_time", "0.5"), ("drag", "0.3"), ("angular_drag", "3.0")]}
    for scheme in SCHEMES:
        reference = None
        for label, damping in variants.items():
            text = edited(scheme_of(base, scheme), [("rod", n, v) for n, v in damping])
            r = run(args, text, f"spaghetti_{scheme}_{label}", "spaghetti")
            b = series(r, "balance_error")[1:]
            worst, total = float(np.max(np.abs(b))), float(np.sum(np.abs(b)))
            dissipated = float(np.sum(series(r, "dissipated")))
            print(f"info: {scheme}, {label}: max |b_n| {worst:.3e}, sum |b_n| {total:.3e}, "
                  f"sum D {dissipated:.4e}, H(t_end) {series(r, 'total')[-1]:.4f}")
            if reference is None:
                reference = (worst, total)
                continue
            tag = f"{scheme}, {label}"
            positive_dissipation(checks, tag, r)
            checks.check(f"{tag}: max |b_n| / the undamped run's ({reference[0]:.3e})",
                         worst / reference[0], 1.0)
            checks.check(f"{tag}: sum |b_n| / the undamped run's ({reference[1]:.3e})",
                         total / reference[1], 1.0)


# ---- restart ------------------------------------------------------------------------------------

def restart(args, checks):
    text = edited(scheme_of(rs.read_example(args.source, "se3_pg_damped_cantilever.nml"),
                            "generalized_alpha"), [("output", "fields", "'position'"),
                                                   ("output", "xdmf", ".false.")])
    dt = rs.number(text, "time", "dt")
    text = rs.set_variable(text, "time", "t_end", repr(200 * dt))
    reference = rs.run(args, text, "restart_uninterrupted")
    first = rs.run(args, rs.set_variable(text, "time", "t_end", repr(100 * dt)), "restart_first")
    continued = rs.set_variable(text, "run", "restart_from", f"'{first}'")
    path = rs.run_restart(args, continued, "restart_continued",
                          os.path.join(args.workdir, "restart_continued.h5"))
    with h5py.File(path, "r") as f, h5py.File(reference, "r") as g:
        state = f["checkpoint/cantilever/state"][()]
        expected = g["checkpoint/cantilever/state"][()]
        t_got, t_ref = f["rods/cantilever/time"][-1], g["rods/cantilever/time"][-1]
    elements = int(rs.number(text, "rod", "n_elements"))
    size = 24 * (elements + 1) + 6 * elements
    print(f"info: checkpoint state: {state.size} numbers ({size} expected), final time {t_got} "
          f"({t_ref})")
    checks.check(f"the checkpoint holds q, u, q', u' per node and eps' per element ({size})",
                 abs(state.size - size), 0)
    checks.check("final time minus the uninterrupted run's", abs(t_got - t_ref), 0.0)
    nodes = 6 * (elements + 1)
    parts = {"q": (0, nodes), "u": (nodes, 2 * nodes), "q'": (2 * nodes, 3 * nodes),
             "u'": (3 * nodes, 4 * nodes), "eps'": (4 * nodes, size)}
    for name, (start, end) in parts.items():
        difference = np.max(np.abs(state[start:end] - expected[start:end]))
        checks.check(f"final checkpoint state, {name}: largest difference / largest value",
                     float(difference / np.max(np.abs(expected[start:end]))), 1e-8)


if __name__ == "__main__":
    rs.run_cases(__doc__, {"decrement": decrement, "rigid": rigid, "axial": axial,
                           "balance": balance, "restart": restart})
