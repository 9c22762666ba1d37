#!/usr/bin/env python3
"""Loader for planetwear campaign archives (``planetwear sweep -o results.h5``).

The archive layout is docs/archive-format.md; this module follows it and
nothing else. Usage (docs/postprocessing.md)::

    import sys; sys.path.insert(0, "scripts")
    import pwcampaign
    c = pwcampaign.load("results.h5")
    c.design                      # DataFrame: one row per case (index = case),
                                  # factors, status, ..., then every scalar result
    c.units["efficiency"]         # '1'
    c.factors                     # DataFrame: key -> unit, scale, min, max
    c.done                        # boolean Series, True where status == "done"
    f, a = c.spectrum("sun_planet/0/acceleration", 3)   # valid bins only
    x, h = c.wear_profile("sun", 3)                      # final wear vs distance from pitch point
    a = c.array("time_history/sun_planet/0/deflection", 3)
    s = c.saltelli()              # A, B, AB_i matrices of every output, by sample_row
    c.sobol("sun_planet/0/acceleration_rms")             # S1, ST with bootstrap CIs

Run ``pwcampaign.py results.h5`` to print a summary of an archive.
"""

import os
import sys

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def _ensure_scientific_python():
    """Re-exec under Debian's /usr/bin/python3 when numpy/h5py/pandas are missing
    (the first python3 on PATH on these machines lacks them). Only done when this
    file is run as a script; an importing program must already run under a
    Python that has them."""
    try:
        import h5py  # noqa: F401
        import numpy  # noqa: F401
        import pandas  # noqa: F401
    except ImportError as exc:
        system_python = "/usr/bin/python3"
        if __name__ == "__main__" and os.path.exists(system_python) and not os.environ.get("PWPLOT_REEXEC") \
                and os.path.realpath(sys.executable) != os.path.realpath(system_python):
            os.environ["PWPLOT_REEXEC"] = "1"
            os.execv(system_python, [system_python] + sys.argv)
        raise ImportError(f"{exc}; run with /usr/bin/python3 (Debian python3-numpy, python3-h5py, "
                          f"python3-pandas)") from exc


_ensure_scientific_python()

from dataclasses import dataclass, field  # noqa: E402

import h5py  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

import sobol_indices  # noqa: E402

FORMAT = "planetwear.campaign"
FORMAT_VERSION = 1
# Int datasets that give each case's valid length of the padded arrays beside
# them (docs/archive-format.md, "NaN = no result").
LENGTH_DATASETS = ("bins", "elements", "samples")
DESIGN_FIXED = ("case", "status", "message", "wall_time", "rank", "sample_role", "sample_row")


class CampaignError(Exception):
    """A missing file, group or dataset, or a file that is not a campaign archive."""


def _text(v):
    if isinstance(v, bytes):
        return v.decode("utf-8")
    if isinstance(v, np.ndarray) and v.shape == ():
        return _text(v[()])
    if isinstance(v, np.generic):
        return v.item()
    return v


def _column(ds):
    """A 1-D dataset as a numpy array, variable-length strings decoded."""
    if ds.dtype.kind in ("O", "S", "U") or h5py.check_string_dtype(ds.dtype) is not None:
        return np.asarray(ds.asstr()[()], dtype=object)
    return ds[()]


def design_table(path):
    """The /design group as a DataFrame, in the order of its ``columns`` attribute
    (the one-line read of docs/archive-format.md, columns ordered)."""
    with h5py.File(path, "r") as f:
        g = f["design"]
        order = str(_text(g.attrs.get("columns", ""))).split(",")
        names = [c for c in order if c in g] + sorted(k for k in g if k not in order)
        return pd.DataFrame({k: _column(g[k]) for k in names})


@dataclass
class SaltelliSamples:
    """Outputs of a saltelli design arranged as the sample matrices.

    ``A``, ``B``: DataFrames indexed by sample_row j (0..N-1), one column per
    output; ``AB[i]``: the same for matrix AB_i (A with factor i's column from
    B). ``XA``, ``XB``: the factor values of A and B (index sample_row, one
    column per factor). ``complete``: boolean Series over rows, True where every
    role of the row is done (a failed or pending case makes its whole row
    unusable for the estimators)."""
    factors: list
    A: pd.DataFrame
    B: pd.DataFrame
    AB: list
    XA: pd.DataFrame
    XB: pd.DataFrame
    complete: pd.Series

    def matrices(self, output, rows="complete"):
        """(fA [N], fB [N], fAB [N, d]) of one output as numpy arrays, only the
        complete rows (rows="complete", default) or all rows (rows="all")."""
        sel = self.complete.to_numpy() if rows == "complete" else np.ones(len(self.A), dtype=bool)
        fA = self.A[output].to_numpy(dtype=float)[sel]
        fB = self.B[output].to_numpy(dtype=float)[sel]
        fAB = np.column_stack([m[output].to_numpy(dtype=float)[sel] for m in self.AB])
        return fA, fB, fAB


