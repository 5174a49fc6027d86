"""Benchmark: work against precision for every formulation on its benchmarks (issue 11 item 1).

For each benchmark of the method documents, every formulation that can run it
(docs/user/capabilities.md) runs over a grid of element counts and, for dynamic problems, time
steps. Where they apply (issue 25: dynamics without dissipation; adaptive steps not with
contact, quasistatics, relaxation, se3_strand), variants run the same formulation at order 4
(`&time order = 4`) and with error-controlled steps (`&time adaptive`, a ladder of rtol instead
of a ladder of steps), and a table sets each of their runs against the formulation's order-2
fixed steps at the same error. Each run gives

- an error: the benchmark's quantity (the tip or end point position at the end time, relative
  to the rod's length; for the free vibration the first frequency, relative) against a
  converged reference;
- a work: rodsolve's own time of the time loop (the summary line, output excluded), the median
  of `--repeat` runs on one rank; the runs of a benchmark alternate, round after round.

The reference is either an exact solution (the elastica: shooting with RK4,
tests/regression/ph_director/elastica_reference.py, its last step doubling is the check) or a
run finer than all others together with a check run that is one level coarser in both the mesh
and the time step. Their difference estimates the reference's own error; a run whose error is
less than 10 times that difference is listed but marked and left out of the plots and of the
table of the cheapest runs.

`--quick` runs a few points once, with references one level coarser (half the elements, twice
the step), for development only.

With --write the tables replace the GENERATED block of docs/performance.md and the plots are
written to docs/figures/workprecision_<benchmark>.png (otherwise both stay in the work
directory).

    OPENBLAS_NUM_THREADS=1 /usr/bin/python3 tests/bench/workprecision/workprecision.py \\
        --rodsolve build/rodsolve --mpiexec mpirun --source . --workdir build/bench_wp \\
        [--quick] [--repeat 3] [--only NAME] [--write]
"""
import collections
import math
import os
import re
import statistics
import subprocess
import sys
import time

import h5py
import matplotlib
import numpy as np
import scipy.optimize

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "regression",
                                "ph_director"))
from bench_common import SUMMARY, rs, measured_on, write_generated  # noqa: E402
from ph_planar_bench import set_all_rods  # noqa: E402
import elastica_reference  # noqa: E402

class Variant(collections.namedtuple("Variant",
                                     "formulation elements steps quick edits label tolerances")):
    """A formulation on a benchmark: the formulation, the element counts and time steps of its
    grid (None: the scene's), the `--quick` subsets, extra (group, variable, value) edits of the
    scene (e.g. the Newton tolerance in the formulation's residual norm, or &time order = 4),
    and its name in tables and plots (the formulation's unless given). An adaptive variant
    (`adaptive`) has a ladder of `tolerances` (rtol) instead of a ladder of steps: its one
    `steps` entry is the record interval, which is also the largest step."""
    __slots__ = ()

    def __new__(cls, formulation, elements, steps, quick, edits, label=None, tolerances=None):
        return super().__new__(cls, formulation, elements, steps, quick, edits,
                               label or formulation, tolerances)

    @property
    def adaptive(self):
        return self.tolerances is not None


def adaptive_variant(formulation, elements, interval, tolerances, quick, edits=(), label=None):
    """A variant with error-controlled steps (&time adaptive): element counts times `tolerances`
    (rtol, atol = ATOL_PER_RTOL rtol L), records every `interval`; `quick` = (element counts,
    tolerances)."""
    return Variant(formulation, elements, (interval,), quick, edits,
                   label or f"{formulation}, adaptive", tolerances)


#: A run: the variant (its label), its element count and time step; adaptive runs: the record
#: interval as dt and their rtol.
Point = collections.namedtuple("Point", "formulation n dt rtol", defaults=(None,))


class Benchmark:
    """One benchmark: its scene, how to read its quantity and how to get its reference."""

    def __init__(self, key, title, scene, rod, length, variants, reference=None, check=None,
                 t_end=None, edits=(), quantity="tip", what="tip position at the end time"):
        self.key, self.title, self.scene, self.rod = key, title, scene, rod
        self.length, self.variants, self.t_end, self.edits = length, variants, t_end, edits
        self.reference, self.check = reference, check
        self.quantity, self.what = quantity, what

    def variant(self, formulation):
        return next(v for v in self.variants if v.label == formulation)


