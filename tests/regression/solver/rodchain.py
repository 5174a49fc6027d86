"""The rodchain LU package (src/solver/rodchain.c, include/rs_rodchain.h; DESIGN.md §3
"Structure first"), the default LU of the single-rod steppers without native_lu, against the
packages it replaced: the same solution and the same stopping rule.

Each case runs example scenes of input/ (shortened) with rodchain (and -mat_rodchain_view) and
with each reference package, chosen by appending `-pc_factor_mat_solver_type <package>` to the
scene's `&solver petsc_options` (a package the scene itself names there is removed first). Where
rodchain is the default (ph_director, se3_pg, ph_planar's quasistatic PH-EM) its run names no
package, and the reference is MUMPS, the package before it (and PETSc's LU for the heavy top,
whose scene asks for it). Where the formulation says its Jacobian needs no pivoting
(planar_native_lu, se3_strand), PETSc's LU stays the default: its run names no package and must
print nothing of rodchain, and rodchain, named, is compared with it and with MUMPS.

    rodchain.py ph_director              flying spaghetti (80 steps); extensible elastica
                                         (quasistatic: 10 load steps and the endpoint solve)
    rodchain.py ph_director_constrained  Kirchhoff cantilever (inextensible, 80 steps): rodchain
                                         hands such rods to MUMPS (documented fallback)
    rodchain.py ph_planar                planar flying spaghetti (80 steps; PETSc's LU by
                                         default); planar roll-up (quasistatic PH-EM: zero
                                         diagonals, rodchain by default)
    rodchain.py cl_em_planar             the same two scenes with formulation = 'cl_em_planar'
                                         (PETSc's LU by default in both)
    rodchain.py se3_pg                   heavy top (2000 of 64000 steps); cantilever with
                                         follower tip loads (statics, 20 increments)
    rodchain.py se3_strand               strand vibration (300 of 3000 steps); 45-degree bend
                                         (statics by relaxation, 28 steps); PETSc's LU by default

Checks for every scene and reference package:
- the same stopping rule: the Newton iterations of every step (series/newton/iterations, every
  step recorded), the step sizes (series/dt) and the summary's steps, iterations and cut-backs
  are identical, and no step of either run ended at the rounding floor (there the count is
  decided by round-off, whatever the package: see cl_em_planar below);
- the same solution: every record of position, directors (the rotation's columns for se3_pg),
  velocity, director velocity and stress, per field relative to its largest magnitude in the
  reference run, within the bound of BOUNDS;
- rodchain served: its run prints its panels ("rodchain (from the start|end)") and no fallback
  line ("MUMPS factors such Jacobians"), the reference runs print nothing of rodchain;
  for the constrained rod the fallback line is printed (include/rs_chain_lu.h: a constrained
  element's rows make a panel singular from either end of the chain).

Bounds. Both runs start every step from the same predictor and evaluate the same residuals and
Jacobians; their factors differ by round-off only, so each Newton correction differs by about
cond(J) eps of its size, Newton damps that (it converges quadratically), and both stop at the
same test (the scaled residual at most newton_atol). An accepted state thus differs by the
round-off of the last corrections, which later steps carry as any perturbation; a priori the
difference is at most twice what newton_atol leaves, ||J^-1|| newton_atol. Measured, the
differences are far below that: from 1e-17 to 1e-9 of the field's magnitude, the largest for
the stresses that the Kirchhoff rod carries in its multipliers and for the se3 cantilever (its
tangent's smallest stiffness EI / L^3 = 8e-11 lets the residual tolerance 1e-10 leave position
differences of 5e-8 m on 1000 m between any two LU packages). These are the sizes at which two
correct packages disagree: MUMPS with the METIS ordering (-mat_mumps_icntl_7 2) differs from
MUMPS by as much (Kirchhoff stresses 2.6e-9, rodchain 9.1e-10; se3 cantilever positions 7.5e-11,
PETSc's LU 5.5e-11, rodchain 4.6e-11). Each bound is the smallest power of ten at least 10
times the largest measured value over the reference packages (so 10 to 100 times it), and at
least 1e-15 (a few eps); the measured value is in the comment beside it. Velocities of a static
run are zero in every run, and compared absolutely with the bound 0.

cl_em_planar's flying spaghetti runs at newton_atol = 1e-10, not the scene's 1e-11: at 1e-11,
66 to 69 of its 80 steps end above the tolerance at the rounding floor, and the Newton
iterations differ between every pair of packages (rodchain 381, MUMPS 377, PETSc 379); at 3e-11
still (306, 313, 311); at 1e-10 no step reaches the floor and all three take 300.
"""
import os
import re
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

