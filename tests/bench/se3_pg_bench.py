"""Benchmark: se3_pg (issue 7). On one rank, from rodsolve's own timing of the time loop (output
excluded; medians of `--repeat` runs):

1. time to solution of seed 004's 45-degree bend (input/se3_bend45.nml: 80 elements, 10 load
   increments, Newton tolerance 1e-6 N) at 300 N and 600 N, next to the times seed 004 reports
   (0.8 s on a laptop for its own method, 4 s for Abaqus B32; methods/se3_strands.md §1);
2. cost of a static Newton iteration against the number of elements on the cantilever of
   seed 002 §4.1 (input/se3_cantilever.nml, 20 increments).

With --write the tables replace the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/se3_pg_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench_se3 [--write]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import rs, median_case, measured_on, write_generated  # noqa: E402


def bend_table(args):
    base = rs.read_example(args.source, "se3_bend45.nml")
    lines = ["| tip load | increments | Newton iterations | cut-backs | time to solution (s) | "
             "seed 004 (laptop) | Abaqus B32 |", "|---:|---:|---:|---:|---:|---:|---:|"]
    for load in (300, 600):
        text = rs.set_variable(base, "load", "force", f"0.0, 0.0, {load}.0")
        r = median_case(args, text, f"bend45_{load}")
        seconds = r["per_step"] * r["steps"]
        lines.append(f"| {load} N | {r['steps']} | {r['iterations']} | {r['cutbacks']} | "
                     f"{seconds:.3f} | 0.8 | 4 |")
        print(lines[-1], flush=True)
    return "\n".join(lines)


def cantilever_table(args):
    base = rs.read_example(args.source, "se3_cantilever.nml")
    lines = ["| elements | unknowns | Newton iterations | ms per iteration | µs per iteration and "
             "element |", "|---:|---:|---:|---:|---:|"]
    n = 4
    while n <= args.largest:
        text = rs.set_variable(base, "rod", "n_elements", str(n))
        r = median_case(args, text, f"cantilever_{n}")
        lines.append(f"| {n} | {r['unknowns']} | {r['iterations']} | {r['per_iteration'] * 1e3:.3f} | "
                     f"{r['per_iteration'] / n * 1e6:.2f} |")
        print(lines[-1], flush=True)
        n *= 4
    return "\n".join(lines)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--repeat", type=int, default=5, help="runs per case (median)")
    parser.add_argument("--largest", type=int, default=4096, help="largest cantilever mesh")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    block = (f"{measured_on()}; 1 rank; medians of {args.repeat} runs of the time loop (output "
             "excluded).\n\nSeed 004's 45-degree bend with se3_pg (statics, 80 elements):\n\n"
             + bend_table(args) +
             "\n\nCost of a static Newton iteration (cantilever of seed 002 §4.1, 20 increments):\n\n"
             + cantilever_table(args) + "\n")
    print(block)
    if args.write:
        write_generated(args.source, "se3_pg_bench.py", block)


if __name__ == "__main__":
    main()
