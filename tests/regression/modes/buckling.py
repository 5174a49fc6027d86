#!/usr/bin/env python3
"""Linearized buckling (&modes kind = 'buckling'; issue 27 item 2, docs/theory/modes.md)
against closed forms.

Cases:
  euler_se3_pg, euler_ph_planar, euler_cl_em_planar
      Euler's cantilever column, P_E = pi^2 EI / (4 L^2): a steel rod of L = 1 m, r = 1 mm
      (L / r = 1000), clamped at s = 0 and loaded at s = L along its axis by a ramped force
      of a share of P_E; the critical load lambda_1 P against the shear-deformable column's,
      P_cr = P_E (1 - P_E / (G A)) (Engesser's and Haringx's formulas to first order in P_E /
      (G A) = 1.5e-6, which the Cosserat rod's stress stiffness has): observed order 2
      between the meshes, the finest within 1e-5; the load factor does not depend on
      the load applied (se3_pg: 1e-3 P_cr against 0.5 P_cr); the second load factor 9 times
      the first ((3 pi / 2)^2 / (pi / 2)^2); the first buckling mode's shape against
      1 - cos(pi s / (2 L)) and its cross-sections' rotation against the slope (se3_pg).
  euler_ph_director
      the same column of ph_director elements of degree 2 (the default) made Euler's elastica
      exactly (constraint = 'inextensible': shear-rigid and inextensible, so P_cr has no shear
      or extension correction, and the straight prebuckling state is the reference itself):
      observed order 4 between 8 and 16 elements (as its frequencies, docs/theory/modes.md),
      16 within 1e-5 (measured 5.8e-7); the load factor the same at 1e-3 P_cr and 0.5 P_cr to
      round-off (K_T(u_1) - K_T(u_0) is linear in the load); lambda_2 = 9 lambda_1; the mode's
      centreline and cross-section rotations as for se3_pg.
  prandtl_se3_pg
      Prandtl's lateral-torsional buckling of a narrow cantilever under a dead tip force at the
      centroid in its stiff plane: P_cr = gamma sqrt(EI_weak GJ) / L^2 with gamma = 2 j, j the
      first zero of the Bessel function J_{-1/4} (found here by bisection on its series:
      4.0125993...). EI_strong / EI_weak = EI_strong / GJ = 1e4 (the prebuckling deflection,
      which Prandtl neglects and the stress stiffness at the reference too, would move P_cr by
      about 1e-4); the load is 1e-3 P_cr. Observed order 2, the finest mesh within 1e-3
      (measured 2.4e-5 at 200 elements).
  greenhill_se3_pg
      Greenhill's shaft: the steel rod of the Euler case between ball joints, s = 0 held in
      position and twist (&bc hold = 'x', 'y', 'z', 'twist': the twist hold removes the rigid
      turn about the axis), s = L held laterally, twisted by dead axial end moments +-M e_x at
      both ends (the hold carries none: Greenhill's axial torques). The critical moment is
      M_G = 2 pi EI / L ((M / (2 EI))^2 + P / EI = (pi / L)^2 with P = 0); the load is 1e-2 of
      it. Observed order 2 between 100 and 200 elements, the finer within 1e-3 (measured 8e-5);
      the moment and its reverse buckle alike; the buckling mode is Greenhill's helix, the
      lateral displacement y + i z = w (exp(i 2 pi s / L) - 1) (y and z in quadrature: the
      centreline's projection is a circle through the axis), to 1e-3 of |w|; the prebuckling
      twist at s = L is M L / GJ (held at s = 0). The same shaft with the twist hold carrying
      the torque (no moment at s = 0) is a semi-tangential reaction against a dead moment, a
      non-conservative pair without divergence: the run says there are no real factors
      (docs/theory/modes.md, "Greenhill's shaft").
  greenhill_axial_se3_pg
      the shaft of greenhill_se3_pg under axial compression P too, at P / P_E = 0.25 and 0.75
      of the pinned Euler load P_E = pi^2 EI / L^2 at criticality: the load pattern is (P, M)
      on Greenhill's curve, scaled by 1e-2, and the critical factor lambda solves (lambda M /
      (2 EI))^2 + lambda P / EI = (pi / L)^2. Order 2 between 100 and 200 elements, within 1e-3.
  ranks, ranks_ph_director
      the se3_pg (ph_director) column's load factors on 2 ranks (a distributed eigen solve)
      equal those on 1.
  example_euler, example_greenhill
      the examples input/euler_buckling.nml (the se3_pg column of euler_se3_pg at 400
      elements under a tip force of 0.1 N) and input/greenhill_shaft.nml (the shaft of
      greenhill_se3_pg at 200 elements under end moments of 0.01 N m) as given, against the
      closed forms computed here from their own section, length and loads: lambda_1 |F| within
      1e-5 of P_cr (a degenerate pair, the third factor 9 times the first); lambda_1 M within
      1e-3 of M_G (+- pairs) and the prebuckling twist at s = L within 1e-8 of M L / GJ.
"""
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from run_scene import (  # noqa: E402
    Checks, number, numbers, read_example, rod, run, run_cases, run_failing)

