#!/usr/bin/env python3
"""Faults a cluster user meets (issue 21; docs/user/output.md "An existing file"): each case
failed on the code before the fix.

    faults.py two_runs        a second run of the same output path, started while the first
                              runs, stops at once with a message naming the other run and
                              touches nothing; the first completes with every record
                              (item 1); the lock file is gone afterwards; rodplot on the
                              file meanwhile says it is in use (item 20)
    faults.py merge_running   `rodsolve --merge` of a sweep that is still running is refused and
                              deletes nothing; the sweep completes with every member (item 2)
    faults.py overwrite       the output path is the scene itself, a text file, an HDF5 file
                              rodsolve did not write, or a directory: each is refused and left
                              byte for byte as it was; a result of rodsolve is replaced (item 4;
                              item 20's "disk full?" for a directory)
    faults.py killed_sweep    a sweep killed after a few members leaves no result file of the
                              previous sweep of its path, marked completed, beside its members
                              (item 5)
    faults.py merge_edited    `rodsolve --merge` with the sweep's scene edited after the sweep was
                              killed (other EI1 values) is refused naming the member and the
                              variable, and leaves the members as they were; --merge with the
                              scene the sweep ran merges them (item 8)
    faults.py sigterm         SIGTERM (a job's time limit) ends a run after its current step
                              with a last flush, status 'interrupted' and exit status 143;
                              restart_from continues it to the end; on 2 ranks, SIGTERM to
                              every rank (as a batch system sends it) stops both at one step
                              the same way; SIGTERM to mpiexec (which kills its ranks) leaves
                              no rank running and the records up to the last flush (item 18)
    faults.py scene_from_pipe a scene read from a FIFO (written by another program) runs like
                              the same scene from a file (item 19; it read as "no &rod group");
                              rank 0 reads it and shares it, so any rank count works
    faults.py not_relaxed     a relaxation run (statics by damped dynamics) that has not relaxed
                              by t_end ends with status 'not relaxed' and exit status 3, not
                              'completed' and 0; one that relaxes still completes (item 14)
    faults.py disk_full       a full disk (a small tmpfs, or a file-size limit where mounting is
                              not allowed) stops a run on 1 and on 2 ranks within the time
                              limit (2 ranks spun forever), exit status 1, with a message that
                              names the path and the system's reason; the file opens, has
                              status 'failed', and every record it lists equals the same
                              record of a run on a disk with room (they held zeros), with the
                              checkpoint at its last record; an XDMF sidecar rank 0 cannot
                              write stops both ranks the same way (item 3)
    faults.py corrupted_checkpoint
                              a byte changed on disk in a checkpoint's state (1 and 2 ranks)
                              makes restart_from stop with a message that says the checkpoint
                              is corrupted; the intact file restarts; a checkpoint of schema 1
                              (/internal) is refused with its reason; on 1 rank a changed byte in
                              a record's chunk is found by any reader (Fletcher-32) (item 21)
    faults.py flush_every_memory
                              a 5-step run with flush_every = 1000000 stays under 200 MB peak
                              memory (it preallocated 3.2 GB) (item 17)
    faults.py nan_at_start    a run of each formulation (ph_director, ph_planar, cl_em_planar,
                              se3_pg, se3_strand) whose end load (1e300) breaks its first step
                              fails with status 'failed' and a file without NaN or Inf: the
                              failed rod records its last good state, t = 0 (se3_strand
                              accepted a non-finite step and recorded it) (item 20)
"""
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import threading
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "regression"))
import run_scene as rs  # noqa: E402

# Long enough that the second process starts (about 0.5 s) well inside the first one's run.
LONG_STEPS = 200000


def write_scene(args, name, text, output):
    os.makedirs(args.workdir, exist_ok=True)
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(rs.set_variable(text, "output", "path", f"'{output}'"))
    return scene


def long_strand(args):
    """Seed 004's vibrating tube over LONG_STEPS steps (a few seconds), first and last record."""
    text = rs.read_example(args.source, "strand_vibration.nml")
    dt = 5.925872307404123e-4
    text = rs.set_variable(text, "time", "t_end", repr(LONG_STEPS * dt))
    text = rs.set_variable(text, "output", "stride", str(LONG_STEPS))
    return rs.set_variable(text, "output", "flush_every", str(LONG_STEPS))


