#!/usr/bin/env python3
"""Arc-length continuation of the statics (&time continuation = 'arc_length'; issue 27 item 3,
docs/theory/continuation.md) against closed forms and against the modal analysis.

Both cases run the examples of input/ (elastica_continuation.nml, arch_snap_through.nml), the
elastica at two meshes, the arch's stability check from its scene with load steps and &modes.

Cases:
  elastica_ph_planar
      Euler's pinned column past buckling: a steel rod of L = 1 m, r = 1 mm, pinned at s = 0 and
      held laterally at s = L, under an axial end force growing linearly with the load time to
      2 P_E (P_E = pi^2 EI / L^2). The column is perfect except for a small end moment (2e-2
      P_E L, a smooth pulse over the load times 0.3 to 0.6) that leads the path onto the
      buckled branch at the bifurcation and is gone from the load time 0.6 on, where the path
      is the perfect column's. There the load against the end rotation alpha must be the
      inextensible elastica's, P / P_E = (2 K(k) / pi)^2 with k = sin(alpha / 2) (K computed
      here by the arithmetic-geometric mean): alpha runs from 68 to 124 degrees. The rod's
      extension and shear move P by about P / EA ~ 5e-6 relative. Observed order about 2
      between 160 and 640 elements (6.9e-5 and 2.2e-6); the finest within 1e-5.
  elastica_cl_em_planar
      the same pinned column with Stander and Stein's displacement scheme (its static rows).
  elastica_se3_pg, elastica_ph_director
      the same for the cantilever, half the pinned column of twice its length: clamped at s =
      0, loaded at s = L to 2 P_c (P_c = pi^2 EI / (4 L^2)), the rotation of the free end against
      P / P_c = (2 K(k) / pi)^2. se3_pg: order 2 between 160 and 320 elements (9.3e-6, 1.9e-6);
      ph_director of degree 2 with constraint = 'inextensible' (Euler's elastica exactly):
      order 4 between 16 and 32 elements (2.0e-5, 1.3e-6); the finest within 1e-5.
  branch_ph_planar, branch_cl_em_planar, branch_se3_pg, branch_ph_director
      the perfect columns (no pulse) with &time branch_switch: the path crosses the bifurcation
      at the buckling load, the run logs it and leaves the straight column along the critical
      mode, once; then the elastica as above, from the branch's first points (1.5 degrees) on,
      at the same meshes and bounds (a 3D rod of circular section: a double eigenvalue).
  bifurcation_ph_director
      the perfect inextensible ph_director cantilever without branch_switch: one bifurcation
      logged, at Euler's load (0.5 of the load time) within 1e-6, and the column stays
      straight past it.
  arch_se3_pg
      A shallow pinned circular arch (span 1 m, rise 6 mm, r = 5 mm: rise / radius of gyration
      2.4) under a uniform downward load growing linearly with the load time: the path passes
      its limit point (the load time rises, then falls while the crown snaps through, then
      rises again with the crown below the supports). The limit load against the modal
      analysis at the states before it: the lowest squared frequency of the loaded arch
      vanishes at the limit point like sqrt(lambda_lim - lambda) (the path is a parabola in
      lambda there), so omega^4 is linear in lambda and its zero, extrapolated from the
      equilibria at 0.997 and 0.999 of the path's limit load (load-stepped runs), is the limit
      load of the stability analysis; within 2e-3 of the path's maximum (a parabola through
      the three path points about it; measured 1.8e-4). `rodplot.py path` prints the same
      limit point.
  path_end_modes_se3_pg
      &modes about = 'equilibrium' after a continuation that ends below t_end: a se3_pg
      cantilever bent by a follower tip force normal to its end (whose load stiffness enters
      the modes), 12 path steps ending at the load time 0.397 of t_end = 1. The modes must be
      those of the path's last point under the loads of its own load time (attribute
      load_time of /modes/column): against the modes of a load-stepped run to that load time
      (its endpoint equilibrium, the same state) within 1e-6 (measured 3.1e-8; with the loads
      of t_end they were up to 0.357 off). The checkpoint's time is that load time too, and
      the state's unbalance under the loads is at round-off.
"""
import math
import os
import re
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from run_scene import number, numbers, read_example, run, run_cases, set_variable  # noqa: E402

