#!/usr/bin/env python3
"""No code outside a formulation's folder names a formulation (issue 22 item 4, acceptance):
the only string literal equal to a formulation's name outside src/formulations/<folder>/ is in
the descriptor registry (src/formulations/registry.f90, which in fact names none: it lists the
folders' descriptor functions). A name test ('se3_strand' == ...), a case label or a default
value elsewhere would be a second list that a new formulation has to find and extend.

The names are those of the capability matrix that `rodsolve --capabilities` renders from the
registry, so the list checked is the build's own. Text that merely mentions a formulation
inside a longer string (descriptions in the input spec, plan sentences) and comments are not
names in this sense and are not reported.

usage: check_formulation_names.py RODSOLVE SOURCE_DIR
"""
import pathlib
import re
import subprocess
import sys

ALLOWED = {"src/formulations/registry.f90"}


def formulation_names(rodsolve):
    out = subprocess.run([rodsolve, "--capabilities"], capture_output=True, text=True,
                         check=True).stdout
    names = []
    for line in out.splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and re.fullmatch(r"[a-z][a-z0-9_]*", cells[0]):
            names.append(cells[0])
    return names


def code_part(line, suffix):
    """The line without its comment (Fortran '!' outside strings; C '//' and block lines)."""
    if suffix in (".c", ".h"):
        stripped = line.strip()
        if stripped.startswith(("/*", "*", "//")):
            return ""
        return line
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return line[:i]
    return line


def main():
    rodsolve, source = sys.argv[1], pathlib.Path(sys.argv[2])
    names = formulation_names(rodsolve)
    if len(names) < 2:
        print(f"FAIL: --capabilities listed {names}; expected the formulations of the build")
        return 1
    literal = re.compile(r"(['\"])(" + "|".join(map(re.escape, names)) + r")\1")
    folders = {p.parent for p in (source / "src" / "formulations").glob("*/CMakeLists.txt")}
    found = []
    for path in sorted((source / "src").rglob("*")):
        if path.suffix not in (".f90", ".F90", ".c", ".h") or not path.is_file():
            continue
        rel = path.relative_to(source).as_posix()
        if rel in ALLOWED or path.parent in folders:
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            for match in literal.finditer(code_part(line, path.suffix)):
                found.append(f"{rel}:{number}: names formulation '{match.group(2)}'")
    for item in found:
        print(item)
    print(f"{len(names)} formulations ({', '.join(names)}); {len(found)} name(s) outside "
          "their folders and the registry")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
