#!/usr/bin/env python3
"""Observability of the effects of an indepsim2 corpus: what any diagnosis could see.

    /usr/bin/python3 scripts/indepsim2/observability.py DIR [--only rigA3] [--max-duration S] [--json PATH]

For every effect recording of DIR (truth.json, written by corpus.py), the recording is simulated again
noise-free, WITH its effect and WITHOUT it (its healthy twin: the same operating point, start time,
duration, sensor angle, DAQ rate and sensor chain). The noise-free difference Delta of each recorded
channel (mean removed per channel: the accelerometer carries an unknown DC offset) is measured against
that recording's white noise, sigma_ch = 5 % of the channel's standard deviation about its mean (what
corpus.py added):

    d2_ch = sum_t Delta_ch(t)^2 / sigma_ch^2,      d2 = d2_sun_speed + d2_carrier_speed + d2_housing

d2 is the matched filter's deflection: a detector that knew the waveform exactly would see N(0, 1)
without the effect and N(sqrt(d2), 1) with it. Below d2 = z^2 (z = z_{1-alpha/2}, alpha = 0.01,
two-sided: 2.576^2 = 6.63) no test detects the effect with probability >= 1/2: the effect is
"unobservable" and "no missing physics" is the right answer for it. A bound, not a prediction.
d2_baseline_* is the same against a healthy *recording* (a differential comparison): sigma^2 is the
sum of the effect recording's and the operating point's baseline recording's noise variances.
The channels are the ones a diagnosis uses (the rig's sensors): sun speed, carrier speed, housing
accelerometer; so "rig" and "all" are the same here (the keys are kept for scripts/indepsim/confusion.py).

Simulation settings: the corpus's own, through sim.py's Batch and sim.py's sensor functions:
* gear set: DIR/<gearset>/gearset.toml; rig constants sim.RIG_DEFAULTS; sensor housing angle, operating
  points and effect cases from corpus.py (GEARSETS, OPS, case_for); start time, duration, noise
  fraction from truth.json;
* Batch.integrate: DOP853, rtol = 1e-6 (corpus.py's default, the corpus log's setting), atol_scale
  1e-3 (atol 1e-9 m / 1e-8 rad, 1e-5 m/s / 1e-4 rad/s), 50 ms chunks, 40 kHz model output (oversample 4),
  static start at t = 0, first step 2e-6 s;
* sensors: 10 kHz DAQ, 50 ms filter pre-roll, encoders (2^23 counts/rev, 1 kHz low-pass), housing
  accelerometer (rigid ring + rim deflection, 3.5 kHz mount resonance, 4 kHz anti-alias) with the
  recording's housing_gain_scale (the twin: 1).
The only difference from corpus.py/sim.simulate_batch is the batching: per gear set ONE batch holds each
distinct mechanical case once (every effect case, and the healthy case of each operating point, which
is the twin of all effects at that point, of the baselines, controls and of sensor_transfer_path, whose
mechanics are healthy); each recording is then a window of its column. The adaptive step sequence is
shared by all columns, so the integrator's error is largely common to an effect and its twin. The
post-processing (sensor chain) of sim.simulate_batch is repeated here (simulate_windows) with a
column index per window; nothing in sim.py or corpus.py is changed. Because the corpus batch had
other columns (12 recordings) the steps differ from the corpus's: the check against the files on disk
(noise_ratio: std(CSV - noise-free)/sigma, ideally 1; repro: rms of CSV - noise-free - the seeded
noise, in sigma) measures how well the re-simulation reproduces each recording.
Diagnostic only (not used for the verdict): d2_model_unquantised, the same d2 with the encoders' angle
quantisation removed (2^43 instead of 2^23 counts/rev). The recorded speed channels are partly the
encoders' quantisation pattern (one count = 0.0075 rad/s per sample, comparable to the carrier speed's
fluctuation), which any change of the trajectory by a fraction of a count (7.5e-7 rad) rearranges; that
part of d2 is in the recordings but no model-based diagnosis could predict it.
Writes DIR/observability.json (layout of scripts/indepsim/observability.py's) and prints a table.
Run time: about 20 min on one core for the seed-21 corpus (24 recordings, 16 effects).
"""
import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse
import json
import sys
import time

import numpy as np
from scipy.stats import norm

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import corpus  # noqa: E402
import sim  # noqa: E402

