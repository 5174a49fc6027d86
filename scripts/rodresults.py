"""Read rodsolve result files (HDF5, schema versions 1 and 2; docs/user/output.md).

Everything is looked up by dataset name, never by position, so files with more or fewer
fields read the same way. Needs only h5py and numpy.

    from rodresults import open_result
    with open_result("out/flying_spaghetti.h5") as res:
        print(res.rods())                            # ['spaghetti']
        rod = res.rod("spaghetti")
        x = rod.field("position")                    # (steps, nodes, 3)
        d = rod.field("directors")                   # (steps, nodes, 3, 3); d[s, k, i] = d_{i+1}
        t = rod.field("time")
        H = rod.series("energy/total")               # per rod
        W = res.series("energy/external_work")       # summed over rods
        print(rod.unit("position"), rod.description("position"))

Errors are `ResultError` (or its subclasses `NotAResultFile`, `UnknownRod`, `MissingData`),
with a message meant for users.
"""

import os

import h5py
import numpy as np

#: Schema versions this module reads.
SUPPORTED_SCHEMA_VERSIONS = (1, 2)


class ResultError(Exception):
    """A result file cannot give what was asked for."""


class NotAResultFile(ResultError):
    """The file is missing, not HDF5, or has no schema_version attribute."""


class UnknownRod(ResultError):
    """No rod of that name; `available` lists the rods of the file."""

    def __init__(self, name, available, path):
        self.name = name
        self.available = list(available)
        super().__init__(
            "%s: no rod named '%s'; available rods: %s"
            % (path, name, ", ".join(self.available) if self.available else "(none)"))


class MissingData(ResultError):
    """A dataset that the file does not hold (e.g. a field the formulation does not write)."""


def _text(value):
    """An attribute or string-dataset value as str."""
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, np.ndarray) and value.shape == ():
        return _text(value[()])
    if isinstance(value, np.generic):
        return value.item()
    return value


def _datasets_below(group, prefix=""):
    """Names of all datasets below `group`, relative to it ('energy/total')."""
    names = []
    for key in group:
        item = group[key]
        if isinstance(item, h5py.Dataset):
            names.append(prefix + key)
        elif isinstance(item, h5py.Group):
            names.extend(_datasets_below(item, prefix + key + "/"))
    return sorted(names)


class Rod:
    """One rod of a result file: `/rods/<name>/`."""

    def __init__(self, result, name):
        self._result = result
        self.name = name
        self._group = result.file["rods"][name]

    @property
    def formulation(self):
        """The formulation that computed this rod."""
        return _text(self._group.attrs.get("formulation", ""))

    def fields(self):
        """Names of the rod's fields (datasets directly under /rods/<name>/)."""
        return sorted(k for k, v in self._group.items() if isinstance(v, h5py.Dataset))

    def has(self, name):
        """Whether the field or series path (relative to the rod, 'series/dt') exists."""
        return isinstance(self._group.get(name), h5py.Dataset)

    def field(self, name):
        """A field as a numpy array, e.g. 'position' (steps, nodes, 3)."""
        return self._dataset(name)[()]

    def series_names(self):
        """Names of the rod's series ('energy/kinetic', 'dt', ...)."""
        if "series" not in self._group:
            return []
        return _datasets_below(self._group["series"])

    def series(self, name):
        """A series as a numpy array: 'energy/total' (steps,), 'momentum/linear' (steps, 3)."""
        return self._dataset("series/" + name)[()]

    def unit(self, name):
        """The `unit` attribute of a field or of 'series/...'."""
        return _text(self._dataset(name).attrs.get("unit", ""))

    def description(self, name):
        """The `description` attribute of a field or of 'series/...'."""
        return _text(self._dataset(name).attrs.get("description", ""))

    def _dataset(self, name):
        item = self._group.get(name)
        if not isinstance(item, h5py.Dataset):
            raise MissingData(
                "%s: rod '%s' (%s) has no dataset '%s'; it has: %s"
                % (self._result.path, self.name, self.formulation, name,
                   ", ".join(self.fields() + ["series/" + s for s in self.series_names()])))
        return item

    def __repr__(self):
        return "Rod(%r, formulation=%r)" % (self.name, self.formulation)


