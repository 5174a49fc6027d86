"""Benchmark: a parameter sweep on 1 and 2 ranks (issue 9; DESIGN.md §5, §9).

Runs input/sweep_cantilever.nml (64 cantilevers over rod(1)%EI1) with `mpirun --oversubscribe
-np 1` and `-np 2`, `--repeat` times each, alternating the two so that drifts of the shared
machine hit both alike, and reports per configuration the medians of

- the process wall time (what a user waits for: MPI launch, PETSc start-up, the members, the
  merge into one file),
- the sweep's own wall time (the result file's root attribute `wall_time`: dealing, the
  members, up to the merge),
- the members' wall times summed (/summary/wall_time, each member's run on its rank),

the speedup and the parallel efficiency (speedup / ranks; target at least 90 %), and the load
balance on 2 ranks: the estimate rodsolve logs when it deals the members by cost ("slowest
rank / mean = X") and the measured one, the members' wall times summed per rank (/summary/rank
says which rank ran which member), slowest rank over the mean. It checks that the 1- and
2-rank files hold bitwise identical /members/<id>/rods/<rod>/position for every member, that
/summary/id is 1 .. M in order and that every member completed; exit status 1 if not.

Then, per LU package (the chain LU `rodchain`, the default for a single rod, and `mumps`,
the path before it, chosen by `-pc_factor_mat_solver_type`), a sweep of many small rods: the
same cantilever with --small-members members (1000) over EI1, 4 elements, --small-steps (100)
steps, once as in the catalog (statics, &time quasistatic) and once as dynamics (quasistatic =
.false., the same load ramp), each member writing its first and last record only (output
stride = steps). It reports member-steps per second per core (members x steps / (wall time x
ranks)) from the process, sweep and summed member wall times, medians of --small-repeat runs
with the packages taking turns, the ratio of the packages, the members' Newton iterations
summed (/summary/newton_iterations), how many members printed rodchain's message that MUMPS
factors their Jacobians, and the largest difference of the tip positions between the packages.
With --baseline-rodsolve, the same small rods also run with that executable (an older build,
e.g. of the commit before issue 20's work, with its own default LU) in the same run, taking
turns with the others: issue 20's sweep target is a ratio to that path.

With --write the tables replace the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/sweep_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench_sweep [--repeat 5] \\
        [--small-members 1000] [--small-repeat 3] [--only ranks|packages] [--write] \\
        [--baseline-rodsolve OLD/rodsolve --baseline-label "the build of commit b5f9e2f"]
"""
import os
import re
import statistics
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import rs, measured_on, write_generated  # noqa: E402

SCENE = "sweep_cantilever.nml"
RANKS = (1, 2)
DEALT = re.compile(r"rodsolve: sweep of (\d+) members on (\d+) rank\(s\), dealt by estimated "
                   r"cost \(slowest rank / mean = (\S+?)\)")
FINISHED = re.compile(r"rodsolve: sweep of (\d+) members: (\d+) completed, (\d+) failed, "
                      r"(\d+) not run")
MEMBER_DONE = re.compile(r"rodsolve: sweep member \d+ of \d+ done")
FALLBACK = re.compile(r"^rodchain: .*MUMPS factors such Jacobians", re.M)
PACKAGES = ("rodchain", "mumps")
# The path of issue 20's filing: another executable (--baseline-rodsolve) with its defaults.
BASELINE = "baseline"
MODES = {"statics": ".true.", "dynamics": ".false."}
ENVIRONMENT = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
               "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