def wait_for(path, process, seconds=60.0):
    """Wait until `path` exists (or the process ended); whether it does."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and process.poll() is None:
        if os.path.exists(path):
            return True
        time.sleep(0.01)
    return os.path.exists(path)


def run(args, scene, *extra):
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, *extra,
                             scene], capture_output=True, text=True)
    print(result.stdout[-600:] + result.stderr[-600:])
    return result.returncode, result.stdout + result.stderr


def two_runs(args, checks):
    output = os.path.join(args.workdir, "shared.h5")
    for stale in (output, output + ".lock"):
        if os.path.exists(stale):
            os.remove(stale)
    first = write_scene(args, "first", long_strand(args), output)
    second = write_scene(args, "second", long_strand(args), output)
    # One rank without mpiexec, so that this process is rodsolve itself.
    process = subprocess.Popen([args.rodsolve, first], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    locked = wait_for(output + ".lock", process)
    checks.check("the first run holds the lock file", 0 if locked else 1, 0)
    status, log = run(args, second)
    # rodplot on the file being written: it says the file is in use, not "not an HDF5 file"
    # (item 20).
    plot = subprocess.run([sys.executable, os.path.join(args.source, "scripts", "rodplot.py"),
                           "summary", output], capture_output=True, text=True)
    print(plot.stderr[-400:])
    checks.check("rodplot on the file being written: exit status - 2", abs(plot.returncode - 2), 0)
    checks.check("rodplot says the file is open in another program",
                 0 if "open in another program" in plot.stderr else 1, 0)
    running = process.poll() is None
    checks.check("the first run was still running when the second stopped", 0 if running else 1, 0)
    checks.check("exit status of the second run - 1", abs(status - 1), 0)
    checks.check("the second run names the other run",
                 0 if "being written by another run" in log and "first.nml" in log else 1, 0)
    first_log, _ = process.communicate()
    checks.check("exit status of the first run", process.returncode, 0)
    if process.returncode != 0:
        print(first_log[-1000:])
    with h5py.File(output, "r") as f:
        status_attr = f.attrs.get("status", "")
        records = f["rods/tube/time"].shape[0]
        command = f.attrs["command_line"]
    checks.check("the file's status is 'completed'", 0 if status_attr == "completed" else 1, 0)
    checks.check("records of the first run - 2 (first and last)", abs(records - 2), 0)
    checks.check("the file is the first run's", 0 if "first.nml" in command else 1, 0)
    checks.check("the lock file is removed at the end", 1 if os.path.exists(output + ".lock") else 0,
                 0)


def long_sweep(args, members):
    text = rs.read_example(args.source, "sweep_cantilever.nml")
    text = rs.set_variable(text, "time", "dt", "0.0025")
    text = rs.set_variable(text, "time", "quasistatic", ".false.")
    text = rs.set_variable(text, "output", "stride", "400")
    return rs.set_variable(text, "sweep", "logspace", f"1.0, 100.0, {members}")


def ledger_lines(ledger):
    if not os.path.exists(ledger):
        return 0
    with open(ledger, encoding="utf-8") as f:
        return sum(1 for line in f if line.strip())


def killed_sweep_run(args, scene, output, members):
    """Run the sweep `scene` (rodsolve itself, one rank) and SIGKILL it once its ledger
    lists `members` finished members; whether the kill ended it."""
    ledger = output + ".members/ledger_rank0.txt"
    process = subprocess.Popen([args.rodsolve, scene], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    while process.poll() is None and ledger_lines(ledger) < members:
        time.sleep(0.005)
    process.send_signal(signal.SIGKILL)
    process.wait()
    return process.returncode == -signal.SIGKILL


def merge_running(args, checks):
    output = os.path.join(args.workdir, "running.h5")
    if os.path.exists(output):
        os.remove(output)
    scene = write_scene(args, "running", long_sweep(args, 64), output)
    ledger = output + ".members/ledger_rank0.txt"
    process = subprocess.Popen([args.rodsolve, scene], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    deadline = time.monotonic() + 60.0
    while process.poll() is None and ledger_lines(ledger) < 1 and time.monotonic() < deadline:
        time.sleep(0.01)
    members_before = sorted(os.listdir(output + ".members"))
    status, log = run(args, scene, "--merge")
    running = process.poll() is None
    checks.check("the sweep was still running when --merge stopped", 0 if running else 1, 0)
    checks.check("exit status of --merge - 1", abs(status - 1), 0)
    checks.check("--merge says the output is being written",
                 0 if "being written by another run" in log else 1, 0)
    members_after = (os.listdir(output + ".members") if os.path.isdir(output + ".members")
                     else [])
    left = set(members_before) - set(members_after) if running else set()
    checks.check("member files --merge deleted", len(left), 0)
    sweep_log, _ = process.communicate()
    checks.check("exit status of the sweep", process.returncode, 0)
    if process.returncode != 0:
        print(sweep_log[-1000:])
    with h5py.File(output, "r") as f:
        codes = f["summary/status"][()]
        root = f.attrs["status"]
    checks.check("members not completed", int((codes != 0).sum()), 0)
    checks.check("members in the summary - 64", abs(len(codes) - 64), 0)
    checks.check("the sweep's status is 'completed'", 0 if root == "completed" else 1, 0)


def overwrite(args, checks):
    text = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    text = rs.set_variable(text, "time", "t_end", "0.5")
    os.makedirs(args.workdir, exist_ok=True)

    def refused(name, target, expected, scene=None):
        """Run a scene whose output is `target` (the scene `scene` if given, else one written
        here): refused with `expected` in the message, `target` unchanged."""
        if scene is None:
            scene = write_scene(args, name, text, target)
        before = open(target, "rb").read() if os.path.isfile(target) else None
        status, log = run(args, scene)
        checks.check(f"{name}: exit status - 1", abs(status - 1), 0)
        checks.check(f"{name}: the message says '{expected}'", 0 if expected in log else 1, 0)
        after = open(target, "rb").read() if os.path.isfile(target) else None
        checks.check(f"{name}: the file is unchanged", 0 if after == before else 1, 0)

    itself = os.path.join(args.workdir, "itself.nml")
    with open(itself, "w", encoding="utf-8") as f:
        f.write(rs.set_variable(text, "output", "path", f"'{itself}'"))
    refused("scene_itself", itself, "is the scene file itself", scene=itself)
    notes = os.path.join(args.workdir, "notes.txt")
    with open(notes, "w", encoding="utf-8") as f:
        f.write("results I care about\n")
    refused("text_file", notes, "is not an HDF5 file")
    foreign = os.path.join(args.workdir, "foreign.h5")
    with h5py.File(foreign, "w") as f:
        f["data"] = [1.0, 2.0, 3.0]
    refused("foreign_hdf5", foreign, "rodsolve did not write")
    directory = os.path.join(args.workdir, "a_directory")
    os.makedirs(directory, exist_ok=True)
    refused("directory", directory, "is a directory")
    # A result of rodsolve is replaced by the new run (the documented default).
    result = os.path.join(args.workdir, "result.h5")
    scene = write_scene(args, "replaced_1", text, result)
    first, _ = run(args, scene)
    scene = write_scene(args, "replaced_2", rs.set_variable(text, "time", "t_end", "0.3"), result)
    second, _ = run(args, scene)
    checks.check("a rodsolve result: both runs succeed", abs(first) + abs(second), 0)
    with h5py.File(result, "r") as f:
        command = f.attrs["command_line"]
        records = f["rods/spaghetti/time"].shape[0]
    checks.check("a rodsolve result: replaced by the second run",
                 0 if "replaced_2.nml" in command else 1, 0)
    checks.check("a rodsolve result: records of the second run - 4", abs(records - 4), 0)


def killed_sweep(args, checks):
    output = os.path.join(args.workdir, "again.h5")
    if os.path.exists(output):
        os.remove(output)
    short = rs.set_variable(rs.read_example(args.source, "sweep_cantilever.nml"), "sweep",
                            "logspace", "1.0, 100.0, 4")
    scene = write_scene(args, "again", short, output)
    status, _ = run(args, scene)
    with h5py.File(output, "r") as f:
        before = f.attrs["status"]
    checks.check("the first sweep completed", abs(status) + (0 if before == "completed" else 1), 0)
    scene = write_scene(args, "again", long_sweep(args, 64), output)
    killed = killed_sweep_run(args, scene, output, 2)
    checks.check("the second sweep was killed (SIGKILL)", 0 if killed else 1, 0)
    stale = False
    if os.path.exists(output):
        with h5py.File(output, "r") as f:
            stale = f.attrs.get("status", "") == "completed"
    checks.check("a result file marked completed beside the killed sweep's members",
                 1 if stale else 0, 0)


def running(pid):
    """Whether process `pid` exists and is not a zombie."""
    try:
        with open(f"/proc/{pid}/status", encoding="utf-8") as f:
            state = next(line for line in f if line.startswith("State:"))
    except (OSError, StopIteration):
        return False
    return state.split()[1] not in ("Z", "X")


def children(pid):
    """The processes `pid` started (mpiexec's ranks on this host)."""
    found = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True).stdout
    return [int(p) for p in found.split()]


