"""Shared helpers of the regression tests: run rodsolve on a scene text and read results.

A test builds its scene from an example in input/ (so the examples are what is tested), points
the output into its own working directory, runs `mpiexec -np N rodsolve scene.nml` and reads the
HDF5 file with h5py by dataset name (DESIGN.md §7).
"""
import argparse
import os
import re
import subprocess
import sys

import h5py
import numpy as np


def common_arguments(description):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--rodsolve", required=True, help="the rodsolve executable")
    parser.add_argument("--mpiexec", required=True, help="mpiexec of the MPI rodsolve uses")
    parser.add_argument("--source", required=True, help="the source tree (for input/)")
    parser.add_argument("--workdir", required=True, help="directory for scenes and results")
    return parser


def run_cases(description, cases):
    """The main program of a test script with several cases: the common arguments and a case
    name, then that case, cases[name](args, checks), and the verdict of its checks as the exit
    status."""
    parser = common_arguments(description)
    parser.add_argument("case", choices=list(cases))
    args = parser.parse_args()
    checks = Checks()
    cases[args.case](args, checks)
    checks.finish()


def read_example(source, name):
    with open(os.path.join(source, "input", name), encoding="utf-8") as f:
        return f.read()


def set_variable(text, group, variable, value):
    """Replace `variable = ...` (up to the next comma-free end of line or the next variable)
    inside the first `&group` of a scene text, or add it to the group."""
    start = re.search(r"^&" + group + r"\b", text, flags=re.M)
    if start is None:
        raise ValueError(f"no &{group} group")
    end = text.index("\n/", start.end())
    body = text[start.end():end]
    pattern = re.compile(r"\b" + variable + r"\s*=\s*[^=\n]*?(?=(,\s*[A-Za-z_]\w*\s*=)|\s*!|\s*$)",
                         flags=re.M)
    if pattern.search(body):
        body = pattern.sub(f"{variable} = {value}", body, count=1)
    else:
        body = body + f"\n    {variable} = {value}"
    return text[:start.end()] + body + text[end:]


def numbers(text, group, variable):
    """The values of `variable` (one or several, comma-separated) in the first &group of a
    scene text."""
    start = re.search(r"^&" + group + r"\b", text, flags=re.M)
    body = text[start.end():text.index("\n/", start.end())]
    value = r"[+\-]?[0-9.][0-9.eEdD+\-]*"
    found = re.search(r"\b" + variable + r"\s*=\s*(" + value + r"(?:\s*,\s*" + value + r")*)", body)
    return [float(v.replace("d", "e").replace("D", "e")) for v in found.group(1).split(",")]


def number(text, group, variable):
    """The (first) value of `variable` in the first &group of a scene text."""
    return numbers(text, group, variable)[0]


def cut_backs(log):
    """The cut-backs of a run, from its summary line ("N rejected (cut-backs)")."""
    return int(re.search(r"(\d+) rejected \(cut-backs\)", log).group(1))


def vector(values):
    return ", ".join(repr(float(v)) for v in values)


def run(args, text, name, ranks=1, extra=(), want_log=False):
    """Write scene `name`.nml with its output in the work directory, run it, return the path
    of the result file (and the run's log, standard output and error, with `want_log`)."""
    os.makedirs(args.workdir, exist_ok=True)
    output = os.path.join(args.workdir, name + ".h5")
    if os.path.exists(output):
        os.remove(output)
    text = set_variable(text, "output", "path", f"'{output}'")
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    command = [args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve, scene, *extra]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.stdout.write(result.stdout)
        sys.stderr.write(result.stderr)
        raise SystemExit(f"{' '.join(command)} failed with status {result.returncode}")
    if want_log:
        return output, result.stdout + result.stderr
    return output


def run_failing(args, text, name, ranks=1):
    """Write scene `name`.nml as given (its output path untouched), run it and return the exit
    status and everything it printed, for tests of how a run fails."""
    os.makedirs(args.workdir, exist_ok=True)
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve, scene],
                            capture_output=True, text=True)
    print(result.stdout + result.stderr)
    return result.returncode, result.stdout + result.stderr


