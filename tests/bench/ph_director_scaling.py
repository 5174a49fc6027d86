"""Benchmark: cost of a ph_director time step against the number of elements, per LU package
(issues 3, 11 and the chain LU's).

Runs the flying spaghetti (input/flying_spaghetti.nml: p = 2, Table 1 material) with
n_e = 4, 16, 64, 256, 1024, 4096 and 10240 elements for a fixed number of steps during the
loading phase, once with Newton's method (a new Jacobian, i.e. a numeric factorization, at
every iteration; the default) and once keeping the factored Jacobian while every iteration
cuts the residual at least tenfold (`&solver jacobian_reuse = 0.1`), and reads rodsolve's own
timing of the time loop (output excluded), its count of factored Jacobians and its wall time.
Each case runs with every LU package of --packages, chosen by `-pc_factor_mat_solver_type`:

- `rodchain`, the chain LU (include/rs_rodchain.h), the default for a single rod;
- `mumps`, MUMPS with AMD (rodsolve's MUMPS defaults), the path before the chain LU.

Every run also passes `-mat_mumps_icntl_6 0` (no maximum transversal in MUMPS's analysis,
fine for this rod; also what rodchain's MUMPS fallback would use): with the transversal the
analysis takes 19.5 s at n_e = 4096, and its noise alone swamps the difference of two short
runs. A package may stop at a size (`mumps:4096`: MUMPS at n_e = 10240 takes minutes per run).

Each case runs for --steps and for twice as many steps: the difference is the cost of --steps
steps without what a run does once, so the costs per step and per iteration are those of a long
run; the one-time part of the time loop (the first factorization's analysis, the first step's
set-up) is the short run's loop less --steps times that cost per step, and the set-up outside
the loop (building the rod and its stepper, the result file, freeing) is rodsolve's wall time
less the time loop and the output. Each run is repeated --repeat times (64 / n_e times as
often below n_e = 64: those loops last milliseconds), the packages taking turns within each
repetition so that drifts of the shared machine hit them alike; the tables report medians. rodchain's message when it hands a Jacobian to MUMPS is counted and reported.
With --write the tables replace the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/ph_director_scaling.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench [--packages rodchain,mumps:4096] \\
        [--largest 4096] [--repeat 3] [--write]
"""
import os
import re
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_common  # noqa: E402
from bench_common import rs, measured_on, write_generated  # noqa: E402

JACOBIANS = re.compile(r"; (\d+) Jacobians factored")
TIME_LOOP = re.compile(r"time loop (\S+) s, per step")
WALL = re.compile(r"wall time (\S+) s: assembly \S+ s, linear solves and Newton \S+ s, "
                  r"output (\S+) s")
FALLBACK = re.compile(r"^rodchain: .*MUMPS factors such Jacobians", re.M)
SIZES = (4, 16, 64, 256, 1024, 4096, 10240)
REUSE = 0.1
MUMPS_OPTIONS = "-mat_mumps_icntl_6 0"
DESCRIPTION = {"rodchain": "the chain LU (the default for a single rod)",
               "mumps": "MUMPS with AMD and without the maximum transversal (the path before "
                        "the chain LU)",
               "petsc": "PETSc's own LU"}


def parse_packages(text):
    """'rodchain,mumps:4096' -> [('rodchain', None), ('mumps', 4096)]: each package with the
    largest n_e it runs (None: every size)."""
    packages = []
    for item in text.split(","):
        name, _, largest = item.strip().partition(":")
        packages.append((name, int(largest) if largest else None))
    return packages


def scene_text(args, n_elements, reuse, steps, package):
    text = rs.read_example(args.source, "flying_spaghetti.nml")
    text = rs.set_variable(text, "rod", "n_elements", str(n_elements))
    text = rs.set_variable(text, "time", "t_end", repr(steps * 0.1))
    text = rs.set_variable(text, "output", "stride", str(steps))
    text = rs.set_variable(text, "solver", "petsc_options",
                           f"'{MUMPS_OPTIONS} -pc_factor_mat_solver_type {package}'")
    return rs.set_variable(text, "solver", "jacobian_reuse", repr(reuse))


