#!/usr/bin/env python3
"""Figures from planetwear campaign archives (``planetwear sweep``) and wear
snapshots of single runs (``planetwear simulate``); docs/postprocessing.md.

    plot_campaign.py main-effects ARCHIVE [-y OUTPUT ...] [-x FACTOR ...] -o PNG
    plot_campaign.py surface      ARCHIVE -x F1 -y F2 [-z OUTPUT] [--method quadratic|griddata] -o PNG
    plot_campaign.py waterfall    ARCHIVE [--by FACTOR] [--channel CH] [--orders] [--style lines|map] -o PNG
    plot_campaign.py snapshots    RUN.h5 [--channel CH] [--orders] [--style lines|map] -o PNG
    plot_campaign.py wear-profiles ARCHIVE [--family sun] [--by FACTOR] -o PNG
    plot_campaign.py sobol        ARCHIVE [-y OUTPUT ...] [--bootstrap 1000] -o PNG
    plot_campaign.py all          ARCHIVE -d DIR [--prefix campaign_]

Each subcommand has --help. Only done cases are drawn; failed cases are
marked (red ticks) where a factor axis is shown. Uses the Agg backend.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import pwplot  # noqa: E402  (re-execs under /usr/bin/python3 if numpy/h5py/matplotlib are missing)
import pwcampaign  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import cm, colors  # noqa: E402

DEFAULT_OUTPUTS = ("max_wear/sun", "sun_planet/0/acceleration_rms")
DEFAULT_CHANNEL = "sun_planet/0/acceleration"


class PlotError(Exception):
    pass


def _short(name):
    """Factor keys without their section for compact labels."""
    return name.split(".", 1)[1] if "." in name else name


def _values_label(c, column, values):
    """(scaled values, axis label with unit prefix)."""
    unit = c.units.get(column, "")
    if unit in ("", "1", "-", "rpm", "W", "m^2/N", "m/s^2", "Hz"):
        return np.asarray(values, dtype=float), f"{_short(column)} [{unit or '1'}]"
    v, u = pwplot.scaled(values, unit)
    return v, f"{_short(column)} [{u}]"


def _is_log(c, factor):
    return factor in c.factors.index and c.factors.at[factor, "scale"] == "log"


def _require(c, columns, what):
    for k in columns:
        if k not in c.design:
            near = [n for n in c.design.columns if k.split("/")[-1] in n][:8]
            raise PlotError(f"{c.path}: no {what} {k!r}" + (f"; similar: {', '.join(near)}" if near else ""))


def _default_outputs(c):
    out = [o for o in DEFAULT_OUTPUTS if o in c.design and np.isfinite(c.design.loc[c.done, o]).any()]
    if not out:
        out = ["efficiency"] if "efficiency" in c.design else c.scalar_names[:1]
    return out


def _default_factor(c, prefer="operating.input_speed_rpm"):
    if prefer in c.factors.index:
        return prefer
    spread = {k: np.ptp(c.design[k]) for k in c.factor_names}
    return max(spread, key=spread.get)


def _done_or_fail(c):
    t = c.design[c.done]
    if t.empty:
        raise PlotError(f"{c.path}: no case is done yet ({int(c.pending.sum())} pending, {int(c.failed.sum())} failed)")
    return t


def _colour_map(values, log=False, cmap="viridis"):
    v = np.asarray(values, dtype=float)
    lo, hi = np.nanmin(v), np.nanmax(v)
    if hi <= lo:
        hi = lo + 1.0 if lo == 0 else lo * 1.001 + 1e-300
    norm = colors.LogNorm(lo, hi) if log and lo > 0 else colors.Normalize(lo, hi)
    return cm.ScalarMappable(norm=norm, cmap=cmap)


def _title(c):
    n = c.campaign.get("name", "") or os.path.basename(c.path)
    return f"{n}: {int(c.done.sum())} of {c.cases} cases done ({c.design_type})"


# ---------------------------------------------------------------- main effects
def main_effects(c, outputs=None, factors=None, bins=None):
    """Grid outputs x factors: every done case (dots) and the mean response per
    level (full factorial / repeated levels) or per quantile bin of the factor
    (sampled designs), i.e. the main effect E[y | x_i]."""
    outputs = outputs or _default_outputs(c)
    factors = factors or c.factor_names
    _require(c, outputs, "output")
    _require(c, factors, "factor")
    t = _done_or_fail(c)
    fig, axes = plt.subplots(len(outputs), len(factors), figsize=(3.4 * len(factors) + 0.6, 2.8 * len(outputs) + 0.6),
                             squeeze=False, sharey="row")
    for r, out in enumerate(outputs):
        y_all, ylab = _values_label(c, out, c.design[out])
        for k, fac in enumerate(factors):
            ax = axes[r, k]
            x = t[fac].to_numpy(float)
            y = y_all[t.index]
            ok = np.isfinite(y)
            ax.plot(x[ok], y[ok], "o", ms=3.5, color="C0", alpha=0.6, label="cases")
            levels = np.unique(x[ok])
            if len(levels) <= max(8, len(x) // 3):
                centres = levels
                means = np.array([np.mean(y[ok][x[ok] == lv]) for lv in levels])
                lab = "mean per level"
            else:
                nb = bins or int(np.clip(round(np.sqrt(ok.sum())), 3, 10))
                q = np.quantile(np.log(x[ok]) if _is_log(c, fac) else x[ok], np.linspace(0, 1, nb + 1))
                xq = np.log(x[ok]) if _is_log(c, fac) else x[ok]
                idx = np.clip(np.searchsorted(q, xq, side="right") - 1, 0, nb - 1)
                centres = np.array([np.mean(x[ok][idx == b]) for b in range(nb) if np.any(idx == b)])
                means = np.array([np.mean(y[ok][idx == b]) for b in range(nb) if np.any(idx == b)])
                lab = f"mean of {nb} quantile bins"
            ax.plot(centres, means, "-", color="C3", lw=1.8, label=lab)
            fx = c.design.loc[c.failed, fac].to_numpy(float)
            if fx.size:
                ax.plot(fx, np.zeros_like(fx), "|", color="red", ms=12, transform=ax.get_xaxis_transform(),
                        label="failed")
            if _is_log(c, fac):
                ax.set_xscale("log")
            ax.grid(alpha=0.3)
            if r == len(outputs) - 1:
                ax.set_xlabel(_values_label(c, fac, x)[1])
            if k == 0:
                ax.set_ylabel(ylab)
            if r == 0 and k == len(factors) - 1:
                ax.legend(fontsize=7, loc="best")
    fig.suptitle("Main effects — " + _title(c), fontsize=10)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------ response surface
def _quadratic_design(u, v):
    return np.column_stack([np.ones_like(u), u, v, u * u, u * v, v * v])


def surface(c, fx, fy, out=None, method="quadratic", grid=80):
    """Output vs two factors: cases as coloured dots, contours of a least-squares
    quadratic in the (log-)scaled factors (method='quadratic', R^2 in the title)
    or of scipy's griddata linear interpolation (method='griddata')."""
    out = out or _default_outputs(c)[0]
    _require(c, [fx, fy], "factor")
    _require(c, [out], "output")
    t = _done_or_fail(c)
    x, y = t[fx].to_numpy(float), t[fy].to_numpy(float)
    z_all, zlab = _values_label(c, out, c.design[out])
    z = z_all[t.index]
    ok = np.isfinite(z)
    x, y, z = x[ok], y[ok], z[ok]
    if len(z) < 3:
        raise PlotError(f"{c.path}: {out}: {len(z)} done cases with a value; a surface needs at least 3")
    tx = (lambda a: np.log(a)) if _is_log(c, fx) else (lambda a: a)
    ty = (lambda a: np.log(a)) if _is_log(c, fy) else (lambda a: a)
    ux, uy = tx(x), ty(y)
    mx, sx = ux.mean(), (ux.std() or 1.0)
    my, sy = uy.mean(), (uy.std() or 1.0)
    gx = np.linspace(x.min(), x.max(), grid) if not _is_log(c, fx) else np.geomspace(x.min(), x.max(), grid)
    gy = np.linspace(y.min(), y.max(), grid) if not _is_log(c, fy) else np.geomspace(y.min(), y.max(), grid)
    GX, GY = np.meshgrid(gx, gy)
    fig, ax = plt.subplots(figsize=(6.4, 5.0))
    note = ""
    if method == "quadratic":
        if len(z) < 6:
            raise PlotError(f"{c.path}: a quadratic in two factors needs 6 done cases, have {len(z)}; "
                            f"use --method griddata")
        M = _quadratic_design((ux - mx) / sx, (uy - my) / sy)
        coef, *_ = np.linalg.lstsq(M, z, rcond=None)
        pred = M @ coef
        ss = np.sum((z - z.mean()) ** 2)
        r2 = 1 - np.sum((z - pred) ** 2) / ss if ss > 0 else 1.0
        GZ = (_quadratic_design((tx(GX).ravel() - mx) / sx, (ty(GY).ravel() - my) / sy) @ coef).reshape(GX.shape)
        note = f"least-squares quadratic, R² = {r2:.3f} ({len(z)} cases)"
    elif method == "griddata":
        from scipy.interpolate import griddata
        GZ = griddata(np.column_stack([(ux - mx) / sx, (uy - my) / sy]), z,
                      ((tx(GX) - mx) / sx, (ty(GY) - my) / sy), method="linear")
        note = f"linear interpolation (scipy griddata) of {len(z)} cases"
    else:
        raise PlotError(f"unknown method {method!r} (quadratic, griddata)")
    lo, hi = np.nanmin([np.nanmin(GZ), z.min()]), np.nanmax([np.nanmax(GZ), z.max()])
    levels = np.linspace(lo, hi, 15)
    cs = ax.contourf(GX, GY, GZ, levels=levels, cmap="viridis", alpha=0.85)
    ax.contour(GX, GY, GZ, levels=levels, colors="k", linewidths=0.4, alpha=0.5)
    ax.scatter(x, y, c=z, cmap="viridis", norm=colors.Normalize(lo, hi), edgecolors="w", s=40, zorder=3)
    fxf, fyf = c.design.loc[c.failed, fx], c.design.loc[c.failed, fy]
    if len(fxf):
        ax.plot(fxf, fyf, "x", color="red", ms=8, label="failed")
        ax.legend(fontsize=8)
    fig.colorbar(cs, ax=ax, label=zlab)
    ax.set_xlabel(_values_label(c, fx, x)[1])
    ax.set_ylabel(_values_label(c, fy, y)[1])
    if _is_log(c, fx):
        ax.set_xscale("log")
    if _is_log(c, fy):
        ax.set_yscale("log")
    ax.set_title(f"{_short(out)} — {note}", fontsize=9)
    fig.suptitle(_title(c), fontsize=10)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------ waterfalls
