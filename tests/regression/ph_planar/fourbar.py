"""Flexible four-bar mechanism (seed 001 §5.3, Table 3, Figs. 8-11; methods/ph_planar.md §6.3
and §10), input/planar_fourbar.nml and input/planar_fourbar_soft.nml: rods 'crank', 'coupler',
'rocker' joined by revolute joints, one system. P is the middle node of 'coupler' (node 4 of 7).

    fourbar.py stiff               P(1) at h = 0.02; the total energy including the work of
                                   gravity kept per step; P(t) of the methods' 10 s table
    fourbar.py time_order          P(1) for h = 0.1 ... 0.01 against the authors' h = 0.005
                                   reference: the methods' errors and order 2; the h = 0.005 run
                                   reproduces the authors' reference
    fourbar.py space_order         P(1) for n_e = (10, 6, 6) ... (160, 96, 96): the authors'
                                   reference, the methods' errors and order 2
    fourbar.py newton_count        mean residual evaluations per step at Newton tolerance 1e-5
                                   (the paper's 4.594) and 1e-10
    fourbar.py soft                the soft coupler (E = 2.1e8) at h = 0.005 for 10 s
    fourbar.py checkpoint_restart  stopped at t = 1 and restarted from the file's checkpoint to
                                   t = 1.4: the uninterrupted run's records
    fourbar.py ranks               the four-bar and the flying spaghetti in one scene, two
                                   independent systems dealt to two ranks: the same results as
                                   on one rank, bitwise

Tolerances (DESIGN.md §8): P(1) = (1.3993463915, -0.7575291362) to 1e-8 per component and the
energy per step to 1e-9 of the energy scale 220.998 J (the initial gravity potential) are
methods §10 acceptance test 4 (the values to 10 decimals, the energy exact up to Newton at
1e-11). The errors of the convergence tables (methods §6.3 [proto]) are the method document's
own re-computation: centres with a band (2 % in time, 5 % in space), as the soft P(1) (band
1e-3, given to 4 decimals). The mean residual evaluations per step, the paper's 4.594 at
tolerance 1e-5 and the methods' 5.070 at 1e-10, are hit exactly: band 0.005, two evaluations
in the 500 steps (newton_count). The authors' code references (h = 0.005; n_e = (160, 96,
96)) are to 1e-8 per component. The soft energy error
per step < 1e-9 is methods §10 acceptance test 5. A restart agrees with the uninterrupted run
to round-off (docs/user/output.md; 1e-12 in the positions); ranks do not change results.
"""
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import planar  # noqa: E402
from planar import rs  # noqa: E402

RODS = ("crank", "coupler", "rocker")
P_STIFF = (1.3993463915, -0.7575291362)          # methods §6.3, h = 0.02, n_e = (10, 6, 6)
P_REF_TIME = (1.396144818042612, -0.763824524916379)    # the authors' code, h = 0.005
P_REF_SPACE = (1.399354522584749, -0.757502351760989)   # the authors' code, (160, 96, 96)
TIME_ERRORS = {0.1: 2.0327e-1, 0.05: 3.2207e-2, 0.02: 4.4380e-3, 0.01: 8.3460e-4}
SPACE_ERRORS = {6: 1.7591e-5, 12: 4.3654e-6, 24: 1.0439e-6, 48: 2.0906e-7}
ENERGY_SCALE = 220.998   # J, the gravity potential at t = 0 (methods §6.3)
# methods §6.3 [proto], stiff, h = 0.02, tol 1e-10: P(t), 4 decimals.
P_TABLE = {0.5: (2.5555, 0.6850), 1.0: (1.3993, -0.7575), 1.5: (2.9156, -0.6366),
           2.0: (1.4887, 0.5610), 2.5: (1.4004, 0.7553), 3.0: (2.5836, -0.6823),
           3.5: (1.0818, -1.2667), 4.0: (2.2746, 0.6530), 4.5: (2.7991, 0.9207),
           5.0: (2.7818, 0.6336), 5.5: (1.6312, -0.1557), 6.0: (2.5448, -1.2490),
           6.5: (1.6285, 0.1644), 7.0: (1.3551, 0.8399), 7.5: (2.0929, -0.5684),
           8.0: (1.2983, -1.7108), 8.5: (2.0006, 0.4994), 9.0: (2.8815, 0.7564),
           9.5: (2.9160, 0.6297), 10.0: (1.8448, 0.3223)}