def merge_edited(args, checks):
    output = os.path.join(args.workdir, "edited.h5")
    if os.path.exists(output):
        os.remove(output)
    text = long_sweep(args, 64)
    scene = write_scene(args, "edited", text, output)
    killed = killed_sweep_run(args, scene, output, 3)
    checks.check("the sweep was killed (SIGKILL)", 0 if killed else 1, 0)
    members = sorted(os.listdir(output + ".members"))
    edited = write_scene(args, "edited", rs.set_variable(text, "sweep", "logspace",
                                                         "2.0, 200.0, 64"), output)
    status, log = run(args, edited, "--merge")
    checks.check("--merge with an edited scene: exit status - 1", abs(status - 1), 0)
    checks.check("... names the member and the variable",
                 0 if "member 1 was computed from another scene" in log and "EI1" in log else 1,
                 0)
    checks.check("... leaves the members as they were",
                 0 if sorted(os.listdir(output + ".members")) == members else 1, 0)
    checks.check("... writes no result file", 1 if os.path.exists(output) else 0, 0)
    original = write_scene(args, "edited", text, output)
    status, _ = run(args, original, "--merge")
    with h5py.File(output, "r") as f:
        done = int((f["summary/status"][()] == 0).sum())
    checks.check("--merge with the scene the sweep ran: exit status", status, 0)
    checks.check("... merged the finished members (at least 3)", 0 if done >= 3 else 1, 0)


