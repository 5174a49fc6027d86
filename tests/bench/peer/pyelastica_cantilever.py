"""Peer side by side (issue 11 item 2, first piece): a clamped cantilever under a suddenly
applied tip force, run by PyElastica and by rodsolve (ph_director) on the same physical problem.

Problem (SI units): straight rod along e1 from the origin, L = 1 m, circular section r = 5 mm,
clamped at s = 0, at rest; at t = 0 a constant spatial force P e3 is switched on at s = L (a step
load: the rod then oscillates about its static deflection, which is the linear mirror image of
being released from that deflection, see README.md). P = 0.15 EI/L^2, so the static tip
deflection is about 5 % of L and the first swing about 10 %. No gravity, no damping.
Materials: steel (E = 2e11, nu = 0.3, rho = 7800) and rubber-like (E = 1e7, nu = 0.49,
rho = 1100). End time: about two periods of the first bending mode.

Both codes use the same stiffnesses: EA = E A, GA = k G A with PyElastica's k = 27/28 (set as
rodsolve's shear_factor), EI = E pi r^4/4, GJ = G pi r^4/2, rhoA, rhoI = rho pi r^4/4.
PyElastica's `straight_rod` takes `shear_modulus` explicitly (its keyword `nu` is a damping
coefficient, not Poisson's ratio).

Reference: rodsolve with --ref-elements quadratic elements and the finest step; checked by
comparing with the run at half the elements and twice the step. Error of a run: the largest
distance over the sample times between its tip and the reference tip, divided by the largest
tip displacement |x_tip(t) - x_tip(0)| of the reference (column err_u); err_x divides by the
largest |x_tip| instead (about 10x smaller here, since |x_tip| ~ L). Wall time: the time loop
only (rodsolve's own summary line; PyElastica's stepping loop, numba JIT warm-up excluded and
reported), median of --repeat runs.

Usage (from the source tree, after `python3 -m venv build/peer-venv &&
build/peer-venv/bin/pip install pyelastica h5py`):
    build/peer-venv/bin/python tests/bench/peer/pyelastica_cantilever.py [--material steel]
        [--quick] [--repeat 3] [--rodsolve build/rodsolve] [--workdir build/peer-work]
"""
import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import time

import h5py
import numpy as np

L = 1.0
RADIUS = 5e-3
SHEAR_FACTOR = 27.0 / 28.0          # PyElastica's alpha_c (rod/factory_function.py)
LOAD_FACTOR = 0.15                   # P L^2 / EI
MATERIALS = {
    "steel": {"E": 2e11, "nu": 0.3, "rho": 7800.0},
    "rubber": {"E": 1e7, "nu": 0.49, "rho": 1100.0},
}
N_SAMPLES = 100                      # comparison times t_k = k t_end / N_SAMPLES

SUMMARY = re.compile(r"time loop (\S+) s")


def problem(material):
    """Derived data of one material: section constants, load, first period, end time."""
    m = dict(MATERIALS[material])
    area = math.pi * RADIUS ** 2
    inertia = math.pi * RADIUS ** 4 / 4.0
    m["G"] = m["E"] / (2.0 * (1.0 + m["nu"]))
    m["EI"] = m["E"] * inertia
    m["rhoA"] = m["rho"] * area
    m["P"] = LOAD_FACTOR * m["EI"] / L ** 2
    omega1 = 1.8751040687 ** 2 * math.sqrt(m["EI"] / (m["rhoA"] * L ** 4))
    m["T1"] = 2.0 * math.pi / omega1
    m["t_end"] = float(f"{2.0 * m['T1']:.2g}")
    m["grid_dt"] = m["t_end"] / N_SAMPLES
    return m


def pyelastica_dt_limit(m, n):
    """Estimated stability limit 2/omega_max of PositionVerlet on PyElastica's rod: the
    thickness-shear frequency (independent of n) plus the axial and shear waves of one element.
    Checked by hand on the steel rod: n = 25, 50, 100 stable at 1.4e-6, 1.4e-6, 1.0e-6 and
    unstable at -, 1.5e-6, 1.2e-6 (estimates 1.58e-6, 1.46e-6, 1.17e-6)."""
    dx = L / n
    kg_rho = SHEAR_FACTOR * m["G"] / m["rho"]
    omega2 = 4.0 * kg_rho / RADIUS ** 2 + 4.0 * (m["E"] / m["rho"] + kg_rho) / dx ** 2
    return 2.0 / math.sqrt(omega2)