def _waterfall(ax, curves, values, vlabel, xlabel, ylabel, log_colour=False, style="lines", fmax=None):
    """curves: list of (x, amplitude); values: the parameter of each curve."""
    order = np.argsort(values)
    sm = _colour_map(values, log_colour)
    if fmax is not None:
        curves = [(f[f <= fmax], a[f <= fmax]) for f, a in curves]
    peak = max((np.nanmax(a[1:]) if len(a) > 1 else np.nanmax(a)) for _, a in curves if len(a)) or 1.0
    if style == "map":
        xmax = max(f.max() for f, _ in curves if len(f))
        edges = np.linspace(0, xmax, 601)
        grid = 0.5 * (edges[1:] + edges[:-1])
        img = np.array([np.interp(grid, curves[i][0], curves[i][1], left=np.nan, right=np.nan) for i in order])
        vs = np.asarray(values, dtype=float)[order]
        floor = peak * 1e-4
        m = ax.pcolormesh(edges, np.arange(len(vs) + 1), np.log10(np.maximum(img, floor)), cmap="magma", shading="flat")
        ax.set_yticks(np.arange(len(vs)) + 0.5)
        ax.set_yticklabels([f"{v:.4g}" for v in vs], fontsize=6)
        ax.set_ylabel(vlabel + " (one row per case, sorted)")
        plt.colorbar(m, ax=ax, label=f"log10 {ylabel}")
    else:
        step = 0.6
        for rank, i in enumerate(order):
            f, a = curves[i]
            ax.plot(f, rank * step + a / peak, color=sm.to_rgba(values[i]), lw=0.9)
            ax.fill_between(f, rank * step, rank * step + a / peak, color=sm.to_rgba(values[i]), alpha=0.15, lw=0)
        ax.set_yticks(np.arange(len(order)) * step)
        ax.set_yticklabels([f"{values[i]:.4g}" for i in order], fontsize=6)
        ax.set_ylabel(vlabel + f" (offset; amplitude / {peak:.3g})")
        plt.colorbar(sm, ax=ax, label=vlabel)
    ax.set_xlabel(xlabel)
    ax.grid(alpha=0.25)


