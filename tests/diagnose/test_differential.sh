#!/bin/sh
# Differential diagnosis against a healthy baseline (docs/diagnose.md section 6b) on a model-form
# difference the absolute comparison cannot absorb: the "rig" drives a speed-controlled
# dynamometer through an output shaft and reads its speeds through 1.5 kHz encoders (rig.*,
# sensor.encoder_bandwidth_Hz); the diagnosis's model has neither (torsional, 1200 rpm, 20 kW,
# 5 % noise). Baseline: healthy recording seed 3, twice as long as the others (1.56 s: halves of 3
# carrier revolutions where theirs hold 1), so both are analysed in halves of 1 revolution
# (apps/diagnose_command.cpp common_windows).
#   * a second healthy recording (seed 4) is "no_missing_physics";
#   * a cracked sun tooth (seed 5, stiffness factor 0.6) is named sun_tooth_damage, or its class
#     sun_defect with the sun tooth as the lead (under the baseline's budget a sun runout that
#     improves both halves is not told apart: docs/diagnose.md section 5), with its factor within
#     20 % of 0.6, and its uncertainty (noise and model form) covering 0.6;
#   * a baseline sampled at half the rate (seed 6) cannot share the recording's cells: refused;
#   * a housing accelerometer reading 0.6 times as strongly (seed 8) is named sensor_transfer_path,
#     its gain's ratio to the baseline's within 5 % of 0.6;
#   * the mesh damping ratio 0.02 instead of 0.05 (seed 9) and every mesh stiffness x0.8 (seed 10)
#     are named as their class tooth_contact_change (friction, profile and clearance changes act on
#     the mesh harmonics alone as a level does and are not fitted by the change check), fitted as
#     damping_level and stiffness_level respectively, each ratio to the baseline's value within 20 % of the
#     truth (0.4, 0.8; the tolerance the sun tooth's factor has: the baseline's damping is fitted at
#     0.070 on a model without the rig, so the ratio carries model-form error; measured 0.467 and
#     0.7975, session 28).
# Absolute (no baseline), the same two recordings are both "unexplained_residual" (measured
# 2026-11-26: chi2 3.4 and 18.7 times their bounds after the best fit; docs/diagnose.md).
# Measured 2026-11-26 on a loaded 2-core machine: 79 s and 336 s at 2 threads.
# Usage: test_differential.sh <planetwear> <workdir>
set -eu
PW=$1
rm -rf "$2"; mkdir -p "$2"; cd "$2"
RIG="--speed-rpm 1200 --power-w 20000 --noise 0.05 --dc-offset 0.2 --sensor-angle-deg 40
     --start-mesh-cycle 450 --set solver.periodicity_tolerance=1e-3 --set rig.load_control=speed
     --set rig.output_shaft_stiffness_N_m_rad=2e4 --set rig.output_shaft_damping_N_m_s_rad=5
     --set sensor.encoder_bandwidth_Hz=1500"
# shellcheck disable=SC2086
"$PW" synth -q $RIG --seed 3 --seconds 1.56 --decimate 40 -o healthy3.csv
# shellcheck disable=SC2086
"$PW" synth -q $RIG --seed 4 --seconds 0.78 --decimate 40 -o healthy4.csv
# shellcheck disable=SC2086
"$PW" synth -q $RIG --seed 5 --seconds 0.78 --decimate 40 --set 'imperfections.teeth=[{body="sun",tooth=5,stiffness_factor=0.6}]' -o sun5.csv
# A baseline sampled at half the rate has no cells in the upper half of the recording's band: it
# is refused before any fit (exit 1, naming --baseline), and no report is written.
# shellcheck disable=SC2086
"$PW" synth -q $RIG --seed 6 --seconds 0.78 --decimate 80 -o slow6.csv
rc=0; "$PW" diagnose -q -r healthy4.csv --baseline slow6.csv -o slow6_rep --no-plots 2> slow6.err || rc=$?
if [ "$rc" -ne 1 ] || ! grep -q -- "--baseline" slow6.err || [ -e slow6_rep ]; then
  echo "a baseline at another sample rate: exit $rc, expected 1 naming --baseline with nothing written"; cat slow6.err; exit 1
fi
# The housing accelerometer reads 0.6 times as strongly as in the baseline (its sensitivity or
# mounting changed), the gears are as they were.
# shellcheck disable=SC2086
"$PW" synth -q $RIG --seed 8 --seconds 0.78 --decimate 40 --set sensor.gain_m_s2_per_N=6e-4 -o gain8.csv
# A level the gears changed since the baseline: the damping ratio, and every mesh stiffness.
# shellcheck disable=SC2086
"$PW" synth -q $RIG --seed 9 --seconds 0.78 --decimate 40 --set contact.mesh_damping_ratio=0.02 -o damp9.csv
# shellcheck disable=SC2086
"$PW" synth -q $RIG --seed 10 --seconds 0.78 --decimate 40 --set stiffness.scale=0.8 -o stiff10.csv
OMP_NUM_THREADS=1 "$PW" diagnose -q -r damp9.csv --baseline healthy3.csv -o damp9 --threads 1 --no-plots
OMP_NUM_THREADS=1 "$PW" diagnose -q -r stiff10.csv --baseline healthy3.csv -o stiff10 --threads 1 --no-plots
OMP_NUM_THREADS=1 "$PW" diagnose -q -r healthy4.csv --baseline healthy3.csv -o healthy4 --threads 1 --no-plots
OMP_NUM_THREADS=1 "$PW" diagnose -q -r gain8.csv --baseline healthy3.csv -o gain8 --threads 1 --no-plots
OMP_NUM_THREADS=1 "$PW" diagnose -q -r sun5.csv --baseline healthy3.csv -o sun5 --threads 1 --no-plots
/usr/bin/python3 - <<'PY'
import json, re, sys
h = json.load(open("healthy4/report.json"))
s = json.load(open("sun5/report.json"))
if not h["baseline"].endswith("healthy3.csv") or not s["baseline"].endswith("healthy3.csv"):
    sys.exit("the report does not name the baseline")