COLUMN = "elastica_continuation.nml"
ARCH = "arch_snap_through.nml"
E, G, RHO = 2e11, 8e10, 7800.0
# A load proportional to the load time on both sides of 0 (a ramp is clamped at 0 and 1).
LINEAR = "time_function = 'table', table_times = -100.0, 100.0, table_values = -100.0, 100.0"


def elliptic_k(m):
    """The complete elliptic integral of the first kind K(m), m = k^2, by the AGM."""
    a, b = 1.0, math.sqrt(1.0 - m)
    for _ in range(60):
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return math.pi / (2.0 * a)


def column(formulation, n_elements, pinned, atol=1e-9, extra="", radius=1e-3, perfect=False):
    """The column of the elastica cases: pinned (s = 0 pinned, s = L held laterally; its load
    P_E = pi^2 EI / L^2, end rotation at s = 0) or a cantilever (clamped at s = 0; P_c = pi^2 EI
    / (4 L^2), rotation at the free end), loaded along its axis at s = L by a force growing
    linearly with the load time to twice that load, with the vanishing end-moment pulse.
    `perfect`: without the pulse, the path switched to the buckled branch at the bifurcation
    (&time branch_switch). Returns the critical load, the scene and the node whose rotation is
    the elastica's."""
    inertia = math.pi * radius**4 / 4
    critical = math.pi**2 * E * inertia / (1.0 if pinned else 4.0)
    if pinned:
        hold = "'y'" if formulation in ("ph_planar", "cl_em_planar") else "'y', 'z'"
        supports = f"""&bc
    rod = 'column', end = 'start', kind = 'pinned'
/
&bc
    rod = 'column', end = 'end', kind = 'held', hold = {hold}
/"""
    else:
        supports = """&bc
    rod = 'column', end = 'start', kind = 'clamped'
/"""
    pulse = "" if perfect else f"""&load
    rod = 'column', where = '{"start" if pinned else "end"}', moment = 0.0, 0.0, {2e-2 * critical!r}
    time_function = 'pulse', t_on = 0.3, t_off = 0.6
/"""
    return critical, f"""&time
    branch_switch = {".true." if perfect else ".false."}
    t_end = 1.0
    dt = 1.0
    quasistatic = .true.
    continuation = 'arc_length'
    arc_length = 0.01
    arc_length_max = 0.02
    path_steps = 400
/
&solver
    newton_atol = {atol}
/
&rod
    name = 'column', formulation = '{formulation}', n_elements = {n_elements}, length = 1.0
    start = 0.0, 0.0, 0.0, direction = 1.0, 0.0, 0.0
    section = 'circle', radius = {radius}, E = {E}, G = {G}, density = {RHO}
    {extra}
/
{supports}
&load
    rod = 'column', where = 'end', force = {-2 * critical!r}, 0.0, 0.0
    {LINEAR}
/
{pulse}
&output
    path = 'x.h5'
/
""", 0 if pinned else -1


def elastica_errors(args, formulation, n_elements, pinned, perfect=False, **options):
    """End rotations (degrees) of the path's points past the pulse (`perfect`: on the branch
    the path switched to) and P / P_elastica - 1 there: P / P_cr = (2 K(k) / pi)^2, k = sin(alpha
    / 2), for both columns (the cantilever is half the pinned column of twice its length). The
    pinned ph_planar column is the example input/elastica_continuation.nml at n_elements (its
    pulse removed when `perfect`), its critical load from its own section."""
    critical, text, node = column(formulation, n_elements, pinned, perfect=perfect, **options)
    if pinned and formulation == "ph_planar":
        text = set_variable(read_example(args.source, COLUMN), "rod", "n_elements", n_elements)
        radius, modulus = number(text, "rod", "radius"), number(text, "rod", "E")
        critical = math.pi**3 * modulus * radius**4 / 4 / number(text, "rod", "length")**2
        if perfect:
            text = text[:text.rindex("\n&load")] + "\n"
            text = set_variable(text, "time", "branch_switch", ".true.")
    force = -number(text, "load", "force")
    name = f"{'branch' if perfect else 'elastica'}_{formulation}_{n_elements}"
    path, log = run(args, text, name, want_log=True)
    with h5py.File(path, "r") as f:
        rod = f["rods"]["column"]
        load_time = rod["series"]["load_time"][()]
        tangent = rod["directors"][()][:, node, 2, :]
    alpha = np.arccos(np.clip(tangent[:, 0], -1.0, 1.0))
    if perfect:
        # The straight column's points have no rotation; the branch's start at a few degrees.
        switched = [line for line in log.splitlines() if "left the path for the branch" in line]
        print("\n".join(switched))
        if len(switched) != 1:
            raise SystemExit(f"{name}: the path switched branches {len(switched)} times, not once")
        keep = (alpha > 1e-2) & (load_time <= 1.0)
    else:
        keep = (load_time >= 0.6) & (load_time <= 1.0)
    ratio = force * load_time[keep] / critical
    exact = np.array([(2 * elliptic_k(math.sin(a / 2) ** 2) / math.pi) ** 2 for a in alpha[keep]])
    return np.degrees(alpha[keep]), ratio / exact - 1


