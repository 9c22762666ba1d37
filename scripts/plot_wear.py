#!/usr/bin/env python3
"""Wear figures in the style of seed Figs. 9-12 (Bai & Ning 2023) from wear runs.

Input: one or more ``planetwear simulate --mesh-cycles N`` outputs (e.g. 100,
200 and 400 rpm), each with a /wear group (docs/output-format.md, "Wear").
One row per file, sorted by speed. Writes into --outdir:

  fig9_wear_distribution.png   seed Fig. 9 (a-l): wear depth vs distance from
                               the pitch point for the flank families sun,
                               planet_<p>/sun_side, planet_<p>/ring_side, ring;
                               one curve per stored wear update (colour = mesh
                               cycles), each the maximum over the family's
                               teeth; the min-max band over the teeth at the
                               last update.
  wear_tooth_spread.png        tooth-to-tooth spread (max - min over teeth) of
                               the last update, in % of the family maximum.
  wear_growth.png              maximum wear of each family, of the sun-planet
                               (max over sun and planet sun-side flanks) and
                               planet-ring (planet ring-side and ring flanks)
                               meshes, and the backlash, vs mesh cycles.
  wear_penetration_depth.png   seed Fig. 10 "as mesh cycles increase": mesh
                               deflection of planet 0's two meshes over a few
                               mesh periods at every stored snapshot, and its
                               change from the unworn snapshot.
  wear_mesh_acceleration.png   seed Fig. 11: the same for the relative
                               acceleration along the line of action.
  wear_acceleration_spectra.png      seed Fig. 12: acceleration spectra of
                                     every snapshot (/wear/snapshots/<k>/spectra),
                                     log-log, mesh harmonics as dots.
  wear_acceleration_spectra_low.png  the same on linear axes up to --fmax-low
                                     (the seed's 0-1 kHz range), with the
                                     seed's reported frequencies marked.
  wear_snapshot_trends.png     deflection peak-to-peak, acceleration RMS and
                               largest spectral line of every snapshot
                               relative to the unworn one [%].

--suffix NAME is appended to every file name (e.g. "_k0.01" for runs with
stiffness.scale = 0.01). --summary prints the numbers behind the figures
(maxima per family, ratios, frequencies, snapshot changes) as Markdown.

    /usr/bin/python3 scripts/plot_wear.py w100.h5 w200.h5 w400.h5 -d docs/figures --summary
"""

import argparse
import builtins
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pwplot  # noqa: E402  (re-execs under /usr/bin/python3 if needed)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import colors as mcolors  # noqa: E402
from matplotlib.cm import ScalarMappable  # noqa: E402

MESHES = pwplot.MESH_TYPES
MESH_COLORS = {"sun_planet": "tab:blue", "planet_ring": "tab:orange"}
SPEED_STYLES = ["-", "--", ":", "-."]
CMAP = "viridis"
TITLE_NOTE = ""  # e.g. " [mesh stiffness × 0.01 = seed Table 2 level]", appended to every figure title

# Seed values (Bai & Ning 2023, §6; /work/shared/REFERENCE.md).
SEED_SUN_PLANET_MAX_MM = {100: 1.1610e-4, 400: 1.410e-5}
SEED_MAIN_FREQ_HZ = {100: {"sun_planet": 450.0, "planet_ring": 250.0},
                     400: {"sun_planet": 550.0, "planet_ring": 650.0}}
SEED_LOW_BAND_HZ = (112.0, 120.0)


def families(planet):
    """(key in /wear, short label, mesh) of the four flank families."""
    return [("sun", "sun", "sun–planet mesh"),
            (f"planet_{planet}/sun_side", f"planet {planet} sun side", "sun–planet mesh"),
            (f"planet_{planet}/ring_side", f"planet {planet} ring side", "planet–ring mesh"),
            ("ring", "ring", "planet–ring mesh")]


class Family:
    def __init__(self, f, key):
        base = "wear/" + key
        self.depth = pwplot.read(f, base + "/depth", "m").values          # (U, teeth, elements) [m]
        self.x = pwplot.read(f, base + "/distance_from_pitch_point", "m").values  # (elements,) [m]
        if self.depth.ndim != 3 or self.depth.shape[2] != self.x.size:
            raise pwplot.PwPlotError(f"{f.filename}: /{base}/depth has shape {self.depth.shape}, "
                                     f"expected (updates, teeth, {self.x.size})")
        self.max_over_teeth = self.depth.max(axis=1)   # (U, elements)
        self.min_over_teeth = self.depth.min(axis=1)
        self.max_depth = self.depth.max(axis=(1, 2))   # (U,)


