"""Checks a simulate output: every dataset has a unit, the resolved config is
stored and matches the run, spectra/curves exist, CSV agrees with HDF5."""
import sys

import h5py
import numpy as np
import pandas as pd

h5, csv = sys.argv[1], sys.argv[2]
problems = []
with h5py.File(h5, "r") as f:
    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and name != "config/toml" and "unit" not in obj.attrs \
                and not name.startswith("curves/") and not name.startswith("spectra/"):
            problems.append(f"{name}: no unit attribute")
    f.visititems(visit)
    toml = f["config/toml"][()]
    toml = toml.decode() if isinstance(toml, bytes) else str(toml)
    if "input_speed_rpm = 400" not in toml.replace("400.0", "400"):
        problems.append("resolved config does not record the 400 rpm override")
    for p in ["time_history/time", "time_history/sun_planet/0/deflection", "spectra/sun_planet/0/acceleration/amplitude",
              "curves/sun_planet/single_pair/y", "scalars/mesh_frequency"]:
        if p not in f:
            problems.append(f"missing {p}")
    t = f["time_history/time"][:]
    d = f["time_history/sun_planet/0/deflection"][:]
    if f["time_history/sun_planet/0/deflection"].attrs["unit"] not in ("m", b"m"):
        problems.append("deflection unit is not m")
    fm = float(np.asarray(f["scalars/mesh_frequency"]).ravel()[0])
    if abs(fm - 21 * 400 / 60 * (1 - 21 / 102)) > 1e-9 * fm:
        problems.append(f"mesh frequency {fm} Hz is wrong")
df = pd.read_csv(csv)
if len(df) != len(t) or abs(df.iloc[:, 0].values - t).max() > 1e-12:
    problems.append("CSV time column differs from HDF5")
col = [c for c in df.columns if c.startswith("sun_planet/0/deflection")]
if not col or abs(df[col[0]].values - d).max() > 1e-15:
    problems.append("CSV deflection differs from HDF5")
if problems:
    print("\n".join(problems))
    sys.exit(1)
print("output file checks passed")
