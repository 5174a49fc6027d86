"""Pre-twist and rest curvature as functions of arc length (issue 26 item 5(c), &rod geometry =
'curvature'): the reference of ph_director, se3_pg and se3_strand integrated from the Darboux
vector kappa(s) = (kappa1, kappa2, kappa3) in the cross-section frame, R' = R hat(kappa),
phi' = d3 (docs/theory/rest_curvature.md). Every reference number is computed here, from the
theory, not read from rodsolve.

    rest_curvature.py stress_free   a constant-curvature coil and a table rod (a jump and a
                        linear stretch) with no load, in each of the three formulations, 20
                        dynamic steps: every node stays put and at rest (round-off, 1e-13 m and
                        1e-11 m/s); with prestressed = .true. (ph_director, se3_strand) the same
                        coil starts with the bending and twisting moments EI kappa of its
                        straight stress-free shape (1e-2 relative: the discrete strains of the
                        elements, O(h^2))
    rest_curvature.py geometry      the nodes of a constant-curvature rod on the closed-form
                        helix (radius kb / |kappa|^2, pitch 2 pi tau / |kappa|^2 about R0 kappa;
                        1e-13 m) and the nodes and directors of a table rod against a fine
                        fourth-order Runge-Kutta integration of R' = R hat(kappa), phi' = d3
                        written here (1e-12), in the three formulations
    rest_curvature.py cantilever_se3_pg, cantilever_ph_director
                        a straight pre-twisted cantilever (kappa = (0, 0, tau), EI1 != EI2,
                        GA1 != GA2) under a small tip force and moment: tip displacement and
                        rotation against the linear small-strain theory by quadrature (module
                        function linear_tip); +load and -load, half the difference, cancel the
                        quadratic geometric terms; two meshes give the order of convergence
    rest_curvature.py spring_se3_pg, spring_ph_director
                        a helical spring of constant rest curvature (kb, 0, tau) under an axial
                        force through its axis: the axial displacement of the axis point and
                        the rotation of the end section about the axis against Love's formulas
                        (which the quadrature reproduces to 1e-12, checked here); and a
                        straight pre-twisted rod under an axial force: extension F L / EA and
                        no twist (a diagonal constitutive law has no extension-twist coupling)

The measured values and bounds are in each check's line; the module docstring of each case
function states them.
"""
import numpy as np

from run_scene import run_cases, run, rod

# ---------------------------------------------------------------------------------------------
# Rotations and the reference geometry, written here.