def why_unreadable(path, exc):
    """What h5py's OSError on opening `path` means: another program holds it (HDF5's file
    lock, e.g. a rodsolve run writing it: its PATH.lock names the run), or it is no HDF5
    file at all."""
    text = str(exc).lower()
    if "lock" in text or "resource temporarily unavailable" in text or os.path.exists(
            path + ".lock"):
        holder = ""
        if os.path.exists(path + ".lock"):
            with open(path + ".lock", encoding="utf-8", errors="replace") as f:
                holder = f.read().strip()
        return ("open in another program (a run still writing it?%s); wait for it, or read a "
                "copy" % (": " + holder if holder else ""))
    with open(path, "rb") as f:
        if f.read(8) == b"\x89HDF\r\n\x1a\n":
            return "an HDF5 file that cannot be read (damaged or cut short?)"
    return "not an HDF5 file"


class ResultFile:
    """An open rodsolve result file. Use as a context manager or call close()."""

    def __init__(self, path):
        self.path = str(path)
        if not os.path.exists(self.path):
            raise NotAResultFile("%s: no such file" % self.path)
        try:
            self.file = h5py.File(self.path, "r")
        except OSError as exc:
            raise NotAResultFile("%s: %s (%s)" % (self.path, why_unreadable(self.path, exc),
                                                  exc)) from None
        if "schema_version" not in self.file.attrs:
            self.file.close()
            raise NotAResultFile(
                "%s: not a rodsolve result file (no schema_version attribute)" % self.path)
        self.schema_version = int(self.file.attrs["schema_version"])
        if self.schema_version not in SUPPORTED_SCHEMA_VERSIONS:
            self.file.close()
            raise NotAResultFile(
                "%s: schema version %d; this reader knows %s"
                % (self.path, self.schema_version, SUPPORTED_SCHEMA_VERSIONS))

    def close(self):
        """Close the file."""
        self.file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    @property
    def attrs(self):
        """The root attributes (creator, created, command_line, versions, title, ...)."""
        return {k: _text(v) for k, v in self.file.attrs.items()}

    @property
    def title(self):
        """The scene's title."""
        return _text(self.file.attrs.get("title", ""))

    def rods(self):
        """Names of the rods, in file order (alphabetical)."""
        if "rods" not in self.file:
            return []
        return list(self.file["rods"].keys())

    def rod(self, name):
        """The rod `name`; raises UnknownRod listing the available rods."""
        if name not in self.rods():
            raise UnknownRod(name, self.rods(), self.path)
        return Rod(self, name)

    def series_names(self):
        """Names of the root series (summed over rods): 'time', 'energy/total', ..."""
        if "series" not in self.file:
            return []
        return _datasets_below(self.file["series"])

    def series(self, name):
        """A root series as a numpy array: 'time', 'energy/kinetic', 'momentum/linear', ..."""
        item = self.file.get("series/" + name)
        if not isinstance(item, h5py.Dataset):
            raise MissingData("%s: no series '%s'; available: %s"
                              % (self.path, name, ", ".join(self.series_names())))
        return item[()]

    def time(self):
        """The shared time grid of the stored records."""
        return self.series("time")

    def input_text(self):
        """The scene file as given."""
        return self._string("input/text")

    def resolved_input(self):
        """The resolved scene (defaults included) as namelist text."""
        return self._string("input/resolved")

    def petsc_options(self):
        """The PETSc options in use."""
        return self._string("input/petsc_options")

    def _string(self, path):
        item = self.file.get(path)
        if not isinstance(item, h5py.Dataset):
            raise MissingData("%s: no dataset '%s'" % (self.path, path))
        return _text(item[()])


def open_result(path):
    """Open a result file for reading (see ResultFile)."""
    return ResultFile(path)
