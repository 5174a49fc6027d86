"""Parameter sweeps (DESIGN.md §5, §7; issue 9), on input/sweep_cantilever.nml: 64 cantilevers
that differ in EI1 (logspace 1 ... 100), ph_director statics.

    sweep.py ranks    the sweep on 1 and on 2 ranks: every member's positions are bitwise
                      identical; /summary has 64 rows ordered by id, all completed, EI1 the
                      logspace values, both ranks used; each member's tip deflection is the
                      Timoshenko cantilever's F L^3 / (3 EI1) + F L / GA2 within 1e-4 relative
                      (the scene header: the geometric nonlinearity is 1.1e-5 at EI1 = 1)
    sweep.py failing  one member made to fail on purpose (dt = 1 with two Newton iterations and
                      no cut-backs): it is reported failed with its Newton message, the run's exit
                      status is 1, and the other members' results equal a sweep without it
    sweep.py merge    a sweep killed with SIGKILL after some members finished: `rodsolve
                      --merge` rebuilds the file; the finished members are intact (bitwise equal
                      to an uninterrupted run's), the others are marked not run; a second
                      --merge refuses (nothing to merge) and leaves the file as it is
"""
import os
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import run_scene as rs  # noqa: E402

ROD = "cantilever"
N = 64
F, L, GA = 0.01, 1.0, 1e5


def sweep_file(args, text, name, ranks=1, allow_failure=False):
    """Run the sweep `text` as scene `name` on `ranks` ranks; the result file and the status."""
    os.makedirs(args.workdir, exist_ok=True)
    output = os.path.join(args.workdir, name + ".h5")
    if os.path.exists(output):
        os.remove(output)
    text = rs.set_variable(text, "output", "path", f"'{output}'")
    scene = os.path.join(args.workdir, name + ".nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", str(ranks), args.rodsolve,
                             scene], capture_output=True, text=True)
    if result.returncode != 0 and not allow_failure:
        print(result.stdout + result.stderr)
        raise SystemExit(f"the sweep {name} failed with status {result.returncode}")
    return output, result.returncode, result.stdout + result.stderr


def positions(path):
    with h5py.File(path, "r") as f:
        return {int(k): f[f"members/{k}/rods/{ROD}/position"][()] for k in f["members"]
                if f"rods/{ROD}/position" in f[f"members/{k}"]}


def ranks(args, checks):
    text = rs.read_example(args.source, "sweep_cantilever.nml")
    one, _, _ = sweep_file(args, text, "one_rank")
    two, _, printed = sweep_file(args, text, "two_ranks", ranks=2)
    a, b = positions(one), positions(two)
    checks.check("members with results on 1 and on 2 ranks, less 64 each",
                 abs(len(a) - N) + abs(len(b) - N), 0)
    checks.check("largest |position(1 rank) - position(2 ranks)| over all members",
                 max(float(np.max(np.abs(a[k] - b[k]))) for k in a), 0.0)
    with h5py.File(two, "r") as f:
        s = {key: f[f"summary/{key}"][()] for key in ("id", "status", "rank", "tip_position")}
        ei1 = f["summary/parameters/rod(1)%EI1"][()]
        attrs = [f[f"members/{k}"].attrs["rod(1)%EI1"] for k in range(1, N + 1)]
        n_ranks = int(f.attrs["n_ranks"])
    checks.check("/summary/id - (1 .. 64) (complete, ordered by id)",
                 float(np.max(np.abs(s["id"] - np.arange(1, N + 1)))), 0)
    checks.check("members not completed", int(np.count_nonzero(s["status"])), 0)
    checks.check("ranks used - {0, 1}", len(set(s["rank"].tolist()) ^ {0, 1}), 0)
    checks.check("n_ranks attribute - 2", abs(n_ranks - 2), 0)
    expected = np.logspace(0.0, 2.0, N)
    checks.check("largest |EI1 / logspace(1, 100, 64) - 1| (summary and attributes)",
                 float(max(np.max(np.abs(ei1 / expected - 1)), np.max(np.abs(np.array(attrs) / expected - 1)))),
                 1e-14)
    w = -s["tip_position"][:, 2]
    formula = F * L**3 / (3 * ei1) + F * L / GA
    error = np.abs(w / formula - 1)
    print(f"info: tip deflection {w[0]:.6e} (EI1 = 1) ... {w[-1]:.6e} (EI1 = 100); largest relative "
          f"error against the Timoshenko formula {np.max(error):.2e} (member {np.argmax(error) + 1})")
    checks.check("largest |w / (F L^3 / (3 EI1) + F L / GA2) - 1|", float(np.max(error)), 1e-4)
    print("info: " + next(line for line in printed.splitlines() if "dealt by" in line))


