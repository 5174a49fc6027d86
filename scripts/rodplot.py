#!/usr/bin/env python3
"""Plots and a summary of rodsolve result files (docs/user/output.md,
docs/user/postprocessing.md).

    python3 scripts/rodplot.py energy out/flying_spaghetti.h5
    python3 scripts/rodplot.py momentum out/flying_spaghetti.h5
    python3 scripts/rodplot.py snapshots out/flying_spaghetti.h5 -o spaghetti.png --rod spaghetti
    python3 scripts/rodplot.py tip out/soft_arm_circle.h5 --plane xy
    python3 scripts/rodplot.py animate out/flying_spaghetti.h5 -o spaghetti.gif
    python3 scripts/rodplot.py summary out/flying_spaghetti.h5
    python3 scripts/rodplot.py contact out/pressed_rods.h5
    python3 scripts/rodplot.py modes out/modes_cantilever.h5
    python3 scripts/rodplot.py path out/arch_snap_through.h5
    python3 scripts/rodplot.py sweep out/sweep_cantilever.h5 --x 'rod(1)%EI1' --y tip_z
    python3 scripts/rodplot.py summary out/sweep_cantilever.h5

Exit status 0 on success, 1 when the output cannot be written (or Pillow, needed for GIFs, is
missing), 2 for a missing file, a file that is not a rodsolve result, an unknown rod or a
missing dataset (the message names what is available) and for usage errors: for `sweep`, a
file that is not a sweep's, an unknown parameter or quantity (the message lists them).
"""

import argparse
import os
import re
import sys
import textwrap

try:
    import matplotlib

    matplotlib.use("Agg")
    import h5py
    import matplotlib.pyplot as plt
    import matplotlib.transforms
    import numpy as np

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from rodresults import MissingData, ResultError, open_result
except ImportError as exc:
    sys.exit("rodplot.py: %s; it needs h5py, numpy and matplotlib (Debian: apt-get install "
             "python3-h5py python3-matplotlib; run it with /usr/bin/python3)" % exc)

#: Snapshots drawn by `snapshots` (fewer when fewer records are stored).
N_SNAPSHOTS = 12
#: View of the 3D snapshots, as in the figures of seed 000 (methods/ph_director_3d.md §6.1).
VIEW_AZIM, VIEW_ELEV = 55, 15

ENERGY_CURVES = (
    ("energy/total", "total H", {"color": "k", "lw": 2.0}),
    ("energy/kinetic", "kinetic", {"color": "tab:blue"}),
    ("energy/strain", "strain", {"color": "tab:orange"}),
)


def series_source(res, rod_name):
    """(time, series names, getter, description) of one rod's series (`rod_name`) or, for
    None, of the sums over all rods in /series/."""
    if rod_name is not None:
        rod = res.rod(rod_name)
        return (rod.field("time"), rod.series_names(), rod.series,
                "rod '%s' (%s)" % (rod_name, rod.formulation))
    what = "all rods" if len(res.rods()) != 1 else "rod '%s'" % res.rods()[0]
    return res.time(), res.series_names(), res.series, what


def energy_plot(res, rod_name, out, dpi):
    """H, kinetic, strain and the accumulated external work; |balance error| on a log axis."""
    time, names, get, what = series_source(res, rod_name)
    wanted = [c[0] for c in ENERGY_CURVES] + ["energy/external_work", "energy/balance_error"]
    if not any(name in names for name in wanted):
        raise MissingData("%s: %s has no energy series (it has: %s)"
                          % (res.path, what, ", ".join(names) or "nothing"))

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 7), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 2]})
    for name, label, style in ENERGY_CURVES:
        if name in names:
            top.plot(time, get(name), label=label, **style)
    if "energy/external_work" in names:
        top.plot(time, np.cumsum(get("energy/external_work")), "--", color="tab:green",
                 label="external work (accumulated)")
    top.set_ylabel("energy [J]")
    top.legend(loc="best")
    top.grid(True, alpha=0.3)
    top.set_title("%s: energy, %s" % (res.title or os.path.basename(res.path), what))

    if "energy/balance_error" in names:
        error = np.abs(get("energy/balance_error"))
        positive = error > 0
        if positive.any():
            bottom.semilogy(time[positive], error[positive], ".-", color="tab:red")
        else:
            bottom.set_yscale("log")
            bottom.text(0.5, 0.5, "balance error is exactly zero at every record",
                        transform=bottom.transAxes, ha="center", va="center")
        bottom.set_ylabel("|balance error| [J]")
    else:
        bottom.text(0.5, 0.5, "no balance error stored", transform=bottom.transAxes,
                    ha="center", va="center")
    bottom.set_xlabel("time [s]")
    bottom.grid(True, which="both", alpha=0.3)
    bottom.set_title("energy balance error |H$_{n+1}$ - H$_n$ - W$_{ext}$ - W$_{act}$ + D| "
                     "per record", fontsize="medium")
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def equal_3d_axes(ax, points):
    """Equal scaling on a 3D axis around `points` (n x 3), in the view of seed 000's figures."""
    low, high = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (low + high)
    half = 0.5 * max(float((high - low).max()), 1e-12)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=VIEW_ELEV, azim=VIEW_AZIM)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")


def snapshot_indices(n_records, n_snapshots=N_SNAPSHOTS):
    """About `n_snapshots` evenly spaced record indices, first and last included."""
    if n_records <= 0:
        return np.array([], dtype=int)
    count = min(n_snapshots, n_records)
    return np.unique(np.round(np.linspace(0, n_records - 1, count)).astype(int))


def snapshots_plot(res, rod_name, out, dpi):
    """3D centrelines at about 12 stored times, coloured by time, equal axis scaling."""
    names = [rod_name] if rod_name is not None else res.rods()
    if not names:
        raise MissingData("%s: the file holds no rods" % res.path)
    rods = [res.rod(name) for name in names]
    time = rods[0].field("time")
    if time.size == 0:
        raise MissingData("%s: no stored records" % res.path)
    index = snapshot_indices(time.size)
    norm = matplotlib.colors.Normalize(vmin=time[0], vmax=max(time[-1], time[0] + 1e-300))
    cmap = matplotlib.colormaps["viridis"]

    fig = plt.figure(figsize=(8, 7))
    ax = fig.add_subplot(projection="3d")
    points = []
    styles = ("-", "--", ":", "-.")
    for number, rod in enumerate(rods):
        position = rod.field("position")
        style = styles[number % len(styles)]
        for k in index:
            x = position[k]
            ax.plot(x[:, 0], x[:, 1], x[:, 2], style, color=cmap(norm(time[k])), lw=1.5)
            points.append(x)
        if len(rods) > 1:
            ax.plot([], [], style, color="0.3", label=rod.name)
    points = np.concatenate(points)
    equal_3d_axes(ax, points)
    label = ", ".join("'%s'" % n for n in names)
    ax.set_title("%s: %s at %d times" % (res.title or os.path.basename(res.path), label,
                                          index.size))
    bar = fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax,
                       shrink=0.6, pad=0.1)
    bar.set_label("time [s]")
    if len(rods) > 1:
        ax.legend(loc="upper left", title="rod")
    fig.savefig(out, dpi=dpi, bbox_inches="tight")
    plt.close(fig)