def hat(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def rotation(w):
    """Rodrigues: exp(hat(w))."""
    angle = np.linalg.norm(w)
    if angle == 0.0:
        return np.eye(3)
    k = hat(w / angle)
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k


def rotation_vector(a):
    """The rotation vector of a rotation matrix (angles below pi)."""
    angle = np.arccos(np.clip(0.5 * (np.trace(a) - 1.0), -1.0, 1.0))
    axial = 0.5 * np.array([a[2, 1] - a[1, 2], a[0, 2] - a[2, 0], a[1, 0] - a[0, 1]])
    if angle < 1e-8:
        return axial
    return angle / np.sin(angle) * axial


def start_frame(direction, d1):
    d3 = np.asarray(direction, float) / np.linalg.norm(direction)
    d1 = np.asarray(d1, float)
    return np.column_stack([d1, np.cross(d3, d1), d3])


def constant_pose(frame0, start, kappa, s):
    """The pose at s of a constant Darboux vector kappa, from rotations about the fixed spatial
    axis a = R0 kappa / |kappa| (module docstring of tests/unit/model/test_rest_curvature.F90):
    R(s) = Rot(a, |kappa| s) R0, phi(s) = phi0 + (a . d3) a s + sin(k s) / k d3_perp
    + (1 - cos(k s)) / k a x d3_perp."""
    k = np.linalg.norm(kappa)
    if k == 0.0:
        return frame0, start + s * frame0[:, 2]
    a = frame0 @ kappa / k
    d3 = frame0[:, 2]
    d3_perp = d3 - (a @ d3) * a
    point = start + (a @ d3) * a * s + np.sin(k * s) / k * d3_perp \
        + (1.0 - np.cos(k * s)) / k * np.cross(a, d3_perp)
    return rotation(k * s * a) @ frame0, point


def table_kappa(rows, s):
    """kappa(s), piecewise linear between the rows (s, k1, k2, k3); at a jump the value after."""
    rows = np.asarray(rows, float)
    j = np.searchsorted(rows[:, 0], s, side="right") - 1
    j = min(max(j, 0), len(rows) - 2)
    a, b = rows[j], rows[j + 1]
    if b[0] == a[0]:
        return b[1:]
    return a[1:] + (b[1:] - a[1:]) * (s - a[0]) / (b[0] - a[0])


def runge_kutta_poses(frame0, start, rows, s_nodes, steps_per_unit=4000):
    """Classical RK4 on R' = R hat(kappa(s)), phi' = R e3, from break to break (the table's s
    and the nodes'), so that kappa is linear inside every stretch; the poses at s_nodes."""
    rows = np.asarray(rows, float)
    breaks = np.unique(np.concatenate([rows[:, 0], s_nodes]))
    frame, point = frame0.copy(), np.asarray(start, float).copy()
    poses = {0.0: (frame.copy(), point.copy())}
    for lo, hi in zip(breaks[:-1], breaks[1:]):
        j = np.flatnonzero((rows[:-1, 0] <= lo) & (rows[1:, 0] > lo))[-1]
        a, b = rows[j], rows[j + 1]

        def rhs(f, t):
            k = a[1:] + (b[1:] - a[1:]) * (t - a[0]) / (b[0] - a[0])
            return f @ hat(k), f[:, 2]
        n = max(1, int(np.ceil((hi - lo) * steps_per_unit)))
        h = (hi - lo) / n
        for i in range(n):
            t0 = lo + i * h
            k1 = rhs(frame, t0)
            k2 = rhs(frame + 0.5 * h * k1[0], t0 + 0.5 * h)
            k3 = rhs(frame + 0.5 * h * k2[0], t0 + 0.5 * h)
            k4 = rhs(frame + h * k3[0], t0 + h)
            point = point + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
            frame = frame + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
        poses[hi] = (frame.copy(), point.copy())
    frames = np.array([poses[min(poses, key=lambda x: abs(x - s))][0] for s in s_nodes])
    points = np.array([poses[min(poses, key=lambda x: abs(x - s))][1] for s in s_nodes])
    return frames, points


# ---------------------------------------------------------------------------------------------
# The linear small-strain theory of a loaded rod with a curved, twisted reference.


def linear_tip(pose, length, c_n, c_m, force, moment, point=None, n_quad=400):
    """Tip displacement and rotation (spatial) of a rod clamped at s = 0 under a tip force F and
    moment M, by Gauss-Legendre quadrature of the linearized Cosserat equations: the section
    wrench is n = F, m(s) = M + (r(L) - r(s)) x F; the spatial strains are
    eps = R C_n^{-1} R^T n (shear and extension) and kap = R C_m^{-1} R^T m (curvature change),
    C_n = diag(GA1, GA2, EA), C_m = diag(EI1, EI2, GJ) in (d1, d2, d3); the rotation obeys
    theta' = kap and the displacement u' = eps + theta x r', which integrate by parts to
    theta(L) = int kap ds and u(L) = int [eps + kap x (r(L) - r(s))] ds. With `point`, the
    displacement of that point rigidly attached to the end section instead:
    u_p = int [eps + kap x (p - r(s))] ds."""
    x, w = np.polynomial.legendre.leggauss(n_quad)
    s, w = 0.5 * length * (x + 1.0), 0.5 * length * w
    tip = pose(length)[1]
    target = tip if point is None else np.asarray(point, float)
    theta = np.zeros(3)
    u = np.zeros(3)
    for si, wi in zip(s, w):
        frame, r = pose(si)
        m = moment + np.cross(tip - r, force)
        eps = frame @ ((frame.T @ force) / c_n)
        kap = frame @ ((frame.T @ m) / c_m)
        theta += wi * kap
        u += wi * (eps + np.cross(kap, target - r))
    return u, theta


def love_spring(force, wire_length, radius, pitch_angle, ea, ga, ei, gj):
    """Love's small-strain helical spring under an axial force F through its axis (circular
    wire): the axial displacement of the axis point and the rotation of the end about the axis,
    derived in the module docstring of spring(): with a the pitch angle and R the radius,
    delta = F l [sin^2 a / EA + cos^2 a / GA + R^2 cos^2 a / GJ + R^2 sin^2 a / EI] and
    phi = F l R sin a cos a (1 / GJ - 1 / EI), positive about the axis the helix rises along."""
    sa, ca = np.sin(pitch_angle), np.cos(pitch_angle)
    delta = force * wire_length * (sa**2 / ea + ca**2 / ga + radius**2 * ca**2 / gj
                                   + radius**2 * sa**2 / ei)
    phi = force * wire_length * radius * sa * ca * (1.0 / gj - 1.0 / ei)
    return delta, phi


# ---------------------------------------------------------------------------------------------
# Scenes.

SCENE = """&run
    title = 'rest curvature and pre-twist (issue 26 item 5(c))'
/
{time}
&solver
    newton_atol = {atol}
/
&output
    path = 'out/rest_curvature.h5'
    stride = {stride}
/
&rod
    name = 'rod'
    formulation = '{formulation}'
    n_elements = {n}
    geometry = 'curvature'
    direction = {direction}
    d1 = {d1}
    {curvature}
    EA = {ea}, GA1 = {ga1}, GA2 = {ga2}, EI1 = {ei1}, EI2 = {ei2}, GJ = {gj}
    rhoA = 1.0, rhoI1 = 0.01, rhoI2 = 0.02
    {extra}
/
{rest}
"""

DYNAMIC = """&time
    t_end = 0.2
    dt = 0.01
/"""

STATIC = """&time
    t_end = 1.0
    dt = 1.0
    quasistatic = .true.
/"""

#: se3_strand has no quasistatics: statics by damped dynamics, the load constant from t = 0
#: (tests/regression/segments.py), stopped far below the strain energy (~1e-10 J here).
RELAXATION = """&time
    t_end = 2000.0
    dt = 0.02
    relaxation = .true.
    kinetic_energy_tol = 1e-32
/"""

DIRECTION = np.array([1.0, 2.0, 2.0]) / 3.0
D1 = np.array([2.0, 1.0, -2.0]) / 3.0
STIFF = dict(ea=1e4, ga1=2e3, ga2=5e3, ei1=1.0, ei2=4.0, gj=1.5)
#: The coil: constant (kappa1, kappa2, kappa3), length 3.
COIL = np.array([1.5, -2.0, 0.7])
COIL_LENGTH = 3.0
#: The table rod: a linear stretch, a jump at s = 1, a constant stretch, another linear one.
TABLE = np.array([[0.0, 0.0, 1.0, 2.0], [1.0, 2.0, -1.0, 0.5], [1.0, -1.0, 0.0, 1.0],
                  [1.5, -1.0, 0.0, 1.0], [2.5, 0.5, 3.0, -2.0]])
FORMULATIONS = ("ph_director", "se3_pg", "se3_strand")


def vector(v):
    return ", ".join(repr(float(x)) for x in v)


def curvature_text(kind):
    if kind == "coil":
        return f"rest_curvature = {vector(COIL)}\n    length = {COIL_LENGTH}"
    return "rest_curvature_table = " + ",\n        ".join(vector(row) for row in TABLE)


def scene(formulation, n, curvature, time=DYNAMIC, rest="", extra="", atol=1e-12,
          stiffness=STIFF, stride=1):
    return SCENE.format(time=time, atol=atol, stride=stride, formulation=formulation, n=n,
                        direction=vector(DIRECTION), d1=vector(D1), curvature=curvature,
                        extra=extra, rest=rest, **stiffness)


def coil_pose(s):
    return constant_pose(start_frame(DIRECTION, D1), np.zeros(3), COIL, s)


# ---------------------------------------------------------------------------------------------
# Cases.


def stress_free(args, checks):
    """A free rod at its curved, twisted reference stays there: the reference strains are the
    discrete strains of the initial nodes in every formulation (measured: 0 for ph_director and
    se3_strand, 6e-15 m and 9e-13 m/s for se3_pg). prestressed = .true. keeps meaning "the
    stress-free shape is straight": the coil then starts with the moments
    C_m kappa = (1.5, -8, 1.05) N m (measured 2.2e-5 relative for ph_director, 1.8e-15 for
    se3_strand's segment logarithms) and moves."""
    for formulation in FORMULATIONS:
        for kind in ("coil", "table"):
            r = rod(run(args, scene(formulation, 12, curvature_text(kind)),
                        f"free_{formulation}_{kind}"), "rod")
            motion = np.max(np.abs(r["position"] - r["position"][0]))
            speed = np.max(np.abs(r["velocity"]))
            checks.check(f"stress-free {kind}, {formulation}: max |phi(t) - phi(0)| [m]",
                         motion, 1e-13)
            # se3_pg's initial accelerations solve M a = residual of the reference, a round-off
            # of the stiffness (EA eps / rhoA ~ 1e-12 m/s^2).
            checks.check(f"stress-free {kind}, {formulation}: max |v| [m/s]", speed, 1e-11)
    moments = np.array([STIFF["ei1"], STIFF["ei2"], STIFF["gj"]]) * COIL
    for formulation in ("ph_director", "se3_strand"):
        r = rod(run(args, scene(formulation, 24, curvature_text("coil"),
                                extra="prestressed = .true."), f"prestressed_{formulation}"), "rod")
        start = r["stress"][0][:, 3:]
        checks.check(f"prestressed coil, {formulation}: max |M(0) - C_m kappa| / |C_m kappa|",
                     np.max(np.abs(start - moments)) / np.linalg.norm(moments), 1e-2)
        motion = np.max(np.abs(r["position"] - r["position"][0]))
        checks.check(f"prestressed coil, {formulation}: it moves, 1e-3 / max |phi(t) - phi(0)|",
                     1e-3 / motion, 1.0)


def geometry(args, checks):
    """The nodes of the coil on the closed-form helix, and the nodes and directors of the table
    rod against fourth-order Runge-Kutta (4000 steps per metre, error ~1e-14), in every
    formulation (the reference is what each places at t = 0)."""
    k = np.linalg.norm(COIL)
    kb, tau = np.linalg.norm(COIL[:2]), COIL[2]
    frame0 = start_frame(DIRECTION, D1)
    axis = frame0 @ COIL / k
    d3_perp = frame0[:, 2] - (axis @ frame0[:, 2]) * axis
    centre = np.cross(axis, d3_perp) / k
    for formulation in FORMULATIONS:
        r = rod(run(args, scene(formulation, 12, curvature_text("coil")), f"coil_{formulation}"),
                "rod")
        x, s = r["position"][0], r["mesh"]
        # Distance from the axis through `centre`, and the rise along it: the helix of radius
        # kb / |kappa|^2 and pitch 2 pi tau / |kappa|^2 (one turn per 2 pi / |kappa| of arc).
        rel = x - centre
        rise = rel @ axis
        radial = np.linalg.norm(rel - np.outer(rise, axis), axis=1)
        checks.check(f"coil, {formulation}: max |distance from the axis - kb / |kappa|^2| [m]",
                     np.max(np.abs(radial - kb / k**2)), 1e-13)
        checks.check(f"coil, {formulation}: max |rise - pitch s |kappa| / (2 pi)| [m]",
                     np.max(np.abs(rise - 2 * np.pi * tau / k**2 * s * k / (2 * np.pi))), 1e-13)
        expected = np.array([coil_pose(si)[1] for si in s])
        checks.check(f"coil, {formulation}: max |phi - closed form| [m]",
                     np.max(np.abs(x - expected)), 1e-13)
        r = rod(run(args, scene(formulation, 10, curvature_text("table")), f"table_{formulation}"),
                "rod")
        s = r["mesh"]
        frames, points = runge_kutta_poses(frame0, np.zeros(3), TABLE, s)
        checks.check(f"table, {formulation}: max |phi - Runge-Kutta| [m]",
                     np.max(np.abs(r["position"][0] - points)), 1e-12)
        directors = np.transpose(r["directors"][0], (0, 2, 1))
        checks.check(f"table, {formulation}: max |d_i - Runge-Kutta|",
                     np.max(np.abs(directors - frames)), 1e-12)



#: The pre-twisted cantilever: half of a turn and a bit (tau = 0.75 pi / m) over L = 1, a tip
#: force and moment of size 1e-4 (tip displacement ~3e-5 m, so the cubic geometric terms that
#: survive the +/- difference are ~1e-8 relative).
TWIST = 0.75 * np.pi
TIP_FORCE = 1e-4 * np.array([0.2, 1.0, -0.5])
TIP_MOMENT = 1e-4 * np.array([0.3, -0.2, 0.4])
#: Softer in shear and extension than STIFF: se3_pg's residual has a rounding floor that grows
#: with EA / h (2e-9 in the 2-norm at 1024 elements here, 2e-8 with STIFF).
CANTILEVER_STIFF = dict(ea=1e3, ga1=2e2, ga2=5e2, ei1=1.0, ei2=4.0, gj=1.5)


def straight_twisted_pose(s):
    return constant_pose(start_frame(DIRECTION, D1), np.zeros(3), np.array([0.0, 0.0, TWIST]), s)


def tip_response(args, formulation, n, curvature, stiffness, force, moment, name, atol,
                 point=None):
    """Half the difference of the static tip displacement (of `point` rigidly attached to the
    end section, if given) and rotation vector under +load and -load, and the cancelled even
    part's size."""
    result = []
    for sign in (1.0, -1.0):
        rest = f"""&bc
    rod = 'rod', end = 'start', kind = 'clamped'
/
&load
    rod = 'rod', where = 'end'
    force = {vector(sign * force)}
    moment = {vector(sign * moment)}
    time_function = 'ramp', t_on = 0.0, t_off = 1.0
/"""
        time, stride = STATIC, 1
        if formulation == "se3_strand":
            # The last record is the relaxed state whatever the stride.
            time, stride = RELAXATION, 100000
            rest = rest.replace("time_function = 'ramp', t_on = 0.0, t_off = 1.0", "")
        r = rod(run(args, scene(formulation, n, curvature, time=time, rest=rest, atol=atol,
                                stiffness=stiffness, stride=stride),
                    f"{name}_{formulation}_{n}_{'plus' if sign > 0 else 'minus'}"), "rod")
        x, d = r["position"], np.transpose(r["directors"], (0, 1, 3, 2))
        turn = d[-1, -1] @ d[0, -1].T
        u = x[-1, -1] - x[0, -1]
        if point is not None:
            u = u + (turn - np.eye(3)) @ (np.asarray(point) - x[0, -1])
        result.append((u, rotation_vector(turn)))
    (u_p, t_p), (u_m, t_m) = result
    return 0.5 * (u_p - u_m), 0.5 * (t_p - t_m)


def cantilever(formulation, meshes, bound, order, atol):
    def case(args, checks):
        """Module docstring; the quadrature is exact to ~1e-15 with 400 points (the integrand
        is smooth)."""
        curvature = f"rest_curvature = 0.0, 0.0, {TWIST!r}\n    length = 1.0"
        c_n = np.array([CANTILEVER_STIFF[k] for k in ("ga1", "ga2", "ea")])
        c_m = np.array([CANTILEVER_STIFF[k] for k in ("ei1", "ei2", "gj")])
        u_ref, t_ref = linear_tip(straight_twisted_pose, 1.0, c_n, c_m, TIP_FORCE, TIP_MOMENT)
        errors = []
        for n in meshes:
            u, theta = tip_response(args, formulation, n, curvature, CANTILEVER_STIFF, TIP_FORCE,
                                    TIP_MOMENT, "cantilever", atol)
            e_u = np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref)
            e_t = np.linalg.norm(theta - t_ref) / np.linalg.norm(t_ref)
            print(f"{formulation}, {n} elements: tip u {u}, theory {u_ref}; rotation {theta}, "
                  f"theory {t_ref}; errors {e_u:.3e}, {e_t:.3e}")
            errors.append(max(e_u, e_t))
        checks.check(f"pre-twisted cantilever, {formulation}, {meshes[-1]} elements: relative "
                     "error of tip displacement and rotation", errors[-1], bound)
        rate = np.log(errors[0] / errors[1]) / np.log(meshes[1] / meshes[0])
        print(f"observed order {rate:.3f}")
        checks.check(f"pre-twisted cantilever, {formulation}: |observed order - {order}|",
                     abs(rate - order), 0.1)
    return case



