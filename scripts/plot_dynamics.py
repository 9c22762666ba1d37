#!/usr/bin/env python3
"""Dynamic response at the meshing line, in the style of seed Figs. 10-12 (Bai & Ning 2023).

Given one or more ``planetwear simulate`` outputs (e.g. 100, 200 and 400 rpm),
draws for the sun–planet and planet–ring mesh of one planet (default planet 0):

  fig10_penetration_depth.png   mesh deflection along the line of action
                                ("penetration depth at the meshing line", Fig. 10)
                                over the first few recorded mesh periods;
  fig11_mesh_acceleration.png   relative acceleration of the two gears along the
                                line of action (Fig. 11), same time window;
  fig12_acceleration_spectra.png      amplitude spectra of those accelerations
                                      (Fig. 12) over the whole record, log scale,
                                      with the linearized natural frequencies;
  fig12_acceleration_spectra_low.png  the same, first harmonics of the mesh
                                      frequency only, linear scale.

One row per input file (speed), one column per mesh type; time is in mesh
periods T_z = 1/f_z on the x axis, the shading marks where two tooth pairs are
in mesh. Mesh-frequency harmonics k·f_z are marked in the spectra.

Spectra are read from /spectra/<mesh>/<i>/acceleration (Hann window, peak
amplitude scaling, written by planetwear); when absent they are computed here
the same way.

    /usr/bin/python3 scripts/plot_dynamics.py s100.h5 s200.h5 s400.h5 -d docs/figures
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pwplot  # noqa: E402  (re-execs under /usr/bin/python3 if needed)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MESHES = pwplot.MESH_TYPES
COLORS = {"sun_planet": "tab:blue", "planet_ring": "tab:orange"}


class Run:
    """Everything the figures need from one simulate output."""

    def __init__(self, path, planet):
        self.path = path
        with pwplot.open_result(path) as f:
            meshes = pwplot.list_meshes(f)
            for m in MESHES:
                if f"{m}/{planet}" not in meshes:
                    raise pwplot.PwPlotError(f"{path}: no mesh {m}/{planet} in /time_history "
                                             f"(present: {', '.join(meshes) or 'none'})")
            self.rpm = pwplot.speed_rpm(f)
            self.f_mesh = pwplot.scalar(f, "mesh_frequency", "Hz")[0]
            self.t = pwplot.time(f)
            self.natural = []
            if pwplot.has(f, "scalars/natural_frequency"):
                self.natural = sorted(float(f["scalars/natural_frequency"][k][()])
                                      for k in f["scalars/natural_frequency"].keys())
            self.defl, self.acc, self.pairs, self.spec = {}, {}, {}, {}
            for m in MESHES:
                base = f"{m}/{planet}"
                self.defl[m] = pwplot.channel(f, base + "/deflection", "m")
                self.acc[m] = pwplot.channel(f, base + "/acceleration", "m/s^2")
                self.pairs[m] = (pwplot.channel(f, base + "/pairs_in_contact").values
                                 if pwplot.has(f, f"time_history/{base}/pairs_in_contact") else None)
                if pwplot.has(f, f"spectra/{base}/acceleration/amplitude"):
                    fr, a, attrs = pwplot.spectrum(f, base + "/acceleration")
                    self.spec[m] = (fr, a.values, attrs.get("window", "?"), attrs.get("scaling", "?"))
                else:
                    self.spec[m] = hann_spectrum(self.acc[m].values, self.t)
        if self.t.size < 2:
            raise pwplot.PwPlotError(f"{path}: /time_history/time has fewer than 2 samples")
        self.dt = float(np.median(np.diff(self.t)))
        self.tau = (self.t - self.t[0] + self.dt) * self.f_mesh  # time in mesh periods from record start
        self.label = f"{self.rpm:.0f} rpm (f_z = {self.f_mesh:.2f} Hz)"


def hann_spectrum(x, t):
    """Single-sided peak-amplitude spectrum with a periodic Hann window
    (as docs/spectra.md): |X_k| * 2 / sum(w), DC and Nyquist not doubled."""
    n = x.size
    dt = float(np.median(np.diff(t)))
    w = 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(n) / n)
    X = np.abs(np.fft.rfft((x - 0.0) * w)) / w.sum()
    X[1:] *= 2
    if n % 2 == 0:
        X[-1] /= 2
    return np.fft.rfftfreq(n, dt), X, "hann", "peak amplitude (computed by plot_dynamics.py)"


def shade_double_contact(ax, tau, pairs, keep):
    """Light shading where more than one tooth pair is in mesh."""
    if pairs is None:
        return
    p = pairs[keep]
    tt = tau[keep]
    multi = p > 1.5
    if not multi.any():
        return
    edges = np.flatnonzero(np.diff(multi.astype(int)))
    starts = [0] if multi[0] else []
    starts += [e + 1 for e in edges if not multi[e]]
    ends = [e for e in edges if multi[e]] + ([multi.size - 1] if multi[-1] else [])
    for s, e in zip(starts, ends):
        ax.axvspan(tt[s], tt[e], color="0.88", lw=0, zorder=0)


def time_figure(runs, which, periods, planet, title, ylabel, path, dpi):
    fig, axes = plt.subplots(len(runs), 2, figsize=(12, 2.9 * len(runs) + 0.8), squeeze=False, sharex=True)
    letter = iter("abcdefghijklmnopqrstuvwxyz")
    # One unit prefix for the whole figure, so the panels compare directly.
    peak = max(float(np.max(np.abs(getattr(run, which)[m].values))) for run in runs for m in MESHES)
    for r, run in enumerate(runs):
        keep = run.tau <= periods
        for c, m in enumerate(MESHES):
            ax = axes[r][c]
            d = getattr(run, which)[m]
            v, unit = pwplot.scaled(d.values, d.unit, peak)
            shade_double_contact(ax, run.tau, run.pairs[m], keep)
            ax.plot(run.tau[keep], v[keep], color=COLORS[m], lw=0.9)
            mean = v.mean()
            p2p = np.ptp(v)
            if which == "defl":
                ax.axhline(mean, color="0.3", ls=":", lw=0.8)
                stats = f"mean {mean:.4g} {unit}, peak-to-peak {p2p:.4g} {unit}"
            else:  # the mean acceleration is zero to round-off
                stats = f"RMS {np.std(v):.4g} {unit}, peak-to-peak {p2p:.4g} {unit}"
            ax.text(0.99, 0.97, stats + "\n(whole record)",
                    transform=ax.transAxes, ha="right", va="top", fontsize=7.5,
                    bbox=dict(boxstyle="round", fc="white", ec="0.7", alpha=0.85))
            ax.set_title(f"({next(letter)}) {pwplot.MESH_LABELS[m]} {planet}, {run.label}", fontsize=9.5)
            ax.set_ylabel(f"{ylabel} [{unit}]")
            ax.grid(alpha=0.3)
            ax.set_xlim(0, periods)
            lo, hi = np.min(v[keep]), np.max(v[keep])
            pad = 0.3 * (hi - lo if hi > lo else abs(hi) + 1e-30)
            ax.set_ylim(lo - 0.1 * pad, hi + pad)  # headroom for the box
    for c in range(2):
        axes[-1][c].set_xlabel("time t / T_z [mesh periods] (grey: two tooth pairs in mesh)")
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    pwplot.save(fig, path, dpi)
    plt.close(fig)


def mark_harmonics(ax, f_mesh, fmax, n_label, y_text):
    k_max = int(fmax / f_mesh)
    for k in range(1, k_max + 1):
        ax.axvline(k * f_mesh, color="0.55", ls=":", lw=0.7, zorder=0)
        if k <= n_label:
            ax.text(k * f_mesh, y_text, f"{k}f_z" if k > 1 else "f_z", rotation=90, fontsize=7, color="0.35",
                    ha="right", va="top", transform=ax.get_xaxis_transform())


def harmonic_amplitudes(fr, amp, f_mesh, fmax):
    """(k*f_z, amplitude) of the mesh harmonics up to fmax: the largest bin within
    +-1 bin of k*f_z (the record holds whole mesh periods, so the line sits on a bin)."""
    df = fr[1] - fr[0]
    ks = np.arange(1, int(fmax / f_mesh) + 1)
    idx = np.rint(ks * f_mesh / df).astype(int)
    ok = idx + 1 < fr.size
    ks, idx = ks[ok], idx[ok]
    a = np.maximum.reduce([amp[idx - 1], amp[idx], amp[idx + 1]])
    return ks * f_mesh, a


def spectra_figure(runs, planet, fmax, path, dpi, low_harmonics=None):
    fig, axes = plt.subplots(len(runs), 2, figsize=(12, 2.9 * len(runs) + 0.8), squeeze=False)
    letter = iter("abcdefghijklmnopqrstuvwxyz")
    for r, run in enumerate(runs):
        for c, m in enumerate(MESHES):
            ax = axes[r][c]
            fr, amp, window, scaling = run.spec[m]
            top = (low_harmonics + 0.5) * run.f_mesh if low_harmonics else min(fmax, fr[-1])
            sel = (fr > 0) & (fr <= top)
            if low_harmonics:
                ax.plot(fr[sel], amp[sel], color=COLORS[m], lw=0.9)
                mark_harmonics(ax, run.f_mesh, top, low_harmonics, 0.97)
                ax.set_ylim(0, 1.3 * amp[sel].max())
                ax.set_xlim(0, top)
            else:
                # The response is periodic in the mesh period, so the spectrum is a comb of mesh
                # harmonics; draw the raw spectrum faintly and the harmonic amplitudes as dots.
                ax.loglog(fr[sel], amp[sel], color=COLORS[m], lw=0.3, alpha=0.18)
                fh, ah = harmonic_amplitudes(fr, amp, run.f_mesh, top)
                ax.loglog(fh, ah, ".-", color=COLORS[m], ms=2.5, lw=0.6, label="mesh harmonics k·f_z")
                for i, fn in enumerate(fn for fn in run.natural if 1.0 < fn <= top):
                    ax.axvline(fn, color="tab:red", ls="--", lw=0.8, alpha=0.7,
                               label="natural frequencies (linearized)" if i == 0 else None)
                ax.axvline(run.f_mesh, color="0.3", ls=":", lw=0.9)
                ax.text(run.f_mesh, 0.03, " f_z", fontsize=7.5, color="0.3", transform=ax.get_xaxis_transform())
                ax.legend(loc="lower center", fontsize=7.5)
                ax.set_ylim(bottom=max(ah.min() * 0.3, ah.max() * 1e-5))
                ax.set_xlim(0.7 * run.f_mesh, top)
            i_pk = np.argmax(np.where(sel, amp, -np.inf))
            ax.set_title(f"({next(letter)}) {pwplot.MESH_LABELS[m]} {planet}, {run.label}\n"
                         f"largest line {amp[i_pk]:.3g} m/s² at {fr[i_pk]:.1f} Hz = {fr[i_pk] / run.f_mesh:.0f} f_z",
                         fontsize=9)
            ax.set_ylabel("amplitude [m/s²]")
            ax.set_xlabel("frequency [Hz]")
            ax.grid(alpha=0.3)
    win = runs[0].spec[MESHES[0]][2]
    span = (f"first {low_harmonics} mesh harmonics" if low_harmonics
            else f"up to {min(fmax, runs[0].spec[MESHES[0]][0][-1]):.0f} Hz, log–log")
    fig.suptitle(f"FFT of the mesh-line acceleration (cf. seed Fig. 12), {span}; "
                 f"{win} window, peak amplitude", fontsize=11)
    fig.tight_layout()
    pwplot.save(fig, path, dpi)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(
        description="Penetration depth (seed Fig. 10), mesh-line acceleration (Fig. 11) and its spectrum "
                    "(Fig. 12) of the sun–planet and planet–ring mesh of one planet, from one or more "
                    "'planetwear simulate' outputs (one row per file).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Example:\n  for s in 100 200 400; do planetwear simulate --speed-rpm $s -o /tmp/s$s.h5; done\n"
               "  /usr/bin/python3 scripts/plot_dynamics.py /tmp/s100.h5 /tmp/s200.h5 /tmp/s400.h5 "
               "-d docs/figures")
    p.add_argument("files", nargs="+", help="HDF5 files from 'planetwear simulate -o' (sorted by speed)")
    p.add_argument("-d", "--outdir", default="docs/figures", help="directory for the PNGs (default: %(default)s)")
    p.add_argument("--planet", type=int, default=0, help="planet index whose meshes are shown (default: 0)")
    p.add_argument("--periods", type=float, default=4, help="mesh periods shown in Figs. 10/11 (default: 4)")
    p.add_argument("--fmax", type=float, default=None,
                   help="upper frequency of the full (log-log) spectrum [Hz] (default: Nyquist "
                        "frequency 1/(2 dt))")
    p.add_argument("--harmonics", type=int, default=12,
                   help="mesh harmonics shown in the low-frequency spectrum (default: %(default)s)")
    p.add_argument("--prefix", default="", help="prefix for the PNG names (default: none)")
    p.add_argument("--dpi", type=int, default=130, help="resolution (default: %(default)s)")
    a = p.parse_args()
    if a.periods <= 0 or a.harmonics < 1:
        p.error("--periods must be > 0 and --harmonics >= 1")
    try:
        runs = sorted((Run(path, a.planet) for path in a.files), key=lambda r: r.rpm)
        fmax = a.fmax if a.fmax is not None else np.inf
        out = lambda name: os.path.join(a.outdir, a.prefix + name)  # noqa: E731
        time_figure(runs, "defl", a.periods, a.planet,
                    "Penetration depth at the meshing line = mesh deflection along the line of action "
                    "(cf. seed Fig. 10)", "deflection", out("fig10_penetration_depth.png"), a.dpi)
        time_figure(runs, "acc", a.periods, a.planet,
                    "Acceleration at the meshing line: relative acceleration along the line of action "
                    "(cf. seed Fig. 11)", "acceleration", out("fig11_mesh_acceleration.png"), a.dpi)
        spectra_figure(runs, a.planet, fmax, out("fig12_acceleration_spectra.png"), a.dpi)
        spectra_figure(runs, a.planet, fmax, out("fig12_acceleration_spectra_low.png"), a.dpi,
                       low_harmonics=a.harmonics)
    except pwplot.PwPlotError as exc:
        sys.exit(f"plot_dynamics.py: error: {exc}")


if __name__ == "__main__":
    main()
