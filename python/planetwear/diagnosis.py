"""``planetwear diagnose -o FOLDER`` output (docs/diagnose.md, section 6).

    report = load_diagnosis("report/")
    report["verdict"], report["missing_physics"]     # as in report.json
    report["data"]["spectrum/sun_planet_0_acc"]           # pandas DataFrame of data/<stem>.csv, index x

The folder holds report.json (every number of the diagnosis), report.md and
report.html (the same for people) and data/*.csv (the plotted series; the
plot index report.json["plots"] names each file).
"""
import json
import os

import pandas as pd

REPORT = "report.json"


def read_series(path):
    """A data/*.csv series: a '# name; x: ...; values: ...' comment line,
    then a header 'x,<column>,...'. Returns a DataFrame indexed by x, the
    comment in ``.attrs["comment"]``."""
    with open(path, encoding="utf-8") as fh:
        first = fh.readline()
    comment = first[1:].strip() if first.startswith("#") else ""
    # round_trip: pandas' default parser may land one ulp off the written decimal (1 % of a
    # report's values were, against numpy's correctly rounded parse); the series are the
    # report's numbers, so they are read back exactly.
    table = pd.read_csv(path, comment=None, skiprows=1 if comment else 0, index_col="x",
                        float_precision="round_trip")
    table.attrs["comment"] = comment
    return table


def load_diagnosis(folder, data=True):
    """report.json of a diagnosis folder as a dict; with data=True the
    plotted series as ``report["data"][name]`` (DataFrames, name as in
    report.json["plots"]). ``report["folder"]`` is the folder's path."""
    path = os.path.join(folder, REPORT)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{folder}: no {REPORT}: not a planetwear diagnose output folder")
    with open(path, encoding="utf-8") as fh:
        report = json.load(fh)
    report["folder"] = os.path.abspath(folder)
    if data:
        report["data"] = {p["name"]: read_series(os.path.join(folder, p["csv"]))
                          for p in report.get("plots", []) if os.path.isfile(os.path.join(folder, p["csv"]))}
    return report