def run_sweep(args, text, ranks, name, rodsolve=None):
    """Run the sweep on `ranks` ranks into `name`.h5 with the executable `rodsolve` (default
    --rodsolve); the process wall time, the log's estimate, and the file's wall time and
    per-member columns."""
    output = os.path.join(args.workdir, name + ".h5")
    if os.path.exists(output):
        os.remove(output)
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(rs.set_variable(text, "output", "path", f"'{output}'"))
    command = [args.mpiexec, "--oversubscribe", "-np", str(ranks), rodsolve or args.rodsolve,
               scene]
    # Each line with the time it arrived: the last member's line to the final line of the log
    # is the merge on rank 0 (on 1 rank; on more, also the wait for the other ranks).
    stamped = []
    started = time.perf_counter()
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          env=dict(os.environ, **ENVIRONMENT)) as process:
        for line in process.stdout:
            stamped.append((time.perf_counter(), line))
    seconds = time.perf_counter() - started
    log = "".join(line for _, line in stamped)
    if process.returncode != 0:
        sys.stderr.write(log)
        raise SystemExit(f"{' '.join(command)} failed with status {process.returncode}")
    dealt, finished = DEALT.search(log), FINISHED.search(log)
    if dealt is None or finished is None:
        sys.stderr.write(log)
        raise SystemExit(f"{name}: the sweep's log lines are missing")
    last_member = max(t for t, line in stamped if MEMBER_DONE.match(line))
    merged = min(t for t, line in stamped if FINISHED.match(line))
    with h5py.File(output, "r") as f:
        summary = f["summary"]
        run = {"process": seconds, "sweep": float(f.attrs["wall_time"]),
               "merge": merged - last_member,
               "members": int(f.attrs["members"]), "status": str(f.attrs["status"]),
               "id": summary["id"][()], "member_status": summary["status"][()],
               "wall": summary["wall_time"][()],
               "rank": summary["rank"][()] if "rank" in summary else None,
               "estimate": float(dealt[3]), "path": output, "log": log,
               "newton": (summary["newton_iterations"][()]
                          if "newton_iterations" in summary else None),
               "tip": summary["tip_position"][()] if "tip_position" in summary else None}
    run["member_sum"] = float(run["wall"].sum())
    if run["rank"] is not None:
        loads = np.array([run["wall"][run["rank"] == r].sum() for r in range(ranks)])
        run["loads"] = loads
        run["counts"] = [int(np.count_nonzero(run["rank"] == r)) for r in range(ranks)]
        run["balance"] = float(loads.max() / loads.mean())
    return run


def member_datasets(path, only_position):
    """{(member id, path below /members/<id>): array} of a sweep's result file: every rod's
    position, or every dataset under the members' /rods and /series."""
    found = {}
    with h5py.File(path, "r") as f:
        for member, group in f["members"].items():
            names = []
            for part in ("rods",) if only_position else ("rods", "series"):
                if part in group:
                    group[part].visit(lambda name, part=part: names.append(part + "/" + name))
            for name in names:
                item = group[name]
                if isinstance(item, h5py.Dataset) and (
                        not only_position or name.endswith("/position")):
                    found[(int(member), name)] = item[()]
    return found


def compare_members(path_a, path_b, only_position=True):
    """(members compared, members whose datasets are all bitwise identical, the differing
    (member, dataset) keys, datasets compared)."""
    a, b = member_datasets(path_a, only_position), member_datasets(path_b, only_position)
    differing = sorted(key for key in set(a) | set(b)
                       if key not in a or key not in b or a[key].shape != b[key].shape
                       or a[key].dtype != b[key].dtype or a[key].tobytes() != b[key].tobytes())
    members = {key[0] for key in set(a) | set(b)}
    identical = members - {key[0] for key in differing}
    return len(members), len(identical), differing, len(set(a) | set(b))


def start_up(args, ranks):
    """Wall time of `mpirun -np ranks rodsolve --version`: MPI launch and PETSc start-up."""
    started = time.perf_counter()
    subprocess.run([args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve,
                    "--version"], capture_output=True, env=dict(os.environ, **ENVIRONMENT),
                   check=True)
    return time.perf_counter() - started


def median(runs, key):
    return statistics.median(r[key] for r in runs)


