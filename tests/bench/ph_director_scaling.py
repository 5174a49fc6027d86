"""Benchmark: cost of a ph_director time step against the number of elements (issues 3, 11).

Runs the flying spaghetti (input/flying_spaghetti.nml: p = 2, Table 1 material) with
n_e = 16, 64, 256, 1024, 4096 and 10240 elements for a fixed number of steps during the
loading phase, once with Newton's method (a new Jacobian, i.e. a MUMPS numeric factorization,
at every iteration; the default) and once keeping the factored Jacobian while every iteration
cuts the residual at least tenfold (`&solver jacobian_reuse = 0.1`), and reads rodsolve's own
timing of the time loop (output excluded) and its count of factored Jacobians. Each case runs
for --steps and for twice as many steps: the difference is the cost of --steps steps without
what a run does once (MUMPS's analysis of the pattern), so the costs per step and per
iteration are those of a long run. The runs leave out MUMPS's maximum transversal
(`-mat_mumps_icntl_6 0`, fine for this rod): with it the analysis takes 19.5 s at
n_e = 4096, and its noise alone swamps the difference of two short runs. Each run is repeated `--repeat` times; the
table reports medians. With --write the table replaces the GENERATED block of
docs/performance.md.

    /usr/bin/python3 tests/bench/ph_director_scaling.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench [--write]
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_common  # noqa: E402
from bench_common import rs, measured_on, write_generated  # noqa: E402

JACOBIANS = re.compile(r"; (\d+) Jacobians factored")
SIZES = (16, 64, 256, 1024, 4096, 10240)
REUSE = 0.1


def scene_text(args, n_elements, reuse, steps):
    text = rs.read_example(args.source, "flying_spaghetti.nml")
    text = rs.set_variable(text, "rod", "n_elements", str(n_elements))
    text = rs.set_variable(text, "time", "t_end", repr(steps * 0.1))
    text = rs.set_variable(text, "output", "stride", str(steps))
    text = rs.set_variable(text, "solver", "petsc_options", "'-mat_mumps_icntl_6 0'")
    return rs.set_variable(text, "solver", "jacobian_reuse", repr(reuse))


def timed(args, n_elements, reuse, steps):
    """The medians of --repeat runs of the spaghetti with n_elements over `steps` steps: the
    whole time loop, the Newton iterations and the Jacobians factored."""
    text = scene_text(args, n_elements, reuse, steps)
    result = bench_common.median_case(args, text, f"bench_{n_elements}_{reuse}_{steps}")
    result["loop"] = result["per_step"] * result["steps"]
    result["jacobians"] = int(JACOBIANS.search(result["stdout"])[1])
    return result


def run_case(args, n_elements, reuse, steps):
    """The steps from `steps` to 2 `steps` (the difference of two runs): cost per step and per
    Newton iteration and unknown, iterations and Jacobians."""
    short, long = timed(args, n_elements, reuse, steps), timed(args, n_elements, reuse, 2 * steps)
    iterations = long["iterations"] - short["iterations"]
    loop = long["loop"] - short["loop"]
    return {"unknowns": long["unknowns"], "iterations": iterations,
            "jacobians": long["jacobians"] - short["jacobians"], "per_step": loop / steps,
            "us_per_unknown": loop / iterations / long["unknowns"] * 1e6}


def table(args, rows):
    lines = ["| n_e | unknowns | Newton: iterations | ms per step | us per iteration and unknown "
             "| per step / n_e, relative to the smallest | reuse 0.1: iterations | Jacobians "
             "| ms per step | us per iteration and unknown | per step, Newton / reuse |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    n_0, base = rows[0][0], rows[0][1]
    for n_e, newton, reuse in rows:
        growth = (newton["per_step"] / n_e) / (base["per_step"] / n_0)
        cells = [str(n_e), str(newton["unknowns"]), str(newton["iterations"]),
                 f"{newton['per_step'] * 1e3:.4g}", f"{newton['us_per_unknown']:.2f}",
                 f"{growth:.2f}", str(reuse["iterations"]), str(reuse["jacobians"]),
                 f"{reuse['per_step'] * 1e3:.4g}", f"{reuse['us_per_unknown']:.2f}",
                 f"{newton['per_step'] / reuse['per_step']:.2f}"]
        lines.append("| " + " | ".join(cells) + " |")
    header = (f"{measured_on()}; flying spaghetti material, p = 2, 2 Gauss points, h = 0.1, "
              f"steps {args.steps + 1} to {2 * args.steps} from rest (loading phase: the "
              f"difference of runs over {args.steps} and {2 * args.steps} steps), Newton "
              f"tolerance 1e-11, MUMPS with AMD and without the maximum transversal, 1 rank; "
              f"medians of {args.repeat} runs of the "
              f"time loop (output excluded); load average {os.getloadavg()[0]:.1f} at the end.")
    return header + "\n\n" + "\n".join(lines) + "\n"


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--steps", type=int, default=5, help="steps of the shorter run (h = 0.1)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (median)")
    parser.add_argument("--largest", type=int, default=SIZES[-1], help="largest n_e")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

    rows = []
    for n_e in (n for n in SIZES if n <= args.largest):
        newton = run_case(args, n_e, 0.0, args.steps)
        reuse = run_case(args, n_e, REUSE, args.steps)
        rows.append((n_e, newton, reuse))
        print(f"n_e = {n_e:5d}: Newton {newton['per_step'] * 1e3:9.2f} ms/step "
              f"({newton['us_per_unknown']:.2f} us/iteration/unknown, {newton['iterations']} it); "
              f"reuse {reuse['per_step'] * 1e3:9.2f} ms/step ({reuse['us_per_unknown']:.2f} "
              f"us/iteration/unknown, {reuse['iterations']} it, {reuse['jacobians']} Jacobians)",
              flush=True)
    text = table(args, rows)
    print(text)
    if args.write:
        write_generated(args.source, "ph_director_scaling.py", text)


if __name__ == "__main__":
    main()
