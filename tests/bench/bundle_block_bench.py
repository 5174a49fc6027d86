"""Benchmark: the block-Jacobi solver of coupled strands against the direct LU (issue 23).

Dynamic strands of ph_director wires (scripts/make_strand.py --core-radius auto: every wire
touches its neighbours from the first step; dt = 1e-5 s, the top plate's pull ramped over
2e-4 s, contact penalty 1e15 N/m^3, newton_atol 1e-10, 16 elements per wire and lay length of
the first layer), as tests/bench/bundle_bench.py runs them:

- 7, 19, 37, 61 and 91 wires at one lay length of the first layer;
- 19 wires at 1, 2, 4 and 8 lay lengths (the elements grow with the length);

each with the default linear solver (GMRES with block Jacobi over the rods, every rod's block
factored by sequential MUMPS; src/solver/rod_stepper.c) on 1 and 2 ranks, and the direct
LU of the whole system (MUMPS, the path before issue 23: -ksp_type preonly -pc_type lu
-pc_factor_mat_solver_type mumps) on 1 rank where it fits in the budget (DIRECT_UP_TO
unknowns). Per case, from rodsolve's summary lines and -ksp_converged_reason: time per Newton
iteration (median of --repeat runs), Newton iterations per step, Krylov iterations per Newton
iteration, the shares of assembly, contact search and linear solves (and the rest); the time
per Newton iteration divided by the wires (or the lay lengths) shows how linear the cost is.
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
# The direct LU's flops grow as unknowns^2.5 (docs/performance.md, "Bundles"): above this it
# takes minutes per case and is left out (the tables say so).
DIRECT_UP_TO = 50000
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
    command = [args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve, path,
               "-ksp_converged_reason", *extra]
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
    return dict(per_newton=loop / newton, newton_per_step=newton / steps,
                krylov=statistics.mean(krylov) if krylov and extra != DIRECT else None,
                assembly=float(shares.group(1)) / loop, search=float(shares.group(2)) / loop,
                linear=float(shares.group(4)) / loop, unknowns=int(UNKNOWNS.search(log).group(1)),
                positions=positions)


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
        rows.append((WIRES[layers], lengths, one, two, direct))
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
    lines = [measured_on() + "; dynamic strands, " + str(STEPS) + " steps of dt = 1e-5 s; "
             "block Jacobi (GMRES, an LU per rod) on 1 and 2 ranks, the direct LU "
             "(MUMPS) on 1 rank; medians.", "",
             "| wires | lay lengths | unknowns | s per Newton it., block 1 rank | per wire and "
             "lay length (ms) | Krylov its. per Newton it. | assembly / contact search / "
             "linear (share) | s per Newton it., 2 ranks | speedup on 2 ranks | s per Newton "
             "it., direct LU | block against direct | Newton its. per step (block, direct) |",
             "|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|"]
    for wires, lengths, one, two, direct in rows:
        ok = "failed" not in one
        per_unit = f"{1e3 * one['per_newton'] / (wires * lengths):.2f}" if ok else "-"
        speedup = (f"{one['per_newton'] / two['per_newton']:.2f}"
                   if ok and "failed" not in two else "-")
        against = (f"{direct['per_newton'] / one['per_newton']:.1f} times faster"
                   if ok and direct and "failed" not in direct else "-")
        shares = (f"{one['assembly']:.2f} / {one['search']:.3f} / {one['linear']:.2f}"
                  if ok else "-")
        iterations = (f"{one['newton_per_step']:.1f}, "
                      f"{direct['newton_per_step']:.1f}" if ok and direct and "failed" not in direct
                      else (f"{one['newton_per_step']:.1f}, -" if ok else "-"))
        lines.append(f"| {wires} | {lengths} | {one.get('unknowns', '-')} | "
                     f"{number(one, 'per_newton', '{:.4f}')} | {per_unit} | "
                     f"{number(one, 'krylov', '{:.1f}')} | {shares} | "
                     f"{number(two, 'per_newton', '{:.4f}')} | {speedup} | "
                     f"{number(direct, 'per_newton', '{:.4f}')} | {against} | {iterations} |")
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
