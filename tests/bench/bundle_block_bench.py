"""Benchmark: the block-Jacobi solver of coupled strands against the direct LU (issue 23).

Dynamic strands of ph_director wires (scripts/make_strand.py --core-radius auto: every wire
touches its neighbours from the first step; dt = 1e-5 s, the top plate's pull ramped over
2e-4 s, contact penalty 1e15 N/m^3, newton_atol 1e-10, 16 elements per wire and lay length of
the first layer), as tests/bench/bundle_bench.py runs them:

- 7, 19, 37, 61 and 91 wires at one lay length of the first layer;
- 19 wires at 1, 2, 4 and 8 lay lengths (the elements grow with the length);

each with the default linear solver (GMRES preconditioned on the right by block Jacobi over
the rods, every rod's block factored by the chain LU; src/solver/rod_stepper.c) on 1 and 2
ranks; on 1 rank also the first block Jacobi (every block factored by sequential MUMPS,
preconditioned on the left: commit 95c9f1a's default) and the direct LU of the whole system
(MUMPS, the path before issue 23: -ksp_type preonly -pc_type lu -pc_factor_mat_solver_type
mumps) where it fits in the budget (DIRECT_UP_TO unknowns). Per case, from rodsolve's
summary lines, -ksp_converged_reason and PETSc's -log_view: time per Newton iteration (median
of --repeat runs), Newton iterations per step, Krylov iterations per Newton iteration, the
shares of the time loop taken by assembly, contact search, the factorizations of the blocks
(PCSetUp), the Krylov iterations (KSPSolve: block solves, products, orthogonalization) and
the vector exchanges between the ranks (VecScatterBegin/End, waiting included: the gathers of
the state for the assembly and the ghost values of the products); on 2 ranks
the messages, bytes and global reductions per Krylov iteration (the communication volume the
scaling model of docs/performance.md starts from); the time per Newton iteration divided by
the wires (or the lay lengths) shows how linear the cost is.
Every default run's final positions are compared with the direct LU's where that ran, and
with the 1-rank run on 2 ranks: the bench fails (exit status 1) above --tolerance.

    /usr/bin/python3 tests/bench/bundle_block_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench_block [--repeat 3] [--write]
"""
import os
import re
import statistics
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import SUMMARY, measured_on, write_generated  # noqa: E402

DT = 1e-5
RAMP = 2e-4
WIRES = {1: 7, 2: 19, 3: 37, 4: 61, 5: 91}
STEPS = 2
PITCH = 0.060424804560181566    # lay length of the first layer (make_strand --core-radius auto)
DIRECT = ("-ksp_type", "preonly", "-pc_type", "lu", "-pc_factor_mat_solver_type", "mumps")
FIRST_BLOCK = ("-ksp_pc_side", "left", "-sub_pc_factor_mat_solver_type", "mumps")
# The direct LU's flops grow as unknowns^2.5 (docs/performance.md, "Bundles"): above this it
# takes minutes per case and is left out (the tables say so).
DIRECT_UP_TO = 90000
# -log_view's event lines: name, count, its ratio, time (max over ranks), ratio, flop, ratio,
# messages, average message length (bytes), reductions, ...
EVENT = re.compile(r"^(\w+)\s+(\d+) +\S+ +(\S+) +\S+ +\S+ +\S+ +(\S+) +(\S+) +(\S+) ", re.M)
SHARES = re.compile(r"of that, assembly (\S+) s, contact search (\S+) s \((\d+) new Jacobian "
                    r"patterns\), linear solves and the rest (\S+) s")
UNKNOWNS = re.compile(r"(\d+) Newton unknowns")
KRYLOV = re.compile(r"Linear solve converged due to \S+ iterations (\d+)")


def make_scene(args, layers, lengths):
    path = os.path.join(args.workdir, f"strand{WIRES[layers]}_x{lengths}.nml")
    command = [sys.executable, os.path.join(args.source, "scripts", "make_strand.py"), path,
               "--layers", str(layers), "--core-radius", "auto", "--dt", repr(DT),
               "--t-end", repr(STEPS * DT), "--t-off", repr(RAMP), "--stride", str(STEPS),
               "--length", repr(lengths * PITCH), "--elements-per-pitch", "16",
               "--output", "placeholder.h5"]
    subprocess.run(command, check=True, capture_output=True, text=True)
    return path


