"""Flexible heavy top (seed 002 §4.5, Fig. 10; methods/se3_petrov_galerkin.md §10.5, §14.5, §15
item 8), input/se3_heavy_top.nml (stiff) and input/se3_heavy_top_soft.nml (stiffnesses / 1e3):
one se3_pg element pinned at the origin, spinning at Omega = 50 pi about its horizontal axis and
precessing under gravity; implicit midpoint rule, t_end = t1 = 2 pi / Omega_pr = 2.012152 s.
The scenes' step is h = t1 / 64000 = 3.144e-5 s.

    heavy_top.py stiff       h and h/2: max_t |tip - rigid precession|, the tip at t1 and its z
                             range against the methods' RK45 run; the time error at h (from h/2)
    heavy_top.py soft        h and 2h: the tip at t1 within 1e-3 of the RK45 reference (order 2 in
                             h), max |tip - rigid|, z_min, the tip at t1/4, t1/2, 3 t1/4
    heavy_top.py energy      E = T + U + V_g (V_g the nodal-average gravity potential, methods
                             §14.5) and the balance-error sums: E0, the largest |E - E0| over the
                             run and the largest per-step change, their orders in h (soft 4h, 2h,
                             h; stiff 2h, h, h/2)
    heavy_top.py time_order  (slow) both rods from h = t1/2000 to t1/256000: the tables behind the
                             choice of h (distance, tip error, energy, Newton, time loop); the
                             orders, and the h -> 0 limit of the stiff rod's distance

Tolerances (DESIGN.md §8). The reference values are the methods document's own RK45 re-computation
(rtol 1e-8 .. 1e-10, given to 3 .. 6 digits): centres with a band. The band of a value at the
scenes' h is the measured time error there (order 2, from the runs at h/2 or 2h) plus the rounding
of the printed value. The issue's "within 3e-4 of the rigid precession" is read as "about 3e-4":
the h -> 0 limit of max_t |tip - rigid| is 3.030e-4 (Richardson on h/4, h/8), as the methods' RK45
(3.03e-4), so a bound of 3e-4 holds only for an under-resolved run (2.963e-4 at h, 3.012e-4 at h/2);
the check is |max - 3.03e-4| <= 1.5e-5 (5 %: 2 % time error at h, the rest the RK45's digits).
The midpoint rule does not keep this element's energy (methods §7.4): the energy checks assert the
measured orders, 2 for the largest |E - E0| over the run (a bounded oscillation, largest near
t1/2, no secular drift) and 3 for the largest per-step change, each in a band of 0.2 / 0.4, and the
identity sum(balance_error) = E - E0 (gravity is a constant dead load, so the work f . dr is
exactly -dV_g) to 1e-8 J. The one element's two nodes turn together (relative rotation below
6e-11 rad in both runs: their rotation rows and masses are alike), so the Petrov-Galerkin
energy inconsistency of docs/theory/se3_pg.md (second order in the relative rotation) does not
enter: the energy error measured here is the midpoint rule's alone (extrapolated to h -> 0 it
is below 1e-4 J over t1).
Newton stops at 1e-4 N (the scenes' value): the residual's round-off floor grows as 1/h^2 (about
2e-6 N at h, 3e-5 N at h/4, where 4e-4 N is used). The scenes ask for PETSc's LU (&solver
petsc_options), ten times faster than MUMPS on these 9 unknowns, with the same motion.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import se3_scene  # noqa: E402
from se3_scene import rs  # noqa: E402

T1 = 2.0121517637287174               # 2 pi / Omega_pr
OMEGA_PR = 3.122619983462986          # g L / (r^2 Omega), Omega = 50 pi
LENGTH = 0.5
RHO_A, GRAVITY = 251.32741228718348, 9.81
N_SCENE = 64000                       # the scenes' steps: h = t1 / 64000
STIFF, SOFT = "se3_heavy_top.nml", "se3_heavy_top_soft.nml"
E0 = 7804.156                         # methods §14.5, J (3 decimals)
# methods §14.5, RK45 (rtol 1e-8), stiff rod.
STIFF_MAX_DISTANCE = 3.03e-4
STIFF_TIP_T1 = (0.500016, -2.265e-4, -2.247e-5)
STIFF_Z_MIN = -2.52e-4
# methods §14.5, RK45 (rtol 1e-8, unchanged at 1e-10), soft rod.
SOFT_TIP_T1 = (0.429909, -0.236342, -0.057128)
SOFT_MAX_DISTANCE = 0.2761
SOFT_Z_MIN = -0.24741
SOFT_QUARTERS = {1: (0.01507, 0.51758, -0.24736), 2: (-0.48113, 0.12676, -0.01541),
                 3: (-0.05667, -0.52963, -0.21355)}


def newton_atol(steps):
    """1e-4 N down to h/2; above, 1e-4 (steps / 128000)^2, following the 1/h^2 round-off floor."""
    return 1e-4 * max(1.0, (steps / 128000) ** 2)


def run(args, example, steps, allow_failure=False):
    """The example at h = t1 / steps, every step recorded (positions and the series only)."""
    text = se3_scene.edit(rs.read_example(args.source, example), [
        ("time", "dt", repr(T1 / steps)), ("solver", "newton_atol", repr(newton_atol(steps))),
        ("output", "stride", "1"), ("output", "fields", "'position'"), ("output", "xdmf", ".false."),
        ("output", "flush_every", "8000")])
    name = f"{example[:-4]}_{steps}"
    result = se3_scene.run(args, text, name, "top", allow_failure=allow_failure)
    return Measured(result, steps)


class Measured:
    """What the checks use from one run."""

    def __init__(self, result, steps):
        self.result, self.steps, self.h = result, steps, T1 / steps
        self.status = result.status
        t = result["time"]
        self.t, self.tip = t, result["position"][:, -1, :]
        self.completed = result.status == 0 and t.size == steps + 1 and abs(t[-1] - T1) < 1e-12
        rigid = LENGTH * np.stack([np.cos(OMEGA_PR * t), np.sin(OMEGA_PR * t), 0.0 * t], axis=1)
        self.distance = np.linalg.norm(self.tip - rigid, axis=1)
        x = result["position"]
        # V_g = -sum_e b . (r_e + r_e+1) l_e / 2, b = rhoA (0, 0, -g) (methods §14.5).
        potential = RHO_A * GRAVITY * 0.5 * LENGTH * (x[:, 0, 2] + x[:, 1, 2])
        self.energy = (result["series/energy/kinetic"] + result["series/energy/strain"] + potential)
        self.drift = self.energy - self.energy[0]
        self.balance = result["series/energy/balance_error"]
        self.solves = result["series/newton/iterations"][1:]

    def max_distance(self):
        return float(np.max(self.distance))

    def accumulated(self):
        """Largest |E - E0| over the run."""
        return float(np.max(np.abs(self.drift)))

    def per_step(self):
        """Largest |E_n+1 - E_n| (every step is a record)."""
        return float(np.max(np.abs(np.diff(self.energy))))

    def at(self, fraction):
        """The tip at t = fraction t1 (a record: steps divisible by 4)."""
        return self.tip[round(fraction * self.steps)]

    def summary(self):
        r = self.result
        return (f"h = t1/{self.steps} = {self.h:.4e} s: {r.steps} steps, "
                f"{np.mean(self.solves):.3f} linear solves per step (max {np.max(self.solves)}), "
                f"{r.cutbacks} cut-backs, time loop {r.seconds:.3g} s, wall {r.wall_seconds:.3g} s")


def trajectory_difference(fine, coarse):
    """max_t |tip_fine - tip_coarse| on the coarse run's records."""
    k = fine.steps // coarse.steps
    return float(np.max(np.linalg.norm(fine.tip[::k] - coarse.tip, axis=1)))