LENGTH, RADIUS, E, G, RHO = 1.0, 0.001, 2e11, 8e10, 7800.0
INERTIA = math.pi * RADIUS**4 / 4
AREA = math.pi * RADIUS**2
EULER = math.pi**2 * E * INERTIA / (4 * LENGTH**2)
# The shear-deformable column (Engesser, Haringx: equal to first order in EULER / (G A)).
SHEARED = EULER * (1 - EULER / (G * AREA))


CIRCLE = f"section = 'circle', radius = {RADIUS}, E = {E}, G = {G}, density = {RHO}"
# Euler's elastica exactly: shear-rigid and inextensible (ph_director's &rod constraint).
ELASTICA = CIRCLE + "\n    constraint = 'inextensible'"
# The section of each formulation's column.
SECTIONS = {"ph_director": ELASTICA}


def column(formulation, n_elements, share, section=CIRCLE, force=None, atol=1e-8):
    """A cantilever along x loaded at its tip by `force` (default: share P_cr along -x)."""
    if force is None:
        force = (-share * EULER, 0.0, 0.0)
    return f"""&time
    t_end = 1.0
    dt = 0.5
    quasistatic = .true.
/
&solver
    newton_atol = {atol}
/
&rod
    name = 'column', formulation = '{formulation}', n_elements = {n_elements}, length = {LENGTH}
    start = 0.0, 0.0, 0.0, direction = 1.0, 0.0, 0.0
    {section}
/
&bc
    rod = 'column', end = 'start', kind = 'clamped'
/
&load
    rod = 'column', where = 'end', force = {', '.join(repr(float(c)) for c in force)}
    time_function = 'ramp', t_off = 1.0
/
&output
    path = 'x.h5'
/
&modes
    n_modes = 4, about = 'equilibrium', kind = 'buckling'
/
"""


def buckle(args, formulation, n_elements, share, ranks=1):
    path = run(args, column(formulation, n_elements, share,
                            SECTIONS.get(formulation, CIRCLE)),
               f"{formulation}_{n_elements}_{share}_{ranks}", ranks=ranks)
    with h5py.File(path, "r") as f:
        group = f["buckling"]["column"]
        unit = group["load_factor"].attrs["unit"]
        if (unit.decode() if isinstance(unit, bytes) else unit) != "-":
            raise SystemExit(f"/buckling/column/load_factor has the unit {unit!r}, not -")
        factors = group["load_factor"][()] * share
        shapes = None
        if "column" in group:
            shapes = tuple(group["column"][name][()]
                           for name in ("position", "displacement", "rotation"))
    return factors, shapes


