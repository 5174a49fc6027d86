"""scripts/costello_strand.py and scripts/make_strand.py (issue 10, docs/theory/bundles.md).

    test_strand_scripts.py

Costello's linear theory:
  - the linearized stiffness matrix equals central differences of the same resultants under the
    exact (nonlinear) helix kinematics, for every variant, to 1e-6;
  - without Poisson contraction and with strains per reference length the equilibrium route
    (Love's equations, F and M of the wire loads) gives the Hessian of the strain energy of the
    wires, computed here independently from the kinematics alone (symmetric), to 1e-8;
  - nu = 0 without wire bending gives E (A1 + 6 A2 cos^3 theta); straight wires give
    E (A1 + 6 A2) and no torque; with nu the hand-derived closed form of the doc's
    "Reference: Costello's strand theory" for the wire strain;
  - Costello's ellipse condition for touching helical wires agrees with the exact centreline
    distance of make_strand.py to 0.5 % in the touching core radius (lay angles 2..20 deg), and
    that distance agrees with brute-force sampling of the two helices;
  - the line load of the contact potential equals the derivative of the potential integrated
    numerically along the core; the penalty secant stiffness tends to the rigid value and its
    penetration is consistent with the line load.
make_strand.py:
  - the 7-, 19- and 37-wire benchmark scenes (not written to input/) are sane namelists: every
    group closed, only known groups, rod names unique, 1 + 3 k (k + 1) rods, both plates list
    every rod once, the top plate pulls along e_z, every rod has --elements-per-pitch elements
    per pitch of layer 1;
  - every helical wire, evaluated with the documented helix convention (with helix_phase),
    starts at z = 0 on its layer radius at phase 2 pi j / (6 k), stays on that radius, winds
    with the layer's handedness and ends at z = L; the header's gaps match the geometry;
  - --pretension, --bend and --mu write the pulling bottom plate, the bending top plate and
    the friction; --mu with --quasistatic exits 2;
  - the command lines write files and exit 0; a bad option exits 2.
Exit status 1 with a list of failures.
"""

import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.normpath(os.path.join(HERE, '..', '..', 'scripts'))
sys.path.insert(0, SCRIPTS)

import costello_strand as cs  # noqa: E402
import make_strand as ms  # noqa: E402

FAILURES = []


def check(condition, message):
    if not condition:
        FAILURES.append(message)


def close(a, b, rtol, message):
    ok = abs(a - b) <= rtol * max(abs(a), abs(b), 1e-300)
    check(ok, f'{message}: {a!r} vs {b!r} (rtol {rtol:g})')


R1, R2, THETA, E, NU = 1.05e-3, 1.0e-3, math.radians(12.0), 200e9, 0.3


def sampled_neighbour_distance(r, pitch, shift, length):
    """Smallest distance between the point at z = length / 2 of the helix (r cos(w z),
    r sin(w z), z), w = 2 pi / pitch, and the helix turned by shift (both are screw
    symmetric, so one point of the first suffices): the best of a sampling of the second in
    [0, length], refined by Newton's method (independent of make_strand's reduction)."""
    w = 2.0 * math.pi / pitch
    za = 0.5 * length
    a = np.array([r * math.cos(w * za), r * math.sin(w * za), za])

    def derivatives(t):
        c, s = math.cos(w * t + shift), math.sin(w * t + shift)
        d = np.array([r * c, r * s, t]) - a
        d1 = np.array([-r * w * s, r * w * c, 1.0])
        d2 = np.array([-r * w * w * c, -r * w * w * s, 0.0])
        return d, 2.0 * d @ d1, 2.0 * (d1 @ d1 + d @ d2)

    z = np.linspace(0.0, length, 20001)
    sampled = np.hypot(np.hypot(r * np.cos(w * z + shift) - a[0],
                                r * np.sin(w * z + shift) - a[1]), z - a[2])
    t = z[np.argmin(sampled)]
    for _ in range(30):
        _, grad, hess = derivatives(t)
        t -= grad / hess
    return float(np.linalg.norm(derivatives(t)[0]))


def test_linearization():
    g = cs._geometry(R1, R2, THETA, E, NU, 6)
    variants = [dict(), dict(curvature_measure='reference'), dict(poisson_contraction=False),
                dict(wire_bending=False), dict(radial_compliance=2e-12)]
    for opts in variants:
        for eps, tau, h in ((1.0, 0.0, 1e-6), (0.0, 1.0, 1e-3)):
            lin = cs.linear_response(g, eps, tau, **opts)
            plus = cs.exact_response(g, h * eps, h * tau, **opts)
            minus = cs.exact_response(g, -h * eps, -h * tau, **opts)
            for key in ('F', 'M'):
                close((plus[key] - minus[key]) / (2.0 * h), lin[key], 1e-6,
                      f'linear {key} against exact kinematics, {opts}, eps {eps}, tau {tau}')