def interrupted(args, checks, name, command, ranks_text):
    """Start `command` (its scene writes `name`.h5 at debug level), send SIGTERM once a flush
    is done (to rodsolve itself, or to every rank as a batch system does), and check how it
    ends."""
    output = os.path.join(args.workdir, name + ".h5")
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True)
    log = []
    for line in process.stdout:
        log.append(line)
        if "flushed after step" in line:
            if command[0] == args.rodsolve:
                process.send_signal(signal.SIGTERM)
            else:
                for rank in children(process.pid):
                    os.kill(rank, signal.SIGTERM)
            break
    rest, _ = process.communicate(timeout=120)
    log = "".join(log) + rest
    print(log[-1500:])
    checks.check(f"{ranks_text}: exit status is non-zero (128 + 15 = 143 for rodsolve itself)",
                 0 if process.returncode != 0 else 1, 0)
    if command[0] == args.rodsolve:
        checks.check(f"{ranks_text}: exit status - 143", abs(process.returncode - 143), 0)
    checks.check(f"{ranks_text}: the log says it was interrupted",
                 0 if "interrupted by SIGTERM" in log else 1, 0)
    with h5py.File(output, "r") as f:
        status = f.attrs.get("status", "")
        step = int(f["checkpoint/tube/step"][0])
        records = f["rods/tube/time"].shape[0]
    checks.check(f"{ranks_text}: the file's status is 'interrupted'",
                 0 if status == "interrupted" else 1, 0)
    checks.check(f"{ranks_text}: stopped before the end", 0 if 0 < step < LONG_STEPS else 1, 0)
    checks.check(f"{ranks_text}: records - (step + 1) at stride 1", abs(records - (step + 1)), 0)
    return output


def sigterm(args, checks):
    text = long_strand(args)
    text = rs.set_variable(text, "output", "stride", "1")
    text = rs.set_variable(text, "output", "flush_every", "2000")
    text = rs.set_variable(text, "run", "log_level", "'debug'")
    output = os.path.join(args.workdir, "interrupted.h5")
    for stale in (output, output + ".lock"):
        if os.path.exists(stale):
            os.remove(stale)
    scene = write_scene(args, "interrupted", text, output)
    interrupted(args, checks, "interrupted", [args.rodsolve, scene], "1 rank")
    short = rs.set_variable(text, "time", "t_end", repr(6000 * 5.925872307404123e-4))
    short = rs.set_variable(short, "run", "log_level", "'info'")
    short = rs.set_variable(short, "run", "restart_from", f"'{output}'")
    scene = write_scene(args, "interrupted_continued", short, output)
    status, _ = run(args, scene)
    with h5py.File(output, "r") as f:
        checks.check("restart_from continues the interrupted run to its end: exit status",
                     status, 0)
        checks.check("... status 'completed'", 0 if f.attrs.get("status", "") == "completed"
                     else 1, 0)
        checks.check("... records - 6001", abs(f["rods/tube/time"].shape[0] - 6001), 0)
    # Two rods on two ranks under mpiexec: SIGTERM to mpiexec reaches both ranks.
    def group(name):
        start = re.search(r"^&" + name + r"\b", text, flags=re.M).start()
        return text[start:text.index("\n/", start) + 2]
    two = (text + "\n" + group("rod").replace("name = 'tube'", "name = 'other'") + "\n"
           + group("bc").replace("rod = 'tube'", "rod = 'other'"))
    output = os.path.join(args.workdir, "interrupted_ranks.h5")
    for stale in (output, output + ".lock"):
        if os.path.exists(stale):
            os.remove(stale)
    scene = write_scene(args, "interrupted_ranks", two, output)
    interrupted(args, checks, "interrupted_ranks",
                [args.mpiexec, "--oversubscribe", "-np", "2", args.rodsolve, scene], "2 ranks")
    # SIGTERM to mpiexec itself: Open MPI kills the ranks at once (no time for a flush), and
    # none may be left running; the file keeps every record up to its last flush.
    os.remove(output)
    process = subprocess.Popen([args.mpiexec, "--oversubscribe", "-np", "2", args.rodsolve,
                                scene], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True)
    for line in process.stdout:
        if "flushed after step" in line:
            ranks = children(process.pid)
            process.send_signal(signal.SIGTERM)
            break
    process.communicate(timeout=120)
    deadline = time.monotonic() + 10.0
    while any(running(r) for r in ranks) and time.monotonic() < deadline:
        time.sleep(0.05)
    checks.check("SIGTERM to mpiexec: ranks still running 10 s after it ended",
                 sum(running(r) for r in ranks), 0)
    with h5py.File(output, "r") as f:
        step = int(f["checkpoint/tube/step"][0])
        records = f["rods/tube/time"].shape[0]
    checks.check("SIGTERM to mpiexec: records - (last flushed step + 1)", abs(records - (step + 1)),
                 0)