class Snapshot:
    def __init__(self, f, group):
        g = f[group]
        self.cycles = float(g.attrs["mesh_cycles"])
        self.t = pwplot.read(f, group + "/time_history/time", "s").values
        self.defl, self.acc, self.spec = {}, {}, {}
        for m in MESHES:
            self.defl[m] = pwplot.read(f, f"{group}/time_history/{m}/0/deflection", "m").values
            self.acc[m] = pwplot.read(f, f"{group}/time_history/{m}/0/acceleration", "m/s^2").values
            fr = pwplot.read(f, f"{group}/spectra/{m}/0/acceleration/frequency", "Hz").values
            amp = pwplot.read(f, f"{group}/spectra/{m}/0/acceleration/amplitude").values
            self.spec[m] = (fr, amp)


class WearRun:
    """Everything the figures need from one wear run."""

    def __init__(self, path, planet):
        self.path = path
        with pwplot.open_result(path) as f:
            if "wear" not in f:
                raise pwplot.PwPlotError(f"{path}: no /wear group (run 'planetwear simulate --mesh-cycles N')")
            self.rpm = pwplot.speed_rpm(f)
            self.f_mesh = pwplot.scalar(f, "mesh_frequency", "Hz")[0]
            self.natural = []
            if pwplot.has(f, "scalars/natural_frequency"):
                self.natural = sorted(float(f["scalars/natural_frequency"][k][()])
                                      for k in f["scalars/natural_frequency"].keys())
            scale = pwplot.config_value(f, "stiffness.scale")
            self.stiffness_scale = float(scale) if scale is not None else 1.0
            self.power = float(pwplot.config_value(f, "operating.input_power_W") or "nan")
            self.stop_reason = pwplot._decode(f["wear"].attrs.get("stop_reason", ""))
            self.cycles = pwplot.read(f, "wear/mesh_cycles", "1").values
            self.backlash = pwplot.read(f, "wear/backlash", "m").values.reshape(self.cycles.size, 2)
            self.fam = {key: Family(f, key) for key, _, _ in families(planet)}
            snaps = []
            if "wear/snapshots" in f:
                snaps = [Snapshot(f, "wear/snapshots/" + k) for k in f["wear/snapshots"].keys()]
            self.snaps = sorted(snaps, key=lambda s: s.cycles)  # names sort as strings: use the attribute
        self.label = f"{self.rpm:.0f} rpm"
        self.planet = planet

    def mesh_wear(self, which, update=-1):
        """Sun-planet wear = max over the sun and planet sun-side flanks; planet-ring = max over the
        planet ring-side and ring flanks (in the seed case all planets share the same maxima)."""
        keys = list(self.fam)
        pair = keys[:2] if which == "sun_planet" else keys[2:]
        return max(self.fam[k].max_depth[update] for k in pair)


def unit_scale(peak, unit):
    """(divisor, label) that puts values of magnitude `peak` [unit] into O(1..1000) (pwplot.scaled)."""
    if not peak or not np.isfinite(peak):
        return 1.0, pwplot.scaled([0.0], unit)[1]
    v, label = pwplot.scaled([peak], unit, peak)
    return peak / float(v[0]), label


def save(fig, path, dpi):
    """pwplot.save with TITLE_NOTE appended to the figure title."""
    if TITLE_NOTE and fig._suptitle is not None:
        fig._suptitle.set_text(fig._suptitle.get_text() + TITLE_NOTE)
    pwplot.save(fig, path, dpi)


def label_runs(runs):
    """Puts the stiffness scale into the run labels if the runs differ in it; returns a note for the
    figure title if they share one that is not 1."""
    scales = {r.stiffness_scale for r in runs}
    if len(scales) > 1:
        for r in runs:
            r.label = f"{r.rpm:.0f} rpm, stiffness × {r.stiffness_scale:g}"
        return ""
    k = scales.pop()
    return "" if k == 1.0 else f" [mesh stiffness × {k:g}" + (" = seed Table 2 level]" if k == 0.01 else "]")


def panel_box(ax, text, loc="upper center", fontsize=7.5):
    xy = {"upper center": (0.5, 0.97, "center", "top"), "upper right": (0.98, 0.97, "right", "top"),
          "upper left": (0.02, 0.97, "left", "top"), "lower right": (0.98, 0.03, "right", "bottom")}[loc]
    ax.text(xy[0], xy[1], text, transform=ax.transAxes, ha=xy[2], va=xy[3], fontsize=fontsize,
            bbox=dict(boxstyle="round", fc="white", ec="0.7", alpha=0.9))


def cycle_norm(runs):
    top = max(float(r.cycles[-1]) for r in runs)
    return mcolors.Normalize(vmin=0.0, vmax=top if top > 0 else 1.0)


