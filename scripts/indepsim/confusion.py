#!/usr/bin/env python3
"""Runs `planetwear diagnose` on an indepsim corpus and scores it against truth.json.

    /usr/bin/python3 scripts/indepsim/confusion.py DIR --planetwear PATH/planetwear
        [--jobs N] [--threads 1] [--include-held-out] [--calibration-per-rig | --calibrate [--rig-elements E,...] [--ring-body] | --differential]
        [--timeout S]
        [--only NAME,...] [--gearset G] [--sensors all|rig|speeds] [--dry-run] [--check-reader]

For each recording DIR/<gearset>/recordings/rec_NN.csv (sidecar rec_NN.json) it runs
    planetwear diagnose -c DIR/<gearset>/gearset.toml -r rec.csv --meta rec.json
                        -o DIR/diagnosis/<gearset>/rec_NN --threads T --no-plots -q
unless DIR/diagnosis/<gearset>/rec_NN/report.json exists (resumable), reads the report
(docs/diagnose.md section 6), prints a confusion matrix truth effect x reported verdict
(candidate name, "class:a|b" for a class finding, "none" for no_missing_physics, "unexplained",
"refused", "failed") and the counts: named right (of which as a class: the truth is a member of
the class named), controls clean, confident wrong names, refusals, and of the effects left
"unexplained" how many the report located in a line family the true effect's candidate lives in
(`planetwear candidates --format json`: the tool's own table; the report's
location.screened_family). Writes
DIR/diagnosis/results.csv and results.json. Held-out recordings (truth "held_out") are
skipped unless --include-held-out. With DIR/observability.json (observability.py), an effect
that no test could see in its recording is scored apart: "no missing physics" is right there
(unobservable_clean), a name counts as a confident wrong name. So is, from truth.json alone, a
backlash change in a recording where no flank separated (its diagnostics' separation fraction 0:
the larger play is never traversed, the run is the healthy rig's).

--calibration-per-rig: the healthy baseline of each operating point is diagnosed first;
the nuisance values it recalibrated (the report's --set overrides of stiffness.scale,
contact.mesh_damping_ratio, sensor.*) are passed as --set to the other recordings of
that operating point (outputs under DIR/diagnosis_cal/).

--calibrate: `planetwear calibrate` on each gear set's healthy baselines (held-out ones never),
written to DIR/diagnosis_calibrated/<gearset>/calibration.toml; every other recording is then
diagnosed with --calibration (docs/diagnose.md section 6a). With --ring-body, `calibrate
--ring-body` (section 6a item 12; outputs under DIR/diagnosis_calibrated_..._ringbody/).
Each row also carries the report's coverage_gap share (section 6a item 13: the part of the
located excess at frequencies no healthy line tested), and the summary counts the unexplained
effects with more than half of it there.

--differential: every recording that is not itself a baseline is diagnosed against its
operating point's healthy baseline (truth.json "baseline"; also when that baseline is held out:
it is the rig's reference run), `--baseline B.csv --baseline-meta B.json` (docs/diagnose.md
section 6b); outputs under DIR/diagnosis_diff/.

--sensors rig: the sensor set a test rig usually has, the two speed encoders and the housing
accelerometer; the line-of-action mesh accelerations (which need instrumented gears or
telemetry) are left out. Each recording (and baseline) is read through a copy of its sidecar
without those columns, written under the output directory; outputs go to <outroot>_rigsensors/.
--sensors speeds: the two speed encoders alone (a rig without an accelerometer; or, beside a run
with rig, what the housing channel's transfer-path model adds or costs); <outroot>_speedssensors/.
"""
import argparse
import concurrent.futures as cf
import csv
import json
import os
import subprocess
import sys
import time

NUISANCE_PREFIXES = ("stiffness.scale", "contact.mesh_damping_ratio", "sensor.")
# Quantities a test rig rarely measures (instrumented gears, slip rings or telemetry).
MESH_QUANTITIES = ("mesh_acceleration_sun_planet", "mesh_acceleration_planet_ring")
SENSOR_SETS = ("all", "rig", "speeds")
# quantities each reduced sensor set leaves out
LEFT_OUT = {"rig": ("mesh_acceleration_sun_planet", "mesh_acceleration_planet_ring"),
            "speeds": ("mesh_acceleration_sun_planet", "mesh_acceleration_planet_ring", "housing_acceleration")}


