"""Shared helpers of the benchmarks in tests/bench/: run a scene once and read rodsolve's own
summary line (time loop only, output excluded), take medians, name the machine, and replace a
GENERATED block of docs/performance.md."""
import datetime
import os
import platform
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "regression"))
import run_scene as rs  # noqa: E402,F401  (re-exported for the benchmarks)

SUMMARY = re.compile(r"(\d+) steps, (\d+) Newton iterations, (\d+) cut-backs; time loop (\S+) s, "
                     r"per step (\S+) s, per Newton iteration (\S+) s")
UNKNOWNS = re.compile(r"(\d+) Newton unknowns")


def run_case(args, text, name):
    """Run scene `text` as `name`.nml on one rank; return the summary line's numbers and the
    full standard output."""
    os.makedirs(args.workdir, exist_ok=True)
    scene = os.path.join(args.workdir, name + ".nml")
    text = rs.set_variable(text, "output", "path", f"'{scene[:-4]}.h5'")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, scene],
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.stderr.write(result.stdout + result.stderr)
        raise SystemExit(f"{name}: rodsolve failed")
    summary = SUMMARY.search(result.stdout)
    unknowns = UNKNOWNS.search(result.stdout)
    return {"steps": int(summary[1]), "iterations": int(summary[2]), "cutbacks": int(summary[3]),
            "per_step": float(summary[5]), "per_iteration": float(summary[6]),
            "unknowns": int(unknowns[1]), "stdout": result.stdout}


def median_case(args, text, name):
    """`run_case` `args.repeat` times; the times are medians, the counts those of the first."""
    runs = [run_case(args, text, name) for _ in range(args.repeat)]
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


def measured_on():
    """'Measured <date> on <host>: <cores> cores, <cpu>, BLAS <name> (1 thread)'."""
    return (f"Measured {datetime.date.today().isoformat()} on {platform.node()}: {os.cpu_count()} "
            f"cores, {platform.processor() or platform.machine()}, BLAS {blas_name()} (1 thread)")


def write_generated(source, script, block, document="performance.md"):
    """Replace the GENERATED block that belongs to `script` (a path under tests/bench/) in
    docs/`document` (docs/performance.md unless told)."""
    path = os.path.join(source, "docs", document)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    begin = f"<!-- BEGIN GENERATED: tests/bench/{script} -->"
    end = f"<!-- END GENERATED: tests/bench/{script} -->"
    i, j = text.index(begin) + len(begin), text.index(end)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text[:i] + "\n" + block + text[j:])
    print(f"wrote {path}")