def rank_section(args):
    """The 64-member sweep on 1 and 2 ranks: the block's text and the failed checks."""
    text = rs.read_example(args.source, SCENE)
    load_before = os.getloadavg()[0]
    runs = {n: [] for n in RANKS}
    startup = {n: [] for n in RANKS}
    for k in range(args.repeat):
        for n in RANKS:
            startup[n].append(start_up(args, n))
            r = run_sweep(args, text, n, f"sweep_np{n}_{k}")
            runs[n].append(r)
            print(f"run {k + 1}, {n} rank(s): process {r['process']:.3f} s, merge "
                  f"{r['merge']:.3f} s, sweep "
                  f"{r['sweep']:.3f} s, members summed {r['member_sum']:.3f} s, estimate "
                  f"{r['estimate']:.4f}" + (f", measured balance {r['balance']:.4f}"
                                            if "balance" in r else ""), flush=True)

    failures = []
    for n in RANKS:
        for r in runs[n]:
            m = r["members"]
            if not np.array_equal(r["id"], np.arange(1, m + 1)):
                failures.append(f"{r['path']}: /summary/id is not 1 .. {m} in order")
            unfinished = int(np.count_nonzero(r["member_status"] != 0))
            if unfinished or r["status"] != "completed":
                failures.append(f"{r['path']}: status {r['status']!r}, {unfinished} members "
                                "not completed")
    members, identical, differing, _ = compare_members(runs[1][0]["path"], runs[2][0]["path"])
    if identical != members or members != runs[1][0]["members"]:
        failures.append(f"positions differ between 1 and 2 ranks: {differing[:10]}")
    print(f"bitwise identical positions on 1 and 2 ranks: {identical} of {members} members")
    _, all_identical, all_differing, n_datasets = compare_members(
        runs[1][0]["path"], runs[2][0]["path"], only_position=False)
    print(f"every dataset under /members/<id>/rods and /series ({n_datasets}): bitwise "
          f"identical for {all_identical} of {members} members; differing: {all_differing[:10]}")

    t1 = {key: median(runs[1], key) for key in ("process", "sweep", "member_sum")}
    lines = ["| ranks | process wall time (s) | sweep wall time (s) | members' wall time summed "
             "(s) | speedup (process) | parallel efficiency (process) | speedup (sweep) | "
             "parallel efficiency (sweep) |", "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n in RANKS:
        t = {key: median(runs[n], key) for key in ("process", "sweep", "member_sum")}
        sp, ss = t1["process"] / t["process"], t1["sweep"] / t["sweep"]
        lines.append(f"| {n} | {t['process']:.2f} | {t['sweep']:.2f} | {t['member_sum']:.2f} | "
                     f"{sp:.2f} | {100 * sp / n:.0f} % | {ss:.2f} | {100 * ss / n:.0f} % |")
    scaling = "\n".join(lines)

    two = runs[2]
    if two[0].get("rank") is not None:
        lines = ["| run | members per rank | members' wall time per rank (s) | estimated slowest "
                 "rank / mean (log) | measured slowest rank / mean |", "|---:|---|---|---:|---:|"]
        for k, r in enumerate(two):
            lines.append(f"| {k + 1} | {' / '.join(str(c) for c in r['counts'])} | "
                         f"{' / '.join(f'{x:.2f}' for x in r['loads'])} | {r['estimate']:.4f} | "
                         f"{r['balance']:.4f} |")
        balance = "\n".join(lines)
        balance_median = median(two, "balance")
    else:
        balance = ("The file does not say which rank ran which member (no /summary/rank): only "
                   f"the log's estimate is known, slowest rank / mean = {two[0]['estimate']:.4f}.")
        balance_median = float("nan")
    slowdown = median(two, "member_sum") / t1["member_sum"]
    launch = {n: statistics.median(startup[n]) for n in RANKS}
    rest = {n: median(runs[n], "process") - median(runs[n], "sweep") - launch[n] for n in RANKS}
    block = (
        f"{measured_on()}; load average {load_before:.2f} before the runs; input/{SCENE} "
        f"({runs[1][0]['members']} members); `mpirun --oversubscribe -np N`, one BLAS thread; "
        f"medians of {args.repeat} runs per rank count, 1 and 2 ranks alternating. Process wall "
        "time: the whole `mpirun` (MPI launch, PETSc start-up, reading and checking the scene "
        "and its members, the sweep, the merge into one file); sweep wall time: the file's root "
        "attribute `wall_time` (dealing and the members, up to the merge); members' wall time "
        "summed: /summary/wall_time added up.\n\n" + scaling + "\n\n"
        f"On 2 ranks the members took {slowdown:.3f} times their 1-rank wall time (summed, "
        "2 ranks over 1 rank). Outside the sweep's own wall time the process spends "
        f"{launch[1]:.2f} s (1 rank) and {launch[2]:.2f} s (2 ranks) on MPI launch and PETSc "
        "start-up (`mpirun -np N rodsolve --version`, median) and "
        f"{rest[1]:.2f} s and {rest[2]:.2f} s on the rest (reading and checking the members, "
        "the merge on rank 0, exit); the merge alone, from rank 0's last member line to its "
        f"final line, took {median(runs[1], 'merge'):.2f} s on 1 rank.\n\n"
        "Load balance on 2 ranks (the members dealt by estimated cost, nodes x time steps, the "
        "largest first to the least loaded rank; measured from /summary/wall_time and "
        f"/summary/rank), per run; median measured slowest rank / mean {balance_median:.4f}:"
        "\n\n" + balance + "\n\n"
        f"Rank independence: /members/<id>/rods/<rod>/position bitwise identical on 1 and 2 "
        f"ranks for {identical} of {members} members; every dataset under /members/<id>/rods "
        f"and /series ({n_datasets} datasets) for {all_identical} of {members}.\n")
    return block, failures


def small_scene(args, mode, package):
    """The catalog's cantilever sweep with --small-members members over EI1 and --small-steps
    steps to t_end = 1, statics or dynamics, its first and last records, LU `package` (the
    baseline: the executable's own default, no option)."""
    text = rs.read_example(args.source, SCENE)
    text = rs.set_variable(text, "time", "dt", repr(1.0 / args.small_steps))
    text = rs.set_variable(text, "time", "quasistatic", MODES[mode])
    text = rs.set_variable(text, "output", "stride", str(args.small_steps))
    if package != BASELINE:
        text = rs.set_variable(text, "solver", "petsc_options",
                               f"'-pc_factor_mat_solver_type {package}'")
    return rs.set_variable(text, "sweep", "logspace", f"1.0, 100.0, {args.small_members}")


def package_section(args):
    """Many small rods per LU package, taking turns: the block's text and the failed checks."""
    load_before = os.getloadavg()[0]
    ranks = args.small_ranks
    packages = PACKAGES + ((BASELINE,) if args.baseline_rodsolve else ())
    runs = {(m, p): [] for m in MODES for p in packages}
    for k in range(args.small_repeat):
        for mode in MODES:
            for package in packages:
                scene, name = small_scene(args, mode, package), f"small_{mode}_{package}_{k}"
                binary = args.baseline_rodsolve if package == BASELINE else args.rodsolve
                try:
                    r = run_sweep(args, scene, ranks, name, binary)
                except SystemExit as failure:
                    # Once more: on a shared machine the executable may have been relinked
                    # under the run.
                    print(f"{failure}; running it again", flush=True)
                    time.sleep(10)
                    r = run_sweep(args, scene, ranks, name, binary)
                r["fallbacks"] = len(FALLBACK.findall(r["log"]))
                r["log"] = None
                runs[(mode, package)].append(r)
                print(f"run {k + 1}, {mode}, {package}: process {r['process']:.2f} s, sweep "
                      f"{r['sweep']:.2f} s, members summed {r['member_sum']:.2f} s, Newton "
                      f"iterations {int(r['newton'].sum()) if r['newton'] is not None else '?'}, "
                      f"members with a rodchain fallback {r['fallbacks']}", flush=True)

    failures = []
    for (mode, package), group in runs.items():
        for r in group:
            unfinished = int(np.count_nonzero(r["member_status"] != 0))
            if unfinished or r["status"] != "completed" or r["members"] != args.small_members:
                failures.append(f"{r['path']}: status {r['status']!r}, {r['members']} members, "
                                f"{unfinished} not completed")
    member_steps = args.small_members * args.small_steps
    keys = ("process", "sweep", "member_sum")
    rate = {case: {key: member_steps / (median(group, key) * ranks) for key in keys}
            for case, group in runs.items()}
    lines = ["| scene | LU package | process wall time (s) | sweep wall time (s) | members' wall "
             "time summed (s) | member-steps per second per core (process) | (sweep) | "
             "(members) | Newton iterations, all members | members with rodchain's MUMPS "
             "message |", "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for (mode, package), group in runs.items():
        first = group[0]
        newton = int(first["newton"].sum()) if first["newton"] is not None else "-"
        lines.append(f"| {mode} | {package} | {median(group, 'process'):.2f} | "
                     f"{median(group, 'sweep'):.2f} | {median(group, 'member_sum'):.2f} | "
                     + " | ".join(f"{rate[(mode, package)][key]:.0f}" for key in keys)
                     + f" | {newton} | {max(r['fallbacks'] for r in group)} |")
    table = "\n".join(lines)
    new = PACKAGES[0]
    lines = ["| scene | against | member-steps per second, ratio (process) | (sweep) | (members) "
             f"| largest tip-position difference, {new} against it (m) |",
             "|---|---|---:|---:|---:|---:|"]
    for mode in MODES:
        for old in packages[1:]:
            a, b = runs[(mode, new)][0], runs[(mode, old)][0]
            tip = (f"{float(np.nanmax(np.abs(a['tip'] - b['tip']))):.2g}"
                   if a["tip"] is not None and b["tip"] is not None else "-")
            lines.append(f"| {mode} | {new} / {old} | " + " | ".join(
                f"{rate[(mode, new)][key] / rate[(mode, old)][key]:.2f}" for key in keys)
                + f" | {tip} |")
    ratios = "\n".join(lines)
    baseline = ""
    if args.baseline_rodsolve:
        baseline = (f"`{BASELINE}` is another executable, {args.baseline_label}, with its own "
                    "default LU (no `-pc_factor_mat_solver_type`), in the same run. ")
    block = (
        f"Many small rods, per LU package: input/{SCENE} with {args.small_members} members "
        f"(EI1 logspace 1 to 100), 4 elements of degree 2, {args.small_steps} steps to t = 1 "
        "(dt = 1 / steps), statics as in the catalog (&time quasistatic) and dynamics "
        "(quasistatic = .false., the same load ramp), each member writing its first and last "
        f"record only (output stride {args.small_steps}); `mpirun --oversubscribe -np {ranks}`, "
        "one BLAS thread; LU package by `-pc_factor_mat_solver_type`: `rodchain` (the chain LU, "
        "the default for a single rod) and `mumps` (rodsolve's MUMPS defaults, the path before "
        f"it). {baseline}Medians of {args.small_repeat} runs, the scenes and packages taking turns within "
        f"each repetition; load average {load_before:.2f} before these runs, "
        f"{os.getloadavg()[0]:.2f} after. Member-steps per second per core: members x steps / "
        f"(wall time x {ranks} rank(s)), for the process, the sweep's own and the members' "
        "summed wall times; the message column counts the members whose rod printed rodchain's "
        "\"MUMPS factors such Jacobians\" (its fallback, said once per rod).\n\n"
        + table + "\n\n" + ratios + "\n")
    return block, failures


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--repeat", type=int, default=5, help="runs per rank count (median)")
    parser.add_argument("--small-members", type=int, default=1000,
                        help="members of the many-small-rods sweep")
    parser.add_argument("--small-steps", type=int, default=100,
                        help="steps of each small member")
    parser.add_argument("--small-repeat", type=int, default=3,
                        help="runs per scene and LU package of the small rods (median)")
    parser.add_argument("--small-ranks", type=int, default=1,
                        help="ranks of the small-rod sweeps")
    parser.add_argument("--baseline-rodsolve",
                        help="also run the small rods with this executable (an older build)")
    parser.add_argument("--baseline-label", default="an older build",
                        help="what the baseline executable is, for the text")
    parser.add_argument("--only", choices=("ranks", "packages"),
                        help="run one part only (not with --write)")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    if args.write and args.only:
        parser.error("--write replaces the whole block: run both parts")
    os.makedirs(args.workdir, exist_ok=True)

    blocks, failures = [], []
    for name, section in (("ranks", rank_section), ("packages", package_section)):
        if args.only in (None, name):
            block, failed = section(args)
            blocks.append(block)
            failures += failed
    block = "\n".join(blocks)
    print(block)
    if args.write:
        write_generated(args.source, "sweep_bench.py", block)
    for message in failures:
        print("FAILED: " + message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