def waterfall(c, by=None, channel=DEFAULT_CHANNEL, orders=False, style="lines", fmax=None):
    """Spectra of every done case stacked by a factor (default the speed):
    amplitude vs frequency, or vs mesh order (f / mesh_frequency) with --orders."""
    by = by or _default_factor(c)
    _require(c, [by], "factor or column")
    t = _done_or_fail(c)
    curves, vals = [], []
    for i in t.index:
        f, a = c.spectrum(channel, i)
        if not len(f):
            continue
        if orders:
            fz = c.design.at[i, "mesh_frequency"] if "mesh_frequency" in c.design else np.nan
            if not np.isfinite(fz) or fz <= 0:
                raise PlotError(f"{c.path}: case {i} has no mesh_frequency scalar for --orders")
            f = f / fz
        curves.append((f, a))
        vals.append(float(c.design.at[i, by]))
    if not curves:
        raise PlotError(f"{c.path}: no done case has spectrum bins for {channel}")
    fig, ax = plt.subplots(figsize=(7.5, 0.22 * len(curves) + 3.2))
    unit = c.unit("spectra/" + channel)
    _waterfall(ax, curves, np.array(vals), _values_label(c, by, vals)[1],
               "mesh order f / f_z" if orders else "frequency [Hz]", f"amplitude [{unit}]",
               log_colour=_is_log(c, by), style=style, fmax=fmax)
    ax.set_title(f"{channel} amplitude spectra over {_short(by)}", fontsize=9)
    fig.suptitle(_title(c), fontsize=10)
    fig.tight_layout()
    return fig