def elastica(formulation, meshes, order, pinned=True, perfect=False, **options):
    def case(args, checks):
        worst = []
        start = 10.0 if perfect else 70.0
        for n in meshes:
            degrees, errors = elastica_errors(args, formulation, n, pinned, perfect=perfect,
                                              **options)
            worst.append(np.abs(errors).max())
            print(f"{n} elements: {len(errors)} path points, end rotation {degrees.min():.1f} "
                  f"to {degrees.max():.1f} degrees, largest |P / P_elastica - 1| {worst[-1]:.3e}")
            if n == meshes[-1]:
                checks.check("path past 90 degrees: 95 - largest end rotation (degrees)",
                             95.0 - degrees.max(), 0.0)
                checks.check(f"path from below {start:g} degrees: smallest end rotation - "
                             f"{start:g} (degrees)", degrees.min() - start, 0.0)
        observed = math.log(worst[0] / worst[1]) / math.log(meshes[1] / meshes[0])
        print(f"observed order {observed:.2f}")
        checks.check(f"elastica: observed order at least {order} - 0.2 ({order} - order)",
                     order - observed, 0.2)
        checks.check(f"elastica, {meshes[-1]} elements: largest |P / P_elastica - 1|", worst[-1],
                     1e-5)
    return case


def bifurcation(args, checks):
    """The perfect inextensible cantilever (ph_director, degree 2, 16 elements) without
    branch_switch: the path stays on the straight column, and the bifurcation it crosses is
    logged at Euler's load, P_c / (2 P_c) = 0.5 of the load time."""
    critical, text, node = column("ph_director", 16, False, perfect=True,
                                  extra="constraint = 'inextensible'")
    text = set_variable(text, "time", "branch_switch", ".false.")
    text = set_variable(text, "time", "path_steps", "60")
    path, log = run(args, text, "bifurcation_ph_director", want_log=True)
    found = [float(re.search(r"load time ([-+0-9.E]+)", line).group(1))
             for line in log.splitlines() if "crossed a bifurcation" in line]
    print("bifurcations logged at the load times", found)
    checks.check("bifurcations logged - 1", abs(len(found) - 1), 0)
    # Euler's load of the 16 quadratic elements is 5.8e-7 off (tests/regression/modes/
    # buckling.py); the estimate, the zero of the critical eigenvalue interpolated between the
    # path's points on either side, measured 6e-8 off.
    checks.check("the bifurcation's load: |load time / 0.5 - 1|",
                 abs(found[0] / 0.5 - 1) if found else math.inf, 1e-6)
    with h5py.File(path, "r") as f:
        rod = f["rods"]["column"]
        load_time = rod["series"]["load_time"][()]
        tangent = rod["directors"][()][:, node, 2, :]
    checks.check("the path passed the bifurcation: largest load time - 0.55",
                 0.55 - load_time.max(), 0.0)
    checks.check("the column stays straight: largest end rotation (rad)",
                 float(np.arccos(np.clip(tangent[:, 0], -1.0, 1.0)).max()), 1e-6)


def load_stepped(text, load_time, n_modes=3):
    """The scene `text` with load steps to `load_time` in place of its continuation, and the
    lowest `n_modes` modes about its equilibrium."""
    start = text.index("\n&time")
    end = text.index("\n/", start + 1)
    time = f"""
&time
    t_end = {load_time!r}
    dt = {load_time / 40!r}
    quasistatic = .true."""
    return (text[:start] + time + text[end:] +
            f"&modes\n    n_modes = {n_modes}, about = 'equilibrium'\n/\n")