def run(args, scene, ranks, extra, name):
    output = os.path.join(args.workdir, name + ".h5")
    with open(scene, encoding="utf-8") as f:
        text = f.read()
    text = re.sub(r"path = '[^']*'", f"path = '{output}'", text)
    path = os.path.join(args.workdir, name + ".nml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    log_view = os.path.join(args.workdir, name + ".log")
    command = [args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve, path,
               "-ksp_converged_reason", "-log_view", ":" + log_view, *extra]
    result = subprocess.run(command, capture_output=True, text=True)
    log = result.stdout + result.stderr
    summary = SUMMARY.search(log)
    if result.returncode != 0 or summary is None:
        return dict(failed=log[-600:])
    steps, newton = int(summary.group(1)), int(summary.group(2))
    loop = float(summary.group(4))
    shares = SHARES.search(log)
    krylov = [int(k) for k in KRYLOV.findall(log)]
    with h5py.File(output, "r") as f:
        positions = {name: f[f"rods/{name}/position"][-1] for name in f["rods"]}
    events = read_events(log_view)
    iterations = sum(krylov) if krylov and extra != DIRECT else None
    scatter = events.get("VecScatterBegin", {}).get("time", 0.0) + \
        events.get("VecScatterEnd", {}).get("time", 0.0)
    product = events.get("MatMult", {})
    reductions = sum(events.get(e, {}).get("reductions", 0.0)
                     for e in ("VecMDot", "VecNorm", "VecDot"))
    factorization = events["PCSetUp"]["time"] if extra != DIRECT else \
        events.get("MatLUFactorSym", {}).get("time", 0.0) + \
        events.get("MatLUFactorNum", {}).get("time", 0.0)
    return dict(per_newton=loop / newton, newton_per_step=newton / steps,
                krylov=iterations / newton if iterations else None,
                assembly=float(shares.group(1)) / loop, search=float(shares.group(2)) / loop,
                linear=float(shares.group(4)) / loop, unknowns=int(UNKNOWNS.search(log).group(1)),
                factorization=factorization / loop,
                krylov_share=events["KSPSolve"]["time"] / loop if extra != DIRECT else None,
                exchange=scatter / loop,
                messages=product.get("messages", 0.0) / iterations if iterations else None,
                bytes=(product.get("messages", 0.0) * product.get("length", 0.0) / iterations
                       if iterations else None),
                reductions=reductions / iterations if iterations else None,
                positions=positions)


def read_events(path):
    """-log_view's events: time (max over ranks, s), messages (all ranks), average length
    (bytes), reductions."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    return {m.group(1): dict(count=int(m.group(2)), time=float(m.group(3)),
                             messages=float(m.group(4)), length=float(m.group(5)),
                             reductions=float(m.group(6)))
            for m in EVENT.finditer(text)}


def median(args, scene, ranks, extra, name, repeat):
    runs = [run(args, scene, ranks, extra, f"{name}_{k}") for k in range(repeat)]
    good = [r for r in runs if "failed" not in r]
    if not good:
        return runs[0]
    best = dict(good[0])
    best["per_newton"] = statistics.median(r["per_newton"] for r in good)
    return best


def difference(a, b):
    scale = max(np.max(np.abs(p)) for p in a["positions"].values())
    return max(np.max(np.abs(a["positions"][n] - b["positions"][n])) for n in a["positions"]) / scale


def main():
    parser = argparse_parser()
    args = parser.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    rows, bad = [], []
    cases = [(layers, 1) for layers in args.layers] + [(2, k) for k in args.lengths if k != 1]
    for layers, lengths in cases:
        scene = make_scene(args, layers, lengths)
        label = f"{WIRES[layers]} wires, {lengths} lay length{'s' if lengths > 1 else ''}"
        one = median(args, scene, 1, (), f"w{WIRES[layers]}_x{lengths}_r1", args.repeat)
        two = median(args, scene, 2, (), f"w{WIRES[layers]}_x{lengths}_r2", args.repeat)
        first = run(args, scene, 1, FIRST_BLOCK, f"w{WIRES[layers]}_x{lengths}_first")
        direct = None
        if "failed" not in one and one["unknowns"] <= DIRECT_UP_TO:
            direct = run(args, scene, 1, DIRECT, f"w{WIRES[layers]}_x{lengths}_direct")
        for what, case in (("block Jacobi, 1 rank", one), ("block Jacobi, 2 ranks", two)):
            if "failed" in case:
                bad.append(f"{label}, {what}: failed: {case['failed']}")
        if "failed" not in one and "failed" not in two and difference(one, two) > args.tolerance:
            bad.append(f"{label}: 1 and 2 ranks differ by {difference(one, two):.2e}")
        if direct and "failed" not in direct and "failed" not in one and \
                difference(one, direct) > args.tolerance:
            bad.append(f"{label}: block Jacobi and the direct LU differ by "
                       f"{difference(one, direct):.2e}")
        if "failed" not in one and "failed" not in first and \
                difference(one, first) > args.tolerance:
            bad.append(f"{label}: the chain LU's and MUMPS's blocks differ by "
                       f"{difference(one, first):.2e}")
        rows.append((WIRES[layers], lengths, one, two, first, direct))
        print(f"{label}: done", flush=True)
    block = table(rows)
    print(block)
    if args.write:
        write_generated(args.source, "bundle_block_bench.py", block)
    for line in bad:
        print("FAIL " + line)
    sys.exit(1 if bad else 0)


def table(rows):
    def number(case, key, form):
        if case is None:
            return "not run"
        if "failed" in case:
            return "failed"
        return form.format(case[key]) if case[key] is not None else "-"

    def ratio(slow, fast):
        if not slow or not fast or "failed" in slow or "failed" in fast:
            return "-"
        return f"{slow['per_newton'] / fast['per_newton']:.2f}"

    lines = [measured_on() + "; dynamic strands, " + str(STEPS) + " steps of dt = 1e-5 s; "
             "block Jacobi (right-preconditioned GMRES, the chain LU per rod) on 1 and 2 ranks; "
             "on 1 rank also the first block Jacobi (MUMPS per rod, left-preconditioned, commit "
             "95c9f1a) and the direct LU (MUMPS); medians of the default's runs, one run of the "
             "others; shares of the time loop from -log_view (rank 0's time loop, events' "
             "largest time over the ranks).", "",
             "| wires | lay lengths | unknowns | s per Newton it., 1 rank | per wire and lay "
             "length (ms) | Krylov its. per Newton it. | assembly / contact search / "
             "factorization / Krylov, 1 rank | s per Newton it., 2 ranks "
             "| speedup on 2 ranks | first block Jacobi: s per Newton it., Krylov its. | now "
             "against first | direct LU: s per Newton it. | now against direct | Newton its. per "
             "step (now, first, direct) |",
             "|---:|---:|---:|---:|---:|---:|---|---:|---:|---|---:|---:|---:|---|"]
    for wires, lengths, one, two, first, direct in rows:
        ok = "failed" not in one
        per_unit = f"{1e3 * one['per_newton'] / (wires * lengths):.2f}" if ok else "-"
        shares = (f"{one['assembly']:.2f} / {one['search']:.3f} / {one['factorization']:.2f} / "
                  f"{one['krylov_share']:.2f}" if ok else "-")
        newton = ", ".join(f"{c['newton_per_step']:.1f}" if c and "failed" not in c else "-"
                           for c in (one, first, direct))
        lines.append(f"| {wires} | {lengths} | {one.get('unknowns', '-')} | "
                     f"{number(one, 'per_newton', '{:.4f}')} | {per_unit} | "
                     f"{number(one, 'krylov', '{:.1f}')} | {shares} | "
                     f"{number(two, 'per_newton', '{:.4f}')} | {ratio(one, two)} | "
                     f"{number(first, 'per_newton', '{:.4f}')}, "
                     f"{number(first, 'krylov', '{:.1f}')} | "
                     f"{ratio(first, one)} | {number(direct, 'per_newton', '{:.4f}')} | "
                     f"{ratio(direct, one)} | {newton} |")
    lines += ["", "2 ranks, the default: shares of rank 0's time loop (the vector exchanges: "
              "the state's gathers for the assembly and the products' ghost values, waiting "
              "for the other rank included) and what one Krylov iteration sends (the product's "
              "ghost values, both ranks together; the global reductions of GMRES's "
              "orthogonalization and norms):", "",
              "| wires | lay lengths | assembly / factorization / Krylov / vector exchanges | "
              "messages per Krylov it. | bytes per Krylov it. | reductions per Krylov it. |",
              "|---:|---:|---|---:|---:|---:|"]
    for wires, lengths, one, two, first, direct in rows:
        if "failed" in two:
            lines.append(f"| {wires} | {lengths} | failed | | | |")
            continue
        lines.append(f"| {wires} | {lengths} | {two['assembly']:.2f} / "
                     f"{two['factorization']:.2f} / "
                     f"{two['krylov_share']:.2f} / {two['exchange']:.3f} | "
                     f"{number(two, 'messages', '{:.1f}')} | {number(two, 'bytes', '{:.0f}')} | "
                     f"{number(two, 'reductions', '{:.1f}')} |")
    return "\n".join(lines) + "\n"


def argparse_parser():
    import argparse
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rodsolve", required=True)
    parser.add_argument("--mpiexec", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--workdir", required=True)
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (median)")
    parser.add_argument("--layers", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    parser.add_argument("--lengths", type=int, nargs="+", default=[1, 2, 4, 8])
    parser.add_argument("--tolerance", type=float, default=1e-10,
                        help="largest relative position difference allowed")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    return parser


if __name__ == "__main__":
    main()
