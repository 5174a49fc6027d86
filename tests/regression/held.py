"""An end held in chosen directions only (issue 26 item 3, &bc kind = 'held'): the propped
cantilever of input/held_roller.nml, its end on a roller (hold = 'z'), on every formulation
that holds ends so.

    held.py statics   the four formulations (ph_director, se3_pg, ph_planar, cl_em_planar):
                      the tip's z at its reference exactly, its x moved by F L / EA; the
                      roller's reaction from ph_director's shear force at the tip against the
                      closed-form Timoshenko R; the mid-span deflection against the closed
                      form (ph_director to 1e-6; se3_pg within its second-order discretization
                      error, which halves twice with the mesh; the planar ones equal to
                      se3_pg's); in 3D a tip force along y, which the roller lets pass
    held.py dynamics  ph_director and ph_planar under a load pulse: the tip's z held exactly
                      while it moves along x, and the energy balance at round-off (a held
                      coordinate does no work)
    held.py planar    in a plane whose axes are not coordinate axes: a held coordinate axis
                      that a planar formulation cannot hold by elimination (it fixes an oblique
                      planar direction) is refused, naming the rod, the plane's axes and the
                      hold; two held axes that fix the whole plane hold the end

Every closed form is computed here from the scene's parameters, never read from the program.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_scene as rs  # noqa: E402

ROD = "beam"
FORMULATIONS = ("ph_director", "se3_pg", "ph_planar", "cl_em_planar")


def parameters(text):
    """L, EA, GA, EI, the load per length q (along -z) and the tip force F (along x)."""
    return (rs.number(text, "rod", "length"), rs.number(text, "rod", "EA"),
            rs.number(text, "rod", "GA1"), rs.number(text, "rod", "EI1"),
            -rs.numbers(text, "load", "force")[2], force_of_tip(text)[0])


def force_of_tip(text):
    """The tip force of the scene (its second &load)."""
    second = text[text.index("&load", text.index("&load") + 1):]
    return rs.numbers(second, "load", "force")


def reaction(length, ea, ga, ei, q):
    """The roller's reaction of the propped Timoshenko cantilever under q: the tip deflection of
    the cantilever under q, q L^4/(8 EI) + q L^2/(2 GA), taken back by R (L^3/(3 EI) + L/GA)."""
    return (q * length**4 / (8 * ei) + q * length**2 / (2 * ga)) / (length**3 / (3 * ei) + length / ga)


def deflection(x, length, ga, ei, q):
    """The downward deflection of the propped cantilever at x: the cantilever's under q minus
    that under the tip force R (bending and shear parts)."""
    r = reaction(length, 0.0, ga, ei, q)
    under_q = q * x**2 * (6 * length**2 - 4 * length * x + x**2) / (24 * ei) + q * (length * x - x**2 / 2) / ga
    under_r = r * x**2 * (3 * length - x) / (6 * ei) + r * x / ga
    return under_q - under_r


def shear_at_tip(r):
    """n_z at s = L from ph_director's stresses: n = sum_i N_i d_i at the last element's two
    stress points (directors interpolated with the element's quadratic shape functions, methods
    §4.1), extrapolated linearly to the end (the stresses are linear in an element)."""
    s_points = r["stress_mesh"][-2:]
    nodes = r["mesh"][-3:]
    n_z = []
    for k, s in enumerate(s_points):
        shape = [np.prod([(s - nodes[b]) / (nodes[a] - nodes[b]) for b in range(3) if b != a])
                 for a in range(3)]
        d = np.einsum("a,aij->ij", shape, r["directors"][-1, -3:])
        n_z.append(r["stress"][-1, -2 + k, :3] @ d[:, 2])
    slope = (n_z[1] - n_z[0]) / (s_points[1] - s_points[0])
    return n_z[1] + slope * (nodes[-1] - s_points[1])


def statics(args, checks):
    """The roller holds z exactly (eliminated) in every formulation. The tip moves along x by
    F L / EA less the bending's shortening of the chord, 1/2 int w'^2 ~ 7e-4 of it here (bound
    2e-3). The reaction from ph_director's shear force at the tip is the closed form's to 1e-6
    (measured 1.1e-7) and its mid-span deflection to 1e-6 (measured 4.8e-7); se3_pg's two-node
    elements are of second order (1.1e-2 at 16 elements, a quarter of it at 32); the planar
    formulations are se3_pg's discretization in the plane (same deflection to 3e-9). The 3D formulations also carry a tip force F_y along y,
    which the roller lets pass: the tip moves along y as a cantilever's under F_y and the
    tension F (ph_director's mixed element is exact for a tip load; se3_pg within 1e-2)."""
    text = rs.read_example(args.source, "held_roller.nml")
    length, ea, ga, ei, q, force = parameters(text)
    middle = deflection(0.5 * length, length, ga, ei, q)
    lateral = 1e-6
    results = {}
    for formulation in FORMULATIONS:
        scene = rs.set_variable(text, "rod", "formulation", f"'{formulation}'")
        if formulation in ("ph_director", "se3_pg"):
            scene = scene.replace("force = 1e-5, 0.0, 0.0", f"force = 1e-5, {lateral!r}, 0.0")
        results[formulation] = rs.rod(rs.run(args, scene, f"statics_{formulation}"), ROD)
    refined = rs.rod(rs.run(args, rs.set_variable(rs.set_variable(text, "rod", "formulation", "'se3_pg'"),
                                                  "rod", "n_elements", "32"), "statics_se3_pg_32"), ROD)
    errors, mid_z = {}, {}
    for formulation, r in results.items():
        tip = r["position"][:, -1, :]
        mesh = r["mesh"]
        k = int(np.argmin(np.abs(mesh - 0.5 * length)))
        mid_z[formulation] = r["position"][-1, k, 2]
        errors[formulation] = abs(-mid_z[formulation] - middle) / middle
        print(f"info: {formulation}: tip at {tip[-1]}, mid-span z {r['position'][-1, k, 2]:.12e} "
              f"(closed form {-middle:.12e})")
        checks.check(f"{formulation}: max |tip z| over the records [m]", float(np.max(np.abs(tip[:, 2]))), 0.0)
        checks.check(f"{formulation}: |tip x - L - F L / EA| / (F L / EA)",
                     abs(tip[-1, 0] - length - force * length / ea) / (force * length / ea), 2e-3)
    checks.check("ph_director: |mid-span deflection / closed form - 1|", errors["ph_director"], 1e-6)
    r = results["ph_director"]
    expected = reaction(length, ea, ga, ei, q)
    measured = shear_at_tip(r)
    print(f"info: reaction R = {expected:.12e} N (3 q L / 8 = {3 * q * length / 8:.6e}); ph_director's "
          f"shear force at the tip {measured:.12e} N")
    checks.check("ph_director: |n_z(L) / R - 1| (the roller's reaction)", abs(measured / expected - 1), 1e-6)
    checks.check("se3_pg: |mid-span deflection / closed form - 1| (16 elements)", errors["se3_pg"], 2e-2)
    k = int(np.argmin(np.abs(refined["mesh"] - 0.5 * length)))
    fine = abs(-refined["position"][-1, k, 2] - middle) / middle
    checks.check("se3_pg second order: |error(16) / error(32) - 4|", abs(errors["se3_pg"] / fine - 4), 0.1)
    for formulation in ("ph_planar", "cl_em_planar"):
        checks.check(f"{formulation}: |mid-span deflection / se3_pg's - 1| (the same discretization)",
                     abs(mid_z[formulation] / mid_z["se3_pg"] - 1), 1e-7)
    # The cantilever under the tip force F_y and the tension F: F_y/F (L - tanh(k L)/k) with
    # k = sqrt(F/EI) (bending; F L^2/EI = 1e-5 takes 4e-6 off L^3/(3 EI)), plus F_y L/GA.
    k = np.sqrt(force / ei)
    sideways = lateral / force * (length - np.tanh(k * length) / k) + lateral * length / ga
    checks.check("ph_director: |tip y / (F_y/F (L - tanh(kL)/k) + F_y L/GA) - 1|",
                 abs(results["ph_director"]["position"][-1, -1, 1] / sideways - 1), 1e-8)
    checks.check("se3_pg: |tip y / (F_y/F (L - tanh(kL)/k) + F_y L/GA) - 1|",
                 abs(results["se3_pg"]["position"][-1, -1, 1] / sideways - 1), 1e-2)


def dynamics(args, checks):
    """A load pulse (q = 1 N/m along -z, and 1 N along x at the tip; smooth, over 0.2 s) on the
    propped cantilever in dynamics: the tip's z stays at 0 exactly while its x moves, and the
    balance H_{n+1} - H_n - W_n closes at round-off (the roller does no work: v_z = 0 there),
    on ph_director and on ph_planar (PH-EM), both energy-consistent."""
    text = rs.read_example(args.source, "held_roller.nml")
    text = rs.set_variable(text, "time", "quasistatic", ".false.")
    text = rs.set_variable(text, "time", "t_end", "0.4")
    text = rs.set_variable(text, "time", "dt", "0.002")
    text = text.replace("force = 0.0, 0.0, -1e-4", "force = 0.0, 0.0, -1.0")
    text = text.replace("force = 1e-5, 0.0, 0.0", "force = 1.0, 0.0, 0.0")
    text = text.replace("time_function = 'ramp', t_on = 0.0, t_off = 1.0",
                        "time_function = 'pulse', t_on = 0.0, t_off = 0.2")
    for formulation in ("ph_director", "ph_planar"):
        r = rs.rod(rs.run(args, rs.set_variable(text, "rod", "formulation", f"'{formulation}'"),
                          f"dynamics_{formulation}"), ROD)
        tip = r["position"][:, -1, :]
        total = r["series/energy/total"]
        print(f"info: {formulation}: max H = {np.max(total):.6e} J, tip x range {np.ptp(tip[:, 0]):.3e} m")
        checks.check(f"{formulation}: max |tip z| [m]", float(np.max(np.abs(tip[:, 2]))), 0.0)
        checks.check(f"{formulation}: the tip moves along x: 1e-6 m / (range of tip x)",
                     1e-6 / float(np.ptp(tip[:, 0])), 1.0)
        checks.check(f"{formulation}: max |balance_error| / max H",
                     float(np.max(np.abs(r["series/energy/balance_error"])) / np.max(total)), 1e-12)


def planar(args, checks):
    """A plane whose axes are not coordinate axes: the rod along e1 = (2, -1, -1)/sqrt(6) with
    d1 along the normal (1, 1, 1)/sqrt(3) and its loads in the plane (e2 = (0, 1, -1)/sqrt(2)).
    Holding y fixes y = -u1/sqrt(6) + u2/sqrt(2) of the planar coordinates (u1, u2), an oblique
    direction that no planar coordinate is: refused, naming the rod, the plane's axes and the
    hold. Holding x and y fixes both planar coordinates: the end stays where it is."""
    e1 = np.array([2.0, -1.0, -1.0]) / np.sqrt(6.0)
    normal = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
    e2 = np.cross(normal, e1)
    text = rs.read_example(args.source, "held_roller.nml")
    text = rs.set_variable(text, "rod", "formulation", "'ph_planar'")
    text = rs.set_variable(text, "rod", "direction", rs.vector(e1))
    text = rs.set_variable(text, "rod", "d1", rs.vector(normal))
    text = text.replace("force = 0.0, 0.0, -1e-4", f"force = {rs.vector(1e-4 * e2)}")
    text = text.replace("force = 1e-5, 0.0, 0.0", f"force = {rs.vector(1e-5 * e1)}")
    oblique = text.replace("hold = 'z'", "hold = 'y'")
    oblique = rs.set_variable(oblique, "output", "path", f"'{os.path.join(args.workdir, 'oblique.h5')}'")
    status, log = rs.run_failing(args, oblique, "oblique")
    checks.check("exit status is not 0", float(status == 0), 0.0)
    checks.check("the message names the rod and the plane's axes",
                 float("rod 'beam': ph_planar holds the planar coordinates x, y (along e1 = (" not in log), 0.0)
    checks.check("the message names the hold",
                 float("the directions a held end holds must lie along one of them or span the "
                       "plane; hold = 'y'" not in log), 0.0)
    both = text.replace("hold = 'z'", "hold = 'x', 'y'")
    r = rs.rod(rs.run(args, both, "both"), ROD)
    tip = r["position"][:, -1, :]
    checks.check("hold = 'x', 'y': max |tip - reference| [m]", float(np.max(np.abs(tip - tip[0]))), 1e-15)
    checks.check("the rod bends: 1e-9 m / max |mid-span displacement|",
                 1e-9 / float(np.max(np.abs(r["position"][-1, 8] - r["position"][0, 8]))), 1.0)


def main():
    return rs.run_cases(__doc__, {"statics": statics, "dynamics": dynamics, "planar": planar})


if __name__ == "__main__":
    sys.exit(main())
