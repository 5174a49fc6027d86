"""Benchmark: cable bundles on 1 and 2 ranks (issue 10; DESIGN.md §5, §9).

Strands of 7, 19 and 37 ph_director wires (scripts/make_strand.py --layers 1, 2, 3,
--core-radius auto: the helical wires lie on the core and on each other, so contact is active
from the first step), run dynamically: dt = 1e-5 s, the top plate pulled along the axis by
1e-3 L, ramped over 2e-4 s, contact penalty 1e15 N/m^3, Newton tolerance 1e-10; 10, 3 and 2
steps of the ramp (STEPS: the whole benchmark takes about 15 minutes on the 2-core machines).
From rodsolve's own summary lines (time loop only, output excluded) it reports per case

- time per step, Newton iterations per step and time per Newton iteration,
- the shares of the time loop: assembly, contact search, linear solves and the rest (on 2
  ranks these are rank 0's timers: the summary line is printed by rank 0),
- the speedup on 2 ranks (the 1-rank median time per step over the 2-rank one),
- what MUMPS did, from `-ksp_view` after the last factorization: the ordering it used
  (INFOG(7)), its flops (RINFOG(3)) and factor entries (INFOG(29)), delayed pivots
  (INFOG(13)) and whether it permuted large entries onto the diagonal (INFOG(23) =
  ICNTL(6)): counts that do not depend on the load of the machine,
- the partition METIS made on 2 ranks (rod unknowns per rank),

and, in a table per strand, LU settings on 1 and 2 ranks: the MUMPS ordering, threshold
pivoting, ScaLAPACK at the root, work space, parallel analysis, and SuperLU_DIST (SETTINGS).
Every case runs `--repeat` times (the 37-wire strand `--repeat-37` times), all cases of a
round alternating, and the tables show medians (a case that fails is run once). Each case's final positions are compared with the 1-rank default run of
the same scene; the run fails (exit status 1) if a default case fails, cuts a step, or the 1-
and 2-rank default runs differ by more than --tolerance in any position.

With --write the tables replace the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/bundle_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench_bundle [--repeat 3] [--write]
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
from bench_common import SUMMARY, rs, measured_on, write_generated  # noqa: E402

DT = 1e-5
RAMP = 2e-4
WIRES = {1: 7, 2: 19, 3: 37}
# Steps per scene of the main table: a few tens where the budget allows (the whole benchmark
# should stay near 15 minutes on the 2-core machines).
STEPS = {1: 10, 2: 3, 3: 2}
SHARES = re.compile(r"of that, assembly (\S+) s, contact search (\S+) s \((\d+) new Jacobian "
                    r"patterns\), linear solves and the rest (\S+) s")
SIZE = re.compile(r"(\d+) Newton unknowns, (\d+) Jacobian non-zeros")
PARTITION = re.compile(r"^\s+rank (\d+):.*\((\d+) rod unknowns\)", flags=re.M)
MUMPS = {"ordering": r"INFOG\(7\) \(ordering option effectively used after analysis\): (\S+)",
         "flops": r"RINFOG\(3\) \(global estimated flops for the elimination after "
                  r"factorization\): (\S+)",
         "factors": r"INFOG\(29\) \(after factorization: effective number of entries in the "
                    r"factors \(sum over all processors\)\): (\S+)",
         "delayed": r"INFOG\(13\) \(number of delayed pivots after factorization\): (\S+)",
         "icntl6": r"INFOG\(23\) \(after analysis: value of ICNTL\(6\) effectively used\): (\S+)"}
ORDERINGS = {0: "AMD", 2: "AMF", 3: "SCOTCH", 4: "PORD", 5: "METIS", 6: "QAMD"}
FAILURE = re.compile(r"(last SNES reason \w+|encounters zero diagonal|"
                     r"PETSC ERROR: [A-Z][^\n]*|only works on a square[^\n]*)")
ENVIRONMENT = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
               "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}

DIRECT_LU = ("-ksp_type", "preonly", "-pc_type", "lu", "-pc_factor_mat_solver_type", "mumps")
DEFAULT = ("default", "")
# The LU settings tried, (label, options): on 1 rank the matrix is sequential and centralized
# (MUMPS may permute large entries onto the diagonal, ICNTL(6)), on 2 ranks it is distributed.
AUTO = ("ICNTL(7) = 7 (automatic: PORD)", "-mat_mumps_icntl_7 7")
ROOT_ON = ("ICNTL(13) = 0 (ScaLAPACK at the root)", "-mat_mumps_icntl_13 0")
CNTL2 = ("CNTL(1) = 0.01 (MUMPS' pivot threshold)", "-mat_mumps_cntl_1 0.01")
CNTL3 = ("CNTL(1) = 1e-3", "-mat_mumps_cntl_1 1e-3")
OLD = ("CNTL(1) = 0.01, ICNTL(13) = 0 (MUMPS' own)", "-mat_mumps_cntl_1 0.01 -mat_mumps_icntl_13 0")
WORK = ("ICNTL(14) = 100 (work space)", "-mat_mumps_icntl_14 100")
PARALLEL = ("ICNTL(28) = 2, ICNTL(29) = 2 (parallel analysis, ParMETIS)",
            "-mat_mumps_icntl_28 2 -mat_mumps_icntl_29 2")
SUPERLU = ("SuperLU_DIST", "-pc_factor_mat_solver_type superlu_dist")
# Per strand (layers): the settings on 1 and on 2 ranks; the 7-wire strand gets the full set, the
# larger ones those that matter (the whole benchmark should stay near 15 minutes).
SETTINGS = {1: ((DEFAULT, AUTO),
                (DEFAULT, ROOT_ON, CNTL2, CNTL3, OLD, WORK, PARALLEL, SUPERLU)),
            2: ((DEFAULT, AUTO), (DEFAULT, OLD)),
            3: ((DEFAULT, AUTO), (DEFAULT, OLD))}


def make_scene(args, layers, steps):
    """The strand scene of `layers` layers and `steps` steps; its text."""
    path = os.path.join(args.workdir, f"strand{WIRES[layers]}_{steps}.nml")
    command = [sys.executable, os.path.join(args.source, "scripts", "make_strand.py"), path,
               "--layers", str(layers), "--core-radius", "auto", "--dt", repr(DT),
               "--t-end", repr(steps * DT), "--t-off", repr(RAMP), "--stride", str(steps)]
    subprocess.run(command, check=True, capture_output=True, text=True)
    with open(path, encoding="utf-8") as f:
        return f.read()


def last(pattern, text):
    found = re.findall(pattern, text)
    return found[-1] if found else None


def run_bundle(args, text, ranks, options, name):
    """Run the scene on `ranks` ranks with extra PETSc `options`; rodsolve's numbers, the
    MUMPS statistics and the final positions, or the reason it failed."""
    output = os.path.join(args.workdir, name + ".h5")
    if os.path.exists(output):
        os.remove(output)
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(rs.set_variable(text, "output", "path", f"'{output}'"))
    # The direct LU of the whole system (MUMPS), whose settings this bench compares; the
    # default solver of these dynamic strands is block Jacobi since issue 23
    # (tests/bench/bundle_block_bench.py).
    command = [args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve, scene,
               "-ksp_view", *DIRECT_LU, *options.split()]
    started = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True,
                            env=dict(os.environ, **ENVIRONMENT))
    log = result.stdout + result.stderr
    run = {"process": time.perf_counter() - started, "ok": result.returncode == 0}
    summary, shares, size = SUMMARY.search(log), SHARES.search(log), SIZE.search(log)
    if not run["ok"] or summary is None or shares is None:
        reason = FAILURE.search(log)
        run["reason"] = reason[1] if reason else f"exit status {result.returncode}"
        with open(os.path.join(args.workdir, name + ".log"), "w", encoding="utf-8") as f:
            f.write(log)
        return run
    steps, iterations = int(summary[1]), int(summary[2])
    loop = float(summary[4])
    run.update({"steps": steps, "iterations": iterations, "cutbacks": int(summary[3]),
                "loop": loop, "per_step": loop / steps, "per_iteration": loop / iterations,
                "assembly": float(shares[1]) / loop, "search": float(shares[2]) / loop,
                "patterns": int(shares[3]), "solve": float(shares[4]) / loop,
                "unknowns": int(size[1]), "nonzeros": int(size[2]),
                "partition": [int(n) for _, n in PARTITION.findall(log)]})
    for key, pattern in MUMPS.items():
        value = last(pattern, log)
        run[key] = float(value) if value is not None else None
    with h5py.File(output, "r") as f:
        run["positions"] = {rod: f["rods"][rod]["position"][-1] for rod in f["rods"]}
    return run


def difference(a, b):
    """Largest distance between the final positions of two runs (m)."""
    return max(float(np.max(np.abs(a["positions"][rod] - b["positions"][rod])))
               for rod in a["positions"])


def measure(args, cases):
    """Every case its number of times (`args.repeat`, the 37-wire strand `args.repeat_37`),
    each round every case once, so that drifts of the shared machine hit all alike; a case
    that fails is run once."""
    runs = {key: [] for key in cases}
    for round_ in range(max(args.repeat, args.repeat_37)):
        for key, (text, ranks, options) in cases.items():
            wanted = args.repeat_37 if key[0] == WIRES[3] else args.repeat
            if len(runs[key]) >= wanted or (runs[key] and not runs[key][0]["ok"]):
                continue
            name = f"strand{key[0]}_np{ranks}_" + re.sub(r"\W+", "_", key[2]).strip("_")
            r = run_bundle(args, text, ranks, options, name)
            runs[key].append(r)
            state = (f"{r['per_step']:.3f} s per step, {r['iterations']} Newton iterations"
                     if r["ok"] else f"failed: {r['reason']}")
            print(f"round {round_ + 1}: {key[0]} wires, {ranks} rank(s), {key[2]}: {state}",
                  flush=True)
    return runs


def median(runs, key):
    return statistics.median(r[key] for r in runs)


def summary(runs):
    """Medians of the times of `runs`; the counts and statistics of the first."""
    best = dict(runs[0])
    best["runs"] = len(runs)
    if best["ok"]:
        for key in ("per_step", "per_iteration", "assembly", "search", "solve", "process"):
            best[key] = median(runs, key)
    return best


def mumps_cells(r):
    """Ordering | flops | factor entries | delayed pivots | ICNTL(6) of a run."""
    if r.get("flops") is None:
        return "- | - | - | - | -"
    ordering = ORDERINGS.get(int(r["ordering"]), str(int(r["ordering"])))
    return (f"{ordering} | {r['flops']:.3g} | {r['factors'] / 1e6:.2f} | {int(r['delayed'])} | "
            f"{int(r['icntl6'])}")


def main_table(results, layers_list):
    lines = ["| wires | unknowns | Jacobian non-zeros | ranks | steps | Newton iterations per "
             "step | s per step | s per Newton iteration | assembly | contact search | linear "
             "solves and rest | speedup on 2 ranks | runs | MUMPS ordering | flops per "
             "factorization | factor entries (millions) | delayed pivots | ICNTL(6) used | rod "
             "unknowns per rank |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|"
             "---:|---:|---|"]
    for layers in layers_list:
        wires = WIRES[layers]
        one = results[(wires, 1, DEFAULT[0])]
        for ranks in (1, 2):
            r = results[(wires, ranks, DEFAULT[0])]
            if not r["ok"]:
                lines.append(f"| {wires} | | | {ranks} | failed: {r['reason']} |")
                continue
            speedup = (f"{one['per_step'] / r['per_step']:.2f}" if ranks == 2 and one["ok"]
                       else "")
            lines.append(
                f"| {wires} | {r['unknowns']} | {r['nonzeros']} | {ranks} | {r['steps']} | "
                f"{r['iterations'] / r['steps']:.2f} | {r['per_step']:.3g} | "
                f"{r['per_iteration']:.3g} | {100 * r['assembly']:.1f} % | "
                f"{100 * r['search']:.2f} % | {100 * r['solve']:.1f} % | {speedup} | "
                f"{r['runs']} | {mumps_cells(r)} | "
                f"{' / '.join(str(n) for n in r['partition'])} |")
    return "\n".join(lines)


def study_table(results, layers):
    wires = WIRES[layers]
    reference = results[(wires, 1, DEFAULT[0])]
    lines = ["| ranks | setting | s per Newton iteration | relative to the 1-rank default | "
             "Newton iterations | runs | MUMPS ordering | flops per factorization | factor "
             "entries (millions) | delayed pivots | ICNTL(6) used | largest position "
             "difference to the 1-rank default (m) |",
             "|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|"]
    for ranks, settings in zip((1, 2), SETTINGS[layers]):
        for label, _ in settings:
            r = results[(wires, ranks, label)]
            if not r["ok"]:
                lines.append(f"| {ranks} | {label} | fails: {r['reason']} | | | | | | | | | |")
                continue
            relative = (f"{r['per_iteration'] / reference['per_iteration']:.2f}"
                        if reference["ok"] else "-")
            distance = f"{difference(r, reference):.1e}" if reference["ok"] else "-"
            lines.append(f"| {ranks} | {label} | {r['per_iteration']:.3g} | {relative} | "
                         f"{r['iterations']} | {r['runs']} | {mumps_cells(r)} | {distance} |")
    return "\n".join(lines)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (median)")
    parser.add_argument("--repeat-37", type=int, default=1,
                        help="runs per case of the 37-wire strand (median)")
    parser.add_argument("--layers", type=int, nargs="+", default=[1, 2, 3], choices=[1, 2, 3],
                        help="strands: 1 -> 7 wires, 2 -> 19, 3 -> 37")
    parser.add_argument("--defaults-only", action="store_true",
                        help="only the default LU settings (no study)")
    parser.add_argument("--tolerance", type=float, default=1e-9,
                        help="largest position difference of the 1- and 2-rank runs (m)")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    load_before = os.getloadavg()
    started = time.perf_counter()

    cases = {}
    for layers in args.layers:
        text = make_scene(args, layers, STEPS[layers])
        for ranks, settings in zip((1, 2), SETTINGS[layers]):
            for label, options in settings[:1] if args.defaults_only else settings:
                cases[(WIRES[layers], ranks, label)] = (text, ranks, options)
    runs = measure(args, cases)
    results = {key: summary(r) for key, r in runs.items()}
    minutes = (time.perf_counter() - started) / 60
    load_after = os.getloadavg()

    failures, differences = [], []
    for layers in args.layers:
        wires = WIRES[layers]
        one, two = (results[(wires, n, DEFAULT[0])] for n in (1, 2))
        for n, r in ((1, one), (2, two)):
            if not r["ok"]:
                failures.append(f"{wires} wires, {n} rank(s): {r['reason']}")
            elif r["cutbacks"]:
                failures.append(f"{wires} wires, {n} rank(s): {r['cutbacks']} cut-backs")
        if one["ok"] and two["ok"]:
            d = difference(one, two)
            differences.append(f"{wires} wires {d:.1e} m")
            if d > args.tolerance:
                failures.append(f"{wires} wires: positions on 1 and 2 ranks differ by {d:.2e} m "
                                f"> {args.tolerance:g} m")

    block = (
        f"{measured_on()}; load average {load_before[0]:.2f} before and {load_after[0]:.2f} "
        f"after the runs ({minutes:.1f} minutes); `mpirun --oversubscribe -np N`, one BLAS "
        f"thread; medians of {args.repeat} runs per case ({args.repeat_37} for 37 wires), all "
        "cases alternating. Strands from scripts/make_strand.py --core-radius auto (16 "
        "elements per wire and pitch of layer 1, one pitch long), dynamic: dt = "
        f"{DT:g} s, the top plate pulled by 1e-3 L ramped over {RAMP:g} s, contact stiffness "
        "1e15 N/m^3, Newton tolerance 1e-10. Shares are of rodsolve's time loop (output "
        "excluded); on 2 ranks they are rank 0's. MUMPS counts are from `-ksp_view` after the "
        "last factorization of the first run.\n\n"
        + main_table(results, args.layers) + "\n\n"
        "Largest difference of the final positions on 1 and 2 ranks: "
        + (", ".join(differences) or "-") + ".\n")
    if not args.defaults_only:
        for layers in args.layers:
            block += (f"\nLU settings, {WIRES[layers]} wires, {STEPS[layers]} steps (PETSc "
                      "options on the command line; the default for bundles is MUMPS with "
                      "AMD, ICNTL(7) = 0, and ICNTL(14) = 50 on 1 rank; on 2 ranks also "
                      "ICNTL(14) = 400, CNTL(1) = 1e-4 and ICNTL(13) = 1, "
                      "src/solver/rod_stepper.c):\n\n"
                      + study_table(results, layers) + "\n")
    print(block)
    if args.write:
        write_generated(args.source, "bundle_bench.py", block)
    for message in failures:
        print("FAILED: " + message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
