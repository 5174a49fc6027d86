#!/usr/bin/env python3
"""Write a rodsolve scene of a straight multi-layer strand: a core wire and helical layers.

Layer k >= 1 has 6 k wires of radius R on the helix radius r_k = R_core + (2 k - 1) R (each layer
rests on the one below), at the phases 2 pi j / (6 k), j = 0 .. 6 k - 1, all with one lay angle
(--lay-angle) or one pitch (--pitch); the layers are right-handed unless --left (all left) or
--alternate (layer 1 as chosen, then alternating). All wires are ph_director rods whose helical
reference is stress-free, tied at z = 0 to the fixed plate 'bottom' and at z = L to the plate
'top', which is pulled along the axis (--pull, m), turned about it (--twist, rad) and bent
about e_x (--bend, rad) with a time function; with --pretension T the bottom plate pulls
instead, ramped over [0, T] (a strand under tension, then bent or twisted by the top plate).
&contact couples all wires (no self contact), with friction --mu. docs/theory/bundles.md,
"Strand geometry", describes what is built and which wires touch.

    python3 scripts/make_strand.py SCENE.nml [--layers 1..5] [--wire-radius R]
        [--core-radius R_core|auto] [--lay-angle DEG | --pitch P] [--length L]
        [--elements-per-wire N | --elements-per-pitch M] [--E ..] [--nu ..] [--density ..]
        [--stiffness K] [--margin ..] [--mu ..] [--slip-velocity ..] [--dt ..] [--t-end ..]
        [--pull ..] [--twist ..] [--bend ..] [--pretension T] [--time-function ramp]
        [--quasistatic] [--output PATH] [--title ..] [--left|--alternate]

SCENE '-' writes to standard output. The geometry is reported on standard error (and in the
scene's header), with a warning when the wires of a layer overlap their neighbours.

Helix encoding (src/model/rod_geometry.f90, docs/user/input.md, &rod helix_phase): a helix of
axis a starts at `start`, its axis passes through start - r (cos phi u + sin phi w) (u the
default normal of a, e_x for a = +-e_z, w = a x u, phi = helix_phase) and it rises by
helix_pitch / (2 pi) along a per radian, right-handed about a for helix_pitch > 0. A
right-handed wire at the angle psi is therefore direction = e_z, helix_pitch = p,
helix_phase = psi; a LEFT-handed wire that still rises from z = 0 to z = L needs
direction = -e_z and helix_pitch = -p (a negative pitch about +e_z would descend), and then
w = -e_y, so helix_phase = -psi (helix_rod_parameters).

Plain text only: no rodsolve import. For a single layer the header states the Costello
reference (scripts/costello_strand.py, imported from this directory when numpy is present).
"""

import argparse
import math
import os
import sys
import textwrap

AXIS = (0.0, 0.0, 1.0)
# A gap above -1e-12 R is touching (straight wires of layer 1 on a core of radius R: 0 up to
# round-off), not an overlap.
OVERLAP_TOL = 1e-12


def fmt(x):
    """Shortest text that reads back to the float x (namelist real)."""
    x = float(x)
    if x == 0.0:
        return '0.0'
    candidates = [repr(x)]
    for digits in range(1, 18):
        text = f'{x:.{digits}g}'
        if float(text) == x:
            candidates.append(text)
            break
    text = min(candidates, key=len)
    if not any(ch in text for ch in '.en'):
        text += '.0'
    return text


def vec(v):
    return ', '.join(fmt(c) for c in v)