def scene_from_pipe(args, checks):
    text = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    text = rs.set_variable(text, "time", "t_end", "0.5")
    os.makedirs(args.workdir, exist_ok=True)
    output = os.path.join(args.workdir, "piped.h5")
    text = rs.set_variable(text, "output", "path", f"'{output}'")
    fifo = os.path.join(args.workdir, "scene.fifo")
    if os.path.exists(fifo):
        os.remove(fifo)
    os.mkfifo(fifo)

    def feed():
        with open(fifo, "w", encoding="utf-8") as f:
            f.write(text)
    writer = threading.Thread(target=feed)
    writer.start()
    status, log = run(args, fifo)
    writer.join(timeout=60)
    checks.check("a scene from a FIFO: exit status", status, 0)
    with h5py.File(output, "r") as f:
        records = f["rods/spaghetti/time"].shape[0]
    checks.check("a scene from a FIFO: records - 6 (t = 0 and 5 steps)", abs(records - 6), 0)


def not_relaxed(args, checks):
    text = rs.read_example(args.source, "bend45_strand.nml")
    # Seed 004's bend relaxes in 28 steps of 10 s (docs/performance.md); 3 steps do not.
    for name, t_end, status, expected in (("unrelaxed", "30.0", 3, "not relaxed"),
                                          ("relaxed", "1000.0", 0, "completed")):
        output = os.path.join(args.workdir, name + ".h5")
        scene = write_scene(args, name, rs.set_variable(text, "time", "t_end", t_end), output)
        code, log = run(args, scene)
        checks.check(f"{name}: exit status - {status}", abs(code - status), 0)
        with h5py.File(output, "r") as f:
            got = f.attrs.get("status", "")
        checks.check(f"{name}: the file's status is '{expected}'", 0 if got == expected else 1, 0)
        if status:
            checks.check(f"{name}: the log says it did not relax",
                         0 if "did not relax by t_end" in log else 1, 0)


STRAND_DT = 5.925872307404123e-4


def two_rods(text):
    """The scene with a second rod 'other', a copy of 'tube' (one rod per rank on 2 ranks)."""
    def group(name):
        start = re.search(r"^&" + name + r"\b", text, flags=re.M).start()
        return text[start:text.index("\n/", start) + 2]
    return (text + "\n" + group("rod").replace("name = 'tube'", "name = 'other'") + "\n"
            + group("bc").replace("rod = 'tube'", "rod = 'other'"))


def small_file_system(directory, megabytes):
    """Mount a tmpfs of `megabytes` MB at `directory`; whether it worked (root only)."""
    os.makedirs(directory, exist_ok=True)
    subprocess.run(["umount", directory], capture_output=True)
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={megabytes}m", "tmpfs",
                              directory], capture_output=True)
    return mounted.returncode == 0