#: The helical spring: constant kappa = (kb, 0, tau), two turns, a round wire (EI1 = EI2, GA1 =
#: GA2) with GJ != EI, so that the axial force also turns the end (Love).
SPRING_KAPPA = np.array([5.0, 0.0, 2.0])
SPRING_TURNS = 2.0
SPRING_STIFF = dict(ea=1e3, ga1=4e2, ga2=4e2, ei1=1.0, ei2=1.0, gj=0.8)
AXIAL_FORCE = 1e-4


def spring(formulation, meshes, bound, atol, order=None):
    def case(args, checks):
        """The helical spring: d3(0) = `direction`, the spatial Darboux vector R0 kappa fixes
        the axis a; radius R = kb / |kappa|^2, pitch angle alpha with sin alpha = tau / |kappa|
        (the helix rises along a), wire length l = turns 2 pi / |kappa|. A force F a at the end
        with the moment (p - r(L)) x F a, p the point of the axis level with the end, is the
        force F a applied at p. Love's linear answer (derived here: the section moment
        m = F (p - r) x a has length F R, torsion F R cos alpha about d3 and bending
        F R sin alpha; delta = work / F, phi = int kap . a): love_spring(). The quadrature of
        linear_tip() gives the same to 1e-12, which checks both references. The rod's answer
        is the displacement of p, rigidly attached to the end section, along a and the end's
        rotation about a (+F and -F, half the difference). Then a straight rod pre-twisted at
        the same tau under an axial force F d3: extension F L / EA and no twist, because a
        diagonal section law couples nothing (n = F d3 is along d3 in every section)."""
        k = np.linalg.norm(SPRING_KAPPA)
        kb, tau = np.linalg.norm(SPRING_KAPPA[:2]), SPRING_KAPPA[2]
        length = SPRING_TURNS * 2 * np.pi / k
        frame0 = start_frame(DIRECTION, D1)
        axis = frame0 @ SPRING_KAPPA / k
        d3_perp = frame0[:, 2] - (axis @ frame0[:, 2]) * axis
        on_axis = np.cross(axis, d3_perp) / k
        pose = lambda s: constant_pose(frame0, np.zeros(3), SPRING_KAPPA, s)  # noqa: E731
        tip = pose(length)[1]
        p = on_axis + ((tip - on_axis) @ axis) * axis
        force = AXIAL_FORCE * axis
        moment = np.cross(p - tip, force)
        radius, alpha = kb / k**2, np.arcsin(tau / k)
        c_n = np.array([SPRING_STIFF[k] for k in ("ga1", "ga2", "ea")])
        c_m = np.array([SPRING_STIFF[k] for k in ("ei1", "ei2", "gj")])
        delta, phi = love_spring(AXIAL_FORCE, length, radius, alpha, SPRING_STIFF["ea"],
                                 SPRING_STIFF["ga1"], SPRING_STIFF["ei1"], SPRING_STIFF["gj"])
        u_q, t_q = linear_tip(pose, length, c_n, c_m, force, moment, point=p)
        print(f"Love: delta {delta:.15e} m, phi {phi:.15e} rad; quadrature: {u_q @ axis:.15e}, "
              f"{t_q @ axis:.15e}; off the axis {np.linalg.norm(u_q - (u_q @ axis) * axis):.3e} m")
        checks.check("spring: |quadrature - Love| / Love, displacement", abs(u_q @ axis - delta)
                     / delta, 1e-12)
        checks.check("spring: |quadrature - Love| / Love, rotation", abs(t_q @ axis - phi)
                     / abs(phi), 1e-12)
        curvature = f"rest_curvature = {vector(SPRING_KAPPA)}\n    length = {length!r}"
        errors = []
        for n in meshes:
            u, theta = tip_response(args, formulation, n, curvature, SPRING_STIFF, force, moment,
                                    "spring", atol, point=p)
            print(f"{formulation}, {n} elements: delta {u @ axis:.15e}, phi {theta @ axis:.15e}")
            errors.append((abs(u @ axis - delta) / delta, abs(theta @ axis - phi) / abs(phi)))
        checks.check(f"spring, {formulation}, {n} elements: |delta - Love| / Love",
                     errors[-1][0], bound)
        checks.check(f"spring, {formulation}, {n} elements: |phi - Love| / |Love|",
                     errors[-1][1], bound)
        if order is not None:
            rate = np.log(errors[0][1] / errors[1][1]) / np.log(meshes[1] / meshes[0])
            checks.check(f"spring, {formulation}: |observed order of phi - {order}|",
                         abs(rate - order), 0.1)
        # The straight pre-twisted rod under an axial force.
        straight = f"rest_curvature = 0.0, 0.0, {tau!r}\n    length = {length!r}"
        force = AXIAL_FORCE * frame0[:, 2]
        u, theta = tip_response(args, formulation, n, straight, SPRING_STIFF, force,
                                np.zeros(3), "axial", atol)
        stretch = AXIAL_FORCE * length / SPRING_STIFF["ea"]
        print(f"straight pre-twisted rod, {formulation}, {n} elements: u {u}, "
              f"F L / EA {stretch:.15e}, rotation {theta}")
        checks.check(f"straight pre-twisted, {formulation}: |u - F L / EA d3| / (F L / EA)",
                     np.linalg.norm(u - stretch * frame0[:, 2]) / stretch, bound)
        checks.check(f"straight pre-twisted, {formulation}: |rotation| [rad] (no "
                     "extension-twist coupling)", np.linalg.norm(theta), 1e-12)
    return case


if __name__ == "__main__":
    run_cases(__doc__.splitlines()[0], {
        "stress_free": stress_free,
        "geometry": geometry,
        "cantilever_se3_pg": cantilever("se3_pg", (512, 1024), 1e-6, 2.0, 5e-9),
        "cantilever_ph_director": cantilever("ph_director", (16, 32), 1e-6, 4.0, 1e-13),
        "spring_se3_pg": spring("se3_pg", (8,), 1e-8, 1e-12),
        "spring_ph_director": spring("ph_director", (128, 256), 1e-6, 1e-13, 4.0),
        "spring_se3_strand": spring("se3_strand", (8,), 1e-8, 1e-13),
    })