def euler(formulation, meshes, order=2, order_meshes=None, load_tolerance=1e-6,
          shape_tolerance=1e-4, order_bound=0.1, error_bound=1e-5, ratio_bound=2e-3):
    """The Euler column of `formulation` on `meshes`: the observed `order` between
    order_meshes (default all but the finest, whose error se3_pg's round-off reaches) within
    order_bound, the finest within error_bound, lambda_2 / lambda_1 = 9 within ratio_bound; the
    load factor at 1e-3 P_cr against 0.5 P_cr within load_tolerance and the first mode's shape
    within shape_tolerance (3D rods)."""
    order_meshes = order_meshes or meshes[:-1]

    def case(args, checks):
        print(f"Euler: P_E = {EULER:.10g} N; with shear P_cr = {SHEARED:.10g} N")
        planar = formulation in ("ph_planar", "cl_em_planar")
        errors = {}
        for n in meshes:
            factors, shapes = buckle(args, formulation, n, 0.5)
            # A 3D rod buckles in either plane: a degenerate pair.
            distinct = factors if planar else factors[::2]
            # ph_director's column is inextensible and shear-rigid: Euler's own load.
            reference = EULER if formulation == "ph_director" else SHEARED
            errors[n] = distinct[0] * EULER / reference - 1
            print(f"{n} elements: load factors x share {factors}, relative error "
                  f"{errors[n]:.3e}")
        orders = [math.log(abs(errors[a] / errors[b])) / math.log(b / a)
                  for a, b in zip(order_meshes, order_meshes[1:])]
        print("observed orders:", orders)
        checks.check(f"{formulation}: |observed order - {order}| ({order_meshes[0]}-"
                     f"{order_meshes[-1]} elements)", max(abs(o - order) for o in orders),
                     order_bound)
        checks.check(f"{formulation}, {meshes[-1]} elements: |lambda P / P_cr - 1|",
                     abs(errors[meshes[-1]]), error_bound)
        checks.check(f"{formulation}: |lambda_2 / lambda_1 / 9 - 1|",
                     abs(distinct[1] / distinct[0] / 9 - 1), ratio_bound)
        if planar:
            return
        small, _ = buckle(args, formulation, meshes[-2], 1e-3)
        large, _ = buckle(args, formulation, meshes[-2], 0.5)
        checks.check(f"{formulation}: critical load at 1e-3 P_cr against 0.5 P_cr (relative)",
                     abs(small[0] / large[0] - 1), load_tolerance)
        position, displacement, rotation = shapes
        s = position[:, 0]
        w = np.linalg.norm(displacement[0, :, 1:], axis=1)
        w_end = w[-1]
        checks.check("mode 1: largest |w / w(L) - (1 - cos(pi s / 2L))|",
                     float(np.abs(w / w_end - (1 - np.cos(np.pi * s / (2 * LENGTH)))).max()),
                     shape_tolerance)
        checks.check("mode 1: axial displacement / lateral",
                     float(np.abs(displacement[0, :, 0]).max() / np.abs(displacement[0, :, 1:]).max()),
                     1e-6)
        # The cross-sections turn with the centreline's slope (shear is zero or 1e-6 here):
        # |theta| = w' = w(L) pi / (2 L) sin(pi s / 2L), about an axis across the rod.
        theta = np.linalg.norm(rotation[0], axis=1)
        checks.check("mode 1: largest |L |theta| / w(L) - pi/2 sin(pi s / 2L)|",
                     float(np.abs(LENGTH * theta / w_end
                                  - np.pi / 2 * np.sin(np.pi * s / (2 * LENGTH))).max()), 2e-5)
        checks.check("mode 1: twist / rotation", float(np.abs(rotation[0, :, 0]).max()
                                                       / theta.max()), 1e-6)
    return case


def bessel_j(order, x, terms=60):
    """J_order(x) from its power series (x of order 1: the terms fall fast)."""
    return sum((-1)**k * (x / 2)**(2 * k + order) / (math.factorial(k) * math.gamma(k + order + 1))
               for k in range(terms))


def prandtl_gamma():
    """2 j, j the first zero of J_{-1/4} (between 1 and 3), by bisection."""
    lo, hi = 1.0, 3.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (bessel_j(-0.25, lo) > 0) == (bessel_j(-0.25, mid) > 0):
            lo = mid
        else:
            hi = mid
    return lo + hi


def prandtl(args, checks):
    """se3_pg; strong bending about d1 = e_y (EI1), the tip force along d2 = e_z."""
    weak, torsion, strong = 1.0, 1.0, 1e4
    critical = prandtl_gamma() * math.sqrt(weak * torsion) / LENGTH**2
    print(f"Prandtl: gamma = {prandtl_gamma():.12g}, P_cr = {critical:.10g} N")
    meshes = [50, 100, 200]
    errors = []
    for n in meshes:
        load = 1e-3 * critical
        section = (f"section = 'none', EA = 1e8, GA1 = 1e8, GA2 = 1e8, EI1 = {strong}, "
                   f"EI2 = {weak}, GJ = {torsion}\n    rhoA = 1.0, rhoI1 = 1e-4, rhoI2 = 1e-4")
        # The strong plane's forces are 1e4 times the buckling's: Newton's floor is higher.
        text = column("se3_pg", n, 0.0, section, (0.0, 0.0, -load), atol=1e-6)
        path = run(args, text, f"prandtl_{n}")
        with h5py.File(path, "r") as f:
            factors = f["buckling"]["column"]["load_factor"][()] * load
        # The pattern and its reverse buckle alike (a +- pair).
        errors.append(abs(factors[0]) / critical - 1)
        print(f"{n} elements: critical loads {factors} N, relative error {errors[-1]:.3e}")
        checks.check(f"{n} elements: the reversed load buckles alike (relative difference)",
                     abs(abs(factors[0] / factors[1]) - 1), 1e-5)
    order = math.log(abs((errors[0] - errors[1]) / (errors[1] - errors[2]))) / math.log(2)
    print(f"observed order (of the differences) {order:.2f}")
    checks.check("prandtl: |observed order - 2|", abs(order - 2), 0.2)
    checks.check(f"prandtl, {meshes[-1]} elements: |P / P_cr - 1|", abs(errors[-1]), 1e-3)


