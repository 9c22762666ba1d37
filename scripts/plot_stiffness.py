#!/usr/bin/env python3
"""Mesh stiffness of both mesh types, in the style of seed Fig. 8 (Bai & Ning 2023).

Reads /curves/<mesh>/{single_pair,combined} from a file written by
``planetwear stiffness -o st.h5`` (or ``planetwear simulate``) and draws, for
sun–planet and planet–ring:

  left : stiffness vs time in mesh periods T_z: the single-pair curves of
         successive tooth pairs (each entering one mesh period after the
         previous one) and the combined stiffness (their sum);
  right: single-pair stiffness vs signed distance of the contact point from
         the pitch point along the line of action.

Time from distance: the contact point moves one base pitch p_b along the line
of action per mesh period, and p_b = (length of the path of contact) /
contact ratio, both taken from the file.

    /usr/bin/python3 scripts/plot_stiffness.py st.h5 -o docs/figures/fig8_mesh_stiffness.png
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pwplot  # noqa: E402  (re-execs under /usr/bin/python3 if needed)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# Seed Table 2, for the annotation only (the seed's stiffness is ~100x below
# ISO 6336-1 for these gears, REFERENCE.md).
SEED_TABLE2 = {"sun_planet": (6.372e6, 7.776e6), "planet_ring": (6.372e6, 7.033e6)}


def mesh_curves(f, mesh):
    xs, ys, _ = pwplot.curve(f, mesh + "/single_pair")
    xc, yc, _ = pwplot.curve(f, mesh + "/combined")
    if xs.unit != "m" or xc.unit != "1" or ys.unit != "N/m" or yc.unit != "N/m":
        raise pwplot.PwPlotError(f"{f.filename}: unexpected units in /curves/{mesh} "
                                 f"(x: {xs.unit}, {xc.unit}; y: {ys.unit}, {yc.unit})")
    eps = pwplot.scalar(f, mesh + "/contact_ratio")[0]
    p_b = (xs.values[-1] - xs.values[0]) / eps  # base pitch [m]
    return xs.values, ys.values, xc.values, yc.values, eps, p_b


def plot(path_in, path_out, periods, dpi):
    with pwplot.open_result(path_in) as f:
        present = [m for m in pwplot.MESH_TYPES if pwplot.has(f, f"curves/{m}/single_pair")]
        if not present:
            raise pwplot.PwPlotError(f"{path_in}: no /curves/<mesh>/single_pair; write the file with "
                                     f"'planetwear stiffness -o FILE'")
        data = {m: mesh_curves(f, m) for m in present}

    fig, axes = plt.subplots(len(present), 2, figsize=(12, 4.2 * len(present)), squeeze=False,
                             gridspec_kw={"width_ratios": [1.6, 1]})
    letters = "ab"
    for row, mesh in enumerate(present):
        x, k1, tc, kc, eps, p_b = data[mesh]
        label = pwplot.MESH_LABELS[mesh]
        ax = axes[row][0]
        # Single pairs: pair j enters at t = j mesh periods and stays eps periods.
        t1 = (x - x[0]) / p_b
        first = True
        for j in range(-int(np.ceil(eps)), periods + 1):
            tj = t1 + j
            keep = (tj >= 0) & (tj <= periods)
            if keep.any():
                ax.plot(tj[keep], k1[keep] / 1e9, color="tab:blue", lw=1.0, alpha=0.8,
                        label="single tooth pair" if first else None)
                first = False
        # Combined: one period tiled.
        tt = np.concatenate([tc[:-1] + j for j in range(periods)] + [tc[-1:] + periods - 1])
        kk = np.concatenate([kc[:-1]] * periods + [kc[-1:]])
        ax.plot(tt, kk / 1e9, color="tab:red", lw=1.8, label="combined (all pairs in mesh)")
        ax.set_xlim(0, periods)
        ax.set_ylim(0, 1.1 * kc.max() / 1e9)
        ax.set_xlabel("time t / T_z [mesh periods]  (t = 0: a new pair enters)")
        ax.set_ylabel("mesh stiffness [GN/m]")
        ax.set_title(f"({letters[row]}) {label} mesh stiffness vs time")
        ax.grid(alpha=0.3)
        ax.legend(loc="lower right", fontsize=8)
        ax.text(0.01, 0.03,
                f"contact ratio ε = {eps:.3f}\n"
                f"max single pair {k1.max():.3g} N/m, combined {kc.min():.3g}…{kc.max():.3g} N/m\n"
                f"seed Table 2: max single {SEED_TABLE2[mesh][0]:.4g}, max combined {SEED_TABLE2[mesh][1]:.4g} N/m",
                transform=ax.transAxes, fontsize=7.5, va="bottom",
                bbox=dict(boxstyle="round", fc="white", ec="0.7", alpha=0.9))

        ax = axes[row][1]
        ax.plot(x * 1e3, k1 / 1e9, color="tab:blue", lw=1.5)
        ax.axvline(0, color="0.4", ls="--", lw=0.8)
        ax.text(0.0, 0.02, " pitch point", fontsize=8, color="0.3", transform=ax.get_xaxis_transform())
        ax.set_xlabel("contact position: distance from the pitch point\n"
                      "along the line of action [mm] (+ towards driving gear's tip)")
        ax.set_ylabel("single-pair stiffness [GN/m]")
        ax.set_title(f"{label}: single tooth pair vs contact position")
        ax.set_ylim(0, 1.1 * k1.max() / 1e9)
        ax.grid(alpha=0.3)

    fig.suptitle("Mesh stiffness (cf. seed Fig. 8, Bai & Ning 2023) — potential energy method, "
                 f"{os.path.basename(path_in)}", fontsize=11)
    fig.tight_layout()
    pwplot.save(fig, path_out, dpi)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] + " Single-pair and combined stiffness "
                                "of both meshes vs time in mesh periods and vs distance from the pitch point.",
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="Example:\n  planetwear stiffness -o /tmp/st.h5\n"
                                       "  /usr/bin/python3 scripts/plot_stiffness.py /tmp/st.h5 "
                                       "-o docs/figures/fig8_mesh_stiffness.png")
    p.add_argument("file", help="HDF5 file from 'planetwear stiffness -o' or 'planetwear simulate -o'")
    p.add_argument("-o", "--output", default="docs/figures/fig8_mesh_stiffness.png", help="PNG to write "
                   "(default: %(default)s)")
    p.add_argument("--periods", type=int, default=3, help="mesh periods on the time axis (default: %(default)s)")
    p.add_argument("--dpi", type=int, default=130, help="resolution (default: %(default)s)")
    a = p.parse_args()
    if a.periods < 1:
        p.error("--periods must be >= 1")
    try:
        plot(a.file, a.output, a.periods, a.dpi)
    except pwplot.PwPlotError as exc:
        sys.exit(f"plot_stiffness.py: error: {exc}")


if __name__ == "__main__":
    main()