def disk_full(args, checks):
    """A strand at stride 1 with a flush every 100 steps (600 KB of records per rod and flush)
    on a 2 MB file system: the disk is full after a few flushes."""
    text = rs.read_example(args.source, "strand_vibration.nml")
    text = rs.set_variable(text, "time", "t_end", repr(3000 * STRAND_DT))
    text = rs.set_variable(text, "output", "stride", "1")
    text = rs.set_variable(text, "output", "flush_every", "100")
    text = rs.set_variable(text, "output", "xdmf", ".false.")
    small = os.path.join(args.workdir, "small")
    mounted = small_file_system(small, 2)
    limit = None
    env = dict(os.environ)
    if not mounted:
        # No mount allowed: a file-size limit of 2 MB instead (EFBIG rather than ENOSPC). MPI's
        # shared-memory files must not meet it: PMIx keeps its store in memory, and the ranks
        # talk over TCP.
        os.makedirs(small, exist_ok=True)
        limit = 2 * 1024 * 1024
        env.update({"PMIX_MCA_gds": "hash", "OMPI_MCA_btl": "self,tcp"})
    print(f"full disk: {'a 2 MB tmpfs' if mounted else 'a 2 MB file-size limit'}")

    def limited():
        if limit is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    try:
        for ranks, scene_text in ((1, text), (2, two_rods(text))):
            name = f"full_{ranks}"
            output = os.path.join(small, name + ".h5")
            for stale in os.listdir(small):
                os.remove(os.path.join(small, stale))
            scene = write_scene(args, name, scene_text, output)
            command = [args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve, scene]
            started = time.monotonic()
            process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                       text=True, preexec_fn=limited, env=env,
                                       start_new_session=True)
            try:
                log, _ = process.communicate(timeout=60)
                hung = False
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                log, _ = process.communicate()
                hung = True
            print(log[-1500:])
            what = f"{ranks} rank(s)"
            checks.check(f"{what}: ended within 60 s (did not hang)", 1 if hung else 0, 0)
            checks.check(f"{what}: exit status - 1", abs(process.returncode - 1), 0)
            reason = "No space left on device" if mounted else "File too large"
            checks.check(f"{what}: the message names the path and '{reason}'",
                         0 if output in log and reason in log else 1, 0)
            checks.check(f"{what}: the message says the status is 'failed'",
                         0 if "with status 'failed'" in log else 1, 0)
            print(f"{what}: {time.monotonic() - started:.1f} s")
            # The same scene on the work directory's disk, stopped at the same step: its
            # records are the reference for every record the full disk's file lists.
            with h5py.File(output, "r") as f:
                status = f.attrs.get("status", "")
                rods = list(f["rods"])
                records = {r: f[f"rods/{r}/time"].shape[0] for r in rods}
                step = {r: int(f[f"checkpoint/{r}/step"][0]) for r in rods}
                listed = {r: int(f[f"checkpoint/{r}/records"][0]) for r in rods}
            checks.check(f"{what}: the file's status is 'failed'", 0 if status == "failed" else 1,
                         0)
            n = min(records.values())
            checks.check(f"{what}: records were written before the disk was full (> 1)",
                         0 if n > 1 else 1, 0)
            for r in rods:
                checks.check(f"{what}, rod {r}: checkpoint records - records in the file",
                             abs(listed[r] - records[r]), 0)
                checks.check(f"{what}, rod {r}: records - (checkpoint step + 1) at stride 1",
                             abs(records[r] - (step[r] + 1)), 0)
            # A few steps more: the last step of a run may be cut to its t_end.
            roomy = rs.set_variable(scene_text, "time", "t_end", repr((n + 5) * STRAND_DT))
            reference = write_scene(args, name + "_reference", roomy,
                                    os.path.join(args.workdir, name + "_reference.h5"))
            status_code, _ = run(args, reference)
            checks.check(f"{what}: the reference run on a disk with room: exit status",
                         status_code, 0)
            with h5py.File(output, "r") as f, \
                    h5py.File(os.path.join(args.workdir, name + "_reference.h5"), "r") as g:
                for r in rods:
                    for field in ("time", "position", "directors", "velocity", "stress",
                                  "series/energy/total", "series/momentum/angular"):
                        got = f[f"rods/{r}/{field}"][()]
                        want = g[f"rods/{r}/{field}"][()][:got.shape[0]]
                        same = got.shape == want.shape and np.array_equal(got, want)
                        checks.check(f"{what}, rod {r}: {field}: its {got.shape[0]} records "
                                     "equal the reference's", 0 if same else 1, 0)
        # A sidecar rank 0 cannot write (a directory where its temporary file goes) stops
        # both ranks the same way: the failure of one rank is every rank's.
        output = os.path.join(args.workdir, "sidecar.h5")
        for stale in (output, output + ".lock"):
            if os.path.exists(stale):
                os.remove(stale)
        os.makedirs(os.path.join(args.workdir, "sidecar.xdmf.tmp"), exist_ok=True)
        scene = write_scene(args, "sidecar", rs.set_variable(two_rods(text), "output", "xdmf",
                                                             ".true."), output)
        try:
            result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "2",
                                     args.rodsolve, scene], capture_output=True, text=True,
                                    timeout=60)
            code, log = result.returncode, result.stdout + result.stderr
        except subprocess.TimeoutExpired:
            code, log = -1, "(timed out)"
        print(log[-800:])
        checks.check("sidecar not writable, 2 ranks: exit status - 1", abs(code - 1), 0)
        checks.check("... the message names the sidecar",
                     0 if "cannot write the XDMF sidecar" in log else 1, 0)
        with h5py.File(output, "r") as f:
            checks.check("... the file's status is 'failed'",
                         0 if f.attrs.get("status", "") == "failed" else 1, 0)
    finally:
        if mounted:
            # Lazily: a rank that was killed may hold the file open for a moment.
            subprocess.run(["umount", "-l", small], capture_output=True)


