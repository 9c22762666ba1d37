#!/usr/bin/env python3
"""Draw the plots of a `planetwear diagnose` report.

Reads REPORT/report.json and REPORT/data/*.csv (written by the C++ side,
io/diagnosis_report.hpp) and writes one PNG per series into REPORT/:

    spectrum_<channel>.png      amplitude spectra of the held-out window:
                                recording, model before (as configured) and
                                after (nuisance + found physics), log scale
    tsa_<component>_<channel>.png   synchronous averages over the sun, a planet
                                or the carrier: recording, before, after

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
    for p in meta.get("plots", []):
        data = np.genfromtxt(os.path.join(report, p["csv"]), delimiter=",", comments="#", names=True)
        fig, ax = plt.subplots(figsize=(10, 4.2))
        spectrum = p["name"].startswith("spectrum/")
        if spectrum:
            for key, style, label in (("recording", "k-", "recording"), ("before", "C1-", "model before"),
                                      ("after", "C0--", "model after")):
                ax.semilogy(data["x"], np.maximum(data[key], 1e-300), style, lw=0.8, label=label)
            ax.set_xlabel(f"frequency [{p['x_unit']}]")
            ax.set_ylabel(f"amplitude [{p['y_unit']}]")
            top = max(np.max(data["recording"]), 1e-300)
            ax.set_ylim(top * 1e-5, top * 3)
        else:
            ax.plot(data["x"], data["recording"], "k-", lw=0.8, label="recording")
            ax.plot(data["x"], data["before"], "C1-", lw=0.8, label="model before")
            ax.plot(data["x"], data["after"], "C0--", lw=0.8, label="model after")
            ax.plot(data["x"], data["recording"] - data["after"], "C3-", lw=0.6, alpha=0.7, label="residual after")
            ax.set_xlabel(f"position [{p['x_unit']}] (absolute)")
            ax.set_ylabel(f"synchronous average [{p['y_unit']}]")
        ax.set_title(f"{p['name']} — {title}", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(report, p["png"]), dpi=110)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
