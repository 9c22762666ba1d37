"""``planetwear simulate`` output (docs/output-format.md) as an xarray.Dataset.

    ds = load_simulation("run.h5")
    ds.sun_planet_deflection            # (planet, time) [m]
    ds.sun_planet_acceleration_spectrum # (planet, frequency) [m/s^2]
    ds.mesh_frequency                   # 0-d [Hz]
    ds.wear_sun_depth                   # (mesh_cycles, sun_tooth, sun_element) [m], wear runs only
    ds.attrs["config_toml"]             # the resolved configuration

Naming: a dataset path becomes a variable name with '/' -> '_'. A path with
one integer component (``sun_planet/<i>/deflection``, ``load_sharing/<i>``,
``natural_frequency/<k>``) is stacked with its siblings along a dimension
named by the component before the index: ``planet`` for meshes and load
shares, ``mode`` for natural frequencies, ``<component>_index`` otherwise.
Members missing for some index (e.g. ``--channels sun_planet/0/``) are NaN.
Spectra get the suffix ``_spectrum``, curves ``_curve``; a scalar whose name
a channel already has gets ``_scalar`` (``sun_speed_scalar``, the nominal
speed, beside the channel ``sun_speed``).
Every variable and coordinate has a ``units`` attribute (SI, "1" =
dimensionless or an index) and ``description``; ``hdf5_path`` says where the
numbers came from (``{planet}`` standing for the index).
"""
from collections import defaultdict

import numpy as np
import xarray as xr

from . import _hdf5
from ._names import split_index, split_planet_flank, variable_name

FORMAT = "planetwear.simulation"
NEWEST_FORMAT_VERSION = 1

# Coordinates that are indices: their units and descriptions.
_INDEX_DESCRIPTIONS = {
    "planet": "planet number (from 0, docs/derivation.md)",
    "mode": "mode number of the linearized model, by ascending natural frequency",
}


class _Builder:
    """Collects variables, stacks index families, builds the Dataset."""

    def __init__(self):
        self.coords = {}
        self.plain = {}                       # name -> (dims, values, attrs)
        self.families = defaultdict(dict)     # (name, index dim) -> {index: (dims, values, attrs, path)}

    def coordinate(self, name, values, units, description, dim=None):
        self.coords[name] = ((dim or name,), np.asarray(values), {"units": units, "description": description})

    def add(self, h5_name, dims, values, attrs, path, suffix="", on_collision=""):
        """Adds the dataset `h5_name` (relative to its section) with `dims`,
        as `<name><suffix>`, or `<name><suffix><on_collision>` if an earlier
        section took that name (the scalar sun/speed beside the channel)."""
        family, index_dim, index = split_index(h5_name)
        if index_dim is None:
            self.add_plain(variable_name(h5_name) + suffix, dims, values, attrs, path, on_collision)
        else:
            self.add_stacked(variable_name(family) + suffix, index_dim, index, dims, values, attrs, path, on_collision)

    def add_plain(self, name, dims, values, attrs, path, on_collision=""):
        if self._taken(name, None, None):
            name += on_collision
        self.plain[name] = (tuple(dims), np.asarray(values), dict(attrs, hdf5_path=path))

    def add_stacked(self, name, index_dim, index, dims, values, attrs, path, on_collision=""):
        """Adds member `index` of the family `name` stacked along `index_dim`."""
        if self._taken(name, index_dim, index):
            name += on_collision
        self.families[(name, index_dim)][index] = (tuple(dims), np.asarray(values), dict(attrs, hdf5_path=path), path)

    def _taken(self, name, index_dim, index):
        """Whether `name` is used otherwise than by the family (name, index_dim) without `index`."""
        if name in self.plain or name in self.coords:
            return True
        for (other, other_dim), members in self.families.items():
            if other == name and (other_dim != index_dim or index in members):
                return True
        return False

    def build(self, attrs):
        variables = dict(self.plain)
        index_values = defaultdict(set)
        stackable = {}
        for (name, index_dim), members in self.families.items():
            if self._consistent(members):
                stackable[(name, index_dim)] = members
                index_values[index_dim].update(members)
            else:  # different shapes, axes or units: one variable per member
                for index, (dims, values, member_attrs, path) in members.items():
                    variables[f"{name}_{index_dim}_{index}"] = (dims, values, member_attrs)
        coords = dict(self.coords)
        for dim, indices in index_values.items():
            coords[dim] = ((dim,), np.array(sorted(indices)),
                           {"units": "1", "description": _INDEX_DESCRIPTIONS.get(dim, f"index of {dim[:-6] or dim}")})
        for (name, index_dim), members in stackable.items():
            variables[name] = self._stack(index_dim, coords[index_dim][1], members)
        for name in [n for n in variables if n in coords]:  # a coordinate declared after a like-named result
            variables[name + "_value"] = variables.pop(name)
        return xr.Dataset(variables, coords=coords, attrs=attrs)

    @staticmethod
    def _consistent(members):
        first = next(iter(members.values()))
        return all(m[0] == first[0] and m[1].shape == first[1].shape and m[2].get("units") == first[2].get("units")
                   for m in members.values())

    @staticmethod
    def _stack(index_dim, indices, members):
        dims, first, attrs, path = next(iter(members.values()))
        data = np.full((len(indices),) + first.shape, np.nan)
        for index, (_, values, _, _) in members.items():
            data[int(np.searchsorted(indices, index))] = values
        attrs = dict(attrs, hdf5_path=_index_pattern(path, index_dim, next(iter(members))))
        return (index_dim,) + dims, data, attrs