def failing(args, checks):
    base = rs.read_example(args.source, "sweep_cantilever.nml")
    base = rs.set_variable(base, "solver", "max_newton", "2")
    base = rs.set_variable(base, "solver", "max_cutbacks", "0")
    cut = base.index("&sweep")
    good = base[:cut] + "&sweep\n    parameter = 'time%dt'\n    values = 0.05, 0.1, 0.25\n/\n"
    bad = base[:cut] + "&sweep\n    parameter = 'time%dt'\n    values = 0.05, 0.1, 1.0, 0.25\n/\n"
    path, status, printed = sweep_file(args, bad, "with_failure", allow_failure=True)
    reference, _, _ = sweep_file(args, good, "without_failure")
    checks.check("exit status of the sweep with a failing member - 1", abs(status - 1), 0)
    with h5py.File(path, "r") as f:
        codes = f["summary/status"][()]
        message = f["members/3"].attrs["message"]
        message = message.decode() if isinstance(message, bytes) else message
        root = f.attrs["status"]
        root = root.decode() if isinstance(root, bytes) else root
    print(f"info: statuses {codes.tolist()}; member 3: {message}")
    checks.check("statuses - (0, 0, 1, 0)", float(np.max(np.abs(codes - [0, 0, 1, 0]))), 0)
    checks.check("member 3's message names the Newton failure",
                 0 if "Newton did not converge" in message else 1, 0)
    checks.check("root status is 'some members failed'", 0 if root == "some members failed" else 1, 0)
    a, b = positions(path), positions(reference)
    pairs = [(1, 1), (2, 2), (4, 3)]
    checks.check("largest |position - the sweep without the failing member| (members 1, 2, 4)",
                 max(float(np.max(np.abs(a[i] - b[j]))) for i, j in pairs), 0.0)


def merge(args, checks):
    text = rs.read_example(args.source, "sweep_cantilever.nml")
    reference, _, _ = sweep_file(args, text, "uninterrupted")
    os.makedirs(args.workdir, exist_ok=True)
    output = os.path.join(args.workdir, "killed.h5")
    for stale in (output,):
        if os.path.exists(stale):
            os.remove(stale)
    scene = os.path.join(args.workdir, "killed.nml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(rs.set_variable(text, "output", "path", f"'{output}'"))
    ledger = output + ".members/ledger_rank0.txt"
    # One rank without mpiexec, so that the signal reaches rodsolve itself.
    process = subprocess.Popen([args.rodsolve, scene], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    finished = 0
    while process.poll() is None:
        if os.path.exists(ledger):
            with open(ledger, encoding="utf-8") as f:
                finished = sum(1 for line in f if line.strip())
            if finished >= 5:
                process.send_signal(signal.SIGKILL)
                break
        time.sleep(0.005)
    process.wait()
    checks.check("the sweep was killed before its end (exit by SIGKILL)",
                 0 if process.returncode == -signal.SIGKILL else 1, 0)
    checks.check("no sweep file before --merge", 1 if os.path.exists(output) else 0, 0)
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, "--merge",
                             scene], capture_output=True, text=True)
    print(result.stdout[-400:] + result.stderr[-400:])
    checks.check("exit status of rodsolve --merge", result.returncode, 0)
    with h5py.File(output, "r") as f:
        codes = f["summary/status"][()]
    done = int(np.count_nonzero(codes == 0))
    print(f"info: killed after {finished} finished members; merged: {done} completed, "
          f"{int(np.count_nonzero(codes == 2))} not run")
    checks.check("completed members - those the ledger had at the kill (>= 5)",
                 0 if done >= 5 and done >= finished else 1, 0)
    checks.check("members neither completed nor 'not run'",
                 int(np.count_nonzero((codes != 0) & (codes != 2))), 0)
    with h5py.File(output, "r") as f:
        root = f.attrs["status"]
        root = root.decode() if isinstance(root, bytes) else root
    checks.check("root status is 'incomplete: some members not run'",
                 0 if root == "incomplete: some members not run" else 1, 0)
    a, b = positions(output), positions(reference)
    checks.check("finished members with results, less the completed count", abs(len(a) - done), 0)
    checks.check("largest |position - uninterrupted| of the finished members",
                 max(float(np.max(np.abs(a[k] - b[k]))) for k in a), 0.0)
    # The merged file is complete: a second --merge has nothing to merge and leaves it alone.
    again = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, "--merge",
                            scene], capture_output=True, text=True)
    checks.check("exit status of a second --merge - 1 (nothing to merge)", abs(again.returncode - 1), 0)
    checks.check("the second --merge says there is nothing to merge",
                 0 if "nothing to merge" in again.stdout + again.stderr else 1, 0)
    checks.check("members with results after the second --merge, less before",
                 abs(len(positions(output)) - len(a)), 0)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["ranks", "failing", "merge"])
    args = parser.parse_args()
    checks = rs.Checks()
    {"ranks": ranks, "failing": failing, "merge": merge}[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    sys.exit(main())
