"""A cantilever bent by one tendon (seed 000 §5.2; methods/ph_director_3d.md §3.2):
input/tendon_cantilever.nml, and the same rod with the tendon moved to the other axis.

    tendon.py curvature

Closed form (derived in the scene header): a tendon of tension T at material offset rho along
the whole free rod gives the elastic moment M = -R^T (rho x T d3), so
    offset (0, r) = r d2:  K1 = -T r/EI1, K2 = K3 = 0, the rod curves towards +d2;
    offset (r, 0) = r d1:  K2 = +T r/EI2, K1 = K3 = 0, the rod curves towards +d1;
exactly (the tendon stays tangent to d3), with the centreline on a circle of radius
EI/(T r) and N3 = -T carried by the inextensibility constraint. EI1 = 1 and EI2 = 2 differ, so
a mix-up of the axes changes the curvature by a factor 2. Checked at the last record (the
endpoint equilibrium at the full tension): |K| to 1e-5 relative at every stress point, the
other curvature components to 1e-6 of |K|, Gamma = (0, 0, 1) to 1e-10, the nodes on the arc
to 1e-4 of the tip deflection (0.24 m; the bend is 0.5 rad, so a geometrically linear model
would be off by 2 %), N3 = -T to 1e-5. The discrete solution is not exactly the arc (the
directors are interpolated between the nodes); the discretization error of 8 quadratic
elements at curvature 0.5/m is of order 1e-7 relative, far inside these bounds.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import run_scene as rs  # noqa: E402

ROD = "cantilever"
LENGTH = 1.0
EI1, EI2 = 1.0, 2.0
TENSION, OFFSET = 50.0, 0.01


def arc(s, radius, towards):
    """Centreline of a rod along e1 bent with curvature 1/radius towards the unit vector
    `towards` (normal to e1)."""
    along = np.array([1.0, 0.0, 0.0])
    return (radius * np.sin(s / radius))[:, None] * along \
        + (radius * (1 - np.cos(s / radius)))[:, None] * np.asarray(towards)


def curvature(args, checks):
    base = rs.read_example(args.source, "tendon_cantilever.nml")
    # (offset, curvature component, its sign, bending stiffness, spatial direction it bends to):
    # d1 = e2 and d2 = e3 for this rod along e1.
    variants = (("d2", (0.0, OFFSET), 3, -1.0, EI1, (0.0, 0.0, 1.0)),
                ("d1", (OFFSET, 0.0), 4, +1.0, EI2, (0.0, 1.0, 0.0)))
    for label, offset, component, sign, stiffness, towards in variants:
        text = rs.set_variable(base, "actuator", "offset", rs.vector(offset))
        r = rs.rod(rs.run(args, text, f"tendon_{label}"), ROD)
        assert abs(r["time"][-1] - 1.0) < 1e-12
        kappa = TENSION * OFFSET / stiffness
        strain = r["strain"][-1]
        k = strain[:, component]
        others = [c for c in (3, 4, 5) if c != component]
        print(f"info: tendon at r {label}: K{component - 2} in [{k.min():.10f}, {k.max():.10f}], "
              f"expected {sign * kappa:.10f}; other curvatures max "
              f"{np.max(np.abs(strain[:, others])):.2e}")
        checks.check(f"tendon at r {label}: max | |K{component - 2}| / (T r/EI) - 1 |",
                     np.max(np.abs(np.abs(k) / kappa - 1)), 1e-5)
        checks.check(f"tendon at r {label}: sign of K{component - 2} (methods §3.2): "
                     "-min(sign K / |K|)", -np.min(sign * k / np.abs(k)), -1.0)
        checks.check(f"tendon at r {label}: other curvature components / (T r/EI)",
                     np.max(np.abs(strain[:, others])) / kappa, 1e-6)
        checks.check(f"tendon at r {label}: max |Gamma - (0, 0, 1)| (inextensible)",
                     np.max(np.abs(strain[:, :3] - [0.0, 0.0, 1.0])), 1e-10)
        radius = 1.0 / kappa
        exact = arc(r["mesh"], radius, towards)
        deflection = radius * (1 - np.cos(LENGTH / radius))
        error = np.max(np.abs(r["position"][-1] - exact))
        print(f"info: tendon at r {label}: tip {r['position'][-1, -1]}, arc {exact[-1]}, "
              f"max nodal distance {error:.3e} m")
        checks.check(f"tendon at r {label}: nodes on the arc of radius EI/(T r): "
                     "max |phi - arc| / tip deflection", error / deflection, 1e-4)
        checks.check(f"tendon at r {label}: max |N3 / T + 1| (N3 = -T)",
                     np.max(np.abs(r["stress"][-1, :, 2] / TENSION + 1)), 1e-5)


def main():
    parser = rs.common_arguments(__doc__)
    parser.add_argument("case", choices=["curvature"])
    args = parser.parse_args()
    checks = rs.Checks()
    curvature(args, checks)
    checks.finish()


if __name__ == "__main__":
    main()
