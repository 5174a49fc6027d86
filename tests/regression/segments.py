"""Rods that vary along their length (issue 26 item 5, &segment): a stepped cantilever.

A straight cantilever of length L = 1, clamped at s = 0, is stiffer on [0, L/2] (EI = 4,
GA = 4000) than on [L/2, L] (EI = 1, GA = 1000; EA = 1000 throughout) and carries a small dead
tip force P = 1e-5 across it. The linear (Timoshenko) tip deflection is computed here from the
piecewise constants, integrating M(s) (L - s) / EI(s) = P (L - s)^2 / EI(s) and P / GA(s):

    delta = P sum_i [(L - a_i)^3 - (L - b_i)^3] / (3 EI_i) + P sum_i (b_i - a_i) / GA_i.

delta / L is 1e-6, so the geometric nonlinearity changes it by about 1e-12 relative. Every
formulation with segments solves the static problem (ph_director, se3_pg, ph_planar and
cl_em_planar quasistatically). ph_director's mixed elements carry the linear moment exactly and
meet it at 8 elements; the two-node elements of the others converge as h^2, checked by the ratio
of the errors at 1024 and 2048 elements (4) and by the error at 2048 (1e-7 measured).
se3_strand solves it by damped dynamics (&time relaxation, stopped at a kinetic energy of
1e-30 J, far below the strain energy P delta / 2 = 6e-12 J): its segment midpoint curvatures
also converge as h^2 (error 4.3e-7 at 1024 segments, ratio 4 to 512).
The dynamic case drops the same load on the stepped rod (ph_director): its energy balance stays
at round-off with the per-element masses and stiffnesses. The free fall drops a free se3_strand
rod whose density steps (rhoA 3 on [0, L/2], 1 beyond): every node falls alike and the linear
momentum is the rod's mass (rhoA_1 + rhoA_2) L / 2 times g t, which holds only if the
per-node masses of the jump keep the total mass.

The tapered cantilever (cases taper_<formulation>): a circular section whose radius falls
linearly from 0.2 to 0.1 over L = 1 (one &segment with radius_end; E = 1000, G = 400), the same
small tip force. Its linear deflection, P int (L - s)^2 / EI(s) ds + P int 1 / GA(s) ds, is
integrated here by 400-point Gauss-Legendre quadrature. Every formulation evaluates the
properties at each element's midpoint, which costs O(h^2): the error at the fine mesh is below
1e-6 (measured 1.55e-7 at 256 elements for the two-node elements and se3_strand, 5.1e-7 at
1024 for ph_director, whose quadratic elements would do better with quadrature-point values)
and falls by 4 when the mesh is halved.
"""
import h5py
import numpy as np

from run_scene import run_cases, run, rod

P = 1.0e-5
L = 1.0
# (a, b, EI, GA) of the two parts.
PARTS = [(0.0, 0.5, 4.0, 4.0e3), (0.5, 1.0, 1.0, 1.0e3)]

SCENE = """&run
    title = 'stepped cantilever (issue 26 item 5)'
/
&time
    t_end = 1.0
    dt = 1.0
    quasistatic = .true.
/
&solver
    newton_atol = {atol}
/
&output
    path = 'out/stepped.h5'
/
&rod
    name = 'beam'
    formulation = '{formulation}'
    n_elements = {n}
    length = 1.0
    EA = 1e3, GA1 = 1e3, GA2 = 1e3, EI1 = 1.0, EI2 = 1.0, GJ = 1.0
    rhoA = 1.0, rhoI1 = 0.01, rhoI2 = 0.01
/
&segment
    rod = 'beam', s_end = 0.5
    EI1 = 4.0, EI2 = 4.0, GA1 = 4e3, GA2 = 4e3
/
&bc
    rod = 'beam', end = 'start', kind = 'clamped'
/
&load
    rod = 'beam', where = 'end'
    force = 0.0, -1e-5, 0.0
    time_function = 'ramp', t_on = 0.0, t_off = 1.0
/
"""


def closed_form():
    """The Timoshenko tip deflection of the stepped cantilever (module docstring)."""
    return sum(P * ((L - a)**3 - (L - b)**3) / (3.0 * ei) + P * (b - a) / ga
               for a, b, ei, ga in PARTS)


# se3_strand has no quasistatics: statics by relaxation (tests/regression/se3_strand/
# selfweight.py), the load constant from t = 0.
RELAXATION = """&time
    t_end = 400.0
    dt = 0.5
    relaxation = .true.
    kinetic_energy_tol = 1e-30
/"""


def scene(formulation, n, atol):
    text = SCENE.format(formulation=formulation, n=n, atol=atol)
    if formulation == "se3_strand":
        start = text.index("&time")
        text = text[:start] + RELAXATION + text[text.index("/", start) + 1:]
        text = text.replace("time_function = 'ramp', t_on = 0.0, t_off = 1.0", "")
    return text


def tip_error(args, formulation, n, atol=1e-12):
    text = scene(formulation, n, atol)
    path = run(args, text, f"{formulation}_{n}")
    tip = -rod(path, "beam")["position"][-1, -1, 1]
    reference = closed_form()
    print(f"{formulation}, {n} elements: tip deflection {tip:.15e}, closed form {reference:.15e}")
    return abs(tip - reference) / reference


def ph_director(args, checks):
    checks.check("ph_director, 8 elements: |delta - closed form| / closed form",
                 tip_error(args, "ph_director", 8), 1e-10)


R0, R1, E_TAPER, G_TAPER = 0.2, 0.1, 1000.0, 400.0