# Newton tolerances: ph_director's residual is scaled (methods/ph_director_3d.md §5.6), the
# others are raw 2-norms of forces; se3_pg cannot reach 1e-11 on the spaghetti (its first step
# stagnates), on the stiff four-bar PH-EM stagnates below 1e-8 at n_e = 160 and cl-EM below
# 1e-5 (docs/performance.md); se3_pg keeps the bend's 1e-6 N (600 N loads, E = 1e7).
# cl_em_planar runs with its reduced (1-point) axial and shear quadrature (its default; the full
# rule locks, docs/theory/ph_planar.md).
CL_EM = (("rod", "n_gauss", "1"),)
PG_SPAGHETTI = (("solver", "newton_atol", "1e-9"),)
PLANAR_SPAGHETTI = (("solver", "newton_atol", "1e-8"),)
# ph_director and se3_pg from a planar scene: d2 = e_z as in the planar run.
IN_PLANE = (("rod", "d1", "0.8, 0.6, 0.0"),)
SPAGHETTI_STEPS = (0.1, 0.05, 0.025, 0.0125)
# Order 4 (&time order = 4, Suzuki's composition of five midpoint steps): its time error falls
# as h^4 once the steps resolve the mesh's stiffest modes (tests/regression/solver/time_order.py),
# so it reaches with a coarse step what order 2 reaches with a fine one.
ORDER_4 = (("time", "order", "4"),)
# Adaptive steps (&time adaptive, order 2): a ladder of rtol instead of a ladder of steps, on
# the meshes where the step's error shows; atol = ATOL_PER_RTOL rtol L, so that rtol decides
# for every node but those within a hundredth of the rod's length of the origin. The record
# interval (the largest step) is at least the coarsest fixed step and a divisor of the loads'
# kinks (the spaghetti's hat peaks at 2.5 and ends at 5, the cantilever's pulse ends at 0.05).
ATOL_PER_RTOL = 0.01
TOLERANCES = (1e-2, 1e-3, 1e-4, 1e-5)
FOURBAR_STEPS = (0.04, 0.02, 0.01, 0.005, 0.0025)
FOURBAR_PH = (("solver", "newton_atol", "1e-8"),)
FOURBAR_CL = CL_EM + (("solver", "newton_atol", "1e-5"),)
VIBRATION_NEWTON = (("solver", "newton_atol", "1e-10"),)
# The Euler-Bernoulli period of input/strand_vibration.nml, whose dt is a 200th of it.
VIBRATION_PERIOD = 200 * 5.925872307404123e-4
VIBRATION_PERIODS = 3


#: The rod's line on its adaptive steps (src/solver/rod_run.F90).
ADAPTIVE_STEPS = re.compile(r"adaptive steps: (\d+) accepted")

# Runs whose time loop is below CHEAP seconds run CHEAP_ROUNDS times as often.
CHEAP, CHEAP_ROUNDS = 0.1, 2


def per_period(counts):
    return tuple(VIBRATION_PERIOD / c for c in counts)