#: Mode shapes drawn by `modes` (the lowest ones).
N_MODE_SHAPES = 6


def modes_plot(res, rod_name, out, dpi):
    """The modes of /modes (docs/user/output.md): per system the frequencies against the mode
    number, and the shapes of the lowest N_MODE_SHAPES modes, each drawn on the reference
    centreline with its displacement scaled to a tenth of the system's extent. The table of
    frequencies is also printed."""
    if "modes" not in res.file:
        raise MissingData("%s has no /modes: the scene had no &modes group" % res.path)
    systems = [name for name in res.file["modes"]
               if rod_name is None or rod_name == name or rod_name in res.file["modes"][name]]
    if not systems:
        raise MissingData("%s: no modes of rod '%s'; systems with modes: %s" % (
            res.path, rod_name, ", ".join(res.file["modes"])))
    groups = [res.file["modes"][name] for name in systems]
    shapes = max(min(N_MODE_SHAPES, g["frequency"].shape[0]) for g in groups)
    fig = plt.figure(figsize=(4.5 * (1 + min(shapes, 3)), 4.0 * len(groups) * (
        1 + (shapes > 3))))
    rows = len(groups) * (1 + (shapes > 3))
    columns = 1 + min(shapes, 3)
    for number, (name, group) in enumerate(zip(systems, groups)):
        frequency = group["frequency"][()]
        unit = _attr_text(group["frequency"], "unit")
        print("modes of %s (%s):" % (name, unit))
        for k, f in enumerate(frequency):
            print("  %3d  %.8g" % (k + 1, f))
        row = number * (1 + (shapes > 3))
        ax = fig.add_subplot(rows, columns, row * columns + 1)
        ax.plot(np.arange(1, frequency.size + 1), np.abs(frequency), "o-", color="tab:blue")
        ax.set_xlabel("mode")
        ax.set_ylabel(axis_label("|frequency|", unit))
        if np.all(np.abs(frequency) > 0) and np.ptp(np.log10(np.abs(frequency))) > 2:
            ax.set_yscale("log")
        ax.set_title("%s: %d modes" % (name, frequency.size))
        rods = [key for key in group if isinstance(group[key], h5py.Group)]
        if not rods:
            continue
        position = np.concatenate([group[r]["position"][()] for r in rods])
        extent = max(np.ptp(position, axis=0).max(), 1e-300)
        for k in range(min(shapes, frequency.size)):
            slot = row * columns + 2 + k + (k >= 3)
            ax = fig.add_subplot(rows, columns, slot, projection="3d")
            points = []
            for r in rods:
                x = group[r]["position"][()]
                u = group[r]["displacement"][k]
                ax.plot(x[:, 0], x[:, 1], x[:, 2], "--", color="0.6", lw=1.0)
                y = x + 0.1 * extent * u
                ax.plot(y[:, 0], y[:, 1], y[:, 2], "-", color="tab:red", lw=1.5)
                points += [x, y]
            equal_3d_axes(ax, np.concatenate(points))
            ax.set_title("mode %d: %.5g %s" % (k + 1, frequency[k], unit), fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def limit_points(load_time):
    """Indices of the path points where the load time turns (a local maximum or minimum:
    limit points of an arc-length continuation)."""
    turns = []
    for k in range(1, load_time.size - 1):
        before, after = load_time[k] - load_time[k - 1], load_time[k + 1] - load_time[k]
        if before * after < 0:
            turns.append(k)
    return turns


def path_plot(res, rod_name, out, dpi):
    """An arc-length continuation's equilibrium path (series/load_time, docs/theory/
    continuation.md): per rod the load time against the displacement of the node that moves
    farthest (each component and the magnitude), the limit points marked and printed."""
    names = [rod_name] if rod_name is not None else res.rods()
    names = [n for n in names if res.rod(n).has("series/load_time")]
    if not names:
        raise MissingData("%s: no rod has series/load_time: the scene was not an arc-length "
                          "continuation (&time continuation)" % res.path)
    fig, axes = plt.subplots(1, len(names), figsize=(6.5 * len(names), 5.0), squeeze=False)
    for ax, name in zip(axes[0], names):
        rod = res.rod(name)
        load = rod.field("series/load_time")
        position = rod.field("position")
        displacement = position - position[0]
        node = int(np.argmax(np.abs(displacement).max(axis=(0, 2))))
        u = displacement[:, node, :]
        for k, colour in enumerate(("tab:blue", "tab:orange", "tab:green")):
            if np.abs(u[:, k]).max() > 0:
                ax.plot(u[:, k], load, "-", color=colour, lw=1.2, label="u_" + AXIS_NAMES[k])
        ax.plot(np.linalg.norm(u, axis=1), load, "k--", lw=1.0, label="|u|")
        print("path of %s: %d points, load time %.8g to %.8g, node %d moves farthest" % (
            name, load.size, load.min(), load.max(), node + 1))
        for k in limit_points(load):
            print("  limit point near step %d: load time %.8g" % (k, load[k]))
            ax.axhline(load[k], color="tab:red", lw=0.8, ls=":")
        ax.set_xlabel("displacement of node %d [m]" % (node + 1))
        ax.set_ylabel("load time")
        ax.set_title("%s: equilibrium path" % name)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best")
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


#: Coordinate planes of the `tip` projection: name -> the two axes drawn.
PLANES = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
AXIS_NAMES = ("x", "y", "z")


def tip_path(rod):
    """(time, position of the last node) of a rod: arrays (records,) and (records, 3)."""
    time = rod.field("time")
    position = rod.field("position")
    if time.size == 0 or position.shape[0] == 0:
        raise MissingData("rod '%s' has no stored records" % rod.name)
    return time, position[:, -1, :]


def projection_plane(paths, plane="auto"):
    """The two axes of the projection: those of `plane` ('xy', 'xz', 'yz'), or for 'auto'
    the plane normal to the coordinate axis along which the tip paths move least."""
    if plane != "auto":
        return PLANES[plane]
    spread = np.ptp(np.concatenate(paths), axis=0)
    normal = int(np.argmin(spread))
    return tuple(axis for axis in range(3) if axis != normal)


def tip_plot(res, rod_name, out, dpi, plane="auto"):
    """Path of the last node (the tip) of each rod over time: in 3D (line, points coloured by
    time, equal axis scaling, the view of seed 000's figures) and projected on a coordinate
    plane (`plane`; 'auto': the plane across which the tip moves least, the e1-e2 plane for
    the soft arm of seed 000 §6.4, where it shows the circle and the heart)."""
    names = [rod_name] if rod_name is not None else res.rods()
    if not names:
        raise MissingData("%s: the file holds no rods" % res.path)
    tracks = [(name,) + tip_path(res.rod(name)) for name in names]
    axes = projection_plane([path for _, _, path in tracks], plane)
    t_low = min(time[0] for _, time, _ in tracks)
    t_high = max(time[-1] for _, time, _ in tracks)
    norm = matplotlib.colors.Normalize(vmin=t_low, vmax=max(t_high, t_low + 1e-300))
    cmap = matplotlib.colormaps["viridis"]

    fig = plt.figure(figsize=(13, 5.5))
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ax2 = fig.add_subplot(1, 2, 2)
    styles = ("-", "--", ":", "-.")
    for number, (name, time, path) in enumerate(tracks):
        style = styles[number % len(styles)]
        label = name if len(tracks) > 1 else None
        ax3.plot(path[:, 0], path[:, 1], path[:, 2], style, color="0.6", lw=1.0, label=label)
        ax3.scatter(path[:, 0], path[:, 1], path[:, 2], c=time, cmap=cmap, norm=norm, s=8)
        ax2.plot(path[:, axes[0]], path[:, axes[1]], style, color="0.6", lw=1.0, label=label)
        ax2.scatter(path[:, axes[0]], path[:, axes[1]], c=time, cmap=cmap, norm=norm, s=8)
        ax2.plot(path[0, axes[0]], path[0, axes[1]], "ko", ms=5, mfc="none")
    points = np.concatenate([path for _, _, path in tracks])
    equal_3d_axes(ax3, points)
    ax3.set_title("%s: tip path" % (res.title or os.path.basename(res.path)))
    ax2.set_aspect("equal", adjustable="datalim")
    ax2.set_xlabel("%s [m]" % AXIS_NAMES[axes[0]])
    ax2.set_ylabel("%s [m]" % AXIS_NAMES[axes[1]])
    ax2.set_title("projected on the %s-%s plane (open circle: start)"
                  % (AXIS_NAMES[axes[0]], AXIS_NAMES[axes[1]]))
    ax2.grid(True, alpha=0.3)
    if len(tracks) > 1:
        ax2.legend(title="rod", loc="best")
    bar = fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=[ax3, ax2],
                       shrink=0.7, pad=0.02)
    bar.set_label("time [s]")
    fig.savefig(out, dpi=dpi, bbox_inches="tight")
    plt.close(fig)


