"""Checks an XDMF sidecar of a rodsolve result file (src/io/xdmf_writer.f90) against the HDF5
file it refers to.

    check_xdmf.py FILE.xdmf
    check_xdmf.py --expect-failure TEXT FILE.xdmf

With xml.etree and h5py: the XML parses; every DataItem of Format HDF names a file (relative
to the sidecar) and a dataset that exist, with the DataItem's Dimensions equal to the dataset's
shape and DataType/Precision to its type; every HyperSlab DataItem has a start/stride/count
item of 3 x rank integers whose block lies inside the dataset, and its Dimensions equal the
count. Then the layout the writer promises: one temporal collection whose k-th child is the
spatial collection of record k, with a Time equal to /rods/<rod>/time[k]; in it one Uniform
grid per rod with a Polyline topology through the nodes 0 .. n-1 in order, an XYZ geometry
that is record k of /rods/<rod>/position, and node-centred Vector attributes "velocity"
(record k of velocity) and "d1", "d2", "d3" (record k of directors, director index 0, 1, 2)
of n values each; the number of records equals the number of stored records of the file.

If meshio is importable, it reads single-record extracts: meshio's XDMF readers resolve
neither HyperSlab DataItems nor nested collections (TimeSeriesReader takes the mesh of the
first grid only and expects the attributes directly below each time step, meshio 5), so for
the first and the last record and every rod, the grid is copied with each HyperSlab replaced
by a plain HDF item holding the block, read with meshio.read, and its points, polyline and
point data are compared with h5py's values of the result file.

Exit status 1 with a list of failures. With --expect-failure, exit status 0 if and only if the
check fails with a message containing TEXT (a test that the checker catches what it should).
"""

import argparse
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

import h5py
import numpy as np

#: XDMF number types of the datasets rodsolve writes: (DataType, Precision) -> numpy dtype.
NUMBER_TYPES = {("Float", "8"): np.dtype("float64"), ("Float", "4"): np.dtype("float32"),
                ("Int", "4"): np.dtype("int32"), ("Int", "8"): np.dtype("int64")}