CHANNELS = ("sun_speed", "carrier_speed", "housing")
CLEAN_KEY = {"sun_speed": "w_s", "carrier_speed": "w_c", "housing": "acc"}
RIG = CHANNELS                      # the channels the diagnosis uses
ALPHA = 0.01
UNQ = 2 ** 20                       # encoder interpolation factor for the unquantised diagnostic


def simulate_windows(gs, cases, windows, fs=10000.0, oversample=4, rig=None, rtol=1e-6, log=print):
    """One Batch with one column per case; windows: list of dicts {col, start_s, duration_s,
    housing_gain_scale, sensor_angle_housing_deg}. Returns the noise-free channels of each window
    (w_s, w_c in rad/s, acc in m/s^2), theta_c0, and the batch. The integration and the sensor chain
    are sim.simulate_batch's own (sim.integrate_stage, sim.sensor_window), with a column per window."""
    bt = sim.Batch(gs, cases, rig=rig)
    rigp = bt.rig
    t, cat, frp = sim.integrate_stage(bt, windows, fs, oversample, rtol, log)
    rim = sim.rim_parameters(bt)
    out = []
    for r in windows:
        sw = sim.sensor_window(bt, t, cat, frp, rim, r["col"], r, fs, oversample)
        w_s, w_c, acc, nout, k0 = sw["w_s"], sw["w_c"], sw["acc"], sw["nout"], sw["k0"]
        # diagnostic only: the same encoders without their angle quantisation (2^43 counts/rev)
        w_su, _ = sim.encoder_speed(sw["ths_s"], fs, rigp["encoder_lines"], rigp["encoder_interp"] * UNQ,
                                    rigp["encoder_lp_Hz"], zi_value=sw["Om_s"])
        w_cu, _ = sim.encoder_speed(sw["thc_s"], fs, rigp["encoder_lines"], rigp["encoder_interp"] * UNQ,
                                    rigp["encoder_lp_Hz"], zi_value=sw["Om_c"])
        w_su = w_su[k0:k0 + nout]
        w_cu = w_cu[k0:k0 + nout]
        if len(acc) != nout or len(w_s) != nout:
            raise RuntimeError(f"window {r} is short: {len(acc)}, {len(w_s)} of {nout} samples")
        out.append(dict(w_s=w_s, w_c=w_c, acc=acc, w_s_u=w_su, w_c_u=w_cu, acc_u=acc,
                        theta_c0=float(sw["theta_c0"]), sensor_angle_deg=sw["sensor_angle_deg"]))
    return out, bt


def read_csv_channels(path):
    d = np.loadtxt(path, delimiter=",", comments="#", skiprows=2)
    return {"w_s": d[:, 1] * sim.TWO_PI / 60.0, "w_c": d[:, 2], "acc": d[:, 3] * sim.G0}


def file_check(csvd, clean, rec):
    """Compares the recording on disk with the re-simulated noise-free channels. noise_ratio:
    std(CSV - clean)/sigma (1 if the re-simulation is exact); repro: rms of CSV - clean - the seeded
    noise (least-squares scale, plus a constant on the accelerometer for its DC offset), in sigma."""
    n = len(clean["w_s"])
    n_full = int(round(rec["duration_s"] * rec["fs_Hz"]))
    rng = np.random.default_rng(rec["noise_seed"])
    z = {k: rng.standard_normal(n_full)[:n] for k in ("w_s", "w_c", "acc")}     # corpus order: w_s, w_c, acc
    res = {}
    for ch in CHANNELS:
        k = CLEAN_KEY[ch]
        x = csvd[k][:n]
        sig = rec["noise_fraction"] * np.std(clean[k])
        r = x - clean[k]
        A = np.column_stack([z[k], np.ones(n)]) if k == "acc" else z[k][:, None]
        coef, *_ = np.linalg.lstsq(A, r, rcond=None)
        rem = r - A @ coef
        res[ch] = dict(noise_ratio=float(np.std(r) / sig), repro=float(np.sqrt(np.mean(rem ** 2)) / sig),
                       noise_scale=float(coef[0] / sig))
    return res