def _index_pattern(path, index_dim, index):
    """'/time_history/sun_planet/0/deflection' -> '/time_history/sun_planet/{planet}/deflection'."""
    parts = path.split("/")
    for k in reversed(range(len(parts))):  # the last match: /wear/snapshots/<k>/... has an index before it
        p = parts[k]
        if p == str(index):
            parts[k] = "{" + index_dim + "}"
            return "/".join(parts)
        if p == f"planet_{index}":
            parts[k] = "planet_{" + index_dim + "}"
            return "/".join(parts)
    return path


def _attrs(dataset, **extra):
    return dict({"units": _hdf5.unit(dataset), "description": _hdf5.description(dataset)}, **extra)


def _add_time_history(b, group):
    """Time base and channels of a /time_history-like group."""
    if "time" not in group:
        return
    b.coordinate("time", group["time"][()], "s", "sample time")
    for name, ds in _hdf5.datasets_below(group).items():
        if name != "time":
            b.add(name, ("time",), ds[()], _attrs(ds), ds.name)


def _add_spectra(b, group):
    """Spectra on one `frequency` axis; a spectrum on another axis gets a
    dimension `<variable>_frequency` of its own."""
    spectra = {name: g for name, g in _spectrum_groups(group)}
    shared = None
    for name, g in spectra.items():
        frequency = g["frequency"][()]
        if shared is None:
            shared = frequency
            b.coordinate("frequency", frequency, "Hz", "frequency of the spectral bin")
        dim = "frequency"
        if not np.array_equal(frequency, shared):
            dim = variable_name(name) + "_frequency"
            b.coordinate(dim, frequency, "Hz", f"frequency of the bins of the spectrum of {name}")
        amplitude = g["amplitude"]
        attrs = _attrs(amplitude, description=f"amplitude spectrum of {name}: " + _hdf5.description(amplitude))
        for key in ("window", "scaling"):
            if key in g.attrs:
                attrs[key] = _hdf5.text(g.attrs[key])
        b.add(name, (dim,), amplitude[()], attrs, amplitude.name, suffix="_spectrum", on_collision="_2")


def _spectrum_groups(group):
    """(name, group) of every spectrum (a group with frequency and amplitude) below `group`."""
    found = []

    def visit(name, obj):
        if hasattr(obj, "keys") and "frequency" in obj and "amplitude" in obj:
            found.append((name, obj))
    group.visititems(visit)
    return sorted(found, key=lambda item: item[0])


def _add_scalars(b, group):
    for name, ds in _hdf5.datasets_below(group).items():
        b.add(name, (), ds[()], _attrs(ds), ds.name, on_collision="_scalar")


def _add_curves(b, group):
    for name, g in _curve_groups(group):
        var = variable_name(name)
        x_name = _hdf5.text(g.attrs.get("x_name", "x"))
        dim = f"{var}_{variable_name(x_name)}"
        b.coordinate(dim, g["x"][()], _hdf5.unit(g["x"]), x_name)
        b.add(name, (dim,), g["y"][()], _attrs(g["y"], description=_hdf5.description(g) or x_name), g["y"].name,
              suffix="_curve", on_collision="_2")


def _curve_groups(group):
    found = []
    group.visititems(lambda name, obj: found.append((name, obj)) if hasattr(obj, "keys") and "x" in obj and "y" in obj
                     else None)
    return sorted(found, key=lambda item: item[0])