def ranks(formulation, n_elements, tolerance):
    def case(args, checks):
        one, _ = buckle(args, formulation, n_elements, 0.5)
        two, _ = buckle(args, formulation, n_elements, 0.5, ranks=2)
        print("1 rank:", one, "2 ranks:", two)
        checks.check(f"{formulation}: load factors on 2 ranks against 1 (largest relative "
                     "difference)", float(np.max(np.abs(two / one - 1))), tolerance)
    return case


SHAFT_EI = E * INERTIA
SHAFT_GJ = G * 2 * INERTIA
PINNED_EULER = math.pi**2 * SHAFT_EI / LENGTH**2
GREENHILL = 2 * math.pi * SHAFT_EI / LENGTH


def shaft(n_elements, moment, force=0.0, start_moment=True):
    """Greenhill's shaft along x: ball joints at both ends, the twist held at s = 0; dead axial
    end moments +-moment (none at s = 0 if not start_moment) and a dead axial force -force at
    s = L, ramped."""
    start = ""
    if start_moment:
        start = f"""&load
    rod = 'shaft', where = 'start', moment = {-moment!r}, 0.0, 0.0
    time_function = 'ramp', t_off = 1.0
/
"""
    return f"""&time
    t_end = 1.0
    dt = 0.5
    quasistatic = .true.
/
&solver
    newton_atol = 1e-9
/
&rod
    name = 'shaft', formulation = 'se3_pg', n_elements = {n_elements}, length = {LENGTH}
    start = 0.0, 0.0, 0.0, direction = 1.0, 0.0, 0.0
    {CIRCLE}
/
&bc
    rod = 'shaft', end = 'start', kind = 'held', hold = 'x', 'y', 'z', 'twist'
/
&bc
    rod = 'shaft', end = 'end', kind = 'held', hold = 'y', 'z'
/
&load
    rod = 'shaft', where = 'end', moment = {moment!r}, 0.0, 0.0, force = {-force!r}, 0.0, 0.0
    time_function = 'ramp', t_off = 1.0
/
{start}&output
    path = 'x.h5'
/
&modes
    n_modes = 4, about = 'equilibrium', kind = 'buckling'
/
"""


def greenhill_factor(moment, force):
    """The smallest positive lambda with (lambda M / (2 EI))^2 + lambda P / EI = (pi / L)^2."""
    a = (moment / (2 * SHAFT_EI))**2
    b = force / SHAFT_EI
    c = -(math.pi / LENGTH)**2
    if a == 0:
        return -c / b
    return (-b + math.sqrt(b * b - 4 * a * c)) / (2 * a)


def shaft_buckling(args, n, moment, force, name):
    path = run(args, shaft(n, moment, force), name)
    with h5py.File(path, "r") as f:
        group = f["buckling"]["shaft"]
        factors = group["load_factor"][()]
        shapes = (group["shaft"]["position"][()], group["shaft"]["displacement"][()])
    return path, factors, shapes


def order_and_error(checks, label, errors, meshes, bound):
    order = math.log(abs(errors[0] / errors[1])) / math.log(meshes[1] / meshes[0])
    print(f"{label}: relative errors {errors}, observed order {order:.3f}")
    checks.check(f"{label}: |observed order - 2| ({meshes[0]}-{meshes[1]} elements)",
                 abs(order - 2), 0.1)
    checks.check(f"{label}, {meshes[1]} elements: |lambda / lambda_Greenhill - 1|",
                 abs(errors[1]), bound)


