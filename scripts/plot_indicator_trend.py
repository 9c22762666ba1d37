#!/usr/bin/python3
"""Trend of the gear condition indicators over the wear snapshots of a run.

Input: the CSV of ``planetwear indicators --simulation worn.h5 -o trend.csv``
(docs/indicators.md): one row per snapshot (``mesh_cycles [1]``), channel and
gear average, one column per indicator. Draws one panel per indicator against
mesh cycles, one line per (channel, gear) average, into a PNG.

    /usr/bin/python3 scripts/plot_indicator_trend.py trend.csv -o trend.png
    /usr/bin/python3 scripts/plot_indicator_trend.py trend.csv --channel housing/acceleration --relative -o h.png

--relative divides every line by its value at the first snapshot (the unworn
stage), so that the panels show growth factors. Undefined values (``nan``:
e.g. FM4 of a difference signal at round-off level) are left out of the lines;
a panel whose positive values span more than a factor 100 gets a log axis.
Exit status 1 with a message for a file that is not such a table.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

INDICATORS = ["rms", "peak_to_peak", "kurtosis", "crest_factor", "fm0", "fm4", "m6a", "m8a", "na4", "nb4",
              "energy_ratio", "sideband_level_factor"]
TITLES = {"rms": "RMS of the TSA", "peak_to_peak": "peak to peak", "kurtosis": "kurtosis", "crest_factor":
          "crest factor", "fm0": "FM0", "fm4": "FM4", "m6a": "M6A", "m8a": "M8A", "na4": "NA4", "nb4": "NB4",
          "energy_ratio": "energy ratio", "sideband_level_factor": "sideband level factor"}


def load(path):
    t = pd.read_csv(path, dtype={"planet": "Int64"})
    if "mesh_cycles [1]" not in t.columns:
        raise ValueError(f"{path}: no 'mesh_cycles [1]' column: write it with "
                         "'planetwear indicators --simulation RUN.h5 -o trend.csv'")
    cols = {}
    for k in INDICATORS:
        hit = [c for c in t.columns if c.startswith(k + " [")]
        if not hit:
            raise ValueError(f"{path}: no column for indicator '{k}'")
        cols[k] = hit[0]
    return t, cols


def label(row):
    gear = row["gear"] if pd.isna(row["planet"]) else f"{row['gear']} {row['planet']}"
    return f"{row['channel']}: {gear}"


def plot(t, cols, relative, out):
    fig, axes = plt.subplots(4, 3, figsize=(13, 12), sharex=True)
    groups = list(t.groupby(["channel", "gear", "planet"], dropna=False, sort=False))
    colors = plt.cm.tab10(np.linspace(0, 1, max(len(groups), 1)))
    for ax, k in zip(axes.flat, INDICATORS):
        for (key, g), c in zip(groups, colors):
            g = g.sort_values("mesh_cycles [1]")
            y = g[cols[k]].to_numpy(dtype=float)
            x = g["mesh_cycles [1]"].to_numpy(dtype=float)
            if relative:
                y = y / y[0] if np.isfinite(y[0]) and y[0] != 0 else np.full_like(y, np.nan)
            ok = np.isfinite(y)
            if ok.any():
                ax.plot(x[ok], y[ok], "o-", color=c, ms=3, lw=1, label=label(g.iloc[0]))
        # Lines decades apart (e.g. a noise-free simulation's FM4 beside a housing channel's): log axis.
        ys = np.concatenate([ln.get_ydata() for ln in ax.get_lines()]) if ax.get_lines() else np.array([])
        if ys.size and np.all(ys > 0) and ys.max() / ys.min() > 100:
            ax.set_yscale("log")
        unit = "" if relative else (" [" + t["unit"].iloc[0] + "]" if k in ("rms", "peak_to_peak") else " [-]")
        ax.set_title(TITLES[k] + (" / unworn" if relative else unit), fontsize=10)
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("mesh cycles")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8)
    fig.suptitle("gear condition indicators over the wear snapshots (docs/indicators.md)")
    fig.tight_layout(rect=(0, 0.08, 1, 0.97))
    fig.savefig(out, dpi=120)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("trend", help="CSV of planetwear indicators --simulation ... -o trend.csv")
    p.add_argument("-o", "--output", required=True, help="PNG to write")
    p.add_argument("--channel", action="append", help="only this channel (repeatable)")
    p.add_argument("--relative", action="store_true", help="divide each line by its first snapshot")
    a = p.parse_args(argv)
    try:
        t, cols = load(a.trend)
    except (OSError, ValueError, pd.errors.ParserError) as e:
        print(f"plot_indicator_trend.py: {e}", file=sys.stderr)
        return 1
    if a.channel:
        t = t[t["channel"].isin(a.channel)]
        if t.empty:
            print(f"plot_indicator_trend.py: no rows of channel(s) {a.channel}", file=sys.stderr)
            return 1
    plot(t, cols, a.relative, a.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