def test_energy_hessian():
    g = cs._geometry(R1, R2, THETA, E, NU, 6)
    s, c, r = g['s'], g['c'], g['r2']

    def energy(eps, tau):
        # Kinematics alone, no equilibrium: (K1), (K2) with d_r = 0, strains per reference
        # length; energy per unit strand length (wire length per strand length 1 / s).
        A = np.array([[1.0, c / s], [c / s, -1.0]])
        xi, d_alpha = np.linalg.solve(A, [eps, r * tau])
        d_kappa = c**2 / r * xi - 2.0 * s * c / r * d_alpha
        d_tau = s * c / r * xi + (c**2 - s**2) / r * d_alpha
        wire = 0.5 * (g['EA2'] * xi**2 + g['EI2'] * d_kappa**2 + g['GJ2'] * d_tau**2)
        return 0.5 * g['EA1'] * eps**2 + 0.5 * g['GJ1'] * tau**2 + 6.0 * wire / s

    hessian = np.empty((2, 2))
    unit = np.eye(2)
    for i in range(2):
        for j in range(2):
            hp, hm = unit[i] + unit[j], unit[i] - unit[j]
            hessian[i, j] = (energy(*hp) - energy(*hm) - energy(*(-hm)) + energy(*(-hp))) / 4.0
    res = cs.costello_axial_stiffness(R1, R2, THETA, E, NU, poisson_contraction=False,
                                      curvature_measure='reference')
    for i in range(2):
        for j in range(2):
            close(res['stiffness_matrix'][i, j], hessian[i, j], 1e-8,
                  f'stiffness matrix [{i}, {j}] against the energy Hessian')


def test_limits():
    for deg in (0.0, 5.0, 12.0, 25.0):
        t = math.radians(deg)
        res = cs.costello_axial_stiffness(R1, R2, t, E, 0.0, wire_bending=False)
        close(res['K_eps'], E * math.pi * (R1**2 + 6 * R2**2 * math.cos(t)**3), 1e-12,
              f'nu = 0, no bending, {deg} deg: the cos^3 formula')
        # Closed form of the doc with Poisson: xi / eps = (s^2 - nu c^2 R1 / r2) /
        # (1 + nu c^2 R2 / r2), F = E A1 eps + 6 E A2 s xi.
        s, c, r2 = math.cos(t), math.sin(t), R1 + R2
        xi = (s**2 - NU * c**2 * R1 / r2) / (1.0 + NU * c**2 * R2 / r2)
        res = cs.costello_axial_stiffness(R1, R2, t, E, NU, wire_bending=False)
        close(res['K_eps'], E * math.pi * (R1**2 + 6 * R2**2 * s * xi), 1e-12,
              f'Poisson closed form, {deg} deg')
        close(res['per_strain']['xi'], xi, 1e-12, f'wire strain closed form, {deg} deg')
    res = cs.costello_axial_stiffness(R1, R2, 0.0, E, NU)
    close(res['K_eps'], E * math.pi * (R1**2 + 6 * R2**2), 1e-12, 'straight wires: K')
    check(abs(res['K_m']) < 1e-9 * res['K_eps'] * R1, f"straight wires: K_m = {res['K_m']}")
    right = cs.costello_axial_stiffness(R1, R2, THETA, E, NU)
    left = cs.costello_axial_stiffness(R1, R2, THETA, E, NU, handedness=-1)
    close(left['K_eps'], right['K_eps'], 1e-14, 'left-handed: same K_eps')
    close(left['K_m'], -right['K_m'], 1e-14, 'left-handed: opposite torque')
    free = cs.costello_axial_stiffness(R1, R2, THETA, E, NU, rotation_fixed=False)
    g = cs._geometry(R1, R2, THETA, E, NU, 6)
    state = cs.linear_response(g, 1.0, free['twist_per_strain'])
    check(abs(state['M']) < 1e-9 * abs(right['K_m']), f"rotation free: M = {state['M']}")
    check(free['K_eps'] < right['K_eps'], 'rotation free: softer than rotation held')