def rod(path, name):
    """All datasets of /rods/<name> as numpy arrays, keyed by their path below the rod."""
    fields = {}
    with h5py.File(path, "r") as f:
        group = f["rods"][name]

        def visit(key, item):
            if isinstance(item, h5py.Dataset):
                fields[key] = item[()]
        group.visititems(visit)
    return fields


def time_function(kind, t, t_on=0.0, t_off=1.0):
    """f(t) of a &load time function, written here from the table of docs/user/input.md ("Loads
    and time functions"), not read from the program: the tests' own computation of the work."""
    t = np.asarray(t, dtype=float)
    x = (t - t_on) / (t_off - t_on)
    inside = (x > 0) & (x < 1)
    if kind == "constant":
        return np.ones_like(t)
    if kind == "ramp":
        return np.clip(x, 0.0, 1.0)
    if kind == "hat":
        return np.where(inside, 1 - np.abs(2 * x - 1), 0.0)
    if kind == "pulse":
        return np.where(inside, 0.5 * (1 - np.cos(2 * np.pi * x)), 0.0)
    if kind == "sine":
        return np.where(x > 0, np.sin(2 * np.pi * x), 0.0)
    raise ValueError(f"time function {kind!r} not written here")


def one_step_per_record(r):
    """The record times, after checking that every record ends exactly one step (stride 1 and
    no cut-back), so that a record's positions and directors are the step's ends."""
    t = r["time"]
    taken = r["series/dt"][1:]
    if not np.allclose(taken, np.diff(t), rtol=1e-9, atol=0.0):
        raise SystemExit("the work is computed per step: the run needs stride 1 and no cut-back")
    return t


def end_load_work(r, node, force, moment, factor):
    """Work of a dead force and moment f(t) (force, moment) on the node `node` over each step
    (index n for the step from record n to n + 1), computed from the stored positions and
    directors, independently of the program's external_work.

    The midpoint rule's exact discrete work (methods/ph_director_3d.md §5.3 item 1) is
    W_n = h [F(t_mid) . v_mid + M(t_mid) . 1/2 sum_i d_i,mid x v_i,mid]. The kinematic rows give
    h v_mid = phi_{n+1} - phi_n and h v_i,mid = d_i,n+1 - d_i,n (methods §5.2), and
    d_mid x (d_n+1 - d_n) = d_n x d_n+1 exactly, so
    W_n = f(t_mid) [F . (phi_{n+1} - phi_n) + M . 1/2 sum_i d_i,n x d_i,n+1]."""
    t = one_step_per_record(r)
    t_mid = 0.5 * (t[1:] + t[:-1])
    phi = r["position"][:, node, :]
    d = r["directors"][:, node, :, :]
    turn = 0.5 * np.sum(np.cross(d[:-1], d[1:]), axis=1)
    return factor(t_mid) * (np.diff(phi, axis=0) @ np.asarray(force, float)
                            + turn @ np.asarray(moment, float))


class Checks:
    """Named checks with their measured values, printed as a table; exit status 1 if any
    failed (DESIGN.md §8: a test asserts something that can fail)."""

    def __init__(self):
        self.failed = 0

    def check(self, name, measured, bound):
        ok = bool(np.isfinite(measured) and measured <= bound)
        self.failed += 0 if ok else 1
        print(f"{'ok  ' if ok else 'FAIL'} {name}: {measured:.3e} (bound {bound:.1e})")

    def finish(self):
        print(f"{self.failed} check(s) failed")
        sys.exit(1 if self.failed else 0)


def run_restart(args, text, name, output, ranks=1):
    """Like `run`, but the scene continues another run (restart_from) into `output`, which may
    be the restart file itself, so nothing is removed first."""
    text = set_variable(text, "output", "path", f"'{output}'")
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    command = [args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve, scene]
    result = subprocess.run(command, capture_output=True, text=True)
    print(result.stdout + result.stderr)
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed with status {result.returncode}")
    return output
