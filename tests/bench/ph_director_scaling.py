"""Benchmark: cost of a ph_director time step against the number of elements (issue 3).

Runs the flying spaghetti (input/flying_spaghetti.nml: p = 2, Table 1 material) with
n_e = 10, 20, 40, ..., 2560 elements for a fixed number of steps during the loading phase,
with the uncondensed (default) and the condensed step, and reads rodsolve's own timing of the
time loop (output excluded). Each case runs `--repeat` times; the table reports medians.
With --write the table replaces the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/ph_director_scaling.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench [--write]
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_common  # noqa: E402
from bench_common import rs, measured_on, write_generated  # noqa: E402

NON_ZEROS = re.compile(r"(\d+) Newton unknowns \((.*?)\), (\d+) Jacobian non-zeros")


def scene_text(args, n_elements, condensed, steps):
    text = rs.read_example(args.source, "flying_spaghetti.nml")
    text = rs.set_variable(text, "rod", "n_elements", str(n_elements))
    text = rs.set_variable(text, "time", "t_end", repr(steps * 0.1))
    text = rs.set_variable(text, "output", "stride", str(steps))
    text = rs.set_variable(text, "solver", "condense_stresses", ".true." if condensed else ".false.")
    if condensed:
        # MUMPS' workspace estimate is too small for the pivoting the condensed saddle point
        # needs (INFOG(1) = -9 with the default 50 %); docs/performance.md.
        text = rs.set_variable(text, "solver", "petsc_options", "'-mat_mumps_icntl_14 200'")
    return text


def run_case(args, n_elements, condensed, steps, repeat=False):
    """One run (or the medians of --repeat runs) of the spaghetti with n_elements."""
    text = scene_text(args, n_elements, condensed, steps)
    name = f"bench_{n_elements}_{int(condensed)}"
    result = (bench_common.median_case if repeat else bench_common.run_case)(args, text, name)
    result["nnz"] = int(NON_ZEROS.search(result["stdout"])[3])
    return result


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--steps", type=int, default=10, help="time steps per run (h = 0.1)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (median)")
    parser.add_argument("--largest", type=int, default=2560, help="largest n_e")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

    sizes = []
    n = 10
    while n <= args.largest:
        sizes.append(n)
        n *= 2
    rows = []
    for n_e in sizes:
        plain = run_case(args, n_e, False, args.steps, repeat=True)
        # The condensed step stagnates above the Newton tolerance from n_e = 20 on (cut-backs;
        # docs/performance.md), so one run up to n_e = 160 tells the story.
        condensed = run_case(args, n_e, True, args.steps) if n_e <= 160 else None
        rows.append((n_e, plain, condensed))
        c = (f"{condensed['per_step'] * 1e3:.2f} ms/step, {condensed['iterations']} it, "
             f"{condensed['cutbacks']} cut-backs") if condensed else "-"
        print(f"n_e = {n_e:5d}: uncondensed {plain['per_step'] * 1e3:8.2f} ms/step "
              f"({plain['per_iteration'] * 1e3:7.3f} ms/iteration, {plain['iterations']} it); "
              f"condensed {c}", flush=True)

    base = rows[0][1]
    lines = ["| n_e | unknowns | Jacobian non-zeros | Newton iterations | ms per step | ms per iteration "
             "| per step / n_e, relative to n_e = 10 | condensed: unknowns | ms per step | "
             "ms per iteration | Newton iterations (cut-backs) |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n_e, plain, condensed in rows:
        ratio = (plain["per_step"] / n_e) / (base["per_step"] / rows[0][0])
        cells = [str(n_e), str(plain["unknowns"]), str(plain["nnz"]), str(plain["iterations"]),
                 f"{plain['per_step'] * 1e3:.2f}", f"{plain['per_iteration'] * 1e3:.3f}", f"{ratio:.2f}"]
        if condensed:
            cells += [str(condensed["unknowns"]), f"{condensed['per_step'] * 1e3:.2f}",
                      f"{condensed['per_iteration'] * 1e3:.3f}",
                      f"{condensed['iterations']} ({condensed['cutbacks']})"]
        else:
            cells += ["-", "-", "-", "-"]
        lines.append("| " + " | ".join(cells) + " |")
    header = (f"{measured_on()}; flying spaghetti material, "
              f"p = 2, 2 Gauss points, h = 0.1, {args.steps} steps from rest (loading phase), "
              f"Newton tolerance 1e-11, 1 rank; medians of {args.repeat} runs of the time loop "
              f"(output excluded).")
    table = header + "\n\n" + "\n".join(lines) + "\n"
    print(table)
    if args.write:
        write_generated(args.source, "ph_director_scaling.py", table)


if __name__ == "__main__":
    main()