def test_touching():
    for deg in (2.0, 8.0, 12.0, 20.0):
        t = math.radians(deg)
        # Costello: the core radius at which the helical wires touch (ratio = 1).
        lo, hi = 0.5 * R2, 2.0 * R2
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if cs.helical_wire_clearance(mid, R2, t)[0] < 1.0 else (lo, mid)
        costello_touch = 0.5 * (lo + hi)
        exact_touch = ms.auto_core_radius(1, R2, t, clearance=0.0)
        close(costello_touch, exact_touch, 5e-3, f'touching core radius at {deg} deg')
    r, pitch = 4.1e-3, 0.12
    d = ms.neighbour_distance(r, pitch, 12)
    brute = sampled_neighbour_distance(r, pitch, math.pi / 6, 0.5 * pitch)
    close(d, brute, 1e-12, 'neighbour distance against the sampled helices')


def test_contact_load():
    k, r_c = 1e15, R1 + R2
    for delta in (1e-7, 1e-6, 1e-5):

        def energy(r_f):
            a = math.sqrt(r_c**2 - r_f**2)
            u = np.linspace(-a, a, 20001)
            psi = k / (3.0 * r_c**4) * (r_c**2 - r_f**2 - u**2)**3
            return np.sum(0.5 * (psi[1:] + psi[:-1]) * np.diff(u))

        h = 1e-3 * delta
        numeric = -(energy(r_c - delta + h) - energy(r_c - delta - h)) / (2.0 * h)
        close(cs.line_contact_load(delta, k, r_c), numeric, 1e-4,
              f'line load at penetration {delta}')
        p = cs.line_contact_load(delta, k, r_c)
        close(cs.line_contact_penetration(p, k, r_c), delta, 1e-9, 'penetration inverse')
    rigid = cs.costello_axial_stiffness(R1, R2, THETA, E, NU, poisson_contraction=False,
                                        curvature_measure='reference')['K_eps']
    previous = 0.0
    for k in (1e14, 1e16, 1e18, 1e24):
        K, delta, p = cs.penalty_secant_stiffness(R1, R2, THETA, E, NU, k, 1e-3)
        check(previous < K < rigid, f'penalty secant stiffness {K} at k = {k:g}')
        close(cs.line_contact_load(delta, k, R1 + R2), p, 1e-6, f'penalty balance at k = {k:g}')
        previous = K
    close(previous, rigid, 1e-4, 'penalty secant stiffness for a very stiff penalty')


TOKEN = re.compile(r"'(?:[^']|'')*'|&\w+|[=,/]|[^\s=,/']+")


def parse_scene(text):
    """Groups as (name, {variable: [values]}) of a namelist text; raises on bad syntax."""
    clean = []
    for line in text.splitlines():
        out, quoted = [], False
        for ch in line:
            if ch == "'":
                quoted = not quoted
            if ch == '!' and not quoted:
                break
            out.append(ch)
        if quoted:
            raise ValueError(f'unclosed string: {line}')
        clean.append(''.join(out))
    tokens = TOKEN.findall('\n'.join(clean))
    groups, i = [], 0
    while i < len(tokens):
        if not tokens[i].startswith('&'):
            raise ValueError(f'text outside a group: {tokens[i]}')
        name, body, i = tokens[i][1:], {}, i + 1
        var = None
        while True:
            if i >= len(tokens):
                raise ValueError(f'group &{name} is not closed')
            tok = tokens[i]
            if tok == '/':
                i += 1
                break
            if tok.startswith('&'):
                raise ValueError(f'group &{name} is not closed before {tok}')
            if i + 1 < len(tokens) and tokens[i + 1] == '=':
                var = tok.lower()
                if var in body:
                    raise ValueError(f'&{name}: {var} given twice')
                body[var] = []
                i += 2
                continue
            if tok != ',':
                if var is None:
                    raise ValueError(f'&{name}: value {tok} without a variable')
                body[var].append(tok)
            i += 1
        groups.append((name, body))
    return groups


def value(token):
    if token.startswith("'"):
        return token[1:-1].replace("''", "'")
    if token.lower() in ('.true.', '.false.'):
        return token.lower() == '.true.'
    return float(token)


