"""Benchmark: rodsolve against PyElastica on the same rods (issue 11 items 2 and 3).

Three problems, each run by both codes with the same material, geometry, load and end time:
a clamped steel cantilever and the same rubber-like, both given a smooth tip force pulse and
then left to swing, and a free-flying steel rod (no boundary condition) knocked by the same kind
of pulse at one end. The error of every run of either code is measured against one converged
rodsolve reference per problem, whose own error is estimated by successive refinement in time
and in space; an error level is only used if the reference's estimate is below a tenth of it.
Wall times are the time loops only (rodsolve's summary line; PyElastica's stepping loop, its
numba JIT warm-up excluded and reported), medians of --repeat runs. rodsolve's points are run
with each LU package of --packages (default rodchain, the structured chain LU, and mumps, the
general sparse LU it replaced), alternating between the packages in every repeat so that both
see the same load; the reference and its ladders use the first package, and the finest
reference is rerun with the others to check that they agree. From the work-precision points of
both codes the wall time at equal error 1e-2, 1e-3, 1e-4 is interpolated (log-log, on each
code's cheapest-for-its-error points). rodsolve also runs at order 4 and with adaptive steps
(issue 25; SCHEME_RUNS, the first package only), and a table sets them against its order-2
steps at equal error. PyElastica's stable step is found by bisection.

PyElastica runs in a virtual environment that this script creates in the work directory (or
--venv; an existing one with pyelastica and h5py is reused) with `pip install pyelastica h5py`
from PyPI, through peer_pyelastica.py. With --write the tables go into the GENERATED blocks of
docs/performance.md and docs/stability.md and the figures into docs/figures/peer_<case>.png.

    /usr/bin/python3 tests/bench/peer/peer_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/peer-work [--quick] [--repeat 3] \\
        [--packages rodchain,mumps] [--write]
"""
import argparse
import collections
import datetime
import glob
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import bench_common  # noqa: E402
from bench_common import SUMMARY, measured_on, write_generated  # noqa: E402

SCRIPT = "peer/peer_bench.py"
WORKER = os.path.join(HERE, "peer_pyelastica.py")
PYELASTICA = "pyelastica==1.0.0"     # the version the equivalence of README.md was worked out for
L = 1.0
RADIUS = 5e-3
SHEAR_FACTOR = 27.0 / 28.0           # PyElastica's alpha_c (rod/factory_function.py)
N_SAMPLES = 100                      # comparison times t_k = k t_end / N_SAMPLES
LEVELS = (1e-2, 1e-3, 1e-4)
MATERIALS = {
    "steel": {"E": 2e11, "nu": 0.3, "rho": 7800.0},
    "rubber": {"E": 1e7, "nu": 0.49, "rho": 1100.0},
}
# beta_1 L of the first bending mode: clamped-free and free-free
BETA1 = {"clamped": 1.8751040687, "free": 4.7300407449}
# Problems: boundary condition, peak tip force in EI/L^2, pulse length and end time in periods of
# the first bending mode (rounded to two digits), and the runs of both codes: rodsolve's
# (quadratic elements, steps) sweep and reference, PyElastica's element counts.
CASES = {
    "cantilever_steel": {"material": "steel", "bc": "clamped", "load": 0.3, "pulse": 0.5,
                         "end": 2.0},
    "cantilever_rubber": {"material": "rubber", "bc": "clamped", "load": 0.3, "pulse": 0.5,
                          "end": 2.0},
    "free_flying": {"material": "steel", "bc": "free", "load": 1.0, "pulse": 1.0, "end": 5.0},
}
RUNS = {
    "full": {
        "clamped": {"rodsolve": [(2, 100), (4, 100), (4, 200), (4, 400), (8, 400), (8, 800),
                                 (8, 1600), (12, 1600)],
                    "ref": (16, 6400), "pyelastica": [10, 20, 40, 80, 160]},
        "free": {"rodsolve": [(2, 100), (4, 100), (4, 200), (8, 200), (8, 400), (12, 400),
                              (16, 800)],
                 "ref": (24, 3200), "pyelastica": [5, 10, 20, 40, 80, 160, 320]},
        "stability": [10, 20, 40, 80, 160, 320],
        # the case of the target: one more PyElastica level (~1 min a run)
        "cantilever_steel": {"pyelastica": [10, 20, 40, 80, 160, 320]},
    },
    "quick": {
        "clamped": {"rodsolve": [(2, 100), (4, 200)], "ref": (4, 800),
                    "pyelastica": [10, 20]},
        "free": {"rodsolve": [(2, 100), (4, 200)], "ref": (4, 800), "pyelastica": [5, 10]},
        "stability": [10, 40],
    },
}
# rodsolve's time integrators besides order 2 (issue 25), with the first LU package only:
# order 4 (&time order = 4) on meshes whose spatial error is below the levels, and adaptive
# steps (&time adaptive, a ladder of rtol; records at the sample times, which are its largest
# steps) on the meshes where order 2 reaches the levels.
Scheme = collections.namedtuple("Scheme", "name order rtol")
ORDER_2 = Scheme("order 2", 2, None)
ORDER_4 = Scheme("order 4", 4, None)
ATOL_PER_RTOL = 0.01
SCHEME_RUNS = {
    "full": {"order 4": [(4, 100), (8, 100), (8, 200), (12, 100), (12, 200), (16, 200)],
             "adaptive": [(n, rtol) for n in (4, 8, 12) for rtol in (1e-3, 1e-4, 1e-5, 1e-6)]},
    "quick": {"order 4": [(4, 100)], "adaptive": [(4, 1e-4)]},
}
# the targets: PyElastica's wall time over rodsolve's at equal error (`err`)
TARGETS = [("free_flying", 1e-2, 20.0), ("free_flying", 1e-3, 20.0), ("free_flying", 1e-4, 20.0),
           ("cantilever_steel", 1e-2, 1000.0)]
# rodchain's messages: the panels at set-up (-mat_rodchain_view), proof that it factors the
# Jacobians, and its one warning when MUMPS takes over (src/solver/rodchain.c)
RODCHAIN_VIEW = re.compile(r"^rodchain \((.*?)\): (.*)$", re.M)
RODCHAIN_FALLBACK = re.compile(r"^rodchain: (.*?); MUMPS factors such Jacobians", re.M)
# the rod's line on its adaptive steps (src/solver/rod_run.F90)
ADAPTIVE_STEPS = re.compile(r"adaptive steps: (\d+) accepted")
OPENMPI_ENV = {  # scripts/mpi_env.sh
    "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1", "OPENBLAS_NUM_THREADS": "1",
    "OMP_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1",
}


LOADS = []   # 1-min load averages sampled at every rodsolve run