class Checker:
    def __init__(self, xdmf_path):
        self.xdmf_path = xdmf_path
        self.directory = os.path.dirname(os.path.abspath(xdmf_path))
        self.failures = []
        self.files = {}
        self.records = []

    def fail(self, message):
        message = "%s: %s" % (self.xdmf_path, message)
        if message not in self.failures:
            self.failures.append(message)

    def close(self):
        for f in self.files.values():
            f.close()

    # --- data items -----------------------------------------------------------------------

    def hdf_dataset(self, item):
        """The h5py dataset an HDF DataItem refers to, or None (with a failure)."""
        reference = (item.text or "").strip()
        if ":" not in reference:
            self.fail("HDF DataItem %r has no 'file:/dataset'" % reference)
            return None
        name, path = reference.split(":", 1)
        full = os.path.join(self.directory, name)
        if full not in self.files:
            if not os.path.isfile(full):
                self.fail("%s: no such HDF5 file (next to the sidecar)" % name)
                return None
            try:
                self.files[full] = h5py.File(full, "r")
            except OSError as exc:
                self.fail("%s: cannot open: %s" % (name, exc))
                return None
        dataset = self.files[full].get(path)
        if not isinstance(dataset, h5py.Dataset):
            self.fail("%s: no dataset %s" % (name, path))
            return None
        dims = dimensions(item)
        if dims != list(dataset.shape):
            self.fail("%s: Dimensions %s but the dataset has shape %s"
                      % (reference, " ".join(map(str, dims)),
                         " ".join(map(str, dataset.shape))))
        kind = (item.get("DataType") or item.get("NumberType") or "Float",
                item.get("Precision") or "4")
        if NUMBER_TYPES.get(kind) != dataset.dtype:
            self.fail("%s: DataType %s Precision %s but the dataset holds %s"
                      % (reference, kind[0], kind[1], dataset.dtype))
        return dataset

    def resolve(self, item):
        """(values, dataset, start) of a DataItem: XML, HDF or HyperSlab of HDF. `dataset`
        and `start` are None unless it refers to an HDF5 dataset. None on failure."""
        if item.get("ItemType") == "HyperSlab":
            return self.hyperslab(item)
        fmt = item.get("Format", "XML")
        if fmt == "HDF":
            dataset = self.hdf_dataset(item)
            if dataset is None:
                return None
            return dataset[()], dataset, [0] * dataset.ndim
        if fmt == "XML":
            kind = (item.get("DataType") or item.get("NumberType") or "Float",
                    item.get("Precision") or "4")
            values = np.array((item.text or "").split(), dtype=NUMBER_TYPES.get(kind, float))
            dims = dimensions(item)
            if values.size != int(np.prod(dims)):
                self.fail("XML DataItem of Dimensions %s holds %d values" % (dims, values.size))
                return None
            return values.reshape(dims), None, None
        self.fail("DataItem Format %r (expected XML or HDF)" % fmt)
        return None

    def hyperslab(self, item):
        children = item.findall("DataItem")
        if len(children) != 2:
            self.fail("HyperSlab DataItem with %d DataItem children (expected 2)"
                      % len(children))
            return None
        selection, source = children
        if source.get("Format") != "HDF":
            self.fail("HyperSlab of a %s DataItem (expected HDF)" % source.get("Format"))
            return None
        reference = (source.text or "").strip()
        dataset = self.hdf_dataset(source)
        try:
            numbers = [int(v) for v in (selection.text or "").split()]
        except ValueError:
            self.fail("%s: the HyperSlab selection is not integers" % reference)
            return None
        rank = len(dimensions(source))
        if dimensions(selection) != [3, rank] or len(numbers) != 3 * rank:
            self.fail("%s: HyperSlab selection of Dimensions %s with %d numbers (expected 3 x %d)"
                      % (reference, dimensions(selection), len(numbers), rank))
            return None
        start, stride, count = numbers[:rank], numbers[rank:2 * rank], numbers[2 * rank:]
        if dimensions(item) != count:
            self.fail("%s: HyperSlab Dimensions %s differ from its count %s"
                      % (reference, dimensions(item), count))
        if dataset is None:
            return None
        shape = dataset.shape
        if len(shape) != rank or any(s < 0 for s in start) or any(s < 1 for s in stride) or \
                any(c < 1 for c in count) or \
                any(a + (c - 1) * s >= n for a, s, c, n in zip(start, stride, count, shape)):
            self.fail("%s: HyperSlab start %s stride %s count %s exceeds the shape %s"
                      % (reference, start, stride, count, shape))
            return None
        block = tuple(slice(a, a + (c - 1) * s + 1, s) for a, s, c in zip(start, stride, count))
        return dataset[block], dataset, start

    # --- the layout -----------------------------------------------------------------------

    def check(self):
        try:
            root = ET.parse(self.xdmf_path).getroot()
        except (ET.ParseError, OSError) as exc:
            self.fail("not XML: %s" % exc)
            return
        if root.tag != "Xdmf" or root.get("Version", "").split(".")[0] not in ("2", "3"):
            self.fail("root <%s Version=%r> (expected Xdmf version 2 or 3)"
                      % (root.tag, root.get("Version")))
        domains = root.findall("Domain")
        if len(domains) != 1:
            self.fail("%d Domain elements (expected 1)" % len(domains))
            return
        temporal = [g for g in domains[0].findall("Grid")
                    if g.get("GridType") == "Collection"
                    and g.get("CollectionType") == "Temporal"]
        if len(temporal) != 1:
            self.fail("%d temporal collections (expected 1)" % len(temporal))
            return
        records = temporal[0].findall("Grid")
        self.n_rods = None
        self.stored = {}
        previous = None
        for k, record in enumerate(records):
            where = "record %d" % k
            if record.get("GridType") != "Collection" or \
                    record.get("CollectionType") != "Spatial":
                self.fail("%s: not a spatial collection" % where)
                continue
            times = record.findall("Time")
            if len(times) != 1:
                self.fail("%s: %d Time elements" % (where, len(times)))
                continue
            time = float(times[0].get("Value"))
            if previous is not None and not time > previous:
                self.fail("%s: time %r after %r" % (where, time, previous))
            previous = time
            grids = record.findall("Grid")
            if self.n_rods is None:
                self.n_rods = len(grids)
            if len(grids) != self.n_rods or not grids:
                self.fail("%s: %d rods (record 0 has %d)" % (where, len(grids), self.n_rods))
            for grid in grids:
                self.check_rod(grid, k, time)
        for path, n_stored in sorted(self.stored.items()):
            if n_stored != len(records):
                self.fail("%s holds %d records, the sidecar shows %d"
                          % (path, n_stored, len(records)))
        self.records = records

    def check_rod(self, grid, k, time):
        name = grid.get("Name")
        where = "record %d, rod %r" % (k, name)
        if grid.get("GridType") != "Uniform":
            self.fail("%s: GridType %r (expected Uniform)" % (where, grid.get("GridType")))
            return
        topology, geometry = grid.find("Topology"), grid.find("Geometry")
        if topology is None or geometry is None:
            self.fail("%s: no Topology or no Geometry" % where)
            return
        if geometry.get("GeometryType") != "XYZ":
            self.fail("%s: GeometryType %r" % (where, geometry.get("GeometryType")))
        resolved = self.resolve(geometry.find("DataItem"))
        if resolved is None:
            return
        points, dataset, start = resolved
        if dataset is None or not dataset.name == "/rods/%s/position" % name:
            self.fail("%s: the geometry is not /rods/%s/position" % (where, name))
            return
        n = dataset.shape[1]
        if points.size != 3 * n or start[0] != k:
            self.fail("%s: the geometry is not record %d of %s (start %s, %d values)"
                      % (where, k, dataset.name, start, points.size))
        self.stored[dataset.name] = dataset.shape[0]
        time_set = dataset.parent.get("time")
        if isinstance(time_set, h5py.Dataset) and start[0] < time_set.shape[0]:
            expected = time_set[start[0]]
            if abs(time - expected) > 1e-12 * max(1.0, abs(expected)):
                self.fail("%s: Time %r but %s/time[%d] = %r"
                          % (where, time, dataset.parent.name, start[0], expected))

        if topology.get("TopologyType", topology.get("Type")) != "Polyline" or \
                topology.get("NodesPerElement") != str(n) or \
                topology.get("NumberOfElements", "1") != "1":
            self.fail("%s: topology %s (expected one Polyline of %d nodes)"
                      % (where, topology.attrib, n))
        connectivity = self.resolve(topology.find("DataItem"))
        if connectivity is not None and \
                not np.array_equal(np.ravel(connectivity[0]), np.arange(n)):
            self.fail("%s: the polyline does not run through the nodes 0 .. %d in order"
                      % (where, n - 1))

        names = []
        for attribute in grid.findall("Attribute"):
            label = attribute.get("Name")
            names.append(label)
            here = "%s, attribute %r" % (where, label)
            if attribute.get("Center") != "Node" or \
                    attribute.get("AttributeType", attribute.get("Type")) != "Vector":
                self.fail("%s: not a node-centred Vector" % here)
            resolved = self.resolve(attribute.find("DataItem"))
            if resolved is None:
                continue
            values, source, first = resolved
            if values.size != 3 * n:
                self.fail("%s: %d values for %d nodes" % (here, values.size, n))
            if label == "velocity":
                expected = ("/rods/%s/velocity" % name, [k, 0, 0])
            elif label in ("d1", "d2", "d3"):
                expected = ("/rods/%s/directors" % name, [k, 0, int(label[1]) - 1, 0])
            else:
                self.fail("%s: unknown attribute" % here)
                continue
            if source is None or (source.name, list(first)) != expected:
                self.fail("%s: from %s at %s, expected %s at %s"
                          % (here, None if source is None else source.name, first,
                             expected[0], expected[1]))
        if len(set(names)) != len(names):
            self.fail("%s: repeated attributes %s" % (where, names))

    # --- meshio ---------------------------------------------------------------------------

    def check_meshio(self, meshio):
        """Single-record, single-rod extracts read with meshio.read (see the module doc)."""
        if not self.records:
            return 0
        checked = 0
        with tempfile.TemporaryDirectory() as scratch:
            for k in sorted({0, len(self.records) - 1}):
                for grid in self.records[k].findall("Grid"):
                    self.meshio_extract(meshio, grid, k, scratch)
                    checked += 1
        return checked

    def meshio_extract(self, meshio, grid, k, scratch):
        name = grid.get("Name")
        where = "meshio, record %d, rod %r" % (k, name)
        stem = os.path.join(scratch, "extract_%d_%d" % (k, len(os.listdir(scratch))))
        extract = ET.Element("Grid", {"Name": name, "GridType": "Uniform"})
        expected = {}
        with h5py.File(stem + ".h5", "w") as h5:
            for element in grid:
                if element.tag not in ("Topology", "Geometry", "Attribute"):
                    continue
                copy = ET.SubElement(extract, element.tag, dict(element.attrib))
                item = element.find("DataItem")
                if element.tag == "Topology":
                    copy.append(item)
                    continue
                resolved = self.resolve(item)
                if resolved is None:
                    return
                values = np.asarray(resolved[0]).reshape(-1, 3)
                label = "points" if element.tag == "Geometry" else element.get("Name")
                h5[label] = values
                expected[label] = reference_values(resolved[1].file["rods"][name], label, k)
                data = ET.SubElement(copy, "DataItem", {
                    "Format": "HDF", "DataType": "Float", "Precision": "8",
                    "Dimensions": "%d 3" % values.shape[0]})
                data.text = "%s:/%s" % (os.path.basename(stem) + ".h5", label)
        document = ET.Element("Xdmf", {"Version": "3.0"})
        ET.SubElement(document, "Domain").append(extract)
        ET.ElementTree(document).write(stem + ".xdmf")
        try:
            mesh = meshio.read(stem + ".xdmf")
        except Exception as exc:  # noqa: BLE001 - any meshio error is a finding
            self.fail("%s: meshio.read fails: %r" % (where, exc))
            return
        n = expected["points"].shape[0]
        if not np.array_equal(mesh.points, expected["points"]):
            self.fail("%s: points differ from position[%d]" % (where, k))
        blocks = [(block.type, block.data) for block in mesh.cells]
        if len(blocks) != 1 or blocks[0][0] != "line" or \
                not np.array_equal(blocks[0][1], np.arange(n).reshape(1, n)):
            self.fail("%s: cells %s, expected one polyline 0 .. %d" % (where, blocks, n - 1))
        for label, values in expected.items():
            if label == "points":
                continue
            got = mesh.point_data.get(label)
            if got is None or not np.array_equal(got, values):
                self.fail("%s: point data %r differs from the result file" % (where, label))
        if sorted(mesh.point_data) != sorted(k for k in expected if k != "points"):
            self.fail("%s: point data %s" % (where, sorted(mesh.point_data)))


