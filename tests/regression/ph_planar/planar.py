"""Helpers shared by the planar regression tests (methods/ph_planar.md §6): the nodal angle from
the directors, per-rod scene edits and the groups of a scene text.

For the xy-plane rods of ph_planar and cl_em_planar, d3 = (cos theta, sin theta, 0) and
d2 = e_z; directors[k, node, i, :] = d_(i+1).
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402


def theta(directors):
    """The nodal angles theta[record, node] from d3, unwrapped along the records (theta is never
    wrapped by the solver, methods §10; the tests store every step, so that consecutive records
    differ by much less than pi)."""
    d3 = directors[:, :, 2, :]
    return np.unwrap(np.arctan2(d3[..., 1], d3[..., 0]), axis=0)


def record(rod, t):
    """Index of the record at time t (it must exist to 1e-9)."""
    k = int(np.argmin(np.abs(rod["time"] - t)))
    if abs(rod["time"][k] - t) > 1e-9:
        raise SystemExit(f"no record at t = {t} (nearest {rod['time'][k]})")
    return k


def groups(text, name):
    """The full text of every `&name ... /` group of a scene, in file order."""
    return [m.group(0) for m in re.finditer(r"^&" + name + r"\b.*?^/", text, flags=re.M | re.S)]


def set_rod_variable(text, rod, variable, value):
    """set_variable inside the &rod group named `rod` (rs.set_variable edits the first group)."""
    for group in groups(text, "rod"):
        if re.search(r"\bname\s*=\s*'" + rod + r"'", group):
            return text.replace(group, rs.set_variable(group, "rod", variable, value), 1)
    raise ValueError(f"no &rod named '{rod}'")