def greenhill(args, checks):
    share = 1e-2
    moment = share * GREENHILL
    print(f"Greenhill: EI = {SHAFT_EI:.10g} N m^2, GJ = {SHAFT_GJ:.10g} N m^2, "
          f"M_G = 2 pi EI / L = {GREENHILL:.10g} N m")
    meshes = [100, 200]
    errors = []
    for n in meshes:
        path, factors, (position, displacement) = shaft_buckling(args, n, moment, 0.0,
                                                                  f"greenhill_{n}")
        print(f"{n} elements: load factors {factors}")
        # A double pair (either helix sense of the isotropic shaft), +- (the reversed moment).
        positive = factors[factors > 0]
        negative = factors[factors < 0]
        errors.append(positive[0] * share - 1)
        checks.check(f"{n} elements: the reversed moment buckles alike (relative difference)",
                     abs(negative[0] / positive[0] + 1), 1e-6)
    order_and_error(checks, "greenhill", errors, meshes, 1e-3)
    # The mode: y + i z = w (exp(+-i 2 pi s / L) - 1) at the nodes (interior: 0/0 at the ends).
    s = position[:, 0]
    lateral = displacement[0, :, 1] + 1j * displacement[0, :, 2]
    inner = slice(1, len(s) - 1)
    spreads = []
    for sense in (1, -1):
        w = lateral[inner] / (np.exp(sense * 2j * np.pi * s[inner] / LENGTH) - 1)
        spreads.append(float(np.abs(w - w.mean()).max() / np.abs(w.mean())))
    print(f"mode 1: largest |w_k - w| / |w| for either helix sense {spreads}")
    checks.check("mode 1: Greenhill's helix, largest |w_k - w| / |w|", min(spreads), 1e-3)
    checks.check("mode 1: axial displacement / lateral",
                 float(np.abs(displacement[0, :, 0]).max() / np.abs(lateral).max()), 1e-2)
    # The prebuckling twist: d1 turned about x by M s / GJ, held at s = 0.
    fields = rod(path, "shaft")
    d1 = fields["directors"][-1][:, 0, :]
    twist = np.arctan2(d1[:, 2], d1[:, 1])
    print(f"twist at s = 0: {twist[0]:.3e} rad, at s = L: {twist[-1]:.10e} rad "
          f"(M L / GJ = {moment * LENGTH / SHAFT_GJ:.10e})")
    checks.check("twist held at s = 0 (rad)", abs(twist[0]), 1e-14)
    checks.check("twist at s = L against M L / GJ (relative)",
                  abs(twist[-1] / (moment * LENGTH / SHAFT_GJ) - 1), 1e-8)
    # The twist hold carrying the torque: no real factor.
    text = shaft(meshes[0], moment, start_moment=False)
    text = text.replace("path = 'x.h5'", f"path = '{os.path.join(args.workdir, 'held_torque.h5')}'")
    status, log = run_failing(args, text, "held_torque")
    checks.check("the twist hold carrying the torque: the run fails", float(status == 0), 0.0)
    checks.check("... saying it found no real factor, only complex ones",
                 float("SLEPc found 0 real buckling load factors" not in log or
                       "complex ones" not in log), 0.0)


def greenhill_axial(args, checks):
    share = 1e-2
    meshes = [100, 200]
    for ratio in (0.25, 0.75):
        # (P, M) on Greenhill's curve: lambda = 1 / share.
        force = ratio * PINNED_EULER
        moment = GREENHILL * math.sqrt(1 - ratio)
        expected = greenhill_factor(share * moment, share * force)
        print(f"P / P_E = {ratio}: pattern P = {share * force:.6g} N, M = {share * moment:.6g} "
              f"N m; Greenhill's factor {expected:.10g}")
        errors = []
        for n in meshes:
            _, factors, _ = shaft_buckling(args, n, share * moment, share * force,
                                           f"greenhill_axial_{ratio}_{n}")
            print(f"{n} elements: load factors {factors}")
            errors.append(factors[factors > 0][0] / expected - 1)
        order_and_error(checks, f"P / P_E = {ratio}", errors, meshes, 1e-3)


def example_section(text):
    """EI, GA, GJ and L of the circular rod of a scene text."""
    radius, modulus, shear = (number(text, "rod", name) for name in ("radius", "E", "G"))
    inertia = math.pi * radius**4 / 4
    return (modulus * inertia, shear * math.pi * radius**2, shear * 2 * inertia,
            number(text, "rod", "length"))