def reference_values(group, label, k):
    """What the grid of record k should show as `label`, read directly from the rod's group
    of the result file."""
    if label == "points":
        return group["position"][k]
    if label == "velocity":
        return group["velocity"][k]
    return group["directors"][k, :, int(label[1]) - 1, :]


def dimensions(item):
    try:
        return [int(v) for v in (item.get("Dimensions") or "").split()]
    except ValueError:
        return []


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("xdmf", help="the sidecar, FILE.xdmf")
    parser.add_argument("--expect-failure", metavar="TEXT",
                        help="succeed only if the check fails with a message containing TEXT")
    args = parser.parse_args()

    checker = Checker(args.xdmf)
    try:
        checker.check()
        try:
            import meshio
        except ImportError:
            meshio = None
        if meshio is None:
            print("meshio is not installed: no meshio check")
        elif not checker.failures:
            print("meshio %s read %d single-record extracts"
                  % (meshio.__version__, checker.check_meshio(meshio)))
    finally:
        checker.close()

    for message in checker.failures:
        print("FAILED: " + message)
    print("%d failures (%d records)" % (len(checker.failures), len(checker.records)))
    if args.expect_failure is not None:
        if any(args.expect_failure in message for message in checker.failures):
            print("the expected failure was found: %r" % args.expect_failure)
            return 0
        print("FAILED: expected a failure containing %r" % args.expect_failure)
        return 1
    return 1 if checker.failures else 0


if __name__ == "__main__":
    sys.exit(main())