def add_cycle_colorbar(fig, axes, norm):
    sm = ScalarMappable(norm=norm, cmap=CMAP)
    cb = fig.colorbar(sm, ax=np.ravel(axes).tolist(), fraction=0.025, pad=0.01)
    cb.set_label("mesh cycles N")
    cb.formatter.set_powerlimits((0, 0))
    cb.update_ticks()


# ---------------------------------------------------------------- Fig. 9
def fig9_distribution(runs, planet, path, dpi):
    fams = families(planet)
    norm = cycle_norm(runs)
    cmap = plt.get_cmap(CMAP)
    peak = max(float(r.fam[k].max_depth[-1]) for r in runs for k, _, _ in fams)
    scale, unit = unit_scale(peak, "m")
    fig, axes = plt.subplots(len(runs), 4, figsize=(17, 3.1 * len(runs) + 0.9), squeeze=False, constrained_layout=True)
    letter = iter("abcdefghijklmnopqrstuvwxyz")
    for r, run in enumerate(runs):
        for c, (key, label, caption) in enumerate(fams):
            ax = axes[r][c]
            fam = run.fam[key]
            x = fam.x * 1e3
            for u in range(1, run.cycles.size):
                ax.plot(x, fam.max_over_teeth[u] / scale, color=cmap(norm(run.cycles[u])), lw=1.0)
            ax.fill_between(x, fam.min_over_teeth[-1] / scale, fam.max_over_teeth[-1] / scale,
                            color="tab:red", alpha=0.5, lw=0)
            ax.axvline(0.0, color="0.5", ls=":", lw=0.8)
            mx = fam.max_depth[-1]
            i_max = np.unravel_index(np.argmax(fam.depth[-1]), fam.depth[-1].shape)
            spread = 100.0 * np.max(fam.max_over_teeth[-1] - fam.min_over_teeth[-1]) / mx if mx > 0 else 0.0
            text = (f"max {mx * 1e3:.3e} mm at {x[i_max[1]]:+.2f} mm (tooth {i_max[0]})\n"
                    f"after N = {run.cycles[-1]:.3g}; tooth spread ≤ {spread:.2g} % of max")
            seed = SEED_SUN_PLANET_MAX_MM.get(int(round(run.rpm)))
            if key == "sun" and seed is not None and run.stiffness_scale in (1.0, 0.01):
                text += f"\nseed, sun–planet max: {seed:.4e} mm"
            panel_box(ax, text)
            ax.set_title(f"({next(letter)}) {label} flank ({caption}), {run.label}", fontsize=9)
            ax.set_ylabel(f"wear depth [{unit}]")
            ax.set_ylim(0, 1.45 * mx / scale if mx > 0 else 1)
            ax.grid(alpha=0.3)
            if r == len(runs) - 1:
                ax.set_xlabel("distance from pitch point [mm]  (− root, + tip)")
    add_cycle_colorbar(fig, axes, norm)
    fig.suptitle("Wear distribution on the tooth flanks (cf. seed Fig. 9): maximum over the teeth at every wear "
                 "update (colour = mesh cycles);\nred band: min–max over the teeth at the last update (narrower than the line where "
                 "the spread is < 1 %)",
                 fontsize=11)
    save(fig, path, dpi)
    plt.close(fig)


