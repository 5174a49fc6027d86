#!/usr/bin/env python3
"""The result file as a checkpoint (DESIGN.md §7; issue 5 items 3 and 5).

    checkpoint.py sigkill          a run killed with SIGKILL a few steps after a flush leaves a
                                   file that h5py opens with every record up to that flush,
                                   equal to an uninterrupted run's
    checkpoint.py restart          the killed run continued with restart_from (into a new file)
                                   ends in the uninterrupted run's final state (1e-12), and its
                                   file holds the uninterrupted run's records (1e-12)
    checkpoint.py restart_in_place the same, continuing in the killed file itself
    checkpoint.py restart_ranks    two rods on 2 ranks (parallel HDF5), interrupted by a short
                                   t_end and continued to the full one: the same final state
    checkpoint.py restart_refused  a restart of another scene is refused, naming the first
                                   variable that differs (dt, a stiffness), and so is a
                                   checkpoint off the step grid (a last step cut short at
                                   t_end); a later t_end and another title are accepted; the
                                   restart file is left as it was (issue 21 item 7; the planar
                                   spaghetti of input/, for speed)

The scene is the flying spaghetti of input/ (methods/ph_director_3d.md §6.1), shortened.
"""
import os
import signal
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import run_scene as rs  # noqa: E402

ROD = "spaghetti"
FLUSH_EVERY = 10
KILL_FLUSH = 30   # the flush after which the run is killed ...
KILL_STEP = 33    # ... once this step is done (records of steps 31-33 are not in the file)


def scene(args, t_end="6.0"):
    text = rs.read_example(args.source, "flying_spaghetti.nml")
    text = rs.set_variable(text, "time", "t_end", t_end)
    text = rs.set_variable(text, "output", "flush_every", str(FLUSH_EVERY))
    return text


def two_rods(text):
    rod = text[text.index("&rod"):text.index("/", text.index("&rod")) + 1]
    load = text[text.index("&load"):text.index("/", text.index("&load")) + 1]
    second = rod.replace("'spaghetti'", "'second'")
    second_load = load.replace("'spaghetti'", "'second'").replace("force = 20.0", "force = -20.0")
    return text + "\n" + second + "\n" + second_load + "\n"


