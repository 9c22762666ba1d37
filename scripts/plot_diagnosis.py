#!/usr/bin/env python3
"""Draw the plots of a `planetwear diagnose` report.

Reads REPORT/report.json and REPORT/data/*.csv (written by the C++ side,
io/diagnosis_report.hpp) and writes one PNG per plotted series into REPORT/:

    spectrum_<channel>.png   order spectrum of the held-out half (amplitude of
                             every DFT bin of its whole carrier revolutions vs
                             carrier order): recording, model before (nominal)
                             and after (nuisance + found physics), log scale
    residual_<channel>.png   whitened residual rho per feature (held-out half)
                             for the nominal, nuisance-fitted and final model
                             (and the lead, when it leads unnamed)
    tsa_<component>_<channel>.png   the recording's synchronous average over the
                             located component's period (no reference mark:
                             positions from the recording's start)

Series of kind "table" (data/features_*.csv: every feature's amplitudes) are
not plotted.

Usage:  scripts/plot_diagnosis.py REPORT_DIR
Runs with Debian's /usr/bin/python3 (python3-matplotlib, python3-numpy); it
re-executes itself there when the first python3 on PATH lacks them.
"""

import os
import sys


def ensure_scientific_python():
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError as exc:
        system_python = "/usr/bin/python3"
        if os.path.realpath(sys.executable) != os.path.realpath(system_python) and os.path.exists(system_python) \
                and not os.environ.get("PW_PLOT_REEXEC"):
            os.environ["PW_PLOT_REEXEC"] = "1"
            os.execv(system_python, [system_python] + sys.argv)
        sys.exit(f"plot_diagnosis: {exc}; install python3-matplotlib and python3-numpy")


ensure_scientific_python()

import json  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    report = sys.argv[1]
    with open(os.path.join(report, "report.json")) as f:
        meta = json.load(f)
    title = f"{os.path.basename(meta.get('recording', ''))}: {meta.get('verdict', '')}"
    styles = {"recording": ("k-", "recording"), "model_before": ("C1-", "model before (nominal)"),
              "model_after": ("C0--", "model after"), "nominal": ("C1.", "nominal"),
              "nuisance_fitted": ("C2.", "nuisance fitted"), "final": ("C0.", "final"),
              "lead_not_named": ("C3x", "the lead (not named)")}
    for p in meta.get("plots", []):
        if p.get("kind") == "table":
            continue
        data = np.genfromtxt(os.path.join(report, p["csv"]), delimiter=",", skip_header=1, names=True)
        if data.size == 0:
            continue
        fig, ax = plt.subplots(figsize=(10, 4.2))
        kind = p.get("kind", "")
        for col in p.get("columns", []):
            style, label = styles.get(col, ("-", col))
            y = np.atleast_1d(data[col])
            x = np.atleast_1d(data["x"])
            if kind == "spectrum":
                ax.semilogy(x, np.maximum(y, 1e-300), style, lw=0.7, label=label)
            elif kind == "residual":
                ax.plot(x, y, style, ms=2.5, label=label)
            else:
                ax.plot(x, y, style, lw=0.8, label=label)
        if kind == "spectrum":
            top = max(float(np.max(data["recording"])), 1e-300)
            ax.set_ylim(top * 1e-6, top * 3)
        if kind == "residual":
            ax.axhline(3, color="0.6", lw=0.6, ls=":")
            ax.axhline(-3, color="0.6", lw=0.6, ls=":")
        ax.set_xlabel(p.get("x_label", "x"))
        ax.set_ylabel(p.get("y_label", ""))
        ax.set_title(f"{p['name']} — {title}", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(report, p["png"]), dpi=110)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
