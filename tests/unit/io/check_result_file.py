"""Reads the files test_result_file.F90 wrote (argument: their directory) with h5py and checks
them against the closed form the Fortran test used: shapes, every value, units and
descriptions on every dataset, the root attributes, chunking along the steps, the sums in
/series/ (the new dissipated and actuator_work included), the strain and branch_stress datasets
(branch_stress only for the rod with Maxwell branches) with their units and components, the
bundle series series/contact/{energy,force,penetration} and series/ties/force (only for the rod
of a bundle, arm), and the attributes written through the HDF5 layer. Also exercises
scripts/rodresults.py (on PYTHONPATH). Exit status 1 with a list of failures.
"""

import datetime
import math
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                "scripts"))
import rodresults  # noqa: E402

# The closed form of test_result_file.F90 (synthetic_rod and synthetic_meta).
N_STORED = 8
TIME_STEP = 0.25
RODS = {  # name: (k, formulation, nodes, stress points, Maxwell branches)
    "arm": (1, "ph_director", 5, 8, 2),
    "tail": (2, "se3_strand", 7, 6, 0),
}
STRESS_UNIT = "N (N1, N2, N3); N m (M1, M2, M3)"
STRESS_COMPONENTS = "N1 N2 N3 M1 M2 M3"
STRAIN_UNIT = "1 (Gamma); 1/m (K)"
STRAIN_COMPONENTS = "Gamma1 Gamma2 Gamma3 K1 K2 K3"
# Fragments the descriptions must hold (issue 4; methods/ph_director_3d.md §3.1, §5.3, §9.7).
DESCRIPTIONS = {
    "stress": "total stress resultants (elastic branch plus all Maxwell branches)",
    "strain": "strains computed from the displacements at the stress points (straight "
              "reference: Gamma0 = (0, 0, 1), K0 = 0); strain consistency: C sigma_elastic = "
              "strain - strain0",
    "branch_stress": "generalized-Maxwell branches",
    "series/energy/dissipated": "energy dissipated by the Maxwell branches, D_n = h sum_i int "
                                "sigma_mid^(i) . V^(i)^-1 sigma_mid^(i) ds >= 0, summed over "
                                "the steps since the previous record",
    "series/energy/actuator_work": "work of the pneumatic and tendon actuators, W_act = -h int "
                                   "Delta sigma_act . eps_dot(q_mid, v_mid) ds, summed over the "
                                   "steps since the previous record",
    "series/energy/balance_error": "H_{n+1} - H_n - W_ext - W_act + D summed over the steps "
                                   "since the previous record",
}
META = {
    "title": "two synthetic rods",
    "command_line": "test_result_file --synthetic",
    "n_ranks": 3,
    "petsc_version": "Petsc Release Version 3.18.test",
    "mpi_version": "test MPI 1.0",
}
INPUT_TEXT = ("! scene of the synthetic test, caf\u00e9\n&rod name = 'arm', n_elements = 4 /\n\n"
              "\t&rod name = 'tail' /\n")
INPUT_RESOLVED = "&run\n    title = 'two synthetic rods'\n/\n"
PETSC_OPTIONS = "-snes_rtol 0 -snes_stol 0"
# The bundle series (issue 10) of the rod of a bundle: unit and a description fragment.
BUNDLE_SERIES = {
    "contact/energy": ("J", "half the energy of each of its contact pairs"),
    "contact/force": ("N", "total contact force on the rod"),
    "contact/penetration": ("m", "deepest penetration r_c - d"),
    "ties/force": ("N", "end 0 = start, 1 = end"),
    "ties/moment": ("N m", "about the end's node"),
    "contact/friction": ("N", "friction force on the rod"),
    "contact/slip_speed": ("m/s", "largest slip speed"),
}
BUNDLE_RODS = ("arm",)

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


