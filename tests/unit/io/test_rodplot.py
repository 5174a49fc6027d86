"""scripts/rodplot.py on the file test_result_file.F90 wrote.

    test_rodplot.py RODPLOT RESULT.h5 OUT_DIR

Checks: `energy`, `momentum`, `snapshots` and `tip` (all rods, one rod) write PNG images of more
than 10 kB; a wrong rod name, a missing file and a file that is not a rodsolve result exit with
status 2 and a message naming the problem (the available rods for a wrong name); --help
documents the commands and options. `tip` is also run on a synthetic result file written here
with h5py (a rod whose last node moves on a flat helix): the tip path read back is the last
node's, the automatic projection plane is the one the helix lies in, every --plane works, an
unknown plane is a usage error (status 2) and a file without records is a missing-data error.
`momentum` draws a third panel when the file has a momentum balance series (the synthetic file
gets momentum/angular_balance_error) and is a missing-data error without momentum series.
`animate` writes a GIF with one frame per record (at most --frames), named FILE_animate.gif by
default; a non-GIF output is a usage error and a missing Pillow exits with status 1 and the
Debian package to install. `summary` prints title, creator, schema version, ranks and per rod
the formulation, records, time span, dt range, Newton iterations, balance error (absolute and
relative to max |H|), constraint residual and fields, each number compared with the file read
here with h5py; -o writes the same text; --rod limits it to one rod.
Exit status 1 with a list of failures.
"""

import contextlib
import io
import os
import re
import struct
import subprocess
import sys

import h5py
import numpy as np

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
GIF_SIGNATURES = (b"GIF87a", b"GIF89a")

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


def png_height(path):
    """Height in pixels from the PNG header (IHDR)."""
    with open(path, "rb") as f:
        head = f.read(24)
    return struct.unpack(">I", head[20:24])[0]


def check_gif(path, what, frames):
    """A GIF with `frames` frames (read back with Pillow)."""
    if not os.path.isfile(path):
        failures.append("%s: %s not written" % (what, path))
        return
    with open(path, "rb") as f:
        head = f.read(6)
    check(head in GIF_SIGNATURES, "%s: %s has a GIF signature: %r" % (what, path, head))
    from PIL import Image
    with Image.open(path) as image:
        check(image.format == "GIF", "%s: Pillow reads a GIF" % what)
        check(image.n_frames == frames,
              "%s: %d frames, expected %d" % (what, image.n_frames, frames))


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


def momentum_checks(rodplot, out_dir):
    """On the helix file: no momentum series is a missing-data error; with linear and
    angular momentum two panels, with a balance series a third (a taller image)."""
    helix = os.path.join(out_dir, "helix_momentum.h5")
    time, _ = write_helix_file(helix, 20)
    never = os.path.join(out_dir, "never.png")
    p = run(rodplot, "momentum", helix, "--rod", "helix", "-o", never)
    check(p.returncode == 2 and "no momentum series" in p.stderr,
          "momentum without series: exit %d: %r" % (p.returncode, p.stderr))
    check(not os.path.exists(never), "no image without momentum series")
    with h5py.File(helix, "a") as f:
        series = f["rods/helix"].create_group("series")
        series["momentum/linear"] = np.stack([time, 2 * time, np.ones_like(time)], axis=1)
        series["momentum/angular"] = np.stack([np.sin(time), np.cos(time), time], axis=1)
    heights = {}
    for with_balance in (False, True):
        if with_balance:
            with h5py.File(helix, "a") as f:
                f["rods/helix/series/momentum/angular_balance_error"] = 1e-15 * (1 + time)
        out = os.path.join(out_dir, "momentum_balance_%s.png" % with_balance)
        p = run(rodplot, "momentum", helix, "--rod", "helix", "-o", out)
        check(p.returncode == 0, "momentum (balance %s): exit %d: %s"
              % (with_balance, p.returncode, p.stderr))
        check_png(out, "momentum (balance %s)" % with_balance)
        if os.path.isfile(out):
            heights[with_balance] = png_height(out)
    if len(heights) == 2:
        check(heights[True] > 1.3 * heights[False],
              "a third panel for the balance series: heights %s" % heights)


