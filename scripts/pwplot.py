#!/usr/bin/env python3
"""Shared helpers for the planetwear plotting scripts.

Reads the HDF5 files written by ``planetwear simulate`` and ``planetwear
stiffness`` (layout: io/result_writer.hpp):

    /time_history/time                      [s]
    /time_history/<mesh>/<i>/<quantity>     mesh in sun_planet, planet_ring
    /spectra/<channel>/{frequency,amplitude}
    /curves/<mesh>/{single_pair,combined}/{x,y}
    /scalars/<name>                         0-d datasets
Every dataset carries a 'unit' attribute.

Usage from another script in this directory:

    import pwplot                     # re-execs under /usr/bin/python3 if needed
    with pwplot.open_result(path) as f:
        t = pwplot.read(f, "time_history/time")          # -> Data(values, unit)
        meshes = pwplot.list_meshes(f)                    # -> ["planet_ring/0", ...]

Run ``pwplot.py FILE`` to print a summary of a result file.
"""

import os
import sys


def ensure_scientific_python():
    """Re-exec under Debian's /usr/bin/python3 when numpy/h5py/matplotlib are
    missing from the running interpreter (the first python3 on PATH lacks them)."""
    try:
        import h5py  # noqa: F401
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError as exc:
        system_python = "/usr/bin/python3"
        if os.path.realpath(sys.executable) != os.path.realpath(system_python) and os.path.exists(system_python) \
                and not os.environ.get("PWPLOT_REEXEC"):
            os.environ["PWPLOT_REEXEC"] = "1"
            os.execv(system_python, [system_python] + sys.argv)
        sys.exit(f"error: {exc}; run with /usr/bin/python3 (Debian python3-numpy, python3-h5py, "
                 f"python3-matplotlib)")


ensure_scientific_python()

from dataclasses import dataclass  # noqa: E402

import h5py  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import numpy as np  # noqa: E402

MESH_TYPES = ("sun_planet", "planet_ring")
MESH_LABELS = {"sun_planet": "sun–planet", "planet_ring": "planet–ring"}


class PwPlotError(Exception):
    """A missing file, dataset or attribute; the message says which."""


@dataclass
class Data:
    values: np.ndarray
    unit: str

    def __iter__(self):  # allows `values, unit = read(...)`
        return iter((self.values, self.unit))


def open_result(path):
    """Opens a planetwear HDF5 file read-only, with a clear error if impossible."""
    if not os.path.exists(path):
        raise PwPlotError(f"{path}: no such file (write it with 'planetwear simulate -o FILE' or 'planetwear stiffness -o FILE')")
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        raise PwPlotError(f"{path}: not a readable HDF5 file ({exc})") from exc


def _decode(v):
    if isinstance(v, bytes):
        return v.decode("utf-8")
    if isinstance(v, np.ndarray) and v.shape == ():
        return _decode(v[()])
    return str(v)


def has(f, path):
    return path.strip("/") in f


def read(f, path, unit=None):
    """Dataset at `path` (e.g. 'time_history/sun_planet/0/deflection') with its
    'unit' attribute. If `unit` is given, the stored unit must equal it."""
    path = path.strip("/")
    if path not in f:
        parent = path.rsplit("/", 1)[0] if "/" in path else ""
        hint = ""
        if parent and parent in f and isinstance(f[parent], h5py.Group):
            hint = f"; {parent} holds: {', '.join(sorted(f[parent].keys()))}"
        raise PwPlotError(f"{f.filename}: dataset /{path} not found{hint}")
    obj = f[path]
    if not isinstance(obj, h5py.Dataset):
        raise PwPlotError(f"{f.filename}: /{path} is a group, not a dataset")
    u = _decode(obj.attrs.get("unit", ""))
    if unit is not None and u != unit:
        raise PwPlotError(f"{f.filename}: /{path} has unit '{u}', expected '{unit}'")
    return Data(np.asarray(obj[()], dtype=float), u)


def scalar(f, name, unit=None):
    """Value of /scalars/<name> (a float) and its unit."""
    d = read(f, "scalars/" + name, unit)
    return float(d.values), d.unit


def channel(f, name, unit=None):
    """Time history /time_history/<name>."""
    return read(f, "time_history/" + name, unit)


def time(f):
    return read(f, "time_history/time", "s").values


def list_meshes(f):
    """Mesh channel prefixes present in /time_history, e.g. ['sun_planet/0', ...],
    sorted by mesh type then planet index."""
    out = []
    th = f.get("time_history")
    if th is None:
        return out
    for mt in MESH_TYPES:
        if mt in th:
            for i in sorted(th[mt].keys(), key=lambda s: int(s) if s.isdigit() else 10**9):
                out.append(f"{mt}/{i}")
    return out