def snapshots(path, channel=DEFAULT_CHANNEL, orders=False, style="lines", fmax=None):
    """Spectra of the wear snapshots of one `planetwear simulate` run
    (/wear/snapshots/<k>/spectra/<channel>), stacked by mesh cycles."""
    with pwplot.open_result(path) as f:
        if "wear/snapshots" not in f:
            raise PlotError(f"{path}: no /wear/snapshots (run 'planetwear simulate --mesh-cycles N "
                            f"--set wear.snapshot_mesh_cycles=[...]')")
        curves, cycles = [], []
        fz = pwplot.scalar(f, "mesh_frequency", "Hz")[0] if orders else 1.0
        for name, g in f["wear/snapshots"].items():
            p = f"spectra/{channel}"
            if p not in g:
                raise PlotError(f"{path}: /wear/snapshots/{name} has no {p}")
            fr = g[p + "/frequency"][()]
            amp = g[p + "/amplitude"][()]
            curves.append((fr / fz, amp))
            cycles.append(float(g.attrs["mesh_cycles"]))
        unit = pwplot._decode(f[f"wear/snapshots/{name}/{p}"].attrs.get("unit", ""))
        speed = pwplot.speed_rpm(f)
    fig, ax = plt.subplots(figsize=(7.5, 0.25 * len(curves) + 3.2))
    _waterfall(ax, curves, np.array(cycles), "mesh cycles", "mesh order f / f_z" if orders else "frequency [Hz]",
               f"amplitude [{unit}]", style=style, fmax=fmax)
    ax.set_title(f"{channel} amplitude spectra as wear grows — {os.path.basename(path)}, {speed:.4g} rpm",
                 fontsize=9)
    fig.tight_layout()
    return fig


# --------------------------------------------------------------- wear profiles
def wear_profiles(c, family="sun", by=None, which="depth_final"):
    """Final wear depth vs distance from the pitch point, one curve per done case,
    coloured by a factor."""
    by = by or _default_factor(c)
    _require(c, [by], "factor or column")
    if family not in c.wear_families():
        raise PlotError(f"{c.path}: no wear data for family {family!r}; families: {c.wear_families() or 'none'}")
    t = _done_or_fail(c)
    prof, vals = [], []
    for i in t.index:
        x, h = c.wear_profile(family, i, which)
        if len(x):
            prof.append((x, h))
            vals.append(float(c.design.at[i, by]))
    if not prof:
        raise PlotError(f"{c.path}: no done case has wear elements for {family}")
    sm = _colour_map(vals, _is_log(c, by), cmap="plasma")
    peak = max(np.nanmax(np.abs(h)) for _, h in prof)
    _, hu = pwplot.scaled([peak], "m")
    scale = (pwplot.scaled([peak], "m")[0][0] / peak) if peak > 0 else 1.0
    fig, ax = plt.subplots(figsize=(6.8, 4.6))
    for (x, h), v in sorted(zip(prof, vals), key=lambda p: p[1]):
        ax.plot(x * 1e3, h * scale, "-", color=sm.to_rgba(v), lw=1.2, marker=".", ms=3)
    ax.axvline(0, color="k", lw=0.6, ls=":")
    ax.set_xlabel("distance from pitch point [mm] (+ towards the tip)")
    ax.set_ylabel(f"final wear depth, {'mean' if which == 'depth_final' else 'max'} over teeth [{hu}]")
    plt.colorbar(sm, ax=ax, label=_values_label(c, by, vals)[1])
    ax.grid(alpha=0.3)
    ax.set_title(f"{family} flank: final wear profile of {len(prof)} cases, coloured by {_short(by)}", fontsize=9)
    fig.suptitle(_title(c), fontsize=10)
    fig.tight_layout()
    return fig