def default_normal(a):
    """rs_model_rod_geometry default_normal: e_z x a normalized, e_x when a is along e_z."""
    n = (-a[1], a[0], 0.0)
    norm = math.hypot(n[0], n[1])
    if norm < 1e-8:
        return (1.0, 0.0, 0.0)
    return (n[0] / norm, n[1] / norm, 0.0)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def helix_rod_parameters(radius, pitch, psi, handedness):
    """&rod helix variables of a wire on the helix of radius `radius` about the z axis,
    rising by pitch > 0 per turn from z = 0, starting at the angle psi (from e_x towards e_y),
    right-handed (+1) or left-handed (-1): dict(start, direction, helix_pitch, helix_phase)."""
    start = (radius * math.cos(psi), radius * math.sin(psi), 0.0)
    if handedness > 0:
        return dict(start=start, direction=AXIS, helix_pitch=pitch,
                    helix_phase=math.remainder(psi, 2.0 * math.pi))
    return dict(start=start, direction=(0.0, 0.0, -1.0), helix_pitch=-pitch,
                helix_phase=math.remainder(-psi, 2.0 * math.pi))


def helix_point(start, direction, radius, pitch, phase, theta):
    """The centreline of an &rod helix at the helix angle theta (a mirror of
    rs_model_rod_geometry with helix_phase, for checks): axis point + r (cos(theta + phi) u
    + sin(theta + phi) w) + pitch theta / (2 pi) a."""
    u = default_normal(direction)
    w = cross(direction, u)
    centre = [start[i] - radius * (math.cos(phase) * u[i] + math.sin(phase) * w[i])
              for i in range(3)]
    return tuple(centre[i] + radius * (math.cos(theta + phase) * u[i]
                                       + math.sin(theta + phase) * w[i])
                 + pitch * theta / (2.0 * math.pi) * direction[i] for i in range(3))


def neighbour_distance(radius, pitch, n_wires):
    """Minimum distance between the centrelines of two neighbouring wires of one layer: two
    helices of equal radius r and pitch P = 2 pi b, phases 2 pi / n apart. With u the
    difference of their helix angles, d^2(u) = 2 r^2 (1 - cos(u - D)) + b^2 u^2 (D = 2 pi / n);
    the minimum lies in [0, D] (the parabola and the periodic term both decrease towards it)
    and is found on a grid refined by golden sections. pitch = inf: straight wires."""
    spacing = 2.0 * math.pi / n_wires
    if math.isinf(pitch):
        return 2.0 * radius * math.sin(0.5 * spacing)
    b = abs(pitch) / (2.0 * math.pi)

    def d2(u):
        return 2.0 * radius**2 * (1.0 - math.cos(u - spacing)) + (b * u)**2

    grid = [spacing * i / 400.0 for i in range(401)]
    i_min = min(range(len(grid)), key=lambda i: d2(grid[i]))
    lo, hi = grid[max(i_min - 1, 0)], grid[min(i_min + 1, len(grid) - 1)]
    ratio = 0.5 * (math.sqrt(5.0) - 1.0)
    for _ in range(100):
        a, c = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
        if d2(a) < d2(c):
            hi = c
        else:
            lo = a
    return math.sqrt(d2(0.5 * (lo + hi)))


def layer_pitch(radius, lay_angle=None, pitch=None):
    """Pitch of a layer from its lay angle (rad) or the given pitch (m)."""
    if pitch is not None:
        return pitch
    if lay_angle == 0.0:
        return math.inf
    return 2.0 * math.pi * radius / math.tan(lay_angle)


def layout(layers, wire_radius, core_radius, lay_angle=None, pitch=None, first=1,
           alternate=False):
    """The layers: list of dict(k, n, radius, pitch, lay_angle, handedness, gap) where gap is
    the minimum centreline distance of neighbouring wires minus 2 R (< 0: they overlap)."""
    out = []
    for k in range(1, layers + 1):
        r = core_radius + (2 * k - 1) * wire_radius
        p = layer_pitch(r, lay_angle, pitch)
        hand = first * (-1)**(k - 1) if alternate else first
        theta = math.atan(2.0 * math.pi * r / p) if not math.isinf(p) else 0.0
        gap = neighbour_distance(r, p, 6 * k) - 2.0 * wire_radius
        out.append(dict(k=k, n=6 * k, radius=r, pitch=p, lay_angle=theta, handedness=hand,
                        gap=gap))
    return out