@dataclass
class Campaign:
    """A campaign archive, opened by :func:`load`. All tables are read into
    memory; per-case arrays are read from the file on request (the file is
    opened for each call, so the object holds no HDF5 handle)."""
    path: str
    attrs: dict
    campaign: dict
    design: pd.DataFrame
    units: dict
    descriptions: dict
    factors: pd.DataFrame
    scalar_names: list
    texts: dict = field(default_factory=dict)

    # ---- tables -------------------------------------------------------------
    @property
    def factor_names(self):
        return list(self.factors.index)

    @property
    def status(self):
        return self.design["status"]

    @property
    def done(self):
        """Boolean Series over cases: status == "done"."""
        return self.design["status"] == "done"

    @property
    def failed(self):
        return self.design["status"] == "failed"

    @property
    def pending(self):
        return self.design["status"] == "pending"

    @property
    def cases(self):
        return len(self.design)

    @property
    def design_type(self):
        return self.campaign.get("design_type", "")

    def results(self, only_done=True):
        """The design table restricted to done cases (only_done) or all cases."""
        return self.design[self.done] if only_done else self.design

    def label(self, column, unit=True):
        """'column [unit]' for axis labels."""
        u = self.units.get(column, "")
        return f"{column} [{u}]" if unit and u not in ("",) else column

    # ---- per-case arrays ----------------------------------------------------
    def _open(self):
        return h5py.File(self.path, "r")

    @staticmethod
    def _results_path(name):
        name = name.strip("/")
        return name if name.startswith("results/") else "results/" + name

    def array_names(self):
        """Every per-case array (2-D dataset under /results), without the
        'results/' prefix, e.g. 'spectra/sun_planet/0/acceleration'."""
        out = []
        with self._open() as f:
            if "results" in f:
                f["results"].visititems(lambda n, o: out.append(n) if isinstance(o, h5py.Dataset)
                                        and o.ndim == 2 else None)
        return sorted(out)

    def _length_dataset(self, f, path):
        """The int dataset giving the valid length of the 2-D dataset at `path`:
        the nearest bins/elements/samples in its group or a parent group below
        /results."""
        parts = path.split("/")[:-1]
        while len(parts) > 1:
            g = "/".join(parts)
            for n in LENGTH_DATASETS:
                p = g + "/" + n
                if p in f and isinstance(f[p], h5py.Dataset) and f[p].ndim == 1:
                    return p
            parts.pop()
        raise CampaignError(f"{self.path}: no {'/'.join(LENGTH_DATASETS)} dataset beside /{path}")

    def _case_index(self, case):
        i = int(case)
        if not 0 <= i < self.cases:
            raise CampaignError(f"{self.path}: case {case} out of range 0..{self.cases - 1}")
        return i

    def valid_length(self, name, case):
        """Valid length of per-case array `name` in `case` (0 = no data)."""
        path = self._results_path(name)
        i = self._case_index(case)
        with self._open() as f:
            return int(f[self._length_dataset(f, path)][i])

    def array(self, name, case):
        """Row `case` of the per-case array /results/<name>, cut to its valid
        length (empty for a case without data). 1-D datasets give the number."""
        path = self._results_path(name)
        i = self._case_index(case)
        with self._open() as f:
            if path not in f or not isinstance(f[path], h5py.Dataset):
                parent = path.rsplit("/", 1)[0]
                hint = ""
                if parent in f and isinstance(f[parent], h5py.Group):
                    hint = f"; /{parent} holds: {', '.join(sorted(f[parent].keys()))}"
                raise CampaignError(f"{self.path}: dataset /{path} not found{hint}")
            ds = f[path]
            if ds.ndim == 1:
                return ds[i]
            n = int(f[self._length_dataset(f, path)][i])
            return np.asarray(ds[i, :n], dtype=float)

    def arrays(self, name, cases=None):
        """{case: array(name, case)} for the given cases (default: every done case)."""
        if cases is None:
            cases = self.design.index[self.done]
        return {int(i): self.array(name, i) for i in cases}

    def frequency(self, case):
        """Frequency axis [Hz] of the case's spectra (valid bins only)."""
        return self.array("spectra/frequency", case)

    def spectrum(self, channel, case):
        """(frequency [Hz], amplitude) of /results/spectra/<channel>, e.g.
        channel 'sun_planet/0/acceleration'."""
        return self.frequency(case), self.array("spectra/" + channel, case)

    def spectrum_channels(self):
        return [n[len("spectra/"):] for n in self.array_names()
                if n.startswith("spectra/") and n != "spectra/frequency"]

    def wear_families(self):
        """Flank families with wear data, e.g. ['sun', 'planet_0/sun_side', ...]."""
        return [n[len("wear/"):-len("/depth_final")] for n in self.array_names()
                if n.startswith("wear/") and n.endswith("/depth_final")]

    def wear_profile(self, family, case, which="depth_final"):
        """(distance from the pitch point [m], final wear depth [m]) of a flank
        family; which = 'depth_final' (mean over teeth) or 'depth_final_max'."""
        return (self.array(f"wear/{family}/distance_from_pitch_point", case),
                self.array(f"wear/{family}/{which}", case))

    def time_history(self, channel, case):
        """(time [s], values) of /results/time_history/<channel> (decimated)."""
        return self.array("time_history/time", case), self.array("time_history/" + channel, case)

    def unit(self, name):
        """Unit of any dataset: a design column, a scalar or an array name."""
        if name in self.units:
            return self.units[name]
        with self._open() as f:
            for p in (self._results_path(name), "design/" + name):
                if p in f:
                    return str(_text(f[p].attrs.get("unit", "")))
        raise CampaignError(f"{self.path}: no dataset named {name}")

    # ---- configuration of a case -------------------------------------------
    def overrides(self, case):
        """The case's factor values as `planetwear simulate --set` assignments."""
        i = self._case_index(case)
        out = []
        for k in self.factor_names:
            v = float(self.design.at[i, k])
            out.append(f"{k}={int(v)}" if v.is_integer() and abs(v) < 2**53 else f"{k}={v!r}")
        return out

    # ---- Saltelli / Sobol' --------------------------------------------------
    def saltelli(self, outputs=None):
        """Sample matrices of a saltelli design (see SaltelliSamples). `outputs`:
        column names of `design` (default: every scalar result)."""
        if self.design_type != "saltelli":
            raise CampaignError(f"{self.path}: design type is {self.design_type!r}, not 'saltelli'")
        if outputs is None:
            outputs = list(self.scalar_names)
        elif isinstance(outputs, str):
            outputs = [outputs]
        for o in outputs:
            if o not in self.design:
                raise CampaignError(f"{self.path}: no column {o!r} (scalars: {', '.join(self.scalar_names)})")
        d = len(self.factor_names)
        t = self.design
        role, row = t["sample_role"].astype(str), t["sample_row"].astype(int)
        n_rows = int(row.max()) + 1 if len(row) else 0
        roles = ["A", "B"] + [f"AB_{i}" for i in range(d)]
        mats = {}
        ok = pd.Series(True, index=pd.RangeIndex(n_rows, name="sample_row"))
        for r in roles:
            sel = t[role == r]
            if len(sel) != n_rows or sorted(sel["sample_row"].astype(int)) != list(range(n_rows)):
                raise CampaignError(f"{self.path}: role {r} has {len(sel)} cases, expected one per sample_row "
                                    f"0..{n_rows - 1}")
            sel = sel.set_index(sel["sample_row"].astype(int).rename("sample_row")).sort_index()
            mats[r] = sel
            ok &= sel["status"] == "done"
        return SaltelliSamples(
            factors=self.factor_names,
            A=mats["A"][outputs], B=mats["B"][outputs], AB=[mats[f"AB_{i}"][outputs] for i in range(d)],
            XA=mats["A"][self.factor_names], XB=mats["B"][self.factor_names], complete=ok)

    def sobol(self, output, n_bootstrap=1000, confidence=0.95, seed=0):
        """First-order and total Sobol' indices of one output with bootstrap
        confidence intervals (sobol_indices.sobol_indices); rows with a failed or
        pending case are dropped. DataFrame indexed by factor."""
        s = self.saltelli([output])
        fA, fB, fAB = s.matrices(output)
        r = sobol_indices.sobol_indices(fA, fB, fAB, n_bootstrap=n_bootstrap, confidence=confidence, seed=seed)
        r.index = pd.Index(self.factor_names, name="factor")
        r.attrs.update(output=output, rows_used=int(s.complete.sum()), rows=len(s.complete))
        return r