COMPONENT_STYLES = (("x", "tab:blue"), ("y", "tab:orange"), ("z", "tab:green"))


def log_abs_panel(ax, time, values, label, color):
    """|values| per record on a log axis (the largest |component| for vector series); a note
    instead when all are exactly zero."""
    values = np.asarray(values, dtype=float)
    size = np.abs(values) if values.ndim == 1 else np.abs(values).max(axis=1)
    positive = size > 0
    if positive.any():
        ax.semilogy(time[positive], size[positive], ".-", color=color, label=label)
        return True
    return False


def momentum_plot(res, rod_name, out, dpi):
    """Linear and angular momentum components and magnitudes against time; below, the
    momentum balance series the file holds (e.g. momentum/angular_balance_error), |.| on a
    log axis."""
    time, names, get, what = series_source(res, rod_name)
    parts = [(name, title, unit) for name, title, unit in (
        ("momentum/linear", "linear momentum", "kg m/s"),
        ("momentum/angular", "angular momentum about the origin", "kg m$^2$/s"))
        if name in names]
    if not parts:
        raise MissingData("%s: %s has no momentum series (it has: %s)"
                          % (res.path, what, ", ".join(names) or "nothing"))
    balance = [name for name in names if name.startswith("momentum/") and "balance" in name]
    rows = len(parts) + (1 if balance else 0)
    fig, axes = plt.subplots(rows, 1, figsize=(8, 3.2 * rows + 0.6), sharex=True, squeeze=False)
    axes = axes[:, 0]
    for ax, (name, title, unit) in zip(axes, parts):
        values = np.asarray(get(name), dtype=float).reshape(len(time), -1)
        for c in range(values.shape[1]):
            label, color = COMPONENT_STYLES[c % 3]
            ax.plot(time, values[:, c], color=color, label=label)
        ax.plot(time, np.linalg.norm(values, axis=1), "--", color="k", lw=1.0, label="magnitude")
        ax.set_ylabel("%s [%s]" % (name.split("/")[1], unit))
        ax.set_title(title, fontsize="medium")
        ax.legend(loc="best", ncol=4, fontsize="small")
        ax.grid(True, alpha=0.3)
    if balance:
        ax = axes[-1]
        drawn = False
        for number, name in enumerate(balance):
            drawn |= log_abs_panel(ax, time, get(name), name,
                                   ("tab:red", "tab:purple", "tab:brown")[number % 3])
        if drawn:
            ax.legend(loc="best", fontsize="small")
        else:
            ax.set_yscale("log")
            ax.text(0.5, 0.5, "balance error is exactly zero at every record",
                    transform=ax.transAxes, ha="center", va="center")
        ax.set_ylabel("|balance error|")
        ax.set_title("momentum balance per record (largest |component|)", fontsize="medium")
        ax.grid(True, which="both", alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle("%s: momentum, %s" % (res.title or os.path.basename(res.path), what))
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


#: The bundle series of a rod (docs/user/output.md): contact force, penetration, energy share.
CONTACT_SERIES = ("contact/force", "contact/penetration", "contact/energy")
#: Friction of each step (&contact or &obstacle mu): drawn when a rod has any.
FRICTION_SERIES = ("contact/friction", "contact/slip_speed")
TIE_SERIES = "ties/force"


def contact_plot(res, rod_name, out, dpi):
    """Write the figure of `contact_figure` to `out`."""
    fig, _ = contact_figure(res, rod_name)
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def contact_figure(res, rod_name=None):
    """(figure, axes): per rod of a bundle, |contact force|, deepest penetration and contact
    energy share against time, |friction force| and the largest slip speed when a rod has
    friction (a non-zero series/contact/friction), and |tie force| on its start (solid) and end
    (dashed) when the file has series/ties/force. The axes are those of the panels drawn, in
    this order; rods without these series are left out (all of them: MissingData)."""
    names = [rod_name] if rod_name is not None else res.rods()
    rods = [res.rod(name) for name in names]
    rods = [rod for rod in rods
            if any(name in rod.series_names() for name in CONTACT_SERIES + (TIE_SERIES,))]
    if not rods:
        raise MissingData("%s: %s no contact or tie series (series/contact/..., "
                          "series/ties/force: rods of a bundle, &output fields 'contact' and "
                          "'ties')" % (res.path, "rod '%s' has" % rod_name if rod_name
                                       else "no rod has"))
    def drawn(name):
        present = [rod for rod in rods if name in rod.series_names()]
        if name in FRICTION_SERIES:
            return any(np.any(np.asarray(rod.series(name)) != 0.0) for rod in present)
        return bool(present)
    panels = [(name, title) for name, title in (
        ("contact/force", "|contact force| on the rod"),
        ("contact/penetration", "deepest penetration r$_c$ - d (0: no contact)"),
        ("contact/energy", "contact energy share (half of each contact pair)"),
        ("contact/friction", "|friction force| on the rod in the step"),
        ("contact/slip_speed", "largest slip speed of its contact points in the step"),
        (TIE_SERIES, "|force of joints and plates| on the start (solid) and end (dashed)"))
        if drawn(name)]
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.6 * len(panels) + 0.8), sharex=True,
                             squeeze=False)
    axes = axes[:, 0]
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, (name, title) in zip(axes, panels):
        unit = ""
        for number, rod in enumerate(rods):
            if name not in rod.series_names():
                continue
            time = rod.field("time")
            values = np.asarray(rod.series(name), dtype=float)
            unit = rod.unit("series/" + name)
            color = colors[number % len(colors)]
            if name == TIE_SERIES:
                ax.plot(time, np.linalg.norm(values[:, 0, :], axis=1), "-", color=color,
                        label="%s start" % rod.name)
                ax.plot(time, np.linalg.norm(values[:, 1, :], axis=1), "--", color=color,
                        label="%s end" % rod.name)
            elif values.ndim == 2:
                ax.plot(time, np.linalg.norm(values, axis=1), ".-", color=color, label=rod.name)
            else:
                ax.plot(time, values, ".-", color=color, label=rod.name)
        ax.set_ylabel("%s [%s]" % (name.split("/")[-1], unit))
        ax.set_title(title, fontsize="medium")
        ax.legend(loc="best", fontsize="small", ncol=2)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle("%s: contact and ties" % (res.title or os.path.basename(res.path)))
    fig.tight_layout()
    return fig, axes


