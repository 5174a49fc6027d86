"""Flexible heavy top (seed 002 §4.5; methods/se3_petrov_galerkin.md §7.3, §10.5, §14.5) with
the paper's first-order generalized-alpha scheme (issue 25 item 3): input/se3_heavy_top_genalpha.nml
(the stiff rod of se3_heavy_top.nml, rho_inf = 0.9, h = t1 / 2000 = 1.006e-3 s) and the soft rod
of se3_heavy_top_soft.nml with scheme = 'generalized_alpha'. t1 = 2 pi / Omega_pr = 2.012152 s.

    heavy_top_genalpha.py coarse   the stiff rod at h = t1/2000: completes without cut-backs; its
                                   tip's error against a fine reference (t1/64000) is the
                                   scheme's time error (order 2 from t1/4000 to t1/16000, 2.2
                                   from t1/2000); T + U + V_g stays within 0.1 E0 over 5 t1,
                                   where the midpoint rule's exceeds E0
    heavy_top_genalpha.py paper    the stiff rod at t1/64000 (and t1/128000): max_t |tip - rigid|
                                   and the tip at t1 against the methods' RK45 run; the tip
                                   against the midpoint rule's at the same h, within the two
                                   schemes' time errors
    heavy_top_genalpha.py soft     the soft rod at t1/4000 .. t1/32000 against t1/256000: order 2
                                   of the tip and of max |E - E0|; the ledger's balance error
                                   against E - E0; the tip at t1 against RK45
    heavy_top_genalpha.py restart  the coarse scene stopped at t1/2 and continued from its
                                   checkpoint ends as the uninterrupted run (1e-12, the history
                                   in the checkpoint state included); with Newton limited to 2
                                   iterations (cut-backs at most steps) it completes, no less
                                   accurate than without

What this shows (docs/theory/se3_pg.md, "Generalized-alpha"): at h = 1e-3 generalized-alpha keeps
the stiff top bounded where the midpoint rule does not, but it does not reach the paper's accuracy
there: its tip error, 2.4e-2 m, is the second-order time error (the same as the midpoint rule's
at this h), 80 times the rod's 3.03e-4 deviation from the rigid precession that the paper
reports. The paper ran the scheme at h = 1e-5; t1/64000 = 3.1e-5 reproduces its numbers.

Tolerances (DESIGN.md §8). Orders are asymptotic properties: 2 +- 0.2 (stiff, from t1/4000, where
the measured orders are 2.03 and 2.0), 2 +- 0.1 (soft, 2.0 measured). The energy bound 0.1 E0 over
5 t1 at h = 1e-3 is 5 times the measured 0.018 E0: it separates a bounded run from the midpoint
rule's growth (28 E0) and from the chart changes at every step that rang the modes before the
complement threshold of 1.25 pi (0.29 E0). The RK45 values are the methods document's own run,
given to 3 .. 6 digits: centres with a band, the band at t1/64000 being the measured time error
there (4/3 |tip_h - tip_h/2|, order 2) plus the rounding of the printed digits, doubled for the
estimate's own error. Newton stops at 1e-4 N as in the scenes (heavy_top.py explains the choice).
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "io"))
import heavy_top as ht  # noqa: E402
import se3_scene  # noqa: E402
from se3_scene import rs  # noqa: E402
import checkpoint  # noqa: E402

GENALPHA = "se3_heavy_top_genalpha.nml"
N_COARSE = 2000          # the scene's h = t1 / 2000
# Printed digits of the methods' RK45 tip at t1 (stiff): half a unit of the last digit.
STIFF_TIP_ROUNDING = (5e-7, 5e-8, 5e-9)


class Measured(ht.Measured):
    """A run over `periods` precessions (heavy_top.Measured is for one)."""

    def __init__(self, result, steps, periods=1):
        super().__init__(result, steps * periods)
        self.steps, self.h = steps, ht.T1 / steps
        t = result["time"]
        self.completed = (result.status == 0 and t.size == steps * periods + 1
                          and abs(t[-1] - periods * ht.T1) < 1e-12 * periods)


def run(args, example, steps, periods=1, changes=(), fields="'position'", allow_failure=False):
    """`example` at h = t1 / steps over `periods` precessions, every step recorded."""
    text = se3_scene.edit(rs.read_example(args.source, example), [
        ("time", "dt", repr(ht.T1 / steps)), ("time", "t_end", repr(periods * ht.T1)),
        ("solver", "newton_atol", repr(ht.newton_atol(steps))),
        ("output", "stride", "1"), ("output", "fields", fields), ("output", "xdmf", ".false."),
        ("output", "flush_every", "8000"), *changes])
    name = f"ga_{example[:-4]}_{steps}_{periods}" + "".join(f"_{v}" for _, _, v in changes)
    name = name.replace("'", "").replace(".", "p")
    result = se3_scene.run(args, text, name, "top", allow_failure=allow_failure)
    return Measured(result, steps, periods)


def with_genalpha(rho=0.9):
    return (("time", "scheme", "'generalized_alpha'"), ("time", "rho_inf", repr(rho)))


def error_to(reference, m):
    """max_t |tip - tip_reference| on m's records."""
    return ht.trajectory_difference(reference, m)