def d2_of(eff, twin, base_clean, frac):
    ch = {}
    for c in CHANNELS:
        k = CLEAN_KEY[c]
        dx = eff[k] - twin[k]
        s2 = (frac * np.std(eff[k])) ** 2
        s2b = s2 + (frac * np.std(base_clean[k])) ** 2
        dxm = dx - dx.mean()
        du = eff[k + "_u"] - twin[k + "_u"]
        du = du - du.mean()
        ch[c] = dict(d2_model=float(np.sum(dxm ** 2) / s2), d2_baseline=float(np.sum(dxm ** 2) / s2b),
                     d2_model_with_mean=float(np.sum(dx ** 2) / s2),
                     d2_model_unquantised=float(np.sum(du ** 2) / s2),
                     sigma=float(np.sqrt(s2)), delta_rms=float(np.std(dx)))
    return ch


def case_key(case):
    return repr(sorted(case.items()))


def run_gearset(d, truth, g, max_duration=None, log=print):
    spec = corpus.GEARSETS[g]
    gs = sim.read_gearset(os.path.join(d, g, "gearset.toml"))
    recs = {k: r for k, r in truth["recordings"].items() if r["gearset"] == g}
    cases, colof = [], {}

    def col(case):
        kk = case_key(case)
        if kk not in colof:
            colof[kk] = len(cases)
            cases.append(case)
        return colof[kk]

    windows, wkeys = [], []
    for k in sorted(recs):
        r = recs[k]
        rpm, power = corpus.OPS[g][r["operating_point"]]
        dur = r["duration_s"] if max_duration is None else min(r["duration_s"], max_duration)
        base = dict(start_s=r["sim_start_s"], duration_s=dur, sensor_angle_housing_deg=spec["sensor_angle_housing_deg"])
        eff_case = corpus.case_for(r["effect"], r["parameters"], rpm, power)
        windows.append(dict(base, col=col(eff_case), housing_gain_scale=r["parameters"].get("housing_gain_scale", 1.0)))
        wkeys.append((k, "rec"))
        if r["role"] == "effect":
            windows.append(dict(base, col=col(corpus.case_for("none", {}, rpm, power)), housing_gain_scale=1.0))
            wkeys.append((k, "twin"))
    log(f"{g}: {len(recs)} recordings, {len(cases)} distinct cases in one batch, {len(windows)} windows")
    t0 = time.time()
    outs, bt = simulate_windows(gs, cases, windows, fs=corpus.FS, rtol=1e-6, log=log)
    wall = time.time() - t0
    W = {wk: o for wk, o in zip(wkeys, outs)}
    checks = {}
    for k, r in recs.items():
        csvd = read_csv_channels(os.path.join(d, r["csv"]))
        checks[k] = file_check(csvd, W[(k, "rec")], r)
        checks[k]["carrier_angle_at_t0_rad"] = (W[(k, "rec")]["theta_c0"], r["carrier_angle_at_t0_rad"])
    rows = []
    for k in sorted(recs):
        r = recs[k]
        if r["role"] != "effect":
            continue
        base_clean = W[(r["baseline"], "rec")]
        ch = d2_of(W[(k, "rec")], W[(k, "twin")], base_clean, r["noise_fraction"])
        for c in CHANNELS:
            ch[c].update({kk: round(v, 4) for kk, v in checks[k][c].items()})
        rows.append(dict(key=k, effect=r["effect"],
                         parameters={kk: v for kk, v in r["parameters"].items()},
                         operating_point=r["operating_point"], rpm=r["input_speed_rpm"], W=r["input_power_W"],
                         duration_s=r["duration_s"] if max_duration is None else min(r["duration_s"], max_duration),
                         d2_model_rig=sum(ch[c]["d2_model"] for c in RIG),
                         d2_baseline_rig=sum(ch[c]["d2_baseline"] for c in RIG),
                         d2_model_all=sum(ch[c]["d2_model"] for c in CHANNELS),
                         d2_baseline_all=sum(ch[c]["d2_baseline"] for c in CHANNELS),
                         d2_model_unquantised_all=sum(ch[c]["d2_model_unquantised"] for c in CHANNELS),
                         channels=ch,
                         noise_ratio=float(np.mean([checks[k][c]["noise_ratio"] for c in CHANNELS])),
                         repro_max_sigma=float(max(checks[k][c]["repro"] for c in CHANNELS)),
                         case_column=windows[wkeys.index((k, "rec"))]["col"],
                         twin_column=windows[wkeys.index((k, "twin"))]["col"]))
    other = {k: dict(role=recs[k]["role"], noise_ratio={c: round(checks[k][c]["noise_ratio"], 4) for c in CHANNELS},
                     repro={c: round(checks[k][c]["repro"], 4) for c in CHANNELS})
             for k in sorted(recs) if recs[k]["role"] != "effect"}
    return rows, other, dict(cases=len(cases), windows=len(windows), rhs_calls=bt.nfev, wall_s=round(wall, 1))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("corpus")
    ap.add_argument("--only", default="", help="comma-separated gear sets (default: all)")
    ap.add_argument("--max-duration", type=float, default=None,
                    help="truncate every window (smoke test; d2 then not that of the recordings)")
    ap.add_argument("--json", default=None, help="output path (default DIR/observability.json)")
    a = ap.parse_args(argv)
    t_start = time.time()
    with open(os.path.join(a.corpus, "truth.json")) as f:
        truth = json.load(f)
    gsets = sorted({r["gearset"] for r in truth["recordings"].values()})
    if a.only:
        gsets = [g for g in gsets if g in a.only.split(",")]
    z = float(norm.ppf(1.0 - ALPHA / 2.0))
    thr = z * z
    rows, others, runs = [], {}, {}
    for g in gsets:
        rw, ot, info = run_gearset(a.corpus, truth, g, a.max_duration, log=lambda s: print(s, flush=True))
        rows += rw
        others.update(ot)
        runs[g] = info
        print(f"{g}: {info}", flush=True)
    for r in rows:
        r["observable_rig_baseline"] = bool(r["d2_baseline_rig"] >= thr)
        r["observable_rig_model"] = bool(r["d2_model_rig"] >= thr)
        r["observable_any"] = bool(max(r["d2_model_all"], r["d2_baseline_all"], r["d2_model_rig"],
                                       r["d2_baseline_rig"]) >= thr)
    out = dict(alpha=ALPHA, test="two-sided", z=z, unobservable_below_d2=thr, rows=rows,
               channels_used=list(RIG), noise="white, 5 % of each channel's std about its mean (truth.json "
               "noise_fraction); Delta mean removed per channel",
               settings="corpus.py/sim.py: DOP853 rtol 1e-6 atol_scale 1e-3, 50 ms chunks, 40 kHz model output, "
                        "10 kHz DAQ; one batch per gear set of the distinct cases (effects + healthy per op)",
               max_duration=a.max_duration, batches=runs, other_recordings_check=others,
               wall_s=round(time.time() - t_start, 1))
    path = a.json or os.path.join(a.corpus, "observability.json")
    with open(path + ".tmp", "w") as f:
        json.dump(out, f, indent=1)
    os.replace(path + ".tmp", path)
    print()
    print(f"d2 against a noise-free model (mean removed), unobservable below z^2 = {thr:.2f} (alpha {ALPHA}, two-sided)")
    hdr = (f"{'key':14s} {'effect':22s} {'op':2s} {'d2 total':>10s} {'sun_speed':>10s} {'carrier':>10s} "
           f"{'housing':>10s} {'d2 vs base':>10s} {'obs':>4s} {'noise_r':>7s} {'repro':>6s} {'unq sun':>9s} {'unq carr':>9s}")
    print(hdr)
    for r in rows:
        c = r["channels"]
        print(f"{r['key']:14s} {r['effect']:22s} {r['operating_point']:2s} {r['d2_model_all']:10.4g} "
              f"{c['sun_speed']['d2_model']:10.4g} {c['carrier_speed']['d2_model']:10.4g} "
              f"{c['housing']['d2_model']:10.4g} {r['d2_baseline_all']:10.4g} "
              f"{'yes' if r['d2_model_all'] >= thr else 'NO':>4s} {r['noise_ratio']:7.4f} {r['repro_max_sigma']:6.3f} "
              f"{c['sun_speed']['d2_model_unquantised']:9.4g} {c['carrier_speed']['d2_model_unquantised']:9.4g}")
    print("other recordings (noise_ratio / repro per channel):")
    for k, o in others.items():
        print(f"  {k} {o['role']}: " + ", ".join(f"{c} {o['noise_ratio'][c]:.4f}/{o['repro'][c]:.3f}" for c in CHANNELS))
    print(f"wrote {path} in {out['wall_s']} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