def auto_core_radius(layers, wire_radius, lay_angle=None, pitch=None, clearance=0.01):
    """Smallest core radius >= R for which every layer's neighbours are at least
    clearance * R apart (the gap grows with the core radius: bisection)."""
    def worst(rc):
        return min(l['gap'] for l in layout(layers, wire_radius, rc, lay_angle, pitch))
    target = clearance * wire_radius
    lo = wire_radius
    if worst(lo) >= target:
        return lo
    hi = 2.0 * wire_radius
    while worst(hi) < target:
        hi *= 2.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if worst(mid) < target:
            lo = mid
        else:
            hi = mid
    return hi


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('scene', help="scene file to write ('-': standard output)")
    p.add_argument('--layers', type=int, default=1, choices=(1, 2, 3, 4, 5),
                   help='helical layers: 1 -> 7 wires, 2 -> 19, 3 -> 37, 4 -> 61, 5 -> 91')
    p.add_argument('--wire-radius', type=float, default=1e-3, help='R of every wire (m)')
    p.add_argument('--core-radius', default=None,
                   help="core radius (m), or 'auto': the smallest >= R that keeps the wires "
                        "of every layer --clearance apart; default R")
    p.add_argument('--clearance', type=float, default=0.01,
                   help="gap of neighbouring wires of a layer, in R, for --core-radius auto")
    angle = p.add_mutually_exclusive_group()
    angle.add_argument('--lay-angle', type=float, default=None,
                       help='lay angle of every layer (deg, wire against axis); default 12')
    angle.add_argument('--pitch', type=float, default=None,
                       help='pitch of every layer (m): lay length, equal for all layers')
    p.add_argument('--length', type=float, default=None,
                   help='strand length along the axis (m); default one pitch of layer 1')
    mesh = p.add_mutually_exclusive_group()
    mesh.add_argument('--elements-per-wire', type=int, default=None,
                      help='elements of every rod')
    mesh.add_argument('--elements-per-pitch', type=float, default=None,
                      help='elements of every rod per pitch of layer 1 along the axis '
                           '(straight wires: 16 in all); default 16')
    p.add_argument('--E', type=float, default=200e9, help="Young's modulus (Pa)")
    p.add_argument('--nu', type=float, default=0.3, help="Poisson's ratio")
    p.add_argument('--density', type=float, default=7800.0, help='kg/m^3')
    p.add_argument('--stiffness', type=float, default=1e15,
                   help='&contact penalty stiffness k (N/m^3)')
    p.add_argument('--margin', type=float, default=None,
                   help='&contact broad-phase margin (m); default the wire radius')
    p.add_argument('--dt', type=float, default=0.05, help='time step (s; load step)')
    p.add_argument('--t-end', type=float, default=1.0, help='end time (s; load factor)')
    p.add_argument('--pull', type=float, default=None,
                   help='axial displacement of the top plate at f = 1 (m); default 1e-3 L')
    p.add_argument('--twist', type=float, default=0.0,
                   help='rotation of the top plate about the axis at f = 1 (rad)')
    p.add_argument('--bend', type=float, default=0.0,
                   help='rotation of the top plate about e_x at f = 1 (rad): bending')
    p.add_argument('--pretension', type=float, default=None, metavar='T',
                   help='the bottom plate pulls (by --pull, away from the top), ramped over '
                        '[0, T]; the top plate then only turns (--twist, --bend)')
    p.add_argument('--mu', type=float, default=0.0,
                   help='&contact friction coefficient (0: frictionless)')
    p.add_argument('--slip-velocity', type=float, default=None,
                   help='&contact slip_velocity (m/s) of the regularized friction')
    p.add_argument('--time-function', default='ramp',
                   choices=('ramp', 'hat', 'pulse', 'sine', 'constant'),
                   help='time function of the top plate')
    p.add_argument('--t-on', type=float, default=0.0, help='start of the time function (s)')
    p.add_argument('--t-off', type=float, default=None,
                   help='end of the time function (s); default t_end')
    p.add_argument('--quasistatic', action='store_true', help='static load stepping')
    p.add_argument('--newton-atol', type=float, default=1e-10, help='&solver newton_atol')
    p.add_argument('--condense-stresses', action='store_true', help='&solver condense_stresses')
    p.add_argument('--output', default=None, help='&output path (default: rodsolve default)')
    p.add_argument('--stride', type=int, default=1, help='&output stride')
    p.add_argument('--title', default=None, help='&run title')
    hand = p.add_mutually_exclusive_group()
    hand.add_argument('--left', action='store_true', help='all layers left-handed')
    hand.add_argument('--alternate', action='store_true',
                      help='layers alternately right- and left-handed (layer 1 right)')
    args = p.parse_args(argv)
    if args.wire_radius <= 0.0:
        p.error('--wire-radius must be > 0')
    if args.lay_angle is None and args.pitch is None:
        args.lay_angle = 12.0
    if args.lay_angle is not None and not 0.0 <= args.lay_angle < 90.0:
        p.error('--lay-angle must lie in [0, 90) degrees')
    if args.pitch is not None and args.pitch <= 0.0:
        p.error('--pitch must be > 0')
    if args.core_radius not in (None, 'auto'):
        try:
            args.core_radius = float(args.core_radius)
        except ValueError:
            p.error("--core-radius takes a length or 'auto'")
        if args.core_radius <= 0.0:
            p.error('--core-radius must be > 0')
    if args.time_function == 'constant' and (args.twist or args.bend or
                                             (args.pull and args.pretension is None)):
        p.error("a driven plate starts at its reference pose: --time-function 'constant' "
                'cannot pull, twist or bend')
    if args.pretension is not None and args.pretension <= 0.0:
        p.error('--pretension must be > 0 (the end of the ramp, s)')
    if args.mu < 0.0:
        p.error('--mu must be >= 0')
    if args.mu > 0.0 and args.quasistatic:
        p.error('friction (--mu) needs a dynamic run (rodsolve refuses it in a quasistatic one)')
    return args