def run_pyelastica(m, n, safety, repeat):
    """Tip samples at t_k and the median wall time of the stepping loop."""
    import elastica as ea

    class Sim(ea.BaseSystemCollection, ea.Constraints, ea.Forcing):
        pass

    def build():
        sim = Sim()
        rod = ea.CosseratRod.straight_rod(
            n, np.zeros(3), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]), L, RADIUS,
            m["rho"], youngs_modulus=m["E"], shear_modulus=m["G"])
        sim.append(rod)
        sim.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,),
                                 constrained_director_idx=(0,))
        # A ramp of 1e-300 s: the first force evaluation (t = dt/2) already sees the full load.
        sim.add_forcing_to(rod).using(ea.EndpointForces, np.zeros(3),
                                      np.array([0.0, 0.0, m["P"]]), ramp_up_time=1e-300)
        sim.finalize()
        return sim, rod

    per_sample = math.ceil(m["grid_dt"] / (safety * pyelastica_dt_limit(m, n)))
    dt = np.float64(m["grid_dt"] / per_sample)
    walls = []
    for _ in range(repeat):
        sim, rod = build()
        stepper = ea.PositionVerlet()
        t = np.float64(0.0)
        tips = [rod.position_collection[:, -1].copy()]
        start = time.perf_counter()
        for _ in range(N_SAMPLES):
            for _ in range(per_sample):
                t = stepper.step(sim, t, dt)
            tips.append(rod.position_collection[:, -1].copy())
        walls.append(time.perf_counter() - start)
    tips = np.array(tips)
    if not np.all(np.isfinite(tips)):
        raise SystemExit(f"PyElastica n={n} dt={dt:.3g}: unstable")
    return {"code": "PyElastica", "n": n, "dt": float(dt), "steps": per_sample * N_SAMPLES,
            "wall": statistics.median(walls), "tip": tips}


def pyelastica_jit_time():
    """Time of the first (compiling) step of a tiny rod in this process."""
    import elastica as ea

    class Sim(ea.BaseSystemCollection, ea.Constraints, ea.Forcing):
        pass

    start = time.perf_counter()
    sim = Sim()
    rod = ea.CosseratRod.straight_rod(8, np.zeros(3), np.array([1.0, 0, 0]),
                                      np.array([0, 1.0, 0]), 1.0, 0.01, 1000.0,
                                      youngs_modulus=1e6, shear_modulus=1e6 / 3)
    sim.append(rod)
    sim.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,),
                             constrained_director_idx=(0,))
    sim.add_forcing_to(rod).using(ea.EndpointForces, np.zeros(3), np.ones(3),
                                  ramp_up_time=1.0)
    sim.finalize()
    ea.PositionVerlet().step(sim, np.float64(0.0), np.float64(1e-6))
    return time.perf_counter() - start


def scene_text(m, material, n, dt, path):
    """The rodsolve scene of the same problem."""
    stride = round(m["grid_dt"] / dt)
    return f"""! Peer benchmark (tests/bench/peer/pyelastica_cantilever.py): {material} cantilever,
! step tip load P = {LOAD_FACTOR} EI/L^2 at t = 0, PyElastica's shear factor 27/28.
&run
    title = 'peer cantilever {material}'
/
&time
    t_end = {m['t_end']!r}
    dt = {dt!r}
/
&output
    path = '{path}'
    stride = {stride}
    fields = 'position'
/
&rod
    name = 'beam'
    formulation = 'ph_director'
    n_elements = {n}, degree = 2, n_gauss = 2
    start = 0.0, 0.0, 0.0
    direction = 1.0, 0.0, 0.0
    d1 = 0.0, 1.0, 0.0
    length = {L!r}
    section = 'circle', radius = {RADIUS!r}
    E = {m['E']!r}, nu = {m['nu']!r}, density = {m['rho']!r}
    shear_factor = {SHEAR_FACTOR!r}
/
&bc
    rod = 'beam', end = 'start', kind = 'clamped'
/
&load
    rod = 'beam', where = 'end'
    force = 0.0, 0.0, {m['P']!r}
    frame = 'spatial'
    time_function = 'constant'
/
"""