def snap_through(args, checks):
    text = read_example(args.source, ARCH)
    # The crown's height above the supports (at z = 0): the polyline's highest point.
    rise = max(numbers(text, "rod", "points")[2::3])
    path, log = run(args, text, "arch_path", want_log=True)
    # J is singular at the limit point as at a bifurcation, but the load turns there.
    checks.check("the limit point is not taken for a bifurcation: bifurcations logged",
                 sum("crossed a bifurcation" in line for line in log.splitlines()), 0)
    with h5py.File(path, "r") as f:
        rod = f["rods"]["arch"]
        load_time = rod["series"]["load_time"][()]
        position = rod["position"][()]
        unit = rod["time"].attrs["unit"]
        steps = rod["time"][()]
    unit = unit.decode() if isinstance(unit, bytes) else unit
    checks.check("the records' time is the path step: unit '1' (0: yes)", float(unit != "1"), 0.0)
    checks.check("the records' time is the path step: largest |time - record index|",
                 float(np.abs(steps - np.arange(steps.size)).max()), 0.0)
    crown = position[:, position.shape[1] // 2, 2]
    falls = np.nonzero(np.diff(load_time) < 0)[0]
    checks.check("the path turns back at a limit point: (no falling load time)",
                 0.0 if len(falls) else 1.0, 0.0)
    top = falls[0]
    checks.check("the crown snaps through: final crown height / rise (below -1)",
                 crown[-1] / rise + 1.0, 0.0)
    checks.check("the load rises again past the limit load: limit / final load time - 1",
                 load_time[top] / load_time[-1] - 1.0, 0.0)
    # The limit load: a parabola in the path's own parameter through the points about the top.
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(load_time), np.diff(crown) / rise))])
    c = np.polyfit(s[top - 1:top + 2], load_time[top - 1:top + 2], 2)
    limit = c[2] - c[1] ** 2 / (4 * c[0])
    print(f"path: limit load time {limit:.8f} (largest path point {load_time[top]:.8f}), "
          f"{len(load_time) - 1} steps")
    # rodplot's `path` finds the same limit point.
    plot = subprocess.run([sys.executable, os.path.join(args.source, "scripts", "rodplot.py"),
                           "path", path, "-o", os.path.join(args.workdir, "path.png")],
                          capture_output=True, text=True)
    print(plot.stdout + plot.stderr)
    checks.check("rodplot.py path: exit status", plot.returncode, 0)
    printed = [float(line.split()[-1]) for line in plot.stdout.splitlines()
               if "limit point" in line]
    checks.check("rodplot.py path: its first limit point is the path's largest load time "
                 "(difference)", abs(printed[0] - load_time[top]) if printed else math.inf, 1e-8)
    omega4 = []
    loads = (0.997 * limit, 0.999 * limit)
    for k, lam in enumerate(loads):
        result = run(args, load_stepped(text, lam), f"arch_modes_{k}")
        with h5py.File(result, "r") as f:
            omega = f["modes"]["arch"]["angular_frequency"][()]
        positive = omega[omega > 0]
        omega4.append(positive.min() ** 4)
        print(f"load time {lam:.8f}: angular frequencies {omega}")
    stability = loads[0] + (loads[1] - loads[0]) * omega4[0] / (omega4[0] - omega4[1])
    print(f"stability analysis: omega^4 vanishes at the load time {stability:.8f}")
    # Measured 1.8e-4 (the path's parabola and the omega^4 extrapolation).
    checks.check("limit load: |stability analysis / path - 1|", abs(stability / limit - 1), 2e-3)


def follower_cantilever():
    """The cantilever of the elastica cases (se3_pg, 40 elements) under a tip force normal to
    the rod's end (a follower force along d1, its frame turning with the end), growing linearly
    with the load time to 0.9 N (5.7 EI / L^2) at t_end = 1; a continuation of 12 path steps,
    which end near the load time 0.4, well below t_end. No &modes (the callers add them)."""
    return f"""&run
    title = 'Cantilever under a follower tip force, modes at the end of its path'
/
&time
    t_end = 1.0
    dt = 1.0
    quasistatic = .true.
    continuation = 'arc_length'
    arc_length = 0.05
    arc_length_max = 0.1
    path_steps = 12
/
&solver
    newton_atol = 1e-7
/
&rod
    name = 'column', formulation = 'se3_pg', n_elements = 40, length = 1.0
    start = 0.0, 0.0, 0.0, direction = 1.0, 0.0, 0.0
    section = 'circle', radius = 1e-3, E = {E}, G = {G}, density = {RHO}
/
&bc
    rod = 'column', end = 'start', kind = 'clamped'
/
&load
    rod = 'column', where = 'end', force = 0.9, 0.0, 0.0, frame = 'follower'
    {LINEAR}
/
&output
    path = 'x.h5'
/
"""