class PillowMissing(Exception):
    """GIFs need Pillow."""


#: Most frames of an animation (evenly spaced records, first and last included).
N_FRAMES = 100


def animate_plot(res, rod_name, out, dpi, frames=N_FRAMES, fps=10):
    """3D centrelines of the rods over time, one frame per record (at most `frames`, evenly
    spaced), fixed axes with equal scaling over the whole motion, written as a GIF with
    matplotlib's PillowWriter."""
    try:
        import PIL  # noqa: F401 - PillowWriter needs it
        from matplotlib.animation import PillowWriter
    except ImportError:
        raise PillowMissing("animate writes GIFs with Pillow, which is not installed "
                            "(Debian: apt-get install python3-pil)") from None
    names = [rod_name] if rod_name is not None else res.rods()
    if not names:
        raise MissingData("%s: the file holds no rods" % res.path)
    rods = [res.rod(name) for name in names]
    time = rods[0].field("time")
    if time.size == 0:
        raise MissingData("%s: no stored records" % res.path)
    positions = [rod.field("position") for rod in rods]
    index = snapshot_indices(time.size, frames)
    points = np.concatenate([p[index].reshape(-1, 3) for p in positions])
    fig = plt.figure(figsize=(6, 5.5))
    ax = fig.add_subplot(projection="3d")
    equal_3d_axes(ax, points)
    colors = matplotlib.colormaps["tab10"]
    lines = []
    for number, (rod, position) in enumerate(zip(rods, positions)):
        x = position[index[0]]
        ax.plot(x[:, 0], x[:, 1], x[:, 2], color="0.8", lw=1.0)
        lines.append(ax.plot(x[:, 0], x[:, 1], x[:, 2], "-", color=colors(number % 10), lw=2.0,
                             label=rod.name)[0])
    if len(rods) > 1:
        ax.legend(loc="upper left", title="rod")
    title = ax.set_title("")
    heading = res.title or os.path.basename(res.path)
    writer = PillowWriter(fps=fps)
    with writer.saving(fig, out, dpi):
        for k in index:
            for line, position in zip(lines, positions):
                x = position[k]
                line.set_data_3d(x[:, 0], x[:, 1], x[:, 2])
            title.set_text("%s\nt = %.6g s (record %d of %d)" % (heading, time[k], k + 1,
                                                                  time.size))
            writer.grab_frame()
    plt.close(fig)
    return index.size


def number(value):
    """A number as the summary prints it: 6 significant digits."""
    return "%.6g" % value


def rod_summary(rod):
    """Lines describing one rod of a result file."""
    lines = ["rod '%s' (%s)" % (rod.name, rod.formulation or "formulation not recorded")]
    table = []
    time = rod.field("time")
    if rod.has("position"):
        table.append(("nodes", str(rod.field("position").shape[1])))
    if time.size:
        table.append(("records", "%d, t = %s .. %s s"
                      % (time.size, number(time[0]), number(time[-1]))))
    else:
        table.append(("records", "0"))
    series = rod.series_names()
    # Record 0 is the initial state: no step ended there.
    steps = slice(1, None) if time.size > 1 else slice(None)
    if "dt" in series and time.size:
        dt = rod.series("dt")[steps]
        table.append(("dt", "%s .. %s s" % (number(dt.min()), number(dt.max()))))
    if "newton/iterations" in series and time.size:
        iterations = rod.series("newton/iterations")
        table.append(("Newton iterations", "%d total, %d max per step (stored records)"
                      % (int(iterations.sum()), int(iterations.max()))))
    if "energy/balance_error" in series and time.size:
        error = float(np.abs(rod.series("energy/balance_error")).max())
        text = "%s J" % number(error)
        if "energy/total" in series:
            scale = float(np.abs(rod.series("energy/total")).max())
            text += (" = %s max |H|" % number(error / scale)) if scale > 0 else " (H = 0)"
        table.append(("max |balance error|", text))
    if "constraint_residual" in series and rod.series("constraint_residual").size:
        table.append(("constraint residual",
                      "max %s" % number(float(np.max(rod.series("constraint_residual"))))))
    else:
        table.append(("constraint residual", "not stored"))
    table.append(("fields", ", ".join(rod.fields()) or "none"))
    table.append(("series", ", ".join(series) or "none"))
    width = max(len(key) for key, _ in table)
    for key, value in table:
        lines += textwrap.wrap(value, 96, initial_indent="  %-*s  " % (width, key),
                               subsequent_indent=" " * (width + 4), break_on_hyphens=False)
    return lines


def summary_text(res, rod_name=None):
    """What a result file holds: its origin, then per rod the formulation, records, time
    span, dt range, Newton iterations, energy balance, constraint residual and fields."""
    attrs = res.attrs
    names = [rod_name] if rod_name is not None else res.rods()
    rods = [res.rod(name) for name in names]
    table = [("file", res.path), ("title", res.title or "(none)"),
             ("creator", attrs.get("creator", "(not recorded)")),
             ("schema version", str(res.schema_version)),
             ("created", attrs.get("created", "(not recorded)")),
             ("ranks", str(attrs.get("n_ranks", "(not recorded)"))),
             ("rods", ", ".join(res.rods()) or "none")]
    if "time" in res.series_names():
        time = res.time()
        if time.size:
            table.append(("records", "%d, t = %s .. %s s"
                          % (time.size, number(time[0]), number(time[-1]))))
    width = max(len(key) for key, _ in table)
    lines = ["%-*s  %s" % (width, key, value) for key, value in table]
    for rod in rods:
        lines.append("")
        lines += rod_summary(rod)
    return "\n".join(lines) + "\n"