def load(path):
    """Opens a campaign archive and reads its tables (docs/archive-format.md).
    Raises CampaignError if the file is missing or not a campaign archive."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise CampaignError(f"{path}: no such file (write it with 'planetwear sweep CAMPAIGN.toml -o {path}')")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise CampaignError(f"{path}: not a readable HDF5 file ({exc})") from exc
    with f:
        fmt = _text(f.attrs.get("format", ""))
        if fmt != FORMAT:
            raise CampaignError(f"{path}: format attribute is {fmt!r}, not {FORMAT!r} "
                                f"(a 'planetwear simulate' output? use scripts/pwplot.py)")
        version = int(_text(f.attrs.get("format_version", 0)))
        if version > FORMAT_VERSION:
            raise CampaignError(f"{path}: format_version {version} is newer than this loader ({FORMAT_VERSION})")
        if "design" not in f:
            raise CampaignError(f"{path}: no /design group")
        attrs = {k: _text(v) for k, v in f.attrs.items()}
        campaign = {k: _text(v) for k, v in f["campaign"].attrs.items()} if "campaign" in f else {}
        texts = {}
        for k in ("toml", "base_config_toml", "list_csv"):
            if f"campaign/{k}" in f:
                texts[k] = _text(f[f"campaign/{k}"][()])
        g = f["design"]
        order = str(_text(g.attrs.get("columns", ""))).split(",")
        names = [c for c in order if c in g] + sorted(k for k in g if k not in order)
        columns, units, descriptions = {}, {}, {}
        for k in names:
            columns[k] = _column(g[k])
            if "unit" in g[k].attrs:
                units[k] = str(_text(g[k].attrs["unit"]))
            descriptions[k] = str(_text(g[k].attrs.get("description", "")))
        n = len(columns["case"]) if "case" in columns else len(next(iter(columns.values())))
        scalars = {}
        if "results/scalars" in f:
            def collect(name, obj):
                if isinstance(obj, h5py.Dataset) and obj.ndim == 1:
                    col = name if name not in columns else "results/scalars/" + name
                    scalars[col] = obj[()]
                    units[col] = str(_text(obj.attrs.get("unit", "")))
                    descriptions[col] = str(_text(obj.attrs.get("description", "")))
            f["results/scalars"].visititems(collect)
        for k, v in list(columns.items()) + list(scalars.items()):
            if len(v) != n:
                raise CampaignError(f"{path}: {k} has {len(v)} rows, /design/case has {n}")
        table = pd.DataFrame({**columns, **{k: scalars[k] for k in sorted(scalars)}})
        if "case" in table and not np.array_equal(table["case"].to_numpy(), np.arange(n)):
            raise CampaignError(f"{path}: /design/case is not 0..{n - 1} (case index = row)")
        table.index = pd.RangeIndex(n, name=None)
        keys = [k for k in str(campaign.get("factors", "")).split(",") if k]
        if not keys:
            keys = [k for k in names if k not in DESIGN_FIXED]
        rows = []
        for k in keys:
            a = g[k].attrs if k in g else {}
            rows.append({"key": k, "unit": str(_text(a.get("unit", ""))), "scale": str(_text(a.get("scale", "linear"))),
                         "min": float(_text(a["min"])) if "min" in a else np.nan,
                         "max": float(_text(a["max"])) if "max" in a else np.nan})
        factors = pd.DataFrame(rows, columns=["key", "unit", "scale", "min", "max"]).set_index("key")
    return Campaign(path=path, attrs=attrs, campaign=campaign, design=table, units=units,
                    descriptions=descriptions, factors=factors, scalar_names=sorted(scalars), texts=texts)


def summary(c):
    """A few lines describing an opened campaign."""
    lines = [f"{c.path}: campaign {c.campaign.get('name', '')!r}, {c.design_type} design, {c.cases} cases: "
             f"{int(c.done.sum())} done, {int(c.failed.sum())} failed, {int(c.pending.sum())} pending"]
    for k, r in c.factors.iterrows():
        v = c.design[k]
        lines.append(f"  factor {k} [{r['unit']}] {r['scale']}: {v.min():.6g} .. {v.max():.6g}")
    lines.append(f"  {len(c.scalar_names)} scalars, e.g. " + ", ".join(c.scalar_names[:6]))
    arrays = c.array_names()
    lines.append(f"  {len(arrays)} per-case arrays: spectra {c.spectrum_channels()}, "
                 f"wear families {c.wear_families()}")
    for i in c.design.index[c.failed]:
        lines.append(f"  case {i} failed: {c.design.at[i, 'message']}")
    return "\n".join(lines)


def main(argv=None):
    import argparse
    p = argparse.ArgumentParser(description="Summarize a planetwear campaign archive (docs/archive-format.md); "
                                            "--csv writes the design table with the scalar results.")
    p.add_argument("archive", help="HDF5 archive written by 'planetwear sweep'")
    p.add_argument("--csv", metavar="FILE", help="write the design table + scalars as CSV ('-' = stdout)")
    a = p.parse_args(argv)
    try:
        c = load(a.archive)
    except CampaignError as exc:
        sys.exit(f"error: {exc}")
    if a.csv:
        c.design.to_csv(sys.stdout if a.csv == "-" else a.csv, index=False)
        if a.csv != "-":
            print(f"wrote {a.csv}")
    else:
        print(summary(c))


if __name__ == "__main__":
    main()