def tooth_spread_figure(runs, planet, path, dpi):
    fams = families(planet)
    fig, axes = plt.subplots(1, 4, figsize=(17, 3.6), squeeze=False, constrained_layout=True)
    for c, (key, label, caption) in enumerate(fams):
        ax = axes[0][c]
        for i, run in enumerate(runs):
            fam = run.fam[key]
            mx = fam.max_depth[-1]
            sp = 100.0 * (fam.max_over_teeth[-1] - fam.min_over_teeth[-1]) / mx if mx > 0 else 0 * fam.x
            ax.plot(fam.x * 1e3, sp, SPEED_STYLES[i % 4], color=f"C{i}", lw=1.1, label=run.label)
        ax.axvline(0.0, color="0.5", ls=":", lw=0.8)
        ax.set_title(f"({'abcd'[c]}) {label} flank ({caption}), {run.fam[key].depth.shape[1]} teeth", fontsize=9)
        ax.set_xlabel("distance from pitch point [mm]  (− root, + tip)")
        ax.set_ylabel("max − min over teeth [% of family max]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5)
    fig.suptitle("Tooth-to-tooth spread of the wear depth at the last update", fontsize=11)
    save(fig, path, dpi)
    plt.close(fig)


# ---------------------------------------------------------------- growth
def growth_figure(runs, planet, path, dpi):
    fams = families(planet)
    fig, axes = plt.subplots(2, 4, figsize=(17, 7.2), squeeze=False, constrained_layout=True)
    peak = max(float(r.fam[k].max_depth[-1]) for r in runs for k, _, _ in fams)
    scale, unit = unit_scale(peak, "m")
    letter = iter("abcdefgh")
    panels = [(axes[0][c], key, f"{label} ({caption})") for c, (key, label, caption) in enumerate(fams)]
    for ax, key, title in panels:
        for i, run in enumerate(runs):
            ax.plot(run.cycles, run.fam[key].max_depth / scale, SPEED_STYLES[i % 4], marker=".", color=f"C{i}",
                    lw=1.1, label=f"{run.label}: {run.fam[key].max_depth[-1] * 1e3:.3e} mm")
        ax.set_title(f"({next(letter)}) max wear, {title}", fontsize=9)
        ax.set_ylabel(f"max wear depth [{unit}]")
    for c, m in enumerate(MESHES):
        ax = axes[1][c]
        for i, run in enumerate(runs):
            w = np.array([run.mesh_wear(m, u) for u in range(run.cycles.size)])
            extra = ""
            if m == "planet_ring":
                sp = run.mesh_wear("sun_planet")
                extra = f" = {100 * w[-1] / sp:.2f} % of sun–planet" if sp > 0 else ""
            ax.plot(run.cycles, w / scale, SPEED_STYLES[i % 4], marker=".", color=f"C{i}", lw=1.1,
                    label=f"{run.label}: {w[-1] * 1e3:.3e} mm{extra}")
        flanks = "sun and planet sun-side flanks" if m == "sun_planet" else "planet ring-side and ring flanks"
        ax.set_title(f"({next(letter)}) {pwplot.MESH_LABELS[m]} wear = max over {flanks}", fontsize=9)
        ax.set_ylabel(f"max wear depth [{unit}]")
    bpeak = max(float(np.max(r.backlash)) for r in runs)
    bscale, bunit = unit_scale(bpeak, "m")
    for c, m in enumerate(MESHES):
        ax = axes[1][2 + c]
        for i, run in enumerate(runs):
            b = run.backlash[:, c]
            ax.plot(run.cycles, b / bscale, SPEED_STYLES[i % 4], marker=".", color=f"C{i}", lw=1.1,
                    label=f"{run.label}: +{(b[-1] - b[0]) * 1e3:.3e} mm")
        ax.set_title(f"({next(letter)}) backlash along the line of action, {pwplot.MESH_LABELS[m]}", fontsize=9)
        ax.set_ylabel(f"backlash [{bunit}]")
    for ax in axes.ravel():
        ax.set_xlabel("mesh cycles N")
        ax.ticklabel_format(axis="x", style="sci", scilimits=(0, 0))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
        ax.set_ylim(bottom=0)
        lo, hi = ax.get_ylim()
        ax.set_ylim(0, hi * 1.25)  # room for the legend
    fig.suptitle("Wear growth: maximum wear depth of each flank family and mesh, and backlash growth "
                 "(mean flank wear of both gears), vs mesh cycles", fontsize=11)
    save(fig, path, dpi)
    plt.close(fig)


# ---------------------------------------------------------------- snapshots
def snapshot_runs(runs):
    return [r for r in runs if len(r.snaps) > 0]


def phase_lag(ref, y, period):
    """Lag L [samples] of y behind ref (y[n] ~ ref[n - L]) from the circular cross-correlation,
    reduced to (-period/2, period/2]: the response repeats every mesh period, so only the phase
    within a period is meaningful."""
    a, b = ref - ref.mean(), y - y.mean()
    c = np.fft.irfft(np.fft.rfft(b) * np.conj(np.fft.rfft(a)), n=a.size)
    lag = int(np.argmax(c))
    return (lag + period // 2) % period - period // 2


def snapshot_time_figure(runs, which, periods, title, ylabel, path, dpi):
    norm = cycle_norm(runs)
    cmap = plt.get_cmap(CMAP)
    fig, axes = plt.subplots(len(runs), 4, figsize=(18, 2.9 * len(runs) + 1.0), squeeze=False, constrained_layout=True)
    letter = iter("abcdefghijklmnopqrstuvwxyz")
    unit_name = "m" if which == "defl" else "m/s^2"
    peak = max(float(np.max(np.abs(getattr(s, which)[m]))) for r in runs for s in r.snaps for m in MESHES)
    for r, run in enumerate(runs):
        s0 = run.snaps[0]
        dt = float(np.median(np.diff(s0.t)))
        period = max(1, int(round(1.0 / (run.f_mesh * dt))))  # samples per mesh period
        for c, m in enumerate(MESHES):
            ax, axd = axes[r][c], axes[r][2 + c]
            ref = getattr(s0, which)[m]
            fac, unit = unit_scale(peak, unit_name)
            # The snapshots start at whole mesh periods, but the stage's speed (set by the constant input
            # power and the frozen load torque) drifts by ~1e-5 as wear changes the friction losses, so
            # the meshing events slide by a few time steps between snapshots; align each snapshot to the
            # first one (circular shift within one mesh period, from the deflection) before subtracting.
            aligned, lags = [], []
            for s in run.snaps:
                y = getattr(s, which)[m]
                if y.size != ref.size:
                    aligned.append(None)
                    lags.append(None)
                    continue
                lag = phase_lag(s0.defl[m], s.defl[m], period)
                aligned.append(np.roll(y, -lag))
                lags.append(lag)
            dpeak = max([float(np.max(np.abs(y - ref))) for y in aligned if y is not None] + [0.0])
            dfac, dunit = unit_scale(dpeak, unit_name)
            lines = []
            for s, y, lag in zip(run.snaps, aligned, lags):
                if y is None:
                    y = getattr(s, which)[m]
                ts = s0.t[:y.size] * run.f_mesh
                k = ts <= periods
                col = cmap(norm(s.cycles))
                ax.plot(ts[k], y[k] / fac, color=col, lw=0.9)
                if lag is not None:
                    axd.plot(ts[k], (y[k] - ref[k]) / dfac, color=col, lw=0.9)
                stat = np.ptp(y) if which == "defl" else np.std(y)
                lines.append(f"N = {s.cycles:.3g}: {stat / fac:.4g} {unit}")
            name = "peak-to-peak" if which == "defl" else "RMS"
            panel_box(ax, f"{name} (whole snapshot):\n" + "\n".join([lines[0], lines[-1]]), loc="upper right")
            ax.set_title(f"({next(letter)}) {pwplot.MESH_LABELS[m]} 0, {run.label}", fontsize=9)
            ax.set_ylabel(f"{ylabel} [{unit}]")
            shift = max((abs(l) for l in lags if l is not None), default=0)
            axd.set_title(f"({next(letter)}) {pwplot.MESH_LABELS[m]} 0, {run.label}: change from N = 0\n"
                          f"(snapshots aligned to N = 0: shifts up to {shift} time steps = "
                          f"{shift / period:.2g} T_z)", fontsize=8.5)
            axd.set_ylabel(f"Δ {ylabel} [{dunit}]")
            for a in (ax, axd):
                a.set_xlim(0, periods)
                a.grid(alpha=0.3)
            lo, hi = ax.get_ylim()
            ax.set_ylim(lo, hi + 0.45 * (hi - lo))
    for c in range(4):
        axes[-1][c].set_xlabel("time t / T_z [mesh periods]")
    add_cycle_colorbar(fig, axes, norm)
    fig.suptitle(title, fontsize=11)
    save(fig, path, dpi)
    plt.close(fig)


def harmonic_amplitudes(fr, amp, f_mesh, fmax):
    """(k f_z, amplitude) of the mesh harmonics up to fmax: largest bin within +-1 bin of k f_z."""
    df = fr[1] - fr[0]
    ks = np.arange(1, int(fmax / f_mesh) + 1)
    idx = np.rint(ks * f_mesh / df).astype(int)
    ok = idx + 1 < fr.size
    ks, idx = ks[ok], idx[ok]
    a = np.maximum.reduce([amp[idx - 1], amp[idx], amp[idx + 1]])
    return ks * f_mesh, a


def snapshot_periods(run):
    """Length of a snapshot record in mesh periods."""
    t = run.snaps[0].t
    return (t[-1] - t[0] + float(np.median(np.diff(t)))) * run.f_mesh


def default_fmax(run):
    """Twice the highest natural frequency (the step resolves it with 32 steps per period;
    lines above are numerical), or the Nyquist frequency if no natural frequency is stored."""
    return 2.0 * max(run.natural) if run.natural else np.inf


def largest_line(fr, amp, fmin=5.0, fmax=np.inf):
    sel = (fr > fmin) & (fr <= fmax)
    if not sel.any():
        return float("nan"), float("nan")
    i = np.argmax(np.where(sel, amp, -np.inf))
    return float(fr[i]), float(amp[i])


def spectra_figure(runs, fmax, path, dpi, low=None):
    norm = cycle_norm(runs)
    cmap = plt.get_cmap(CMAP)
    fig, axes = plt.subplots(len(runs), 2, figsize=(14, 3.0 * len(runs) + 1.0), squeeze=False, constrained_layout=True)
    letter = iter("abcdefghijklmnopqrstuvwxyz")
    for r, run in enumerate(runs):
        for c, m in enumerate(MESHES):
            ax = axes[r][c]
            fr0 = run.snaps[0].spec[m][0]
            top = min(low if low else (fmax or default_fmax(run)), fr0[-1])
            floor = 0.0
            for j, s in enumerate(run.snaps):
                fr, amp = s.spec[m]
                col = cmap(norm(s.cycles))
                sel = (fr > 0) & (fr <= top)
                if low:
                    ax.plot(fr[sel], amp[sel], color=col, lw=0.9)
                else:
                    if j == 0:
                        ax.loglog(fr[sel], amp[sel], color="0.6", lw=0.3, alpha=0.5, zorder=0,
                                  label="raw spectrum, N = 0")
                    fh, ah = harmonic_amplitudes(fr, amp, run.f_mesh, top)
                    ax.loglog(fh, ah, ".-", color=col, ms=2.5, lw=0.6)
                    floor = min(floor, max(ah.min() * 0.3, ah.max() * 1e-4)) if j else max(ah.min() * 0.3, ah.max() * 1e-4)
            f_first, a_first = largest_line(*run.snaps[0].spec[m], fmax=top)
            f_last, a_last = largest_line(*run.snaps[-1].spec[m], fmax=top)
            span = f"below {top:.0f} Hz" if low else "largest line"
            ax.set_title(f"({next(letter)}) {pwplot.MESH_LABELS[m]} 0, {run.label} (f_z = {run.f_mesh:.2f} Hz)\n"
                         f"{span}: N = {run.snaps[0].cycles:.3g}: {a_first:.3g} m/s² at {f_first:.1f} Hz; "
                         f"N = {run.snaps[-1].cycles:.3g}: {a_last:.3g} m/s² at {f_last:.1f} Hz", fontsize=8.5)
            ax.axvspan(*SEED_LOW_BAND_HZ, color="tab:green", alpha=0.25, lw=0, label="seed low band 112–120 Hz")
            seed = SEED_MAIN_FREQ_HZ.get(int(round(run.rpm)), {}).get(m)
            if seed:
                ax.axvline(seed, color="tab:green", ls="--", lw=1.0, label=f"seed main frequency {seed:.0f} Hz")
            for i, fn in enumerate(fn for fn in run.natural if 1.0 < fn <= top):
                ax.axvline(fn, color="tab:red", ls="--", lw=0.8, alpha=0.7,
                           label="natural frequencies (linearized, unworn)" if i == 0 else None)
            if low:
                for k in range(1, int(top / run.f_mesh) + 1):
                    ax.axvline(k * run.f_mesh, color="0.6", ls=":", lw=0.6, zorder=0)
                ax.set_xlim(0, top)
                ax.set_ylim(bottom=0)
                lo, hi = ax.get_ylim()
                ax.set_ylim(0, hi * 1.3)
            else:
                ax.set_xlim(0.7 * run.f_mesh, top)
                ax.set_ylim(bottom=floor)
            ax.set_ylabel("amplitude [m/s²]")
            ax.set_xlabel("frequency [Hz]")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7, loc="upper left")
    add_cycle_colorbar(fig, axes, norm)
    what = (f"0–{low:.0f} Hz, linear (dotted: mesh harmonics k·f_z)" if low
            else "log–log, dots = mesh harmonics k·f_z")
    fig.suptitle(f"FFT of the mesh-line acceleration at each snapshot (cf. seed Fig. 12), {what};\n"
                 f"Hann window, peak amplitude, {snapshot_periods(runs[0]):.0f} mesh periods per snapshot",
                 fontsize=10.5)
    save(fig, path, dpi)
    plt.close(fig)


def snapshot_metrics(run, m):
    """Per snapshot: (cycles, deflection p-p [m], acceleration RMS [m/s^2], largest line (f, a))."""
    out = []
    for s in run.snaps:
        out.append((s.cycles, float(np.ptp(s.defl[m])), float(np.std(s.acc[m])), largest_line(*s.spec[m])))
    return out


def trends_figure(runs, path, dpi):
    fig, axes = plt.subplots(2, 3, figsize=(15, 7), squeeze=False, constrained_layout=True)
    letter = iter("abcdef")
    names = ["mesh deflection peak-to-peak", "mesh-line acceleration RMS", "largest line of the acceleration spectrum"]
    for r, m in enumerate(MESHES):
        for c in range(3):
            ax = axes[r][c]
            for i, run in enumerate(runs):
                met = snapshot_metrics(run, m)
                n = np.array([x[0] for x in met])
                v = np.array([x[1] if c == 0 else x[2] if c == 1 else x[3][1] for x in met])
                ax.plot(n, 100.0 * (v / v[0] - 1.0), SPEED_STYLES[i % 4], marker="o", ms=3.5, color=f"C{i}",
                        label=f"{run.label}: {100.0 * (v[-1] / v[0] - 1.0):+.2f} %")
            if c == 2 and r == 0:
                ax.plot([runs[0].snaps[-1].cycles if runs else 2e5], [102.11], "k*", ms=9,
                        label="seed, 200 rpm: +102.11 %")
            ax.axhline(0, color="0.4", lw=0.8)
            ax.set_title(f"({next(letter)}) {pwplot.MESH_LABELS[m]} 0: {names[c]}", fontsize=9.5)
            ax.set_ylabel("change from N = 0 [%]")
            ax.set_xlabel("mesh cycles N")
            ax.ticklabel_format(axis="x", style="sci", scilimits=(0, 0))
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7.5)
    fig.suptitle("Dynamic response vs mesh cycles: change of each snapshot's amplitudes relative to the unworn "
                 "snapshot", fontsize=11)
    save(fig, path, dpi)
    plt.close(fig)


