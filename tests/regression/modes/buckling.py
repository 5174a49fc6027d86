#!/usr/bin/env python3
"""Linearized buckling (&modes kind = 'buckling'; issue 27 item 2, docs/theory/modes.md)
against closed forms.

Cases:
  euler_se3_pg, euler_ph_planar
      Euler's cantilever column, P_cr = pi^2 EI / (4 L^2): a steel rod of L = 1 m, r = 1 mm
      (L / r = 1000: the Cosserat rod's shear and extension move P_cr by P_cr / (G A) = 1.5e-6
      and P_cr / (E A) = 6e-7), clamped at s = 0 and loaded at s = L along its axis by a
      ramped force of a share of P_cr; the critical load lambda_1 P against Euler's: observed
      order 2 between the meshes, the finest within 1e-5; the load factor does not depend on
      the load applied (se3_pg: 1e-3 P_cr against 0.5 P_cr); the second load factor 9 times
      the first ((3 pi / 2)^2 / (pi / 2)^2); the first buckling mode's shape against
      1 - cos(pi s / (2 L)) (se3_pg).
"""
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from run_scene import Checks, run, run_cases  # noqa: E402

LENGTH, RADIUS, E, G, RHO = 1.0, 0.001, 2e11, 8e10, 7800.0
INERTIA = math.pi * RADIUS**4 / 4
AREA = math.pi * RADIUS**2
EULER = math.pi**2 * E * INERTIA / (4 * LENGTH**2)


def column(formulation, n_elements, share):
    return f"""&time
    t_end = 1.0
    dt = 0.5
    quasistatic = .true.
/
&solver
    newton_atol = 1e-8
/
&rod
    name = 'column', formulation = '{formulation}', n_elements = {n_elements}, length = {LENGTH}
    start = 0.0, 0.0, 0.0, direction = 1.0, 0.0, 0.0
    section = 'circle', radius = {RADIUS}, E = {E}, G = {G}, density = {RHO}
/
&bc
    rod = 'column', end = 'start', kind = 'clamped'
/
&load
    rod = 'column', where = 'end', force = {-share * EULER!r}, 0.0, 0.0
    time_function = 'ramp', t_off = 1.0
/
&output
    path = 'x.h5'
/
&modes
    n_modes = 4, about = 'equilibrium', kind = 'buckling'
/
"""


def buckle(args, formulation, n_elements, share):
    path = run(args, column(formulation, n_elements, share), f"{formulation}_{n_elements}_{share}")
    with h5py.File(path, "r") as f:
        group = f["buckling"]["column"]
        unit = group["load_factor"].attrs["unit"]
        if (unit.decode() if isinstance(unit, bytes) else unit) != "-":
            raise SystemExit(f"/buckling/column/load_factor has the unit {unit!r}, not -")
        factors = group["load_factor"][()] * share
        shapes = None
        if "column" in group:
            shapes = (group["column"]["position"][()], group["column"]["displacement"][()])
    return factors, shapes


def euler(formulation, meshes):
    def case(args, checks):
        print(f"Euler: P_cr = {EULER:.10g} N; with shear (Engesser) "
              f"{EULER / (1 + EULER / (G * AREA)):.10g} N")
        planar = formulation == "ph_planar"
        errors = []
        for n in meshes:
            factors, shapes = buckle(args, formulation, n, 0.5)
            # A 3D rod buckles in either plane: a degenerate pair.
            distinct = factors if planar else factors[::2]
            errors.append(distinct[0] - 1)
            print(f"{n} elements: load factors x share {factors}, relative error "
                  f"{errors[-1]:.3e}")
        orders = [math.log(abs(errors[k] / errors[k + 1])) / math.log(meshes[k + 1] / meshes[k])
                  for k in range(len(meshes) - 2)]
        print("observed orders:", orders)
        checks.check(f"{formulation}: |observed order - 2| ({meshes[0]}-{meshes[-2]} elements)",
                     max(abs(o - 2) for o in orders), 0.1)
        checks.check(f"{formulation}, {meshes[-1]} elements: |lambda P / P_cr - 1|",
                     abs(errors[-1]), 1e-5)
        checks.check(f"{formulation}: |lambda_2 / lambda_1 / 9 - 1|",
                     abs(distinct[1] / distinct[0] / 9 - 1), 2e-3)
        if planar:
            return
        small, _ = buckle(args, formulation, meshes[-2], 1e-3)
        large, _ = buckle(args, formulation, meshes[-2], 0.5)
        checks.check(f"{formulation}: critical load at 1e-3 P_cr against 0.5 P_cr (relative)",
                     abs(small[0] / large[0] - 1), 1e-6)
        position, displacement = shapes
        s = position[:, 0]
        w = np.linalg.norm(displacement[0, :, 1:], axis=1)
        w = w / w[-1]
        checks.check("mode 1: largest |w / w(L) - (1 - cos(pi s / 2L))|",
                     float(np.abs(w - (1 - np.cos(np.pi * s / (2 * LENGTH)))).max()), 1e-4)
        checks.check("mode 1: axial displacement / lateral",
                     float(np.abs(displacement[0, :, 0]).max() / np.abs(displacement[0, :, 1:]).max()),
                     1e-6)
    return case


if __name__ == "__main__":
    run_cases(__doc__, {
        "euler_se3_pg": euler("se3_pg", [50, 100, 200, 400]),
        "euler_ph_planar": euler("ph_planar", [50, 100, 200, 400]),
    })
