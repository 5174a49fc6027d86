"""Benchmark: the cost of a time error at order 2 and at order 4 (&time order; issue 25).

On a fixed mesh, each problem runs over a ladder of steps at order 2 (the midpoint rule) and at
order 4 (Suzuki's composition of five midpoint steps). The error is the tip position at the end
time against a reference on the same mesh (order 4 with a quarter of the finest step), relative
to the rod's length: the time error alone, the mesh's error is the same in every run. The
reference's own error is estimated by its difference to the run with twice its step. The work is
rodsolve's time loop (the summary line, output excluded), the median of `--repeat` runs, the
runs of a problem alternating between the orders.

The cost of an error level is that of the cheapest run of each order whose error is at most the
level (the steps halve along a ladder, so either cost may be overstated by up to 2 times; the
errors need not fall monotonically where the steps leave stiff modes unresolved, so no
interpolation); the table gives both and their ratio (issue 25's target: order 4 at least 5
times cheaper at 1e-6).

Adaptive steps (&time adaptive, order 2, atol = rtol / 100 m) run on the spaghetti for rtol
1e-3 ... 1e-7; their cost is set against that of a fixed step reaching the same error, read off
the order-2 ladder by log-log interpolation between the two runs that bracket it (issue 25's
target: at most 1.5 times).

Problems: the steel cantilever of the peer bench (tests/bench/peer/peer_bench.py, 8 quadratic
elements, the tip pulse and two periods of the first mode) and the flying spaghetti
(input/flying_spaghetti.nml, its mesh, to the end of the load at t = 5).

    /usr/bin/python3 tests/bench/time_order_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench_time_order [--repeat 3] [--write]
"""
import math
import os
import re
import statistics
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "peer"))
from bench_common import measured_on, rs, run_case, write_generated  # noqa: E402
import peer_bench  # noqa: E402

SCRIPT = "time_order_bench.py"
TARGETS = (1e-4, 1e-5, 1e-6, 1e-7)


def steel_cantilever():
    p = peer_bench.problem("cantilever_steel")
    text = peer_bench.scene_text(p, 8, 100)
    steps = [p["t_end"] / n for n in (100, 200, 400, 800, 1600, 3200)]
    return {"key": "steel_cantilever", "title": "steel cantilever of the peer bench (8 elements, "
            f"t_end = {p['t_end']:g} s)", "text": text, "rod": "beam", "length": p["L"],
            "t_end": p["t_end"], "steps": {2: steps, 4: steps[:5]}}


def spaghetti():
    text = rs.read_example(os.path.join(HERE, "..", ".."), "flying_spaghetti.nml")
    steps = [5.0 / n for n in (50, 100, 200, 400, 800, 1600, 3200, 6400, 12800)]
    return {"key": "spaghetti", "title": "flying spaghetti (10 elements, t_end = 5)",
            "text": text, "rod": "spaghetti", "length": 10.0, "t_end": 5.0,
            "steps": {2: steps, 4: steps[:5]}, "adaptive": (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)}


def scene(problem, order, h):
    text = rs.set_variable(problem["text"], "time", "t_end", repr(problem["t_end"]))
    text = rs.set_variable(text, "time", "dt", repr(h))
    text = rs.set_variable(text, "time", "order", str(order))
    text = rs.set_variable(text, "output", "stride", str(round(problem["t_end"] / h)))
    return rs.set_variable(text, "output", "fields", "'position'")


def adaptive_scene(problem, rtol):
    """The problem with adaptive steps of order 2 at rtol (atol = rtol / 100 m), records at its dt."""
    text = scene(problem, 2, rs.number(problem["text"], "time", "dt"))
    text = rs.set_variable(text, "output", "stride", "1000000")
    for variable, value in (("adaptive", ".true."), ("rtol", repr(rtol)), ("atol", repr(rtol / 100))):
        text = rs.set_variable(text, "time", variable, value)
    return text


def tip(args, problem, order, h, name):
    r = rs.rod(os.path.join(args.workdir, name + ".h5"), problem["rod"])
    if abs(r["time"][-1] - problem["t_end"]) > 1e-9 * problem["t_end"]:
        raise SystemExit(f"{name}: ended at {r['time'][-1]}")
    return r["position"][-1, -1, :]