def sidecar(corpus, csv_rel, outroot, sensors):
    """The sidecar a recording is read through: its own for --sensors all; for rig (speeds), a copy
    under DIR/<outroot>/sidecars/ without the mesh-acceleration columns (and the housing accelerometer)."""
    own = os.path.join(corpus, os.path.splitext(csv_rel)[0] + ".json")
    if sensors == "all":
        return own
    with open(own) as f:
        meta = json.load(f)
    meta["columns"] = {k: v for k, v in meta["columns"].items() if v.get("quantity") not in LEFT_OUT[sensors]}
    path = os.path.join(corpus, outroot, "sidecars", os.path.splitext(csv_rel)[0] + ".json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(meta, f, indent=1)
    return path


def find_key(obj, names):
    """First value of any key in names, searched depth-first."""
    if isinstance(obj, dict):
        for k in names:
            if k in obj:
                return obj[k]
        for v in obj.values():
            r = find_key(v, names)
            if r is not None:
                return r
    elif isinstance(obj, list):
        for v in obj:
            r = find_key(v, names)
            if r is not None:
                return r
    return None


def read_report(path):
    """-> (verdict label, raw verdict, summary, overrides list)."""
    with open(path) as f:
        rep = json.load(f)
    verdict = rep.get("verdict", "")
    summary = rep.get("summary", "")
    label = verdict
    if verdict == "no_missing_physics":
        label = "none"
    elif verdict == "unexplained_residual":
        label = "unexplained"
    elif verdict == "missing_physics_found":
        mp = rep.get("missing_physics")
        name = None
        if isinstance(mp, str):
            name = mp
        elif isinstance(mp, dict):
            name = mp.get("candidate") or mp.get("name") or mp.get("physics")
        if name is None:
            name = find_key(rep, ("winner", "candidate", "missing_physics_name"))
        label = str(name) if name else "missing_physics(?)"
        # A class finding (docs/diagnose.md section 5, "Class findings") names a class of candidates
        # the data do not tell apart: "class:member1|member2|..." over the members the report
        # names and every physics the class stands for ("covers": tooth_contact_change covers a
        # stiffness level too), so that scoring can check the truth's membership and the table
        # keeps class names apart from single names.
        fc = rep.get("finding_class")
        if isinstance(fc, dict) and fc.get("members"):
            label = "class:" + "|".join(sorted(set(fc["members"]) | set(fc.get("covers") or [])))
    # the nuisance-only model's --set overrides (report.json "nuisance" -> "overrides")
    nu = rep.get("nuisance")
    ov = nu.get("overrides") if isinstance(nu, dict) else None
    if ov is None:
        ov = find_key(rep, ("overrides",))
    overrides = []
    if isinstance(ov, list):
        overrides = [str(x) for x in ov if isinstance(x, str) and "=" in x]
    elif isinstance(ov, dict):
        overrides = [f"{k}={v}" for k, v in ov.items()]
    return label, verdict, summary, overrides


# The clearance is traversed only where a flank separates: a larger backlash changes nothing of a
# run in which no mesh ever left its drive flank. The independent simulators record that fraction
# of their recorded steps in truth.json's diagnostics (indepsim3: of the recorded time, indepsim4:
# of the recorded steps; indepsim3 also says so in the recording's notes).
SEPARATION_KEYS = ("fraction_of_time_a_mesh_separated", "fraction_of_steps_a_mesh_in_backlash")


def inert_by_truth(rec):
    """True when the generator's own record proves the effect changed nothing in this recording: a
    backlash change where no flank separated in the recorded window (the play is never traversed,
    so the equations of the run are those of the healthy rig: no test can see it)."""
    if rec.get("role") != "effect" or rec.get("effect") != "backlash":
        return False
    diag = rec.get("diagnostics") or {}
    fractions = [diag[k] for k in SEPARATION_KEYS if k in diag]
    return bool(fractions) and all(f == 0 for f in fractions)


def score(label, truth_effect, unobservable=False):
    """The outcome of one diagnosis: its reported label against the truth's effect ("none" for a
    control); unobservable: the effect leaves no signature any test could see (observability.py)."""
    if label in ("refused", "failed"):
        return label
    if truth_effect == "none":
        return {"none": "control_clean", "unexplained": "control_unexplained"}.get(label, "control_false_name")
    if unobservable:
        return {"none": "unobservable_clean", "unexplained": "unobservable_unexplained"}.get(label,
                                                                                           "unobservable_named")
    if label == truth_effect:
        return "named_right"
    if label.startswith("class:") and truth_effect in label[len("class:"):].split("|"):
        return "named_right_as_class"
    return {"none": "missed", "unexplained": "unexplained"}.get(label, "wrong_name")


def candidate_families(exe):
    """{candidate name: [line families]} from `planetwear candidates --format json` (the tool's own
    table, so that a located family is mapped as the tool maps it); {} when the binary has no such
    command (then no located_right figure is printed)."""
    try:
        p = subprocess.run([exe, "candidates", "--format", "json"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return {}
    if p.returncode != 0:
        return {}
    return {r["name"]: r["families"] for r in json.loads(p.stdout)}


def located_family(report_path):
    """The line family a report located by the candidates' own signatures (report.json
    location.screened_family), or None (not located, no report)."""
    try:
        with open(report_path) as f:
            loc = json.load(f).get("location") or {}
    except (OSError, ValueError):
        return None
    return loc.get("screened_family")


def coverage_gap_share(report_path):
    """The share of a report's located excess outside the frequencies its calibration's (or
    baseline's) healthy lines tested (report.json coverage_gap.share), or None (not known)."""
    try:
        with open(report_path) as f:
            gap = json.load(f).get("coverage_gap")
    except (OSError, ValueError):
        return None
    return gap.get("share") if isinstance(gap, dict) else None


def run_one(exe, corpus, key, rec, outroot, threads, timeout, extra_args=(), sensors="all"):
    g, name = rec["gearset"], rec["name"]
    out = os.path.join(corpus, outroot, g, name)
    rj = os.path.join(out, "report.json")
    refused = os.path.join(out, "refused.txt")
    if os.path.exists(rj):
        return key, "cached", read_report(rj), 0.0, ""
    if os.path.exists(refused):
        with open(refused) as f:
            return key, "cached-refused", ("refused", "refused", f.read().strip(), []), 0.0, ""
    os.makedirs(out, exist_ok=True)
    csvp = os.path.join(corpus, rec["csv"])
    cmd = [exe, "diagnose", "-c", os.path.join(corpus, g, "gearset.toml"), "-r", csvp,
           "--meta", sidecar(corpus, rec["csv"], outroot, sensors), "-o", out, "--threads", str(threads), "--no-plots", "-q"]
    cmd += list(extra_args)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return key, "timeout", ("failed", "timeout", f"timeout after {timeout} s", []), time.time() - t0, ""
    dt = time.time() - t0
    if p.returncode == 0 and os.path.exists(rj):
        return key, "ran", read_report(rj), dt, p.stdout.strip()
    msg = (p.stderr.strip().splitlines() or ["?"])[-1]
    if p.returncode == 1:      # pw::InputError: the reader refused the recording
        with open(refused, "w") as f:
            f.write(msg + "\n")
        return key, "refused", ("refused", "refused", msg, []), dt, ""
    return key, "failed", ("failed", f"exit {p.returncode}", msg, []), dt, ""


def check_reader(exe, corpus, rec, timeout=300):
    """Starts `planetwear diagnose` (without -q) only until the recording has been read and
    order-analysed (the "baseline model" progress line), then stops that process (by its pid).
    -> ("accepted" | "refused" | "failed", message). No diagnosis is run."""
    g = rec["gearset"]
    csvp = os.path.join(corpus, rec["csv"])
    out = os.path.join(corpus, "reader_check", g, rec["name"])
    os.makedirs(out, exist_ok=True)
    cmd = [exe, "diagnose", "-c", os.path.join(corpus, g, "gearset.toml"), "-r", csvp,
           "--meta", os.path.splitext(csvp)[0] + ".json", "-o", out, "--threads", "1", "--no-plots"]
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    t0 = time.time()
    lines = []
    try:
        for line in p.stderr:
            lines.append(line.strip())
            if "baseline model" in line:
                p.terminate()
                p.wait(timeout=30)
                return "accepted", lines[-1]
            if time.time() - t0 > timeout:
                p.terminate()
                p.wait(timeout=30)
                return "failed", "reader check timed out"
        rc = p.wait(timeout=30)
    finally:
        if p.poll() is None:
            p.kill()
    msg = lines[-1] if lines else ""
    return ("refused" if rc == 1 else "failed"), msg


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("corpus")
    ap.add_argument("--planetwear", required=True)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--include-held-out", action="store_true")
    ap.add_argument("--calibration-per-rig", action="store_true")
    ap.add_argument("--calibrate", action="store_true",
                    help="planetwear calibrate on each gear set's (non-held-out) baselines, then diagnose the other "
                         "recordings with --calibration (outputs under DIR/diagnosis_calibrated/)")
    ap.add_argument("--rig-elements", default="",
                    help="with --calibrate: passed to planetwear calibrate --rig-elements (e.g. "
                         "encoder_bandwidth,motor_inertia,load_inertia); outputs under "
                         "DIR/diagnosis_calibrated_<elements>/ so that runs with other rig elements are kept apart")
    ap.add_argument("--ring-body", action="store_true",
                    help="with --calibrate: passed to planetwear calibrate (the lateral-torsional ring body as a "
                         "housing path); outputs under DIR/diagnosis_calibrated_..._ringbody/")
    ap.add_argument("--differential", action="store_true",
                    help="diagnose each recording against its operating point's healthy baseline (--baseline); "
                         "outputs under DIR/diagnosis_diff/")
    ap.add_argument("--baseline-transfer", choices=("additive", "line_ratio"), default="additive",
                    help="with --differential: planetwear diagnose --baseline-transfer (docs/diagnose.md section 6b "
                         "item 9); line_ratio writes under DIR/diagnosis_diff_ratio*/")
    ap.add_argument("--timeout", type=float, default=3 * 3600)
    ap.add_argument("--only", default="", help="comma-separated gearset/rec_NN keys")
    ap.add_argument("--gearset", default="")
    ap.add_argument("--sensors", choices=SENSOR_SETS, default="all",
                    help="all: every column of the sidecar; rig: encoders and housing only")
    ap.add_argument("--dry-run", action="store_true", help="score existing reports only, run nothing")
    ap.add_argument("--check-reader", action="store_true",
                    help="only check that planetwear's reader accepts each recording (stops each run after "
                         "reading; no diagnosis); writes reader_check.json")
    a = ap.parse_args(argv)
    with open(os.path.join(a.corpus, "truth.json")) as f:
        truth = json.load(f)
    recs = truth["recordings"]
    keys = sorted(k for k, r in recs.items()
                  if (a.include_held_out or not r.get("held_out")) and (not a.gearset or r["gearset"] == a.gearset)
                  and (not a.only or k in a.only.split(",")))
    if a.check_reader:
        res = {}
        for i, k in enumerate(keys):
            how, msg = check_reader(a.planetwear, a.corpus, recs[k])
            expect = "refused" if recs[k].get("reader_should_refuse") else "accepted"
            res[k] = dict(result=how, expected=expect, message=msg)
            print(f"[{i + 1}/{len(keys)}] {k}: {how} (expected {expect}) {msg if how != 'accepted' else ''}",
                  flush=True)
        with open(os.path.join(a.corpus, "reader_check.json"), "w") as f:
            json.dump(res, f, indent=1)
        bad = [k for k, v in res.items() if v["result"] != v["expected"]]
        print(f"{len(keys) - len(bad)}/{len(keys)} as expected" + (f"; unexpected: {bad}" if bad else ""))
        return 1 if bad else 0
    if sum([a.calibrate, a.calibration_per_rig, a.differential]) > 1:
        ap.error("--calibrate, --calibration-per-rig and --differential are alternatives")
    if a.rig_elements and not a.calibrate:
        ap.error("--rig-elements needs --calibrate")
    if a.ring_body and not a.calibrate:
        ap.error("--ring-body needs --calibrate")
    outroot = ("diagnosis_calibrated" if a.calibrate else "diagnosis_cal" if a.calibration_per_rig
               else "diagnosis_diff" if a.differential else "diagnosis")
    if a.baseline_transfer != "additive":
        if not a.differential:
            ap.error("--baseline-transfer needs --differential")
        outroot += "_ratio"
    if a.rig_elements:
        outroot += "_" + a.rig_elements.replace(",", "+")
    if a.ring_body:
        outroot += "_ringbody"
    if a.sensors != "all":
        outroot += "_" + a.sensors + "sensors"
    results = {}
    t_start = time.time()
    done_times = []

    def progress(key, how, res, dt):
        results[key] = (how, res, dt)
        if how == "ran" or how in ("refused", "failed", "timeout"):
            done_times.append(dt)
        left = len(keys) - len(results)
        eta = ""
        if done_times:
            per = sum(done_times) / len(done_times) / max(1, a.jobs)
            eta = f", ETA {per * left / 60:.0f} min"
        print(f"[{len(results)}/{len(keys)}] {key}: truth {recs[key]['effect']} -> {res[0]} ({how}, {dt:.0f} s){eta}",
              flush=True)

    def jobs_for(klist, extra=lambda k: ()):
        if a.dry_run:
            for k in klist:
                r = recs[k]
                rj = os.path.join(a.corpus, outroot, r["gearset"], r["name"], "report.json")
                rf = os.path.join(a.corpus, outroot, r["gearset"], r["name"], "refused.txt")
                if os.path.exists(rj):
                    progress(k, "cached", read_report(rj), 0.0)
                elif os.path.exists(rf):
                    progress(k, "cached-refused", ("refused", "refused", open(rf).read().strip(), []), 0.0)
            return
        with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
            futs = [ex.submit(run_one, a.planetwear, a.corpus, k, recs[k], outroot, a.threads, a.timeout, extra(k),
                              a.sensors)
                    for k in klist]
            for fu in cf.as_completed(futs):
                key, how, res, dt, _ = fu.result()
                progress(key, how, res, dt)

    if a.calibration_per_rig:
        base_keys = sorted({recs[k]["baseline"] for k in keys})
        # baselines first (also when held out: they are the rig's calibration runs)
        jobs_for([k for k in base_keys])
        cal = {}
        for bk in base_keys:
            if bk in results and results[bk][1][0] not in ("refused", "failed"):
                cal[bk] = [s for s in results[bk][1][3] if s.startswith(NUISANCE_PREFIXES)]
        jobs_for([k for k in keys if k not in results],
                 extra=lambda k: [x for s in cal.get(recs[k]["baseline"], []) for x in ("--set", s)])
    elif a.calibrate:
        # planetwear calibrate per gear set on its healthy baselines (never the held-out ones),
        # then every other recording diagnosed with --calibration.
        cal_files = {}
        for g in sorted({recs[k]["gearset"] for k in keys}):
            bases = sorted(k for k, r in recs.items()
                           if r["gearset"] == g and r["role"] == "baseline" and not r.get("held_out")
                           and not r.get("reader_should_refuse"))
            cf_path = os.path.join(a.corpus, outroot, g, "calibration.toml")
            os.makedirs(os.path.dirname(cf_path), exist_ok=True)
            if not os.path.exists(cf_path) and not a.dry_run:
                cmd = [a.planetwear, "calibrate", "-c", os.path.join(a.corpus, g, "gearset.toml"), "-o", cf_path,
                       "--threads", str(a.threads)]
                if a.rig_elements:
                    cmd += ["--rig-elements", a.rig_elements]
                if a.ring_body:
                    cmd += ["--ring-body"]
                for b in bases:
                    csvp = os.path.join(a.corpus, recs[b]["csv"])
                    cmd += ["-r", csvp, "--meta", sidecar(a.corpus, recs[b]["csv"], outroot, a.sensors)]
                t0 = time.time()
                p = subprocess.run(cmd, capture_output=True, text=True,
                                   env=dict(os.environ, OMP_NUM_THREADS=str(a.threads)))
                with open(cf_path + ".log", "w") as f:
                    f.write(" ".join(cmd) + "\n" + p.stdout + p.stderr)
                print(f"calibrated {g} on {len(bases)} baselines in {time.time() - t0:.0f} s (exit {p.returncode})",
                      flush=True)
                print(p.stdout, flush=True)
            cal_files[g] = cf_path
            keys[:] = [k for k in keys if k not in bases]
        jobs_for(keys, extra=lambda k: ["--calibration", cal_files[recs[k]["gearset"]]])
    elif a.differential:
        def baseline_args(k):
            b = recs[recs[k]["baseline"]]["csv"]
            return ["--baseline", os.path.join(a.corpus, b), "--baseline-meta", sidecar(a.corpus, b, outroot, a.sensors),
                    "--baseline-transfer", a.baseline_transfer]
        keys[:] = [k for k in keys if recs[k]["role"] != "baseline" and recs[k].get("baseline")]
        jobs_for(keys, extra=baseline_args)
    else:
        jobs_for(keys)

    # ---- scoring
    # An effect whose signature no test could see in its recording (observability.py: matched-filter
    # deflection below z_{1-alpha}^2 on every channel against a noise-free model) is scored apart:
    # "no missing physics" is the right answer there, a name a confident wrong one.
    unobservable = set()
    obs_path = os.path.join(a.corpus, "observability.json")
    if os.path.exists(obs_path):
        with open(obs_path) as f:
            obs = json.load(f)
        unobservable = {r["key"] for r in obs["rows"] if r["d2_model_all"] < obs["unobservable_below_d2"]}
    # Without a re-simulation, what the generator recorded: a backlash no flank ever reached.
    unobservable |= {k for k in keys if inert_by_truth(recs[k])}
    # Where an effect is not named, whether the report's located family (by the candidates' own
    # signatures) is one the true effect's candidate lives in: what an "unexplained residual"
    # still tells its reader, scored with the tool's own candidate table.
    families = candidate_families(a.planetwear)
    rows = []
    for k in keys:
        if k not in results:
            continue
        how, (label, verdict, summary, ov), dt = results[k]
        r = recs[k]
        truth_eff = r["effect"]
        outcome = score(label, truth_eff, k in unobservable)
        report_path = os.path.join(a.corpus, outroot, r["gearset"], r["name"], "report.json")
        located = located_family(report_path)
        located_right = None
        if families and truth_eff in families and located is not None:
            located_right = located in families[truth_eff]
        rows.append(dict(key=k, gearset=r["gearset"], name=r["name"], role=r["role"], truth=truth_eff,
                         reported=label, verdict=verdict, outcome=outcome, located=located,
                         located_right=located_right, coverage_gap_share=coverage_gap_share(report_path),
                         held_out=r.get("held_out", False),
                         reader_should_refuse=r.get("reader_should_refuse", False), op=r["operating_point"],
                         rpm=r["input_speed_rpm"], W=r["input_power_W"], duration_s=r["duration_s"],
                         seconds=round(dt, 1), summary=summary.replace("\n", " ")[:300]))
    odir = os.path.join(a.corpus, outroot)
    os.makedirs(odir, exist_ok=True)
    if rows:
        with open(os.path.join(odir, "results.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)
    truths = sorted({r["truth"] for r in rows})
    cols = sorted({r["reported"] for r in rows} - {"none", "unexplained", "refused", "failed"})
    cols = ["none"] + cols + ["unexplained", "refused", "failed"]
    mat = {t: {c: 0 for c in cols} for t in truths}
    for r in rows:
        mat[r["truth"]][r["reported"]] += 1
    counts = {}
    for r in rows:
        counts[r["outcome"]] = counts.get(r["outcome"], 0) + 1
    n_eff = sum(1 for r in rows if r["truth"] != "none" and r["outcome"] not in ("refused", "failed"))
    n_ctl = sum(1 for r in rows if r["truth"] == "none" and r["outcome"] not in ("refused", "failed"))
    n_unobs = sum(1 for r in rows if r["outcome"].startswith("unobservable_"))
    summary = dict(
        recordings=len(rows), effects_scored=n_eff, controls_scored=n_ctl,
        named_right=counts.get("named_right", 0) + counts.get("named_right_as_class", 0),
        named_right_as_class=counts.get("named_right_as_class", 0), controls_clean=counts.get("control_clean", 0),
        effects_observable=n_eff - n_unobs, unobservable_clean=counts.get("unobservable_clean", 0),
        confident_wrong_names=counts.get("wrong_name", 0) + counts.get("control_false_name", 0)
        + counts.get("unobservable_named", 0),
        unexplained=counts.get("unexplained", 0) + counts.get("control_unexplained", 0),
        missed=counts.get("missed", 0), refusals=counts.get("refused", 0), failures=counts.get("failed", 0),
        refusals_expected=sum(1 for r in rows if r["outcome"] == "refused" and r["reader_should_refuse"]),
        unexplained_effects_located=sum(1 for r in rows if r["outcome"] == "unexplained" and r["located"] is not None),
        unexplained_effects_located_right=sum(1 for r in rows if r["outcome"] == "unexplained" and r["located_right"]),
        unexplained_effects_mostly_untested=sum(1 for r in rows if r["outcome"] == "unexplained"
                                                and (r["coverage_gap_share"] or 0) > 0.5),
        wall_s=round(time.time() - t_start, 1))
    with open(os.path.join(odir, "results.json"), "w") as f:
        json.dump(dict(summary=summary, confusion=mat, rows=rows), f, indent=1)
    w0 = max([len(t) for t in truths] + [20])
    short = {c: c[:11] for c in cols}
    print()
    print("truth \\ reported".ljust(w0) + " ".join(short[c].rjust(11) for c in cols))
    for t in truths:
        print(t.ljust(w0) + " ".join((str(mat[t][c]) if mat[t][c] else ".").rjust(11) for c in cols))
    print()
    for k, v in summary.items():
        print(f"{k}: {v}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