# ----------------------------------------------------------------------- Sobol
def sobol_figure(c, outputs=None, n_bootstrap=1000, seed=0, confidence=0.95):
    """Bars of S1 and ST per factor with bootstrap intervals, one panel per output."""
    outputs = outputs or _default_outputs(c)
    fig, axes = plt.subplots(1, len(outputs), figsize=(1.2 + 1.1 * len(c.factor_names) * len(outputs) + 1.5,
                                                        3.8), squeeze=False)
    tables = {}
    for ax, out in zip(axes[0], outputs):
        r = c.sobol(out, n_bootstrap=n_bootstrap, seed=seed, confidence=confidence)
        tables[out] = r
        k = np.arange(len(r))
        for off, col, lab, colr in ((-0.18, "S1", "first order S1", "C0"), (0.18, "ST", "total ST", "C1")):
            err = np.vstack([r[col] - r[col + "_lo"], r[col + "_hi"] - r[col]])
            ax.bar(k + off, r[col], width=0.36, color=colr, label=lab, yerr=np.clip(err, 0, None), capsize=3)
        ax.axhline(0, color="k", lw=0.6)
        ax.set_xticks(k)
        ax.set_xticklabels([_short(f) for f in r.index], rotation=20, fontsize=8, ha="right")
        ax.set_ylim(min(-0.1, float(np.nanmin(r[["S1_lo", "ST_lo"]].to_numpy())) - 0.05),
                    max(1.05, float(np.nanmax(r[["S1_hi", "ST_hi"]].to_numpy())) + 0.05))
        ax.set_title(f"{_short(out)} ({r.attrs['rows_used']}/{r.attrs['rows']} rows)", fontsize=9)
        ax.grid(alpha=0.3, axis="y")
    axes[0][0].set_ylabel(f"Sobol' index ({100 * confidence:g} % bootstrap CI)")
    axes[0][0].legend(fontsize=8)
    fig.suptitle(_title(c), fontsize=10)
    fig.tight_layout()
    return fig, tables


# ------------------------------------------------------------------------- CLI
def _save(fig, path):
    pwplot.save(fig, path)
    plt.close(fig)


def cmd_all(a):
    c = pwcampaign.load(a.archive)
    made = []

    def attempt(name, make):
        try:
            fig = make()
            if isinstance(fig, tuple):
                fig = fig[0]
            _save(fig, os.path.join(a.dir, f"{a.prefix}{name}.png"))
            made.append(name)
        except PlotError as exc:
            print(f"skipped {name}: {exc}")
    attempt("main_effects", lambda: main_effects(c))
    if len(c.factor_names) >= 2:
        f2 = [k for k in c.factor_names if k != _default_factor(c)]
        attempt("surface", lambda: surface(c, _default_factor(c), f2[0]))
    if c.spectrum_channels():
        attempt("waterfall", lambda: waterfall(c))
    if "sun" in c.wear_families():
        attempt("wear_profiles", lambda: wear_profiles(c))
    if c.design_type == "saltelli":
        attempt("sobol", lambda: sobol_figure(c))
    return 0 if made else 1


