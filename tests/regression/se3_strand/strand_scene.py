"""Helpers shared by the se3_strand regression tests: the se3_pg tests' run-and-parse helpers
(tests/regression/se3_pg/se3_scene.py: the rod's summary line, the run's wall time, the result
file's datasets) and the 'relaxed after <n> steps' line of &time relaxation.
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "se3_pg"))
import se3_scene  # noqa: E402,F401
from se3_scene import rs  # noqa: E402,F401

# "  <rod>: relaxed after <n> steps (t = ...): kinetic energy ... < ..." (src/solver/rod_run.F90)
RELAXED = re.compile(r"^\s+(\S+): relaxed after (\d+) steps", flags=re.M)


def relaxed_steps(run, rod):
    """Steps the run took to relax, or None if it never did."""
    for m in RELAXED.finditer(run.text):
        if m.group(1) == rod:
            return int(m.group(2))
    return None