# methods §6.3 [proto], soft, h = 0.005, tol 1e-9: P(t), 4 decimals.
P_SOFT = {0.5: (2.6033, 0.6777), 1.0: (1.4859, -0.5512), 1.5: (2.6571, -0.9237),
          2.0: (1.7722, -0.2101), 3.0: (2.8607, -0.8167), 4.0: (1.8131, 0.2021),
          5.0: (2.5294, -1.2249), 6.0: (1.6891, -0.1067), 7.0: (1.0320, -1.5889),
          8.0: (1.2907, -0.9008), 9.0: (2.8661, -0.7421), 10.0: (1.3292, -1.2447)}


def scene(args, changes=(), example="planar_fourbar.nml"):
    text = rs.read_example(args.source, example)
    for group, variable, value in changes:
        text = rs.set_variable(text, group, variable, value)
    return text


def point_p(path, time=None):
    """P = the middle node of 'coupler' (node 4 of 7 at n_e = 6) at `time` (default: last record)."""
    coupler = rs.rod(path, "coupler")
    k = -1 if time is None else planar.record(coupler, time)
    nodes = coupler["position"].shape[1]
    return coupler["position"][k, (nodes - 1) // 2, :2], coupler


def system_energy(path):
    """Per-step change of the total energy E_n = H_n - sum_{k <= n} W_k (H = kinetic + strain of
    all rods, W_k = the work of gravity over step k, /series), and the system's balance error
    (on the first rod)."""
    with h5py.File(path, "r") as f:
        total = f["series"]["energy"]["total"][()]
        work = f["series"]["energy"]["external_work"][()]
        balance = f["rods"][RODS[0]]["series"]["energy"]["balance_error"][()]
    energy = total - np.cumsum(work)
    return np.abs(np.diff(energy)), np.abs(balance)


def stiff(args, checks):
    path = rs.run(args, scene(args, [("time", "t_end", "1.0")]), "stiff")
    p, coupler = point_p(path, 1.0)
    print(f"info: P(1) = ({p[0]!r}, {p[1]!r}); P(0) = {coupler['position'][0, 3, :2].tolist()}")
    checks.check("|P(0) - (2.75, 1.0)| (methods §9 item 1)",
                 float(np.max(np.abs(coupler["position"][0, 3, :2] - [2.75, 1.0]))), 1e-14)
    for c in range(2):
        checks.check(f"|P(1) component {c} - ({P_STIFF[c]})|", abs(p[c] - P_STIFF[c]), 1e-8)
    drift, balance = system_energy(path)
    crank = rs.rod(path, "crank")
    rho_a, g = 2710.0 * 0.05**2, 9.81
    potential = rho_a * g * (np.sqrt(5) * 0.5 + 1.5 * 1.0 + np.sqrt(2) * 0.5)
    print(f"info: initial gravity potential {potential:.6f} J (methods 220.998); max per-step "
          f"|delta(H - W)| = {np.max(drift):.3e} J, max |balance error| {np.max(balance):.3e} J; "
          f"Newton linear solves per step {np.mean(crank['series/newton/iterations'][1:]):.3f}")
    checks.check("max per-step |delta(H - W)| / 220.998 J, h = 0.02, tol 1e-11",
                 float(np.max(drift)) / ENERGY_SCALE, 1e-9)
    checks.check("max |balance error of the system| / 220.998 J", float(np.max(balance)) / ENERGY_SCALE,
                 1e-9)
    # The methods' 10 s trajectory (tol 1e-10, 4 decimals).
    path = rs.run(args, scene(args, [("solver", "newton_atol", "1e-10")]), "stiff_10s")
    worst = 0.0
    for time, expected in P_TABLE.items():
        p, _ = point_p(path, time)
        difference = float(np.max(np.abs(p - expected)))
        worst = max(worst, difference)
        checks.check(f"t = {time}: largest |P component - methods §6.3 ({expected[0]}, {expected[1]})|",
                     difference, 1e-4)
    drift, _ = system_energy(path)
    print(f"info: 10 s at tol 1e-10: largest difference from the P(t) table {worst:.2e}; max "
          f"per-step |delta(H - W)| = {np.max(drift):.3e} J (methods: 6e-12)")


def relative_error(p, reference):
    return float(np.linalg.norm(np.asarray(p) - reference) / np.linalg.norm(reference))


def time_order(args, checks):
    """Errors e(h) = |P_h(1) - P_ref| / |P_ref| (methods eq. 82) against the authors' h = 0.005
    reference, n_e = (10, 6, 6), Newton at 1e-9 (as the methods' table; the authors' script uses
    1e-5). The observed order between two steps h1 > h2 is log(e(h1) / e(h2)) / log(h1 / h2),
    taken on the last two refinements 0.05 -> 0.02 and 0.02 -> 0.01. With the reference at
    h = 0.005 in the error, e(0.01) is 3/4 of the true error, so the last order comes out near
    2.4 for an exactly second-order scheme (methods: 2.16 and 2.41): band [1.8, 2.6]."""
    def p_at_1(h):
        text = scene(args, [("time", "t_end", "1.0"), ("time", "dt", repr(h)),
                            ("solver", "newton_atol", "1e-9"), ("output", "stride", str(round(1 / h)))])
        p, _ = point_p(rs.run(args, text, f"time_h{h}"), 1.0)
        return p
    p_ref = p_at_1(0.005)
    print(f"info: h = 0.005: P(1) = ({p_ref[0]!r}, {p_ref[1]!r}), relative difference from the "
          f"authors' reference {relative_error(p_ref, P_REF_TIME):.2e}")
    for c in range(2):
        checks.check(f"h = 0.005: |P(1) component {c} - authors' reference ({P_REF_TIME[c]})|",
                     abs(p_ref[c] - P_REF_TIME[c]), 1e-8)
    errors = {}
    for h, expected in TIME_ERRORS.items():
        p = p_at_1(h)
        errors[h] = relative_error(p, P_REF_TIME)
        print(f"info: h = {h}: P(1) = ({p[0]:.10f}, {p[1]:.10f}), relative error {errors[h]:.5e} "
              f"(methods {expected:.4e})")
        checks.check(f"h = {h}: |error / methods' {expected:.4e} - 1|", abs(errors[h] / expected - 1),
                     0.02)
    for h1, h2 in ((0.05, 0.02), (0.02, 0.01)):
        order = np.log(errors[h1] / errors[h2]) / np.log(h1 / h2)
        print(f"info: observed order {h1} -> {h2}: {order:.3f}")
        checks.check(f"|observed order {h1} -> {h2} - 2.2| (band [1.8, 2.6])", abs(order - 2.2), 0.4)


def space_order(args, checks):
    """h = 0.02, T = 1, Newton at 1e-8, n_e = (10 n / 6, n, n) for n = 6 ... 96 (the authors'
    script: the coupler and the rocker get n, the crank 10 n / 6). Errors against the finest run;
    the order from the changes |P_n - P_2n| between consecutive meshes, which do not involve the
    reference (methods: 1.99 each), band [1.9, 2.1]."""
    points = []
    for n in (6, 12, 24, 48, 96):
        text = scene(args, [("time", "t_end", "1.0"), ("solver", "newton_atol", "1e-8"),
                            ("output", "stride", "50")])
        for rod, count in zip(RODS, (10 * n // 6, n, n)):
            text = planar.set_rod_variable(text, rod, "n_elements", str(count))
        p, coupler = point_p(rs.run(args, text, f"space_n{n}"), 1.0)
        assert coupler["position"].shape[1] == n + 1
        points.append(p)
        print(f"info: n_e = ({10 * n // 6}, {n}, {n}): P(1) = ({p[0]!r}, {p[1]!r})")
    points = np.array(points)
    for c in range(2):
        checks.check(f"(160, 96, 96): |P(1) component {c} - authors' reference ({P_REF_SPACE[c]})|",
                     abs(points[-1, c] - P_REF_SPACE[c]), 1e-8)
    for p, (n, expected) in zip(points, SPACE_ERRORS.items()):
        error = relative_error(p, points[-1])
        print(f"info: n = {n}: relative error against (160, 96, 96) {error:.5e} (methods {expected:.4e})")
        checks.check(f"n = {n}: |error / methods' {expected:.4e} - 1|", abs(error / expected - 1), 0.05)
    changes = np.linalg.norm(np.diff(points, axis=0), axis=1)
    for i in range(len(changes) - 1):
        order = np.log2(changes[i] / changes[i + 1])
        print(f"info: |P_n - P_2n| {changes[i]:.4e} -> {changes[i + 1]:.4e}: order {order:.3f}")
        checks.check(f"|order from the changes at n = {6 * 2**i}, {12 * 2**i} - 2|", abs(order - 2.0), 0.1)


def newton_count(args, checks):
    """Mean residual evaluations per step = linear solves + 1 (methods §4.6: the paper counts
    passes through the Newton loop), over the 500 steps of the stiff run (h = 0.02, T = 10);
    series/newton/iterations at stride 1 holds each step's linear solves (system: first rod)."""
    means = {}
    for tol in ("1e-5", "1e-10"):
        text = scene(args, [("solver", "newton_atol", tol), ("output", "stride", "1")])
        path = rs.run(args, text, f"newton_{tol}")
        iterations = rs.rod(path, RODS[0])["series/newton/iterations"][1:]
        assert iterations.size == 500, iterations.size
        means[tol] = float(np.mean(iterations)) + 1
        drift, _ = system_energy(path)
        print(f"info: tol {tol}: mean residual evaluations per step {means[tol]:.4f} (linear "
              f"solves {np.mean(iterations):.4f}, max {iterations.max()}); max per-step "
              f"|delta(H - W)| {np.max(drift):.2e} J")
    # A mean Newton count is a property of the solver (the residual scaling, the tolerance test,
    # the Jacobian), not of the solution: kept as a regression check against the paper's 4.594
    # and the methods' re-computation 5.070 at 1e-10, which are hit exactly (2297 and 2535
    # evaluations in 500 steps). The mean of 500 integers moves in steps of 0.002; the bound
    # 0.005 allows two steps whose final residual lies within round-off of the tolerance to
    # take one iteration more or less (another BLAS or compiler), and fails on any change of
    # the Newton loop that costs or saves an iteration in three steps of 500.
    checks.check("tol 1e-5: |mean residual evaluations per step - 4.594| (paper, Fig. 11)",
                 abs(means["1e-5"] - 4.594), 0.005)
    checks.check("tol 1e-10: |mean residual evaluations per step - 5.070| (methods §6.3 [proto])",
                 abs(means["1e-10"] - 5.070), 0.005)


def soft(args, checks):
    path = rs.run(args, scene(args, example="planar_fourbar_soft.nml"), "soft")
    with h5py.File(path, "r") as f:
        status = f.attrs["status"]
    p, coupler = point_p(path, 1.0)
    t = coupler["time"]
    checks.check("the run completed (status 'completed', 2001 records, last at t = 10)",
                 float(status != "completed" or t.size != 2001 or abs(t[-1] - 10.0) > 1e-9), 0.0)
    drift, balance = system_energy(path)
    print(f"info: max |balance error| per step {np.max(balance):.3e} J, max per-step "
          f"|delta(H - W)| {np.max(drift):.3e} J (methods: at most 5.6e-10); Newton linear solves "
          f"per step {np.mean(rs.rod(path, RODS[0])['series/newton/iterations'][1:]):.3f} "
          "(methods: 3.97)")
    checks.check("max per-step |balance error| (J)", float(np.max(balance)), 1e-9)
    for c in range(2):
        checks.check(f"|P(1) component {c} - methods' ({P_SOFT[1.0][c]})|", abs(p[c] - P_SOFT[1.0][c]),
                     1e-3)
    for time, expected in P_SOFT.items():
        q, _ = point_p(path, time)
        print(f"info: t = {time:4}: P = ({q[0]:.4f}, {q[1]:.4f}), methods {expected}, difference "
              f"{np.max(np.abs(q - expected)):.1e}")


def checkpoint_restart(args, checks):
    """The three-rod system stopped at t = 1 (flush_every = 10, so the last checkpoint is step 50)
    and continued from that file's checkpoint into a new file to t = 1.4, against one run to 1.4."""
    base = scene(args, [("output", "flush_every", "10")])
    uninterrupted = rs.run(args, rs.set_variable(base, "time", "t_end", "1.4"), "uninterrupted")
    first = rs.run(args, rs.set_variable(base, "time", "t_end", "1.0"), "first_part")
    with h5py.File(first, "r") as f:
        checkpoints = {name: (int(g["step"][0]), float(g["time"][0])) for name, g in f["checkpoint"].items()}
    print(f"info: checkpoints of the first part: {checkpoints}")
    checks.check("checkpoint after step 50 at t = 1 in the first part",
                 float(not checkpoints or any(v != (50, 1.0) for v in checkpoints.values())), 0.0)
    continued = rs.set_variable(rs.set_variable(base, "time", "t_end", "1.4"), "run", "restart_from",
                                f"'{first}'")
    restarted = rs.run_restart(args, continued, "continued", os.path.join(args.workdir, "continued.h5"))
    worst_position, worst_any, worst_key = 0.0, 0.0, ""
    for name in RODS:
        got, ref = rs.rod(restarted, name), rs.rod(uninterrupted, name)
        checks.check(f"rod {name}: records of the restarted file minus the uninterrupted run's (71)",
                     float(abs(got["time"].size - ref["time"].size) + abs(ref["time"].size - 71)), 0.0)
        worst_position = max(worst_position, float(np.max(np.abs(got["position"] - ref["position"]))))
        for key in ref:
            if key == "series/newton/iterations" or got[key].shape != ref[key].shape:
                continue
            difference = float(np.max(np.abs(np.asarray(got[key], float) - ref[key]), initial=0.0))
            if difference > worst_any:
                worst_any, worst_key = difference, f"{name}/{key}"
    print(f"info: largest absolute difference of any dataset {worst_any:.3e} ({worst_key!r})")
    checks.check("largest |position difference| of any record of any rod (m)", worst_position, 1e-12)
    moved = float(np.max(np.abs(rs.rod(uninterrupted, "coupler")["position"][-1]
                                - rs.rod(first, "coupler")["position"][-1])))
    checks.check("the mechanism moves between t = 1 and 1.4 (the comparison can fail)", -moved, -1e-3)


def combined_scene(args):
    """The four-bar (gravity on its three rods only) and the planar flying spaghetti in one scene,
    to t = 1 at h = 0.02, Newton at 1e-10: at 1e-11 the spaghetti at h = 0.02 stalls at its
    round-off floor (1.13e-11 at t = 0.92; the raw residual norm grows as 1/h, methods §4.6)."""
    text = scene(args, [("time", "t_end", "1.0"), ("solver", "newton_atol", "1e-10")])
    gravity = planar.groups(text, "load")[0]
    text = text.replace(gravity, "\n".join(
        gravity.replace("where = 'gravity'", f"rod = '{name}', where = 'gravity'") for name in RODS))
    spaghetti = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    return text + "\n" + "\n".join(planar.groups(spaghetti, "rod") + planar.groups(spaghetti, "load")) + "\n"


def run_printing(args, text, name, ranks):
    output = os.path.join(args.workdir, name + ".h5")
    if os.path.exists(output):
        os.remove(output)
    status, printed = rs.run_failing(args, rs.set_variable(text, "output", "path", f"'{output}'"),
                                     name, ranks=ranks)
    if status != 0:
        raise SystemExit(f"{name} failed with status {status}")
    return output, printed


def ranks(args, checks):
    text = combined_scene(args)
    one, printed_one = run_printing(args, text, "one_rank", 1)
    two, printed_two = run_printing(args, text, "two_ranks", 2)
    # rank 0 prints the summary line of the systems it solved.
    systems_one = re.findall(r"^  (\S+): \d+ steps", printed_one, flags=re.M)
    systems_two = re.findall(r"^  (\S+): \d+ steps", printed_two, flags=re.M)
    print(f"info: systems solved on rank 0: 1 rank {systems_one}, 2 ranks {systems_two}")
    checks.check("2 ranks: rank 0 solves the four-bar system and not the spaghetti (dealt to rank 1)",
                 float(systems_two != ["crank+coupler+rocker"] or len(systems_one) != 2), 0.0)
    p_one, _ = point_p(one, 1.0)
    p_two, _ = point_p(two, 1.0)
    print(f"info: P(1) on 1 rank ({p_one[0]!r}, {p_one[1]!r}), on 2 ranks ({p_two[0]!r}, {p_two[1]!r})")
    checks.check("P(1): 1 rank and 2 ranks differ (bitwise)", float(not np.array_equal(p_one, p_two)), 0.0)
    checks.check("P(1) (tol 1e-10) against methods (1.3993463915, -0.7575291362), largest component",
                 float(np.max(np.abs(p_one - P_STIFF))), 1e-8)
    differing = []
    for name in RODS + ("spaghetti",):
        a, b = rs.rod(one, name), rs.rod(two, name)
        differing += [f"{name}/{key}" for key in sorted(set(a) | set(b))
                      if key not in a or key not in b or not np.array_equal(a[key], b[key])]
    print(f"info: datasets that differ between 1 and 2 ranks: {differing}")
    checks.check("datasets of any rod that differ between 1 and 2 ranks", float(len(differing)), 0.0)


def main():
    parser = rs.common_arguments(__doc__)
    cases = {"stiff": stiff, "time_order": time_order, "space_order": space_order,
             "newton_count": newton_count, "soft": soft, "checkpoint_restart": checkpoint_restart,
             "ranks": ranks}
    parser.add_argument("case", choices=list(cases))
    args = parser.parse_args()
    checks = rs.Checks()
    cases[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
