#!/usr/bin/env python3
"""Runs rodsolve on one scene of tests/input/ and checks the verdict (DESIGN.md §6, §8).

A bad scene states the messages it must produce in lines `! expect: <fragment>`. The check:
exit status 2, every fragment in the output, the first fragment printed once (rank 0 only, on
any number of ranks), and nothing created in the working directory (no output file).
A good scene (--good) must pass `--check-input` with status 0 and print its resolved text.
"""
import argparse
import os
import subprocess
import sys
import tempfile


def resolved_text(stdout):
    """The resolved scene of --check-input: its groups, without the header and verdict lines and
    without the plan (the comment block from "! plan:" on, which names the number of ranks and
    so differs between the 2-rank check and the 1-rank re-read)."""
    kept, in_plan = [], False
    for line in stdout.splitlines():
        if line.startswith("! plan:"):
            in_plan = True
        elif in_plan and not line.startswith("!"):
            in_plan = False
        if in_plan or line.startswith("! resolved scene of") or line.startswith("rodsolve: "):
            continue
        kept.append(line)
    return "\n".join(kept) + "\n"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--rodsolve", required=True)
    parser.add_argument("--mpiexec", required=True)
    parser.add_argument("--np", type=int, default=2)
    parser.add_argument("--good", action="store_true", help="the scene must be valid")
    parser.add_argument("--check-only", action="store_true", help="use --check-input")
    parser.add_argument("--expect", action="append", default=[], help="extra expected fragment")
    parser.add_argument("--rodsolve-arg", action="append", default=[],
                        help="extra argument for rodsolve, after the scene (use --rodsolve-arg=X)")
    parser.add_argument("scene")
    args = parser.parse_args()

    scene = os.path.abspath(args.scene)
    expected = list(args.expect)
    if os.path.exists(scene):
        # errors="replace": a bad scene may be invalid UTF-8 on purpose (bad/non_utf8.nml).
        with open(scene, encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("! expect:"):
                    expected.append(line[len("! expect:"):].strip())

    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    with tempfile.TemporaryDirectory() as workdir:
        # One rank runs the binary itself (an MPI singleton): the verdict is the same code path
        # on every rank, and mpiexec's start-up would cost more than the check (the 2-rank
        # cases of CMakeLists.txt keep the collective verdict tested).
        command = [args.rodsolve]
        if args.np > 1:
            command = [args.mpiexec, "--oversubscribe", "-np", str(args.np), args.rodsolve]
        if args.good or args.check_only:
            command.append("--check-input")
        command.append(scene)
        command += args.rodsolve_arg
        result = subprocess.run(command, cwd=workdir, env=env, capture_output=True, text=True, errors="replace",
                                timeout=120)
        output = result.stdout + result.stderr
        left_behind = os.listdir(workdir)
        echo_differs = None
        if args.good and result.returncode == 0:
            # The resolved echo is itself a scene that resolves to the same text.
            resolved = resolved_text(result.stdout)
            again_path = os.path.join(workdir, "resolved.nml")
            with open(again_path, "w", encoding="utf-8") as f:
                f.write(resolved)
            again = subprocess.run([args.rodsolve, "--check-input", again_path], cwd=workdir,
                                   env=env, capture_output=True, text=True, errors="replace", timeout=120)
            os.remove(again_path)
            if again.returncode != 0 or resolved_text(again.stdout) != resolved:
                echo_differs = again.stdout + again.stderr

    failures = []
    if args.good:
        if result.returncode != 0:
            failures.append(f"exit status {result.returncode}, expected 0")
        if "is valid" not in output:
            failures.append("no 'is valid' line")
        if echo_differs is not None:
            failures.append("the resolved echo does not read back to itself:\n" + echo_differs)
    else:
        if result.returncode != 2:
            failures.append(f"exit status {result.returncode}, expected 2")
        if not expected:
            failures.append("the scene states no '! expect:' line")
        for fragment in expected:
            if fragment not in output:
                failures.append(f"missing message fragment: {fragment!r}")
        if expected and output.count(expected[0]) > 1:
            failures.append(f"printed {output.count(expected[0])} times (rank 0 only expected)")
    if left_behind:
        failures.append(f"files were created: {left_behind}")

    print(" ".join(command))
    print(output)
    if failures:
        for failure in failures:
            print("FAIL:", failure)
        print("0 passed, 1 failed")
        return 1
    print("1 passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