def build(args):
    """The strand: dict(core_radius, length, layers, rods) from parsed arguments."""
    R = args.wire_radius
    theta = math.radians(args.lay_angle) if args.lay_angle is not None else None
    if args.core_radius == 'auto':
        core = auto_core_radius(args.layers, R, theta, args.pitch, args.clearance)
    else:
        core = args.core_radius if args.core_radius is not None else R
    first = -1 if args.left else 1
    layers = layout(args.layers, R, core, theta, args.pitch, first, args.alternate)
    length = args.length
    if length is None:
        length = layers[0]['pitch']
        if math.isinf(length):
            raise SystemExit('make_strand.py: straight wires (lay angle 0) need --length')
    if length <= 0.0:
        raise SystemExit('make_strand.py: --length must be > 0')
    rods = []
    if args.elements_per_wire is not None:
        n_el = args.elements_per_wire
    else:
        # One element length along the axis for every rod: the pitch of layer 1 over M (so an
        # outer layer, with a longer pitch, gets more elements per turn).
        p1 = layers[0]['pitch']
        per_pitch = args.elements_per_pitch or 16.0
        n_el = max(2, math.ceil(per_pitch * length / p1 - 1e-9)) if not math.isinf(p1) else 16
    rods.append(dict(name='core', geometry='straight', radius=core, n_elements=n_el))
    for layer in layers:
        turns = length / layer['pitch']
        for j in range(layer['n']):
            psi = 2.0 * math.pi * j / layer['n']
            rod = dict(name=f"w{layer['k']}_{j + 1}", geometry='helix', radius=R,
                       n_elements=n_el, layer=layer['k'], psi=psi,
                       helix_radius=layer['radius'], turns=turns,
                       handedness=layer['handedness'])
            if math.isinf(layer['pitch']):
                rod['geometry'] = 'straight'
                rod['start'] = (layer['radius'] * math.cos(psi),
                                layer['radius'] * math.sin(psi), 0.0)
            else:
                rod.update(helix_rod_parameters(layer['radius'], layer['pitch'], psi,
                                                layer['handedness']))
            rods.append(rod)
    return dict(core_radius=core, length=length, layers=layers, rods=rods)


