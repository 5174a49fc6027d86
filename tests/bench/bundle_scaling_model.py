"""The scaling model of a 1,000-wire bundle to 1,000 ranks (issue 23 item 4; docs/performance.md,
"Bundles: a scaling model to 1,000 ranks").

Not a measurement: a prediction from the per-wire and per-pair costs and the communication
volumes measured by tests/bench/bundle_block_bench.py on this machine (the constants below
say where each comes from), and from network figures of a cluster that this 2-core machine
cannot measure (ALLREDUCE_HOP, LATENCY, BANDWIDTH: typical of an InfiniBand HDR cluster).
The time per Newton iteration on P ranks of a bundle of W wires (one lay length each) is

    T = compute + communication + replicated,

- compute: the busiest rank's wires and contact pairs, a w + b p (w = W / P wires, p their
  contact element pairs), times IMBALANCE where a rank holds a few wires (the wires of the
  outer layer have fewer contacts than the inner ones);
- communication: per Krylov iteration the global reductions of GMRES and the product's ghost
  values from the neighbouring ranks, per Newton iteration SNES's reductions and the gathers of
  the neighbouring rods before each evaluation;
- replicated: what every rank does for the whole bundle once per step today (the contact
  search over all pairs, the gather of the whole state after the step), spread over the
  Newton iterations of the step.

    /usr/bin/python3 tests/bench/bundle_scaling_model.py [--source .] [--write]
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import write_generated  # noqa: E402

# Measured (bundle_block_bench.py, 2026-11-26, 1 rank): the time per Newton iteration of the
# strands of 7 to 91 wires is fitted by a W + b pairs within 0.94 to 1.11 (8 strands).
WIRE_SECONDS = 0.97e-3          # a: a wire of one lay length (1182 unknowns)
PAIR_SECONDS = 6.0e-6           # b: a contact element pair
PAIRS_PER_WIRE = 204            # the 91-wire strand: 18,522 pairs (its plan)
KRYLOV_PER_NEWTON = 2.0         # 7 to 91 wires at one lay length (5.0 at 8 lay lengths)
NEWTON_PER_STEP = 3.0
REDUCTIONS_PER_KRYLOV = 2.3     # -log_view, 2 ranks
REDUCTIONS_PER_NEWTON = 10.0    # -log_view, 2 ranks: TSStep's reductions over the iterations
EVALUATIONS_PER_NEWTON = 3.0    # residuals and the Jacobian (SNESFunctionEval, JacobianEval)
SEARCH_SECONDS_PER_PAIR = 96e-9  # contact search per pair and step (the 91-wire strand)
WIRE_DOUBLES = 2 * 1182         # state and unknowns of a wire (the needed-entry gathers)
CONTACT_NODE_DOUBLES = 33 * 3   # a neighbour's positions (the product's ghost values)
NEIGHBOURS = 6                  # a wire's contact neighbours (hexagonal packing)
MEMORY_PER_WIRE = 7.9e6         # bytes, 1 rank (peak RSS 718 MB at 91 wires)
REPLICATED_PER_WIRE = 5.3e6     # bytes every rank holds per wire of the bundle (2 ranks: 608
                                # and 597 MB against 718 MB on 1)
IMBALANCE = 1.1                 # busiest wire / mean wire (assumed: 6 against 4 neighbours)
# A cluster's network (assumed, not measured here).
ALLREDUCE_HOP = 3e-6            # s per doubling of the ranks
LATENCY = 2e-6                  # s per message
BANDWIDTH = 10e9                # bytes per second


def allreduce(ranks):
    return ALLREDUCE_HOP * max(1.0, math.log2(ranks))


def newton_iteration(wires, ranks):
    """(compute, communication, replicated) seconds per Newton iteration."""
    per_rank = wires / ranks
    imbalance = 1.0
    if ranks > 1 and per_rank < 10:
        imbalance += (IMBALANCE - 1.0) * (1 - per_rank / 10)
    compute = (WIRE_SECONDS + PAIR_SECONDS * PAIRS_PER_WIRE) * per_rank * imbalance
    communication = 0.0
    if ranks > 1:
        messages = min(NEIGHBOURS, ranks - 1)
        krylov = (REDUCTIONS_PER_KRYLOV * allreduce(ranks) + messages * LATENCY +
                  messages * CONTACT_NODE_DOUBLES * 8 / BANDWIDTH)
        gathers = EVALUATIONS_PER_NEWTON * (messages * LATENCY + messages * WIRE_DOUBLES * 8 /
                                            BANDWIDTH)
        communication = (KRYLOV_PER_NEWTON * krylov + REDUCTIONS_PER_NEWTON * allreduce(ranks) +
                         gathers)
    search = SEARCH_SECONDS_PER_PAIR * PAIRS_PER_WIRE * wires
    gather_all = wires * WIRE_DOUBLES / 2 * 8 / BANDWIDTH + allreduce(ranks) if ranks > 1 else 0.0
    replicated = (search + gather_all) / NEWTON_PER_STEP
    return compute, communication, replicated


def ideal(wires, ranks):
    return (WIRE_SECONDS + PAIR_SECONDS * PAIRS_PER_WIRE) * wires / ranks


def table():
    rows = ["Model (not measured): " + __doc__.split("\n\n")[1].replace("\n", " ").strip(), "",
            "| scaling | wires | ranks | compute (ms) | communication (ms) | replicated today "
            "(ms) | per Newton it. (ms) | efficiency | efficiency without the replicated part "
            "| memory per rank today | without replication |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    cases = [("strong", 1000, p) for p in (1, 2, 10, 100, 1000)] + \
            [("weak", p, p) for p in (2, 10, 100, 1000)]
    for kind, wires, ranks in cases:
        compute, communication, replicated = newton_iteration(wires, ranks)
        total = compute + communication + replicated
        base = ideal(wires, ranks)
        memory = (MEMORY_PER_WIRE - REPLICATED_PER_WIRE) * wires / ranks + \
            REPLICATED_PER_WIRE * wires
        lean = MEMORY_PER_WIRE * wires / ranks
        rows.append(f"| {kind} | {wires} | {ranks} | {1e3 * compute:.2f} | "
                    f"{1e3 * communication:.3f} | {1e3 * replicated:.2f} | {1e3 * total:.2f} | "
                    f"{base / total:.2f} | {base / (compute + communication):.2f} | "
                    f"{memory / 1e9:.2f} GB | {lean / 1e9:.3f} GB |")
    return "\n".join(rows) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--source", default=".")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    block = table()
    print(block)
    if args.write:
        write_generated(args.source, "bundle_scaling_model.py", block)


if __name__ == "__main__":
    main()