def killed_run(args, text, name):
    """Run `text` on one rank (no mpiexec, so the signal reaches rodsolve itself) and kill it
    with SIGKILL once step KILL_STEP is done after the flush of step KILL_FLUSH."""
    os.makedirs(args.workdir, exist_ok=True)
    output = os.path.join(args.workdir, name + ".h5")
    for stale in (output, output[:-3] + ".xdmf"):
        if os.path.exists(stale):
            os.remove(stale)
    text = rs.set_variable(text, "output", "path", f"'{output}'")
    text = rs.set_variable(text, "run", "log_level", "'debug'")
    path = os.path.join(args.workdir, name + ".nml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    process = subprocess.Popen([args.rodsolve, path], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    flushed = False
    killed = False
    for line in process.stdout:
        if f"flushed after step {KILL_FLUSH}" in line:
            flushed = True
        if flushed and f"step {KILL_STEP} done" in line:
            process.send_signal(signal.SIGKILL)
            killed = True
            break
    process.wait()
    if not killed:
        raise SystemExit(f"the run ended (status {process.returncode}) before it could be killed")
    print(f"info: killed after step {KILL_STEP} (status {process.returncode})")
    return output, text


def final_state(path, name=ROD):
    with h5py.File(path, "r") as f:
        g = f["rods"][name]
        return {key: g[key][-1] for key in ("position", "directors", "velocity", "stress")}, \
            g["time"][-1]


def compare_records(checks, what, path, reference, name=ROD):
    """Every dataset of the rod against the uninterrupted run: same shape, and values within
    1e-12 relative to max(1, |dataset|) (the balance error relative to max |H|). Not bitwise:
    the restarted Newton iterations agree only to round-off (docs/user/output.md)."""
    got, ref = rs.rod(path, name), rs.rod(reference, name)
    shapes = [key for key in ref if key not in got or got[key].shape != ref[key].shape]
    checks.check(f"{what}: datasets missing or of another shape than the uninterrupted run's",
                 float(len(shapes)), 0.0)
    worst, worst_key = 0.0, ""
    for key in ref:
        if key in shapes:
            continue
        a, b = np.asarray(got[key], dtype=float), np.asarray(ref[key], dtype=float)
        if key == "series/newton/iterations":
            continue
        scale = max(1.0, float(np.max(np.abs(b), initial=0.0)))
        if key == "series/energy/balance_error":
            # A round-off residual: its scale is the energy it balances.
            scale = max(scale, float(np.max(np.abs(ref["series/energy/total"]))))
        difference = float(np.max(np.abs(a - b), initial=0.0)) / scale
        if difference > worst:
            worst, worst_key = difference, key
    print(f"info: {what}: {len(ref)} datasets compared; largest relative difference in {worst_key!r}")
    checks.check(f"{what}: largest difference of any record from the uninterrupted run "
                 "(relative to max(1, |dataset|))", worst, 1e-12)


def check_final(checks, what, path, reference, name=ROD):
    got, t_got = final_state(path, name)
    ref, t_ref = final_state(reference, name)
    checks.check(f"{what}: final time minus the uninterrupted run's", abs(t_got - t_ref), 0.0)
    for key in ref:
        scale = max(1.0, float(np.max(np.abs(ref[key]))))
        checks.check(f"{what}: final {key}, largest difference / max(1, |value|)",
                     float(np.max(np.abs(got[key] - ref[key]))) / scale, 1e-12)


def sigkill(args, checks):
    text = scene(args)
    reference = rs.run(args, text, "uninterrupted")
    killed, _ = killed_run(args, text, "killed")
    with h5py.File(killed, "r") as f:
        g = f["rods"][ROD]
        n_records = g["time"].shape[0]
        checkpoint_step = int(f["checkpoint"][ROD]["step"][0])
        status = f.attrs.get("status", "(none)")
    print(f"info: the killed file opens; {n_records} records, checkpoint after step "
          f"{checkpoint_step}, status {status!r}")
    checks.check("records in the killed file minus (initial + steps 1..KILL_FLUSH)",
                 abs(n_records - (KILL_FLUSH + 1)), 0.0)
    checks.check("checkpoint step minus KILL_FLUSH", abs(checkpoint_step - KILL_FLUSH), 0.0)
    with h5py.File(reference, "r") as f:
        ref = {key: f["rods"][ROD][key][:KILL_FLUSH + 1] for key in ("time", "position",
                                                                       "stress")}
    with h5py.File(killed, "r") as f:
        differences = [key for key in ref if not np.array_equal(f["rods"][ROD][key][()],
                                                                ref[key])]
    checks.check("datasets of the killed file that differ from the uninterrupted run's first "
                 "records", float(len(differences)), 0.0)


def restart(args, checks, in_place):
    text = scene(args)
    reference = rs.run(args, text, "uninterrupted")
    killed, killed_text = killed_run(args, text, "killed_in_place" if in_place else "killed")
    name = "killed_in_place" if in_place else "restarted"
    output = killed if in_place else os.path.join(args.workdir, "restarted.h5")
    continued = rs.set_variable(killed_text, "run", "restart_from", f"'{killed}'")
    continued = rs.set_variable(continued, "run", "log_level", "'info'")
    path = rs.run_restart(args, continued, name + "_continued", output)
    check_final(checks, name, path, reference)
    compare_records(checks, name, path, reference)
    with h5py.File(path, "r") as f:
        checks.check(f"{name}: /series/time differs from the uninterrupted run's",
                     float(not np.array_equal(f["series"]["time"][()],
                                              h5py.File(reference, "r")["series"]["time"][()])),
                     0.0)
        checks.check(f"{name}: status is 'completed'", float(f.attrs["status"] != "completed"),
                     0.0)


def restart_ranks(args, checks):
    full = two_rods(scene(args, "4.0"))
    reference = rs.run(args, full, "ranks_uninterrupted", ranks=2)
    short = rs.set_variable(full, "time", "t_end", "2.0")
    first = rs.run(args, short, "ranks_first_part", ranks=2)
    continued = rs.set_variable(full, "run", "restart_from", f"'{first}'")
    path = rs.run_restart(args, continued, "ranks_continued",
                          os.path.join(args.workdir, "ranks_continued.h5"), ranks=2)
    for name in (ROD, "second"):
        check_final(checks, f"2 ranks, rod {name}", path, reference, name)
        compare_records(checks, f"2 ranks, rod {name}", path, reference, name)


def restart_refused(args, checks):
    text = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    first = rs.run(args, rs.set_variable(text, "time", "t_end", "1.0"), "refused_first")
    with open(first, "rb") as f:
        before = f.read()
    later = rs.set_variable(text, "time", "t_end", "2.0")
    later = rs.set_variable(later, "run", "restart_from", f"'{first}'")
    cases = [("dt", rs.set_variable(later, "time", "dt", "0.05"),
              "&time dt: 0.1 in the checkpoint's scene, 0.05 in this one"),
             ("EA", later.replace("EA = 1e4", "EA = 2e4"),
              "&rod 'spaghetti' EA: 10000.0 in the checkpoint's scene, 20000.0 in this one")]
    for what, changed, expected in cases:
        output = os.path.join(args.workdir, f"refused_{what}.h5")
        status, log = rs.run_failing(args, rs.set_variable(changed, "output", "path",
                                                           f"'{output}'"), f"refused_{what}")
        checks.check(f"changed {what}: exit status - 1", abs(status - 1), 0)
        checks.check(f"changed {what}: the message names it", 0 if expected in log else 1, 0)
    with open(first, "rb") as f:
        checks.check("the restart file is unchanged", 0 if f.read() == before else 1, 0)
    accepted = rs.set_variable(later, "run", "title", "'the same scene, later'")
    path = rs.run_restart(args, accepted, "refused_accepted",
                          os.path.join(args.workdir, "refused_accepted.h5"))
    with h5py.File(path, "r") as f:
        checks.check("a later t_end and another title: continued to t = 2",
                     abs(float(f["rods/spaghetti/time"][-1]) - 2.0), 1e-12)
    # A last step cut short: t_end = 1.05 with dt = 0.1 ends at t = 1.05, not on the grid.
    short = rs.run(args, rs.set_variable(text, "time", "t_end", "1.05"), "refused_short")
    off_grid = rs.set_variable(text, "time", "t_end", "1.05")
    off_grid = rs.set_variable(off_grid, "run", "restart_from", f"'{short}'")
    off_grid = rs.set_variable(off_grid, "time", "t_end", "2.0")
    output = os.path.join(args.workdir, "refused_off_grid.h5")
    status, log = rs.run_failing(args, rs.set_variable(off_grid, "output", "path", f"'{output}'"),
                                 "refused_off_grid")
    checks.check("off the step grid: exit status - 1", abs(status - 1), 0)
    checks.check("off the step grid: the message says so", 0 if "not on the step grid" in log
                 else 1, 0)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["sigkill", "restart", "restart_in_place",
                                         "restart_ranks", "restart_refused"])
    args = parser.parse_args()
    checks = rs.Checks()
    if args.case == "sigkill":
        sigkill(args, checks)
    elif args.case == "restart":
        restart(args, checks, in_place=False)
    elif args.case == "restart_in_place":
        restart(args, checks, in_place=True)
    elif args.case == "restart_refused":
        restart_refused(args, checks)
    else:
        restart_ranks(args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