# The own simulator's baseline is fitted inside every box: nothing is listed as a limit.
if h.get("baseline_at_bound") != [] or s.get("baseline_at_bound") != []:
    sys.exit(f"baseline values listed at a bound: {h.get('baseline_at_bound')}, {s.get('baseline_at_bound')}")
if h["verdict"] != "no_missing_physics":
    sys.exit(f"healthy recording against its baseline: {h['verdict']}: {h['summary'][:300]}")
# The change check ran on the healthy recording (both levels and the housing gain tested), and
# nothing it tested passed as a finding.
hc = h["changes_since_baseline"]
if {"stiffness_level", "damping_level"} - {c["name"] for c in hc} or any(c["passes"] and c["explains"] and (c["posterior"] or 0) >= 0.995 for c in hc):
    sys.exit(f"healthy recording: changes_since_baseline {hc}")
if s["missing_physics"] not in ("sun_tooth_damage", "sun_defect") or s["lead"]["name"] != "sun_tooth_damage":
    sys.exit(f"cracked sun tooth against the baseline: {s['verdict']}, {s['missing_physics']}: {s['summary'][:300]}")
text = s["summary"]
m = re.search(r"stiffness_factor = ([0-9.]+)", text)
if not m:
    sys.exit("no fitted stiffness_factor in the summary: " + text[:300])
factor = float(m.group(1))
if abs(factor - 0.6) > 0.2 * 0.6:
    sys.exit(f"stiffness factor {factor}, true 0.6 (more than 20 % off)")
# The size's uncertainty includes the baseline's model-form budget (docs/diagnose.md section 5,
# "model-form uncertainty"): the fit's noise error alone (~0.002) does not cover the truth here, the
# whole uncertainty must, at the diagnosis's alpha = 0.01 (z = 2.576).
win = next(c for c in s["candidates"] if c["name"] == "sun_tooth_damage")
p = next(q for q in win["parameters"] if q["name"] == "stiffness_factor")
mf, se = p["model_form_std"], p["std_error"]
if not (mf and mf > 0) or "model form" not in text:
    sys.exit(f"no model-form uncertainty on the stiffness factor (model_form_std {mf}): " + text[:300])
lo, hi = p["model_form_range"]
if not (lo <= 0.6 <= hi) or abs(p["value"] - 0.6) > 2.576 * (se * se + mf * mf) ** 0.5:
    sys.exit(f"stiffness factor {p['value']} ± {se} (model form ± {mf}: {lo} to {hi}) does not cover the true 0.6")
# The sensor's gain change: named sensor_transfer_path, the channel reading the baseline's lines
# 0.6 times as strongly within 5 % (its standard error is ~1.5 %; measured 0.598, session 26).
g = json.load(open("gain8/report.json"))
if g["missing_physics"] != "sensor_transfer_path":
    sys.exit(f"housing gain x0.6 against the baseline: {g['verdict']}, {g['missing_physics']}: {g['summary'][:300]}")
gp = next(q for q in g["candidates"][0]["parameters"] if q["name"].startswith("housing_gain_ratio"))
ratio = gp["value"]
if abs(ratio - 0.6) > 0.05 * 0.6:
    sys.exit(f"housing gain ratio {ratio:.4f} to the baseline's, true 0.6 (more than 5 % off)")
for name, cand, key, truth in (("damp9", "damping_level", "contact.mesh_damping_ratio", 0.4),
                               ("stiff10", "stiffness_level", "stiffness.scale", 0.8)):
    r = json.load(open(name + "/report.json"))
    fc = r.get("finding_class") or {}
    if (r["missing_physics"] != "tooth_contact_change" or r["candidates"][0]["name"] != cand
            or (fc.get("members") or [None])[0] != cand or cand not in fc.get("covers", [])):
        sys.exit(f"{key} x{truth} against the baseline: {r['verdict']}, {r['missing_physics']}, fitted "
                 f"{r['candidates'][0]['name'] if r['candidates'] else None}: {r['summary'][:300]}")
    q = next(q for q in r["candidates"][0]["parameters"] if q["name"] == key)
    ratio = q["value"] / q["initial"]
    if abs(ratio - truth) > 0.2 * truth:
        sys.exit(f"{key}: ratio {ratio:.4f} to the baseline's, true {truth} (more than 20 % off)")
    # The report lists every hypothesis of the change check; the named one passed its tests, with
    # its ratio, and won among the rivals at posterior >= 1 - alpha/2.
    ch = {c["name"]: c for c in r["changes_since_baseline"]}
    c = ch.get(cand)
    if not c or not c["passes"] or c["posterior"] < 0.995 or abs(c["ratio"] - ratio) > 1e-9 * ratio:
        sys.exit(f"{name}: changes_since_baseline does not record the named {cand}: {r['changes_since_baseline']}")
    print(name + ":", r["summary"][:200])
print("healthy:", h["summary"][:160])
print("gain x0.6:", g["summary"][:200])
print("sun tooth:", text[:200])
PY
