#!/usr/bin/env python3
"""Plots of rodsolve result files (docs/user/output.md).

    python3 scripts/rodplot.py energy out/flying_spaghetti.h5
    python3 scripts/rodplot.py snapshots out/flying_spaghetti.h5 -o spaghetti.png --rod spaghetti
    python3 scripts/rodplot.py tip out/soft_arm_circle.h5 --plane xy

Exit status 0 on success, 1 when the image cannot be written, 2 for a missing file, a file
that is not a rodsolve result, an unknown rod or a missing dataset (the message names what is
available).
"""

import argparse
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
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


def energy_plot(res, rod_name, out, dpi):
    """H, kinetic, strain and the accumulated external work; |balance error| on a log axis."""
    if rod_name is not None:
        rod = res.rod(rod_name)
        time = rod.field("time")
        names = rod.series_names()
        get = rod.series
        what = "rod '%s' (%s)" % (rod_name, rod.formulation)
    else:
        time = res.time()
        names = res.series_names()
        get = res.series
        what = "all rods" if len(res.rods()) != 1 else "rod '%s'" % res.rods()[0]
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
    bottom.set_title("|H$_{n+1}$ - H$_n$ - W$_n$| per record", fontsize="medium")
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


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
    low, high = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (low + high)
    half = 0.5 * max(float((high - low).max()), 1e-12)
    ax3.set_xlim(centre[0] - half, centre[0] + half)
    ax3.set_ylim(centre[1] - half, centre[1] + half)
    ax3.set_zlim(centre[2] - half, centre[2] + half)
    ax3.set_box_aspect((1, 1, 1))
    ax3.view_init(elev=VIEW_ELEV, azim=VIEW_AZIM)
    ax3.set_xlabel("x [m]")
    ax3.set_ylabel("y [m]")
    ax3.set_zlabel("z [m]")
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


COMMANDS = {"energy": energy_plot, "snapshots": snapshots_plot, "tip": tip_plot}


def parser():
    p = argparse.ArgumentParser(
        prog="rodplot.py",
        description="Plots of a rodsolve result file (HDF5; see docs/user/output.md).",
        epilog="commands:\n"
               "  energy     total energy H, kinetic and strain energy and the accumulated\n"
               "             external work against time; below, |balance error| per record\n"
               "             on a log axis. Without --rod: the sums over all rods (/series).\n"
               "  snapshots  3D centrelines (position) at about 12 evenly spaced stored\n"
               "             times, coloured by time (viridis), equal axis scaling, view\n"
               "             azimuth 55, elevation 15. Without --rod: every rod.\n"
               "  tip        path of the last node (the tip) over time: 3D (coloured by time,\n"
               "             viridis) and projected on a coordinate plane (--plane; by\n"
               "             default the one across which it moves least). Without --rod:\n"
               "             every rod.\n\n"
               "exit status: 0 on success; 1 when the image cannot be written; 2 for a\n"
               "missing file, a file that is not a rodsolve result (no schema_version\n"
               "attribute), an unknown rod (the message lists the rods) or a missing\n"
               "dataset.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("command", choices=sorted(COMMANDS), help="what to plot (see below)")
    p.add_argument("file", help="result file written by rodsolve (FILE.h5)")
    p.add_argument("-o", "--output", metavar="OUT.png",
                   help="image to write (default: FILE_<command>.png next to FILE)")
    p.add_argument("--rod", metavar="NAME", help="plot only this rod")
    p.add_argument("--dpi", type=int, default=150, help="resolution of the image (default 150)")
    p.add_argument("--plane", choices=["auto"] + sorted(PLANES), default="auto",
                   help="tip only: the coordinate plane of the projection (default auto: the "
                        "plane across which the tip moves least)")
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    out = args.output
    if out is None:
        out = os.path.splitext(args.file)[0] + "_" + args.command + ".png"
    try:
        with open_result(args.file) as res:
            if os.path.dirname(out):
                os.makedirs(os.path.dirname(out), exist_ok=True)
            extra = {"plane": args.plane} if args.command == "tip" else {}
            COMMANDS[args.command](res, args.rod, out, args.dpi, **extra)
    except ResultError as exc:
        print("rodplot.py: error: %s" % exc, file=sys.stderr)
        return 2
    except OSError as exc:
        print("rodplot.py: error: cannot write %s: %s" % (out, exc), file=sys.stderr)
        return 1
    print("rodplot.py: wrote %s" % out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