def order(coarse_value, fine_value, ratio=2.0):
    return float(np.log(coarse_value / fine_value) / np.log(ratio))


def check_completed(checks, m, label=""):
    checks.check(f"{label}h = t1/{m.steps}: the run reached t1 in {m.steps} steps without cut-backs",
                 float(not m.completed or m.result.cutbacks != 0), 0.0)


def stiff(args, checks):
    h, half = run(args, STIFF, N_SCENE), run(args, STIFF, 2 * N_SCENE)
    for m in (h, half):
        print(f"info: {m.summary()}")
        check_completed(checks, m)
        tip = m.tip[-1]
        print(f"info: h = t1/{m.steps}: max_t |tip - rigid| = {m.max_distance():.5e} at t = "
              f"{m.t[np.argmax(m.distance)]:.4f}; tip(t1) = ({tip[0]:.7f}, {tip[1]:.5e}, "
              f"{tip[2]:.5e}); z in [{np.min(m.tip[:, 2]):.4e}, {np.max(m.tip[:, 2]):.3e}]")
    time_error = 4.0 / 3.0 * trajectory_difference(half, h)
    limit = half.max_distance() + (half.max_distance() - h.max_distance()) / 3.0
    print(f"info: time error of the tip at h (4/3 max_t |tip_h - tip_h/2|, order 2) {time_error:.3e}"
          f" = {time_error / STIFF_MAX_DISTANCE:.1%} of the deviation; max |tip - rigid| "
          f"extrapolated to h -> 0: {limit:.4e} (methods' RK45 3.03e-4); the issue's bound 3e-4 "
          f"{'holds' if h.max_distance() <= 3e-4 else 'fails'} at h and "
          f"{'holds' if half.max_distance() <= 3e-4 else 'fails'} at h/2")
    checks.check("h: |max_t |tip - rigid precession| - 3.03e-4 (RK45)| (band 5 %)",
                 abs(h.max_distance() - STIFF_MAX_DISTANCE), 1.5e-5)
    checks.check("h/2: |max_t |tip - rigid precession| - 3.03e-4 (RK45)| (band 2 %)",
                 abs(half.max_distance() - STIFF_MAX_DISTANCE), 6e-6)
    for c in range(3):
        checks.check(f"h: |tip(t1) component {c} - RK45 {STIFF_TIP_T1[c]}|",
                     abs(h.tip[-1, c] - STIFF_TIP_T1[c]), 5e-6)
    checks.check(f"h: |min_t z_tip - RK45 {STIFF_Z_MIN}|", abs(np.min(h.tip[:, 2]) - STIFF_Z_MIN), 5e-6)
    checks.check("h: max_t z_tip (RK45: z <= 0; the time error at h lifts it)",
                 float(np.max(h.tip[:, 2])), 2e-5)
    checks.check("time error of the tip at h / the 3.03e-4 deviation (measured 10 %)",
                 time_error / STIFF_MAX_DISTANCE, 0.15)


