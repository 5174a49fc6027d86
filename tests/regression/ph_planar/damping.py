"""Kelvin-Voigt viscosity, drag and angular drag of the planar formulations (issue 26 item 1;
docs/theory/damping.md, docs/theory/ph_planar.md "Damping"), ph_planar (PH-EM) and cl_em_planar
(Stander-Stein, its default 1-point rule, and em_variant = 'ph_irreducible').

    damping.py decrement   input/planar_kelvin_voigt_cantilever.nml: a slender cantilever under
                           a small step load vibrates about its static deflection; the tip's
                           logarithmic decrement equals 2 pi zeta / sqrt(1 - zeta^2),
                           zeta = tau omega_1 / 2, omega_1 = beta_1^2 sqrt(EI / (rhoA L^4)) of
                           Euler-Bernoulli (beta_1 L = 1.875104068711961), within 0.5 % (20
                           elements, h = T_1 / 89: measured 0.10 % for both formulations; 40
                           elements at h / 2, ph_planar: 0.06 %), and the damped period
                           2 pi / (omega_1 sqrt(1 - zeta^2)) within 0.2 %; without viscosity the
                           decrement is below 1e-2 of it (the decay is the viscosity's; what
                           remains, 2.6e-3, is the measurement's floor: the undamped higher
                           modes beat with the first)
    components             kelvin_voigt_time given per component (EA, GA1, GA2, EI1, EI2, GJ):
                           the cantilever bends about d2 (the plane normal), so EI2's time alone
                           gives the first mode's decrement (0.5 %: its strain energy is
                           bending), and EI1's and GJ's (out of the plane) give none (1e-2)
    balance                the planar flying spaghetti (large rotations, free flight) with
                           Kelvin-Voigt viscosity, drag and angular drag, each alone and all
                           together: per step, computed from the stored series,
                           |H_{n+1} - H_n - W_n + D_n| <= 1e-13 max H (round-off: measured
                           <= 1.5e-15) and D_n > 0; the booked D_n equals the laws' closed forms
                           computed here from the stored positions, angles and strains (drag
                           h v_mid^T C v_mid, C the consistent matrix; Kelvin-Voigt
                           h sum_e L_e (de/h)^T V (de/h) for the P0 strains of PH-EM and the
                           one-point strains of cl-EM) within 1e-12 relative (measured 7e-15)
    terminal_velocity      a free rod falling under gravity with drag c: every node's velocity
                           follows v_t (1 - exp(-c t / rhoA)), v_t = rhoA g / c, within twice the
                           midpoint rule's leading error lambda^3 h^2 t exp(-lambda t) / 12
                           (lambda = c / rhoA), and the end velocity is v_t within 1 %
    spin                   a free rod spinning in its plane about its centre with angular drag
                           c_w: J(t) = J_0 exp(-c_w t / (rhoA L^2 / 12 + rhoI)) within four
                           times the midpoint rule's leading error (the rest: the rod's bending
                           under the drag, and cl-EM's O(h^2) angular momentum defect)
    plan                   --check-input names the damping of a damped rod (damping_plan_text
                           and the in-plane times of its six), and 'none' for an undamped one

The closed forms are computed here; nothing is copied from the program's output. Every record
ends one step (stride 1, no cut-back), so series differences are per step.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import planar  # noqa: E402
from planar import rs  # noqa: E402

BETA1_L = 1.875104068711961
CANTILEVER = "planar_kelvin_voigt_cantilever.nml"


def with_formulation(text, formulation, variant=None, n_gauss=None):
    """The scene's rod with another planar formulation (and cl_em_planar's variant, rule)."""
    text = rs.set_variable(text, "rod", "formulation", f"'{formulation}'")
    if variant is not None:
        text = rs.set_variable(text, "rod", "em_variant", f"'{variant}'")
    if n_gauss is not None:
        text = rs.set_variable(text, "rod", "n_gauss", str(n_gauss))
    return text


def extrema(t, y):
    """Times and values of the local extrema of a sampled signal, each refined by the parabola
    through its three samples."""
    k = np.where((y[1:-1] - y[:-2]) * (y[2:] - y[1:-1]) < 0)[0] + 1
    y0, y1, y2 = y[k - 1], y[k], y[k + 1]
    shift = (y0 - y2) / (2 * (y0 - 2 * y1 + y2))
    return t[k] + shift * (t[k + 1] - t[k]), y1 - 0.25 * (y0 - y2) * shift


def decrement(r, t_from):
    """The tip's logarithmic decrement per period and its damped period, from the extrema after
    t_from. For y = y_s + C exp(-sigma t) cos(omega_d t + phi) the extrema are T_d / 2 apart and
    the differences of successive extrema alternate in sign with |d_k| proportional to
    exp(-sigma t_k), whatever the static offset y_s: a least-squares line through log |d_k|
    has the slope -delta / 2 per extremum."""
    t_ext, y_ext = extrema(r["time"], r["position"][:, -1, 1])
    keep = t_ext > t_from
    t_ext, y_ext = t_ext[keep], y_ext[keep]
    slope = np.polyfit(np.arange(y_ext.size - 1), np.log(np.abs(np.diff(y_ext))), 1)[0]
    return -2.0 * slope, 2.0 * np.mean(np.diff(t_ext)), y_ext.size


def cantilever_closed_form(text):
    """omega_1 (Euler-Bernoulli), and for a time tau the decrement and damped period."""
    length = rs.number(text, "rod", "length")
    ei = rs.number(text, "rod", "EI2")
    rho_a = rs.number(text, "rod", "rhoA")
    omega = BETA1_L**2 * np.sqrt(ei / (rho_a * length**4))

    def of(tau):
        zeta = 0.5 * tau * omega
        return (2 * np.pi * zeta / np.sqrt(1 - zeta**2),
                2 * np.pi / (omega * np.sqrt(1 - zeta**2)))
    return omega, of


def run_decrement(args, text, name):
    r = rs.rod(rs.run(args, text, name), "beam")
    rs.one_step_per_record(r)
    # After one period of the first mode the higher modes (zeta_k = tau omega_k / 2, 6.3 times
    # zeta_1 and more) have decayed to below 1e-4 of their small share.
    omega, _ = cantilever_closed_form(text)
    return decrement(r, 2 * np.pi / omega)


def decrement_case(args, checks):
    text = rs.read_example(args.source, CANTILEVER)
    tau = rs.number(text, "rod", "kelvin_voigt_time")
    omega, closed_form = cantilever_closed_form(text)
    delta_exact, period_exact = closed_form(tau)
    print(f"info: omega_1 = {omega:.6f} rad/s, zeta = {0.5 * tau * omega:.6f}, "
          f"decrement {delta_exact:.6f}, damped period {period_exact:.6f} s")
    n_e, h = rs.number(text, "rod", "n_elements"), rs.number(text, "time", "dt")
    finer = rs.set_variable(rs.set_variable(text, "rod", "n_elements", str(int(2 * n_e))),
                            "time", "dt", repr(h / 2))
    for formulation, scene, mesh in (("ph_planar", text, n_e), ("cl_em_planar", text, n_e),
                                     ("ph_planar", finer, 2 * n_e)):
        label = f"{formulation}, {mesh:.0f} elements"
        delta, period, n = run_decrement(args, with_formulation(scene, formulation),
                                         f"{formulation}_{mesh:.0f}")
        print(f"info: {label}: decrement {delta:.6f} from {n} extrema, period {period:.6f} s")
        checks.check(f"{label}: |decrement / (2 pi zeta / sqrt(1 - zeta^2)) - 1|",
                     abs(delta / delta_exact - 1), 5e-3)
        checks.check(f"{label}: |damped period / (2 pi / omega_d) - 1|",
                     abs(period / period_exact - 1), 2e-3)
    undamped = rs.set_variable(text, "rod", "kelvin_voigt_time", "0.0")
    delta, _, _ = run_decrement(args, undamped, "undamped")
    print(f"info: without viscosity: decrement {delta:.3e}")
    checks.check("no viscosity: |decrement| / the damped one", abs(delta) / delta_exact, 1e-2)


def components(args, checks):
    text = rs.read_example(args.source, CANTILEVER)
    tau = rs.number(text, "rod", "kelvin_voigt_time")
    _, closed_form = cantilever_closed_form(text)
    delta_exact, _ = closed_form(tau)
    # (EA, GA1, GA2, EI1, EI2, GJ); d2 is the plane normal of this scene (its plan says so).
    bending = rs.set_variable(text, "rod", "kelvin_voigt_time", f"0, 0, 0, 0, {tau}, 0")
    delta, _, _ = run_decrement(args, bending, "ei2_only")
    print(f"info: EI2's time only: decrement {delta:.6f}")
    checks.check("EI2's time only: |decrement / closed form - 1|", abs(delta / delta_exact - 1),
                 5e-3)
    outside = rs.set_variable(text, "rod", "kelvin_voigt_time", f"0, 0, 0, {tau}, 0, {tau}")
    delta, _, _ = run_decrement(args, outside, "ei1_gj_only")
    print(f"info: EI1's and GJ's times only: decrement {delta:.3e}")
    checks.check("EI1's and GJ's times only (out of the plane): |decrement| / closed form",
                 abs(delta) / delta_exact, 1e-2)


# The spaghetti's damping: Kelvin-Voigt time 0.05 s (zeta about 0.4 on its axial modes), drag
# 0.5 N s/m^2 (rhoA = 1: 0.5 /s) and angular drag 5 N s (rhoI = 10: 0.5 /s); each removes from a
# third to a half of the energy the loads put in by t = 5.
LAWS = {"kv": {"kelvin_voigt_time": 0.05}, "drag": {"drag": 0.5},
        "angular": {"angular_drag": 5.0}}
LAWS["all"] = {**LAWS["kv"], **LAWS["drag"], **LAWS["angular"]}


def booked_dissipation(r, text, laws, kelvin_voigt):
    """D_n of the step ending at record n + 1 from the stored motion: drag and angular drag
    h v_mid^T C v_mid with v_mid = (x_{n+1} - x_n)/h and C the consistent matrix
    c L_e/6 [[2, 1], [1, 2]] per component; with kelvin_voigt, h sum_e L_e (de/h)^T V (de/h),
    V = tau (EA, GA, EI), de from the stored strains (N3 axial, the shear on the in-plane
    director, the bending about the normal; the others are zero in the plane)."""
    h = np.diff(r["time"])[:, None]
    n_e = int(rs.number(text, "rod", "n_elements"))
    le = rs.number(text, "rod", "length") / n_e
    d = np.zeros(h.size)

    def consistent(delta):   # sum over the elements of dx_e^T (L_e/6 [[2, 1], [1, 2]]) dx_e
        a, b = delta[:, :-1], delta[:, 1:]
        return le / 3 * np.sum(a * a + a * b + b * b, axis=1)
    dx = np.diff(r["position"][:, :, :2], axis=0)
    d += laws.get("drag", 0.0) * (consistent(dx[..., 0]) + consistent(dx[..., 1])) / h[:, 0]
    dtheta = np.diff(planar.theta(r["directors"]), axis=0)
    d += laws.get("angular_drag", 0.0) * consistent(dtheta) / h[:, 0]
    if kelvin_voigt and "kelvin_voigt_time" in laws:
        tau = laws["kelvin_voigt_time"]
        de = np.diff(r["strain"], axis=0)
        v = tau * np.array([rs.number(text, "rod", k) for k in ("GA1", "GA2", "EA", "EI1", "EI2")])
        d += le * np.sum(v * de[:, :, :5]**2, axis=(1, 2)) / h[:, 0]
    return d


def balance(args, checks):
    text = rs.read_example(args.source, "planar_flying_spaghetti.nml")
    # The loads act until 2.5, then free flight; Newton to round-off.
    text = rs.set_variable(text, "time", "t_end", "5.0")
    text = rs.set_variable(text, "solver", "newton_atol", "1e-12")
    # (label, formulation, variant, n_gauss, condensed, whether the stored strains are the
    # viscous stress's, laws)
    runs = [("PH-EM", "ph_planar", None, None, False, True, law) for law in LAWS]
    runs += [("cl-EM 1-pt", "cl_em_planar", None, None, False, True, law) for law in LAWS]
    runs += [("PH-EM condensed", "ph_planar", None, None, True, True, "all"),
             ("cl-EM 2-pt", "cl_em_planar", None, 2, False, False, "all"),
             ("PH-EMi 2-pt", "cl_em_planar", "ph_irreducible", 2, False, False, "all")]
    worst = 0.0
    for label, formulation, variant, n_gauss, condensed, stored, law in runs:
        scene = with_formulation(text, formulation, variant, n_gauss)
        if condensed:
            scene = rs.set_variable(scene, "solver", "condense_stresses", ".true.")
        for variable, value in LAWS[law].items():
            scene = rs.set_variable(scene, "rod", variable, repr(value))
        name = re.sub(r"\W+", "_", f"{label}_{law}")
        r = rs.rod(rs.run(args, scene, name), "spaghetti")
        rs.one_step_per_record(r)
        total = r["series/energy/total"]
        work = r["series/energy/external_work"][1:]
        dissipated = r["series/energy/dissipated"][1:]
        error = np.max(np.abs(np.diff(total) - work + dissipated)) / np.max(total)
        worst = max(worst, error)
        print(f"info: {label}, {law}: max |H_n+1 - H_n - W + D| / max H = {error:.2e}, "
              f"sum D = {np.sum(dissipated):.4f}, min D_n = {np.min(dissipated):.3e}, "
              f"H(5) = {total[-1]:.4f}")
        checks.check(f"{label}, {law}: max |H_n+1 - H_n - W_n + D_n| / max H", error, 1e-13)
        checks.check(f"{label}, {law}: -(smallest D_n) (D_n > 0 every step)",
                     -np.min(dissipated), -np.finfo(float).tiny)
        expected = booked_dissipation(r, scene, LAWS[law], stored)
        if stored or "kelvin_voigt_time" not in LAWS[law]:
            difference = np.max(np.abs(dissipated - expected) / expected)
            checks.check(f"{label}, {law}: max |D_n - closed form| / closed form", difference,
                         1e-12)
        else:
            # The viscous stresses used the Gauss-point strains, which the output averages:
            # the drag parts alone are a lower bound.
            checks.check(f"{label}, {law}: drag part - D_n (Kelvin-Voigt adds to it)",
                         np.max(expected - dissipated), 0.0)
    print(f"info: largest relative balance error {worst:.2e}")


def free_rod(args, formulation, name, edits):
    """A free straight rod of length 1 along x (4 elements, h = 0.01, t_end = 4) with edits to
    its &rod group and &load groups appended."""
    text = "\n".join([
        "&time", "    t_end = 4.0", "    dt = 0.01", "/",
        "&solver", f"    newton_atol = {edits.pop('newton_atol')}", "/",
        "&output", "    path = 'x'", "/",
        "&rod", "    name = 'rod'", f"    formulation = '{formulation}'", "    n_elements = 4",
        f"    start = {edits.pop('start')}", "    direction = 1.0, 0.0, 0.0", "    length = 1.0",
        f"    EA = {edits['EA']}, GA1 = {edits['EA']}, GA2 = {edits['EA']}",
        f"    EI1 = {edits['EI']}, EI2 = {edits['EI']}, GJ = {edits['EI']}",
        "    rhoA = 2.0, rhoI1 = 1e-3, rhoI2 = 1e-3", "/", ""])
    for variable, value in edits.get("rod", {}).items():
        text = rs.set_variable(text, "rod", variable, value)
    text += edits.get("loads", "")
    r = rs.rod(rs.run(args, text, name), "rod")
    rs.one_step_per_record(r)
    return r, text


def terminal_velocity(args, checks):
    g, c = 1.0, 4.0
    for formulation in ("ph_planar", "cl_em_planar"):
        # Stiff enough to fall as a rigid body, soft enough for Newton's round-off (cl-EM's
        # force rows at EA 1e6 floor above 1e-10 a few metres from the origin).
        r, text = free_rod(args, formulation, f"fall_{formulation}", {
            "newton_atol": "1e-10", "start": "0.0, 0.0, 0.0", "EA": "1e4", "EI": "10.0",
            "rod": {"drag": repr(c)},
            "loads": f"&load where = 'gravity', acceleration = 0.0, {-g}, 0.0 /\n"})
        rho_a = rs.number(text, "rod", "rhoA")
        lam, v_t, h = c / rho_a, rho_a * g / c, 0.01
        t = r["time"]
        v = -r["velocity"][:, :, 1]
        error = np.max(np.abs(v - (v_t * (1 - np.exp(-lam * t)))[:, None])) / v_t
        bound = 2 * np.max(lam**3 * h**2 * t * np.exp(-lam * t) / 12)
        print(f"info: {formulation}: v(4) = {np.mean(v[-1]):.8f}, v_t = {v_t}; "
              f"max |v - v_t (1 - exp(-c t / rhoA))| / v_t = {error:.3e} "
              f"(midpoint rule's leading error {bound / 2:.3e})")
        checks.check(f"{formulation}: max over nodes and t |v - v_t (1 - exp(-c t / rhoA))| / v_t "
                     "(bound: twice the midpoint rule's leading error)", error, bound)
        checks.check(f"{formulation}: |v(t_end) / (rhoA g / c) - 1| (terminal velocity)",
                     np.max(np.abs(v[-1] / v_t - 1)), 1e-2)


def spin(args, checks):
    c_w, omega0 = 0.1, 1.0
    for formulation in ("ph_planar", "cl_em_planar"):
        r, text = free_rod(args, formulation, f"spin_{formulation}", {
            "newton_atol": "1e-9", "start": "-0.5, 0.0, 0.0", "EA": "1e6", "EI": "1e3",
            "rod": {"angular_drag": repr(c_w), "angular_velocity": f"0.0, 0.0, {omega0}",
                    "rotation_center": "0.0, 0.0, 0.0"}})
        inertia = (rs.number(text, "rod", "rhoA") * rs.number(text, "rod", "length")**2 / 12
                   + rs.number(text, "rod", "rhoI2"))
        lam, h = c_w / inertia, 0.01
        t = r["time"]
        j = r["series/momentum/angular"][:, 2]
        error = np.max(np.abs(j / (inertia * omega0) - np.exp(-lam * t)))
        leading = np.max(lam**3 * h**2 * t * np.exp(-lam * t) / 12)
        print(f"info: {formulation}: J(0) = {j[0]:.15f} (I omega_0 = {inertia * omega0:.15f}), "
              f"J(4)/J(0) = {j[-1] / j[0]:.10f} (exp(-lambda t) = {np.exp(-lam * t[-1]):.10f}); "
              f"max |J/(I omega_0) - exp(-lambda t)| = {error:.3e} (midpoint rule's leading "
              f"error {leading:.3e})")
        checks.check(f"{formulation}: max |J(t) / (I omega_0) - exp(-c_w t / I)| (bound: four "
                     "times the midpoint rule's leading error)", error, 4 * leading)


def plan(args, checks):
    text = rs.read_example(args.source, CANTILEVER)
    times = (1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3)
    damped = rs.set_variable(text, "rod", "kelvin_voigt_time", ", ".join(map(repr, times)))
    damped = rs.set_variable(damped, "rod", "drag", "0.25")
    _, log = rs.run(args, damped, "plan_damped", extra=("--check-input",), want_log=True)
    line = re.search(r"^!\s+damping: (.*)$", log, flags=re.M)
    print(f"info: {line.group(0) if line else 'no damping line'}")
    checks.check("damped rod: the plan has a damping line", 0.0 if line else 1.0, 0.0)
    words = line.group(1) if line else ""
    named = re.search(r"Kelvin-Voigt \(EA, GA1, GA2, EI1, EI2, GJ\) ([^;]*) s;", words)
    given = [float(v) for v in named.group(1).split(",")] if named else [np.nan]
    checks.check("the plan's six Kelvin-Voigt times = the given ones (largest difference)",
                 np.max(np.abs(np.subtract(given, times))) if len(given) == 6 else np.inf, 1e-12)
    checks.check("the plan names the drag", 0.0 if re.search(r"drag 0?\.25|drag 2\.50*E-01",
                                                              words) else 1.0, 0.0)
    plane = re.search(r"\(EA, GA1, EI2\) = \(([^)]*)\) s", words)
    in_plane = [float(v) for v in plane.group(1).split(",")] if plane else [np.nan]
    # d2 is the plane normal: the plane takes EA, the shear along d1 (GA1) and bending about d2.
    checks.check("the plan's in-plane times = those of EA, GA1, EI2 (largest difference)",
                 np.max(np.abs(np.subtract(in_plane, [times[0], times[1], times[4]])))
                 if len(in_plane) == 3 else np.inf, 1e-12)
    undamped = rs.set_variable(text, "rod", "kelvin_voigt_time", "0.0")
    _, log = rs.run(args, undamped, "plan_undamped", extra=("--check-input",), want_log=True)
    checks.check("undamped rod: the plan says 'damping: none'",
                 0.0 if re.search(r"^!\s+damping: none$", log, flags=re.M) else 1.0, 0.0)


if __name__ == "__main__":
    rs.run_cases(__doc__, {"decrement": decrement_case, "components": components,
                           "balance": balance, "terminal_velocity": terminal_velocity,
                           "spin": spin, "plan": plan})