def check_close(actual, expected, message, rtol=1e-14, atol=1e-14):
    actual = np.asarray(actual)
    expected = np.asarray(expected)
    if actual.shape != expected.shape:
        failures.append("%s: shape %s, expected %s" % (message, actual.shape, expected.shape))
    elif not np.allclose(actual, expected, rtol=rtol, atol=atol):
        worst = np.unravel_index(np.argmax(np.abs(actual - expected)), actual.shape)
        failures.append("%s: at %s %r, expected %r"
                        % (message, worst, actual[worst], expected[worst]))


def rotation(psi):
    c, s = math.cos(psi), math.sin(psi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_rate(psi):
    """d rotation / d psi."""
    c, s = math.cos(psi), math.sin(psi)
    return np.array([[-s, -c, 0.0], [c, -s, 0.0], [0.0, 0.0, 0.0]])


def expected_rod(k, n_nodes, n_points, n_branches):
    """The arrays in h5py layout ([step, ...]); branch_stress only with n_branches > 0."""
    length, omega, rise = float(k), 0.5 * k, 0.1 * k
    t = TIME_STEP * np.arange(N_STORED)
    j = np.arange(1, N_STORED + 1)
    mesh = length * np.arange(n_nodes) / (n_nodes - 1)
    e = {"time": t, "mesh": mesh,
         "stress_mesh": length * (np.arange(1, n_points + 1) - 0.5) / n_points}
    position = np.zeros((N_STORED, n_nodes, 3))
    velocity = np.zeros((N_STORED, n_nodes, 3))
    directors = np.zeros((N_STORED, n_nodes, 3, 3))
    director_velocity = np.zeros((N_STORED, n_nodes, 3, 3))
    stress = np.zeros((N_STORED, n_points, 6))
    strain = np.zeros((N_STORED, n_points, 6))
    for step in range(N_STORED):
        th = omega * t[step]
        for a in range(n_nodes):
            s = mesh[a]
            position[step, a] = [s * math.cos(th), s * math.sin(th), rise * t[step]]
            velocity[step, a] = [-s * omega * math.sin(th), s * omega * math.cos(th), rise]
            psi = th + 0.1 * a
            for i in range(3):
                # h5py [step, node, i, :] = d_(i+1) = column i of the rotation.
                directors[step, a, i, :] = rotation(psi)[:, i]
                director_velocity[step, a, i, :] = omega * rotation_rate(psi)[:, i]
        for p in range(n_points):
            for c in range(6):
                stress[step, p, c] = (c + 1) + 10.0 * (p + 1) + 100.0 * t[step] + 1000.0 * k
                strain[step, p, c] = 1.0e-3 * ((c + 1) + 10.0 * (p + 1)) + 0.1 * t[step] * k
    e.update(position=position, velocity=velocity, directors=directors,
             director_velocity=director_velocity, stress=stress, strain=strain)
    if n_branches > 0:
        # h5py [step, branch, point, k]: branch b (1-based) holds 0.1 b stress.
        b = np.arange(1, n_branches + 1)
        e["branch_stress"] = 0.1 * b[None, :, None, None] * stress[:, None, :, :]
    series = {
        "energy/kinetic": k * (1.0 + t**2),
        "energy/strain": k * np.cos(t),
        "energy/external_work": 0.01 * k * (j - 1),
        "energy/balance_error": 1.0e-14 * k * j * (-1.0)**j,
        "energy/dissipated": 0.001 * k * j,
        "energy/actuator_work": -0.002 * k * (j - 1),
        "momentum/linear": k * np.outer(1.0 + t, [1.0, 2.0, 3.0]),
        "momentum/angular": k * np.stack([0.5 + 0 * t, -0.5 + 0 * t, t], axis=1),
        "center_of_mass": np.stack([k * t, 0 * t, 0.5 * length + 0 * t], axis=1),
        "constraint_residual": 1.0e-15 * j,
        "newton/iterations": j + k,
        "newton/residual": 1.0e-10 / j,
        "dt": TIME_STEP + 0 * t,
    }
    series["energy/total"] = series["energy/kinetic"] + series["energy/strain"]
    if k == 1:  # the rod of a bundle
        series["contact/energy"] = 1.0e-3 * j
        series["contact/penetration"] = 1.0e-5 * (j % 3)
        series["contact/force"] = np.stack([1.0 * j, -2.0 * j, 0.5 + 0 * t], axis=1)
        # h5py [step, end, component]; end 0 = start holds Fortran's end 1.
        ends = np.arange(1, 3)
        series["ties/force"] = np.stack([ends[None, :] + 0 * j[:, None],
                                         10.0 * j[:, None] + 0 * ends[None, :],
                                         -1.0 * ends[None, :] * j[:, None]], axis=2)
        series["ties/moment"] = np.stack([0.1 * ends[None, :] * j[:, None],
                                          -1.0 * ends[None, :] + 0 * j[:, None],
                                          0.5 * j[:, None] + 0 * ends[None, :]], axis=2)
        series["contact/friction"] = np.stack([0.25 * j, 0 * t, -1.0 + 0 * t], axis=1)
        series["contact/slip_speed"] = 1.0e-3 * j
    return e, series


def check_result(path):
    with h5py.File(path, "r") as f:
        # Root attributes.
        attrs = f.attrs
        for name in ("schema_version", "creator", "created", "command_line", "n_ranks",
                     "petsc_version", "hdf5_version", "mpi_version", "title"):
            check(name in attrs, "root attribute %s missing" % name)
        check(attrs.get("schema_version") == 2, "schema_version is 2")
        check(re.fullmatch(r"rodsolve \S+ \(git \S+\)", str(attrs.get("creator", ""))),
              "creator 'rodsolve <version> (git <commit>)': %r" % attrs.get("creator"))
        try:
            created = datetime.datetime.fromisoformat(str(attrs.get("created")))
            age = datetime.datetime.now(created.tzinfo) - created
            check(abs(age.total_seconds()) < 3600, "created is recent: %s" % created)
        except ValueError:
            failures.append("created is not ISO 8601: %r" % attrs.get("created"))
        check(re.fullmatch(r"\d+\.\d+\.\d+", str(attrs.get("hdf5_version", ""))),
              "hdf5_version major.minor.release: %r" % attrs.get("hdf5_version"))
        for name, value in META.items():
            check(attrs.get(name) == value, "root attribute %s = %r, expected %r"
                  % (name, attrs.get(name), value))

        # Input texts, verbatim.
        for name, value in (("text", INPUT_TEXT), ("resolved", INPUT_RESOLVED),
                            ("petsc_options", PETSC_OPTIONS)):
            ds = f.get("input/" + name)
            check(isinstance(ds, h5py.Dataset), "/input/%s exists" % name)
            if isinstance(ds, h5py.Dataset):
                check(ds.asstr()[()] == value, "/input/%s verbatim: %r" % (name, ds.asstr()[()]))

        # Every dataset has a unit and a non-empty description.
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                check("unit" in obj.attrs, "%s has a unit" % name)
                check(str(obj.attrs.get("description", "")).strip() != "",
                      "%s has a description" % name)
        f.visititems(visit)

        check(sorted(f["rods"].keys()) == sorted(RODS), "rods: %s" % list(f["rods"].keys()))
        sums = {}
        for name, (k, formulation, n_nodes, n_points, n_branches) in RODS.items():
            g = f["rods"][name]
            check(g.attrs.get("formulation") == formulation, "%s formulation" % name)
            fields, series = expected_rod(k, n_nodes, n_points, n_branches)
            check(("branch_stress" in g) == (n_branches > 0),
                  "%s: branch_stress present exactly with Maxwell branches (%d)"
                  % (name, n_branches))
            if "branch_stress" in g:
                check(g["branch_stress"].shape == (N_STORED, n_branches, n_points, 6),
                      "%s/branch_stress shape %s" % (name, g["branch_stress"].shape))
                check(g["branch_stress"].attrs.get("unit") == STRESS_UNIT,
                      "%s/branch_stress unit" % name)
                check(g["branch_stress"].attrs.get("components") == STRESS_COMPONENTS,
                      "%s/branch_stress components" % name)
            check(g["strain"].shape == (N_STORED, n_points, 6),
                  "%s/strain shape %s" % (name, g["strain"].shape))
            check(g["strain"].attrs.get("unit") == STRAIN_UNIT, "%s/strain unit" % name)
            check(g["strain"].attrs.get("components") == STRAIN_COMPONENTS,
                  "%s/strain components: %r" % (name, g["strain"].attrs.get("components")))
            check(g["stress"].attrs.get("unit") == STRESS_UNIT, "%s/stress unit" % name)
            for key, fragment in DESCRIPTIONS.items():
                if key in g:
                    check(fragment in str(g[key].attrs.get("description", "")),
                          "%s/%s description holds %r" % (name, key, fragment))
                elif key != "branch_stress":
                    failures.append("%s/%s missing" % (name, key))
            if name == "tail":  # the formulation left these out
                del fields["director_velocity"]
                del series["constraint_residual"]
                check("director_velocity" not in g, "tail: no director_velocity dataset")
                check("constraint_residual" not in g["series"],
                      "tail: no constraint_residual dataset (size 0)")
            for field, value in fields.items():
                check(field in g, "%s/%s exists" % (name, field))
                if field in g:
                    check_close(g[field][()], value, "%s/%s" % (name, field))
            for key, value in series.items():
                ds = g["series"].get(key)
                check(ds is not None, "%s/series/%s exists" % (name, key))
                if ds is not None:
                    check_close(ds[()], value, "%s/series/%s" % (name, key), atol=0.0)
                    if key.startswith(("energy/", "momentum/")):
                        sums[key] = sums.get(key, 0) + value
            check(g["stress"].attrs.get("components") == "N1 N2 N3 M1 M2 M3",
                  "%s/stress components" % name)
            check(g["series/newton/iterations"].dtype.kind == "i", "iterations are integers")
            for key, (unit, fragment) in BUNDLE_SERIES.items():
                ds = g["series"].get(key)
                check((ds is not None) == (name in BUNDLE_RODS),
                      "%s/series/%s present exactly for a rod of a bundle" % (name, key))
                if ds is not None:
                    check(ds.attrs.get("unit") == unit, "%s/series/%s unit %r"
                          % (name, key, ds.attrs.get("unit")))
                    check(fragment in str(ds.attrs.get("description", "")),
                          "%s/series/%s description holds %r" % (name, key, fragment))
            if name not in BUNDLE_RODS:
                check("contact" not in g["series"] and "ties" not in g["series"],
                      "%s: no contact or ties group" % name)
            # Chunked along the steps (64 records a chunk, fewer only when a chunk would exceed
            # 1 MiB; records arrive a few at a time) and extendable there; the meshes are
            # contiguous.
            for key in ("position", "directors", "stress", "strain", "time", "series/dt",
                        "series/momentum/linear", "series/energy/dissipated") + \
                    (("branch_stress",) if n_branches > 0 else ()):
                ds = g[key]
                record_bytes = 8 * int(np.prod(ds.shape[1:]))
                check(ds.chunks is not None
                      and ds.chunks[0] == max(1, min(64, (1 << 20) // record_bytes))
                      and ds.chunks[1:] == ds.shape[1:],
                      "%s/%s chunked by steps: %s" % (name, key, ds.chunks))
                check(ds.maxshape[0] is None and ds.maxshape[1:] == ds.shape[1:],
                      "%s/%s extendable along the steps: %s" % (name, key, ds.maxshape))
            check(g["mesh"].chunks is None, "%s/mesh contiguous" % name)

        # Root series: the shared time grid and the sums over the rods.
        check_close(f["series/time"][()], TIME_STEP * np.arange(N_STORED), "/series/time")
        for key in ("energy/dissipated", "energy/actuator_work", "energy/balance_error"):
            check(key in sums, "rod series %s summed" % key)
            check(key in f["series"], "/series/%s exists" % key)
        for key, value in sums.items():
            ds = f["series"].get(key)
            check(ds is not None, "/series/%s exists" % key)
            if ds is not None:
                check_close(ds[()], value, "/series/%s" % key)
        check("constraint_residual" not in f["series"], "no root constraint_residual")
        check("contact" not in f["series"] and "ties" not in f["series"],
              "no root contact or ties series")


def check_reader(path):
    """scripts/rodresults.py reads by name."""
    with rodresults.open_result(path) as res:
        check(res.schema_version == 2, "rodresults schema_version")
        check(res.rods() == ["arm", "tail"], "rodresults rods: %s" % res.rods())
        check(res.title == META["title"], "rodresults title")
        check(res.input_text() == INPUT_TEXT, "rodresults input_text")
        tail = res.rod("tail")
        check(tail.formulation == "se3_strand", "rodresults formulation")
        check(not tail.has("director_velocity"), "rodresults: tail has no director_velocity")
        check(tail.field("position").shape == (N_STORED, 7, 3), "rodresults position shape")
        check(tail.unit("position") == "m", "rodresults unit")
        check("energy/balance_error" in tail.series_names(), "rodresults series names")
        check_close(res.series("energy/kinetic"),
                    sum(expected_rod(k, n, p, b)[1]["energy/kinetic"]
                        for k, _, n, p, b in RODS.values()), "rodresults root series")
        check_close(res.series("energy/dissipated"),
                    sum(expected_rod(k, n, p, b)[1]["energy/dissipated"]
                        for k, _, n, p, b in RODS.values()), "rodresults root dissipated")
        check({"energy/dissipated", "energy/actuator_work"} <= set(res.series_names()),
              "rodresults root series names: %s" % res.series_names())
        check(not tail.has("branch_stress") and res.rod("arm").has("branch_stress"),
              "rodresults: branch_stress only for the rod with branches")
        try:
            res.rod("nope")
            failures.append("rodresults: unknown rod raises")
        except rodresults.UnknownRod as exc:
            check("arm, tail" in str(exc), "UnknownRod lists the rods: %s" % exc)
        try:
            tail.field("director_velocity")
            failures.append("rodresults: missing field raises")
        except rodresults.MissingData as exc:
            check("director_velocity" in str(exc), "MissingData names the field: %s" % exc)


def check_layer(path):
    """Attributes and datasets written directly through rs_io_hdf5_file."""
    with h5py.File(path, "r") as f:
        check(f.attrs.get("label") == "root label", "root string attribute")
        check(isinstance(f.get("a/b/c"), h5py.Group), "nested groups")
        m = f["a/matrix"]
        # Fortran reshape([1..6], [2, 3]) appears transposed: h5py shape (3, 2).
        check_close(m[()], np.arange(1.0, 7.0).reshape(3, 2), "/a/matrix reversed dims")
        check(m.chunks is None, "/a/matrix contiguous")
        check(m.attrs.get("count") == 7, "integer attribute replaced: %r" % m.attrs.get("count"))
        check(m.attrs.get("unit") == "kg", "unit")
        check(f["a/b"].attrs.get("scale") == 2.5, "real attribute")
        check_close(f["a/b"].attrs.get("vector"), [1.0, 2.0, 3.0], "real vector attribute")
        check(f["a/empty_text"].asstr()[()] == "", "empty text dataset")
        check(h5py.check_string_dtype(f["a/empty_text"].dtype).length is None,
              "strings are variable length")


def main():
    directory = sys.argv[1]
    check_result(os.path.join(directory, "nested", "two_rods.h5"))
    check_reader(os.path.join(directory, "nested", "two_rods.h5"))
    check_layer(os.path.join(directory, "layer.h5"))
    for message in failures:
        print("FAILED: " + message)
    print("%d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
