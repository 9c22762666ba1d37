#!/usr/bin/env python3
"""Run `planetwear diagnose` on every recording of a corpus (scripts/make_corpus.py)
and score it against the corpus's truth.json.

Prints, and writes to OUT/summary.json:
  * the confusion matrix (true effect x named effect);
  * for every correctly named effect, the relative error of its main fitted
    parameter (the requirement is <= 20 %); a saturating parameter (backlash
    wider than the teeth ever separate) is reported by the diagnosis as a lower
    limit only, and is checked as "the true value is not below the limit by
    more than that tolerance" and listed apart;
  * the control cases (no effect): the verdict must be "no missing physics";
  * wall time per recording, their sum, and the elapsed time of the whole run
    (what --jobs shortens; not measured when reports are reused).

How a diagnosis is read as a named effect (the mapping is fixed, not tuned):
  * verdict missing_physics_found -> the winning candidate, mapped to the
    corpus's effect names (pin_error -> planet_pin_error, sun_runout ->
    sun_eccentricity, carrier_runout -> carrier_eccentricity, torque_ripple ->
    input_torque_ripple, friction -> friction_coefficient);
  * a class finding (report.json "finding_class") -> "class:a|b" of its members'
    effects; right when the truth is a member, counted apart ("as a class"), no
    parameter error (the class's size is not one parameter);
  * otherwise, if a nuisance parameter moved from its nominal value (the gear
    set's, reported as "initial" in report.json) by more than 3 standard
    errors and 5 %, that recalibration is the named effect (stiffness.scale ->
    mesh_stiffness_level, mesh_damping_ratio -> mesh_damping_level, sensor
    gain -> sensor_transfer_path);
  * otherwise "none" (no missing physics), or "unexplained".

Usage:
    scripts/run_corpus.py CORPUS [-o OUT] [--planetwear PATH] [--jobs 1] [--threads 2]
        [--min-accuracy 0] [--require-controls] [--max-parameter-error 0.2]
Exit status 1 if a diagnosis crashed, or the accuracy / control / parameter
requirements given on the command line are not met.
"""

import os
import sys


def ensure_system_python():
    system_python = "/usr/bin/python3"
    if os.path.realpath(sys.executable) != os.path.realpath(system_python) and os.path.exists(system_python) \
            and not os.environ.get("PW_RUNCORPUS_REEXEC"):
        os.environ["PW_RUNCORPUS_REEXEC"] = "1"
        os.execv(system_python, [system_python] + sys.argv)


ensure_system_python()

import argparse  # noqa: E402
import json  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import time  # noqa: E402
from concurrent.futures import ThreadPoolExecutor  # noqa: E402
from pathlib import Path  # noqa: E402

REPO = Path(__file__).resolve().parent.parent

CANDIDATE_TO_EFFECT = {
    "pin_error": "planet_pin_error",
    "sun_runout": "sun_eccentricity",
    "carrier_runout": "carrier_eccentricity",
    "torque_ripple": "input_torque_ripple",
    "friction": "friction_coefficient",
}
NUISANCE_TO_EFFECT = {
    "stiffness.scale": "mesh_stiffness_level",
    "contact.mesh_damping_ratio": "mesh_damping_level",
    "sensor.gain_m_s2_per_N": "sensor_transfer_path",
}
# truth parameter -> (report parameter name, how to compare)
MAIN_PARAMETER = {
    "sun_tooth_damage": ("stiffness_factor", "stiffness_factor"),
    "planet_tooth_damage": ("stiffness_factor", "stiffness_factor"),
    "ring_tooth_damage": ("stiffness_factor", "stiffness_factor"),
    "mesh_stiffness_level": ("stiffness_scale", "stiffness.scale"),
    "mesh_damping_level": ("mesh_damping_ratio", "contact.mesh_damping_ratio"),
    "friction_coefficient": ("friction_coefficient", "contact.friction_coefficient"),
    "input_torque_ripple": ("torque_ripple_fraction", "torque_ripple_fraction"),
    "worn_profile": ("worn_profile_depth_m", "worn_profile_depth_m"),
    "backlash": ("backlash_sun_planet_m", "contact.backlash_sun_planet_m"),
}


def find_planetwear(given):
    if given:
        return str(Path(given).resolve())
    for c in sorted(REPO.glob("build*/apps/planetwear")):
        if os.access(c, os.X_OK):
            return str(c)
    found = shutil.which("planetwear")
    if found:
        return found
    sys.exit("run_corpus: no planetwear executable (pass --planetwear)")


