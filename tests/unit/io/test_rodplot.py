"""scripts/rodplot.py on the file test_result_file.F90 wrote.

    test_rodplot.py RODPLOT RESULT.h5 OUT_DIR

Checks: `energy` and `snapshots` (all rods, one rod) write PNG images of more than 10 kB;
a wrong rod name, a missing file and a file that is not a rodsolve result exit with status 2
and a message naming the problem (the available rods for a wrong name); --help documents the
commands and options. Exit status 1 with a list of failures.
"""

import os
import subprocess
import sys

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

failures = []


def run(rodplot, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, rodplot] + list(args), capture_output=True,
                          text=True, env=env, timeout=120)


def check(condition, message):
    if not condition:
        failures.append(message)


def check_png(path, what):
    if not os.path.isfile(path):
        failures.append("%s: %s not written" % (what, path))
        return
    with open(path, "rb") as f:
        head = f.read(8)
    check(head == PNG_SIGNATURE, "%s: %s has the PNG signature" % (what, path))
    size = os.path.getsize(path)
    check(size > 10_000, "%s: %s is %d bytes (> 10 kB expected)" % (what, path, size))


def main():
    rodplot, result, out_dir = sys.argv[1:4]
    os.makedirs(out_dir, exist_ok=True)

    for command, extra in (("energy", []), ("snapshots", []), ("energy", ["--rod", "tail"]),
                           ("snapshots", ["--rod", "arm"])):
        out = os.path.join(out_dir, "%s%s.png" % (command, "_" + extra[1] if extra else ""))
        if os.path.exists(out):
            os.remove(out)
        p = run(rodplot, command, result, "-o", out, *extra)
        check(p.returncode == 0, "%s %s: exit %d: %s" % (command, extra, p.returncode, p.stderr))
        check_png(out, "%s %s" % (command, extra))

    # The default name: FILE_<command>.png next to FILE.
    default = os.path.splitext(result)[0] + "_energy.png"
    if os.path.exists(default):
        os.remove(default)
    p = run(rodplot, "energy", result)
    check(p.returncode == 0, "energy without -o: exit %d: %s" % (p.returncode, p.stderr))
    check_png(default, "energy without -o")

    p = run(rodplot, "snapshots", result, "--rod", "no_such_rod",
            "-o", os.path.join(out_dir, "never.png"))
    check(p.returncode == 2, "wrong rod: exit %d, expected 2" % p.returncode)
    check("no_such_rod" in p.stderr and "arm, tail" in p.stderr,
          "wrong rod: the message names the rod and the available rods: %r" % p.stderr)
    check(not os.path.exists(os.path.join(out_dir, "never.png")), "wrong rod: no image")

    p = run(rodplot, "energy", os.path.join(out_dir, "does_not_exist.h5"))
    check(p.returncode == 2, "missing file: exit %d, expected 2" % p.returncode)
    check("does_not_exist.h5: no such file" in p.stderr, "missing file message: %r" % p.stderr)

    layer = os.path.join(os.path.dirname(os.path.dirname(result)), "layer.h5")
    p = run(rodplot, "energy", layer)
    check(p.returncode == 2, "not a result file: exit %d, expected 2" % p.returncode)
    check("not a rodsolve result file" in p.stderr, "not a result message: %r" % p.stderr)

    p = run(rodplot, "--help")
    check(p.returncode == 0, "--help exit %d" % p.returncode)
    for word in ("energy", "snapshots", "--rod", "--output", "exit status", "viridis"):
        check(word in p.stdout, "--help mentions %s" % word)

    for message in failures:
        print("FAILED: " + message)
    print("%d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