def run_rodsolve(args, m, material, n, dt, repeat):
    """Tip samples at t_k and the median time-loop time of rodsolve's summary."""
    os.makedirs(args.workdir, exist_ok=True)
    name = f"{material}_n{n}_dt{dt:.3g}"
    scene = os.path.join(args.workdir, name + ".nml")
    h5 = os.path.join(args.workdir, name + ".h5")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(scene_text(m, material, n, dt, h5))
    walls = []
    for _ in range(repeat):
        result = subprocess.run([args.rodsolve, scene], capture_output=True, text=True)
        if result.returncode != 0:
            sys.stderr.write(result.stdout + result.stderr)
            raise SystemExit(f"{name}: rodsolve failed")
        walls.append(float(SUMMARY.search(result.stdout)[1]))
    with h5py.File(h5, "r") as f:
        times = f["/rods/beam/time"][()]
        tips = f["/rods/beam/position"][:, -1, :]
    if len(times) != N_SAMPLES + 1 or abs(times[-1] - m["t_end"]) > 1e-9 * m["t_end"]:
        raise SystemExit(f"{name}: unexpected output times {times[:3]} ... {times[-1]}")
    return {"code": "rodsolve", "n": n, "dt": dt, "steps": round(m["t_end"] / dt),
            "wall": statistics.median(walls), "tip": tips}


def errors(tip, ref):
    """(err_u, err_x): max over t_k of |tip - ref| over max |ref - ref(0)|, over max |ref|."""
    dist = np.max(np.linalg.norm(tip - ref, axis=1))
    return (dist / np.max(np.linalg.norm(ref - ref[0], axis=1)),
            dist / np.max(np.linalg.norm(ref, axis=1)))


def bench(args, material):
    m = problem(material)
    print(f"\n== {material}: E = {m['E']:g}, nu = {m['nu']}, rho = {m['rho']:g}, "
          f"EI = {m['EI']:.5g} N m^2, P = {m['P']:.5g} N, T1 = {m['T1']:.4g} s, "
          f"t_end = {m['t_end']:g} s, samples every {m['grid_dt']:.4g} s", flush=True)
    g = m["grid_dt"]
    ref_n = args.ref_elements
    levels = [(4, g), (8, g / 2), (16, g / 4)] + ([] if args.quick else [(32, g / 8)])
    ref = run_rodsolve(args, m, material, ref_n, g / args.ref_refine, 1)
    check = run_rodsolve(args, m, material, ref_n // 2, 2 * g / args.ref_refine, 1)
    amp = np.max(np.linalg.norm(ref["tip"] - ref["tip"][0], axis=1))
    print(f"reference: rodsolve {ref_n} quadratic elements, dt = {ref['dt']:.4g} s; "
          f"max tip displacement {amp:.5g} m; halving both changes it by "
          f"err_u = {errors(check['tip'], ref['tip'])[0]:.2e}", flush=True)
    rows = [run_rodsolve(args, m, material, n, dt, args.repeat) for n, dt in levels]
    pe_levels = [10, 20, 40] + ([] if args.quick else [80, 160])
    rows += [run_pyelastica(m, n, args.safety, args.repeat) for n in pe_levels]
    print(f"{'code':<11}{'n_e':>5}{'dt [s]':>11}{'steps':>9}{'err_u':>10}{'err_x':>10}"
          f"{'wall [s]':>10}")
    for r in rows:
        eu, ex = errors(r["tip"], ref["tip"])
        r["err_u"] = eu
        print(f"{r['code']:<11}{r['n']:>5}{r['dt']:>11.3g}{r['steps']:>9}{eu:>10.2e}{ex:>10.2e}"
              f"{r['wall']:>10.3g}", flush=True)
    # PyElastica converges at first order in 1/n on this problem (README.md): its own
    # Richardson extrapolation 2 tip(2n) - tip(n) estimates its converged answer.
    extrapolated = 2.0 * rows[-1]["tip"] - rows[-2]["tip"]
    print(f"PyElastica Richardson (order 1, n = {rows[-2]['n']}, {rows[-1]['n']}) vs the rodsolve "
          f"reference: err_u = {errors(extrapolated, ref['tip'])[0]:.2e} (the converged "
          f"references must agree before a ratio is quoted)")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--material", choices=["steel", "rubber", "both"], default="both")
    parser.add_argument("--rodsolve", default="build/rodsolve")
    parser.add_argument("--workdir", default="build/peer-work")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--ref-elements", type=int, default=64)
    parser.add_argument("--ref-refine", type=int, default=16,
                        help="reference dt = t_end / (100 ref_refine)")
    parser.add_argument("--safety", type=float, default=0.8,
                        help="PyElastica dt as a fraction of the estimated stability limit")
    parser.add_argument("--quick", action="store_true", help="fewer and coarser runs")
    args = parser.parse_args()
    from importlib.metadata import version
    print(f"PyElastica {version('pyelastica')}, numba {version('numba')}; "
          f"numba JIT warm-up (excluded from the timings): {pyelastica_jit_time():.1f} s",
          flush=True)
    for material in (["steel", "rubber"] if args.material == "both" else [args.material]):
        bench(args, material)


if __name__ == "__main__":
    main()