def comment(*paragraphs):
    """Comment lines ('! ...') of the paragraphs, wrapped below 100 characters."""
    out = []
    for paragraph in paragraphs:
        out += ['! ' + line for line in textwrap.wrap(paragraph, 94, break_on_hyphens=False)]
    return out


def _costello_lines(args, strand, pull):
    """Header lines with Costello's reference for a 1+6 strand (empty if numpy is missing)."""
    if len(strand['layers']) != 1 or strand['layers'][0]['lay_angle'] == 0.0:
        return []
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    try:
        import costello_strand as cs
    except ImportError:
        return comment('(Costello reference not computed: scripts/costello_strand.py needs '
                       'numpy.)')
    R1, R2 = strand['core_radius'], args.wire_radius
    layer = strand['layers'][0]
    theta, L = layer['lay_angle'], strand['length']
    eps = pull / L
    full = cs.costello_axial_stiffness(R1, R2, theta, args.E, args.nu,
                                       handedness=layer['handedness'])
    model = cs.costello_axial_stiffness(R1, R2, theta, args.E, args.nu,
                                        poisson_contraction=False,
                                        curvature_measure='reference',
                                        handedness=layer['handedness'])
    text = [
        f"Reference (scripts/costello_strand.py; docs/theory/bundles.md, \"Reference: "
        f"Costello's strand theory\"), rotation held, strand strain eps = pull / L = "
        f"{eps:.6g}:",
        f"Costello (Poisson contraction, wire bending and torsion): K_eps = "
        f"{full['K_eps']:.6e} N, F = {full['K_eps'] * eps:.6e} N, M = "
        f"{full['K_m'] * eps:.6e} N m about e_z;",
        f"the rod model's kinematics (no Poisson contraction, strains per reference length, "
        f"rigid contact): K_eps = {model['K_eps']:.6e} N, F = {model['K_eps'] * eps:.6e} N, "
        f"M = {model['K_m'] * eps:.6e} N m;",
        f"E (A1 + 6 A2 cos^3 theta) = {full['K_simple']:.6e} N."]
    if args.twist or args.bend:
        text.append('(These are for the pull alone; the scene also turns the top plate.)')
    if args.stiffness and eps > 0.0:
        try:
            K, delta, _ = cs.penalty_secant_stiffness(R1, R2, theta, args.E, args.nu,
                                                      args.stiffness, eps)
            text.append(f"With the penalty k = {fmt(args.stiffness)} N/m^3 the helical wires "
                        f"sink about {delta:.3e} m into the core (continuous line contact): "
                        f"secant K = {K:.6e} N ({K / model['K_eps'] - 1.0:+.2%} against the "
                        f"rigid-contact value).")
        except ValueError as err:
            text.append(f'Penalty estimate failed: {err}.')
    return comment(*text)


def _plates_sentence(args):
    """How the plates move, for the header."""
    motions = [what for what, on in (('turned about the axis', args.twist),
                                     ('bent about e_x', args.bend)) if on]
    if args.pretension is not None:
        return ("tied at z = 0 to the plate 'bottom', which pulls the strand (a ramp to t = "
                f"{fmt(args.pretension)} s), and at z = L to the plate 'top'"
                + (', which is ' + ' and '.join(motions) if motions else ', which is held'))
    return ("tied at z = 0 to the fixed plate 'bottom' and at z = L to the plate 'top', which "
            "is pulled along the axis" + ''.join(', ' + m for m in motions))