# ---------------------------------------------------------------- summary
def pct(a, b):
    return 100.0 * (a / b - 1.0) if b else float("nan")


def print_summary(runs, planet, fmax_low, out=sys.stdout):
    fams = families(planet)
    _print = builtins.print

    def print(*args, **kw):  # noqa: A001  (everything below goes to `out`)
        _print(*args, file=out, **kw)

    print("\n### Wear after the last update (max over teeth and elements) [mm]\n")
    print("| run | speed [rpm] | stiffness scale | N | " + " | ".join(k for k, _, _ in fams)
          + " | sun–planet | planet–ring | planet–ring / sun–planet | backlash sp, pr [mm] |")
    print("|---|---:|---:|---:|" + "---:|" * (len(fams) + 4))
    for r in runs:
        sp, pr = r.mesh_wear("sun_planet"), r.mesh_wear("planet_ring")
        print(f"| {os.path.basename(r.path)} | {r.rpm:.0f} | {r.stiffness_scale:g} | {r.cycles[-1]:.3g} | "
              + " | ".join(f"{r.fam[k].max_depth[-1] * 1e3:.4e}" for k, _, _ in fams)
              + f" | {sp * 1e3:.4e} | {pr * 1e3:.4e} | {100 * pr / sp:.2f} % | "
              f"{r.backlash[-1, 0] * 1e3:.3e}, {r.backlash[-1, 1] * 1e3:.3e} |")
    if len(runs) >= 2:
        lo, hi = runs[0], runs[-1]
        print(f"\n### Change {lo.rpm:.0f} → {hi.rpm:.0f} rpm\n")
        for k, _, _ in fams:
            print(f"- {k}: {pct(hi.fam[k].max_depth[-1], lo.fam[k].max_depth[-1]):+.2f} %")
        for m in MESHES:
            print(f"- {m}: {pct(hi.mesh_wear(m), lo.mesh_wear(m)):+.2f} %")
        print("- wear × speed / (wear × speed at the lowest speed), sun–planet: "
              + ", ".join(f"{r.rpm:.0f} rpm {r.mesh_wear('sun_planet') * r.rpm / (lo.mesh_wear('sun_planet') * lo.rpm):.4f}"
                          for r in runs))
    if any(r.snaps for r in runs):
        print("\n### Snapshot spectra of the mesh-line acceleration (planet 0)\n")
        print(f"| run | mesh | N | largest line [Hz] (k = f/f_z) | amplitude [m/s²] | largest line below "
              f"{fmax_low:.0f} Hz [Hz] (amplitude) | largest line below 300 Hz [Hz] (amplitude) | "
              "line at 111.18 Hz [m/s²] | acc. RMS [m/s²] | defl. p-p [µm] |")
        print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        for r in runs:
            for m in MESHES:
                for s in r.snaps:
                    fr, amp = s.spec[m]
                    f1, a1 = largest_line(fr, amp)
                    f2, a2 = largest_line(fr, amp, fmax=300.0)
                    f3, a3 = largest_line(fr, amp, fmax=fmax_low)
                    i111 = np.argmin(np.abs(fr - 111.176))
                    a111 = max(amp[max(i111 - 1, 0):i111 + 2])
                    print(f"| {os.path.basename(r.path)} | {m} | {s.cycles:.3g} | {f1:.1f} ({f1 / r.f_mesh:.2f}) | "
                          f"{a1:.4g} | {f3:.1f} ({a3:.3g}) | {f2:.1f} ({a2:.3g}) | {a111:.3g} | {np.std(s.acc[m]):.4g} | "
                          f"{np.ptp(s.defl[m]) * 1e6:.4f} |")
        print("\n### Change of the snapshot amplitudes from the first to the last snapshot\n")
        for r in runs:
            for m in MESHES:
                met = snapshot_metrics(r, m)
                if len(met) >= 2:
                    a, b = met[0], met[-1]
                    print(f"- {os.path.basename(r.path)} {m}: deflection p-p {pct(b[1], a[1]):+.3f} %, "
                          f"acceleration RMS {pct(b[2], a[2]):+.3f} %, largest line {pct(b[3][1], a[3][1]):+.3f} %")