def path_end_modes(args, checks):
    text = follower_cantilever()
    path = run(args, text + "&modes\n    n_modes = 4, about = 'equilibrium'\n/\n", "path_end")
    with h5py.File(path, "r") as f:
        load_time = f["rods"]["column"]["series"]["load_time"][()]
        tip = f["rods"]["column"]["position"][-1, -1]
        modes = f["modes"]["column"]
        frequency = modes["frequency"][()]
        about_load_time = modes.attrs["load_time"]
        unbalance = modes.attrs["unbalance"]
        checkpoint_time = f["checkpoint"]["column"]["time"][()][0]
    end = load_time[-1]
    print(f"path: {len(load_time) - 1} steps to the load time {end:.8f}, tip at {tip}; "
          f"frequencies (Hz) {frequency}, unbalance {unbalance:.3e}")
    checks.check("the path ends well below t_end = 1: its last load time - 0.5", end - 0.5, 0.0)
    checks.check("the path bends the rod: tip x / L - 0.9 (below 0)", tip[0] - 0.9, 0.0)
    checks.check("/modes load_time is the path's last load time (difference)",
                 abs(about_load_time - end), 0.0)
    checks.check("/checkpoint time is the path's last load time (difference)",
                 abs(checkpoint_time - end), 0.0)
    # Measured 2.2e-17; with the loads of t_end 1.9e-9, below the run's warning at 1e-8.
    checks.check("the modes' state is in equilibrium under their loads: unbalance", unbalance,
                 1e-15)
    reference = run(args, load_stepped(text, end, n_modes=4), "path_end_load_stepped")
    with h5py.File(reference, "r") as f:
        expected = f["modes"]["column"]["frequency"][()]
    print(f"load steps to {end:.8f}: frequencies (Hz) {expected}")
    # Measured 3.1e-8 (both states converged to newton_atol = 1e-7). With the loads of t_end,
    # which the modes took before the end state carried its load time (the follower force
    # 1 / 0.397 = 2.5 times its value at the state, and so its stiffness), the same state gave
    # 1.7686, 2.0938, 7.4051, 8.5056 Hz: up to 0.357 off, 3.6e5 times the bound.
    checks.check("modes about the path's end against the load-stepped equilibrium at its load "
                 "time: largest |f / f_reference - 1|", np.abs(frequency / expected - 1).max(),
                 1e-6)


if __name__ == "__main__":
    run_cases(__doc__, {
        # Measured 6.9e-5 and 2.2e-6.
        "elastica_ph_planar": elastica("ph_planar", (160, 640), 2),
        # Measured 9.3e-6 and 1.9e-6 (se3_pg's Newton residual has a rounding floor near 1e-7
        # N at 320 elements: newton_atol 1e-6 N, 3e-7 of the load).
        "elastica_se3_pg": elastica("se3_pg", (160, 320), 2, pinned=False, atol=1e-6),
        # Degree 2, inextensible and shear-rigid (Euler's elastica exactly): 2.0e-5, 1.3e-6.
        "elastica_ph_director": elastica("ph_director", (16, 32), 4, pinned=False,
                                         extra="constraint = 'inextensible'"),
        # Stander and Stein's displacement scheme: its Newton residual has a rounding floor
        # (EA eps |r| / l: 1.1e-8 N at 160 elements, 2e-7 N at 640), so newton_atol 1e-6 N,
        # 3e-7 of the load.
        "elastica_cl_em_planar": elastica("cl_em_planar", (160, 640), 2, atol=1e-6),
        # The perfect columns, switched onto the buckled branch at the bifurcation.
        "branch_ph_planar": elastica("ph_planar", (160, 640), 2, perfect=True),
        "branch_se3_pg": elastica("se3_pg", (160, 320), 2, pinned=False, atol=1e-6,
                                  perfect=True),
        "branch_cl_em_planar": elastica("cl_em_planar", (160, 640), 2, atol=1e-6, perfect=True),
        "branch_ph_director": elastica("ph_director", (16, 32), 4, pinned=False,
                                       extra="constraint = 'inextensible'", perfect=True),
        "bifurcation_ph_director": bifurcation,
        "arch_se3_pg": snap_through,
        "path_end_modes_se3_pg": path_end_modes,
    })
