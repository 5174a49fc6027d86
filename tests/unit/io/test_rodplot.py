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
`sweep` and the summary of a sweep run on synthetic sweep files written here with h5py in the
layout of src/app/run_sweep.F90 (/members/<id>, /summary; one parameter in logspace with a
failed and a member not run, and a product of two parameters): the figure's curve holds exactly
the completed members' values sorted by the parameter, on log axes for a logspace parameter and
linear ones for a linspace, the failed and not-run members are drawn at their parameter values
with their own markers, the tip components and the parameter are found by every documented
name, one curve per value of the other parameter; unknown names, a file that is not a sweep and
a rod command on a sweep file exit with status 2 naming what there is; the sweep summary's
counts, ranges, per-rank wall time and failure messages match the file.
`contact` draws the bundle series of the rod that has them ('arm'): the curves are
|contact force|, penetration, contact energy and |tie force| at both ends of the closed form of
test_result_file.F90; for a rod without them ('tail') it exits with status 2 naming the rod.
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


SWEEP_PARAMETER = "rod(1)%EI1"


def write_sweep_file(path, parameters, status, rank, seed=1):
    """A synthetic sweep result (the layout of src/app/run_sweep.F90): `parameters` maps a
    parameter path to its values per member; tip z = -1 / (3 EI1 ...), a wall time per member,
    NaN where a member did not complete; /members/<id> with the parameters as attributes."""
    rng = np.random.default_rng(seed)
    names = list(parameters)
    values = np.stack([np.asarray(parameters[n], dtype=float) for n in names], axis=1)
    n = values.shape[0]
    status = np.asarray(status)
    done = status == 0
    scale = values.prod(axis=1)
    tip = np.stack([np.full(n, 1.0), np.zeros(n), -1.0 / (3.0 * scale)], axis=1)
    wall = np.where(status == 2, -1.0, 0.5 + rng.random(n))
    nan = np.full(n, np.nan)
    tip[~done] = np.nan
    with h5py.File(path, "w") as f:
        f.attrs["schema_version"] = 1
        f.attrs["title"] = "synthetic sweep"
        f.attrs["creator"] = "test_rodplot.py"
        f.attrs["n_ranks"] = int(max(rank) + 1)
        f.attrs["status"] = "completed" if done.all() else "some members failed"
        f.attrs["members"] = n
        f.attrs["wall_time"] = float(wall[wall > 0].sum())
        for i in range(n):
            g = f.create_group("members/%d" % (i + 1))
            for k, name in enumerate(names):
                g.attrs[name] = values[i, k]
            g.attrs["status"] = ("completed", "failed", "not run")[status[i]]
            g.attrs["message"] = ("", "Newton failed after 0 cut-backs at t = 0.1",
                                  "not run")[status[i]]
            g.attrs["wall_time"] = wall[i]
        s = f.create_group("summary")
        s["id"] = np.arange(1, n + 1, dtype=np.int32)
        for k, name in enumerate(names):
            s["parameters/" + name] = values[:, k]
            s["parameters/" + name].attrs["unit"] = "-"
        s["status"] = status.astype(np.int32)
        s["wall_time"] = wall
        s["wall_time"].attrs["unit"] = "s"
        s["final_time"] = np.where(done, 1.0, nan)
        s["final_time"].attrs["unit"] = "s"
        s["tip_position"] = tip
        s["tip_position"].attrs["unit"] = "m"
        s["tip_position"].attrs["description"] = "position of the last node of rod 'beam'"
        s["max_balance_error"] = np.where(done, 1e-14 * (1 + np.arange(n)), nan)
        s["max_balance_error"].attrs["unit"] = "J"
        s["newton_iterations"] = np.where(done, 10.0 + np.arange(n), nan)
        s["records"] = np.where(done, 11, 0).astype(np.int32)
        s["rank"] = np.asarray(rank, dtype=np.int32)
    return values, tip, wall


def data_lines(ax):
    """The axes' lines drawn in data coordinates (the curves), and the others (markers at
    the axis), as (marker, x, y) tuples."""
    curves, at_axis = [], []
    for line in ax.get_lines():
        item = (line.get_marker(), np.asarray(line.get_xdata(), dtype=float),
                np.asarray(line.get_ydata(), dtype=float))
        (curves if line.get_transform() == ax.transData else at_axis).append(item)
    return curves, at_axis