def log(text):
    print(f"[{datetime.datetime.now(datetime.timezone.utc):%H:%M:%S}] {text}", flush=True)


# ---------------------------------------------------------------------------- the problems

def problem(name):
    """The physical data of case `name`, as both codes get them (SI units)."""
    c = CASES[name]
    m = MATERIALS[c["material"]]
    area = math.pi * RADIUS ** 2
    inertia = math.pi * RADIUS ** 4 / 4.0
    ei = m["E"] * inertia
    omega1 = BETA1[c["bc"]] ** 2 * math.sqrt(ei / (m["rho"] * area * L ** 4))
    period = 2.0 * math.pi / omega1
    return {"name": name, "material": c["material"], "bc": c["bc"], "L": L, "radius": RADIUS,
            "E": m["E"], "nu": m["nu"], "G": m["E"] / (2.0 * (1.0 + m["nu"])), "rho": m["rho"],
            "EI": ei, "P": c["load"] * ei / L ** 2, "period": period,
            "t_pulse": float(f"{c['pulse'] * period:.2g}"),
            "t_end": float(f"{c['end'] * period:.2g}"), "n_samples": N_SAMPLES}


def pyelastica_dt_estimate(p, n):
    """Estimated stability limit 2/omega_max of PyElastica's PositionVerlet: the thickness-shear
    frequency of a section (independent of n) plus the axial and shear waves of one element
    (README.md); the bisection in docs/stability.md checks it."""
    dx = p["L"] / n
    kg_rho = SHEAR_FACTOR * p["G"] / p["rho"]
    omega2 = 4.0 * kg_rho / p["radius"] ** 2 + 4.0 * (p["E"] / p["rho"] + kg_rho) / dx ** 2
    return 2.0 / math.sqrt(omega2)


def scene_text(p, n, steps, samples=N_SAMPLES, jacobian_reuse=0.0, package=None,
               scheme=ORDER_2):
    """The rodsolve scene of problem p with n quadratic elements and `steps` steps; `package`
    is the LU package of the Newton steps (rodsolve's default if None); `scheme` the time
    integrator (an adaptive one takes `steps` as the number of records, its largest steps)."""
    bc = ("&bc\n    rod = 'beam', end = 'start', kind = 'clamped'\n/\n"
          if p["bc"] == "clamped" else "")
    solver = [f"jacobian_reuse = {jacobian_reuse!r}"] if jacobian_reuse else []
    if package:
        options = f"-pc_factor_mat_solver_type {package}"
        if package == "rodchain":
            options += " -mat_rodchain_view"
        solver.append(f"petsc_options = '{options}'")
    if solver:
        bc += "&solver\n    " + "\n    ".join(solver) + "\n/\n"
    return f"""! Peer benchmark (tests/bench/peer/peer_bench.py): {p['name']}, the same problem as
! PyElastica's (peer_pyelastica.py): tip force pulse, PyElastica's shear factor 27/28.
&run
    title = 'peer {p['name']}'
/
&time
    t_end = {p['t_end']!r}
    dt = {p['t_end'] / steps!r}{time_options(scheme, p)}
/
&output
    path = 'set by the benchmark'
    stride = {steps // samples}
    fields = 'position'
/
&rod
    name = 'beam'
    formulation = 'ph_director'
    n_elements = {n}, degree = 2, n_gauss = 2
    start = 0.0, 0.0, 0.0
    direction = 1.0, 0.0, 0.0
    d1 = 0.0, 1.0, 0.0
    length = {p['L']!r}
    section = 'circle', radius = {p['radius']!r}
    E = {p['E']!r}, nu = {p['nu']!r}, density = {p['rho']!r}
    shear_factor = {SHEAR_FACTOR!r}
/
{bc}&load
    rod = 'beam', where = 'end'
    force = 0.0, 0.0, {p['P']!r}
    frame = 'spatial'
    time_function = 'pulse', t_on = 0.0, t_off = {p['t_pulse']!r}
/
"""


def time_options(scheme, p):
    """The &time lines of a scheme beyond t_end and dt: its order, and for adaptive steps
    rtol with atol = rtol times ATOL_PER_RTOL L (docs/user/input.md: about rtol times the
    rod's size)."""
    lines = [f"order = {scheme.order}"] if scheme.order != 2 else []
    if scheme.rtol is not None:
        lines += ["adaptive = .true.", f"rtol = {scheme.rtol!r}",
                  f"atol = {ATOL_PER_RTOL * scheme.rtol * p['L']!r}"]
    return "".join(f"\n    {line}" for line in lines)


# ---------------------------------------------------------------------------- rodsolve

def run_rodsolve(args, p, n, steps, repeat, samples=N_SAMPLES, packages=None, scheme=ORDER_2):
    """For each LU package of `packages` (default --packages): median time loop of `repeat`
    runs, Newton iterations, tips at the sample times, rodchain's fallback warnings. The
    repeats alternate between the packages, so that a change of the machine's load falls on
    all of them alike. With adaptive steps (`scheme`) `steps` is the number of records and the
    row's steps are those accepted."""
    packages = packages or args.packages
    scenes = {}
    tag = (f"_rtol{scheme.rtol:.0e}" if scheme.rtol is not None else
           f"_o{scheme.order}" if scheme.order != 2 else "")
    for package in packages:
        name = f"{p['name']}_n{n}_s{steps}{tag}_{package}"
        text = bench_common.rs.set_variable(
            scene_text(p, n, steps, samples, args.jacobian_reuse, package, scheme), "output",
            "path", f"'{os.path.join(args.workdir, name)}.h5'")
        scenes[package] = os.path.join(args.workdir, name + ".nml")
        with open(scenes[package], "w", encoding="utf-8") as f:
            f.write(text)
    walls = {package: [] for package in packages}
    out = {}
    for _ in range(repeat):
        for package in packages:
            stdout = run_scene(args, scenes[package])
            summary = SUMMARY.search(stdout)
            walls[package].append(float(summary[4]))
            view = RODCHAIN_VIEW.search(stdout)
            if (package == "rodchain") != bool(view):
                raise SystemExit(f"{scenes[package]}: LU package {package} asked for, but "
                                 f"rodchain's set-up line is {'missing' if not view else 'there'}")
            accepted = ADAPTIVE_STEPS.search(stdout)
            taken = int(accepted[1]) if accepted else steps
            row = out.setdefault(package, {
                "code": "rodsolve", "package": package, "scheme": scheme, "n": n,
                "steps": taken, "dt": p["t_end"] / taken, "iterations": int(summary[2]),
                "cutbacks": int(summary[3]), "fallbacks": set(),
                "panels": view[2] if view else None})
            if int(summary[2]) != row["iterations"]:
                log(f"  {scenes[package]}: {summary[2]} Newton iterations, "
                    f"{row['iterations']} in the first run")
            row["fallbacks"].update(RODCHAIN_FALLBACK.findall(stdout))
    for package, row in out.items():
        with h5py.File(scenes[package][:-4] + ".h5", "r") as f:
            times = f["/rods/beam/time"][()]
            row["tip"] = f["/rods/beam/position"][:, -1, :]
        if len(times) != samples + 1 or abs(times[-1] - p["t_end"]) > 1e-9 * p["t_end"]:
            raise SystemExit(f"{scenes[package]}: unexpected output times {times[:3]} ... "
                             f"{times[-1]}")
        row["walls"] = walls[package]
        row["wall"] = statistics.median(walls[package])
        for why in row["fallbacks"]:
            log(f"  {scenes[package]}: rodchain fell back to MUMPS: {why}")
    return out


