#!/usr/bin/env python3
"""The layers of rodsolve as its build declares them (docs/developer/architecture.md).

    architecture.py graph [SOURCE]   print the library graph of src/**/CMakeLists.txt: one line
                                     per target with the rodsolve targets it links, in the order
                                     of the layers, then a Mermaid diagram of the same graph
    architecture.py check [SOURCE]   compare that block with the one in
                                     docs/developer/architecture.md, and check who may call
                                     whom: MPI only in src/parallel (and the parallel HDF5 file
                                     in src/io), HDF5 only in src/io, PETSc and MUMPS only in
                                     src/solver, METIS only in src/parallel; no target links a
                                     layer above its own; exit 1 on a difference

The graph is read from the CMake files (add_library, add_executable, target_link_libraries), so
the document cannot drift from the build without this check failing (test architecture_doc).
"""
import os
import re
import sys

# The layers from the bottom up (DESIGN.md §2): a target may link targets of its own layer or
# of layers below it, never above.
LAYERS = [
    ("core", ["rs_core"]),
    ("parallel, math, assembly", ["rs_parallel", "rs_math", "rs_assembly"]),
    ("model, contact", ["rs_model", "rs_contact"]),
    ("formulations", ["rs_formulation_base", "rs_formulations_ph_director",
                      "rs_formulations_ph_planar", "rs_formulations_se3_pg",
                      "rs_formulations_se3_strand", "rs_formulations"]),
    ("system", ["rs_system"]),
    ("io, solver", ["rs_io", "rs_solver"]),
    ("app", ["rodsolve"]),
]
BEGIN = "<!-- BEGIN GENERATED: scripts/architecture.py graph -->"
END = "<!-- END GENERATED -->"

# Which source folders may include or use a library directly (the library: a pattern of its
# use in Fortran or C).
LIBRARY_USE = {
    "MPI": (re.compile(r"^\s*(use\s+mpi(_f08)?\b|#\s*include\s*[<\"]mpi\.h)", re.I | re.M),
            ["src/parallel/", "src/io/hdf5_file.F90"]),
    "HDF5": (re.compile(r"^\s*(use\s+hdf5\b|#\s*include\s*[<\"]hdf5)", re.I | re.M), ["src/io/"]),
    "PETSc": (re.compile(r"^\s*(use\s+petsc|#\s*include\s*[<\"]petsc)", re.I | re.M),
              ["src/solver/"]),
    "MUMPS": (re.compile(r"^\s*#\s*include\s*[<\"]dmumps", re.I | re.M), ["src/solver/"]),
    "METIS": (re.compile(r"^\s*#\s*include\s*[<\"]metis", re.I | re.M), ["src/parallel/"]),
}


def cmake_targets(source):
    """{target: [linked rodsolve targets]} from every CMakeLists.txt under src/."""
    targets = {}
    for folder, _, files in sorted(os.walk(os.path.join(source, "src"))):
        if "CMakeLists.txt" not in files:
            continue
        text = open(os.path.join(folder, "CMakeLists.txt"), encoding="utf-8").read()
        text = re.sub(r"#[^\n]*", "", text)
        for name in re.findall(r"add_(?:library|executable)\(\s*([A-Za-z0-9_]+)", text):
            targets.setdefault(name, [])
        for name, body in re.findall(r"target_link_libraries\(\s*([A-Za-z0-9_]+)([^)]*)\)", text):
            links = [w for w in body.split() if w.startswith("rs_")]
            targets.setdefault(name, []).extend(links)
    return targets


def layer_of(target):
    for i, (_, names) in enumerate(LAYERS):
        if target in names:
            return i
    return None


def graph_text(targets):
    lines = ["Targets by layer, each with the rodsolve libraries it links:", ""]
    ordered = [t for _, names in LAYERS for t in names if t in targets]
    ordered += sorted(t for t in targets if t not in ordered)
    for t in ordered:
        links = ", ".join(sorted(set(targets[t]))) or "-"
        lines.append(f"    {t:<30} {links}")
    lines += ["", "```mermaid", "graph BT"]
    for t in ordered:
        for link in sorted(set(targets[t])):
            lines.append(f"    {t} --> {link}")
    lines.append("```")
    return "\n".join(lines)


def library_use_problems(source):
    problems = []
    for folder, _, files in sorted(os.walk(os.path.join(source, "src"))):
        for f in sorted(files):
            if not f.endswith((".f90", ".F90", ".c", ".h")):
                continue
            path = os.path.join(folder, f)
            rel = os.path.relpath(path, source)
            text = open(path, encoding="utf-8", errors="replace").read()
            for library, (pattern, allowed) in LIBRARY_USE.items():
                if pattern.search(text) and not any(rel.startswith(a) for a in allowed):
                    problems.append(f"{rel} uses {library} directly (allowed only in "
                                    f"{', '.join(allowed)})")
    return problems


def layering_problems(targets):
    problems = []
    for t, links in targets.items():
        here = layer_of(t)
        if here is None:
            problems.append(f"target {t} is in no layer of scripts/architecture.py LAYERS")
            continue
        for link in links:
            there = layer_of(link)
            if there is not None and there > here:
                problems.append(f"{t} ({LAYERS[here][0]}) links {link}, a layer above "
                                f"({LAYERS[there][0]})")
    return problems


def main():
    if len(sys.argv) < 2 or sys.argv[1] not in ("graph", "check"):
        print(__doc__)
        return 2
    source = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..")
    targets = cmake_targets(source)
    generated = graph_text(targets)
    if sys.argv[1] == "graph":
        print(generated)
        return 0
    problems = layering_problems(targets) + library_use_problems(source)
    doc = os.path.join(source, "docs", "developer", "architecture.md")
    text = open(doc, encoding="utf-8").read()
    documented = text[text.index(BEGIN) + len(BEGIN):text.index(END)].strip()
    if documented != generated.strip():
        problems.append(f"{doc}: the library graph is out of date; replace the block between its "
                        "GENERATED markers with the output of `scripts/architecture.py graph`")
    for p in problems:
        print("FAIL", p)
    print(f"{0 if problems else 1} passed, {1 if problems else 0} failed")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