def sweep_checks(rodplot, result, out_dir):
    sys.path.insert(0, os.path.dirname(os.path.abspath(rodplot)))
    import rodplot as module
    from rodresults import open_result

    # One parameter in logspace: member 3 failed, member 8 not run.
    one = os.path.join(out_dir, "sweep_one.h5")
    ei = np.logspace(0, 3, 8)
    status = [0, 0, 1, 0, 0, 0, 0, 2]
    rank = [0, 1, 1, 0, 1, 0, 1, -1]
    values, tip, wall = write_sweep_file(one, {SWEEP_PARAMETER: ei[::-1]}, status, rank)
    x = values[:, 0]
    done = np.asarray(status) == 0
    with open_result(one) as res:
        table = module.SweepTable(res)
        for name in ("tip_z", "tip_position:z", "tip_position:3", "tip_position:Z"):
            _, got, unit, _ = table.quantity(name)
            check(np.array_equal(got, tip[:, 2], equal_nan=True) and unit == "m",
                  "sweep: quantity %s is /summary/tip_position[:, 2] in m" % name)
        _, got, _, _ = table.quantity("tip_x")
        check(np.array_equal(got, tip[:, 0], equal_nan=True), "sweep: tip_x is column 0")
        for name in (SWEEP_PARAMETER, "ROD(1)%ei1", "EI1", None):
            check(table.parameter(name) == SWEEP_PARAMETER,
                  "sweep: parameter %r found as %s" % (name, SWEEP_PARAMETER))
        fig, ax = module.sweep_figure(res, None, "tip_z")
        curves, at_axis = data_lines(ax)
        order = np.argsort(x[done])
        check(len(curves) == 1 and np.array_equal(curves[0][1], x[done][order])
              and np.array_equal(curves[0][2], tip[done, 2][order]),
              "sweep: one curve of the 6 completed members sorted by EI1: %s" % curves)
        markers = {m: xs for m, xs, _ in at_axis}
        check(set(markers) == {"x", "s"} and np.array_equal(markers["x"], x[[2]])
              and np.array_equal(markers["s"], x[[7]]),
              "sweep: failed (x) and not run (s) members at their EI1: %s" % markers)
        check(ax.get_xscale() == "log" and ax.get_yscale() == "linear",
              "sweep: auto scales of a logspace EI1 against a tip z spanning 1e3: %s, %s"
              % (ax.get_xscale(), ax.get_yscale()))
        module.plt.close(fig)
        fig, ax = module.sweep_figure(res, "EI1", "max_balance_error", "linear", "log")
        check(ax.get_xscale() == "linear" and ax.get_yscale() == "log",
              "sweep: --xscale linear --yscale log: %s, %s" % (ax.get_xscale(), ax.get_yscale()))
        module.plt.close(fig)
    check(module.auto_log(np.logspace(0, 3, 8), 10.0, True)
          and not module.auto_log(np.linspace(1, 1000, 8), 10.0, True)
          and not module.auto_log(np.linspace(-1, 1, 8), 10.0, True),
          "auto_log: log for a logspace, linear for a linspace and for signed values")

    for extra in ([], ["--x", SWEEP_PARAMETER, "--logy"], ["--x", "EI1", "--y", "tip_position:1"]):
        out = os.path.join(out_dir, "sweep%s.png" % len(extra))
        if os.path.exists(out):
            os.remove(out)
        args = extra if "--y" in extra else extra + ["--y", "tip_z"]
        p = run(rodplot, "sweep", one, "-o", out, *args)
        check(p.returncode == 0, "sweep %s: exit %d: %s" % (args, p.returncode, p.stderr))
        check_png(out, "sweep %s" % args)
    default = os.path.splitext(one)[0] + "_sweep.png"
    p = run(rodplot, "sweep", one, "--y", "wall_time")
    check(p.returncode == 0 and os.path.isfile(default),
          "sweep without -o writes %s: exit %d: %s" % (default, p.returncode, p.stderr))
    never = os.path.join(out_dir, "never.png")
    for args, words in ((["--x", "EI2", "--y", "tip_z"], ["EI2", SWEEP_PARAMETER]),
                        (["--y", "tip_w"], ["tip_w", "tip_x, tip_y, tip_z", "final_time"]),
                        (["--y", "tip_position:4"], ["x, y, z"])):
        p = run(rodplot, "sweep", one, "-o", never, *args)
        check(p.returncode == 2 and all(w in p.stderr for w in words),
              "sweep %s: exit %d, expected 2 naming %s: %r" % (args, p.returncode, words,
                                                               p.stderr))
    p = run(rodplot, "sweep", one, "-o", never)
    check(p.returncode == 2 and "--y" in p.stderr,
          "sweep without --y: usage error: exit %d: %r" % (p.returncode, p.stderr))
    p = run(rodplot, "sweep", result, "--y", "tip_z", "-o", never)
    check(p.returncode == 2 and "not a sweep" in p.stderr,
          "sweep on a single run's file: exit %d: %r" % (p.returncode, p.stderr))
    p = run(rodplot, "energy", one, "-o", never)
    check(p.returncode == 2 and "sweep" in p.stderr and "/members/<id>" in p.stderr,
          "energy on a sweep file: exit %d: %r" % (p.returncode, p.stderr))
    check(not os.path.exists(never), "no image for failed sweep plots")

    # A product of two parameters in linspace: one curve per load.
    two = os.path.join(out_dir, "sweep_two.h5")
    ei2 = np.tile(np.linspace(1.0, 4.0, 4), 3)
    load = np.repeat([1.0, 2.0, 3.0], 4)
    write_sweep_file(two, {SWEEP_PARAMETER: ei2, "load(1)%amplitude": load}, [0] * 12,
                     [0, 1] * 6)
    with open_result(two) as res:
        p = None
        try:
            module.sweep_figure(res, None, "tip_z")
        except module.MissingData as exc:
            p = str(exc)
        check(p is not None and "--x" in p and "load(1)%amplitude" in p,
              "sweep: two parameters and no --x: an error naming both: %r" % p)
        fig, ax = module.sweep_figure(res, "EI1", "tip_z")
        curves, at_axis = data_lines(ax)
        check(len(curves) == 3 and not at_axis and all(
            np.array_equal(c[1], np.linspace(1.0, 4.0, 4)) and np.allclose(
                c[2], -1.0 / (3.0 * np.linspace(1.0, 4.0, 4) * a), rtol=1e-14, atol=0)
            for c, a in zip(curves, (1.0, 2.0, 3.0))),
            "sweep: one curve per load amplitude, sorted by EI1: %s" % curves)
        labels = ax.get_legend_handles_labels()[1]
        check(labels == ["load(1)%%amplitude = %g" % a for a in (1, 2, 3)],
              "sweep: curves labelled by the other parameter: %s" % labels)
        check(ax.get_xscale() == "linear", "sweep: linspace EI1 on a linear axis")
        module.plt.close(fig)

    # The summary of a sweep.
    p = run(rodplot, "summary", one)
    check(p.returncode == 0, "summary of a sweep: exit %d: %s" % (p.returncode, p.stderr))
    text = p.stdout
    has_line(text, "members", "8: 6 completed, 1 failed, 1 not run", "sweep summary")
    has_line(text, "status", "some members failed", "sweep summary")
    has_line(text, SWEEP_PARAMETER, "8 values, 1 .. 1000, evenly spaced in log", "sweep summary")
    ran = np.asarray(status) != 2
    has_line(text, "wall time per member", "%s .. %s s, median %s s, sum %s s"
             % (g(wall[ran].min()), g(wall[ran].max()), g(np.median(wall[ran])),
                g(wall[ran].sum())), "sweep summary")
    loads = [wall[ran & (np.asarray(rank) == r)].sum() for r in (0, 1)]
    has_line(text, "rank 0", "3 members, %s s" % g(loads[0]), "sweep summary")
    has_line(text, "rank 1", "4 members, %s s" % g(loads[1]), "sweep summary")
    has_line(text, "slowest rank / mean", "%.3f (members' wall time summed per rank)"
             % (max(loads) / np.mean(loads)), "sweep summary")
    has_line(text, "Newton iterations", "%s .. %s per member, %d in all"
             % (g(10 + np.flatnonzero(done).min()), g(10 + np.flatnonzero(done).max()),
                (10 + np.flatnonzero(done)).sum()), "sweep summary")
    check("id 3 (%s = %s), failed: Newton failed after 0 cut-backs" % (SWEEP_PARAMETER, g(x[2]))
          in text and "id 8 (%s = %s), not run\n" % (SWEEP_PARAMETER, g(x[7])) in text,
          "sweep summary lists the failed and the not-run member: %r" % text)
    check("\nmembers\n" not in text, "sweep summary: no member rows without --members")
    p = run(rodplot, "summary", one, "--members")
    rows = p.stdout.split("\nmembers\n")[-1].strip().splitlines()
    check(p.returncode == 0 and len(rows) == 9 and rows[0].split()[:2] == ["id", SWEEP_PARAMETER]
          and rows[3].split()[-1] == "failed" and rows[8].split()[-1] == "run",
          "summary --members: a header and 8 rows: %r" % rows)
    p = run(rodplot, "summary", one, "--rod", "beam")
    check(p.returncode == 2 and "/members/<id>" in p.stderr,
          "summary --rod on a sweep: exit %d: %r" % (p.returncode, p.stderr))


