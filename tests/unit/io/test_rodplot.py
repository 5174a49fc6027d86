"""scripts/rodplot.py on the file test_result_file.F90 wrote.

    test_rodplot.py RODPLOT RESULT.h5 OUT_DIR

Checks: `energy`, `snapshots` and `tip` (all rods, one rod) write PNG images of more than 10 kB;
a wrong rod name, a missing file and a file that is not a rodsolve result exit with status 2
and a message naming the problem (the available rods for a wrong name); --help documents the
commands and options. `tip` is also run on a synthetic result file written here with h5py (a
rod whose last node moves on a flat helix): the tip path read back is the last node's, the
automatic projection plane is the one the helix lies in, every --plane works, an unknown
plane is a usage error (status 2) and a file without records is a missing-data error.
Exit status 1 with a list of failures.
"""

import os
import subprocess
import sys

import h5py
import numpy as np

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


def write_helix_file(path, n_records):
    """A minimal result file (the attributes and datasets rodresults.py reads): rod 'helix'
    with 5 nodes, the last on (cos t, sin t, 0.01 t), the others on the axis."""
    time = np.linspace(0.0, 2 * np.pi, n_records)
    position = np.zeros((n_records, 5, 3))
    position[:, :, 2] = np.linspace(-1.0, 0.0, 5)
    position[:, -1, :] = np.stack([np.cos(time), np.sin(time), 0.01 * time], axis=1)
    with h5py.File(path, "w") as f:
        f.attrs["schema_version"] = 1
        f.attrs["title"] = "synthetic helix"
        group = f.create_group("rods/helix")
        group.attrs["formulation"] = "ph_director"
        group["time"] = time
        group["position"] = position
        group["mesh"] = np.linspace(0.0, 1.0, 5)
    return time, position[:, -1, :]


def tip_checks(rodplot, out_dir):
    sys.path.insert(0, os.path.dirname(os.path.abspath(rodplot)))
    import rodplot as module
    from rodresults import open_result

    helix = os.path.join(out_dir, "helix.h5")
    time, tip = write_helix_file(helix, 50)
    with open_result(helix) as res:
        t, path = module.tip_path(res.rod("helix"))
    check(np.array_equal(t, time) and np.array_equal(path, tip),
          "tip_path returns the time and the last node's positions")
    check(module.projection_plane([path]) == (0, 1),
          "auto plane of a flat helix is x-y: %s" % (module.projection_plane([path]),))
    swapped = path[:, [0, 2, 1]]
    check(module.projection_plane([swapped]) == (0, 2),
          "auto plane of a helix in x-z is x-z: %s" % (module.projection_plane([swapped]),))
    for plane in ("auto", "xy", "xz", "yz"):
        out = os.path.join(out_dir, "helix_tip_%s.png" % plane)
        if os.path.exists(out):
            os.remove(out)
        p = run(rodplot, "tip", helix, "--plane", plane, "-o", out)
        check(p.returncode == 0, "tip --plane %s: exit %d: %s" % (plane, p.returncode, p.stderr))
        check_png(out, "tip --plane %s" % plane)
    p = run(rodplot, "tip", helix, "--plane", "xx", "-o", os.path.join(out_dir, "never.png"))
    check(p.returncode == 2 and "--plane" in p.stderr,
          "unknown plane: exit %d, expected 2 with a usage message: %r" % (p.returncode, p.stderr))
    empty = os.path.join(out_dir, "empty.h5")
    write_helix_file(empty, 0)
    p = run(rodplot, "tip", empty, "-o", os.path.join(out_dir, "never.png"))
    check(p.returncode == 2 and "no stored records" in p.stderr,
          "no records: exit %d, expected 2 with a message: %r" % (p.returncode, p.stderr))
    check(not os.path.exists(os.path.join(out_dir, "never.png")), "no image for failed tip plots")


def main():
    rodplot, result, out_dir = sys.argv[1:4]
    os.makedirs(out_dir, exist_ok=True)

    for command, extra in (("energy", []), ("snapshots", []), ("energy", ["--rod", "tail"]),
                           ("snapshots", ["--rod", "arm"]), ("tip", []), ("tip", ["--rod", "arm"])):
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
    for word in ("energy", "snapshots", "tip", "--rod", "--output", "--plane", "exit status",
                 "viridis"):
        check(word in p.stdout, "--help mentions %s" % word)

    tip_checks(rodplot, out_dir)

    for message in failures:
        print("FAILED: " + message)
    print("%d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