def animate_checks(rodplot, result, out_dir):
    sys.path.insert(0, os.path.dirname(os.path.abspath(rodplot)))
    import rodplot as module

    with h5py.File(result, "r") as f:
        n_records = f["rods/arm/time"].shape[0]
    for extra, frames in (([], n_records), (["--rod", "arm", "--frames", "3"], 3)):
        out = os.path.join(out_dir, "animate%s.gif" % "_".join([""] + extra))
        if os.path.exists(out):
            os.remove(out)
        p = run(rodplot, "animate", result, "-o", out, *extra)
        check(p.returncode == 0, "animate %s: exit %d: %s" % (extra, p.returncode, p.stderr))
        check_gif(out, "animate %s" % extra, frames)
    default = os.path.splitext(result)[0] + "_animate.gif"
    if os.path.exists(default):
        os.remove(default)
    p = run(rodplot, "animate", result, "--frames", "2")
    check(p.returncode == 0, "animate without -o: exit %d: %s" % (p.returncode, p.stderr))
    check_gif(default, "animate without -o", 2)
    p = run(rodplot, "animate", result, "-o", os.path.join(out_dir, "never.png"))
    check(p.returncode == 2 and "GIF" in p.stderr,
          "animate to a PNG: exit %d, expected a usage error: %r" % (p.returncode, p.stderr))
    p = run(rodplot, "animate", result, "--rod", "no_such_rod",
            "-o", os.path.join(out_dir, "never.gif"))
    check(p.returncode == 2 and "no_such_rod" in p.stderr and "arm, tail" in p.stderr,
          "animate, wrong rod: exit %d: %r" % (p.returncode, p.stderr))
    check(not os.path.exists(os.path.join(out_dir, "never.gif")), "animate, wrong rod: no GIF")

    # Without Pillow (an import that fails): status 1 and the package to install.
    saved = sys.modules.get("PIL")
    sys.modules["PIL"] = None
    stderr = io.StringIO()
    try:
        with contextlib.redirect_stderr(stderr), contextlib.redirect_stdout(io.StringIO()):
            status = module.main(["animate", result, "-o",
                                  os.path.join(out_dir, "no_pillow.gif")])
    finally:
        if saved is None:
            del sys.modules["PIL"]
        else:
            sys.modules["PIL"] = saved
    check(status == 1 and "Pillow" in stderr.getvalue() and "python3-pil" in stderr.getvalue(),
          "animate without Pillow: status %r: %r" % (status, stderr.getvalue()))
    check(not os.path.exists(os.path.join(out_dir, "no_pillow.gif")), "no GIF without Pillow")


def g(value):
    return "%.6g" % value


def rod_section(text, name):
    """The lines of the summary's section of rod `name` (up to the next blank line)."""
    for block in text.split("\n\n"):
        if block.startswith("rod '%s' " % name):
            return block
    failures.append("summary has no section for rod %r: %r" % (name, text))
    return ""


def has_line(text, key, value, what):
    """The summary has a line `key  value` (any run of spaces between)."""
    pattern = r"^\s*%s\s+%s\s*$" % (re.escape(key), re.escape(value))
    check(re.search(pattern, text, re.MULTILINE) is not None,
          "%s: a line %r %r in %r" % (what, key, value, text))