def example_euler(args, checks):
    """input/euler_buckling.nml as given."""
    text = read_example(args.source, "euler_buckling.nml")
    bending, shear, _, length = example_section(text)
    force = abs(number(text, "load", "force"))
    euler_load = math.pi**2 * bending / (4 * length**2)
    critical = euler_load * (1 - euler_load / shear)
    path = run(args, text, "example_euler")
    with h5py.File(path, "r") as f:
        factors = f["buckling"]["column"]["load_factor"][()]
    print(f"P_cr = {critical:.10g} N, tip force {force} N: expected factor "
          f"{critical / force:.10g}; load factors {factors}")
    checks.check("euler_buckling.nml: |lambda_1 F / P_cr - 1|",
                 abs(factors[0] * force / critical - 1), 1e-5)
    checks.check("euler_buckling.nml: the two bending planes alike (|lambda_2 / lambda_1 - 1|)",
                 abs(factors[1] / factors[0] - 1), 1e-8)
    checks.check("euler_buckling.nml: |lambda_3 / lambda_1 / 9 - 1|",
                 abs(factors[2] / factors[0] / 9 - 1), 2e-3)


def example_greenhill(args, checks):
    """input/greenhill_shaft.nml as given."""
    text = read_example(args.source, "greenhill_shaft.nml")
    bending, _, torsion, length = example_section(text)
    moment = abs(numbers(text, "load", "moment")[0])
    greenhill_moment = 2 * math.pi * bending / length
    path = run(args, text, "example_greenhill")
    with h5py.File(path, "r") as f:
        factors = f["buckling"]["shaft"]["load_factor"][()]
    print(f"M_G = {greenhill_moment:.10g} N m, end moments {moment} N m: expected factor "
          f"{greenhill_moment / moment:.10g}; load factors {factors}")
    positive, negative = factors[factors > 0], factors[factors < 0]
    checks.check("greenhill_shaft.nml: |lambda_1 M / M_G - 1|",
                 abs(positive[0] * moment / greenhill_moment - 1), 1e-3)
    checks.check("greenhill_shaft.nml: the reversed moments buckle alike (relative difference)",
                 abs(negative[0] / positive[0] + 1), 1e-6)
    d1 = rod(path, "shaft")["directors"][-1][:, 0, :]
    twist = np.arctan2(d1[-1, 2], d1[-1, 1])
    checks.check("greenhill_shaft.nml: twist at s = L against M L / GJ (relative)",
                 abs(twist / (moment * length / torsion) - 1), 1e-8)


if __name__ == "__main__":
    run_cases(__doc__, {
        "euler_se3_pg": euler("se3_pg", [50, 100, 200, 400]),
        "euler_ph_planar": euler("ph_planar", [50, 100, 200, 400]),
        # cl-EM's column converges at order 2 toward P_cr (1 + 8e-7) (its shortening), which
        # bends the order between finer meshes (1.92 from 100 to 200): measured |order - 2|
        # 0.021 from 50 to 100 elements (bound 0.25, 12x), 3.2e-6 at 400 (bound 5e-5, 16x),
        # lambda_2 / lambda_1 / 9 - 1 = 1.6e-5 (bound 1e-3, 61x). Under a second.
        "euler_cl_em_planar": euler("cl_em_planar", [50, 100, 400], order_meshes=[50, 100],
                                    order_bound=0.25, error_bound=5e-5, ratio_bound=1e-3),
        # Degree 2: order 4 (measured 3.996 between 8 and 16 elements, errors 9.3e-6 and
        # 5.8e-7); the load factor does not depend on the load to 9e-16; at 16 elements the
        # shape within 2.4e-7, the rotations within 7.1e-7 (both order 4 from 8 to 32).
        "euler_ph_director": euler("ph_director", [8, 16], order=4, order_meshes=[8, 16],
                                   load_tolerance=1e-12, shape_tolerance=1e-5),
        "prandtl_se3_pg": prandtl,
        "greenhill_se3_pg": greenhill,
        "greenhill_axial_se3_pg": greenhill_axial,
        "ranks": ranks("se3_pg", 200, 1e-8),
        # Measured 2e-14 (MUMPS pivots differently on 2 ranks).
        "ranks_ph_director": ranks("ph_director", 16, 1e-12),
        "example_euler": example_euler,
        "example_greenhill": example_greenhill,
    })