def test_scenes():
    known = {'run', 'time', 'solver', 'output', 'rod', 'plate', 'contact'}
    cases = [(1, ['--core-radius', '1.05e-3']),
             (2, ['--core-radius', 'auto', '--alternate', '--length', '0.12']),
             (3, ['--core-radius', 'auto', '--alternate', '--length', '0.12',
                  '--elements-per-pitch', '12'])]
    for layers, extra in cases:
        argv = ['-', '--layers', str(layers), '--quasistatic', '--pull', '1e-4', '--twist',
                '0.02', '--output', f'out/bundle_{layers}.h5'] + extra
        text, strand = ms.scene_text(ms.parse_args(argv), 'make_strand.py ' + ' '.join(argv))
        tag = f'{layers}-layer scene'
        try:
            groups = parse_scene(text)
        except ValueError as err:
            FAILURES.append(f'{tag}: {err}')
            continue
        check(not {g for g, _ in groups} - known, f'{tag}: unknown groups')
        check(all(len(line) < 100 for line in text.splitlines()), f'{tag}: long lines')
        rods = [{k: [value(t) for t in v] for k, v in body.items()}
                for g, body in groups if g == 'rod']
        names = [r['name'][0] for r in rods]
        n_expected = 1 + 3 * layers * (layers + 1)
        check(len(names) == n_expected, f'{tag}: {len(names)} rods, expected {n_expected}')
        check(len(set(names)) == len(names), f'{tag}: rod names not unique')
        plates = [{k: [value(t) for t in v] for k, v in body.items()}
                  for g, body in groups if g == 'plate']
        check(len(plates) == 2, f'{tag}: {len(plates)} plates')
        for plate in plates:
            check(sorted(plate['rods']) == sorted(names) and len(plate['rods']) <= 128,
                  f"{tag}: plate {plate['name']} does not list every rod once")
        ends = {p['name'][0]: p['end'][0] for p in plates}
        check(ends == {'bottom': 'start', 'top': 'end'}, f'{tag}: plate ends {ends}')
        top = [p for p in plates if p['name'][0] == 'top'][0]
        check(top['displacement'] == [0.0, 0.0, 1e-4] and top['rotation'] == [0.0, 0.0, 0.02],
              f'{tag}: top plate motion')
        check(sum(1 for g, _ in groups if g == 'contact') == 1, f'{tag}: one &contact')
        per_pitch = 12 if layers == 3 else 16
        n_el = math.ceil(per_pitch * strand['length'] / strand['layers'][0]['pitch'] - 1e-9)
        check({r['n_elements'][0] for r in rods} == {n_el},
              f'{tag}: element counts {sorted({r["n_elements"][0] for r in rods})}, '
              f'expected {n_el} for every rod')
        L = strand['length']
        layer_of = {l['k']: l for l in strand['layers']}
        counts = {}
        for rod in rods:
            check(rod['formulation'] == ['ph_director'] and rod['section'] == ['circle']
                  and rod['contact_radius'] == rod['radius'], f"{tag}: {rod['name']} section")
            if rod['name'][0] == 'core':
                check(rod['geometry'] == ['straight'] and rod['length'] == [L],
                      f'{tag}: core geometry')
                continue
            k, j = (int(x) for x in rod['name'][0][1:].split('_'))
            counts[k] = counts.get(k, 0) + 1
            layer = layer_of[k]
            radius, pitch = rod['helix_radius'][0], rod['helix_pitch'][0]
            turns, phase = rod['helix_turns'][0], rod['helix_phase'][0]
            start, axis = rod['start'], rod['direction']
            psi = 2.0 * math.pi * (j - 1) / layer['n']
            close(radius, layer['radius'], 1e-15, f"{tag}: {rod['name']} radius")
            theta = np.linspace(0.0, 2.0 * math.pi * turns, 97)
            pts = np.array([ms.helix_point(start, axis, radius, pitch, phase, t)
                            for t in theta])
            rho = np.hypot(pts[:, 0], pts[:, 1])
            check(np.max(np.abs(rho - layer['radius'])) < 1e-12 * L,
                  f"{tag}: {rod['name']} leaves its layer radius")
            check(np.allclose(pts[0], [radius * math.cos(psi), radius * math.sin(psi), 0.0],
                              atol=1e-15), f"{tag}: {rod['name']} start")
            close(pts[-1][2], L, 1e-12, f"{tag}: {rod['name']} ends at z = L")
            check(np.all(np.diff(pts[:, 2]) > 0.0), f"{tag}: {rod['name']} does not rise")
            angle = np.unwrap(np.arctan2(pts[:, 1], pts[:, 0]))
            winding = np.sign(angle[-1] - angle[0])
            check(winding == layer['handedness'],
                  f"{tag}: {rod['name']} winds {winding}, layer handedness "
                  f"{layer['handedness']}")
            close(angle[-1] - angle[0], layer['handedness'] * 2.0 * math.pi * L /
                  layer['pitch'], 1e-12, f"{tag}: {rod['name']} turns")
        for k, layer in layer_of.items():
            check(counts.get(k) == 6 * k, f'{tag}: layer {k} has {counts.get(k)} wires')
            # The header's gap against two sampled neighbouring wires of the layer.
            r, p = layer['radius'], layer['pitch']
            brute = sampled_neighbour_distance(r, p, 2.0 * math.pi / layer['n'], min(L, p))
            wire = rods[1]['radius'][0]
            close(brute - 2.0 * wire, layer['gap'], 1e-8, f'{tag}: layer {k} gap')
            if layers > 1:
                check(layer['gap'] > 0.0, f'{tag}: layer {k} overlaps with --core-radius auto')