def measure(args, problem):
    """Errors and median time loops of every (order, h); the reference and its check."""
    finest = problem["steps"][4][-1]
    references = {}
    for label, h in (("reference", finest / 4), ("check", finest / 2)):
        name = f"{problem['key']}_{label}"
        run_case(args, scene(problem, 4, h), name)
        references[label] = tip(args, problem, 4, h, name)
    check = np.linalg.norm(references["check"] - references["reference"]) / problem["length"]
    runs = [(order, h) for order in (2, 4) for h in problem["steps"][order]]
    runs += [("adaptive", rtol) for rtol in problem.get("adaptive", ())]
    times = {run: [] for run in runs}
    results = {}
    for _ in range(args.repeat):
        for order, h in runs:
            name = f"{problem['key']}_o{order}_{h:.6g}"
            text = adaptive_scene(problem, h) if order == "adaptive" else scene(problem, order, h)
            out = run_case(args, text, name)
            times[(order, h)].append(out["per_step"] * out["steps"])
            error = np.linalg.norm(tip(args, problem, order, h, name) - references["reference"])
            accepted = re.search(r"adaptive steps: (\d+) accepted", out["stdout"])
            results[(order, h)] = {"error": error / problem["length"], "iterations": out["iterations"],
                                   "steps": int(accepted[1]) if accepted else out["steps"]}
    for run in runs:
        results[run]["time"] = statistics.median(times[run])
    return results, check


def cost_at(results, order, target):
    """The time loop of the cheapest run of `order` whose error is at most `target` (None if
    none is)."""
    reached = [r["time"] for (o, _), r in results.items() if o == order and r["error"] <= target]
    return min(reached) if reached else None


def interpolated_cost(results, order, target):
    """The time loop of `order`'s fixed steps at error `target`, log-log between the two runs
    of its ladder that bracket it (None outside the ladder)."""
    ladder = sorted(((r["error"], r["time"]) for (o, _), r in results.items() if o == order),
                    reverse=True)
    for (e0, t0), (e1, t1) in zip(ladder, ladder[1:]):
        if e1 <= target <= e0 and e1 < e0:
            return t0 * (t1 / t0) ** (math.log(target / e0) / math.log(e1 / e0))
    return None


def section(problem, results, check):
    lines = [f"**{problem['title']}**: tip error relative to the length against a reference "
             f"on the same mesh (order 4, h/4 of the finest step; its difference to h/2: "
             f"{check:.1e}).", "",
             "| order | h | Newton iterations | time loop (s) | error |", "|---:|---:|---:|---:|---:|"]
    for (order, h), r in sorted((k, v) for k, v in results.items() if k[0] != "adaptive"):
        lines.append(f"| {order} | {h:.4g} | {r['iterations']} | {r['time']:.3g} | {r['error']:.2e} |")
    lines += ["", "| error | order 2 (s) | order 4 (s) | order 2 / order 4 |", "|---:|---:|---:|---:|"]
    for target in TARGETS:
        if target < 10 * check:
            continue
        two, four = cost_at(results, 2, target), cost_at(results, 4, target)
        ratio = f"{two / four:.1f}" if two and four else "-"
        lines.append(f"| {target:.0e} | {two or float('nan'):.3g} | {four or float('nan'):.3g} | "
                     f"{ratio} |")
    adaptive = sorted(((h, r) for (o, h), r in results.items() if o == "adaptive"), reverse=True)
    if adaptive:
        lines += ["", "| adaptive, rtol | steps | time loop (s) | error | fixed steps at that error (s) "
                  "| adaptive / fixed |", "|---:|---:|---:|---:|---:|---:|"]
        for rtol, r in adaptive:
            fixed = interpolated_cost(results, 2, r["error"])
            ratio = f"{r['time'] / fixed:.2f}" if fixed else "-"
            lines.append(f"| {rtol:.0e} | {r['steps']} | {r['time']:.3g} | {r['error']:.2e} | "
                         f"{fixed or float('nan'):.3g} | {ratio} |")
    return "\n".join(lines) + "\n"


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--repeat", type=int, default=3, help="runs per point (median)")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    load = os.getloadavg()[0]
    sections = []
    for problem in (steel_cantilever(), spaghetti()):
        print(f"{problem['key']}:", flush=True)
        results, check = measure(args, problem)
        sections.append(section(problem, results, check))
        print(sections[-1], flush=True)
    block = (f"{measured_on()}; 1 rank; median of {args.repeat} runs; load average (1 min) "
             f"{load:.1f} to {os.getloadavg()[0]:.1f}.\n\n" + "\n".join(sections))
    print(block)
    if args.write:
        write_generated(args.source, SCRIPT, block)


if __name__ == "__main__":
    main()