def corrupt(path, dataset, offset_in_data=8):
    """Change one byte of `dataset` in the file: at `offset_in_data` bytes into a contiguous
    dataset, or into the first chunk of a chunked one."""
    with h5py.File(path, "r") as f:
        ds = f[dataset]
        if ds.chunks is None:
            at = ds.id.get_offset()
        else:
            at = ds.id.get_chunk_info(0).byte_offset
    with open(path, "r+b") as f:
        f.seek(at + offset_in_data)
        byte = f.read(1)
        f.seek(at + offset_in_data)
        f.write(bytes([byte[0] ^ 0x10]))


def corrupted_checkpoint(args, checks):
    text = rs.read_example(args.source, "strand_vibration.nml")
    text = rs.set_variable(text, "output", "stride", "10")
    text = rs.set_variable(text, "output", "flush_every", "50")
    text = rs.set_variable(text, "output", "xdmf", ".false.")
    first = rs.set_variable(text, "time", "t_end", repr(100 * STRAND_DT))
    later = rs.set_variable(text, "time", "t_end", repr(200 * STRAND_DT))
    for ranks, scene_text in ((1, first), (2, two_rods(first))):
        what = f"{ranks} rank(s)"
        written = os.path.join(args.workdir, f"checked_{ranks}.h5")
        scene = write_scene(args, f"checked_{ranks}", scene_text, written)
        status, _ = subprocess.run([args.mpiexec, "--oversubscribe", "-np", str(ranks),
                                    args.rodsolve, scene], capture_output=True).returncode, None
        checks.check(f"{what}: the first run: exit status", status, 0)
        intact = os.path.join(args.workdir, f"intact_{ranks}.h5")
        damaged = os.path.join(args.workdir, f"damaged_{ranks}.h5")
        shutil.copy(written, intact)
        shutil.copy(written, damaged)
        corrupt(damaged, "checkpoint/tube/state", 8 * 40 + 3)
        continued = later if ranks == 1 else two_rods(later)
        for source, fails in ((intact, False), (damaged, True)):
            kind = "damaged" if fails else "intact"
            restart = rs.set_variable(continued, "run", "restart_from", f"'{source}'")
            output = os.path.join(args.workdir, f"continued_{kind}_{ranks}.h5")
            scene = write_scene(args, f"continued_{kind}_{ranks}", restart, output)
            result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", str(ranks),
                                     args.rodsolve, scene], capture_output=True, text=True)
            log = result.stdout + result.stderr
            print(log[-800:])
            if fails:
                checks.check(f"{what}: restart from a damaged checkpoint: exit status - 1",
                             abs(result.returncode - 1), 0)
                checks.check(f"{what}: ... the message says the checkpoint of 'tube' is "
                             "corrupted", 0 if "checkpoint of rod \"tube\"" in log and
                             "is corrupted" in log else 1, 0)
            else:
                checks.check(f"{what}: restart from the intact copy: exit status",
                             result.returncode, 0)
    # A checkpoint of schema 1 (each formulation's own book-keeping in /internal, before the
    # record ledger of issue 22) is refused with its reason, not read in the wrong layout.
    old = os.path.join(args.workdir, "schema_1.h5")
    shutil.copy(os.path.join(args.workdir, "intact_1.h5"), old)
    with h5py.File(old, "r+") as f:
        f.move("checkpoint/tube/ledger", "checkpoint/tube/internal")
        f.attrs["schema_version"] = 1
    restart = rs.set_variable(later, "run", "restart_from", f"'{old}'")
    output = os.path.join(args.workdir, "continued_schema_1.h5")
    scene = write_scene(args, "continued_schema_1", restart, output)
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, scene],
                            capture_output=True, text=True)
    log = result.stdout + result.stderr
    print(log[-600:])
    checks.check("restart from a schema-1 checkpoint: exit status - 1", abs(result.returncode - 1), 0)
    checks.check("... the message names the older schema and what to do",
                 0 if "schema 1" in log and "run the scene again from the start" in log else 1, 0)
    # On one rank every growing dataset carries HDF5's Fletcher-32 checksum: a reader finds a
    # changed byte in a record.
    damaged = os.path.join(args.workdir, "damaged_records.h5")
    shutil.copy(os.path.join(args.workdir, "checked_1.h5"), damaged)
    corrupt(damaged, "rods/tube/position", 100)
    with h5py.File(damaged, "r") as f:
        checks.check("1 rank: position has the Fletcher-32 filter",
                     0 if "fletcher32" in f["rods/tube/position"]._filters else 1, 0)
        try:
            f["rods/tube/position"][()]
            detected = False
        except OSError as error:
            print(f"h5py: {error}")
            detected = "Fletcher32" in str(error) or "checksum" in str(error)
    checks.check("1 rank: a changed byte in a record's chunk is found on reading",
                 0 if detected else 1, 0)