def test_bending_scene():
    """--pretension, --bend, --mu: the bottom plate pulls along -e_z on a ramp, the top plate
    turns about e_x with the time function and does not pull, &contact has the friction; a
    quasistatic run with friction is refused."""
    argv = ['-', '--layers', '1', '--core-radius', 'auto', '--pull', '6e-5', '--pretension',
            '0.01', '--bend', '0.05', '--time-function', 'sine', '--t-on', '0.01', '--t-off',
            '0.05', '--mu', '0.3', '--slip-velocity', '5e-3', '--dt', '5e-4', '--t-end', '0.09']
    text, _ = ms.scene_text(ms.parse_args(argv), 'make_strand.py ' + ' '.join(argv))
    groups = parse_scene(text)
    plates = {body['name'][0].strip("'"): {k: [value(t) for t in v] for k, v in body.items()}
              for g, body in groups if g == 'plate'}
    bottom, top = plates['bottom'], plates['top']
    check(bottom['displacement'] == [0.0, 0.0, -6e-5] and bottom['time_function'] == ['ramp']
          and bottom['t_off'] == [0.01], f'bending scene: bottom plate {bottom}')
    check(top['displacement'] == [0.0, 0.0, 0.0] and top['rotation'] == [0.05, 0.0, 0.0]
          and top['time_function'] == ['sine'], f'bending scene: top plate {top}')
    contact = [{k: [value(t) for t in v] for k, v in body.items()}
               for g, body in groups if g == 'contact'][0]
    check(contact['mu'] == [0.3] and contact['slip_velocity'] == [5e-3],
          f'bending scene: contact {contact}')
    header = ' '.join(line[2:] for line in text.splitlines() if line.startswith('! '))
    check('friction mu = 0.3' in header and 'bent about e_x' in header, 'bending scene: header')
    refused = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'make_strand.py'), '-',
                              '--mu', '0.3', '--quasistatic'], capture_output=True, text=True)
    check(refused.returncode == 2 and 'dynamic run' in refused.stderr,
          f'make_strand.py --mu --quasistatic: exit {refused.returncode}')


def test_command_lines():
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, 'strand.nml')
        run = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'make_strand.py'), scene,
                              '--layers', '1', '--core-radius', 'auto'],
                             capture_output=True, text=True)
        check(run.returncode == 0 and os.path.getsize(scene) > 1000,
              f'make_strand.py exit {run.returncode}: {run.stderr}')
        check('neighbour gap +0.01000 R' in run.stderr, f'auto core clearance: {run.stderr}')
        bad = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'make_strand.py'), scene,
                              '--lay-angle', '12', '--pitch', '0.1'],
                             capture_output=True, text=True)
        check(bad.returncode == 2 and 'not allowed with' in bad.stderr,
              f'make_strand.py --lay-angle with --pitch: exit {bad.returncode}')
        overlap = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'make_strand.py'), '-'],
                                 capture_output=True, text=True)
        check(overlap.returncode == 0 and 'overlap their neighbours' in overlap.stderr
              and 'WARNING' in overlap.stdout, 'equal radii: the overlap warning')
    for argv in ([], ['--sweep'], ['--penalty', '1e16']):
        run = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'costello_strand.py')]
                             + argv, capture_output=True, text=True)
        check(run.returncode == 0 and ('K_eps' in run.stdout or 'theta_deg' in run.stdout),
              f'costello_strand.py {argv}: exit {run.returncode} {run.stderr}')


def main():
    for test in (test_linearization, test_energy_hessian, test_limits, test_touching,
                 test_contact_load, test_scenes, test_bending_scene, test_command_lines):
        before = len(FAILURES)
        test()
        print(f"{test.__name__}: {'ok' if len(FAILURES) == before else 'FAILED'}")
    for failure in FAILURES:
        print('FAIL:', failure)
    return 1 if FAILURES else 0


if __name__ == '__main__':
    sys.exit(main())