VIEW_LINE = re.compile(r"^rodchain \(from the (start|end)\): (\d+) panels", flags=re.M)
FALLBACK = "MUMPS factors such Jacobians"
# "  <rod>: <steps> steps, <its> Newton iterations, <cuts> cut-backs; time loop <s> s, ..." and
# "  <rod>: <n> steps ended above newton_atol at the rounding floor ..." (src/solver/rod_run.F90)
SUMMARY = re.compile(r"^\s+(\S+): (\d+) steps, (\d+) Newton iterations, (\d+) cut-backs; "
                     r"time loop (\S+) s", flags=re.M)
FLOOR = re.compile(r"^\s+(\S+): (\d+) steps ended above newton_atol at the rounding floor",
                   flags=re.M)

# Per scene and field: the bound on max over records |rodchain - reference| / max |reference|,
# and (comment) the largest measured value over the reference packages.
BOUNDS = {
    "flying_spaghetti": {"position": 1e-14,             # 8.2e-16
                         "directors": 1e-13,            # 4.5e-15
                         "velocity": 1e-12,             # 4.2e-14
                         "director_velocity": 1e-12,    # 3.7e-14
                         "stress": 1e-11},              # 2.0e-13
    "elastica_extensible": {"position": 1e-13,          # 1.1e-15
                            "directors": 1e-13,         # 2.4e-15
                            "velocity": 1e-12,          # 4.7e-14
                            "director_velocity": 1e-12,  # 4.3e-14
                            "stress": 1e-13},           # 2.0e-15
    "kirchhoff_cantilever": {"position": 1e-14,         # 3.3e-16
                             "directors": 1e-13,        # 2.5e-15
                             "velocity": 1e-11,         # 9.0e-13
                             "director_velocity": 1e-10,  # 2.9e-12
                             "stress": 1e-8},           # 9.1e-10 (MUMPS with METIS: 2.6e-9)
    "ph_planar_flying_spaghetti": {"position": 1e-13,        # 7.4e-15
                                   "directors": 1e-12,       # 3.6e-14
                                   "velocity": 1e-12,        # 2.5e-14
                                   "director_velocity": 1e-12,  # 2.8e-14
                                   "stress": 1e-12},         # 9.6e-14
    "ph_planar_rollup": {"position": 1e-13,             # 9.4e-15
                         "directors": 1e-12,            # 3.8e-14
                         "velocity": 0.0,               # zero throughout (statics)
                         "director_velocity": 0.0,      # zero throughout
                         "stress": 1e-12},              # 1.2e-14
    "cl_em_planar_flying_spaghetti": {"position": 1e-13,        # 9.7e-15
                                      "directors": 1e-12,       # 1.5e-14
                                      "velocity": 1e-11,        # 3.2e-13
                                      "director_velocity": 1e-12,  # 5.4e-14
                                      "stress": 1e-10},         # 4.7e-12
    "cl_em_planar_rollup": {"position": 1e-13,          # 9.6e-15
                            "directors": 1e-12,         # 4.0e-14
                            "velocity": 0.0,            # zero throughout (statics)
                            "director_velocity": 0.0,   # zero throughout
                            "stress": 1e-11},           # 3.4e-13
    "se3_heavy_top": {"position": 1e-12,                # 5.8e-14
                      "directors": 1e-10,               # 7.9e-12
                      "velocity": 1e-9},                # 1.1e-11
    "se3_cantilever": {"position": 1e-9,                # 4.6e-11 (PETSc's LU 5.5e-11)
                       "directors": 1e-9,               # 8.3e-11
                       "velocity": 0.0,                 # zero throughout (statics)
                       "director_velocity": 0.0,        # zero throughout
                       "stress": 1e-8},                 # 1.3e-10
    "strand_vibration": {"position": 1e-15,             # 1.4e-17
                         "directors": 1e-15,            # 2.1e-17
                         "velocity": 1e-13,             # 1.8e-15
                         "director_velocity": 1e-12,    # 1.5e-14
                         "stress": 1e-13},              # 1.4e-15
    "bend45_strand": {"position": 1e-10,                # 2.9e-12
                      "directors": 1e-10,               # 7.2e-12
                      "velocity": 1e-10,                # 4.7e-12
                      "director_velocity": 1e-10,       # 7.1e-12
                      "stress": 1e-10},                 # 5.6e-12
}


def petsc_options(text):
    """The scene's `&solver petsc_options` string ('' if none)."""
    solver = re.search(r"^&solver\b.*?^/", text, flags=re.M | re.S)
    if solver is None:
        return ""
    value = re.search(r"\bpetsc_options\s*=\s*'([^']*)'", solver.group(0))
    return value.group(1) if value else ""