def main(argv=None):
    import argparse
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def add(name, help_text, archive=True):
        s = sub.add_parser(name, help=help_text, description=help_text)
        if archive:
            s.add_argument("archive", help="campaign archive written by 'planetwear sweep'")
        return s

    s = add("main-effects", "Main effects: each output vs each factor, cases and mean response per level/bin.")
    s.add_argument("-y", "--output", action="append", help="scalar output (repeatable; default: max_wear/sun, "
                                                           "sun_planet/0/acceleration_rms)")
    s.add_argument("-x", "--factor", action="append", help="factor (repeatable; default: all)")
    s.add_argument("--bins", type=int, help="quantile bins for sampled designs (default sqrt(cases), 3..10)")
    s.add_argument("-o", "--out", required=True, help="PNG to write")

    s = add("surface", "Response surface of an output over two factors: contours of a fitted quadratic "
                       "(or griddata interpolation) and the cases.")
    s.add_argument("-x", required=True, help="factor on the x axis")
    s.add_argument("-y", required=True, help="factor on the y axis")
    s.add_argument("-z", "--output", help="scalar output (default max_wear/sun)")
    s.add_argument("--method", choices=("quadratic", "griddata"), default="quadratic")
    s.add_argument("-o", "--out", required=True, help="PNG to write")

    s = add("waterfall", "Spectra waterfall over a factor (default the input speed).")
    s.add_argument("--by", help="factor (or any design column) ordering the spectra")
    s.add_argument("--channel", default=DEFAULT_CHANNEL, help=f"spectrum channel (default {DEFAULT_CHANNEL})")
    s.add_argument("--orders", action="store_true", help="x axis in mesh orders f / mesh_frequency")
    s.add_argument("--style", choices=("lines", "map"), default="lines")
    s.add_argument("--fmax", type=float, help="upper end of the x axis (Hz, or orders with --orders)")
    s.add_argument("-o", "--out", required=True, help="PNG to write")

    s = add("snapshots", "Spectra waterfall over mesh cycles from the wear snapshots of one "
                         "'planetwear simulate' run (/wear/snapshots).", archive=False)
    s.add_argument("run", help="HDF5 output of 'planetwear simulate --mesh-cycles N' with snapshots")
    s.add_argument("--channel", default=DEFAULT_CHANNEL, help=f"spectrum channel (default {DEFAULT_CHANNEL})")
    s.add_argument("--orders", action="store_true", help="x axis in mesh orders")
    s.add_argument("--style", choices=("lines", "map"), default="lines")
    s.add_argument("--fmax", type=float, help="upper end of the x axis")
    s.add_argument("-o", "--out", required=True, help="PNG to write")

    s = add("wear-profiles", "Final wear depth vs distance from the pitch point, one curve per case, "
                             "coloured by a factor.")
    s.add_argument("--family", default="sun", help="flank family: sun, planet_<i>/sun_side, "
                                                   "planet_<i>/ring_side, ring (default sun)")
    s.add_argument("--by", help="colouring factor (default the input speed)")
    s.add_argument("--max", action="store_true", help="maximum over the teeth instead of the mean")
    s.add_argument("-o", "--out", required=True, help="PNG to write")

    s = add("sobol", "First-order and total Sobol' indices with bootstrap intervals (saltelli designs).")
    s.add_argument("-y", "--output", action="append", help="scalar output (repeatable)")
    s.add_argument("--bootstrap", type=int, default=1000)
    s.add_argument("--seed", type=int, default=0)
    s.add_argument("--confidence", type=float, default=0.95)
    s.add_argument("-o", "--out", required=True, help="PNG to write")

    s = add("all", "Every applicable figure with default choices into a directory.")
    s.add_argument("-d", "--dir", required=True, help="output directory")
    s.add_argument("--prefix", default="campaign_", help="file name prefix (default campaign_)")

    a = p.parse_args(argv)
    try:
        if a.command == "all":
            return cmd_all(a)
        if a.command == "snapshots":
            _save(snapshots(a.run, a.channel, a.orders, a.style, a.fmax), a.out)
            return 0
        c = pwcampaign.load(a.archive)
        if a.command == "main-effects":
            fig = main_effects(c, a.output, a.factor, a.bins)
        elif a.command == "surface":
            fig = surface(c, a.x, a.y, a.output, a.method)
        elif a.command == "waterfall":
            fig = waterfall(c, a.by, a.channel, a.orders, a.style, a.fmax)
        elif a.command == "wear-profiles":
            fig = wear_profiles(c, a.family, a.by, "depth_final_max" if a.max else "depth_final")
        elif a.command == "sobol":
            fig, tables = sobol_figure(c, a.output, a.bootstrap, a.seed, a.confidence)
            for out, r in tables.items():
                print(f"{out}:\n{r.round(4).to_string()}")
        _save(fig, a.out)
        return 0
    except (PlotError, pwcampaign.CampaignError, pwplot.PwPlotError, ValueError, KeyError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