def _add_wear(b, wear):
    """/wear: backlash and, per flank family, depth, max depth and element
    positions over the wear updates (dimension mesh_cycles); the flanks of
    the planets are stacked along `planet`."""
    b.coordinate("mesh_cycles", wear["mesh_cycles"][()], "1", "mesh cycles run at the wear update")
    backlash = wear["backlash"]
    columns = _hdf5.text(backlash.attrs.get("columns", "sun_planet,planet_ring")).split(",")
    b.coordinate("mesh", np.array(columns, dtype=object), "1", "mesh family of a backlash column")
    b.add_plain("wear_backlash", ("mesh_cycles", "mesh"), backlash[()], _attrs(backlash), backlash.name, "_2")
    for flank_name, g in _flank_groups(wear):
        family, planet = split_planet_flank(flank_name)
        f = variable_name(family)
        tooth, element = f"{f}_tooth", f"{f}_element"
        depth, positions = g["depth"], g["distance_from_pitch_point"]
        b.coordinate(tooth, np.arange(depth.shape[1]), "1", f"tooth number of the {family} flanks")
        b.coordinate(element, np.arange(depth.shape[2]), "1", f"flank element of the {family} flanks, "
                     "ordered as distance_from_pitch_point")
        entries = [(f"wear_{f}_depth", ("mesh_cycles", tooth, element), depth),
                   (f"wear_{f}_max_depth", ("mesh_cycles",), g["max_depth"]),
                   (f"{f}_distance_from_pitch_point", (element,), positions)]
        for name, dims, ds in entries:
            if planet is None:
                b.add_plain(name, dims, ds[()], _attrs(ds), ds.name, "_2")
            else:
                b.add_stacked(name, "planet", planet, dims, ds[()], _attrs(ds), ds.name, "_2")


def _flank_groups(wear):
    found = []
    wear.visititems(lambda name, obj: found.append((name, obj)) if hasattr(obj, "keys") and "depth" in obj else None)
    return sorted(found, key=lambda item: item[0])


def _as_coordinates(ds):
    """Element positions become coordinates (of the element dimension; of
    (planet, element) if the planets' flanks differ)."""
    names = [n for n in ds.data_vars if n.endswith("_distance_from_pitch_point")]
    ds = ds.set_coords(names)
    for n in names:  # the planets share one gear design: keep one row if all stored rows are equal
        if "planet" not in ds[n].dims:
            continue
        stored = ds[n].dropna("planet", how="all")  # planets with no flank data are all NaN
        if stored.sizes["planet"] and bool((stored == stored.isel(planet=0)).all()):
            ds = ds.assign_coords({n: stored.isel(planet=0, drop=True)})
    return ds


def _root_attrs(f, path):
    attrs = {"source": str(path)}
    for key, value in f.attrs.items():
        attrs[key] = _hdf5.text(value) if isinstance(value, (bytes, str)) else value.item()
    if "config" in f and "toml" in f["config"]:
        attrs["config_toml"] = f["config/toml"].asstr()[()]
    if "time_history" in f and "time_step_s" in f["time_history"].attrs:
        attrs["time_step_s"] = float(f["time_history"].attrs["time_step_s"])
    return attrs


def load_simulation(path, wear=True):
    """The simulation file `path` as an xarray.Dataset (module docstring).

    wear=False skips /wear (large wear runs). The dynamic snapshots of a
    wear run are in load_wear_snapshots(path). Raises FormatError for a file
    that is not a planetwear simulation file."""
    with _hdf5.open_checked(path, FORMAT, NEWEST_FORMAT_VERSION) as f:
        b = _Builder()
        _add_time_history(b, f["time_history"])
        _add_spectra(b, f["spectra"])
        _add_scalars(b, f["scalars"])
        _add_curves(b, f["curves"])
        attrs = _root_attrs(f, path)
        if wear and "wear" in f:
            _add_wear(b, f["wear"])
            attrs["wear_stop_reason"] = _hdf5.text(f["wear"].attrs.get("stop_reason", ""))
            attrs["wear_snapshots"] = len(f["wear/snapshots"]) if "snapshots" in f["wear"] else 0
        ds = b.build(attrs)
    return _as_coordinates(ds)


def load_wear_snapshots(path):
    """The dynamic snapshots of a wear run (docs/output-format.md, "Wear"),
    one xarray.Dataset each (time histories and spectra, named as in
    load_simulation), in order of mesh cycles (attribute ``mesh_cycles``).
    Empty for a run without wear."""
    with _hdf5.open_checked(path, FORMAT, NEWEST_FORMAT_VERSION) as f:
        if "wear/snapshots" not in f:
            return []
        groups = sorted(f["wear/snapshots"].values(), key=lambda g: float(g.attrs["mesh_cycles"]))
        out = []
        for g in groups:
            b = _Builder()
            if "time_history" in g:
                _add_time_history(b, g["time_history"])
            if "spectra" in g:
                _add_spectra(b, g["spectra"])
            out.append(b.build({"source": str(path), "mesh_cycles": float(g.attrs["mesh_cycles"]),
                                "hdf5_path": g.name}))
        return out