def with_package(text, package):
    """The scene with the LU package `package` in `&solver petsc_options` (None: the one the
    stepper chooses): the scene's own choice of package is removed, its other options stay
    (rodchain takes no ordering, so an ordering option leaves it unchanged)."""
    if re.search(r"^&solver\b", text, flags=re.M) is None:
        text = re.sub(r"^&output\b", "&solver\n/\n&output", text, count=1, flags=re.M)
    options = re.sub(r"-pc_factor_mat_solver_type\s+\S+", "", petsc_options(text))
    if package:
        options += f" -pc_factor_mat_solver_type {package}"
    return rs.set_variable(text, "solver", "petsc_options", f"'{' '.join(options.split())}'")


def newton_atol(text):
    value = re.search(r"^\s*newton_atol\s*=\s*(\S+)", text, flags=re.M)
    return value.group(1) if value else "none (one linear solve per step)"


class Result:
    """One run of a one-rod scene: what it printed, its summary line and the rod's datasets."""

    def __init__(self, args, text, name, rod, extra=()):
        started = time.monotonic()
        path, self.log = rs.run(args, text, name, extra=extra, want_log=True)
        self.seconds = time.monotonic() - started
        self.summary, self.time_loop = None, float("nan")
        for m in SUMMARY.finditer(self.log):
            if m.group(1) == rod:
                self.summary = tuple(int(m.group(i)) for i in (2, 3, 4))
                self.time_loop = float(m.group(5))
        self.floor = sum(int(m.group(2)) for m in FLOOR.finditer(self.log) if m.group(1) == rod)
        self.fields = rs.rod(path, rod)


def compare(args, checks, label, text, rod, references, fallback=False, default="rodchain"):
    """Run the one-rod scene `text` with rodchain and with each package of `references`; check
    which package served, the stopping rule and the states (the module docstring). `default`:
    the package the stepper chooses for this rod; the run with it names no package."""
    text = rs.set_variable(text, "output", "stride", "1")
    text = rs.set_variable(text, "output", "xdmf", ".false.")

    def scene_with(package):
        return with_package(text, None if package == default else package)

    chain = Result(args, scene_with("rodchain"), f"{label}_rodchain", rod,
                   extra=("-mat_rodchain_view",))
    views = VIEW_LINE.findall(chain.log)
    print(f"info: {label}: newton_atol {newton_atol(text)}; default package {default}; rodchain: "
          f"{chain.summary} (steps, Newton iterations, cut-backs), time loop "
          f"{chain.time_loop:.3g} s, run {chain.seconds:.2f} s")
    for line in chain.log.splitlines():
        if line.startswith("rodchain"):
            print(f"info: {label}: rodchain printed: {line}")
    if fallback:
        checks.check(f"{label}: rodchain's fallback line is missing",
                     float(FALLBACK not in chain.log), 0.0)
    else:
        checks.check(f"{label}: rodchain's panels line is missing", float(len(views) != 1), 0.0)
        checks.check(f"{label}: rodchain's fallback line is printed", float(FALLBACK in chain.log),
                     0.0)
    checks.check(f"{label}: rodchain's steps at the rounding floor", float(chain.floor), 0.0)
    bounds = BOUNDS[label]
    a = chain.fields
    checks.check(f"{label}: fields written without a bound here, or bounded but not written",
                 float(len(set(bounds) ^ {f for f in a if f in FIELDS})), 0.0)
    for package in references:
        reference = Result(args, scene_with(package), f"{label}_{package}", rod)
        b = reference.fields
        print(f"info: {label}: {package}{' (the default)' if package == default else ''}: "
              f"{reference.summary}, time loop {reference.time_loop:.3g} s, run "
              f"{reference.seconds:.2f} s")
        checks.check(f"{label}, {package}: lines of the run about rodchain",
                     float(len(re.findall(r"^rodchain", reference.log, flags=re.M))), 0.0)
        checks.check(f"{label}, {package}: steps at the rounding floor", float(reference.floor),
                     0.0)
        checks.check(f"{label}, {package}: summary (steps, Newton iterations, cut-backs) differs",
                     float(chain.summary is None or chain.summary != reference.summary), 0.0)
        its_a, its_b = a["series/newton/iterations"], b["series/newton/iterations"]
        if its_a.shape != its_b.shape:
            checks.check(f"{label}, {package}: records {its_a.shape} and {its_b.shape} differ",
                         np.inf, 0.0)
            continue
        checks.check(f"{label}, {package}: steps with other Newton iterations",
                     float(np.count_nonzero(its_a != its_b)), 0.0)
        checks.check(f"{label}, {package}: steps with another dt",
                     float(np.count_nonzero(a["series/dt"] != b["series/dt"])), 0.0)
        for field, bound in bounds.items():
            scale = np.max(np.abs(b[field]))
            difference = np.max(np.abs(a[field] - b[field]))
            last = np.max(np.abs(a[field][-1] - b[field][-1]))
            # A field that is zero throughout (velocities in statics) is compared absolutely.
            unit = scale if scale > 0 else 1.0
            print(f"info: {label}, {package}: {field}: max|{field}| {scale:.3e}, max|rodchain - "
                  f"{package}| {difference:.3e} (last record {last:.3e})")
            checks.check(f"{label}, {package}: max over records |{field} rodchain - {package}| / "
                         f"max|{field}|", difference / unit, bound)