def summary_command(res, rod_name, out, dpi, members=False):
    """Print the summary (of a sweep: sweep_summary_text); also write it to `out` when
    given."""
    if is_sweep(res):
        if rod_name is not None:
            raise MissingData("%s: a sweep's result file: --rod does not apply (each member's "
                              "rods are under /members/<id>/rods)" % res.path)
        text = sweep_summary_text(res, members)
    else:
        text = summary_text(res, rod_name)
    if out is not None:
        with open(out, "w", encoding="utf-8") as f:
            f.write(text)
    sys.stdout.write(text)


# ---- Sweeps: a result file with /members/<id>/ and /summary (docs/user/output.md) ----------

#: /summary/status codes.
SWEEP_STATUS = {0: "completed", 1: "failed", 2: "not run"}
#: Components of an [members x 3] summary column: suffix -> column.
COMPONENTS = {"x": 0, "y": 1, "z": 2, "1": 0, "2": 1, "3": 2}
#: Short names of the tip components (the names the usage and the errors list).
TIP_NAMES = {"tip_x": ("tip_position", 0), "tip_y": ("tip_position", 1),
             "tip_z": ("tip_position", 2)}
#: Curves drawn with their own legend entry; more share one colour map and no legend.
MAX_LEGEND_CURVES = 10


class NotASweep(MissingData):
    """A sweep command on a file without /summary."""


def is_sweep(res):
    """Whether `res` is a sweep's result file (it has /members and /summary)."""
    return isinstance(res.file.get("summary"), h5py.Group) and "members" in res.file


def spacing_of(values):
    """'even', 'log' (evenly spaced in log) or '' for the distinct values of a parameter."""
    u = np.unique(values[np.isfinite(values)])
    if u.size < 3:
        return ""
    step = np.diff(u)
    if np.ptp(step) <= 1e-6 * np.abs(step).max():
        return "even"
    if u[0] > 0:
        ratio = np.diff(np.log(u))
        if np.ptp(ratio) <= 1e-6 * ratio.max():
            return "log"
    return ""


def auto_log(values, min_ratio, by_spacing):
    """Whether a log axis suits `values`: all positive, spanning at least `min_ratio`, and
    (`by_spacing`) at least as evenly spaced in log as in linear scale."""
    v = np.unique(values[np.isfinite(values)])
    if v.size < 2 or v[0] <= 0 or v[-1] / v[0] < min_ratio:
        return False
    if not by_spacing or v.size < 3:
        return True

    def spread(steps):
        return np.std(steps) / np.mean(steps)
    return spread(np.diff(np.log(v))) <= spread(np.diff(v))


class SweepTable:
    """The /summary table of a sweep's result file: one row per member, in id order."""

    def __init__(self, res):
        if not is_sweep(res):
            raise NotASweep("%s: not a sweep's result file (no /summary and /members; it holds: "
                            "%s)" % (res.path, ", ".join(res.file.keys()) or "nothing"))
        self.res = res
        self.group = res.file["summary"]
        if "id" not in self.group or "status" not in self.group:
            raise MissingData("%s: /summary has no id or status column (it has: %s)"
                              % (res.path, ", ".join(self.group.keys())))
        self.ids = self.group["id"][()].astype(int)
        self.status = self.group["status"][()].astype(int)
        parameters = self.group.get("parameters")
        self.parameters = list(parameters.keys()) if isinstance(parameters, h5py.Group) else []

    @property
    def size(self):
        return self.ids.size

    def parameter(self, name):
        """The full name of parameter `name`: exact, else case-insensitive, else the unique
        parameter whose variable (after the last '%') is `name`; None for the only one."""
        if name is None:
            if len(self.parameters) == 1:
                return self.parameters[0]
            raise MissingData("%s: the sweep has %d parameters: give one with --x (%s)"
                              % (self.res.path, len(self.parameters), self._listed()))
        for match in ([p for p in self.parameters if p == name],
                      [p for p in self.parameters if p.lower() == name.lower()],
                      [p for p in self.parameters
                       if p.rsplit("%", 1)[-1].lower() == name.lower()]):
            if len(match) == 1:
                return match[0]
        raise MissingData("%s: no swept parameter '%s'; the parameters are: %s"
                          % (self.res.path, name, self._listed()))

    def _listed(self):
        return ", ".join(self.parameters) or "(none)"

    def parameter_values(self, name):
        return np.asarray(self.group["parameters"][name][()], dtype=float)

    def parameter_unit(self, name):
        unit = _attr_text(self.group["parameters"][name], "unit")
        return "" if unit in ("", "-") else unit

    def quantities(self):
        """Names `quantity` accepts: the per-member columns of /summary (tip_x, tip_y, tip_z
        for the [members x 3] tip position)."""
        names = []
        for key, item in self.group.items():
            if not isinstance(item, h5py.Dataset) or key in ("id", "status"):
                continue
            if item.ndim == 1:
                names.append(key)
            elif key == "tip_position":
                names += list(TIP_NAMES)
            elif item.ndim == 2 and item.shape[1] == 3:
                names += ["%s:%s" % (key, c) for c in "xyz"]
        return names

    def quantity(self, name):
        """(label, values [members], unit, description) of a /summary column: a 1-D column by
        name, tip_x / tip_y / tip_z or NAME:x|y|z|1|2|3 for a [members x 3] column."""
        column, component = name, None
        if name in TIP_NAMES:
            column, component = TIP_NAMES[name]
        elif ":" in name:
            column, suffix = name.split(":", 1)
            component = COMPONENTS.get(suffix.lower())
            if component is None:
                raise MissingData("%s: '%s': the component after ':' is x, y, z or 1, 2, 3"
                                  % (self.res.path, name))
        item = self.group.get(column)
        if (not isinstance(item, h5py.Dataset) or column in ("id", "status")
                or item.ndim != (1 if component is None else 2)):
            raise MissingData("%s: no summary quantity '%s'; the quantities are: %s"
                              % (self.res.path, name, ", ".join(self.quantities())))
        values = np.asarray(item[()], dtype=float)
        if component is not None:
            values = values[:, component]
        label = name if component is None else "%s (%s)" % (column, "xyz"[component])
        return (label, values, _attr_text(item, "unit"), _attr_text(item, "description"))

    def column(self, name):
        """A /summary column as float numbers, or None."""
        item = self.group.get(name)
        return np.asarray(item[()], dtype=float) if isinstance(item, h5py.Dataset) else None

    def message(self, member_id):
        group = self.res.file.get("members/%d" % member_id)
        return _attr_text(group, "message") if group is not None else ""


def _attr_text(item, name):
    """Attribute `name` of an HDF5 object as str ('' when absent)."""
    value = item.attrs.get(name, "")
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    return value.decode("utf-8", "replace") if isinstance(value, bytes) else str(value)


def axis_label(name, unit):
    return "%s [%s]" % (name, unit) if unit and unit != "-" else name