def coarse(args, checks):
    reference = run(args, GENALPHA, 64000)
    runs = [run(args, GENALPHA, n) for n in (N_COARSE, 2 * N_COARSE, 4 * N_COARSE, 8 * N_COARSE)]
    errors = []
    for m in runs:
        print(f"info: {m.summary()}")
        ht.check_completed(checks, m)
        errors.append(error_to(reference, m))
        print(f"info: h = t1/{m.steps}: max_t |tip - tip(t1/64000)| = {errors[-1]:.4e}; max_t |tip - "
              f"rigid| = {m.max_distance():.4e} (the paper's deviation 3.03e-4); max_t |E - E0| = "
              f"{m.accumulated():.4e} J = {m.accumulated() / m.energy[0]:.2e} E0, E(t1) - E0 = "
              f"{m.drift[-1]:.3e} J")
    # From t1/2000 the order is 2.2: the bending-shear modes ringing at omega h = 2 add to the
    # error at h = 1e-3; from t1/4000 on the runs are in the asymptotic range.
    for (a, b), ea, eb in zip(zip(runs[:-1], runs[1:]), errors[:-1], errors[1:]):
        p = ht.order(ea, eb)
        print(f"info: order of the tip error, t1/{a.steps} -> t1/{b.steps}: {p:.3f}")
        if a.steps > N_COARSE:
            checks.check(f"|order of max_t |tip - reference|, t1/{a.steps} -> t1/{b.steps}, - 2|",
                         abs(p - 2.0), 0.2)
    long = run(args, GENALPHA, N_COARSE, periods=5)
    midpoint = run(args, ht.STIFF, N_COARSE, periods=5, allow_failure=True)
    for label, m in (("generalized-alpha", long), ("midpoint", midpoint)):
        print(f"info: 5 t1 at t1/{N_COARSE}, {label}: {m.summary()}; max_t |E - E0| = "
              f"{m.accumulated():.4e} J = {m.accumulated() / m.energy[0]:.3e} E0, largest strain energy "
              f"{np.max(m.result['series/energy/strain']):.4g} J")
    checks.check(f"5 t1 at t1/{N_COARSE}: generalized-alpha reached 5 t1 without cut-backs",
                 float(not long.completed or long.result.cutbacks != 0), 0.0)
    checks.check(f"5 t1 at t1/{N_COARSE}: generalized-alpha max_t |E - E0| / E0 (bounded)",
                 long.accumulated() / long.energy[0], 0.1)
    checks.check(f"5 t1 at t1/{N_COARSE}: E0 / (the midpoint rule's max_t |E - E0|) (the test is not "
                 "trivial: the midpoint rule's energy grows past E0 here)",
                 midpoint.energy[0] / midpoint.accumulated(), 1.0)


def paper(args, checks):
    ga, ga_half = run(args, GENALPHA, ht.N_SCENE), run(args, GENALPHA, 2 * ht.N_SCENE)
    mid, mid_half = run(args, ht.STIFF, ht.N_SCENE), run(args, ht.STIFF, 2 * ht.N_SCENE)
    for m in (ga, ga_half, mid, mid_half):
        print(f"info: {m.summary()}")
        ht.check_completed(checks, m)
    ga_error = 4.0 / 3.0 * ht.trajectory_difference(ga_half, ga)
    mid_error = 4.0 / 3.0 * ht.trajectory_difference(mid_half, mid)
    tip_error = 4.0 / 3.0 * np.abs(ga_half.tip[-1] - ga.tip[-1])
    tip = ga.tip[-1]
    print(f"info: generalized-alpha at t1/{ht.N_SCENE}: max_t |tip - rigid| = {ga.max_distance():.5e} "
          f"(RK45 3.03e-4); tip(t1) = ({tip[0]:.7f}, {tip[1]:.5e}, {tip[2]:.5e}) (RK45 "
          f"{ht.STIFF_TIP_T1}); time error of the tip over t1 {ga_error:.3e}, at t1 {tip_error}; "
          f"the midpoint rule's over t1 {mid_error:.3e}")
    checks.check("|max_t |tip - rigid precession| - 3.03e-4 (RK45)| (band 5 %, as heavy_top.py)",
                 abs(ga.max_distance() - ht.STIFF_MAX_DISTANCE), 1.5e-5)
    for c in range(3):
        band = 2.0 * (tip_error[c] + STIFF_TIP_ROUNDING[c])
        checks.check(f"|tip(t1) component {c} - RK45 {ht.STIFF_TIP_T1[c]}| - band {band:.2e} "
                     "(twice the time error at t1 and the rounding)",
                     abs(tip[c] - ht.STIFF_TIP_T1[c]) - band, 0.0)
    difference = ht.trajectory_difference(ga, mid)
    print(f"info: max_t |tip(generalized-alpha) - tip(midpoint)| at t1/{ht.N_SCENE} = {difference:.3e}")
    checks.check("max_t |tip(generalized-alpha) - tip(midpoint)| - (their time errors summed)",
                 difference - (ga_error + mid_error), 0.0)


