"""Benchmark: the planar formulations of seed 001 (issue 6).

Measures, on one rank, rodsolve's own timing of the time loop (output excluded; medians of
`--repeat` runs):

1. the four-bar (input/planar_fourbar.nml, h = 0.02, t_end = 2) and the flying spaghetti
   (input/planar_flying_spaghetti.nml, h = 0.1, t_end = 15) with every planar scheme:
   PH-EM (strains as unknowns and condensed), Stander-Stein with 1 and 2 Gauss points, PH-EMi;
   Newton iterations (linear solves) per step and wall time per step. The four-bar runs at the
   paper's Newton tolerance 1e-5 (Fig. 11; the displacement schemes stall below it, methods
   §4.6), the spaghetti at 1e-9 (the condensed step stalls near 1e-11, docs/performance.md);
2. the same planar scene as ph_planar and as ph_director (the 3D formulation, p = 2; p = 1
   is left out: on this step load its loaded end element stretches to 30 times its length,
   tests/regression/ph_planar/flying_spaghetti.py planar_vs_3d):
   the spaghetti with n_e = 10, 40, 160, h = 0.1, 25 steps (the loading phase), Newton
   tolerance 1e-9: time per step and the planar-over-3D speed ratio;
3. ph_planar's LU package: PETSc's own LU (the default for systems that need no pivoting) against
   MUMPS, on the spaghetti with n_e = 10 to 2560.

With --write the tables replace the GENERATED block of docs/performance.md.

    /usr/bin/python3 tests/bench/ph_planar_bench.py --rodsolve build/rodsolve \\
        --mpiexec mpirun --source . --workdir build/bench_planar [--write]
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import rs, median_case, measured_on, write_generated  # noqa: E402

SCHEMES = [  # label, formulation, n_gauss, em_variant, condense
    ("PH-EM (ph_planar)", "ph_planar", 2, None, False),
    ("PH-EM, strains condensed", "ph_planar", 2, None, True),
    ("cl-EM, 1-point shear (cl_em_planar)", "cl_em_planar", 1, None, False),
    ("cl-EM, 2-point (locks)", "cl_em_planar", 2, None, False),
    ("PH-EMi (em_variant = 'ph_irreducible')", "cl_em_planar", 2, "'ph_irreducible'", False),
]


def set_all_rods(text, variable, value):
    """Set `variable` in every &rod group."""
    parts = re.split(r"(?m)^(?=&rod\b)", text)
    out = [parts[0]]
    for part in parts[1:]:
        out.append(rs.set_variable(part, "rod", variable, value))
    return "".join(out)


def scheme_text(base, formulation, n_gauss, variant, condense, atol):
    text = set_all_rods(base, "formulation", f"'{formulation}'")
    text = set_all_rods(text, "n_gauss", str(n_gauss))
    if variant:
        text = set_all_rods(text, "em_variant", variant)
    text = rs.set_variable(text, "solver", "condense_stresses", ".true." if condense else ".false.")
    return rs.set_variable(text, "solver", "newton_atol", atol)


def schemes_table(args):
    fourbar = rs.read_example(args.source, "planar_fourbar.nml")
    fourbar = rs.set_variable(fourbar, "time", "t_end", "2.0")
    spaghetti = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    lines = ["| scheme | four-bar: Newton solves per step | residual evaluations per step | "
             "ms per step | spaghetti: Newton solves per step | ms per step |",
             "|---|---:|---:|---:|---:|---:|"]
    for k, (label, formulation, n_gauss, variant, condense) in enumerate(SCHEMES):
        a = median_case(args, scheme_text(fourbar, formulation, n_gauss, variant, condense, "1e-5"),
                        f"fourbar_{k}")
        b = median_case(args, scheme_text(spaghetti, formulation, n_gauss, variant, condense,
                                          "1e-9"), f"spaghetti_{k}")
        row = [label, f"{a['iterations'] / a['steps']:.3f}", f"{a['iterations'] / a['steps'] + 1:.3f}",
               f"{a['per_step'] * 1e3:.3f}", f"{b['iterations'] / b['steps']:.3f}",
               f"{b['per_step'] * 1e3:.3f}"]
        if a["cutbacks"] or b["cutbacks"]:
            row[0] += f" ({a['cutbacks']} + {b['cutbacks']} cut-backs)"
        lines.append("| " + " | ".join(row) + " |")
        print(lines[-1], flush=True)
    return "\n".join(lines)


def planar_vs_3d_table(args):
    base = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    base = rs.set_variable(base, "time", "t_end", "2.5")
    base = rs.set_variable(base, "solver", "newton_atol", "1e-9")
    base = rs.set_variable(base, "output", "stride", "25")
    lines = ["| n_e | ph_planar: unknowns | ms per step | Newton iterations | ph_director p = 2: "
             "unknowns | ms per step | Newton iterations | time per step, 3D / planar |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n_e in (10, 40, 160):
        text = rs.set_variable(base, "rod", "n_elements", str(n_e))
        planar = median_case(args, text, f"vs3d_planar_{n_e}")
        cells = [str(n_e), str(planar["unknowns"]), f"{planar['per_step'] * 1e3:.3f}",
                 str(planar["iterations"])]
        three = rs.set_variable(text, "rod", "formulation", "'ph_director'")
        three = rs.set_variable(three, "rod", "degree", "2")
        # d2 = e_z as in the planar run (isotropic section: the choice does not matter).
        three = rs.set_variable(three, "rod", "d1", "0.8, 0.6, 0.0")
        d = median_case(args, three, f"vs3d_director_{n_e}")
        cells += [str(d["unknowns"]), f"{d['per_step'] * 1e3:.3f}", str(d["iterations"]),
                  f"{d['per_step'] / planar['per_step']:.0f}"]
        lines.append("| " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    return "\n".join(lines)


def lu_table(args):
    base = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    base = rs.set_variable(base, "time", "t_end", "1.0")
    base = rs.set_variable(base, "solver", "newton_atol", "1e-9")
    base = rs.set_variable(base, "output", "stride", "10")
    lines = ["| n_e | unknowns | PETSc LU (nested dissection): ms per step | MUMPS: ms per step | "
             "MUMPS / PETSc LU | PETSc LU: ms per step / n_e, relative to n_e = 10 |",
             "|---:|---:|---:|---:|---:|---:|"]
    first = None
    n_e = 10
    while n_e <= args.largest:
        text = rs.set_variable(base, "rod", "n_elements", str(n_e))
        native = median_case(args, text, f"lu_native_{n_e}")
        mumps = median_case(args, rs.set_variable(
            text, "solver", "petsc_options", "'-pc_factor_mat_solver_type mumps'"), f"lu_mumps_{n_e}")
        per = native["per_step"] / n_e
        first = first or per
        lines.append(f"| {n_e} | {native['unknowns']} | {native['per_step'] * 1e3:.3f} | "
                     f"{mumps['per_step'] * 1e3:.3f} | {mumps['per_step'] / native['per_step']:.1f} | "
                     f"{per / first:.2f} |")
        print(lines[-1], flush=True)
        n_e *= 4
    return "\n".join(lines)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (median)")
    parser.add_argument("--largest", type=int, default=2560, help="largest n_e of the LU table")
    parser.add_argument("--write", action="store_true", help="update docs/performance.md")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    block = (f"{measured_on()}; 1 rank; medians of "
             f"{args.repeat} runs of the time loop (output excluded).\n\n"
             "Schemes (four-bar: h = 0.02, t_end = 2, Newton tolerance 1e-5 as in the paper's "
             "Fig. 11; spaghetti: h = 0.1, t_end = 15, Newton tolerance 1e-9):\n\n"
             + schemes_table(args) +
             "\n\nThe same planar scene (flying spaghetti, loading phase: 25 steps of h = 0.1, "
             "Newton tolerance 1e-9) as ph_planar and as ph_director:\n\n"
             + planar_vs_3d_table(args) +
             "\n\nph_planar's LU package (flying spaghetti, 10 steps of h = 0.1, Newton "
             "tolerance 1e-9):\n\n" + lu_table(args) + "\n")
    print(block)
    if args.write:
        write_generated(args.source, "ph_planar_bench.py", block)


if __name__ == "__main__":
    main()