def flush_every_memory(args, checks):
    text = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    text = rs.set_variable(text, "time", "t_end", "0.5")
    text = rs.set_variable(text, "output", "flush_every", "1000000")
    output = os.path.join(args.workdir, "memory.h5")
    scene = write_scene(args, "memory", text, output)
    # rodsolve itself (one rank, no mpiexec), so that the children's peak is its own.
    result = subprocess.run([args.rodsolve, scene], capture_output=True, text=True)
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
    print(result.stderr[-600:])
    print(f"peak resident memory of the 5-step run with flush_every = 1000000: {peak:.0f} MB")
    checks.check("exit status", result.returncode, 0)
    # 52 MB measured (PETSc, MPI and the libraries); the 1000004 preallocated records of 11
    # nodes took 3.2 GB.
    checks.check("peak resident memory below 200 MB", 0 if peak < 200.0 else 1, 0)
    with h5py.File(output, "r") as f:
        checks.check("records - 6 (t = 0 and 5 steps)",
                     abs(f["rods/spaghetti/time"].shape[0] - 6), 0)


def nan_at_start(args, checks):
    cases = (("ph_director", "flying_spaghetti.nml", "spaghetti", None),
             ("ph_planar", "planar_flying_spaghetti.nml", "spaghetti", None),
             ("cl_em_planar", "planar_flying_spaghetti.nml", "spaghetti", "cl_em_planar"),
             ("se3_pg", "se3_cantilever.nml", "cantilever", None),
             ("se3_strand", "strand_vibration.nml", "tube", None))
    for name, example, rod, formulation in cases:
        text = rs.read_example(args.source, example)
        if formulation:
            text = text.replace("formulation = 'ph_planar'", f"formulation = '{formulation}'")
        # An end load no step survives: 1e300 overflows the work and the state.
        planar = "planar" in example
        force = "1e300, 1e300, 0.0" if planar else "1e300, 1e300, 1e300"
        moment = "0.0, 0.0, 1e300" if planar else "1e300, 0.0, 1e300"
        text += (f"\n&load\n    rod = '{rod}', where = 'end'\n    force = {force}\n"
                 f"    moment = {moment}\n/\n")
        output = os.path.join(args.workdir, f"nan_{name}.h5")
        scene = write_scene(args, f"nan_{name}", text, output)
        status, log = run(args, scene)
        checks.check(f"{name}: exit status - 1", abs(status - 1), 0)
        non_finite = []
        with h5py.File(output, "r") as f:
            def visit(path, item):
                if isinstance(item, h5py.Dataset) and item.dtype.kind == "f":
                    count = int((~np.isfinite(item[()])).sum())
                    if count:
                        non_finite.append(f"{path} ({count})")
            f.visititems(visit)
            state = f.attrs.get("status", "")
            times = f[f"rods/{rod}/time"][()]
        print(f"{name}: non-finite values in {non_finite or 'no dataset'}; records at {times}")
        checks.check(f"{name}: the file's status is 'failed'", 0 if state == "failed" else 1, 0)
        checks.check(f"{name}: values that are NaN or Inf, in datasets", len(non_finite), 0)
        checks.check(f"{name}: the rod's records - 1 (its last good state, t = 0)",
                     abs(len(times) - 1), 0)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["two_runs", "merge_running", "overwrite", "killed_sweep",
                                         "merge_edited", "sigterm", "scene_from_pipe",
                                         "not_relaxed", "disk_full", "corrupted_checkpoint",
                                         "flush_every_memory", "nan_at_start"])
    args = parser.parse_args()
    checks = rs.Checks()
    {"two_runs": two_runs, "merge_running": merge_running, "overwrite": overwrite,
     "killed_sweep": killed_sweep, "merge_edited": merge_edited, "sigterm": sigterm,
     "scene_from_pipe": scene_from_pipe,
     "not_relaxed": not_relaxed, "disk_full": disk_full,
     "corrupted_checkpoint": corrupted_checkpoint,
     "flush_every_memory": flush_every_memory,
     "nan_at_start": nan_at_start}[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
