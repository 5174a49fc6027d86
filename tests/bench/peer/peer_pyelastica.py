"""PyElastica side of tests/bench/peer/peer_bench.py. Runs in the benchmark's virtual environment
(pyelastica, h5py) as `python peer_pyelastica.py JOB.json OUT.json`; the job names the problem
(material, section, boundary condition, tip force pulse, end time) and what to do:

- `warmup`: time the first step of a tiny rod of the same kind (numba JIT compilation, or loading
  the compiled kernels from numba's on-disk cache);
- `sweep`: for each (n, steps per sample) run the problem `repeat` times; tips at the sample
  times and the wall time of the stepping loop of each run (building the system and the JIT
  warm-up, done beforehand on a tiny rod, are excluded);
- `stability`: for each n, the largest step that stays bounded for a fixed number of steps,
  by bisection between a stable and an unstable step.

The problem is the one of peer_bench.py: a straight rod along e1 from the origin, directors
d1 = e2, d3 = e1, PyElastica's `straight_rod` with `shear_modulus` given, clamped at s = 0 by
`OneEndFixedBC` (position of node 0 and directors of element 0) or free, and a spatial force
F P(t) at the last node with P(t) = (1 - cos(2 pi t / t_pulse)) / 2 for t < t_pulse, else 0.
"""
import json
import math
import sys
import time

import elastica as ea
import numpy as np


class TipPulse(ea.NoForces):
    """Force `force` (1 - cos(2 pi t / t_pulse)) / 2 on the last node for t < t_pulse (the same
    time function as rodsolve's `time_function = 'pulse'` with t_on = 0, t_off = t_pulse)."""

    def __init__(self, force, t_pulse):
        super().__init__()
        self.force = np.asarray(force, dtype=np.float64)
        self.t_pulse = float(t_pulse)

    def apply_forces(self, system, time=np.float64(0.0)):
        t = float(time)
        if t < self.t_pulse:
            system.external_forces[:, -1] += self.force * (
                0.5 * (1.0 - math.cos(2.0 * math.pi * t / self.t_pulse)))


class Sim(ea.BaseSystemCollection, ea.Constraints, ea.Forcing):
    pass


def build(p, n):
    """The simulator and the rod of problem `p` with n elements."""
    sim = Sim()
    rod = ea.CosseratRod.straight_rod(
        n, np.zeros(3), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]), p["L"],
        p["radius"], p["rho"], youngs_modulus=p["E"], shear_modulus=p["G"])
    sim.append(rod)
    if p["bc"] == "clamped":
        sim.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,),
                                 constrained_director_idx=(0,))
    sim.add_forcing_to(rod).using(TipPulse, np.array([0.0, 0.0, p["P"]]), p["t_pulse"])
    sim.finalize()
    return sim, rod


def warmup(p):
    """Seconds for building a 4-element rod and its first step."""
    start = time.perf_counter()
    sim, _ = build(p, 4)
    ea.PositionVerlet().step(sim, np.float64(0.0), np.float64(1e-9))
    return time.perf_counter() - start


def run(p, n, per_sample):
    """One run: tips at the n_samples + 1 sample times and the stepping loop's wall time."""
    sim, rod = build(p, n)
    stepper = ea.PositionVerlet()
    dt = np.float64(p["t_end"] / p["n_samples"] / per_sample)
    t = np.float64(0.0)
    tips = [rod.position_collection[:, -1].copy()]
    start = time.perf_counter()
    for _ in range(p["n_samples"]):
        for _ in range(per_sample):
            t = stepper.step(sim, t, dt)
        tips.append(rod.position_collection[:, -1].copy())
    wall = time.perf_counter() - start
    return np.array(tips), wall


def bounded(p, n, dt, steps):
    """True if `steps` steps of dt leave every node finite and within 10 L of the origin. The
    rod starts with random velocities of 1e-9 m/s and angular velocities of 1e-7 rad/s (fixed
    seed): from the exactly straight state an unstable mode would otherwise only be fed by the
    slowly growing load and round-off, and take tens of thousands of steps to show."""
    sim, rod = build(p, n)
    rng = np.random.default_rng(12345)
    rod.velocity_collection[...] += 1e-9 * rng.standard_normal(rod.velocity_collection.shape)
    rod.omega_collection[...] += 1e-7 * rng.standard_normal(rod.omega_collection.shape)
    stepper = ea.PositionVerlet()
    t = np.float64(0.0)
    dt = np.float64(dt)
    for k in range(steps):
        t = stepper.step(sim, t, dt)
        if k % 100 == 99 or k == steps - 1:
            x = rod.position_collection
            if not np.all(np.isfinite(x)) or np.max(np.abs(x)) > 10.0 * p["L"]:
                return False
    return True


def stable_limit(p, n, guess, steps, rtol):
    """(largest stable, smallest unstable) step bracketing the limit within rtol, starting
    from `guess`; the bracket is widened by factors of 2 until it holds."""
    lo, hi = 0.5 * guess, 2.0 * guess
    while not bounded(p, n, lo, steps):
        hi, lo = lo, 0.5 * lo
    while bounded(p, n, hi, steps):
        lo, hi = hi, 2.0 * hi
    while hi / lo > 1.0 + rtol:
        mid = math.sqrt(lo * hi)
        if bounded(p, n, mid, steps):
            lo = mid
        else:
            hi = mid
    return lo, hi


def main():
    with open(sys.argv[1], encoding="utf-8") as f:
        job = json.load(f)
    p = job["problem"]
    out = {"warmup": warmup(p)}
    if job["mode"] == "sweep":
        out["runs"] = []
        for n, per_sample in job["runs"]:
            walls = []
            for _ in range(job["repeat"]):
                tips, wall = run(p, n, per_sample)
                walls.append(wall)
            out["runs"].append({"n": n, "per_sample": per_sample, "walls": walls,
                                "tip": tips.tolist()})
            print(f"  PyElastica n = {n}: {min(walls):.3g} s", flush=True)
    elif job["mode"] == "stability":
        out["limits"] = []
        for n, guess in job["runs"]:
            start = time.perf_counter()
            lo, hi = stable_limit(p, n, guess, job["steps"], job["rtol"])
            out["limits"].append({"n": n, "stable": lo, "unstable": hi,
                                  "seconds": time.perf_counter() - start})
            print(f"  PyElastica n = {n}: stable {lo:.4g} s, unstable {hi:.4g} s", flush=True)
    with open(sys.argv[2], "w", encoding="utf-8") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