def contact_checks(rodplot, result, out_dir):
    """`contact` on the file of test_result_file.F90: 'arm' has the bundle series (its closed
    form: contact force (j, -2j, 0.5), penetration 1e-5 (j mod 3), energy 1e-3 j, friction
    force (j / 4, 0, -1), slip speed 1e-3 j, tie force (e, 10j, -e j) on end e = 1 (start),
    2 (end), record j = 1, 2, ...), 'tail' none."""
    out = os.path.join(out_dir, "contact.png")
    if os.path.exists(out):
        os.remove(out)
    p = run(rodplot, "contact", result, "-o", out)
    check(p.returncode == 0, "contact: exit %d: %s" % (p.returncode, p.stderr))
    check_png(out, "contact")
    p = run(rodplot, "contact", result, "--rod", "tail", "-o",
            os.path.join(out_dir, "never_contact.png"))
    check(p.returncode == 2, "contact --rod tail: exit %d, expected 2" % p.returncode)
    check("rod 'tail' has no contact or tie series" in p.stderr,
          "contact --rod tail: message %r" % p.stderr)

    sys.path.insert(0, os.path.dirname(os.path.abspath(rodplot)))
    import rodplot as module
    from rodresults import open_result
    with open_result(result) as res:
        n = len(res.rod("arm").field("time"))
        j = np.arange(1.0, n + 1)
        expected = [
            [np.sqrt(j**2 + 4 * j**2 + 0.25)],
            [1.0e-5 * (j % 3)],
            [1.0e-3 * j],
            [np.sqrt((0.25 * j)**2 + 1.0)],
            [1.0e-3 * j],
            [np.sqrt(1 + 101 * j**2), np.sqrt(4 + 104 * j**2)],
        ]
        fig, axes = module.contact_figure(res)
        check(len(axes) == 6, "contact: 6 panels (with friction), got %d" % len(axes))
        for number, (ax, want) in enumerate(zip(axes, expected)):
            curves, _ = data_lines(ax)
            check(len(curves) == len(want), "contact panel %d: %d curves (only arm), got %d"
                  % (number, len(want), len(curves)))
            for (_, _, y), w in zip(curves, want):
                check(y.shape == w.shape and np.allclose(y, w, rtol=1e-12, atol=0),
                      "contact panel %d: %s, expected %s" % (number, y, w))
        module.plt.close(fig)


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
    for word in ("energy", "momentum", "snapshots", "tip", "animate", "summary", "contact",
                 "--rod",
                 "--output", "--plane", "--frames", "--fps", "exit status", "viridis", "Pillow",
                 "sweep", "--x", "--y", "--logx", "--yscale", "--members", "tip_z"):
        check(word in p.stdout, "--help mentions %s" % word)

    tip_checks(rodplot, out_dir)
    momentum_checks(rodplot, out_dir)
    animate_checks(rodplot, result, out_dir)
    summary_checks(rodplot, result, out_dir)
    sweep_checks(rodplot, result, out_dir)
    contact_checks(rodplot, result, out_dir)

    for message in failures:
        print("FAILED: " + message)
    print("%d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