BENCHMARKS = [
    Benchmark(
        "spaghetti_3d", "3D flying spaghetti (seed 000 §6.1), t_end = 5 (end of the load)",
        "flying_spaghetti.nml", "spaghetti", 10.0, t_end=5.0,
        variants=[
            Variant("ph_director", (3, 5, 10), SPAGHETTI_STEPS[:3],
                    ((5,), (0.1, 0.05)), ()),
            Variant("ph_director", (5, 10), SPAGHETTI_STEPS,
                    ((5,), (0.1, 0.05)), ORDER_4, "ph_director, order 4"),
            adaptive_variant("ph_director", (5, 10), 0.5, TOLERANCES, ((5,), (1e-2, 1e-3))),
            Variant("se3_pg", (10, 20, 40), SPAGHETTI_STEPS[:3],
                    ((10, 20), (0.1, 0.05)), PG_SPAGHETTI),
            adaptive_variant("se3_pg", (10, 20), 0.5, TOLERANCES, ((10,), (1e-2, 1e-3)),
                             PG_SPAGHETTI)],
        reference=Point("ph_director", 20, 0.003125), check=Point("ph_director", 10, 0.00625)),
    Benchmark(
        "spaghetti_planar", "planar flying spaghetti (seed 001 §5.1), t_end = 5",
        "planar_flying_spaghetti.nml", "spaghetti", 10.0, t_end=5.0, edits=PLANAR_SPAGHETTI,
        variants=[
            Variant("ph_planar", (5, 10, 20, 40, 80), SPAGHETTI_STEPS,
                    ((10, 20), (0.1, 0.05)), ()),
            Variant("ph_planar", (20, 40, 80), SPAGHETTI_STEPS,
                    ((10, 20), (0.1, 0.05)), ORDER_4, "ph_planar, order 4"),
            adaptive_variant("ph_planar", (40, 80), 0.5, TOLERANCES, ((20,), (1e-2, 1e-3))),
            Variant("cl_em_planar", (5, 10, 20, 40, 80), SPAGHETTI_STEPS,
                    ((10, 20), (0.1, 0.05)), CL_EM),
            adaptive_variant("cl_em_planar", (40, 80), 0.5, TOLERANCES, ((20,), (1e-2, 1e-3)),
                             CL_EM),
            Variant("ph_director", (10, 20, 40), SPAGHETTI_STEPS[:3],
                    ((10,), (0.1,)), IN_PLANE),
            Variant("se3_pg", (10, 20, 40, 80), SPAGHETTI_STEPS[:3],
                    ((10,), (0.1,)), IN_PLANE)],
        reference=Point("ph_planar", 640, 0.00078125), check=Point("ph_planar", 320, 0.0015625)),
    Benchmark(
        "kirchhoff_cantilever", "Kirchhoff cantilever (seed 000 §6.2, inextensible), "
        "t_end = 0.1", "kirchhoff_cantilever.nml", "cantilever", 1.0, t_end=0.1,
        variants=[Variant("ph_director", (4, 8, 16), (2e-3, 1e-3, 5e-4, 2.5e-4),
                          ((4, 8), (2e-3, 1e-3)), ()),
                  Variant("ph_director", (8, 16), (2e-3, 1e-3, 5e-4, 2.5e-4),
                          ((4, 8), (2e-3, 1e-3)), ORDER_4, "ph_director, order 4"),
                  adaptive_variant("ph_director", (8, 16), 0.01, TOLERANCES[1:],
                                   ((8,), (1e-3, 1e-4)))],
        reference=Point("ph_director", 32, 6.25e-5), check=Point("ph_director", 16, 1.25e-4)),
    Benchmark(
        "elastica", "quasistatic elastica (seed 000 §6.3, extensible and shear-deformable)",
        "elastica_extensible.nml", "cantilever", 2 * math.pi, quantity="tip",
        what="tip position at load factor 1",
        variants=[
            Variant("ph_director", (2, 4, 8, 16, 32), (None,),
                    ((4, 8), (None,)), ()),
            Variant("ph_planar", (8, 16, 32, 64, 128), (0.1, 0.05, 0.025),
                    ((8, 16), (0.1,)), ()),
            Variant("cl_em_planar", (8, 16, 32, 64, 128), (0.1, 0.05, 0.025),
                    ((8, 16), (0.1,)), CL_EM),
            Variant("se3_pg", (8, 16, 32, 64, 128, 256), (None,),
                    ((8, 16), (None,)), ()),
            Variant("se3_strand", (8, 16, 32, 64), (None,), ((8, 16), (None,)),
                    (("time", "quasistatic", ".false."), ("time", "relaxation", ".true."),
                     ("time", "t_end", "1000.0"), ("time", "dt", "1.0"),
                     ("rod", "external_damping", "0.1"), ("load", "time_function",
                                                          "'constant'")))]),
    Benchmark(
        "bend45", "45-degree bend (seed 004 §3.2) at 600 N, statics",
        "se3_bend45.nml", "bend", 100 * math.pi / 4, what="tip position at load factor 1",
        variants=[
            Variant("se3_pg", (10, 20, 40, 80, 160, 320), (None,),
                    ((10, 20), (None,)), ()),
            Variant("ph_director", (2, 4, 8, 16, 32), (None,),
                    ((4, 8), (None,)), (("solver", "newton_atol", "1e-9"),)),
            Variant("se3_strand", (10, 20, 40, 80, 160), (None,),
                    ((20, 40), (None,)),
                    (("time", "quasistatic", ".false."), ("time", "relaxation", ".true."),
                     ("time", "t_end", "1000.0"), ("time", "dt", "10.0"),
                     ("rod", "external_damping", "0.1"), ("load", "time_function",
                                                          "'constant'")))],
        reference=Point("ph_director", 128, None), check=Point("ph_director", 64, None)),
    Benchmark(
        "vibration", f"free vibration (seed 004 §3.1, L = 4 m), {VIBRATION_PERIODS} periods",
        "strand_vibration.nml", "tube", 4.0, t_end=VIBRATION_PERIODS * VIBRATION_PERIOD,
        quantity="frequency", what="first frequency, fitted to the tip's motion",
        edits=(("output", "stride", "1"),),
        variants=[
            Variant("se3_strand", (8, 16, 32), per_period((50, 100, 200, 400, 800)),
                    ((8, 16), per_period((50, 100))), ()),
            Variant("ph_director", (2, 4, 8), per_period((25, 50, 100)),
                    ((2, 4), per_period((25,))), VIBRATION_NEWTON),
            Variant("ph_director", (2, 4), per_period((12.5, 25, 50)),
                    ((2,), per_period((25,))), VIBRATION_NEWTON + ORDER_4,
                    "ph_director, order 4"),
            # Records every T/25 for the fit. Below rtol 1e-3 the steps resolve the tube's
            # stiff modes, which the release from the arc excites: 43,000 steps for 3 periods
            # at 1e-4 with 2 elements, at the mesh's error floor.
            adaptive_variant("ph_director", (2, 4), VIBRATION_PERIOD / 25, (1e-1, 1e-2, 1e-3),
                             ((2,), (1e-1, 1e-2)), VIBRATION_NEWTON)],
        reference=Point("ph_director", 16, VIBRATION_PERIOD / 800),
        check=Point("ph_director", 8, VIBRATION_PERIOD / 400)),
    Benchmark(
        "fourbar", "flexible four-bar (seed 001 §5.3), P(1): the middle of the coupler at t = 1",
        "planar_fourbar.nml", "coupler", 1.5, t_end=1.0, quantity="middle",
        what="position of P (the coupler's middle) at t = 1",
        variants=[
            Variant("ph_planar", (10, 20, 40), FOURBAR_STEPS,
                    ((10, 20), (0.02, 0.01)), FOURBAR_PH),
            Variant("ph_planar", (10, 20), FOURBAR_STEPS,
                    ((10,), (0.02, 0.01)), FOURBAR_PH + ORDER_4, "ph_planar, order 4"),
            adaptive_variant("ph_planar", (10, 20), 0.04, TOLERANCES, ((10,), (1e-2, 1e-3)),
                             FOURBAR_PH),
            Variant("cl_em_planar", (10, 20, 40), FOURBAR_STEPS,
                    ((10, 20), (0.02, 0.01)), FOURBAR_CL),
            adaptive_variant("cl_em_planar", (10, 20), 0.04, TOLERANCES, ((10,), (1e-2, 1e-3)),
                             FOURBAR_CL)],
        reference=Point("ph_planar", 160, 0.0003125), check=Point("ph_planar", 80, 0.000625)),
]