def soft(args, checks):
    changes = with_genalpha()
    reference = run(args, ht.SOFT, 256000, changes=changes)
    steps = (4000, 8000, 16000, 32000)
    runs = [run(args, ht.SOFT, n, changes=changes) for n in steps]
    errors, energies = [], []
    for m in runs:
        print(f"info: {m.summary()}")
        ht.check_completed(checks, m)
        errors.append(error_to(reference, m))
        energies.append(m.accumulated())
        print(f"info: h = t1/{m.steps}: max_t |tip - tip(t1/256000)| = {errors[-1]:.4e}; max_t |E - E0| "
              f"= {energies[-1]:.4e} J, E(t1) - E0 = {m.drift[-1]:.4e} J; tip(t1) = {m.tip[-1]}")
        checks.check(f"h = t1/{m.steps}: max_t |sum of balance_error - (E - E0)| (J)",
                     float(np.max(np.abs(np.cumsum(m.balance) - m.drift))), 1e-8)
    for i in range(1, len(runs)):
        p_tip, p_energy = ht.order(errors[i - 1], errors[i]), ht.order(energies[i - 1], energies[i])
        print(f"info: t1/{steps[i - 1]} -> t1/{steps[i]}: order of the tip error {p_tip:.3f}, of "
              f"max |E - E0| {p_energy:.3f}")
        checks.check(f"|order of max_t |tip - reference|, t1/{steps[i - 1]} -> t1/{steps[i]}, - 2|",
                     abs(p_tip - 2.0), 0.1)
        checks.check(f"|order of max_t |E - E0|, t1/{steps[i - 1]} -> t1/{steps[i]}, - 2|",
                     abs(p_energy - 2.0), 0.2)
    checks.check(f"t1/{steps[-1]}: |tip(t1) - RK45 (0.429909, -0.236342, -0.057128)| (issue 7: 1e-3)",
                 float(np.linalg.norm(runs[-1].tip[-1] - ht.SOFT_TIP_T1)), 1e-3)


def restart(args, checks):
    text = se3_scene.edit(rs.read_example(args.source, GENALPHA), [
        ("output", "flush_every", "250"), ("output", "xdmf", ".false.")])
    reference = rs.run(args, text, "ga_uninterrupted")
    half = repr(N_COARSE // 2 * ht.T1 / N_COARSE)
    first = rs.run(args, rs.set_variable(text, "time", "t_end", half), "ga_first_half")
    continued = rs.set_variable(text, "run", "restart_from", f"'{first}'")
    path = rs.run_restart(args, continued, "ga_continued", os.path.join(args.workdir, "ga_continued.h5"))
    checkpoint.check_final(checks, "restart at t1/2", path, reference, name="top")
    checkpoint.compare_records(checks, "restart at t1/2", path, reference, name="top")
    with h5py.File(path, "r") as f, h5py.File(reference, "r") as g:
        state, expected = f["checkpoint/top/state"][()], g["checkpoint/top/state"][()]
    print(f"info: checkpoint state: {state.size} numbers (24 per node: q, u and the history q', u')")
    checks.check("the checkpoint holds q, u, q', u' (24 per node of the 2)", abs(state.size - 48), 0)
    checks.check("restart at t1/2: final checkpoint state (history included), largest difference / "
                 "max(1, |state|)", float(np.max(np.abs(state - expected)) / max(1.0, np.max(np.abs(expected)))),
                 1e-12)
    # Cut-backs: every retry starts from X_n, history included (src/solver/rodmid.c), so a run
    # whose Newton is limited to 2 iterations (most steps then cut to two halves) is the same
    # scheme on a finer, uneven grid: it must complete, and be no less accurate than the run
    # without cut-backs (a history spoiled by a failed attempt would be an O(1) error).
    fine = run(args, GENALPHA, 64000)
    uncut = run(args, GENALPHA, N_COARSE)
    cut = run(args, GENALPHA, N_COARSE, changes=(("solver", "max_newton", "2"),))
    print(f"info: with max_newton = 2: {cut.summary()}; max_t |tip - tip(t1/64000)| "
          f"{error_to(fine, cut):.3e} (without cut-backs {error_to(fine, uncut):.3e})")
    checks.check("max_newton = 2: the run reached t1", float(not cut.completed), 0.0)
    checks.check("max_newton = 2: 1 / cut-backs (there are some)", 1.0 / max(cut.result.cutbacks, 1e-300),
                 1.0)
    checks.check("max_newton = 2: max_t |tip - reference| / the uncut run's",
                 error_to(fine, cut) / error_to(fine, uncut), 1.0)


if __name__ == "__main__":
    rs.run_cases(__doc__, {"coarse": coarse, "paper": paper, "soft": soft, "restart": restart})