def run_once(args, n_elements, reuse, steps, package):
    """One run: the time loop, rodsolve's wall time less the loop and the output, the counts."""
    text = scene_text(args, n_elements, reuse, steps, package)
    name = f"bench_{package}_{n_elements}_{reuse}_{steps}"
    try:
        result = bench_common.run_case(args, text, name)
    except SystemExit as failure:
        # Once more: on a shared machine the executable may have been relinked under the run.
        print(f"{failure}; running it again", flush=True)
        time.sleep(10)
        result = bench_common.run_case(args, text, name)
    wall = WALL.search(result["stdout"])
    result["loop"] = float(TIME_LOOP.search(result["stdout"])[1])
    result["outside"] = float(wall[1]) - result["loop"] - float(wall[2])
    result["jacobians"] = int(JACOBIANS.search(result["stdout"])[1])
    result["fallbacks"] = len(FALLBACK.findall(result["stdout"]))
    return result


def summarize(args, short, long):
    """The steps from --steps to 2 --steps (the difference of the median loops), the one-time
    parts, and the counts, from the repeated runs `short` and `long` of one case."""
    steps = args.steps
    loop_short = statistics.median(r["loop"] for r in short)
    loop_long = statistics.median(r["loop"] for r in long)
    iterations = long[0]["iterations"] - short[0]["iterations"]
    unknowns = long[0]["unknowns"]
    per_step = (loop_long - loop_short) / steps
    steady = all(len({(r["iterations"], r["jacobians"]) for r in runs}) == 1
                 for runs in (short, long))
    return {"unknowns": unknowns, "iterations": iterations,
            "jacobians": long[0]["jacobians"] - short[0]["jacobians"], "per_step": per_step,
            "per_iteration": (loop_long - loop_short) / iterations,
            "us_per_unknown": (loop_long - loop_short) / iterations / unknowns * 1e6,
            "one_time": loop_short - steps * per_step,
            "outside": statistics.median(r["outside"] for r in short),
            "fallbacks": sum(r["fallbacks"] for r in short + long),
            "steady": steady}