def main():
    p = argparse.ArgumentParser(
        description="Wear figures (seed Figs. 9-12 as mesh cycles increase) from 'planetwear simulate "
                    "--mesh-cycles N' outputs, one row per file (sorted by speed).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Example:\n  for s in 100 200 400; do planetwear simulate --speed-rpm $s --mesh-cycles 2e5 \\\n"
               "      --set 'wear.snapshot_mesh_cycles=[0,50000,100000,150000,200000]' -o /tmp/w$s.h5; done\n"
               "  /usr/bin/python3 scripts/plot_wear.py /tmp/w100.h5 /tmp/w200.h5 /tmp/w400.h5 -d docs/figures "
               "--summary")
    p.add_argument("files", nargs="+", help="HDF5 files from 'planetwear simulate --mesh-cycles N -o'")
    p.add_argument("-d", "--outdir", default="docs/figures", help="directory for the PNGs (default: %(default)s)")
    p.add_argument("--planet", type=int, default=0, help="planet whose flank families are shown (default: 0)")
    p.add_argument("--periods", type=float, default=3, help="mesh periods shown in the snapshot time plots "
                                                            "(default: %(default)s)")
    p.add_argument("--fmax", type=float, default=None, help="upper frequency of the log-log spectra [Hz] "
                                                            "(default: 2 x the highest natural frequency)")
    p.add_argument("--fmax-low", type=float, default=1000.0, help="upper frequency of the linear spectra [Hz] "
                                                                  "(default: %(default)s)")
    p.add_argument("--suffix", default="", help="appended to every PNG name, e.g. _k0.01 (default: none)")
    p.add_argument("--summary", nargs="?", const="-", default=None, metavar="FILE",
                   help="write the numbers behind the figures as Markdown to FILE (default: stdout)")
    p.add_argument("--dpi", type=int, default=110, help="resolution (default: %(default)s)")
    a = p.parse_args()
    if a.periods <= 0 or a.fmax_low <= 0:
        p.error("--periods and --fmax-low must be > 0")
    try:
        runs = sorted((WearRun(path, a.planet) for path in a.files), key=lambda r: r.rpm)
        global TITLE_NOTE
        TITLE_NOTE = label_runs(runs)
        out = lambda name: os.path.join(a.outdir, name + a.suffix + ".png")  # noqa: E731
        fig9_distribution(runs, a.planet, out("fig9_wear_distribution"), a.dpi)
        tooth_spread_figure(runs, a.planet, out("wear_tooth_spread"), a.dpi)
        growth_figure(runs, a.planet, out("wear_growth"), a.dpi)
        sruns = snapshot_runs(runs)
        if sruns:
            snapshot_time_figure(sruns, "defl", a.periods,
                                 "Penetration depth at the meshing line (mesh deflection) as mesh cycles increase "
                                 "(cf. seed Fig. 10); right: change from the unworn snapshot, phase-aligned",
                                 "deflection", out("wear_penetration_depth"), a.dpi)
            snapshot_time_figure(sruns, "acc", a.periods,
                                 "Acceleration at the meshing line (relative, along the line of action) as mesh "
                                 "cycles increase (cf. seed Fig. 11); right: change from the unworn snapshot, phase-aligned",
                                 "acceleration", out("wear_mesh_acceleration"), a.dpi)
            spectra_figure(sruns, a.fmax, out("wear_acceleration_spectra"), a.dpi)
            spectra_figure(sruns, a.fmax, out("wear_acceleration_spectra_low"), a.dpi, low=a.fmax_low)
            trends_figure(sruns, out("wear_snapshot_trends"), a.dpi)
        else:
            print("no /wear/snapshots in the inputs: snapshot figures skipped")
        for r in runs:
            if r.stop_reason:
                print(f"note: {r.path}: {r.stop_reason}")
        if a.summary == "-":
            print_summary(runs, a.planet, a.fmax_low)
        elif a.summary:
            with open(a.summary, "w", encoding="utf-8") as fh:
                print_summary(runs, a.planet, a.fmax_low, fh)
            print(f"wrote {a.summary}")
    except pwplot.PwPlotError as exc:
        sys.exit(f"plot_wear.py: error: {exc}")


if __name__ == "__main__":
    main()