def sweep_plot(res, rod_name, out, dpi, x=None, y=None, xscale="auto", yscale="auto"):
    """Write the figure of `sweep_figure` to `out`."""
    if rod_name is not None:
        raise MissingData("%s: --rod does not apply to `sweep` (it plots /summary, which holds "
                          "each member's first rod)" % res.path)
    fig, _ = sweep_figure(res, x, y, xscale, yscale)
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def sweep_figure(res, x=None, y=None, xscale="auto", yscale="auto"):
    """(figure, axes): a /summary quantity (`y`) against a swept parameter (`x`), one point
    per completed member; with more parameters one curve per combination of the others. Failed
    members are red crosses and members that did not run grey squares, both on the x axis at
    their parameter value; completed members without the quantity (NaN) are counted in a note.
    Scales: 'log', 'linear' or 'auto' (x: log for positive values spanning a factor of 10 or
    more that are at least as evenly spaced in log as in linear scale, e.g. a logspace sweep;
    y: log for positive values spanning a factor of 1000 or more)."""
    table = SweepTable(res)
    if y is None:
        raise MissingData("%s: give the quantity with --y; the quantities are: %s"
                          % (res.path, ", ".join(table.quantities())))
    xname = table.parameter(x)
    xv = table.parameter_values(xname)
    ylabel, yv, yunit, ydescription = table.quantity(y)
    status = table.status
    plotted = (status == 0) & np.isfinite(yv) & np.isfinite(xv)
    no_value = (status == 0) & ~plotted
    others = [p for p in table.parameters if p != xname]

    logx = xscale == "log" or (xscale == "auto" and auto_log(xv, 10.0, True))
    logy = yscale == "log" or (yscale == "auto" and auto_log(yv[plotted], 1e3, False))
    hidden = 0
    if logx:
        hidden += int(np.count_nonzero(plotted & ~(xv > 0)))
        plotted &= xv > 0
    if logy:
        hidden += int(np.count_nonzero(plotted & ~(yv > 0)))
        plotted &= yv > 0

    fig, ax = plt.subplots(figsize=(8, 5.5))
    if others:
        keys = np.stack([table.parameter_values(p) for p in others], axis=1)
        combos, group_of = np.unique(keys, axis=0, return_inverse=True)
        group_of = np.asarray(group_of).reshape(-1)
    else:
        combos, group_of = np.zeros((1, 0)), np.zeros(table.size, dtype=int)
    many = len(combos) > MAX_LEGEND_CURVES
    cmap = matplotlib.colormaps["viridis"]
    for g, combo in enumerate(combos):
        index = np.flatnonzero(plotted & (group_of == g))
        index = index[np.argsort(xv[index], kind="stable")]
        if many:
            style = {"color": cmap(g / max(len(combos) - 1, 1)), "lw": 1.0, "ms": 3}
        else:
            style = {"ms": 5}
            if others:
                style["label"] = ", ".join("%s = %s" % (p, number(v))
                                           for p, v in zip(others, combo))
        ax.plot(xv[index], yv[index], "o-", **style)
    at_axis = matplotlib.transforms.blended_transform_factory(ax.transData, ax.transAxes)
    failed, not_run = status == 1, status == 2
    for mask, marker, style, name in ((failed, "x", {"color": "tab:red", "mew": 2.0, "ms": 9},
                                       "failed"),
                                      (not_run, "s", {"color": "0.5", "mfc": "none", "ms": 7},
                                       "not run")):
        shown = mask & np.isfinite(xv) & ((xv > 0) if logx else True)
        if mask.any():
            # On the x axis itself (axes y = 0): below every data point (5 % margin).
            ax.plot(xv[shown], np.zeros(int(shown.sum())), marker, transform=at_axis,
                    clip_on=False, linestyle="none", zorder=5,
                    label="%s (%d member%s, on the x axis)" % (name, mask.sum(),
                                                             "" if mask.sum() == 1 else "s"),
                    **style)
    if logx:
        ax.set_xscale("log")
    if logy and plotted.any():
        ax.set_yscale("log")
    notes = []
    if no_value.any():
        notes.append("%d completed member(s) have no %s (NaN), not shown"
                     % (no_value.sum(), ylabel))
    if hidden:
        notes.append("%d non-positive value(s) not shown on the log axis" % hidden)
    if many:
        notes.append("%d curves, one per value of %s (colour: viridis, in increasing order)"
                     % (len(combos), ", ".join(others)))
    if not plotted.any():
        notes.append("no completed member has a value to draw")
    if notes:
        ax.text(0.01, 0.99, "\n".join(notes), transform=ax.transAxes, ha="left", va="top",
                fontsize="small", color="0.3")
    ax.set_xlabel(axis_label(xname, table.parameter_unit(xname)))
    ax.set_ylabel(axis_label(ylabel, yunit))
    ax.grid(True, which="both", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize="small")
    counts = ", ".join("%d %s" % (np.count_nonzero(status == code), name)
                       for code, name in SWEEP_STATUS.items())
    heading = textwrap.shorten(res.title or os.path.basename(res.path), 90, placeholder=" ...")
    ax.set_title("%s\nsweep of %d members: %s" % (heading, table.size, counts),
                 fontsize="medium")
    # The description without its shape note (", [member x 3]").
    ydescription = re.sub(r",?\s*\[[^\]]*\]\s*$", "", ydescription)
    if ydescription:
        fig.text(0.5, 0.005, "\n".join(textwrap.wrap("%s: %s" % (ylabel, ydescription), 110)),
                 ha="center", va="bottom", fontsize="x-small", color="0.3")
    fig.tight_layout(rect=(0, 0.04 if ydescription else 0, 1, 1))
    return fig, ax


def value_range(values, unit=""):
    """'low .. high unit' of the finite values, or 'none'."""
    v = values[np.isfinite(values)]
    if v.size == 0:
        return "none"
    text = "%s .. %s" % (number(v.min()), number(v.max())) if v.min() != v.max() \
        else number(v.min())
    return text + (" " + unit if unit and unit != "-" else "")