def soft(args, checks):
    h, double = run(args, SOFT, N_SCENE), run(args, SOFT, N_SCENE // 2)
    errors = {}
    for m in (double, h):
        print(f"info: {m.summary()}")
        check_completed(checks, m)
        errors[m.steps] = float(np.linalg.norm(m.tip[-1] - SOFT_TIP_T1))
        tip = m.tip[-1]
        print(f"info: h = t1/{m.steps}: tip(t1) = ({tip[0]:.6f}, {tip[1]:.6f}, {tip[2]:.6f}), "
              f"|tip(t1) - RK45| = {errors[m.steps]:.3e}; max |tip - rigid| {m.max_distance():.5f}; "
              f"z_min {np.min(m.tip[:, 2]):.6f}")
    checks.check("h: |tip(t1) - RK45 (0.429909, -0.236342, -0.057128)| (issue 7: 1e-3)",
                 errors[N_SCENE], 1e-3)
    p = order(errors[N_SCENE // 2], errors[N_SCENE])
    print(f"info: order of the tip error at t1, 2h -> h: {p:.3f}")
    checks.check("|order of the tip error at t1 (2h -> h) - 2|", abs(p - 2.0), 0.2)
    checks.check("h: |max_t |tip - rigid| - 0.2761 (RK45, 4 digits)|",
                 abs(h.max_distance() - SOFT_MAX_DISTANCE), 2e-4)
    checks.check("h: |min_t z_tip - (-0.24741) (RK45, 5 digits)|",
                 abs(np.min(h.tip[:, 2]) - SOFT_Z_MIN), 2e-5)
    # The methods' quarter points are RK45 steps near k t1 / 4 (3401 steps, about 6e-4 s, at a tip
    # speed of 1.6 m/s): x at t1/4 differs by 1.6e-4 in the limit h -> 0.
    for k, expected in SOFT_QUARTERS.items():
        got = h.at(k / 4)
        print(f"info: tip({k} t1/4) = ({got[0]:.6f}, {got[1]:.6f}, {got[2]:.6f}), RK45 about {expected}")
        checks.check(f"h: largest |tip({k} t1/4) component - RK45 {expected}| (RK45 output time "
                     "approximate)", float(np.max(np.abs(got - expected))), 1e-3)


def energy_checks(checks, label, runs):
    """runs: from coarse to fine, each h half the previous."""
    for m in runs:
        print(f"info: {label} {m.summary()}")
        check_completed(checks, m, label + " ")
        print(f"info: {label} h = t1/{m.steps}: E0 = {m.energy[0]:.6f} J; max_t |E - E0| = "
              f"{m.accumulated():.4e} J at t = {m.t[np.argmax(np.abs(m.drift))]:.3f} "
              f"({m.accumulated() / m.energy[0]:.2e} of E0); E(t1) - E0 = {m.drift[-1]:.3e} J; "
              f"largest per-step |dE| = {m.per_step():.4e} J; mean per-step dE = "
              f"{np.mean(np.diff(m.energy)):.2e} J; balance_error: largest |per step| "
              f"{np.max(np.abs(m.balance)):.4e} J, sum {np.sum(m.balance):.4e} J")
        checks.check(f"{label} h = t1/{m.steps}: |E0 - 7804.156 J (methods §14.5)|",
                     abs(m.energy[0] - E0), 5e-4)
        checks.check(f"{label} h = t1/{m.steps}: max_t |sum of balance_error - (E - E0)| (J)",
                     float(np.max(np.abs(np.cumsum(m.balance) - m.drift))), 1e-8)
    for coarse, fine in zip(runs[:-1], runs[1:]):
        p_acc = order(coarse.accumulated(), fine.accumulated())
        p_step = order(coarse.per_step(), fine.per_step())
        print(f"info: {label} t1/{coarse.steps} -> t1/{fine.steps}: max |E - E0| falls by "
              f"{coarse.accumulated() / fine.accumulated():.3f} (order {p_acc:.3f}), the largest "
              f"per-step change by {coarse.per_step() / fine.per_step():.3f} (order {p_step:.3f})")
        checks.check(f"{label} |order of max_t |E - E0|, t1/{coarse.steps} -> t1/{fine.steps}, - 2|",
                     abs(p_acc - 2.0), 0.2)
        checks.check(f"{label} |order of the largest per-step |dE|, t1/{coarse.steps} -> "
                     f"t1/{fine.steps}, - 3|", abs(p_step - 3.0), 0.4)


def energy(args, checks):
    energy_checks(checks, "soft", [run(args, SOFT, n) for n in (N_SCENE // 4, N_SCENE // 2, N_SCENE)])
    energy_checks(checks, "stiff", [run(args, STIFF, n) for n in (N_SCENE // 2, N_SCENE, 2 * N_SCENE)])


def time_order(args, checks):
    """Both rods from t1/2000 (h = 1e-3) to t1/256000 (7.9e-6 s). Orders are checked from
    t1/16000 on: at t1/2000 the stiff rod's energy grows (+469 J over t1, without bound over
    more precessions; its bending-shear modes at 1870 and 2170 rad/s make omega h = 2.2), at
    t1/4000 it wanders by 2 %, at t1/8000 the energy order is 2.24. The energy orders stop at
    t1/128000: at t1/256000 Newton's 4e-4 N (one solve per step) is felt."""
    steps = (2000, 4000, 8000, 16000, 32000, 64000, 128000, 256000)
    for example, label in ((STIFF, "stiff"), (SOFT, "soft")):
        runs = [run(args, example, n, allow_failure=n < 8000) for n in steps]
        print(f"info: {label}: steps | h | max|tip - rigid| | max_t|tip - tip(2h)| | "
              "|tip(t1) - RK45| | max|E - E0| | max per-step |dE| | E(t1) - E0 | solves/step | "
              "time loop s | status")
        differences = {}
        for i, m in enumerate(runs):
            if i > 0 and m.completed and runs[i - 1].completed:
                differences[m.steps] = trajectory_difference(m, runs[i - 1])
            reference = STIFF_TIP_T1 if label == "stiff" else SOFT_TIP_T1
            print(f"info: {label}: {m.steps} | {m.h:.3e} | {m.max_distance():.4e} | "
                  f"{differences.get(m.steps, float('nan')):.3e} | "
                  f"{np.linalg.norm(m.tip[-1] - reference):.3e} | {m.accumulated():.3e} | "
                  f"{m.per_step():.3e} | {m.drift[-1]:.3e} | {np.mean(m.solves):.3f} | "
                  f"{m.result.seconds:.3g} | {'completed' if m.completed else 'FAILED'}")
        for n in steps[3:-1]:
            if n in differences and 2 * n in differences:
                p = order(differences[n], differences[2 * n])
                checks.check(f"{label}: |order of max_t |tip_h - tip_2h| at t1/{n} -> t1/{2 * n} - 2|",
                             abs(p - 2.0), 0.2)
        fine = [m for m in runs if 16000 <= m.steps <= 128000]
        for coarse, m in zip(fine[:-1], fine[1:]):
            p = order(coarse.accumulated(), m.accumulated())
            checks.check(f"{label}: |order of max_t |E - E0| at t1/{coarse.steps} -> t1/{m.steps} - 2|",
                         abs(p - 2.0), 0.2)
        if label == "soft":
            errors = [np.linalg.norm(m.tip[-1] - SOFT_TIP_T1) for m in fine]
            for (a, b), ea, eb in zip(zip(fine[:-1], fine[1:]), errors[:-1], errors[1:]):
                checks.check(f"soft: |order of |tip(t1) - RK45| at t1/{a.steps} -> t1/{b.steps} - 2|",
                             abs(order(ea, eb) - 2.0), 0.2)
        else:
            last, before = runs[-1], runs[-2]
            limit = last.max_distance() + (last.max_distance() - before.max_distance()) / 3.0
            print(f"info: stiff: max |tip - rigid| extrapolated to h -> 0: {limit:.4e} (RK45 3.03e-4)")
            checks.check("stiff: |extrapolated max |tip - rigid| - 3.03e-4 (RK45)|",
                         abs(limit - STIFF_MAX_DISTANCE), 3e-6)


if __name__ == "__main__":
    rs.run_cases(__doc__, {"stiff": stiff, "soft": soft, "energy": energy, "time_order": time_order})