def summary_checks(rodplot, result, out_dir):
    p = run(rodplot, "summary", result)
    check(p.returncode == 0, "summary: exit %d: %s" % (p.returncode, p.stderr))
    text = p.stdout
    with h5py.File(result, "r") as f:
        attrs = f.attrs
        has_line(text, "title", attrs["title"], "summary")
        has_line(text, "creator", attrs["creator"], "summary")
        has_line(text, "schema version", str(attrs["schema_version"]), "summary")
        has_line(text, "ranks", str(attrs["n_ranks"]), "summary")
        has_line(text, "rods", "arm, tail", "summary")
        for name in ("arm", "tail"):
            rod = f["rods"][name]
            section = rod_section(text, name)
            what = "summary of %s" % name
            check(section.startswith("rod '%s' (%s)" % (name, rod.attrs["formulation"])),
                  "%s: formulation in the heading: %r" % (what, section[:60]))
            time = rod["time"][()]
            has_line(section, "records", "%d, t = %s .. %s s" % (time.size, g(time[0]),
                                                                  g(time[-1])), what)
            dt = rod["series/dt"][1:]
            has_line(section, "dt", "%s .. %s s" % (g(dt.min()), g(dt.max())), what)
            iterations = rod["series/newton/iterations"][()]
            has_line(section, "Newton iterations", "%d total, %d max per step (stored records)"
                     % (iterations.sum(), iterations.max()), what)
            error = np.abs(rod["series/energy/balance_error"][()]).max()
            scale = np.abs(rod["series/energy/total"][()]).max()
            has_line(section, "max |balance error|", "%s J = %s max |H|"
                     % (g(error), g(error / scale)), what)
            if "constraint_residual" in rod["series"]:
                has_line(section, "constraint residual",
                         "max %s" % g(rod["series/constraint_residual"][()].max()), what)
            else:
                has_line(section, "constraint residual", "not stored", what)
            fields = sorted(k for k, v in rod.items() if isinstance(v, h5py.Dataset))
            listed = re.search(r"fields\s+(.*?)\n\s*series", section, re.DOTALL)
            check(listed is not None and listed.group(1).split() ==
                  [n + "," for n in fields[:-1]] + fields[-1:],
                  "%s: fields %s in %r" % (what, fields, section))
    check("branch_stress" in rod_section(text, "arm")
          and "branch_stress" not in rod_section(text, "tail"),
          "summary: branch_stress only for arm")

    out = os.path.join(out_dir, "summary.txt")
    p = run(rodplot, "summary", result, "-o", out)
    check(p.returncode == 0 and os.path.isfile(out), "summary -o: exit %d" % p.returncode)
    if os.path.isfile(out):
        with open(out, encoding="utf-8") as f:
            check(f.read() == text, "summary -o writes the printed text")
    p = run(rodplot, "summary", result, "--rod", "tail")
    check(p.returncode == 0 and "rod 'tail'" in p.stdout and "rod 'arm'" not in p.stdout,
          "summary --rod tail: only tail: %r" % p.stdout)
    p = run(rodplot, "summary", result, "--rod", "no_such_rod")
    check(p.returncode == 2 and "no_such_rod" in p.stderr and "arm, tail" in p.stderr,
          "summary, wrong rod: exit %d: %r" % (p.returncode, p.stderr))
    p = run(rodplot, "summary", os.path.join(out_dir, "does_not_exist.h5"))
    check(p.returncode == 2 and "no such file" in p.stderr,
          "summary, missing file: exit %d: %r" % (p.returncode, p.stderr))
    helix = os.path.join(out_dir, "helix_summary.h5")
    write_helix_file(helix, 5)
    p = run(rodplot, "summary", helix)
    check(p.returncode == 0 and "constraint residual  not stored" in p.stdout
          and "records              5, t = 0 .. 6.28319 s" in p.stdout,
          "summary of a file without series: exit %d: %r %r" % (p.returncode, p.stdout, p.stderr))


def main():
    rodplot, result, out_dir = sys.argv[1:4]
    os.makedirs(out_dir, exist_ok=True)

    for command, extra in (("energy", []), ("snapshots", []), ("energy", ["--rod", "tail"]),
                           ("snapshots", ["--rod", "arm"]), ("tip", []), ("tip", ["--rod", "arm"]),
                           ("momentum", []), ("momentum", ["--rod", "tail"])):
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
    for word in ("energy", "momentum", "snapshots", "tip", "animate", "summary", "--rod",
                 "--output", "--plane", "--frames", "--fps", "exit status", "viridis", "Pillow"):
        check(word in p.stdout, "--help mentions %s" % word)

    tip_checks(rodplot, out_dir)
    momentum_checks(rodplot, out_dir)
    animate_checks(rodplot, result, out_dir)
    summary_checks(rodplot, result, out_dir)

    for message in failures:
        print("FAILED: " + message)
    print("%d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
