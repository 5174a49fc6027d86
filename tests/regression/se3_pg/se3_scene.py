"""Helpers shared by the se3_pg regression tests: run a scene and keep what rodsolve printed
(the summary line carries the load increments, Newton iterations, cut-backs and the wall time of
the time loop, src/solver/rod_run.F90), and small scene edits.
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402,F401

# "  <rod>: <steps> steps, <its> Newton iterations, <cuts> cut-backs; time loop <s> s, ..."
SUMMARY = re.compile(r"^\s+(\S+): (\d+) steps, (\d+) Newton iterations, (\d+) cut-backs; "
                     r"time loop (\S+) s", flags=re.M)
# "rodsolve: <n> rod(s), ...; wall time <s> s: ..." (the whole run: setup, time loop, output)
WALL = re.compile(r"^rodsolve: \d+ rod\(s\),.*; wall time (\S+) s", flags=re.M)


class Run:
    """One rodsolve run: its status, its printed text, the summary of rod `rod` and, if the
    result file exists, the datasets of /rods/<rod>."""

    def __init__(self, status, text, path, rod):
        self.status = status
        self.text = text
        self.path = path
        self.steps = self.iterations = self.cutbacks = None
        self.seconds = float("nan")
        wall = WALL.search(text)
        self.wall_seconds = float(wall.group(1)) if wall else float("nan")
        for m in SUMMARY.finditer(text):
            if m.group(1) == rod:
                self.steps, self.iterations, self.cutbacks = (int(m.group(i)) for i in (2, 3, 4))
                self.seconds = float(m.group(5))
        self.fields = rs.rod(path, rod) if os.path.exists(path) else {}

    def __getitem__(self, key):
        return self.fields[key]

    def summary(self):
        return (f"{self.steps} increments, {self.iterations} Newton iterations, "
                f"{self.cutbacks} cut-backs, time loop {self.seconds:.4g} s")


def run(args, text, name, rod, allow_failure=False):
    """Write scene `name`.nml with its output in the work directory and run it on one rank.
    A failing run stops the test unless `allow_failure` (then the last good state that rodsolve
    wrote is returned with the status)."""
    os.makedirs(args.workdir, exist_ok=True)
    output = os.path.join(args.workdir, name + ".h5")
    if os.path.exists(output):
        os.remove(output)
    text = rs.set_variable(text, "output", "path", f"'{output}'")
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    command = [args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, scene]
    result = subprocess.run(command, capture_output=True, text=True)
    printed = result.stdout + result.stderr
    if result.returncode != 0:
        sys.stdout.write(printed)
        if not allow_failure:
            raise SystemExit(f"{' '.join(command)} failed with status {result.returncode}")
    return Run(result.returncode, printed, output, rod)


def edit(text, changes):
    """Apply (group, variable, value) edits with rs.set_variable (first group of each name)."""
    for group, variable, value in changes:
        text = rs.set_variable(text, group, variable, value)
    return text