def mesh(bench, text, n):
    """Set the element count: n for every rod; the four-bar's coupler and rocker get 3/5 of
    the crank's, as in the paper's (10, 6, 6)."""
    if bench.key != "fourbar":
        return set_all_rods(text, "n_elements", str(n))
    parts = re.split(r"(?m)^(?=&rod\b)", text)
    counts = (n, 3 * n // 5, 3 * n // 5)
    return parts[0] + "".join(rs.set_variable(part, "rod", "n_elements", str(count))
                              for part, count in zip(parts[1:], counts))


def scene_text(args, bench, point):
    """The benchmark's scene as `point`'s formulation, element count and time step."""
    variant = bench.variant(point.formulation)
    text = rs.read_example(args.source, bench.scene)
    text = set_all_rods(text, "formulation", f"'{variant.formulation}'")
    if variant.formulation == "ph_director":
        text = set_all_rods(set_all_rods(text, "degree", "2"), "n_gauss", "2")
    else:
        text = re.sub(r",\s*(degree|n_gauss)\s*=\s*\d+", "", text)
    text = mesh(bench, text, point.n)
    if bench.t_end is not None:
        text = rs.set_variable(text, "time", "t_end", repr(bench.t_end))
    if point.dt is not None:
        text = rs.set_variable(text, "time", "dt", repr(point.dt))
    text = rs.set_variable(text, "output", "stride", "1000000")  # the end state only
    for group, variable, value in bench.edits + variant.edits + adaptive_edits(bench, point):
        text = edit(text, group, variable, value)
    return rs.set_variable(text, "output", "fields", "'position,directors'")


def adaptive_edits(bench, point):
    """The &time edits of an adaptive run (none for a fixed step): its rtol and an atol in
    proportion to it and to the rod's length (docs/user/input.md: about rtol times the rod's
    size; the positions decide, the directors' entries are at most 1)."""
    if point.rtol is None:
        return ()
    return (("time", "adaptive", ".true."), ("time", "rtol", repr(point.rtol)),
            ("time", "atol", repr(ATOL_PER_RTOL * point.rtol * bench.length)))


def edit(text, group, variable, value):
    """Set `variable` in every &rod group, or in the first `&group` (added if missing)."""
    if group == "rod":
        return set_all_rods(text, variable, value)
    if not re.search(r"(?m)^&" + group + r"\b", text):
        text += f"\n&{group}\n/\n"
    return rs.set_variable(text, group, variable, value)


def run_once(args, text, name):
    """Run `text` as `name`.nml on one rank. Returns the summary line's time loop (s), steps
    (adaptive runs: the steps accepted), Newton iterations and cut-backs, or None (and prints
    why) if rodsolve failed."""
    os.makedirs(args.workdir, exist_ok=True)
    path = os.path.join(args.workdir, name + ".nml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(rs.set_variable(text, "output", "path", f"'{path[:-4]}.h5'"))
    result = subprocess.run([args.mpiexec, "--oversubscribe", "-np", "1", args.rodsolve, path],
                            capture_output=True, text=True)
    summary = SUMMARY.search(result.stdout)
    if result.returncode != 0 or summary is None:
        reason = re.search(r"Newton did not converge[^;]*", result.stdout + result.stderr)
        print(f"  {name}: failed ({reason[0] if reason else 'status %d' % result.returncode})")
        return None
    accepted = ADAPTIVE_STEPS.search(result.stdout)
    return {"loop": float(summary[4]), "steps": int(accepted[1] if accepted else summary[1]),
            "iterations": int(summary[2]), "cutbacks": int(summary[3]),
            "output": path[:-4] + ".h5"}


def tip_frequency(time_, tip, rest):
    """First frequency of the tip's motion about its rest position `rest`: the frequency f of
    the damped sinusoid exp(-d t) (a cos 2 pi f t + b sin 2 pi f t) + c fitted by least
    squares to the tip's displacement along its initial one (higher modes are left in the
    residual), started from the peak of the zero-padded spectrum."""
    offset = tip - rest
    signal = offset @ (offset[0] / np.linalg.norm(offset[0]))
    spectrum = np.abs(np.fft.rfft(signal - signal.mean(), 2**16))
    start = np.argmax(spectrum[1:]) + 1
    start /= 2**16 * (time_[1] - time_[0])

    def misfit(x):
        phase, decay = 2 * np.pi * x[0] * time_, np.exp(-x[1] * time_)
        basis = np.stack([decay * np.cos(phase), decay * np.sin(phase), np.ones_like(time_)], 1)
        return basis @ np.linalg.lstsq(basis, signal, rcond=None)[0] - signal
    return scipy.optimize.least_squares(misfit, [start, 0.0], x_scale=[start, 1.0],
                                        xtol=1e-14, ftol=1e-14).x[0]


def read_quantity(bench, path):
    """The benchmark's quantity from a result file: a position (3,) or a frequency."""
    with h5py.File(path, "r") as f:
        rod = f["rods"][bench.rod]
        if bench.quantity == "tip":
            return rod["position"][-1, -1]
        if bench.quantity == "middle":
            positions = rod["position"][-1]
            return positions[(len(positions) - 1) // 2]
        # Released from the prestressed arc, the rod rests straight along the clamp's d3.
        rest = rod["position"][0, 0] + bench.length * rod["directors"][0, 0, 2]
        return tip_frequency(rod["time"][()], rod["position"][:, -1], rest)


def error(bench, value, reference):
    """Relative error: a position against the rod's length, a frequency against itself."""
    if bench.quantity == "frequency":
        return abs(value - reference) / reference
    return float(np.linalg.norm(np.asarray(value) - np.asarray(reference))) / bench.length


def point_name(bench, point):
    dt = "qs" if point.dt is None else f"{point.dt:.6g}"
    rtol = "" if point.rtol is None else f"_rtol{point.rtol:.0e}"
    label = re.sub(r"\W+", "_", point.formulation)
    return f"{bench.key}_{label}_{point.n}_{dt}{rtol}"


def reference(args, bench):
    """The reference value, its check difference (an estimate of its own error, relative as
    the errors) and a sentence on how both were obtained; None if a run failed."""
    if bench.reference is None:
        exact = elastica_reference.solve(ea=5.0, ga=1.0)
        value = np.append(exact["tip"], 0.0)
        check = exact["change"] / bench.length
        return value, check, (
            "Reference: the exact tip of the planar Reissner rod (EA = 5, GA = 1), by shooting "
            "with RK4 (tests/regression/ph_director/elastica_reference.py, "
            f"{exact['steps']} steps, Richardson-extrapolated); check: its last step doubling "
            f"moved the tip by {check:.1e} L.")
    values, points = {}, {}
    for role, point in (("reference", bench.reference), ("check", bench.check)):
        if args.quick:
            point = point._replace(n=point.n // 2, dt=point.dt and 2 * point.dt)
        run = run_once(args, scene_text(args, bench, point), point_name(bench, point) + "_ref")
        if run is None:
            return None
        values[role], points[role] = read_quantity(bench, run["output"]), point
        print(f"  {role} {point}: {values[role]}", flush=True)
    check = error(bench, values["check"], values["reference"])
    return values["reference"], check, (
        f"Reference: {describe(points['reference'])}; check: {describe(points['check'])}, "
        f"whose difference to the reference is {check:.1e}.")


def describe(point):
    steps = "" if point.dt is None else f", h = {point.dt:.6g}"
    return f"{point.formulation} with n_e = {point.n}{steps}"


def grid(bench, quick):
    """The runs of a benchmark: every variant's element counts times its time steps (adaptive
    variants: times its tolerances)."""
    points = []
    for variant in bench.variants:
        elements, ladder = variant.quick if quick else (
            variant.elements, variant.tolerances if variant.adaptive else variant.steps)
        if variant.adaptive:
            points += [Point(variant.label, n, variant.steps[0], rtol)
                       for n in elements for rtol in ladder]
        else:
            points += [Point(variant.label, n, dt) for n in elements for dt in ladder]
    return points


def measure(args, bench):
    """All runs of a benchmark in rounds of every run once: `args.repeat` rounds, and
    `CHEAP_ROUNDS` times as many for runs whose time loop is below `CHEAP` s, whose timing is
    the noisiest. Returns a dict point -> {error, loop (median), steps, iterations, cutbacks};
    failed runs are None. None if the reference could not be computed."""
    if (found := reference(args, bench)) is None:
        return None
    value, check, how = found
    points = grid(bench, args.quick)
    results = {}
    for round_ in range(CHEAP_ROUNDS * args.repeat):
        for point in points:
            if round_ and (results[point] is None or round_ >= args.repeat
                           and results[point]["loops"][0] >= CHEAP):
                continue
            run = run_once(args, scene_text(args, bench, point), point_name(bench, point))
            if round_ == 0:
                results[point] = run and dict(run, loops=[run["loop"]], error=error(
                    bench, read_quantity(bench, run["output"]), value))
            elif run is not None:
                results[point]["loops"].append(run["loop"])
        print(f"  {bench.key}: round {round_ + 1}/{CHEAP_ROUNDS * args.repeat} done", flush=True)
    for result in results.values():
        if result is not None:
            result["loop"] = statistics.median(result["loops"])
    return results, check, how


def valid(result, check):
    """A run counts if it finished and its error is at least 10 times the reference's check."""
    return result is not None and result["error"] >= 10 * check


def cell(result, check, steps=False):
    """'error · time' of a run (`steps`: and its steps), '†' if below 10 times the reference
    check."""
    if result is None:
        return "failed"
    mark = "" if valid(result, check) else " †"
    count = f" · {result['steps']} steps" if steps else ""
    return f"{result['error']:.1e}{mark} · {result['loop']:.3g} s{count}"


def runs_table(bench, results, check, adaptive=False):
    """Error · time loop for every run of the fixed-step variants (`adaptive`: of the adaptive
    ones, with their steps taken): a row per variant and element count, a column per time step
    (per rtol)."""
    variants = [v for v in bench.variants if v.adaptive == adaptive]
    labels = {v.label for v in variants}
    runs = [p for p in results if p.formulation in labels]
    if adaptive:
        columns = sorted({p.rtol for p in runs}, reverse=True)
        head = [f"rtol = {rtol:.0e}" for rtol in columns]
    else:
        columns = sorted({p.dt for p in runs if p.dt is not None}, reverse=True)
        columns += [None] if any(p.dt is None for p in runs) else []
        head = ["the scene's h" if dt is None else f"h = {dt:.4g}" for dt in columns]
    lines = ["| " + " | ".join(["formulation", "n_e"] + head) + " |",
             "|---|---:|" + "---:|" * len(columns)]
    for variant in variants:
        for n in sorted({p.n for p in runs if p.formulation == variant.label}):
            points = [Point(variant.label, n, variant.steps[0], c) if adaptive
                      else Point(variant.label, n, c) for c in columns]
            cells = [cell(results[p], check, adaptive) if p in results else "" for p in points]
            lines.append(f"| {variant.label} | {n} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def cheapest(results, check, target):
    """Per formulation, the fastest valid run with error <= target (formulations without one
    are missing)."""
    reached = [(r["loop"], p) for p, r in results.items()
               if valid(r, check) and r["error"] <= target]
    return {p.formulation: p for _, p in sorted(reached, key=lambda x: x[0], reverse=True)}


def cheapest_table(bench, results, check):
    """For each decade of error the runs reach: the cheapest run of each formulation and the
    ratio of the two cheapest formulations."""
    errors = [r["error"] for r in results.values() if valid(r, check)]
    if not errors:
        return "No run is above 10 times the reference check."
    formulations = [v.label for v in bench.variants]
    lines = ["| error ≤ | " + " | ".join(formulations) + " | cheapest |",
             "|---:|" + "---:|" * len(formulations) + "---|"]
    finest = math.floor(-math.log10(min(errors)))
    for k in range(max(1, min(math.ceil(-math.log10(max(errors))), finest)), finest + 1):
        target = 10.0 ** -k
        best = cheapest(results, check, target)
        cells = ["-" if f not in best else
                 f"{results[best[f]]['loop']:.3g} s ({describe_short(best[f])})"
                 for f in formulations]
        ranked = sorted(best, key=lambda f: results[best[f]]["loop"])
        verdict = ranked[0]
        if len(ranked) > 1:
            ratio = results[best[ranked[1]]]["loop"] / results[best[ranked[0]]]["loop"]
            verdict += f", {ratio:.1f}× faster than {ranked[1]}"
        lines.append(f"| 1e-{k} | " + " | ".join(cells) + f" | {verdict} |")
    return "\n".join(lines)


def describe_short(point):
    if point.rtol is not None:
        return f"n_e {point.n}, rtol {point.rtol:.0e}"
    return f"n_e {point.n}" + ("" if point.dt is None else f", h {point.dt:.4g}")


def cost_at(front, target):
    """The time loop at error `target` on a Pareto front (error ascending, time descending):
    ('interpolated', time) log-log between the two runs that bracket it, ('below', time of the
    cheapest run, already more accurate) or ('unreached', time of the most accurate run)."""
    if target < front[0][0]:
        return "unreached", front[0][1]
    if target >= front[-1][0]:
        return "below", front[-1][1]
    for (e0, t0), (e1, t1) in zip(front, front[1:]):
        if e0 <= target < e1:
            return "interpolated", t0 * (t1 / t0) ** (math.log(target / e0) / math.log(e1 / e0))


def matched_table(bench, results, check):
    """Each order-4 and adaptive variant against its formulation's order-2 fixed steps at the
    same error: for every run on the variant's front, the base's time loop at that error on
    the base's front over all its meshes, and the ratio base / variant (> 1: the variant is
    cheaper). None if the benchmark has no such variant."""
    lines = []
    for variant in [v for v in bench.variants if v.label != v.formulation]:
        base = [(r["error"], r["loop"]) for p, r in results.items()
                if p.formulation == variant.formulation and valid(r, check)]
        own = {(r["error"], r["loop"]): p for p, r in results.items()
               if p.formulation == variant.label and valid(r, check)}
        if not base or not own:
            continue
        front = pareto(base)
        for e, t in reversed(pareto(own)):
            kind, cost = cost_at(front, e)
            ratio = {"interpolated": f"{cost / t:.2f}", "below": f"≤ {cost / t:.2g}",
                     "unreached": f"> {cost / t:.2g} (not reached)"}[kind]
            lines.append(f"| {variant.label} | {describe_short(own[(e, t)])} | {e:.1e} | "
                         f"{t:.3g} s | {results[own[(e, t)]]['steps']} | {cost:.3g} s | "
                         f"{ratio} |")
    if not lines:
        return None
    return "\n".join(["| variant | run | error | time loop | steps | order 2, fixed steps, at "
                      "that error | order 2 / variant |", "|---|---|---:|---:|---:|---:|---:|"]
                     + lines)


def pareto(points):
    """The (error, time) points that no other point beats in both."""
    front = []
    for e, t in sorted(points):
        if not front or t < front[-1][1]:
            front.append((e, t))
    return front


#: Plot styles of a formulation's variants: order 2 fixed steps, order 4, adaptive steps.
STYLES = {"fixed": ("o", "-"), "order 4": ("s", "--"), "adaptive": ("^", ":")}


def kind(variant):
    if variant.adaptive:
        return "adaptive"
    return "order 4" if ORDER_4[0] in variant.edits else "fixed"


def plot(bench, results, check, path):
    """Log-log work against precision: every valid run as a marker, each variant's Pareto front
    as a line; one colour per formulation, the marker and line style tell its variants apart
    (STYLES)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    formulations = list(dict.fromkeys(v.formulation for v in bench.variants))
    for variant in bench.variants:
        points = [(r["error"], r["loop"]) for p, r in results.items()
                  if p.formulation == variant.label and valid(r, check)]
        if not points:
            continue
        marker, line = STYLES[kind(variant)]
        color = f"C{formulations.index(variant.formulation)}"
        e, t = zip(*points)
        ax.loglog(e, t, marker, color=color, alpha=0.45, label=variant.label)
        fe, ft = zip(*pareto(points))
        ax.loglog(fe, ft, line, color=color)
    ax.set_xlabel(f"relative error ({bench.what})")
    ax.set_ylabel("time loop (s), median")
    ax.set_title(bench.title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def describe_variant(results, variant):
    """'label: n_e = ...' and, for an adaptive variant, its tolerances and record interval."""
    counts = sorted({p.n for p in results if p.formulation == variant.label})
    text = f"{variant.label}: n_e = {', '.join(str(n) for n in counts)}"
    if variant.adaptive:
        tolerances = sorted({p.rtol for p in results if p.formulation == variant.label},
                            reverse=True)
        text += (f", rtol = {', '.join(f'{r:.0e}' for r in tolerances)}, records (the largest "
                 f"step) every {variant.steps[0]:.4g}")
    return text


def section(bench, results, check, how):
    """The benchmark's part of the GENERATED block: what was run, the reference, the plot and
    the tables."""
    runs = "; ".join(describe_variant(results, v) for v in bench.variants)
    measure_text = ("relative" if bench.quantity == "frequency"
                    else f"distance to the reference over the length {bench.length:.4g}")
    text = (f"**{bench.title}** (input/{bench.scene}). Error: {bench.what}, {measure_text}. "
            f"Runs: {runs}. {how}\n\n"
            f"![work against precision: {bench.title}](figures/workprecision_{bench.key}.png)\n\n"
            "Cheapest run of each variant per error level (time loop, median):\n\n"
            + cheapest_table(bench, results, check))
    if (matched := matched_table(bench, results, check)) is not None:
        text += ("\n\nOrder 4 and adaptive steps against order 2 at the same error: each run on "
                 "the variant's front, and the time loop of its formulation's order-2 fixed "
                 "steps at that error (log-log between the two runs of their front, over all "
                 "meshes, that bracket it; ≤: their cheapest run is already as accurate; >: "
                 "their most accurate run is not):\n\n" + matched)
    text += ("\n\nAll runs with fixed steps (relative error · time loop; † below 10 times the "
             "reference check, left out of the plot and of the tables above):\n\n"
             + runs_table(bench, results, check))
    if any(v.adaptive for v in bench.variants):
        text += (f"\n\nAll runs with adaptive steps (atol = {ATOL_PER_RTOL:g} rtol L; relative "
                 "error · time loop · steps accepted):\n\n"
                 + runs_table(bench, results, check, adaptive=True))
    return text + "\n"


def load_average():
    return os.getloadavg()[0]


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--repeat", type=int, default=3, help="runs per point (median)")
    parser.add_argument("--quick", action="store_true", help="a few points, for development")
    parser.add_argument("--only", action="append", help="run only this benchmark (repeatable)")
    parser.add_argument("--write", action="store_true",
                        help="update docs/performance.md and docs/figures")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    started, loads = time.perf_counter(), [load_average()]
    figures = (os.path.join(args.source, "docs", "figures") if args.write else args.workdir)
    os.makedirs(figures, exist_ok=True)
    sections = []
    for bench in BENCHMARKS:
        if args.only and bench.key not in args.only:
            continue
        print(f"{bench.key}:", flush=True)
        measured = measure(args, bench)
        loads.append(load_average())
        if measured is None:
            sections.append(f"**{bench.title}**: not measured, a reference run failed.\n")
            continue
        results, check, how = measured
        plot(bench, results, check, os.path.join(figures, f"workprecision_{bench.key}.png"))
        sections.append(section(bench, results, check, how))
    minutes = (time.perf_counter() - started) / 60
    block = (f"{measured_on()}; 1 rank; time loop = rodsolve's own timing (output excluded), "
             f"median of {args.repeat} runs ({CHEAP_ROUNDS * args.repeat} for runs under "
             f"{CHEAP} s), the runs of a benchmark alternating. Load average "
             f"(1 min) {min(loads):.1f} to {max(loads):.1f} on this shared machine; the whole "
             f"benchmark took {minutes:.0f} minutes.\n\n" + "\n".join(sections))
    print(block)
    if args.write:
        write_generated(args.source, "workprecision/workprecision.py", block)


if __name__ == "__main__":
    main()
