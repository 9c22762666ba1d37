"""``planetwear sweep`` archives (docs/archive-format.md) as pandas tables.

    design, results = load_campaign("campaign.h5")
    design                                  # DataFrame, index "case": factors, status, message, ...
    results.scalars                         # DataFrame, index "case": one column per scalar result
    table = design.join(results.scalars)    # both are indexed by the case
    results.units["efficiency"]             # '1'
    results.spectrum("sun_planet/0/acceleration", 3)    # xarray.DataArray over frequency [Hz]
    results.array("wear/sun/depth_final", 3)            # numpy, the case's valid elements only

Row r of every /design and /results dataset belongs to case /design/case[r]
(the archive declares /case, equal to it, the dimension scale of those rows); in a
whole-campaign archive r = case, in the slice archives of an array job not
necessarily, so rows are looked up by case. Pending and failed cases have
NaN results.
"""
import numpy as np
import pandas as pd
import xarray as xr

from . import _hdf5

FORMAT = "planetwear.campaign"
NEWEST_FORMAT_VERSION = 1

# Beside a padded [cases, k] dataset, the int dataset giving each case's valid k.
_LENGTHS = ("bins", "elements", "samples")


def _design_table(f):
    """/design as a DataFrame in the archive's column order, strings decoded."""
    group = f["design"]
    order = _hdf5.text(group.attrs.get("columns", "")).split(",")
    names = [c for c in order if c in group] + sorted(c for c in _hdf5.datasets_below(group) if c not in order)
    columns = {}
    for name in names:
        ds = group[name]
        columns[name] = _hdf5.read_strings(ds) if ds.dtype.kind in "OS" else ds[()]
    index = pd.Index(group["case"][()], name="case")
    table = pd.DataFrame({k: v for k, v in columns.items() if k != "case"}, index=index)
    table.attrs["units"] = {k: _hdf5.unit(group[k], default="") for k in names if "unit" in group[k].attrs}
    return table


class CampaignResults:
    """The /results of an archive: scalar results as a DataFrame indexed by
    case, and the per-case arrays (spectra, wear profiles, time histories)
    read on demand, cut to each case's valid length."""

    def __init__(self, path, scalars, units, descriptions, arrays, lengths, attrs, campaign, base_config_toml,
                 done_cases, row_of_case):
        self.path = path
        self.scalars = scalars              #: DataFrame, index case, column per /results/scalars/<name>
        self.units = units                  #: unit of every scalar and array (name without "results/")
        self.descriptions = descriptions    #: description attribute, same keys
        self.array_names = arrays           #: every per-case array, e.g. "spectra/sun_planet/0/acceleration"
        self._lengths = lengths             # array name -> name of its valid-length dataset
        self.attrs = attrs                  #: root attributes (cases_done, complete, ...)
        self.campaign = campaign            #: /campaign attributes (design_type, factors, hashes, ...)
        self.base_config_toml = base_config_toml  #: the resolved base case
        self.done_cases = np.asarray(done_cases)  #: case indices whose status is "done"
        self._row_of_case = row_of_case     # case index -> row of the datasets

    def array(self, name, case):
        """Row `case` of /results/<name>, cut to the case's valid length
        (empty for a case without data)."""
        name = name[len("results/"):] if name.startswith("results/") else name
        if name not in self.array_names:
            raise KeyError(f"{self.path}: no per-case array {name!r}; have {self.array_names}")
        row = self._row_of_case[int(case)]
        with _hdf5.open_checked(self.path, FORMAT, NEWEST_FORMAT_VERSION) as f:
            values = f["results/" + name][row]
            length = int(f["results/" + self._lengths[name]][row])
        return np.asarray(values[:length])

    def arrays(self, name, cases=None):
        """{case: array(name, case)} for `cases` (default: every done case)."""
        if cases is None:
            cases = self.done_cases
        return {int(c): self.array(name, int(c)) for c in cases}

    def spectrum(self, channel, case):
        """Amplitude spectrum of `channel` in `case` over its frequency axis."""
        return self._over("spectra/" + channel, "spectra/frequency", "frequency", case)

    def time_history(self, channel, case):
        """Decimated time history of `channel` in `case` over its time axis."""
        return self._over("time_history/" + channel, "time_history/time", "time", case)

    def wear_profile(self, family, case, which="depth_final"):
        """Final wear depth of flank family `family` (sun, planet_<i>/sun_side,
        ...) over the element positions (distance from the pitch point)."""
        return self._over(f"wear/{family}/{which}", f"wear/{family}/distance_from_pitch_point",
                          "distance_from_pitch_point", case)

    def _over(self, name, axis, dim, case):
        values, coordinate = self.array(name, case), self.array(axis, case)
        return xr.DataArray(values, dims=(dim,), name=name,
                            coords={dim: (dim, coordinate, {"units": self.units[axis],
                                                            "description": self.descriptions[axis]})},
                            attrs={"units": self.units[name], "description": self.descriptions[name], "case": case})


def load_campaign(path):
    """(design, results) of the campaign archive `path`.

    design: DataFrame indexed by case: the factors, status, message,
    wall_time, rank, sample_role, sample_row (strings decoded); units in
    ``design.attrs["units"]``. results: CampaignResults; ``results.scalars``
    is indexed by case too, so ``design.join(results.scalars)`` is the whole
    table. Raises FormatError for a file that is not a campaign archive."""
    with _hdf5.open_checked(path, FORMAT, NEWEST_FORMAT_VERSION) as f:
        design = _design_table(f)
        found = _hdf5.datasets_below(f["results"])
        scalars = {n[len("scalars/"):]: ds for n, ds in found.items() if n.startswith("scalars/")}
        table = pd.DataFrame({n: ds[()] for n, ds in scalars.items()}, index=design.index)
        units = {n: _hdf5.unit(ds) for n, ds in scalars.items()}
        descriptions = {n: _hdf5.description(ds) for n, ds in scalars.items()}
        arrays, lengths = [], {}
        for n, ds in found.items():
            if ds.ndim != 2:
                continue
            group = n.rsplit("/", 1)[0]
            length = next((f"{group}/{k}" for k in _LENGTHS if f"{group}/{k}" in found), None)
            if length is None:  # time_history/<channel>/...: the lengths sit at the section's top
                top = n.split("/", 1)[0]
                length = next((f"{top}/{k}" for k in _LENGTHS if f"{top}/{k}" in found), None)
            if length is not None:
                arrays.append(n)
                lengths[n] = length
                units[n], descriptions[n] = _hdf5.unit(ds), _hdf5.description(ds)
        attrs = {k: _hdf5.text(v) if isinstance(v, (bytes, str)) else v.item() for k, v in f.attrs.items()}
        campaign = {k: _hdf5.text(v) if isinstance(v, (bytes, str)) else v.item() for k, v in f["campaign"].attrs.items()}
        base = f["campaign/base_config_toml"].asstr()[()] if "campaign/base_config_toml" in f else ""
    done = design.index[design["status"] == "done"]
    rows = {int(case): row for row, case in enumerate(design.index)}
    results = CampaignResults(str(path), table, units, descriptions, arrays, lengths, attrs, campaign, base, done,
                              rows)
    return design, results