def list_curves(f):
    """Curve names under /curves, e.g. ['sun_planet/single_pair', ...]."""
    out = []
    if "curves" not in f:
        return out
    f["curves"].visititems(lambda name, obj: out.append(name) if isinstance(obj, h5py.Group) and "x" in obj else None)
    return sorted(out)


def curve(f, name):
    """(x Data, y Data, attrs dict) of /curves/<name>."""
    g = "curves/" + name
    x = read(f, g + "/x")
    y = read(f, g + "/y")
    attrs = {k: _decode(v) for k, v in f[g].attrs.items()}
    return x, y, attrs


def spectrum(f, name):
    """(frequency [Hz], amplitude Data, attrs) of /spectra/<name>."""
    g = "spectra/" + name
    fr = read(f, g + "/frequency", "Hz").values
    a = read(f, g + "/amplitude")
    attrs = {k: _decode(v) for k, v in f[g].attrs.items()}
    return fr, a, attrs


def config_value(f, dotted_key):
    """Value (as text) of a key in /config/toml, e.g. 'operating.input_speed_rpm';
    None if absent. Small parser for 'key = value' lines within [sections]."""
    if "config/toml" not in f:
        return None
    text = _decode(f["config/toml"][()])
    section, key = dotted_key.rsplit(".", 1)
    current = ""
    for line in text.splitlines():
        s = line.split("#", 1)[0].strip()
        if s.startswith("[") and s.endswith("]"):
            current = s.strip("[]").strip()
        elif "=" in s and current == section:
            k, v = (p.strip() for p in s.split("=", 1))
            if k == key:
                return v.strip('"')
    return None


def speed_rpm(f):
    """Nominal input speed [rpm] from /scalars/sun_speed (or the config)."""
    if has(f, "scalars/sun_speed"):
        return scalar(f, "sun_speed", "rad/s")[0] * 60.0 / (2.0 * np.pi)
    v = config_value(f, "operating.input_speed_rpm")
    if v is None:
        raise PwPlotError(f"{f.filename}: neither /scalars/sun_speed nor operating.input_speed_rpm found")
    return float(v)


# Engineering prefixes for axis labels: pick a scale so the numbers are O(1..1000).
_PREFIX = {-12: "p", -9: "n", -6: "µ", -3: "m", 0: "", 3: "k", 6: "M", 9: "G"}


def scaled(values, unit, peak=None):
    """(values * 10^-e, 'prefix+unit') with e a multiple of 3 chosen from `peak`
    (default max|values|; pass a common peak to give several panels one unit).
    Compound units ('N/m') are prefixed as a whole, e.g. 'µm', 'MN/m'."""
    v = np.asarray(values, dtype=float)
    if peak is None:
        finite = v[np.isfinite(v)]
        peak = float(np.max(np.abs(finite))) if finite.size else 0.0
    if peak == 0.0 or unit in ("", "1"):
        return v, unit
    e = int(np.floor(np.log10(peak) / 3.0)) * 3
    e = max(-12, min(9, e))
    if unit == "m/s^2":  # keep acceleration in m/s² (prefixed m/s² reads oddly)
        return v, "m/s²"
    return v / 10.0**e, _PREFIX[e] + unit.replace("^2", "²")


def save(fig, path, dpi=130):
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    print(f"wrote {path}")


def main():
    import argparse
    p = argparse.ArgumentParser(description="Summarize a planetwear HDF5 result: meshes, channels with units, "
                                            "curves, spectra and scalars.")
    p.add_argument("file", help="HDF5 file written by 'planetwear simulate' or 'planetwear stiffness'")
    a = p.parse_args()
    try:
        with open_result(a.file) as f:
            print(f"{a.file}: format {_decode(f.attrs.get('format', '?'))} "
                  f"v{_decode(f.attrs.get('format_version', '?'))}")
            meshes = list_meshes(f)
            print("meshes:", ", ".join(meshes) if meshes else "(none)")
            if "time_history" in f:
                t = time(f)
                print(f"time: {t.size} samples, {t[0]:.6g} … {t[-1]:.6g} s")

                def show(name, obj):
                    if isinstance(obj, h5py.Dataset) and name != "time":
                        print(f"  time_history/{name} [{_decode(obj.attrs.get('unit', ''))}]")
                f["time_history"].visititems(show)
            for c in list_curves(f):
                print(f"  curves/{c}")
            if "spectra" in f:
                f["spectra"].visititems(lambda n, o: print(f"  spectra/{n}") if isinstance(o, h5py.Group)
                                        and "frequency" in o else None)
            if "scalars" in f:
                f["scalars"].visititems(lambda n, o: print(f"  scalars/{n} = {float(o[()]):.6g} "
                                                           f"{_decode(o.attrs.get('unit', ''))}")
                                        if isinstance(o, h5py.Dataset) else None)
    except PwPlotError as exc:
        sys.exit(f"error: {exc}")


if __name__ == "__main__":
    main()
