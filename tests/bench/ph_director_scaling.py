"""Benchmark: cost of a ph_director time step against the number of elements (issue 3).

Runs the flying spaghetti (input/flying_spaghetti.nml: p = 2, Table 1 material) with
n_e = 10, 20, 40, ..., 2560 elements for a fixed number of steps during the loading phase,
with the uncondensed (default) and the condensed step, and reads rodsolve's own timing of the
time loop (output excluded). Each case runs `--repeat` times; the table reports medians.
With --write the table replaces the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/ph_director_scaling.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench [--write]
"""
import datetime
import os
import platform
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "regression"))
import run_scene as rs  # noqa: E402

SUMMARY = re.compile(r"(\d+) steps, (\d+) Newton iterations, (\d+) cut-backs; time loop (\S+) s, "
                     r"per step (\S+) s, per Newton iteration (\S+) s")
UNKNOWNS = re.compile(r"(\d+) Newton unknowns \((.*?)\), (\d+) Jacobian non-zeros")


def run_case(args, n_elements, condensed, steps):
    text = rs.read_example(args.source, "flying_spaghetti.nml")
    text = rs.set_variable(text, "rod", "n_elements", str(n_elements))
    text = rs.set_variable(text, "time", "t_end", repr(steps * 0.1))
    text = rs.set_variable(text, "output", "stride", str(steps))
    text = rs.set_variable(text, "solver", "condense_stresses", ".true." if condensed else ".false.")
    if condensed:
        # MUMPS' workspace estimate is too small for the pivoting the condensed saddle point
        # needs (INFOG(1) = -9 with the default 50 %); docs/performance.md.
        text = rs.set_variable(text, "solver", "petsc_options", "'-mat_mumps_icntl_14 200'")
    os.makedirs(args.workdir, exist_ok=True)
    scene = os.path.join(args.workdir, f"bench_{n_elements}_{int(condensed)}.nml")
    output = scene[:-4] + ".h5"
    text = rs.set_variable(text, "output", "path", f"'{output}'")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, scene],
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.stderr.write(result.stdout + result.stderr)
        raise SystemExit(f"n_e = {n_elements}: rodsolve failed")
    summary = SUMMARY.search(result.stdout)
    unknowns = UNKNOWNS.search(result.stdout)
    return {"steps": int(summary[1]), "iterations": int(summary[2]), "cutbacks": int(summary[3]),
            "per_step": float(summary[5]), "per_iteration": float(summary[6]),
            "unknowns": int(unknowns[1]), "nnz": int(unknowns[3])}


def median_case(args, n_elements, condensed, steps):
    runs = [run_case(args, n_elements, condensed, steps) for _ in range(args.repeat)]
    best = dict(runs[0])
    best["per_step"] = statistics.median(r["per_step"] for r in runs)
    best["per_iteration"] = statistics.median(r["per_iteration"] for r in runs)
    return best


def blas_name():
    try:
        link = os.path.realpath("/usr/lib/x86_64-linux-gnu/libblas.so.3")
        return os.path.basename(os.path.dirname(link)) or link
    except OSError:
        return "unknown"


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
        plain = median_case(args, n_e, False, args.steps)
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
    machine = (f"{platform.node()}: {os.cpu_count()} cores, {platform.processor() or platform.machine()}, "
               f"BLAS {blas_name()} (1 thread)")
    header = (f"Measured {datetime.date.today().isoformat()} on {machine}; flying spaghetti material, "
              f"p = 2, 2 Gauss points, h = 0.1, {args.steps} steps from rest (loading phase), "
              f"Newton tolerance 1e-11, 1 rank; medians of {args.repeat} runs of the time loop "
              f"(output excluded).")
    table = header + "\n\n" + "\n".join(lines) + "\n"
    print(table)
    if args.write:
        path = os.path.join(args.source, "docs", "performance.md")
        with open(path, encoding="utf-8") as f:
            text = f.read()
        begin = "<!-- BEGIN GENERATED: tests/bench/ph_director_scaling.py -->"
        end = "<!-- END GENERATED: tests/bench/ph_director_scaling.py -->"
        i, j = text.index(begin) + len(begin), text.index(end)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text[:i] + "\n" + table + text[j:])
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
