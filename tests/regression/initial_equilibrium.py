"""The initial equilibrium of a dynamic run (issue 26 item 3, &time initial_equilibrium;
docs/theory/prestretched_starts.md) in every formulation that has it, on a prestrained rod.

    <formulation>    two scenes, each started in its static equilibrium under gravity:
                     - a bar hanging from a clamp, placed straight, vertical and stretched by
                       eps = 1e-3 beyond its stress-free length L0 = 1 (so its equilibrium
                       position is neither the placement nor the stress-free rod): it stays
                       straight, and with Simo-Reissner's axial law N = EA (stretch - 1) its
                       node at stress-free arc length S hangs at depth S + w (L0 S - S^2 / 2) /
                       EA (w = rhoA g), computed here; two-node elements and ph_director's
                       quadratic ones are exact at the nodes for this one-dimensional problem
                       with the consistent load, so every node within 1e-10 L0 (measured at
                       round-off: 1e-16 to 5e-16);
                     - a prestrained cantilever bent by gravity (tip deflection 0.34 L, well
                       into the nonlinear range): its initial equilibrium against the endpoint
                       equilibrium of the same scene run quasistatically (&time quasistatic,
                       gravity ramped: another path to the same static problem, whose
                       equations are the same), every nodal coordinate within 1e-8 L0
                       (Newton tolerance 1e-10 on forces of order 1; measured 2.5e-12 for
                       ph_director, 1.2e-13 and below for the others);
                     and both, run on for 100 steps with nothing changing, stay at rest: the
                     largest nodal speed below 1e-10 m/s (the speed scale of these scenes,
                     sqrt(g L0) = 1.7 m/s; measured 0). se3_pg also with generalized-alpha
                     (rho_inf = 0.8), whose history the equilibrium sets to that of rest.
"""
import numpy as np

from run_scene import run_cases, run, rod

EA = 1.0e4
RHO_A = 1.0
G = 3.0
EPS = 1.0e-3

SCENE = """&run
    title = 'initial equilibrium (issue 26 item 3)'
/
&time
{time}
/
&output
    path = 'out/initial_equilibrium.h5'
/
&rod
    name = 'beam'
    formulation = '{formulation}'
    n_elements = 8
    length = {length!r}
    direction = {direction}
    d1 = 0, 0, 1
    EA = {ea!r}, GA1 = 1e4, GA2 = 1e4, EI1 = 1, EI2 = 1, GJ = 1
    rhoA = {rho_a!r}, rhoI1 = 1e-4, rhoI2 = 1e-4
    prestrain = {eps!r}
/
&bc rod = 'beam', end = 'start', kind = 'clamped' /
&load
    where = 'gravity'
    acceleration = 0, {minus_g!r}, 0
    time_function = '{time_function}', t_on = 0, t_off = 1
/
"""

DYNAMIC = "    t_end = 0.1\n    dt = 0.001\n    initial_equilibrium = .true."
QUASISTATIC = "    t_end = 1.0\n    dt = 0.25\n    quasistatic = .true."


def scene(formulation, direction, dynamic=True, scheme=None):
    time = DYNAMIC if dynamic else QUASISTATIC
    if scheme is not None:
        time += f"\n    scheme = '{scheme[0]}', rho_inf = {scheme[1]!r}"
    return SCENE.format(time=time, formulation=formulation, length=1 + EPS,
                        direction=direction, ea=EA, rho_a=RHO_A, eps=EPS, minus_g=-G,
                        time_function="constant" if dynamic else "ramp")


def largest_speed(r):
    return np.max(np.linalg.norm(r["velocity"], axis=2))


def case_of(formulation, scheme=None):
    def case(args, checks):
        r = rod(run(args, scene(formulation, "0, -1, 0", scheme=scheme), "hanging"), "beam")
        s = r["mesh"] / (1 + EPS)
        depth = s + RHO_A * G * (s - 0.5 * s**2) / EA
        position = r["position"][0]
        checks.check("hanging bar: nodes against the closed form (m)",
                     max(np.max(np.abs(position[:, 1] + depth)), np.max(np.abs(position[:, 0]))),
                     1e-10)
        checks.check("hanging bar: largest nodal speed over 100 steps (m/s)", largest_speed(r),
                     1e-10)
        bent = rod(run(args, scene(formulation, "1, 0, 0", scheme=scheme), "bent"), "beam")
        static = rod(run(args, scene(formulation, "1, 0, 0", dynamic=False), "static"), "beam")
        tip = bent["position"][0, -1]
        print(f"info: {formulation}: cantilever tip at t = 0 ({tip[0]:.9f}, {tip[1]:.9f}) m")
        checks.check("cantilever: initial equilibrium against the quasistatic endpoint (m)",
                     np.max(np.abs(bent["position"][0] - static["position"][-1])), 1e-8)
        checks.check("cantilever: largest nodal speed over 100 steps (m/s)",
                     largest_speed(bent), 1e-10)
    return case


CASES = {name: case_of(name) for name in ("ph_director", "ph_planar", "cl_em_planar",
                                          "se3_pg")}
CASES["se3_pg_generalized_alpha"] = case_of("se3_pg", ("generalized_alpha", 0.8))

if __name__ == "__main__":
    run_cases(__doc__.splitlines()[0], CASES)
