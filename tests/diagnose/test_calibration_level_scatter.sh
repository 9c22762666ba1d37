#!/bin/sh
# A level changed since the baseline is judged against how far the calibration's healthy
# recordings scatter that level, not against the noise error alone (docs/diagnose.md section 6b
# item 7, level_move_test in level_change.hpp).
# The seed stage, 1 kW, 1 s, 5 % noise. A "rig" whose mesh damping the model needs at 0.05 at
# 400 rpm and at 0.025 at 800 rpm (as on a rig whose damping law the model gets wrong: the level
# is then fitted to each operating point), and a recording at 400 rpm whose damping is 0.0375
# (x0.75 of the 400 rpm healthy recording's).
#   * calibrated on the 400 rpm recording alone (no scatter known): the test is the noise-only
#     one, and damping_level is named with its ratio within 20 % of 0.75 (the tolerance the
#     differential test gives a level's ratio: the fit carries the nuisance levels' errors);
#   * calibrated on both (ln 2 apart: sqrt(2) s = ln 2 = 0.69 in ln, one degree of freedom): the
#     same ratio lies inside the scatter, nothing is named, report.json gives the scatter and
#     the threshold for damping_level, and the summary says why it is not named.
# Usage: test_calibration_level_scatter.sh <planetwear> <workdir>
set -eu
PW=$1
rm -rf "$2"; mkdir -p "$2"; cd "$2"
S="--power-w 1000 --seconds 1.0 --noise 0.05 --decimate 32"
# shellcheck disable=SC2086
"$PW" synth -q $S --speed-rpm 400 --seed 3 -o h400.csv
# shellcheck disable=SC2086
"$PW" synth -q $S --speed-rpm 800 --seed 4 --set contact.mesh_damping_ratio=0.025 -o h800.csv
# shellcheck disable=SC2086
"$PW" synth -q $S --speed-rpm 400 --seed 5 --set contact.mesh_damping_ratio=0.0375 -o d400.csv
OMP_NUM_THREADS=1 "$PW" calibrate -q -r h400.csv -r h800.csv -o cal_two.toml --threads 1 > cal_two.txt
OMP_NUM_THREADS=1 "$PW" calibrate -q -r h400.csv -o cal_one.toml --threads 1 > cal_one.txt
for c in two one; do
  OMP_NUM_THREADS=1 "$PW" diagnose -q -r d400.csv --calibration cal_$c.toml -o diag_$c --threads 1 --no-plots > /dev/null
done
/usr/bin/python3 - <<'PY'
import json, math, sys, tomllib
cal = tomllib.load(open("cal_two.toml", "rb"))
levels = [float(dict(l.split("=", 1) for l in f["values"])["contact.mesh_damping_ratio"]) for f in cal["fit"]]
scatter = abs(math.log(levels[0] / levels[1]))  # sqrt(2) x the sample std of two ln values
if scatter < 0.3:
    sys.exit(f"the calibration's damping levels {levels} do not scatter: the test has nothing to judge against")

def damping(name):
    r = json.load(open(f"{name}/report.json"))
    for c in r["changes_since_baseline"]:
        if c["name"] == "damping_level":
            return r, c
    sys.exit(f"{name}: no damping_level in changes_since_baseline: {r['summary'][:400]}")

r1, c1 = damping("diag_one")
r2, c2 = damping("diag_two")
print(f"levels {levels}; one recording: {r1['verdict']}, x{c1['ratio']:.4g} +- {c1['ratio_std_error']:.2g}, "
      f"threshold {c1['ln_ratio_threshold']:.3g}; two: {r2['verdict']}, scatter {c2['ln_ratio_healthy_scatter']:.3g}, "
      f"threshold {c2['ln_ratio_threshold']:.3g}")
if r1["verdict"] != "missing_physics_found" or r1["candidates"][0]["name"] != "damping_level":
    sys.exit(f"one-recording calibration: damping_level not named: {r1['summary'][:400]}")
if not 0.75 * 0.8 <= c1["ratio"] <= 0.75 * 1.2:
    sys.exit(f"one-recording calibration: ratio {c1['ratio']} not within 20 % of 0.75")
if c1["ln_ratio_healthy_scatter"] != 0:
    sys.exit(f"one-recording calibration carried a scatter: {c1}")
if r2["verdict"] == "missing_physics_found":
    sys.exit(f"two-recording calibration named a change inside the healthy scatter: {r2['summary'][:400]}")
# The scatter in the report is sqrt(2) s of the calibration's two values (1e-9: round-off of the
# values as the TOML writes them).
if abs(c2["ln_ratio_healthy_scatter"] - scatter) > 1e-9 * scatter:
    sys.exit(f"scatter {c2['ln_ratio_healthy_scatter']} is not |ln({levels[0]}/{levels[1]})| = {scatter}")
if not (c2["explains"] and not c2["passes"] and abs(math.log(c2["ratio"])) < c2["ln_ratio_threshold"]):
    sys.exit(f"two-recording calibration: expected a level that explains but lies inside its threshold: {c2}")
if "healthy recordings scatter contact.mesh_damping_ratio" not in r2["summary"]:
    sys.exit(f"the summary does not say why the damping level is not named: {r2['summary']}")
PY