def run_scene(args, scene):
    """One run of rodsolve on `scene` (one rank); its standard output."""
    for attempt in range(40):   # the lead may be rebuilding build/: wait for the binary
        if os.path.exists(args.rodsolve):
            result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1",
                                     args.rodsolve, scene], capture_output=True, text=True)
            if result.returncode == 0 or os.path.exists(args.rodsolve):
                break
        log(f"{args.rodsolve} missing, waiting (attempt {attempt + 1})")
        time.sleep(30)
    LOADS.append(os.getloadavg()[0])
    if result.returncode != 0:
        sys.stderr.write(result.stdout + result.stderr)
        raise SystemExit(f"{scene}: rodsolve failed")
    return result.stdout


def tip_distance(a, b):
    return float(np.max(np.linalg.norm(a - b, axis=1)))


def reference(args, p, runs):
    """The reference run (n, steps) and its error estimate: Richardson on the time ladder
    steps/4, steps/2, steps at n and on the space ladder n/2, n, 2n at steps/4, all with the
    first LU package; the finest run again with each other package, and their distance."""
    n, steps = runs["ref"]
    first = args.packages[:1]
    ladder_t = [run_rodsolve(args, p, n, s, 1, packages=first)[first[0]]
                for s in (steps // 4, steps // 2, steps)]
    ladder_x = [run_rodsolve(args, p, k, steps // 4, 1, packages=first)[first[0]]
                for k in (n // 2, 2 * n)]
    ladder_x.insert(1, ladder_t[0])
    ref = ladder_t[-1]
    amp = float(np.max(np.linalg.norm(ref["tip"] - ref["tip"][0], axis=1)))

    def estimate(ladder):
        coarse = tip_distance(ladder[0]["tip"], ladder[1]["tip"]) / amp
        fine = tip_distance(ladder[1]["tip"], ladder[2]["tip"]) / amp
        q = coarse / fine if fine > 0 else math.inf
        # geometric tail of the differences: error of the finest ~ fine / (q - 1)
        est = fine / (q - 1.0) if q > 1.2 else math.inf
        return {"coarse": coarse, "fine": fine, "ratio": q, "order": math.log2(q) if q > 0
                else math.nan, "estimate": est}

    check = {"time": estimate(ladder_t), "space": estimate(ladder_x)}
    check["estimate"] = check["time"]["estimate"] + check["space"]["estimate"]
    check["wall"] = ref["wall"]
    check["packages"] = {}
    for package in args.packages[1:]:
        other = run_rodsolve(args, p, n, steps, 1, packages=[package])[package]
        check["packages"][package] = {"distance": tip_distance(other["tip"], ref["tip"]) / amp,
                                      "wall": other["wall"], "iterations": other["iterations"]}
        log(f"{p['name']}: reference with {package}: {other['wall']:.3g} s "
            f"({first[0]}: {ref['wall']:.3g} s), distance to {first[0]}'s "
            f"{check['packages'][package]['distance']:.1e} of the excursion")
    log(f"{p['name']}: reference n = {n}, {steps} steps, tip excursion {amp:.4g} m; "
        f"time ladder differences {check['time']['coarse']:.2e}, {check['time']['fine']:.2e}, "
        f"space ladder {check['space']['coarse']:.2e}, {check['space']['fine']:.2e}; "
        f"estimate {check['estimate']:.2e}")
    return ref, amp, check


def scheme_points(args, p, runs):
    """rodsolve's order-4 and adaptive runs of problem p (`runs`: SCHEME_RUNS), with the first
    LU package, the repeats of a point in a row: scheme name -> rows."""
    package = args.packages[0]
    points = [(ORDER_4, n, steps) for n, steps in runs["order 4"]]
    points += [(Scheme("adaptive", 2, rtol), n, N_SAMPLES) for n, rtol in runs["adaptive"]]
    out = {}
    for scheme, n, steps in points:
        row = run_rodsolve(args, p, n, steps, args.repeat, packages=[package],
                           scheme=scheme)[package]
        out.setdefault(scheme.name, []).append(row)
        log(f"  rodsolve {scheme.name} n = {n}, {row['steps']} steps"
            + (f" (rtol {scheme.rtol:g})" if scheme.rtol else "")
            + f": {row['wall']:.3g} s ({row['iterations']} it.)")
    return out


# ---------------------------------------------------------------------------- PyElastica

def venv_python(args):
    """The virtual environment's python, creating the environment if it has no pyelastica."""
    venv = args.venv or os.path.join(args.workdir, "venv")
    python = os.path.join(venv, "bin", "python")
    info = {"path": venv, "created": False}
    probe = [python, "-c", "import elastica, h5py"]
    if not (os.path.exists(python) and subprocess.run(probe, capture_output=True).returncode == 0):
        log(f"creating {venv} and installing {args.pyelastica} h5py from PyPI")
        start = time.perf_counter()
        subprocess.run(["/usr/bin/python3", "-m", "venv", venv], check=True)
        subprocess.run([python, "-m", "pip", "install", "--quiet", args.pyelastica, "h5py"],
                       check=True)
        info.update(created=True, seconds=time.perf_counter() - start)
    versions = subprocess.run(
        [python, "-c", "import importlib.metadata as m, sys; print(sys.version.split()[0], "
         "*(m.version(p) for p in ('pyelastica', 'numba', 'llvmlite', 'numpy')))"],
        capture_output=True, text=True, check=True).stdout.split()
    info["versions"] = dict(zip(("python", "pyelastica", "numba", "llvmlite", "numpy"), versions))
    return python, info


def pyelastica(args, python, job):
    """Run one job of peer_pyelastica.py in the virtual environment; its JSON answer."""
    stem = os.path.join(args.workdir, f"pyelastica_{job['mode']}_{job['problem']['name']}")
    with open(stem + "_job.json", "w", encoding="utf-8") as f:
        json.dump(job, f)
    subprocess.run([python, WORKER, stem + "_job.json", stem + "_out.json"], check=True)
    with open(stem + "_out.json", encoding="utf-8") as f:
        return json.load(f)


def warmup(args, python, clear):
    """numba JIT warm-up of PyElastica in two fresh processes: the first compiles the kernels
    (cold) if the environment was just made or `clear` removed numba's on-disk cache first;
    the second loads them from that cache, as every later process does."""
    p = problem("cantilever_steel")
    out = {}
    if clear:
        site = glob.glob(os.path.join(os.path.dirname(os.path.dirname(python)), "lib",
                                      "python*", "site-packages", "elastica"))
        for path in glob.glob(os.path.join(site[0], "**", "*.nb[ic]"), recursive=True):
            os.remove(path)
    first = pyelastica(args, python, {"mode": "warmup", "problem": p})["warmup"]
    out["cached"] = pyelastica(args, python, {"mode": "warmup", "problem": p})["warmup"]
    if clear or args.venv_created:
        out["cold"] = first
    log(f"PyElastica warm-up: {out}")
    return out


def pyelastica_sweep(args, python, p, ns):
    """PyElastica's runs at 0.8 of the estimated stable step (a whole number of steps per
    sample interval)."""
    grid = p["t_end"] / N_SAMPLES
    runs = [(n, math.ceil(grid / (args.safety * pyelastica_dt_estimate(p, n)))) for n in ns]
    out = pyelastica(args, python, {"mode": "sweep", "problem": p, "runs": runs,
                                    "repeat": args.repeat})
    rows = []
    for r in out["runs"]:
        tip = np.array(r["tip"])
        if not np.all(np.isfinite(tip)):
            raise SystemExit(f"PyElastica {p['name']} n = {r['n']}: unstable")
        rows.append({"code": "PyElastica", "n": r["n"], "steps": r["per_sample"] * N_SAMPLES,
                     "dt": grid / r["per_sample"], "wall": statistics.median(r["walls"]),
                     "walls": r["walls"], "tip": tip})
    return rows, out["warmup"]


# ---------------------------------------------------------------------------- analysis

def pyelastica_limit(rows, ref, amp):
    """PyElastica's own converged answer against the rodsolve reference: Richardson
    extrapolation of its three finest runs (n doubling) with their observed order."""
    if len(rows) < 3:
        return None
    a, b, c = sorted(rows, key=lambda r: r["n"])[-3:]
    q = math.log2(tip_distance(a["tip"], b["tip"]) / tip_distance(b["tip"], c["tip"]))
    limit = c["tip"] + (c["tip"] - b["tip"]) / (2.0 ** q - 1.0)
    return {"n": (a["n"], b["n"], c["n"]), "order": q,
            "distance": tip_distance(limit, ref["tip"]) / amp}


def front(rows, key):
    """The points no cheaper point beats in error (`key`), sorted by wall time."""
    best, out = math.inf, []
    for r in sorted(rows, key=lambda r: r["wall"]):
        if r[key] < best:
            best = r[key]
            out.append(r)
    return out


def pyelastica_model(p, safety):
    """Extrapolation of PyElastica's wall time to an error level it did not reach: its error
    falls like n^-q (q from its two finest runs), its step is `safety` of the estimated stable
    step at that n, and its cost per step grows linearly in n (fit through the two finest runs).
    Returns (wall, n) or None."""
    def model(level, rows, key):
        a, b = sorted(rows, key=lambda r: r["n"])[-2:]
        if not b[key] < a[key]:
            return None
        q = math.log(a[key] / b[key]) / math.log(b["n"] / a["n"])
        n = b["n"] * (b[key] / level) ** (1.0 / q)
        per_a, per_b = a["wall"] / a["steps"], b["wall"] / b["steps"]
        per_step = per_b + max((per_b - per_a) / (b["n"] - a["n"]), 0.0) * (n - b["n"])
        return per_step * p["t_end"] / (safety * pyelastica_dt_estimate(p, n)), n
    return model


def wall_at(rows, key, level, model=None):
    """Wall time at error `level` on the log-log front: ('interp', wall), ('below', wall of the
    cheapest run, already more accurate), or ('unreached', best error, its wall, model(level)
    = (extrapolated wall, n) or None)."""
    pts = front(rows, key)
    if pts[0][key] <= level:
        return ("below", pts[0]["wall"])
    for a, b in zip(pts, pts[1:]):
        if a[key] >= level >= b[key]:
            s = math.log(level / a[key]) / math.log(b[key] / a[key])
            return ("interp", math.exp(math.log(a["wall"]) + s * math.log(b["wall"] / a["wall"])))
    return ("unreached", pts[-1][key], pts[-1]["wall"], model(level, rows, key) if model else None)


def fmt_wall(w, level):
    if w[0] == "interp":
        return f"{w[1]:.3g}"
    if w[0] == "below":
        return f"< {w[1]:.3g} (cheapest run)"
    text = f"not reached: best {w[1]:.2g} ({w[1] / level:.3g}x the level) in {w[2]:.3g}"
    return text + (f"; extrapolated ~{w[3][0]:.2g} (n ~ {w[3][1]:.3g})" if w[3] else "")


def ratio_cell(ws, wp):
    """PyElastica's wall over rodsolve's, with the direction of a bound."""
    if ws[0] == "interp" and wp[0] == "interp":
        return f"**{wp[1] / ws[1]:.3g}**"
    if wp[0] == "unreached":
        low = wp[2] / ws[1]
        text = f">= {low:.3g}" if ws[0] == "interp" else f"> {low:.3g}"
        return text + (f" (extrapolated ~{wp[3][0] / ws[1]:.2g})" if wp[3] else "")
    if ws[0] == "unreached":
        return f"<= {wp[1] / ws[2]:.3g} (rodsolve did not reach it)"
    if ws[0] == "below" and wp[0] == "interp":
        return f"> {wp[1] / ws[1]:.3g}"
    if wp[0] == "below" and ws[0] == "interp":
        return f"< {wp[1] / ws[1]:.3g}"
    return "both below their cheapest run"


def speedup_cell(new, old):
    """Wall time of package `old` over that of `new` at the same error level."""
    if new[0] == "interp" and old[0] == "interp":
        return f"**{old[1] / new[1]:.3g}**"
    if new[0] == "below" and old[0] == "below":
        return f"{old[1] / new[1]:.3g} (cheapest runs)"
    if new[0] == "below" and old[0] == "interp":
        return f"> {old[1] / new[1]:.3g}"
    if new[0] == "interp" and old[0] == "below":
        return f"< {old[1] / new[1]:.3g}"
    return "not reached"


def ratio_header(packages):
    old = [f"{pk} / {packages[0]}" for pk in packages[1:]]
    cols = (["case", "level"] + [f"rodsolve {pk} [s]" for pk in packages] + ["PyElastica [s]"]
            + [f"PyElastica / {pk}" for pk in packages] + old)
    return ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]


def ratio_rows(case, key, levels, ref_est, safety, packages):
    rows = []
    for level in levels:
        if 10.0 * ref_est > level:
            rows.append(f"| {case['p']['name']} | {level:g} | reference not fine enough "
                        f"(estimate {ref_est:.1e} > level/10) |" + " |" * (3 * len(packages)))
            continue
        ws = {pk: wall_at(case["rodsolve"][pk], key, level) for pk in packages}
        wp = wall_at(case["pyelastica"], key, level, pyelastica_model(case["p"], safety))
        cells = ([case["p"]["name"], f"{level:g}"] + [fmt_wall(ws[pk], level) for pk in packages]
                 + [fmt_wall(wp, level)] + [ratio_cell(ws[pk], wp) for pk in packages]
                 + [speedup_cell(ws[packages[0]], ws[pk]) for pk in packages[1:]])
        rows.append("| " + " | ".join(cells) + " |")
    return rows


def target_cell(case, level, required, package, safety):
    """The ratio PyElastica / rodsolve (`err`) at `level` and whether it shows the target."""
    ws = wall_at(case["rodsolve"][package], "err", level)
    wp = wall_at(case["pyelastica"], "err", level, pyelastica_model(case["p"], safety))
    if 10.0 * case["check"]["estimate"] > level:
        return "reference not fine enough"
    cell = ratio_cell(ws, wp)
    if ws[0] == "interp" and wp[0] == "interp":
        return cell + (" (met)" if wp[1] / ws[1] >= required else " (**not met**)")
    bound = (wp[2] / ws[1] if wp[0] == "unreached" and ws[0] != "unreached" else
             wp[1] / ws[1] if ws[0] == "below" and wp[0] == "interp" else None)
    if bound is None:
        return cell
    return cell + (" (met by the measured bound)" if bound >= required else
                   " (not shown by the measured bound)")


def scheme_label(scheme):
    """' order 4', ' adaptive (rtol 1e-05)', or '' for order 2 (the rows' code column)."""
    if scheme.rtol is not None:
        return f" adaptive (rtol {scheme.rtol:.0e})"
    return "" if scheme == ORDER_2 else f" {scheme.name}"


def scheme_header():
    cols = ["case", "level", "order 2 [s]", "order 4 [s]", "adaptive [s]", "order 2 / order 4",
            "order 2 / adaptive", "PyElastica / cheapest rodsolve"]
    return ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]


def scheme_rows(case, levels, package, safety):
    """Wall time of rodsolve's order 2, order 4 and adaptive steps at each error level, their
    ratios, and PyElastica's against the cheapest of them."""
    rows = []
    for level in levels:
        if 10.0 * case["check"]["estimate"] > level:
            continue
        ws = {"order 2": wall_at(case["rodsolve"][package], "err", level)}
        ws.update({name: wall_at(runs, "err", level) for name, runs in case["schemes"].items()})
        reached = [w for w in ws.values() if w[0] != "unreached"]
        best = min(reached, key=lambda w: w[1]) if reached else None
        wp = wall_at(case["pyelastica"], "err", level, pyelastica_model(case["p"], safety))
        cells = ([case["p"]["name"], f"{level:g}"]
                 + [fmt_wall(ws[name], level) if name in ws else "-"
                    for name in ("order 2", "order 4", "adaptive")]
                 + [speedup_cell(ws[name], ws["order 2"]) if name in ws else "-"
                    for name in ("order 4", "adaptive")]
                 + [ratio_cell(best, wp) if best else "-"])
        rows.append("| " + " | ".join(cells) + " |")
    return rows


def figure(case, path, packages):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    curves = [(case["rodsolve"][pk], "o-", f"C{2 * i}",
               f"rodsolve, LU {pk} (quadratic elements, steps)", i == 0)
              for i, pk in enumerate(packages)]
    curves += [(case["schemes"][name], style, color, f"rodsolve {name}, LU {packages[0]}", False)
               for name, style, color in (("order 4", "D--", "C3"), ("adaptive", "^:", "C4"))
               if name in case["schemes"]]
    curves.append((case["pyelastica"], "s-", "C1", "PyElastica 1.0.0 (elements)", True))
    for rows, style, color, label, annotate in curves:
        ax.loglog([r["err"] for r in rows], [r["wall"] for r in rows], style[0], alpha=0.35,
                  color=color)
        pts = front(rows, "err")
        ax.loglog([r["err"] for r in pts], [r["wall"] for r in pts], style, color=color,
                  label=label)
        for r in rows if annotate else []:
            text = f"{r['n']},{r['steps']}" if r["code"] == "rodsolve" else f"{r['n']}"
            ax.annotate(text, (r["err"], r["wall"]), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
    for level in LEVELS:
        ax.axvline(level, color="grey", ls=":", lw=0.8)
    ax.axvspan(1e-7, 10.0 * case["check"]["estimate"], color="grey", alpha=0.12,
               label="below 10x the reference's error estimate")
    errs = [r["err"] for rows, *_ in curves for r in rows]
    ax.set_xlim(min(min(errs), 5e-5) / 2, max(errs) * 2)
    ax.set_xlabel("max over the run of |tip - tip_ref| / tip excursion")
    ax.set_ylabel("wall time of the time loop [s] (median)")
    ax.set_title(f"{case['p']['name']}: work against precision")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------------------- stability

def stability(args, python, ns, names):
    """PyElastica's stable step against n for the rods `names`, by bisection."""
    out = {}
    for name in names:
        p = problem(name)
        job = {"mode": "stability", "problem": p, "steps": args.stability_steps,
               "rtol": args.stability_rtol,
               "runs": [(n, pyelastica_dt_estimate(p, n)) for n in ns]}
        log(f"{name}: PyElastica's stable step by bisection")
        out[name] = pyelastica(args, python, job)["limits"]
    return out


def big_step(args, p, ref):
    """rodsolve with 8 elements and 10 steps over the whole run: finite, and how far off."""
    r = run_rodsolve(args, p, 8, 10, 1, samples=10, packages=args.packages[:1])
    r = r[args.packages[0]]
    err = float(np.linalg.norm(r["tip"][-1] - ref["tip"][-1]))
    return {"dt": r["dt"], "iterations": r["iterations"], "cutbacks": r["cutbacks"],
            "finite": bool(np.all(np.isfinite(r["tip"]))), "err_end": err}


# ---------------------------------------------------------------------------- documents

def describe_problem(p, amp):
    bc = "clamped at s = 0" if p["bc"] == "clamped" else "free (no boundary condition)"
    return (f"| {p['name']} | {p['material']}: E = {p['E']:g}, nu = {p['nu']}, "
            f"rho = {p['rho']:g} | {bc} | {p['P']:.4g} N (= {CASES[p['name']]['load']} EI/L^2) "
            f"| {p['t_pulse']:g} | {p['t_end']:g} | {p['period']:.4g} | {amp:.4g} |")


def package_check(args, cases):
    """How far the LU packages' runs lie apart: references, every point's tip, its err, its
    Newton iterations; rodchain's fallbacks to MUMPS."""
    first, others = args.packages[0], args.packages[1:]
    out = {"ref": [], "tip": 0.0, "err": 0.0, "points": 0, "iterations": [], "fallbacks": []}
    for c in cases:
        for package, ch in c["check"]["packages"].items():
            out["ref"].append(f"{c['p']['name']} {ch['distance']:.1e} ({package} "
                              f"{ch['wall']:.3g} s, {first} {c['check']['wall']:.3g} s)")
        for i, r0 in enumerate(c["rodsolve"][first]):
            out["points"] += 1
            for package in others:
                r = c["rodsolve"][package][i]
                out["tip"] = max(out["tip"], tip_distance(r["tip"], r0["tip"]) / c["amp"])
                out["err"] = max(out["err"], abs(r["err"] - r0["err"]), abs(r["err_x"] -
                                                                          r0["err_x"]))
                if r["iterations"] != r0["iterations"] or r["cutbacks"] != r0["cutbacks"]:
                    out["iterations"].append(
                        f"{c['p']['name']} n = {r['n']}, {r['steps']} steps: {first} "
                        f"{r0['iterations']} ({r0['cutbacks']} cut-backs), {package} "
                        f"{r['iterations']} ({r['cutbacks']})")
        for package in args.packages:
            for r in c["rodsolve"][package]:
                out["fallbacks"] += [f"{c['p']['name']} n = {r['n']}, {r['steps']} steps: "
                                     f"{why}" for why in sorted(r["fallbacks"])]
    return out


def performance_block(args, env, cases, warm, seconds):
    first, others = args.packages[0], args.packages[1:]
    agree = package_check(args, cases)
    not_run = [name for name in CASES if name not in [c["p"]["name"] for c in cases]]
    lines = [
        f"{measured_on()}; rodsolve {env['rodsolve']} on one rank, &solver jacobian_reuse = "
        f"{args.jacobian_reuse:g}{' (default)' if not args.jacobian_reuse else ''}; LU "
        f"package of the Newton steps {' and '.join(args.packages)} "
        f"(`-pc_factor_mat_solver_type` in the scene's `&solver petsc_options`; "
        f"rodchain is the default of a single ph_director rod, mumps the path it replaced), "
        f"each point run with every package in turn, {args.repeat} time(s). Load average "
        f"{env['load_before'][0]:.2f} before, {env['load_after'][0]:.2f} after, "
        f"{min(LOADS):.2f} to {max(LOADS):.2f} at the rodsolve runs (other agents share the "
        f"{os.cpu_count()} cores: compare the ratios, measured in the same run, rather than "
        f"absolute times). Cases run: {', '.join(c['p']['name'] for c in cases)}"
        + (f" (not run this time: {', '.join(not_run)})" if not_run else "")
        + f". PyElastica {env['venv']['versions']['pyelastica']} (numba "
        f"{env['venv']['versions']['numba']}, llvmlite {env['venv']['versions']['llvmlite']}, "
        f"numpy {env['venv']['versions']['numpy']}, Python "
        f"{env['venv']['versions']['python']}), installed from PyPI into a virtual environment"
        + (f" in {env['venv']['seconds']:.0f} s" if env["venv"]["created"] else
           " (reused)") + f". Median of {args.repeat} run(s); bench run time "
        f"{seconds / 60:.1f} min" + (" (--quick)" if args.quick else "") + ".",
        "",
        "PyElastica's numba JIT warm-up (first step of a process; excluded from every time "
        "below): " + (f"**{warm['cold']:.1f} s** with an empty kernel cache (a fresh install), "
                      if "cold" in warm else "") + f"{warm['cached']:.2f} s when numba's "
        f"on-disk cache holds the kernels (every later process); in the sweeps "
        f"{', '.join(f'{c}: {w:.2f} s' for c, w in env['sweep_warmups'].items())}.",
        "",
        "Problems (L = 1 m, circular section r = 5 mm, PyElastica's shear factor 27/28 in both, "
        "no gravity, no damping; tip force F (1 - cos(2 pi t / t_pulse))/2 e3 for t < t_pulse, "
        "then free motion; T1 the first bending period):",
        "",
        "| case | material [SI] | support | peak force | t_pulse [s] | t_end [s] | T1 [s] | "
        "tip excursion [m] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    lines += [describe_problem(c["p"], c["amp"]) for c in cases]
    lines += [
        "",
        "**Error** (`err`): the largest distance over the 101 sample times t_k = k t_end/100 "
        "between a run's tip and the reference's tip, divided by the reference's largest tip "
        "excursion max |x_tip(t) - x_tip(0)|. `err_x` divides by max |x_tip| (about L) "
        "instead: the tip position error relative to the tip position.",
        "",
        "**References**: one rodsolve run per problem (quadratic elements, midpoint steps); "
        "checked by the time ladder steps/4, steps/2, steps (same mesh) and the space ladder "
        "n/2, n, 2n (at steps/4). Differences of neighbours (coarse, fine) relative to the "
        "excursion; error estimate of the finest = fine/(coarse/fine - 1), summed over time "
        "and space. A level is only used if it is above 10x the estimate.",
        "",
        "| case | reference | time ladder: differences, observed order | space ladder: "
        "differences, observed order | error estimate | levels allowed |",
        "|---|---|---|---|---|---|",
    ]
    for c in cases:
        ch, (n, s) = c["check"], c["runs"]["ref"]
        allowed = [f"{lv:g}" for lv in LEVELS if 10.0 * ch["estimate"] <= lv]
        lines.append(
            f"| {c['p']['name']} | n = {n}, {s} steps ({ch['wall']:.3g} s) | "
            f"{ch['time']['coarse']:.2e}, {ch['time']['fine']:.2e}, {ch['time']['order']:.2f} | "
            f"{ch['space']['coarse']:.2e}, {ch['space']['fine']:.2e}, "
            f"{ch['space']['order']:.2f} | {ch['estimate']:.1e} | "
            f"{', '.join(allowed) or 'none'} |")
    if others:
        lines += ["", f"**LU packages**: the finest reference rerun with "
                  f"{' and '.join(others)}, its distance to {first}'s relative to the "
                  f"excursion: {'; '.join(agree['ref'])}. Over the "
                  f"{agree['points']} work-precision points the tips of the packages differ by "
                  f"at most {agree['tip']:.1e} of the excursion and err, err_x by at most "
                  f"{agree['err']:.1e}: the errors below are those of either package. Newton "
                  "iterations and cut-backs " + ("are the same in every point" if not
                                                 agree["iterations"] else "differ: " +
                                                 "; ".join(agree["iterations"])) + "."]
    lines += ["", "rodchain's fallbacks to MUMPS (its warning in rodsolve's output): "
              + ("; ".join(sorted(set(agree["fallbacks"]))) if agree["fallbacks"] else
                 "none") + "."] if "rodchain" in args.packages else []
    lines += ["", "PyElastica's own limit (Richardson on its three finest runs with their "
              "observed order q) against the rodsolve reference, relative to the excursion: "
              + "; ".join(
                  f"{c['p']['name']}: {c['check']['pyelastica']['distance']:.1e} "
                  f"(n = {', '.join(map(str, c['check']['pyelastica']['n']))}, "
                  f"q = {c['check']['pyelastica']['order']:.2f})"
                  for c in cases if c["check"].get("pyelastica")) + "."]
    for key, title in (("err", "err (relative to the tip excursion)"),
                       ("err_x", "err_x (relative to the tip position)")):
        lines += ["", f"**Wall time at equal error, {title}**: interpolated log-log between "
                  "neighbouring points of each code's front (its runs that no cheaper run "
                  "beats); ratio = PyElastica / rodsolve with each LU package"
                  + (f", and {' and '.join(others)} / {first}: how much faster the chain LU "
                     "makes rodsolve" if others else "") + ". 'Extrapolated' is not a "
                  "measurement: PyElastica's error continued as n^-q (q from its two finest "
                  "runs), its step at 0.8 of the stable estimate for that n, its cost per step "
                  "linear in n.", ""] + ratio_header(args.packages)
        for c in cases:
            lines += ratio_rows(c, key, LEVELS, c["check"]["estimate"], args.safety,
                                args.packages)
    targets = [t for t in TARGETS if t[0] in [c["p"]["name"] for c in cases]]
    if targets:
        lines += ["", "**The issue's targets** (PyElastica / rodsolve at equal `err`, from the "
                  "first table):", "",
                  "| case | level | required | " + " | ".join(
                      f"with {pk}" for pk in args.packages) + " |",
                  "|---|---|---|" + "---|" * len(args.packages)]
        for name, level, required in targets:
            c = [c for c in cases if c["p"]["name"] == name][0]
            lines.append(f"| {name} | {level:g} | >= {required:g} | " + " | ".join(
                target_cell(c, level, required, pk, args.safety) for pk in args.packages)
                + " |")
    lines += ["", f"**rodsolve's time integrators at equal error** (`err`, LU package {first}; "
              "interpolated as above on each integrator's front over all its meshes; order 2 "
              "/ order 4 > 1: order 4 is cheaper; the last column sets PyElastica against the "
              "cheapest of the three):", ""] + scheme_header()
    for c in cases:
        lines += scheme_rows(c, LEVELS, first, args.safety)
    lines += ["", "**Work-precision points** (PyElastica at 0.8 of the estimated stable step; "
              "rodsolve: Newton iterations of the run, with each LU package; order 4 and "
              "adaptive steps with the first one; adaptive runs: the steps accepted, dt their "
              "mean):", "",
              "| case | code | elements | steps | dt [s] | err | err_x | wall [s] | "
              "Newton it. |", "|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        schemes = [r for rows in c["schemes"].values() for r in rows]
        for r in ([r for pk in args.packages for r in c["rodsolve"][pk]] + schemes
                  + c["pyelastica"]):
            code = (f"rodsolve{scheme_label(r['scheme'])}, {r['package']}"
                    if r["code"] == "rodsolve" else r["code"])
            lines.append(f"| {c['p']['name']} | {code} | {r['n']}"
                         f"{' (quadratic)' if r['code'] == 'rodsolve' else ''} | {r['steps']} | "
                         f"{r['dt']:.3g} | {r['err']:.2e} | {r['err_x']:.2e} | {r['wall']:.3g} | "
                         f"{r.get('iterations', '-')} |")
    lines += ["", "Figures: " + ", ".join(
        f"[{c['p']['name']}](figures/peer_{c['p']['name']}.png)" for c in cases), ""]
    lines += [f"![{c['p']['name']}](figures/peer_{c['p']['name']}.png)" for c in cases]
    return "\n".join(lines) + "\n"


def stability_block(args, env, cases, limits):
    lines = [
        f"{measured_on()}; PyElastica {env['venv']['versions']['pyelastica']}, PositionVerlet. "
        f"Largest stable step by bisection (geometric, to a relative bracket of "
        f"{args.stability_rtol:g}): a step is stable if {args.stability_steps} steps of the "
        "problem (same rod, support and load as in docs/performance.md), started with random "
        "velocities of 1e-9 m/s and angular velocities of 1e-7 rad/s to seed every mode, leave "
        "every node finite and within 10 L of the origin (unseeded, the exactly straight rod "
        "needs tens of thousands of steps to show the same limit). Estimate: 2/omega_max with omega_max^2 = "
        "4 k G/(rho r^2) + 4 (E + k G)/(rho dx^2) (thickness shear of a section plus the "
        "axial and shear waves of one element, tests/bench/peer/README.md).",
        "",
        "| rod | elements | dx [m] | estimate [s] | stable [s] | unstable [s] | "
        "stable / estimate | steps for t_end at the limit |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for c in cases:
        p = c["p"]
        for lim in limits.get(p["name"], []):
            est = pyelastica_dt_estimate(p, lim["n"])
            lines.append(f"| {p['name']} | {lim['n']} | {p['L'] / lim['n']:.3g} | {est:.3g} | "
                         f"{lim['stable']:.4g} | {lim['unstable']:.4g} | "
                         f"{lim['stable'] / est:.3f} | {math.ceil(p['t_end'] / lim['stable'])} |")
    lines += [
        "",
        "rodsolve (ph_director, implicit midpoint rule) has no stability limit; its step is "
        "chosen for accuracy. Steps of the side by side and one run with 10 steps over the whole "
        f"problem (8 quadratic elements, LU package {args.packages[0]}):",
        "",
        "| rod | rodsolve dt in the sweep [s] | / PyElastica's limit (n = 10) | 10 steps: dt [s] "
        "| Newton it., cut-backs | finite | tip error at t_end [m] |",
        "|---|---|---|---|---|---|---|",
    ]
    for c in cases:
        p = c["p"]
        dts = [r["dt"] for r in c["rodsolve"][args.packages[0]]]
        lim10 = [lim["stable"] for lim in limits.get(p["name"], []) if lim["n"] == 10]
        ratio = (f"{min(dts) / lim10[0]:.0f} to {max(dts) / lim10[0]:.0f}" if lim10 else "-")
        b = c["big_step"]
        lines.append(f"| {p['name']} | {min(dts):.3g} to {max(dts):.3g} | {ratio} | "
                     f"{b['dt']:.3g} | {b['iterations']}, {b['cutbacks']} | {b['finite']} | "
                     f"{b['err_end']:.3g} |")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------- main

def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rodsolve", default="build/rodsolve")
    parser.add_argument("--rodsolve-note", default="",
                        help="said after rodsolve's version in the block (e.g. which sources a "
                        "copied binary was built from)")
    parser.add_argument("--mpiexec", default="mpirun")
    parser.add_argument("--source", default=".")
    parser.add_argument("--workdir", default="build/peer-work")
    parser.add_argument("--venv", help="virtual environment (default: WORKDIR/venv)")
    parser.add_argument("--pyelastica", default=PYELASTICA, help="pip requirement")
    parser.add_argument("--repeat", type=int, default=3, help="runs per point (median)")
    parser.add_argument("--quick", action="store_true",
                        help="coarse reference, few runs, one repeat (development, < 3 min)")
    parser.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES))
    parser.add_argument("--safety", type=float, default=0.8,
                        help="PyElastica's step as a fraction of the estimated stable step")
    parser.add_argument("--jacobian-reuse", type=float, default=0.0,
                        help="rodsolve's &solver jacobian_reuse (default 0: rodsolve's default)")
    parser.add_argument("--packages", type=lambda text: text.split(","),
                        default=["rodchain", "mumps"],
                        help="rodsolve's LU packages, comma-separated (default rodchain,mumps); "
                        "the first one runs the reference")
    parser.add_argument("--stability-steps", type=int, default=None)
    parser.add_argument("--stability-rtol", type=float, default=None)
    parser.add_argument("--write", action="store_true",
                        help="update docs/performance.md, docs/stability.md, docs/figures")
    args = parser.parse_args()
    if args.quick:
        args.repeat = 1 if "--repeat" not in sys.argv else args.repeat
    args.stability_steps = args.stability_steps or (1000 if args.quick else 5000)
    args.stability_rtol = args.stability_rtol or (0.05 if args.quick else 0.01)
    args.workdir = os.path.abspath(args.workdir)
    args.rodsolve = os.path.abspath(args.rodsolve)
    os.makedirs(args.workdir, exist_ok=True)
    for k, v in OPENMPI_ENV.items():
        os.environ[k] = v
    start = time.perf_counter()
    runs = RUNS["quick" if args.quick else "full"]
    version = subprocess.run([args.rodsolve, "--version"], capture_output=True, text=True)
    env = {"load_before": os.getloadavg(), "sweep_warmups": {},
           "rodsolve": version.stdout.split("\n")[0].replace("rodsolve ", "")
           + (f" ({args.rodsolve_note})" if args.rodsolve_note else "")}
    python, env["venv"] = venv_python(args)
    args.venv_created = env["venv"]["created"]
    log(f"PyElastica environment {env['venv']}")
    warm = warmup(args, python, clear=not args.quick)

    cases = []
    for name in args.cases:
        p = problem(name)
        case_runs = dict(runs[p["bc"]], **runs.get(name, {}))
        log(f"{name}: t_pulse {p['t_pulse']} s, t_end {p['t_end']} s, T1 {p['period']:.4g} s")
        ref, amp, check = reference(args, p, case_runs)
        rows = {package: [] for package in args.packages}
        for n, steps in case_runs["rodsolve"]:
            point = run_rodsolve(args, p, n, steps, args.repeat)
            for package in args.packages:
                rows[package].append(point[package])
            log(f"  rodsolve n = {n}, {steps} steps: " + ", ".join(
                f"{package} {point[package]['wall']:.3g} s ({point[package]['iterations']} it.)"
                for package in args.packages))
        schemes = scheme_points(args, p, SCHEME_RUNS["quick" if args.quick else "full"])
        pe_rows, env["sweep_warmups"][name] = pyelastica_sweep(args, python, p,
                                                               case_runs["pyelastica"])
        ref_x = float(np.max(np.linalg.norm(ref["tip"], axis=1)))
        for r in ([r for package in args.packages for r in rows[package]] + pe_rows
                  + [r for scheme_rows in schemes.values() for r in scheme_rows]):
            d = tip_distance(r["tip"], ref["tip"])
            r["err"], r["err_x"] = d / amp, d / ref_x
            log(f"  {r['code']:<10} {r.get('package', ''):<8} n = {r['n']:>4} "
                f"steps = {r['steps']:>7} err = {r['err']:.2e} err_x = {r['err_x']:.2e} "
                f"wall = {r['wall']:.3g} s")
        check["pyelastica"] = pyelastica_limit(pe_rows, ref, amp)
        case = {"p": p, "runs": case_runs, "amp": amp, "check": check, "rodsolve": rows,
                "schemes": schemes,
                "pyelastica": pe_rows, "big_step": big_step(args, p, ref)}
        agree = package_check(args, [case])
        log(f"{name}: packages: largest tip difference {agree['tip']:.1e}, err difference "
            f"{agree['err']:.1e} over {agree['points']} points; references {agree['ref']}; "
            f"iterations differing: {agree['iterations'] or 'none'}; rodchain fallbacks: "
            f"{agree['fallbacks'] or 'none'}")
        for line in ratio_header(args.packages) + ratio_rows(
                case, "err", LEVELS, check["estimate"], args.safety, args.packages):
            log(line)
        cases.append(case)

    limits = stability(args, python, runs["stability"], args.cases)
    env["load_after"] = os.getloadavg()
    seconds = time.perf_counter() - start
    perf = performance_block(args, env, cases, warm, seconds)
    stab = stability_block(args, env, cases, limits)
    figdir = os.path.join(args.source, "docs", "figures") if args.write else args.workdir
    for c in cases:
        figure(c, os.path.join(figdir, f"peer_{c['p']['name']}.png"), args.packages)
    print(perf)
    print(stab)
    if args.write:
        write_generated(args.source, SCRIPT, perf)
        write_generated(args.source, SCRIPT, stab, document="stability.md")
    log(f"bench_peer done in {seconds / 60:.1f} min")


if __name__ == "__main__":
    main()