CLASS_PREFIX = "class:"


def named_effect(report):
    if report.get("verdict") == "missing_physics_found":
        fc = report.get("finding_class")
        if isinstance(fc, dict) and fc.get("members"):
            # A class finding (docs/diagnose.md section 5): the members the data did not tell apart.
            return CLASS_PREFIX + "|".join(sorted(CANDIDATE_TO_EFFECT.get(m, m) for m in fc["members"]))
        name = report.get("missing_physics")
        return CANDIDATE_TO_EFFECT.get(name, name)
    for p in report.get("nuisance", {}).get("parameters", []):
        # "initial": the gear set's nominal value the diagnosis started the nuisance fit from
        start, se = p.get("initial"), p.get("std_error")
        if start is None or se is None or not se or se != se:
            continue
        if abs(p["value"] - start) > 3 * se and abs(p["value"] - start) > 0.05 * abs(start):
            return NUISANCE_TO_EFFECT.get(p["name"], p["name"])
    return "none" if report.get("verdict") == "no_missing_physics" else "unexplained"


def fitted_parameters(report):
    out = {}
    src = report.get("fitted_parameters") or report.get("nuisance", {}).get("parameters", [])
    for p in src:
        out[p["name"]] = (p["value"], p.get("std_error"))
        if p.get("saturates") and p.get("lower_limit") is not None:
            out[p["name"] + "#lower_limit"] = (p["lower_limit"], None)
    for p in report.get("nuisance", {}).get("parameters", []):
        out.setdefault(p["name"], (p["value"], p.get("std_error")))
    return out


