#!/usr/bin/env python3
"""How visible each effect of an independent corpus is in its own recording: the truth side's
bound on what any diagnosis could find.

    /usr/bin/python3 scripts/indepsim/observability.py DIR [--jobs N] [--alpha 0.01]
        [--results DIR/<outroot>/results.json] [--json DIR/observability.json]

For every effect recording of DIR (made by corpus.py; its truth.json gives the seed), the same
case is simulated twice in one batch, at the recording's own DAQ rate and time step: once with
its effect and once without (its healthy twin: same operating point, duration, sensor angle,
warm-up). Their noise-free difference Delta is the effect's signature in each channel, mean
removed (the accelerometers carry unknown DC offsets; the diagnosis compares order lines, not
means). Against the recording's white noise (sigma = noise_fraction x the channel's standard
deviation, corpus.add_noise) the signature's deflection is

    d2 = sum over samples and channels of Delta^2 / sigma^2.

d2 is the matched filter's: the statistic of a detector that knows the effect's exact waveform
is N(0, 1) without the effect and N(sqrt(d2), 1) with it. So **no test at level alpha detects the
effect with probability >= 1/2 when sqrt(d2) < z_{1-alpha}**, i.e. d2 < z_{1-alpha}^2 (5.41 at
alpha = 0.01, planetwear diagnose's default): such an effect is unobservable in that recording,
and "no missing physics" is the right answer there, not a miss. d2 is an upper bound on
visibility, not a prediction: a diagnosis does not know the waveform, compares against a model
with its own model-form error, and may need the effect to repeat between two halves.

Two figures per recording: d2_model (against a noise-free model: the calibrated comparison, the
recording's noise alone) and d2_baseline (against a healthy recording of the same operating
point: the differential comparison, sigma^2 of both recordings). Both over the rig's sensors
(the two speed encoders and the housing accelerometer, confusion.py --sensors rig) and over all
five channels.

The re-simulated effect recording is checked against the recording on disk: the CSV minus the
noise-free signal (mean removed) must have the standard deviation of the noise (ratio 1 within
a few per cent); the table prints that ratio.

With --results (a confusion.py results.json) the verdicts are printed beside d2.
"""
import argparse
import csv
import json
import math
import multiprocessing
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import corpus  # noqa: E402
import sim  # noqa: E402

CHANNELS = ("sun_speed", "carrier_speed", "acc_sp0", "acc_pr0", "housing")
RIG_CHANNELS = ("sun_speed", "carrier_speed", "housing")
CSV_COLUMN = {src: (name, factor) for (name, _, _, src, factor) in corpus.COLUMNS}


def deflection(delta, sigma):
    """Matched-filter deflection sum(delta^2) / sigma^2 of a signature delta in white noise of
    standard deviation sigma (delta's mean removed first)."""
    d = np.asarray(delta, float)
    d = d - d.mean()
    return float(np.dot(d, d) / (sigma * sigma)) if sigma > 0 else math.inf


def unobservable_below(alpha):
    """d2 under which no level-alpha test detects a known waveform with probability >= 1/2:
    z_{1-alpha}^2, z the standard normal quantile."""
    return statistics.NormalDist().inv_cdf(1.0 - alpha) ** 2


def signature(effect, twin, noise_fraction):
    """Per channel: d2 against the recording's noise alone and against both recordings' noise."""
    out = {}
    for ch in CHANNELS:
        x, y = np.asarray(effect[ch], float), np.asarray(twin[ch], float)
        n = min(x.size, y.size)
        s_rec = noise_fraction * float(np.std(x[:n]))
        s_base = noise_fraction * float(np.std(y[:n]))
        delta = x[:n] - y[:n]
        out[ch] = dict(d2_model=deflection(delta, s_rec),
                       d2_baseline=deflection(delta, math.sqrt(s_rec ** 2 + s_base ** 2)))
    return out