def sweep_summary_text(res, show_members=False):
    """What a sweep's result file holds: its origin, the members' status, the parameters'
    ranges, wall times (per member, per rank when /summary/rank says who ran what) and the
    ranges of the summary quantities; the failed members with their messages; with
    `show_members` one row per member."""
    attrs = res.attrs
    table = SweepTable(res)
    status = table.status
    counts = {name: int(np.count_nonzero(status == code)) for code, name in SWEEP_STATUS.items()}
    head = [("file", res.path), ("title", res.title or "(none)"),
            ("creator", attrs.get("creator", "(not recorded)")),
            ("schema version", str(res.schema_version)),
            ("created", attrs.get("created", "(not recorded)")),
            ("ranks", str(attrs.get("n_ranks", "(not recorded)"))),
            ("status", str(attrs.get("status", "(not recorded)"))),
            ("members", "%d: %d completed, %d failed, %d not run"
             % (table.size, counts["completed"], counts["failed"], counts["not run"]))]
    if "wall_time" in attrs:
        head.append(("wall time", "%s s (root attribute wall_time)"
                     % number(float(attrs["wall_time"]))))
    width = max(len(key) for key, _ in head)
    lines = ["%-*s  %s" % (width, key, value) for key, value in head]

    lines += ["", "parameters"]
    rows = []
    for name in table.parameters:
        values = table.parameter_values(name)
        spacing = {"even": ", evenly spaced", "log": ", evenly spaced in log",
                   "": ""}[spacing_of(values)]
        rows.append((name, "%d values, %s%s" % (np.unique(values).size,
                                                  value_range(values, table.parameter_unit(name)),
                                                  spacing)))
    lines += _aligned(rows or [("(none)", "")])

    lines += ["", "results (of each member's first rod; ranges over the completed members)"]
    rows = []
    wall = table.column("wall_time")
    if wall is not None:
        ran = np.isfinite(wall) & (wall >= 0) & (status != 2)
        if ran.any():
            rows.append(("wall time per member", "%s .. %s s, median %s s, sum %s s"
                         % (number(wall[ran].min()), number(wall[ran].max()),
                            number(np.median(wall[ran])), number(wall[ran].sum()))))
        rank = table.column("rank")
        if rank is not None and ran.any():
            rows += rank_rows(wall, rank, ran, int(attrs.get("n_ranks", 0) or 0))
    done = status == 0
    for column, what in (("final_time", "final time"), ("records", "records"),
                         ("newton_iterations", "Newton iterations"),
                         ("max_balance_error", "max |balance error|")):
        values = table.column(column)
        if values is None:
            continue
        unit = _attr_text(table.group[column], "unit")
        text = value_range(values[done], unit)
        if column == "newton_iterations" and np.isfinite(values[done]).any():
            text += " per member, %d in all" % int(np.nansum(values[done]))
        rows.append((what, text))
    tip = table.group.get("tip_position")
    if isinstance(tip, h5py.Dataset) and tip.ndim == 2:
        values = np.asarray(tip[()], dtype=float)[done]
        unit = _attr_text(tip, "unit")
        rows.append(("tip position", "; ".join("%s %s" % (c, value_range(values[:, k], unit))
                                               for k, c in enumerate("xyz"))))
    lines += _aligned(rows or [("(no result columns)", "")])

    bad = np.flatnonzero(status != 0)
    if bad.size:
        lines += ["", "members that did not complete (%d)" % bad.size]
        for i in bad[:20]:
            values = ", ".join("%s = %s" % (p, number(table.parameter_values(p)[i]))
                               for p in table.parameters)
            name = SWEEP_STATUS.get(status[i], "status %d" % status[i])
            message = table.message(int(table.ids[i]))
            text = "id %d (%s), %s" % (table.ids[i], values, name)
            if message and message != name:
                text += ": " + message
            lines += textwrap.wrap(text, 96, initial_indent="  ", subsequent_indent="      ")
        if bad.size > 20:
            lines.append("  ... and %d more (/summary/status, /members/<id> message)"
                         % (bad.size - 20))
    if show_members:
        lines += ["", "members"] + member_rows(table)
    return "\n".join(lines) + "\n"


#: Most ranks listed one by one in a sweep's summary (more: the slowest and the fastest).
MAX_RANK_ROWS = 16


def rank_rows(wall, rank, ran, n_ranks):
    """Summary rows of the members' wall time summed per rank (from /summary/rank, the rank
    that ran each member) and the slowest rank over the mean: the measured load balance."""
    n_ranks = max(n_ranks, int(rank[ran].max()) + 1)
    loads = np.array([wall[ran & (rank == r)].sum() for r in range(n_ranks)])
    counts = [int(np.count_nonzero(ran & (rank == r))) for r in range(n_ranks)]
    shown = range(n_ranks) if n_ranks <= MAX_RANK_ROWS else \
        sorted({int(np.argmax(loads)), int(np.argmin(loads))})
    rows = [("rank %d" % r, "%d members, %s s" % (counts[r], number(loads[r]))) for r in shown]
    if loads.mean() > 0:
        rows.append(("slowest rank / mean", "%.3f (members' wall time summed per rank)"
                     % (loads.max() / loads.mean())))
    return rows


def _aligned(rows):
    width = max(len(key) for key, _ in rows)
    lines = []
    for key, value in rows:
        lines += textwrap.wrap(value, 96, initial_indent="  %-*s  " % (width, key),
                               subsequent_indent=" " * (width + 4),
                               break_on_hyphens=False) or ["  " + key]
    return lines


def member_rows(table):
    """One line per member: id, parameters, status, wall time and the summary quantities."""
    columns = [("id", table.ids.astype(float), "%d")]
    columns += [(p, table.parameter_values(p), None) for p in table.parameters]
    for name in ("wall_time", "final_time", "records", "newton_iterations",
                 "max_balance_error", "rank"):
        values = table.column(name)
        if values is not None:
            columns.append((name, values, "%d" if name in ("records", "rank") else None))
    tip = table.group.get("tip_position")
    if isinstance(tip, h5py.Dataset) and tip.ndim == 2:
        values = np.asarray(tip[()], dtype=float)
        columns += [(n, values[:, k], None) for k, n in enumerate(("tip_x", "tip_y", "tip_z"))]
    cells = [[name for name, _, _ in columns] + ["status"]]
    for i in range(table.size):
        row = []
        for _, values, form in columns:
            v = values[i]
            row.append("nan" if not np.isfinite(v) else (form % v if form else number(v)))
        cells.append(row + [SWEEP_STATUS.get(int(table.status[i]), "?")])
    widths = [max(len(row[k]) for row in cells) for k in range(len(cells[0]))]
    return ["  " + "  ".join(c.rjust(w) for c, w in zip(row, widths)).rstrip() for row in cells]


COMMANDS = {"energy": energy_plot, "momentum": momentum_plot, "snapshots": snapshots_plot,
            "tip": tip_plot, "animate": animate_plot, "summary": summary_command,
            "sweep": sweep_plot, "contact": contact_plot, "modes": modes_plot,
            "path": path_plot}
#: What each command writes by default, next to FILE (None: standard output only).
DEFAULT_SUFFIX = {"animate": ".gif", "summary": None}