def scene_text(args, command=None):
    """The scene file text and the strand of build()."""
    strand = build(args)
    R, L, core = args.wire_radius, strand['length'], strand['core_radius']
    n_rods = len(strand['rods'])
    pull = args.pull if args.pull is not None else 1e-3 * L
    t_off = args.t_off if args.t_off is not None else args.t_end
    title = args.title or (f"{'1+' + '+'.join(str(l['n']) for l in strand['layers'])} strand "
                           f"({n_rods} wires) pulled by end plates")
    hands = {1: 'right', -1: 'left'}
    lines = comment(
        f"{title}: a straight core wire and {len(strand['layers'])} helical layer(s) of "
        "ph_director wires with stress-free helical references, "
        + _plates_sentence(args) + ("; frictionless penalty contact between the wires "
                                    if args.mu == 0.0 else
                                    f"; penalty contact between the wires with friction mu = "
                                    f"{fmt(args.mu)} ")
        + "(docs/theory/bundles.md, \"Strand geometry\").",
        'Generated by scripts/make_strand.py' + (f': {command}' if command else '') + '.',
        f"Settings the results depend on: wire radius R = {fmt(R)} m, core radius {fmt(core)} "
        f"m, length L = {fmt(L)} m, E = {fmt(args.E)} Pa, nu = {fmt(args.nu)}, contact "
        f"stiffness {fmt(args.stiffness)} N/m^3, Newton tolerance {fmt(args.newton_atol)}, "
        f"dt = {fmt(args.dt)}, pull {fmt(pull)} m, twist {fmt(args.twist)} rad, bend "
        f"{fmt(args.bend)} rad.")
    lines.append('! layer  wires  helix radius (m)  lay angle (deg)  pitch (m)   hand  turns  '
                 'gap (R)')
    for layer in strand['layers']:
        lines.append(
            f"! {layer['k']:5d}  {layer['n']:5d}  {layer['radius']:16.9g}  "
            f"{math.degrees(layer['lay_angle']):15.6f}  {layer['pitch']:9.6g}  "
            f"{hands[layer['handedness']]:>5s}  {L / layer['pitch']:5.3f}  "
            f"{layer['gap'] / R:+.5f}")
    lines += comment('gap: the smallest distance between the centrelines of neighbouring '
                     'wires of a layer minus 2 R.')
    overlapping = [l['k'] for l in strand['layers'] if l['gap'] < -OVERLAP_TOL * R]
    if overlapping:
        lines += comment(f'WARNING: the wires of layer(s) {overlapping} overlap their '
                         'neighbours (negative gap): contact acts on the reference, which is '
                         'then not stress-free (--core-radius auto separates them).')
    lines += _costello_lines(args, strand, pull)
    lines += comment('Expected: the axial force on the top plate F = K_eps pull / L to the '
                     'agreement stated in docs/theory/bundles.md (penalty penetration, end '
                     'effects, mesh); no wire penetrates another by more than the stated '
                     'tolerance.')
    lines += ['&run', f"    title = '{title}'", '/', '&time', f'    t_end = {fmt(args.t_end)}',
              f'    dt = {fmt(args.dt)}']
    if args.quasistatic:
        lines.append('    quasistatic = .true.')
    lines += ['/', '&solver', f'    newton_atol = {fmt(args.newton_atol)}']
    if args.condense_stresses:
        lines.append('    condense_stresses = .true.')
    lines += ['/', '&output']
    if args.output:
        lines.append(f"    path = '{args.output}'")
    lines += [f'    stride = {args.stride}', '/']
    material = (f"    section = 'circle', radius = {{r}}, contact_radius = {{r}}\n"
                f"    E = {fmt(args.E)}, nu = {fmt(args.nu)}, density = {fmt(args.density)}")
    for rod in strand['rods']:
        lines += ['&rod', f"    name = '{rod['name']}'", "    formulation = 'ph_director'",
                  f"    geometry = '{rod['geometry']}'"]
        if rod['name'] == 'core':
            lines += ['    start = 0.0, 0.0, 0.0', f'    direction = {vec(AXIS)}',
                      f'    length = {fmt(L)}']
        elif rod['geometry'] == 'straight':
            lines += [f"    start = {vec(rod['start'])}", f'    direction = {vec(AXIS)}',
                      f'    length = {fmt(L)}']
        else:
            lines += [f"    start = {vec(rod['start'])}",
                      f"    direction = {vec(rod['direction'])}"
                      + ('    ! left-handed: axis -e_z, pitch < 0, rises along e_z'
                         if rod['handedness'] < 0
                         else ''),
                      f"    helix_radius = {fmt(rod['helix_radius'])}, "
                      f"helix_pitch = {fmt(rod['helix_pitch'])}",
                      f"    helix_turns = {fmt(rod['turns'])}, "
                      f"helix_phase = {fmt(rod['helix_phase'])}"]
        lines.append(f"    n_elements = {rod['n_elements']}")
        lines.append(material.format(r=fmt(rod['radius'])))
        lines.append('/')
    names = [f"'{rod['name']}'" for rod in strand['rods']]
    chunks = [', '.join(names[i:i + 8]) for i in range(0, len(names), 8)]
    rod_list = ',\n         '.join(chunks)
    lines += ['&plate', "    name = 'bottom'", f'    rods = {rod_list}', "    end = 'start'"]
    top_pull = pull
    if args.pretension is not None:
        lines += ['    centre = 0.0, 0.0, 0.0', f'    displacement = 0.0, 0.0, {fmt(-pull)}',
                  f"    time_function = 'ramp', t_on = 0.0, t_off = {fmt(args.pretension)}"]
        top_pull = 0.0
    lines += ['/', '&plate', "    name = 'top'", f'    rods = {rod_list}', "    end = 'end'",
              f'    centre = 0.0, 0.0, {fmt(L)}',
              f'    displacement = 0.0, 0.0, {fmt(top_pull)}',
              f'    rotation = {fmt(args.bend)}, 0.0, {fmt(args.twist)}',
              f"    time_function = '{args.time_function}'"]
    if args.time_function != 'constant':
        lines.append(f'    t_on = {fmt(args.t_on)}, t_off = {fmt(t_off)}')
    lines += ['/', '&contact', f'    stiffness = {fmt(args.stiffness)}',
              f'    margin = {fmt(args.margin if args.margin is not None else R)}',
              '    self_contact = .false.']
    if args.mu > 0.0:
        lines.append(f'    mu = {fmt(args.mu)}' + (f', slip_velocity = {fmt(args.slip_velocity)}'
                                                   if args.slip_velocity is not None else ''))
    lines += ['/']
    return '\n'.join(lines) + '\n', strand


def main(argv=None):
    args = parse_args(argv)
    command = 'make_strand.py ' + ' '.join(sys.argv[1:] if argv is None else argv)
    text, strand = scene_text(args, command)
    for layer in strand['layers']:
        print(f"layer {layer['k']}: {layer['n']} wires on r = {layer['radius']:.6g} m, lay "
              f"angle {math.degrees(layer['lay_angle']):.4f} deg, pitch {layer['pitch']:.6g} m, "
              f"neighbour gap {layer['gap'] / args.wire_radius:+.5f} R", file=sys.stderr)
        if layer['gap'] < -OVERLAP_TOL * args.wire_radius:
            print(f"make_strand.py: warning: the wires of layer {layer['k']} overlap their "
                  'neighbours; --core-radius auto separates them', file=sys.stderr)
    if args.scene == '-':
        sys.stdout.write(text)
    else:
        with open(args.scene, 'w', encoding='utf-8') as handle:
            handle.write(text)
    return 0


if __name__ == '__main__':
    sys.exit(main())
