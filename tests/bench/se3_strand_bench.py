"""Benchmark: se3_strand (issue 8). Seed 004's 45-degree bend at 600 N (input/bend45_strand.nml:
statics by damped dynamics, one linear solve per step) on one rank, from rodsolve's own timing:
the summary line's time loop (assembly and linear solves, output excluded) and the run line's
wall time and its split. Every case runs `--repeat` times and the tables show medians; the runs
of all cases alternate, so that the solver ratios come from the same runs (DESIGN.md §9).

1. time per step against the number of segments N, with PETSc's LU in natural ordering (the
   default), and the exponent of a least-squares fit of log(time per step) against log(N);
2. time to solution at N = 80 (Table 4 of seed 004: 0.8 s for the paper's Python + numba on a
   1.8 GHz Core i5 laptop, 4 s for Abaqus B32; methods/se3_strands.md §5);
3. the LU: PETSc's in natural (default), reverse Cuthill-McKee and nested-dissection
   ordering, and MUMPS, at three sizes.

With --write the tables replace the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/se3_strand_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench_strand [--write]
"""
import math
import os
import re
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import SUMMARY, rs, measured_on, write_generated  # noqa: E402

RUN = re.compile(r"wall time (\S+) s: assembly (\S+) s, linear solves and Newton (\S+) s, "
                 r"output (\S+) s")
SIZE = re.compile(r"(\d+) unknowns, (\d+) matrix non-zeros")
RELAXED = re.compile(r"relaxed after (\d+) steps")

SEGMENTS = (80, 160, 320, 640, 1280, 2560, 5120)
SOLVER_SEGMENTS = (80, 640, 5120)
SOLVERS = (("PETSc natural (default)", ""),
           ("PETSc RCM", "-pc_factor_mat_ordering_type rcm"),
           ("PETSc ND", "-pc_factor_mat_ordering_type nd"),
           ("MUMPS", "-pc_factor_mat_solver_type mumps"))


def scene(base, n, options):
    text = rs.set_variable(base, "rod", "n_elements", str(n))
    if options:
        text += f"\n&solver\n    petsc_options = '{options}'\n/\n"
    return text


def run_strand(args, text, name):
    """Run scene `text` as `name`.nml on one rank; return rodsolve's timings and counts and the
    wall time of the whole process (MPI launch and PETSc start-up included)."""
    os.makedirs(args.workdir, exist_ok=True)
    path = os.path.join(args.workdir, name + ".nml")
    text = rs.set_variable(text, "output", "path", f"'{path[:-4]}.h5'")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    started = time.perf_counter()
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, path],
                            capture_output=True, text=True)
    process = time.perf_counter() - started
    if result.returncode != 0:
        sys.stderr.write(result.stdout + result.stderr)
        raise SystemExit(f"{name}: rodsolve failed")
    summary, run, size = (p.search(result.stdout) for p in (SUMMARY, RUN, SIZE))
    if not RELAXED.search(result.stdout):
        sys.stderr.write(result.stdout)
        raise SystemExit(f"{name}: the bend did not relax")
    steps = int(summary[1])
    return {"steps": steps, "iterations": int(summary[2]), "cutbacks": int(summary[3]),
            "loop": float(summary[4]), "per_step": float(summary[5]), "wall": float(run[1]),
            "assembly": float(run[2]) / steps, "solve": float(run[3]) / steps,
            "output": float(run[4]), "process": process, "unknowns": int(size[1]),
            "nonzeros": int(size[2])}


def medians(runs):
    """Medians of the times of `runs`; the counts of the first (they do not change)."""
    best = dict(runs[0])
    for key in ("loop", "per_step", "wall", "assembly", "solve", "output", "process"):
        best[key] = statistics.median(r[key] for r in runs)
    return best


def measure(args):
    """All cases, `args.repeat` rounds, each round every case once."""
    base = rs.read_example(args.source, "bend45_strand.nml")
    cases = [(n, 0) for n in SEGMENTS if n <= args.largest]
    cases += [(n, k) for n in SOLVER_SEGMENTS if n <= args.largest
              for k in range(1, len(SOLVERS))]
    runs = {case: [] for case in cases}
    for round_ in range(args.repeat):
        for n, k in cases:
            r = run_strand(args, scene(base, n, SOLVERS[k][1]), f"bend45_{n}_{k}")
            runs[(n, k)].append(r)
        print(f"round {round_ + 1}/{args.repeat} done", flush=True)
    return {case: medians(r) for case, r in runs.items()}


def fit_exponent(points):
    """Slope of the least-squares line through (log N, log t)."""
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    return (sum((x - mx) * (y - my) for x, y in zip(xs, ys))
            / sum((x - mx) ** 2 for x in xs))


