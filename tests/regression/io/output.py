#!/usr/bin/env python3
"""What a run writes and prints (DESIGN.md §7; issue 5 items 3, 4 and 7), on the flying
spaghetti of input/ shortened to t_end = 2.

    output.py fields     &output fields and stride: only the selected fields, every dataset
                         with unit and description, the checkpoint, the root attributes
    output.py xdmf       the XDMF sidecar of a run parses and references existing datasets
                         with matching shapes (tests/unit/io/check_xdmf.py, meshio if present)
    output.py units      &run units = 'mm_tonne_s' names the units in the file
    output.py progress   progress lines (time, step, dt, Newton, balance, time left) and the
                         summary line; --quiet prints neither
    output.py unused_options  a misspelled PETSc option in petsc_options and another on the
                         command line are named in a warning and in the root attribute
                         unused_petsc_options; options the run reads are not (issue 21 item 19)
"""
import os
import re
import subprocess
import sys

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
import run_scene as rs  # noqa: E402

ROD = "spaghetti"


def scene(args):
    text = rs.read_example(args.source, "flying_spaghetti.nml")
    return rs.set_variable(text, "time", "t_end", "2.0")


def fields(args, checks):
    text = rs.set_variable(scene(args), "output", "fields", "'position, stress'")
    text = rs.set_variable(text, "output", "stride", "5")
    path = rs.run(args, text, "fields")
    with h5py.File(path, "r") as f:
        g = f["rods"][ROD]
        present = set(g.keys())
        checks.check("unselected fields written (directors, velocity, director_velocity, strain)",
                     float(len(present & {"directors", "velocity", "director_velocity", "strain"})),
                     0.0)
        checks.check("selected fields missing (position, stress, time, series)",
                     float(len({"position", "stress", "time", "series"} - present)), 0.0)
        checks.check("records at stride 5 over 20 steps minus 5", abs(g["time"].shape[0] - 5), 0.0)
        checks.check("position records minus time records",
                     abs(g["position"].shape[0] - g["time"].shape[0]), 0.0)
        missing = []

        def visit(name, item):
            if isinstance(item, h5py.Dataset) and not name.startswith("checkpoint"):
                if "unit" not in item.attrs or not item.attrs.get("description", ""):
                    missing.append(name)
        f.visititems(visit)
        print(f"info: datasets without unit or description: {missing}")
        checks.check("datasets without unit or description", float(len(missing)), 0.0)
        c = f["checkpoint"][ROD]
        checks.check("checkpoint step minus the last step (20)", abs(int(c["step"][0]) - 20), 0.0)
        checks.check("checkpoint records minus the records", abs(int(c["records"][0]) - 5), 0.0)
        checks.check("status is 'completed'", float(f.attrs["status"] != "completed"), 0.0)
        for key in ("schema_version", "creator", "created", "command_line", "n_ranks",
                    "petsc_version", "hdf5_version", "mpi_version", "units"):
            checks.check(f"root attribute {key} missing", float(key not in f.attrs), 0.0)


def xdmf(args, checks):
    path = rs.run(args, scene(args), "xdmf", ranks=2)
    sidecar = path[:-3] + ".xdmf"
    checks.check("the sidecar exists", float(not os.path.exists(sidecar)), 0.0)
    result = subprocess.run([sys.executable, os.path.join(args.source, "tests", "unit", "io",
                                                          "check_xdmf.py"), sidecar],
                            capture_output=True, text=True)
    print(result.stdout + result.stderr)
    checks.check("check_xdmf.py status", float(result.returncode), 0.0)


def units(args, checks):
    text = rs.set_variable(scene(args), "run", "units", "'mm_tonne_s'")
    path = rs.run(args, text, "units")
    with h5py.File(path, "r") as f:
        g = f["rods"][ROD]
        got = {key: g[key].attrs["unit"] for key in ("position", "velocity", "time",
                                                     "series/energy/total")}
        print(f"info: units {got}, stress {g['stress'].attrs['unit']!r}")
        expected = {"position": "mm", "velocity": "mm/s", "time": "s",
                    "series/energy/total": "mJ"}
        checks.check("unit attributes not in mm-tonne-s",
                     float(sum(got[k] != v for k, v in expected.items())), 0.0)
        checks.check("root attribute units", float(f.attrs["units"] != "mm_tonne_s"), 0.0)


def progress(args, checks):
    text = rs.set_variable(scene(args), "run", "progress_interval", "1e-9")
    status, output = rs.run_failing(args, rs.set_variable(
        text, "output", "path", f"'{os.path.join(args.workdir, 'progress.h5')}'"), "progress")
    lines = [line for line in output.splitlines() if line.startswith("rodsolve: t = ")]
    pattern = re.compile(r"rodsolve: t = \S+, step \d+/20, dt = 0\.1, Newton iterations \d+, "
                         r"energy balance \S+ of max H, \S+ s, \S+ s left")
    checks.check("run status", float(status), 0.0)
    checks.check("progress lines minus steps (one per step at this interval)",
                 abs(len(lines) - 20), 0.0)
    checks.check("progress lines not in the documented form",
                 float(sum(not pattern.fullmatch(line) for line in lines)), 0.0)
    summary = re.search(r"rodsolve: 1 rod\(s\), 20 steps, \d+ rejected \(cut-backs\), \d+ Newton "
                        r"iterations; wall time \S+ s: assembly \S+ s, linear solves and Newton "
                        r"\S+ s, output \S+ s", output)
    checks.check("summary line missing", float(summary is None), 0.0)
    quiet = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, "--quiet",
                            os.path.join(args.workdir, "progress.nml")],
                           capture_output=True, text=True)
    checks.check("--quiet: status", float(quiet.returncode), 0.0)
    checks.check("--quiet: characters printed", float(len(quiet.stdout.strip())), 0.0)


def unused_options(args, checks):
    text = rs.set_variable(scene(args), "solver", "petsc_options",
                           "'-snes_monitr -snes_max_it 30'")
    path, log = rs.run(args, text, "unused_options", extra=("-ksp_typo", "preonly"),
                       want_log=True)
    warning = next((line for line in log.splitlines() if "never used" in line), "")
    print(f"info: {warning}")
    for name, where in (("-snes_monitr", "petsc_options"), ("-ksp_typo", "command line")):
        checks.check(f"the warning names {name} ({where})",
                     0 if f"{name} ({where})" in warning else 1, 0)
    checks.check("an option the run reads is not named (-snes_max_it)",
                 0 if "-snes_max_it" not in warning else 1, 0)
    with h5py.File(path, "r") as f:
        stored = f.attrs.get("unused_petsc_options", "")
    checks.check("the root attribute holds the same list", 0 if stored and stored in warning
                 else 1, 0)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["fields", "xdmf", "units", "progress",
                                         "unused_options"])
    args = parser.parse_args()
    checks = rs.Checks()
    {"fields": fields, "xdmf": xdmf, "units": units, "progress": progress,
     "unused_options": unused_options}[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
