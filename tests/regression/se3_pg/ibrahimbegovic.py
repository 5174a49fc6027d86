"""SE(3) rod bent to a helical form (Ibrahimbegovic 1997), seed 002 §4.4 (methods/
se3_petrov_galerkin.md §10.4, §14.4), input/se3_helical_form.nml: 30 elements, dead end moment
(0, 0, 200 pi) and dead end force (0, 0, 50), 400 nominal load increments halved on failure.

    ibrahimbegovic.py tip   the run reaches the full load (cut-backs reported); the final tip
                            within 1e-6 per component of (0.0022941, 0.0000209, -0.0765547)
                            (methods §14.4, the same 30 elements, printed to 7 decimals;
                            measured 1.6e-8, 4.2e-8, 1.2e-8, the printing's half unit 5e-8 and
                            Newton at 1e-8; issue 7 accepted "about (0.0023, 0, -0.0766) within
                            1e-3", which the 0.0023 of x alone could not test);
                            the tip on the path at load factors 0.05 and 0.2 (grid points) and
                            at 0.10125, 0.300625, 0.500625 (methods' "0.1013", "0.3006",
                            "0.5006": points its adaptive stepping put between the 1/400 grid
                            points; each solved by a run that ends there) within 1e-4 per
                            component of methods §14.4 (printed to 5 decimals: a re-computation's
                            centre with a band, DESIGN.md §8; measured 1.8e-6 ... 4.9e-6, the
                            printing's half unit 5e-6); the z extrema of the tip on the
                            1/400 path alternate in sign and decay in magnitude (methods §15
                            item 7), at least 19 of them inside (0, 1) (10 maxima at half turns,
                            9 minima; the 10th minimum, at about 0.9988, falls between the last
                            two grid points). The extrema are compared with methods §14.4's list
                            as information only: both are samples of a path at different load
                            points (a sample a step of 1/400 away from an extremum misses it by
                            up to |z''| / 2 (1/400)^2, 1.5e-2 at the first maximum), so the
                            listed values are not a sampling-independent measure.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import se3_scene  # noqa: E402
from se3_scene import rs  # noqa: E402

ROD = "rod"
FINAL_TIP = (0.0022941, 0.0000209, -0.0765547)   # methods §14.4, 30 elements
PATH = {0.05: (0.71043, 6.28668, 2.74615), 0.2: (0.11287, 0.00809, -0.59908),
        0.10125: (0.50802, 0.08442, -1.04503), 0.300625: (0.07030, 0.00472, -0.39649),
        0.500625: (0.02911, 0.00135, -0.22558)}
# methods §14.4: local extrema of the tip's z (value, load factor), in order.
EXTREMA = [(3.2726, 0.035), (-1.2994, 0.089), (0.8526, 0.146), (-0.6280, 0.195), (0.4995, 0.248),
           (-0.4078, 0.296), (0.3478, 0.348), (-0.2971, 0.398), (0.2620, 0.448),
           (-0.2287, 0.498), (0.2057, 0.548), (-0.1814, 0.598), (0.1652, 0.648),
           (-0.1461, 0.698), (0.1338, 0.748), (-0.1184, 0.798), (0.1082, 0.848),
           (-0.0958, 0.898), (0.0864, 0.948), (-0.0767, 0.998)]


def extrema(t, z):
    """Sampled local extrema (k, t_k, z_k) and their parabola through the three samples."""
    found = []
    for k in range(1, len(t) - 1):
        if (z[k] - z[k - 1]) * (z[k + 1] - z[k]) < 0:
            h = t[k + 1] - t[k]
            d1 = (z[k + 1] - z[k - 1]) / (2 * h)
            d2 = (z[k + 1] + z[k - 1] - 2 * z[k]) / h**2
            found.append((t[k], z[k], z[k] - 0.5 * d1**2 / d2))
    return found


def tip(args, checks):
    text = rs.read_example(args.source, "se3_helical_form.nml")
    r = se3_scene.run(args, text, "path", ROD, allow_failure=True)
    residual = r["series/newton/residual"][1:]
    print(f"info: {r.summary()}; largest final residual of an increment {np.max(residual):.2e}")
    checks.check("exit status of rodsolve", r.status, 0)
    checks.check("1 - final load factor", 1.0 - r["time"][-1], 0)
    checks.check("largest residual 2-norm at the end of an increment", float(np.max(residual)),
                 1e-8)
    end = r["position"][-1, -1]
    print(f"info: final tip ({end[0]:.7f}, {end[1]:.7f}, {end[2]:.7f}); methods §14.4 "
          f"{FINAL_TIP}; difference {np.array2string(end - FINAL_TIP, precision=2)}")
    for c in range(3):
        checks.check(f"|final tip component {c} - ({FINAL_TIP[c]})|", abs(end[c] - FINAL_TIP[c]),
                     1e-6)
    t = r["time"]
    for load, expected in PATH.items():
        k = int(np.argmin(np.abs(t - load)))
        if abs(t[k] - load) < 1e-12:
            got = r["position"][k, -1]
        else:
            # Not a grid point: a run with the same increments that ends at this load factor.
            part = se3_scene.run(args, se3_scene.edit(text, [("time", "t_end", repr(load))]),
                                 f"path_to_{load}", ROD)
            got = part["position"][-1, -1]
            print(f"info: run to {load}: {part.summary()}")
        print(f"info: tip at load factor {load}: ({got[0]:.6f}, {got[1]:.6f}, {got[2]:.6f}); "
              f"methods {expected}")
        checks.check(f"load factor {load}: largest |tip component - methods §14.4|",
                     float(np.max(np.abs(got - expected))), 1e-4)
    found = extrema(t, r["position"][:, -1, 2])
    print("info: tip z extrema: load factor, sampled z, parabola z | methods (z, load factor)")
    for i, (t_k, z_k, z_p) in enumerate(found):
        listed = EXTREMA[i] if i < len(EXTREMA) else None
        print(f"info:   {t_k:.4f} {z_k:+.5f} {z_p:+.5f} | {listed}")
    signs = [np.sign(z) for _, z, _ in found]
    checks.check("interior z extrema short of 19", max(0, 19 - len(found)), 0)
    checks.check("z extrema not alternating in sign (count)",
                 sum(1 for i, s in enumerate(signs) if s != (1 if i % 2 == 0 else -1)), 0)
    for kind, first in (("maxima", 0), ("minima", 1)):
        values = np.abs([z for _, z, _ in found[first::2]])
        checks.check(f"z {kind}: increases of |z| from one to the next (count)",
                     int(np.sum(np.diff(values) >= 0)), 0)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["tip"])
    args = parser.parse_args()
    checks = rs.Checks()
    tip(args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