def scaling_table(results):
    ns = sorted(n for n, k in results if k == 0)
    first = results[(ns[0], 0)]
    lines = ["| N | unknowns | matrix non-zeros | steps to relax | ms per step | of which "
             "assembly | of which LU and rest | µs per step and segment | per step / N, "
             f"relative to N = {ns[0]} |", "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n in ns:
        r = results[(n, 0)]
        relative = (r["per_step"] / n) / (first["per_step"] / ns[0])
        lines.append(f"| {n} | {r['unknowns']} | {r['nonzeros']} | {r['steps']} | "
                     f"{r['per_step'] * 1e3:.3f} | {r['assembly'] * 1e3:.3f} | "
                     f"{r['solve'] * 1e3:.3f} | {r['per_step'] / n * 1e6:.2f} | "
                     f"{relative:.2f} |")
    points = [(n, results[(n, 0)]["per_step"]) for n in ns]
    large = [p for p in points if p[0] >= 640]
    text = ("\n".join(lines) + f"\n\nLeast-squares fit of log(time per step) against log(N): "
            f"exponent {fit_exponent(points):.2f} for N = {ns[0]} to {ns[-1]}")
    if len(large) >= 2:
        text += f", {fit_exponent(large):.2f} for N = {large[0][0]} to {large[-1][0]}"
    points = [(n, results[(n, 0)]["assembly"]) for n in ns]
    text += f" (assembly alone: {fit_exponent(points):.2f} for N = {ns[0]} to {ns[-1]})."
    return text


def solution_table(results):
    r = results[(80, 0)]
    rest = r["wall"] - r["loop"] - r["output"]
    lines = ["| steps to relax | linear solves | time loop (s) | rodsolve wall time (s) | "
             "of which output (s) | of which set-up (s) | process, with MPI launch (s) | "
             "seed 004 (Python + numba, laptop) | Abaqus B32 (seed 004) |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
             f"| {r['steps']} | {r['iterations']} | {r['loop']:.4f} | {r['wall']:.3f} | "
             f"{r['output']:.3f} | {rest:.3f} | {r['process']:.2f} | 0.8 | 4 |"]
    return "\n".join(lines)


def solver_table(results):
    ns = sorted(n for n, k in results if k == 1)
    head = "| N | unknowns | " + " | ".join(f"{name}: ms per step" for name, _ in SOLVERS)
    head += " | " + " | ".join(f"{name} / default" for name, _ in SOLVERS[1:]) + " |"
    lines = [head, "|---:|---:|" + "---:|" * (2 * len(SOLVERS) - 1)]
    for n in ns:
        times = [results[(n, k)]["per_step"] for k in range(len(SOLVERS))]
        lines.append(f"| {n} | {results[(n, 0)]['unknowns']} | "
                     + " | ".join(f"{t * 1e3:.3f}" for t in times) + " | "
                     + " | ".join(f"{t / times[0]:.1f}" for t in times[1:]) + " |")
    return "\n".join(lines)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--repeat", type=int, default=5, help="runs per case (median)")
    parser.add_argument("--largest", type=int, default=5120, help="largest N")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    results = measure(args)
    block = (f"{measured_on()}; 1 rank; medians of {args.repeat} runs, all cases alternating. "
             "Seed 004's 45-degree bend at 600 N (input/bend45_strand.nml: dt = 10 s, damping "
             "0.1, relaxed when the kinetic energy is below 1e-12 J), one linear solve per "
             "step. Times per step are rodsolve's time loop (assembly and linear solve, output "
             "excluded) over the steps; assembly is the matrix and right-hand side, the rest "
             "is the LU and the update.\n\n"
             "Time per step against the number of segments (PETSc LU, natural ordering):\n\n"
             + scaling_table(results) +
             "\n\nTime to solution at N = 80 (Table 4 of seed 004: \"81 nodes, 960 DOF\"). The "
             "seed's times are from other machines: its own method in Python + numba on a "
             "1.8 GHz Core i5 laptop, Abaqus on hardware it does not state:\n\n"
             + solution_table(results) +
             "\n\nThe LU package and ordering (`&solver petsc_options`): PETSc's LU in natural, "
             "reverse Cuthill-McKee and nested-dissection ordering, and MUMPS (which gets "
             "PETSc's natural ordering as its pivot order); ratios from the same runs:\n\n"
             + solver_table(results) + "\n")
    print(block)
    if args.write:
        write_generated(args.source, "se3_strand_bench.py", block)


if __name__ == "__main__":
    main()