def repeats(args, n_elements):
    """Runs per case: --repeat, times 64 / n_e below 64 elements, whose loops last only
    milliseconds, so that one preemption on the shared machine does not make the median."""
    return args.repeat * max(1, 64 // n_elements)


def measure(args, n_elements, packages):
    """{(package, reuse): summary} for one n_e; within each repetition the packages and the
    two run lengths take turns."""
    runs = {(p, reuse, s): [] for p in packages for reuse in (0.0, REUSE)
            for s in (args.steps, 2 * args.steps)}
    for _ in range(repeats(args, n_elements)):
        for reuse in (0.0, REUSE):
            for steps in (args.steps, 2 * args.steps):
                for package in packages:
                    runs[(package, reuse, steps)].append(
                        run_once(args, n_elements, reuse, steps, package))
    return {(p, reuse): summarize(args, runs[(p, reuse, args.steps)],
                                  runs[(p, reuse, 2 * args.steps)])
            for p in packages for reuse in (0.0, REUSE)}


def cell(results, key, fmt):
    return format(results[key], fmt) if results is not None else "-"


def both(values):
    """One number where the packages agree, 'a / b' where they do not."""
    present = [v for v in values if v is not None]
    return str(present[0]) if len(set(present)) == 1 else " / ".join(
        str(v) if v is not None else "-" for v in values)


def tables(args, names, rows, sizes_of, load_start):
    """The header and the three tables: Newton's method, jacobian_reuse, one-time costs."""
    ratio = len(names) >= 2
    old, new = (names[1], names[0]) if ratio else (None, None)
    reference = next((row for row in rows if row[0] >= 64), rows[0])

    def get(row, name, reuse):
        return row[1].get((name, reuse))

    head = ["n_e", "unknowns", "Newton iterations" + (f" ({' / '.join(names)})" if ratio else "")]
    for name in names:
        head += [f"{name}: ms per step", f"{name}: us per iteration",
                 f"{name}: us per iteration and unknown",
                 f"{name}: per step / n_e, relative to n_e = {reference[0]}"]
    if ratio:
        head.append(f"per step, {old} / {new}")
    newton = ["| " + " | ".join(head) + " |", "|" + "---:|" * len(head)]
    for row in rows:
        n_e = row[0]
        first = next(r for r in (get(row, n, 0.0) for n in names) if r is not None)
        cells = [str(n_e), str(first["unknowns"]),
                 both([get(row, n, 0.0)["iterations"] if get(row, n, 0.0) else None
                       for n in names])]
        for name in names:
            r, base = get(row, name, 0.0), get(reference, name, 0.0)
            cells += ["-" if r is None else f"{r['per_step'] * 1e3:.4g}",
                      "-" if r is None else f"{r['per_iteration'] * 1e6:.4g}",
                      cell(r, "us_per_unknown", ".2f"),
                      "-" if r is None or base is None else
                      f"{(r['per_step'] / n_e) / (base['per_step'] / reference[0]):.2f}"]
        if ratio:
            a, b = get(row, old, 0.0), get(row, new, 0.0)
            cells.append("-" if a is None or b is None else f"{a['per_step'] / b['per_step']:.2f}")
        newton.append("| " + " | ".join(cells) + " |")

    head = ["n_e", "iterations" + (f" ({' / '.join(names)})" if ratio else ""),
            "Jacobians" + (f" ({' / '.join(names)})" if ratio else "")]
    for name in names:
        head += [f"{name}: ms per step", f"{name}: us per iteration and unknown",
                 f"{name}: per step, Newton / reuse"]
    if ratio:
        head.append(f"per step, {old} / {new}")
    reuse = ["| " + " | ".join(head) + " |", "|" + "---:|" * len(head)]
    for row in rows:
        cells = [str(row[0]),
                 both([get(row, n, REUSE)["iterations"] if get(row, n, REUSE) else None
                       for n in names]),
                 both([get(row, n, REUSE)["jacobians"] if get(row, n, REUSE) else None
                       for n in names])]
        for name in names:
            r, full = get(row, name, REUSE), get(row, name, 0.0)
            cells += ["-" if r is None else f"{r['per_step'] * 1e3:.4g}",
                      cell(r, "us_per_unknown", ".2f"),
                      "-" if r is None else f"{full['per_step'] / r['per_step']:.2f}"]
        if ratio:
            a, b = get(row, old, REUSE), get(row, new, REUSE)
            cells.append("-" if a is None or b is None else f"{a['per_step'] / b['per_step']:.2f}")
        reuse.append("| " + " | ".join(cells) + " |")

    head = ["n_e"]
    for name in names:
        head += [f"{name}: one-time part of the time loop (ms)", f"{name}: per element (us)",
                 f"{name}: set-up outside the time loop (ms)", f"{name}: per element (us)"]
    once = ["| " + " | ".join(head) + " |", "|" + "---:|" * len(head)]
    for row in rows:
        n_e, cells = row[0], [str(row[0])]
        for name in names:
            r = get(row, name, 0.0)
            cells += ["-"] * 4 if r is None else [
                f"{r['one_time'] * 1e3:.4g}", f"{r['one_time'] / n_e * 1e6:.4g}",
                f"{r['outside'] * 1e3:.4g}", f"{r['outside'] / n_e * 1e6:.4g}"]
        once.append("| " + " | ".join(cells) + " |")

    packages = "; ".join(
        f"`{name}`: {DESCRIPTION.get(name, name)}, n_e up to {max(sizes_of[name])}"
        for name in names)
    notes = []
    fallbacks = [(row[0], name, r["fallbacks"]) for row in rows for (name, _), r in
                 row[1].items() if r["fallbacks"]]
    notes.append("rodchain handed no Jacobian to MUMPS in any run." if not fallbacks else
                 "rodchain's message that MUMPS factors a Jacobian appeared in " + ", ".join(
                     f"{count} runs of {name} at n_e = {n_e}" for n_e, name, count in fallbacks)
                 + ".")
    unsteady = [(row[0], name, reuse) for row in rows for (name, reuse), r in row[1].items()
                if not r["steady"]]
    if unsteady:
        notes.append("Iteration or Jacobian counts differed between repetitions of " + ", ".join(
            f"{name} at n_e = {n_e} ({'reuse' if reuse else 'Newton'})"
            for n_e, name, reuse in unsteady) + " (the table takes the first run's).")
    header = (
        f"{measured_on()}; flying spaghetti material, p = 2, 2 Gauss points, h = 0.1, "
        f"steps {args.steps + 1} to {2 * args.steps} from rest (loading phase: the difference "
        f"of runs over {args.steps} and {2 * args.steps} steps), Newton tolerance 1e-11, 1 rank. "
        f"LU packages (`-pc_factor_mat_solver_type`, every run with `{MUMPS_OPTIONS}`): "
        f"{packages}. Medians of {args.repeat} runs of the time loop (output excluded; "
        f"{args.repeat} x 64 / n_e below n_e = 64, where a loop lasts milliseconds), the "
        f"packages taking turns within each repetition; load average {load_start:.1f} at the "
        f"start, {os.getloadavg()[0]:.1f} at the end. " + " ".join(notes))
    return (header + "\n\nNewton's method (a new Jacobian at every iteration):\n\n"
            + "\n".join(newton) + f"\n\n`&solver jacobian_reuse = {REUSE}` (the factored "
            "Jacobian kept while each iteration cuts the residual tenfold):\n\n"
            + "\n".join(reuse) + "\n\nWhat a run does once, Newton's method: the one-time part "
            f"of the time loop is the {args.steps}-step run's loop less {args.steps} times the "
            "cost per step above (the first factorization's analysis, the first step's set-up); "
            "the set-up outside the time loop is rodsolve's wall time less the time loop and "
            f"the output (building the rod and its stepper, the result file, freeing), median "
            f"of the {args.steps}-step runs:\n\n" + "\n".join(once) + "\n")


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--steps", type=int, default=5, help="steps of the shorter run (h = 0.1)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (median)")
    parser.add_argument("--largest", type=int, default=SIZES[-1], help="largest n_e")
    parser.add_argument("--packages", default="rodchain,mumps:4096",
                        help="LU packages, comma-separated, each optionally with the largest "
                             "n_e it runs (name:n_e); the first is the new one, the second the "
                             "old one of the ratios")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    packages = parse_packages(args.packages)
    names = [name for name, _ in packages]
    load_start = os.getloadavg()[0]

    rows, sizes_of = [], {name: [] for name in names}
    for n_e in (n for n in SIZES if n <= args.largest):
        here = [name for name, largest in packages if largest is None or n_e <= largest]
        if not here:
            continue
        results = measure(args, n_e, here)
        rows.append((n_e, results))
        for name in here:
            sizes_of[name].append(n_e)
            newton, reuse = results[(name, 0.0)], results[(name, REUSE)]
            print(f"n_e = {n_e:5d} {name:>8}: Newton {newton['per_step'] * 1e3:9.3f} ms/step "
                  f"({newton['us_per_unknown']:.3f} us/iteration/unknown, "
                  f"{newton['per_iteration'] * 1e6:.1f} us/iteration, {newton['iterations']} "
                  f"it; one-time {newton['one_time'] * 1e3:.2f} ms in the loop, "
                  f"{newton['outside'] * 1e3:.2f} ms outside); reuse "
                  f"{reuse['per_step'] * 1e3:9.3f} ms/step ({reuse['us_per_unknown']:.3f} "
                  f"us/iteration/unknown, {reuse['iterations']} it, {reuse['jacobians']} "
                  f"Jacobians); rodchain fallbacks {newton['fallbacks'] + reuse['fallbacks']}",
                  flush=True)
    text = tables(args, names, rows, sizes_of, load_start)
    print(text)
    if args.write:
        write_generated(args.source, "ph_director_scaling.py", text)


if __name__ == "__main__":
    main()