FIELDS = ("position", "directors", "velocity", "director_velocity", "stress")


def scene(args, name, changes=()):
    text = rs.read_example(args.source, name)
    for group, variable, value in changes:
        text = rs.set_variable(text, group, variable, value)
    return text


def ph_director(args, checks):
    # The loaded phase (to t = 5) and 3 s of free flight.
    compare(args, checks, "flying_spaghetti",
            scene(args, "flying_spaghetti.nml", [("time", "t_end", "8.0")]), "spaghetti",
            ["mumps"])
    # The whole scene: ten midpoint load steps, then the endpoint solve (DESIGN.md §3), whose
    # Jacobian has no mass: the chain's panels must not cut the free end's element apart.
    compare(args, checks, "elastica_extensible", scene(args, "elastica_extensible.nml"),
            "cantilever", ["mumps"])


def ph_director_constrained(args, checks):
    # The pulse (to t = 0.05) and 0.03 s of free vibration.
    compare(args, checks, "kirchhoff_cantilever",
            scene(args, "kirchhoff_cantilever.nml", [("time", "t_end", "0.08")]), "cantilever",
            ["mumps"], fallback=True)


def planar(args, checks, formulation):
    changes = [("rod", "formulation", f"'{formulation}'")]
    # Above cl_em_planar's rounding floor (the module docstring).
    if formulation == "cl_em_planar":
        changes.append(("solver", "newton_atol", "1e-10"))
    compare(args, checks, f"{formulation}_flying_spaghetti",
            scene(args, "planar_flying_spaghetti.nml", changes + [("time", "t_end", "8.0")]),
            "spaghetti", ["petsc", "mumps"], default="petsc")
    # PH-EM's uncondensed quasistatic Jacobian has zero (x, y) diagonals, so MUMPS served it
    # before and rodchain now (planar_native_lu); cl_em_planar's has none (PETSc's LU), and it
    # needs 1-point shear here (with 2 points it locks, tests/regression/ph_planar/rollup.py).
    if formulation == "ph_planar":
        compare(args, checks, "ph_planar_rollup", scene(args, "planar_rollup.nml"), "beam",
                ["mumps"])
    else:
        compare(args, checks, "cl_em_planar_rollup",
                scene(args, "planar_rollup.nml", [("rod", "formulation", "'cl_em_planar'"),
                                                  ("rod", "n_gauss", "1")]),
                "beam", ["petsc", "mumps"], default="petsc")


def se3_pg(args, checks):
    # 2000 of the scene's 64000 steps (1/32 of the precession, 1.6 turns of the spin); the
    # scene asks for PETSc's LU, which is one of the references.
    top = scene(args, "se3_heavy_top.nml", [
        ("time", "t_end", repr(2000 * 3.1439871308261206e-05)),
        ("output", "fields", "'position,directors,velocity'"), ("output", "flush_every", "1000")])
    compare(args, checks, "se3_heavy_top", top, "top", ["mumps", "petsc"])
    compare(args, checks, "se3_cantilever", scene(args, "se3_cantilever.nml"), "cantilever",
            ["mumps"])


def se3_strand(args, checks):
    # 300 of the scene's 3000 steps (1.5 periods).
    compare(args, checks, "strand_vibration",
            scene(args, "strand_vibration.nml",
                  [("time", "t_end", repr(300 * 5.925872307404123e-4))]),
            "tube", ["petsc", "mumps"], default="petsc")
    compare(args, checks, "bend45_strand", scene(args, "bend45_strand.nml"), "bend",
            ["petsc", "mumps"], default="petsc")


CASES = {"ph_director": ph_director, "ph_director_constrained": ph_director_constrained,
         "ph_planar": lambda args, checks: planar(args, checks, "ph_planar"),
         "cl_em_planar": lambda args, checks: planar(args, checks, "cl_em_planar"),
         "se3_pg": se3_pg, "se3_strand": se3_strand}


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=list(CASES))
    args = parser.parse_args()
    checks = rs.Checks()
    CASES[args.case](args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