def taper_reference():
    """The tapered cantilever's linear tip deflection by Gauss-Legendre quadrature."""
    x, w = np.polynomial.legendre.leggauss(400)
    s, w = 0.5 * L * (x + 1.0), 0.5 * L * w
    r = R0 + (R1 - R0) * s / L
    ei = E_TAPER * np.pi * r**4 / 4.0
    ga = G_TAPER * np.pi * r**2
    return P * np.sum(w * (L - s)**2 / ei) + P * np.sum(w / ga)


def taper_error(args, formulation, n):
    text = scene(formulation, n, 1e-12)
    start = text.index("&rod")
    end = text.index("&bc")
    text = text[:start] + f"""&rod
    name = 'beam'
    formulation = '{formulation}'
    n_elements = {n}
    length = {L}
    section = 'circle', radius = {R0}, E = {E_TAPER}, G = {G_TAPER}, density = 1.0
/
&segment
    rod = 'beam', s_end = {L}, radius_end = {R1}
/
""" + text[end:]
    path = run(args, text, f"taper_{formulation}_{n}")
    tip = -rod(path, "beam")["position"][-1, -1, 1]
    reference = taper_reference()
    print(f"tapered, {formulation}, {n} elements: tip deflection {tip:.15e}, quadrature "
          f"{reference:.15e}")
    return abs(tip - reference) / reference


def tapered(formulation, n):
    def case(args, checks):
        coarse = taper_error(args, formulation, n // 2)
        fine = taper_error(args, formulation, n)
        checks.check(f"tapered, {formulation}, {n} elements: |delta - quadrature| / quadrature",
                     fine, 1e-6)
        checks.check(f"tapered, {formulation}: |error({n // 2}) / error({n}) - 4| (order 2)",
                     abs(coarse / fine - 4.0), 0.05)
    return case


def converging(formulation, n=2048):
    def case(args, checks):
        # The max-norm residual of 2048 stiff elements bottoms out near 1e-12.
        coarse = tip_error(args, formulation, n // 2, 1e-11)
        fine = tip_error(args, formulation, n, 1e-11)
        checks.check(f"{formulation}, {n} elements: |delta - closed form| / closed form",
                     fine, 1e-6)
        checks.check(f"{formulation}: |error({n // 2}) / error({n}) - 4| (order 2)",
                     abs(coarse / fine - 4.0), 0.05)
    return case


def free_fall(args, checks):
    """A free se3_strand rod with a density step falls under gravity (module docstring)."""
    g, rho_a = 9.81, (3.0, 1.0)
    text = SCENE.format(formulation="se3_strand", n=8, atol=1e-12)
    start = text.index("&time")
    text = text[:start] + "&time\n    t_end = 0.1\n    dt = 0.01\n/" + text[text.index("/", start) + 1:]
    start = text.index("&bc")
    text = text[:start] + text[text.index("/", start) + 1:]
    start = text.index("&load")
    text = text[:start] + ("&load\n    rod = 'beam', where = 'gravity'\n"
                           f"    acceleration = 0.0, 0.0, {-g}\n/\n")
    text = text.replace("EI1 = 4.0, EI2 = 4.0", f"rhoA = {rho_a[0]}, EI1 = 4.0, EI2 = 4.0")
    path = run(args, text, "free_fall")
    with h5py.File(path, "r") as f:
        t = f["series/time"][()]
        linear = f["series/momentum/linear"][()]
    mass = 0.5 * L * sum(rho_a)
    expected = mass * g * t
    print(f"free fall: linear momentum z at t = {t[-1]}: {linear[-1, 2]:.15e}, "
          f"-m g t = {-expected[-1]:.15e}")
    checks.check("free fall, se3_strand with a density step: max |l_z + m g t| / (m g t_end)",
                 np.max(np.abs(linear[:, 2] + expected)) / expected[-1], 1e-14)


def dynamic(args, checks):
    """The tip force switched on at t = 0 on the stepped rod at rest: the balance of H with the
    load's work stays at round-off (ph_director's exact discrete energy balance)."""
    text = SCENE.format(formulation="ph_director", n=8, atol=1e-12)
    text = text.replace("quasistatic = .true.", "").replace("t_end = 1.0\n    dt = 1.0",
                                                             "t_end = 0.5\n    dt = 0.01")
    text = text.replace("time_function = 'ramp', t_on = 0.0, t_off = 1.0", "")
    path = run(args, text, "dynamic")
    with h5py.File(path, "r") as f:
        total = f["series/energy/total"][()]
        work = f["series/energy/external_work"][()]
        balance = f["series/energy/balance_error"][()]
    scale = max(np.max(np.abs(total)), np.max(np.abs(work)))
    checks.check("dynamic, ph_director: max |balance_error| / max(|H|, |W|)",
                 np.max(np.abs(balance)) / scale, 1e-13)
    # A constant dead force does the work P times the tip's displacement along it (the
    # series holds the work of each record interval).
    tip = -rod(path, "beam")["position"][:, -1, 1]
    checks.check("dynamic, ph_director: max |W - P delta_tip| / max |W|",
                 np.max(np.abs(np.cumsum(work) - P * tip)) / np.max(np.abs(np.cumsum(work))), 1e-13)


if __name__ == "__main__":
    run_cases(__doc__.splitlines()[0], {
        "ph_director": ph_director,
        "se3_pg": converging("se3_pg"),
        "ph_planar": converging("ph_planar"),
        "cl_em_planar": converging("cl_em_planar"),
        "se3_strand": converging("se3_strand", 1024),
        "free_fall": free_fall,
        "taper_ph_director": tapered("ph_director", 1024),
        "taper_se3_pg": tapered("se3_pg", 256),
        "taper_ph_planar": tapered("ph_planar", 256),
        "taper_cl_em_planar": tapered("cl_em_planar", 256),
        "taper_se3_strand": tapered("se3_strand", 256),
        "dynamic": dynamic,
    })