def noise_ratio(csv_path, effect, noise_fraction):
    """Median over channels of std(CSV - noise-free signal) / the noise's standard deviation."""
    with open(csv_path) as f:
        f.readline()  # comment line
        header = f.readline().strip().split(",")
        data = np.loadtxt(f, delimiter=",")
    ratios = []
    for ch in CHANNELS:
        name, factor = CSV_COLUMN[ch]
        col = data[:, header.index(name)] / factor
        x = np.asarray(effect[ch], float)
        n = min(col.size, x.size)
        ratios.append(float(np.std(col[:n] - x[:n]) / (noise_fraction * np.std(x[:n]))))
    return statistics.median(ratios)


def run_batch(job):
    gs = corpus.gearsets()[job["gearset"]]
    stage = sim.Stage(gs, corpus.rig_of(job["gearset"]))
    cases = []
    for e in job["entries"]:
        base = dict(e["case"])
        cases.append(sim.Case(**base, faults=sim.Faults(**e["faults"])))
        cases.append(sim.Case(**base, faults=sim.Faults()))
    t0 = time.time()
    fs, res, _ = sim.simulate_batch(stage, cases, warmup_s=job["warmup_s"], dt_factor=job["dt_factor"],
                                    fs=job["fs"], D=job["D"])
    return job["key"], fs, res, time.time() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("corpus", help="corpus directory (truth.json, <gearset>/recordings/)")
    ap.add_argument("--jobs", type=int, default=1, help="batches simulated at once (default 1)")
    ap.add_argument("--alpha", type=float, default=0.01, help="test level of the bound (default 0.01)")
    ap.add_argument("--results", help="a confusion.py results.json: its verdicts printed beside d2")
    ap.add_argument("--json", help="output file (default DIR/observability.json)")
    ap.add_argument("--only", help="comma-separated gearset/rec_NN keys")
    a = ap.parse_args(argv)
    if not 0 < a.alpha < 0.5:
        ap.error(f"--alpha must lie in (0, 0.5); got {a.alpha}")

    with open(os.path.join(a.corpus, "truth.json")) as f:
        truth = json.load(f)
    entries, _, batches, joblist = corpus.plan_entries(truth.get("quick", False), truth.get("seed", 1),
                                                        variant=truth.get("plan", "main"))
    recs = truth["recordings"]
    for e in entries:  # the corpus must be the one these entries describe
        r = recs.get(f"{e['gearset']}/{e['name']}")
        if r is None or r["noise_seed"] != e["seed"]:
            sys.exit(f"observability.py: {a.corpus} was not made by corpus.py with seed {truth.get('seed')}")
    only = set(a.only.split(",")) if a.only else None
    rate = {(b["gearset"], b["cls"]): (b["fs_Hz"], b["dt_s"]) for b in truth["batches"]}
    jobs = []
    for j in joblist:
        g, cls = j["name"]
        picked = [(i, ent) for i, ent in zip(j["idx"], j["entries"])
                  if entries[i]["role"] == "effect"
                  and (only is None or f"{entries[i]['gearset']}/{entries[i]['name']}" in only)]
        if not picked:
            continue
        fs, dt = rate[(g, cls)]
        jobs.append(dict(key=(g, cls), gearset=g, warmup_s=j["warmup_s"], dt_factor=j["dt_factor"], fs=fs,
                         D=int(round(1.0 / (fs * dt))), entries=[ent for _, ent in picked],
                         idx=[i for i, _ in picked]))
    verdicts = {}
    if a.results:
        with open(a.results) as f:
            verdicts = {r["key"]: r for r in json.load(f)["rows"]}

    bound = unobservable_below(a.alpha)
    t0 = time.time()
    rows = []
    results = {}
    if a.jobs > 1 and len(jobs) > 1:
        with multiprocessing.Pool(min(a.jobs, len(jobs))) as pool:
            for key, fs, res, wall in pool.imap_unordered(run_batch, jobs):
                results[key] = (fs, res)
                print(f"  batch {key}: {len(res) // 2} recordings and their twins, {wall:.0f} s", flush=True)
    else:
        for j in jobs:
            key, fs, res, wall = run_batch(j)
            results[key] = (fs, res)
            print(f"  batch {key}: {len(res) // 2} recordings and their twins, {wall:.0f} s", flush=True)
    for j in jobs:
        fs, res = results[j["key"]]
        for k, i in enumerate(j["idx"]):
            e = entries[i]
            key = f"{e['gearset']}/{e['name']}"
            nf = sim.Case(e["rpm"], e["W"], e["duration_s"]).noise_fraction
            sig = signature(res[2 * k], res[2 * k + 1], nf)
            row = dict(key=key, effect=e["effect"], parameters=recs[key]["parameters"],
                       operating_point=e["op"], rpm=e["rpm"], W=e["W"], duration_s=e["duration_s"],
                       d2_model_rig=sum(sig[c]["d2_model"] for c in RIG_CHANNELS),
                       d2_baseline_rig=sum(sig[c]["d2_baseline"] for c in RIG_CHANNELS),
                       d2_model_all=sum(sig[c]["d2_model"] for c in CHANNELS),
                       d2_baseline_all=sum(sig[c]["d2_baseline"] for c in CHANNELS),
                       channels=sig,
                       noise_ratio=noise_ratio(os.path.join(a.corpus, recs[key]["csv"]), res[2 * k], nf))
            row["observable_rig_baseline"] = row["d2_baseline_rig"] >= bound
            row["observable_rig_model"] = row["d2_model_rig"] >= bound
            row["observable_any"] = row["d2_model_all"] >= bound  # the most generous: every channel, no baseline noise
            v = verdicts.get(key)
            if v:
                row["reported"], row["outcome"] = v["reported"], v["outcome"]
            rows.append(row)
    rows.sort(key=lambda r: r["key"])

    out = a.json or os.path.join(a.corpus, "observability.json")
    with open(out + ".tmp", "w") as f:
        json.dump(dict(alpha=a.alpha, unobservable_below_d2=bound, rows=rows,
                       wall_s=round(time.time() - t0, 1)), f, indent=1)
    os.replace(out + ".tmp", out)
    with open(os.path.splitext(out)[0] + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["key", "effect", "op", "duration_s", "d2_baseline_rig", "d2_model_rig", "d2_baseline_all",
                    "observable_rig_baseline", "noise_ratio", "reported", "outcome"])
        for r in rows:
            w.writerow([r["key"], r["effect"], r["operating_point"], r["duration_s"], f"{r['d2_baseline_rig']:.4g}",
                        f"{r['d2_model_rig']:.4g}", f"{r['d2_baseline_all']:.4g}", r["observable_rig_baseline"],
                        f"{r['noise_ratio']:.3f}", r.get("reported", ""), r.get("outcome", "")])

    print(f"\nunobservable below d2 = z_(1-{a.alpha})^2 = {bound:.2f} (matched filter, detection probability 1/2)")
    print(f"{'recording':16} {'effect':22} {'op':3} {'s':>4} {'d2 diff rig':>12} {'d2 model rig':>13} "
          f"{'d2 diff all':>12} {'noise':>6}  verdict")
    for r in rows:
        mark = "" if r["observable_rig_baseline"] else "  (unobservable)"
        print(f"{r['key']:16} {r['effect']:22} {r['operating_point']:3} {r['duration_s']:4.0f} "
              f"{r['d2_baseline_rig']:12.4g} {r['d2_model_rig']:13.4g} {r['d2_baseline_all']:12.4g} "
              f"{r['noise_ratio']:6.3f}  {r.get('reported', '')}{mark}")
    n_obs = sum(r["observable_rig_baseline"] for r in rows)
    print(f"\n{n_obs} of {len(rows)} effect recordings observable with the rig's sensors against a healthy "
          f"recording; written {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