def parameter_error(effect, truth_params, report):
    fitted = fitted_parameters(report)
    if effect in MAIN_PARAMETER:
        tkey, rkey = MAIN_PARAMETER[effect]
        if tkey in truth_params and rkey + "#lower_limit" in fitted:
            return tkey + "#lower_limit", truth_params[tkey], fitted[rkey + "#lower_limit"][0], None
        if tkey in truth_params and rkey in fitted:
            t, (f, se) = truth_params[tkey], fitted[rkey]
            return tkey, t, f, se
    if effect == "planet_pin_error":
        # Amplitudes cannot tell the planets apart (relabelling them cyclically, or adding a
        # common offset, changes no amplitude), so the pattern's peak-to-peak spread is compared.
        t = truth_params["pin_error_m"]
        pins = [0.0] + [fitted[k][0] for k in sorted(fitted) if k.startswith("pin_error_m[")]
        if len(pins) > 1:
            return "pin_error_peak_to_peak_m", max(t) - min(t), max(pins) - min(pins), None
    if effect in ("sun_eccentricity", "carrier_eccentricity"):
        key = "sun_eccentricity" if effect == "sun_eccentricity" else "carrier_eccentricity"
        if f"{key}_m" in fitted:
            return f"{key}_m", truth_params[f"{key}_m"], fitted[f"{key}_m"][0], fitted[f"{key}_m"][1]
        if f"{key}_x_m" in fitted:
            x, y = fitted[f"{key}_x_m"][0], fitted[f"{key}_y_m"][0]
            return f"{key}_m", truth_params[f"{key}_m"], (x * x + y * y) ** 0.5, None
    if effect == "sensor_transfer_path":
        if "window_width_rad" in truth_params and "sensor.window_width_rad" in fitted:
            return "window_width_rad", truth_params["window_width_rad"], fitted["sensor.window_width_rad"][0], None
        if "gain_m_s2_per_N" in truth_params and "sensor.gain_m_s2_per_N" in fitted:
            return "gain_m_s2_per_N", truth_params["gain_m_s2_per_N"], fitted["sensor.gain_m_s2_per_N"][0], None
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("corpus")
    ap.add_argument("-o", "--output", help="reports go to OUTPUT/<recording>/ (default CORPUS/diagnoses)")
    ap.add_argument("--planetwear")
    ap.add_argument("--jobs", type=int, default=1, help="recordings diagnosed at once (default 1)")
    ap.add_argument("--threads", type=int, default=2, help="OpenMP threads per diagnosis (default 2)")
    ap.add_argument("--plots", action="store_true", help="draw the PNGs too")
    ap.add_argument("--reuse", action="store_true",
                    help="score an existing OUTPUT/<recording>/report.json instead of diagnosing again "
                         "(resume an interrupted run; only recordings without a report are diagnosed)")
    ap.add_argument("--min-accuracy", type=float, default=0.0, help="fail below this fraction of correct names")
    ap.add_argument("--require-controls", action="store_true", help="fail unless every control says 'none'")
    ap.add_argument("--max-wrong-names", type=int, default=None,
                    help="fail if more recordings than this are named a wrong effect with confidence "
                         "(a control named anything, an effect named another; 'unexplained' is not a name)")
    ap.add_argument("--max-parameter-error", type=float, default=None,
                    help="fail if a correctly named effect's main parameter is off by more than this fraction")
    args = ap.parse_args()
    corpus = Path(args.corpus)
    truth = json.loads((corpus / "truth.json").read_text())["recordings"]
    out = Path(args.output) if args.output else corpus / "diagnoses"
    out.mkdir(parents=True, exist_ok=True)
    pw = find_planetwear(args.planetwear)

    def run(name):
        rec = corpus / "recordings" / f"{name}.csv"
        cmd = [pw, "diagnose", "-q", "-c", str(corpus / "gearset.toml"), "--recording", str(rec),
               "--meta", str(rec.with_suffix(".json")), "-o", str(out / name), "--threads", str(args.threads)]
        if not args.plots:
            cmd.append("--no-plots")
        existing = out / name / "report.json"
        if args.reuse and existing.exists():
            report = json.loads(existing.read_text())
            wall = float(report.get("timing", {}).get("total_s", 0.0))
            print(f"{name}: reused {existing}  truth {truth[name]['effect']:<22} -> "
                  f"{named_effect(report)}", flush=True)
            return name, report, wall, None
        t0 = time.monotonic()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.monotonic() - t0
        report = None
        if p.returncode == 0 and (out / name / "report.json").exists():
            report = json.loads((out / name / "report.json").read_text())
        print(f"{name}: {wall:6.1f} s  exit {p.returncode}  truth {truth[name]['effect']:<22} -> "
              f"{named_effect(report) if report else 'FAILED: ' + p.stderr.strip()[:200]}", flush=True)
        return name, report, wall, p

    names = sorted(truth)
    t_start = time.monotonic()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(run, names))
    elapsed = time.monotonic() - t_start
    reused = sum(1 for _, _, _, p in results if p is None)

    rows, crashed = [], []
    for name, report, wall, p in results:
        t = truth[name]
        if report is None:
            crashed.append(name)
            rows.append({"recording": name, "truth": t["effect"], "named": "crashed", "wall_s": wall})
            continue
        named = named_effect(report)
        lead = (report.get("lead") or {}).get("name")
        row = {"recording": name, "truth": t["effect"], "named": named, "verdict": report["verdict"],
               "lead": CANDIDATE_TO_EFFECT.get(lead, lead) if lead else None,
               "wall_s": round(wall, 1), "speed_rpm": t["speed_rpm"], "power_W": t["power_W"],
               "summary": report["summary"]}
        if named == t["effect"] and t["effect"] != "none":
            pe = parameter_error(t["effect"], t["parameters"], report)
            if pe:
                key, tv, fv, se = pe
                if key.endswith("#lower_limit"):
                    # Error = how far the truth lies below the reported lower limit (0 if above it).
                    row["parameter"] = {"name": key.split("#")[0], "truth": tv, "lower_limit": fv,
                                        "relative_error": max(0.0, fv - tv) / abs(tv) if tv else None}
                else:
                    row["parameter"] = {"name": key, "truth": tv, "fitted": fv, "std_error": se,
                                        "relative_error": abs(fv - tv) / abs(tv) if tv else None}
        rows.append(row)

    effects = sorted({r["truth"] for r in rows} | {r["named"] for r in rows})
    print("\nConfusion matrix (rows: truth, columns: named)")
    width = max(len(e) for e in effects) + 1
    print(" " * width + " ".join(f"{e[:8]:>8}" for e in effects))
    for te in sorted({r["truth"] for r in rows}):
        counts = [sum(1 for r in rows if r["truth"] == te and r["named"] == ne) for ne in effects]
        print(f"{te:<{width}}" + " ".join(f"{c:>8}" for c in counts))
    effect_rows = [r for r in rows if r["truth"] != "none"]
    control_rows = [r for r in rows if r["truth"] == "none"]
    def in_class(r):
        return r["named"].startswith(CLASS_PREFIX) and r["truth"] in r["named"][len(CLASS_PREFIX):].split("|")

    as_class = sum(1 for r in effect_rows if in_class(r))
    correct = sum(1 for r in effect_rows if r["named"] == r["truth"]) + as_class
    accuracy = correct / len(effect_rows) if effect_rows else 1.0
    controls_ok = sum(1 for r in control_rows if r["named"] == "none")
    print(f"\nNamed the right effect: {correct}/{len(effect_rows)} = {100 * accuracy:.0f} %"
          f"{f' ({as_class} of them as a class of findings the truth belongs to)' if as_class else ''}")
    print(f"Controls answered 'no missing physics': {controls_ok}/{len(control_rows)}")
    wrong = [r["recording"] for r in rows
             if r["named"] not in (r["truth"], "none", "unexplained", "crashed") and not in_class(r)]
    lead_right = sum(1 for r in effect_rows if r["named"] == "unexplained" and r.get("lead") == r["truth"])
    print(f"Confident wrong names: {len(wrong)}{' ' + str(wrong) if wrong else ''}; "
          f"'unexplained' with the right lead: {lead_right}")
    print("\nParameter errors (correctly named effects):")
    within = limits_ok = 0
    with_param = [r for r in rows if "parameter" in r]
    with_limit = [r for r in with_param if "lower_limit" in r["parameter"]]
    for r in with_param:
        p = r["parameter"]
        ok = p["relative_error"] is not None and p["relative_error"] <= 0.2
        if "lower_limit" in p:
            limits_ok += ok
            print(f"  {r['recording']} {r['truth']:<22} {p['name']:<24} truth {p['truth']:.4g} lower limit "
                  f"{p['lower_limit']:.4g}  {'ok (truth above the limit)' if ok else 'truth BELOW the limit'}")
            continue
        within += ok
        print(f"  {r['recording']} {r['truth']:<22} {p['name']:<24} truth {p['truth']:.4g} fitted {p['fitted']:.4g}"
              f"  error {100 * p['relative_error']:.1f} % {'ok' if ok else '> 20 %'}")
    print(f"  within 20 %: {within}/{len(with_param) - len(with_limit)} identifiable parameters")
    if with_limit:
        print(f"  saturating parameters reported as a lower limit, truth above it: {limits_ok}/{len(with_limit)}")
    # Two different times: the elapsed time of the whole run (what --jobs shortens) and the sum
    # of the recordings' own wall times (the cost of one diagnosis, whatever ran beside it).
    summed = sum(r["wall_s"] for r in rows)
    if reused:
        print(f"\nElapsed: not measured ({reused} of {len(rows)} reports reused)")
    else:
        print(f"\nElapsed: {elapsed:.0f} s for {len(rows)} recordings with --jobs {args.jobs} --threads {args.threads}")
    print(f"Summed per-recording wall time: {summed:.0f} s ({summed / max(1, len(rows)):.0f} s each)")
    summary = {"elapsed_s": None if reused else round(elapsed, 1), "summed_wall_s": round(summed, 1), "rows": rows, "accuracy": accuracy, "correct": correct, "correct_as_class": as_class, "effects": len(effect_rows),
               "controls_ok": controls_ok, "controls": len(control_rows), "parameters_within_20pct": within,
               "parameters_checked": len(with_param) - len(with_limit), "lower_limits_ok": limits_ok,
               "lower_limits_checked": len(with_limit), "crashed": crashed, "confident_wrong_names": wrong,
               "unexplained_with_right_lead": lead_right}
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    status = 0
    if crashed:
        print(f"run_corpus: {len(crashed)} diagnoses failed: {crashed}", file=sys.stderr)
        status = 1
    if accuracy < args.min_accuracy:
        print(f"run_corpus: accuracy {accuracy:.2f} below --min-accuracy {args.min_accuracy}", file=sys.stderr)
        status = 1
    if args.max_wrong_names is not None and len(wrong) > args.max_wrong_names:
        print(f"run_corpus: {len(wrong)} confident wrong names (at most {args.max_wrong_names}): {wrong}",
              file=sys.stderr)
        status = 1
    if args.require_controls and controls_ok < len(control_rows):
        print("run_corpus: a control was not answered 'no missing physics'", file=sys.stderr)
        status = 1
    if args.max_parameter_error is not None:
        bad = [r["recording"] for r in with_param
               if r["parameter"]["relative_error"] is None or r["parameter"]["relative_error"] > args.max_parameter_error]
        if bad:
            print(f"run_corpus: parameter error above {args.max_parameter_error}: {bad}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