def parser():
    p = argparse.ArgumentParser(
        prog="rodplot.py",
        description="Plots and a summary of a rodsolve result file (HDF5; see "
                    "docs/user/output.md and docs/user/postprocessing.md).",
        epilog="commands:\n"
               "  energy     total energy H, kinetic and strain energy and the accumulated\n"
               "             external work against time; below, |balance error| per record\n"
               "             on a log axis. Without --rod: the sums over all rods (/series).\n"
               "  momentum   linear and angular momentum (components and magnitude) against\n"
               "             time; below, the momentum balance series the file holds\n"
               "             (e.g. momentum/angular_balance_error) on a log axis. Without\n"
               "             --rod: the sums over all rods (/series).\n"
               "  snapshots  3D centrelines (position) at about 12 evenly spaced stored\n"
               "             times, coloured by time (viridis, with a colour bar), equal axis\n"
               "             scaling, view azimuth 55, elevation 15. Without --rod: every rod.\n"
               "  tip        path of the last node (the tip) over time: 3D (coloured by time,\n"
               "             viridis) and projected on a coordinate plane (--plane; by\n"
               "             default the one across which it moves least). Without --rod:\n"
               "             every rod.\n"
               "  contact    rods of a bundle: |contact force|, deepest penetration and\n"
               "             contact energy share against time, |friction force| and slip\n"
               "             speed (with friction), and |tie force| on each\n"
               "             rod's start (solid) and end (dashed) when the file has\n"
               "             series/ties/force. Without --rod: every rod that has them.\n"
               "  modes      the modes of a scene with &modes (/modes): per system the\n"
               "             frequencies against the mode number and the shapes of the six\n"
               "             lowest modes on the reference centreline (displacement scaled\n"
               "             to a tenth of the system's extent); the frequencies are also\n"
               "             printed. --rod: the system of that rod.\n"
               "  path       an arc-length continuation (&time continuation): the load time\n"
               "             against the displacement of the node that moves farthest, with\n"
               "             its limit points (turns of the load time) marked and printed.\n"
               "             Without --rod: every rod.\n"
               "  animate    3D centrelines over time as a GIF (needs Pillow): one frame per\n"
               "             record, at most --frames evenly spaced, --fps frames a second,\n"
               "             fixed equal axes. Without --rod: every rod.\n"
               "  summary    text: title, creator, schema version, ranks, and per rod the\n"
               "             formulation, records, time span, dt range, Newton iterations\n"
               "             (total, max), largest |energy balance error| (also relative to\n"
               "             max |H|), largest constraint residual and the fields present.\n"
               "             Printed; also written to -o when given. For a sweep's file:\n"
               "             members completed/failed/not run, parameter ranges, wall time\n"
               "             (per member and per rank), the ranges of the summary columns and\n"
               "             the members that did not complete; --members adds one row per\n"
               "             member.\n"
               "  sweep      a sweep's file: the /summary column --y against the swept\n"
               "             parameter --x, one point per completed member (with several\n"
               "             parameters, one curve per combination of the others); failed\n"
               "             members as red crosses, members not run as grey squares, on the\n"
               "             x axis. --x: a name under /summary/parameters\n"
               "             ('rod(1)%EI1', or just 'EI1' when unique; optional for one\n"
               "             parameter). --y: final_time, max_balance_error,\n"
               "             newton_iterations, records, wall_time, rank, or tip_x, tip_y,\n"
               "             tip_z (also tip_position:x|y|z|1|2|3). --xscale/--yscale\n"
               "             auto|linear|log (--logx, --logy): auto is log for x when the\n"
               "             values are positive and evenly spaced in log (logspace), for y\n"
               "             when positive and spanning a factor of 1000 or more.\n\n"
               "output: -o, or by default FILE_<command>.png (.gif for animate) next to FILE;\n"
               "summary prints to standard output.\n\n"
               "exit status: 0 on success; 1 when the output cannot be written (or Pillow is\n"
               "missing for animate); 2 for a missing file, a file that is not a rodsolve\n"
               "result (no schema_version attribute), an unknown rod (the message lists the\n"
               "rods), a missing dataset, sweep on a file that is not a sweep's or a rod\n"
               "command on one that is, an unknown parameter or quantity (the message lists\n"
               "them), or a usage error.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("command", choices=list(COMMANDS), help="what to draw or print (see below)")
    p.add_argument("file", help="result file written by rodsolve (FILE.h5)")
    p.add_argument("-o", "--output", metavar="OUT.png|OUT.gif",
                   help="file to write (default: FILE_<command>.png, .gif for animate, next "
                        "to FILE; summary: standard output only)")
    p.add_argument("--rod", metavar="NAME", help="only this rod")
    p.add_argument("--dpi", type=int, default=None,
                   help="resolution (default 150; 80 for animate)")
    p.add_argument("--plane", choices=["auto"] + sorted(PLANES), default="auto",
                   help="tip only: the coordinate plane of the projection (default auto: the "
                        "plane across which the tip moves least)")
    p.add_argument("--frames", type=int, default=N_FRAMES,
                   help="animate only: most frames (default %d)" % N_FRAMES)
    p.add_argument("--fps", type=float, default=10.0,
                   help="animate only: frames per second (default 10)")
    p.add_argument("--x", metavar="PARAM",
                   help="sweep only: the swept parameter on the x axis (a name under "
                        "/summary/parameters; optional when there is one)")
    p.add_argument("--y", metavar="QUANTITY",
                   help="sweep only: the /summary column on the y axis (tip_x, tip_y, tip_z, "
                        "final_time, max_balance_error, newton_iterations, records, wall_time)")
    for axis in ("x", "y"):
        p.add_argument("--%sscale" % axis, choices=("auto", "linear", "log"), default="auto",
                       help="sweep only: scale of the %s axis (default auto)" % axis)
        p.add_argument("--log%s" % axis, dest="%sscale" % axis, action="store_const",
                       const="log", help="sweep only: same as --%sscale log" % axis)
    p.add_argument("--members", action="store_true",
                   help="summary of a sweep only: also one row per member")
    return p


def main(argv=None):
    p = parser()
    args = p.parse_args(argv)
    out = args.output
    suffix = DEFAULT_SUFFIX.get(args.command, ".png")
    if out is None and suffix is not None:
        out = os.path.splitext(args.file)[0] + "_" + args.command + suffix
    if args.command == "animate" and not out.lower().endswith(".gif"):
        p.error("animate writes a GIF: give -o NAME.gif")
    if args.frames < 1 or args.fps <= 0:
        p.error("--frames must be at least 1 and --fps positive")
    dpi = args.dpi if args.dpi is not None else (80 if args.command == "animate" else 150)
    extra = {}
    if args.command == "tip":
        extra = {"plane": args.plane}
    elif args.command == "animate":
        extra = {"frames": args.frames, "fps": args.fps}
    elif args.command == "sweep":
        extra = {"x": args.x, "y": args.y, "xscale": args.xscale, "yscale": args.yscale}
        if args.y is None:
            p.error("sweep needs --y QUANTITY (e.g. tip_z, max_balance_error, wall_time)")
    elif args.command == "summary":
        extra = {"members": args.members}
    try:
        with open_result(args.file) as res:
            if args.command not in ("sweep", "summary") and is_sweep(res):
                raise NotASweep(
                    "%s is a sweep's result file (%s members): use `rodplot.py sweep` or "
                    "`summary`; each member's rods and series are under /members/<id>/"
                    % (args.file, res.attrs.get("members", len(res.file["members"]))))
            if out is not None and os.path.dirname(out):
                os.makedirs(os.path.dirname(out), exist_ok=True)
            COMMANDS[args.command](res, args.rod, out, dpi, **extra)
    except ResultError as exc:
        print("rodplot.py: error: %s" % exc, file=sys.stderr)
        return 2
    except PillowMissing as exc:
        print("rodplot.py: error: %s" % exc, file=sys.stderr)
        return 1
    except OSError as exc:
        print("rodplot.py: error: cannot write %s: %s" % (out, exc), file=sys.stderr)
        return 1
    if out is not None:
        print("rodplot.py: wrote %s" % out, file=sys.stderr if args.command == "summary"
              else sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
