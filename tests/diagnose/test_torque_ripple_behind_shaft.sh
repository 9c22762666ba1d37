#!/bin/sh
# A torque ripple on a motor behind an input shaft, diagnosed with a calibration that kept the
# shaft (docs/diagnose.md section 4, torque_ripple). The rig: the seed stage at 400 rpm, 1 kW, its
# motor of 0.12 kg m^2 (200 times the sun's inertia) behind a 2e4 N m/rad shaft; 3 s recordings
# (4 carrier revolutions: the input-shaft lines resolved), 5 % noise. The gear set does not state
# the motor, so the calibration's shaft element holds a speed-source stand-in behind it (1e4 times
# the sun's inertia, 6 kg m^2): right at the mesh lines, fifty times too heavy at the ripple's
# 2 f_s = 13 Hz, where that inertia takes the ripple torque. What the speed lines fix there is
# the ripple torque over the drive line's inertia, r T / |i w J_in + ...|: with the stand-in held,
# the fraction ran to its bound 0.5 (before session 48); now the motor's inertia is fitted beside
# it as a transfer parameter, and the fraction over the fitted inertia must come within 20 % (the
# issue's size target) of the truth's 0.05 / 0.12 = 0.42 per kg m^2 (measured 0.408: the other
# inertias of the drive line are small beside the motor's). Measured 2026-12-02: about 30 s for
# the calibration and 30 s for the diagnosis at 2 threads.
# Usage: test_torque_ripple_behind_shaft.sh <planetwear> <workdir>
set -eu
PW=$1
rm -rf "$2"; mkdir -p "$2"; cd "$2"
S="--speed-rpm 400 --power-w 1000 --seconds 3.0 --noise 0.05 --decimate 32"
R="--set rig.input_shaft_stiffness_N_m_rad=2e4 --set rig.input_shaft_damping_N_m_s_rad=4 --set stage.input_inertia_kgm2=0.12"
# shellcheck disable=SC2086
"$PW" synth -q $S --seed 3 $R -o healthy.csv
# shellcheck disable=SC2086
"$PW" synth -q $S --seed 4 $R --set imperfections.torque_ripple_fraction=0.05 --set imperfections.torque_ripple_order=2 \
    -o ripple.csv
OMP_NUM_THREADS=1 "$PW" calibrate -q -r healthy.csv --rig-elements input_shaft -o cal.toml --threads 1 > cal.txt 2> cal.err
OMP_NUM_THREADS=1 "$PW" diagnose -q -r ripple.csv --calibration cal.toml -o diag --threads 1 --no-plots > diag.txt 2> diag.err
/usr/bin/python3 - <<'PY'
import json, sys, tomllib
cal = tomllib.load(open("cal.toml", "rb"))["calibration"]
if "input_shaft" not in cal["rig_elements"]:
    sys.exit(f"the calibration left the shaft out ({cal['rig_elements']}): nothing to test")
rep = json.load(open("diag/report.json"))
if "stage.input_inertia_kgm2" not in rep.get("calibration_reference", ""):
    sys.exit(f"the reference does not hold the stand-in motor: {rep.get('calibration_reference', '')}")
name = rep.get("missing_physics") or (rep.get("lead") or {}).get("name")
# At the stand-in the fraction's secant is ~0: the screening's larger S must be the one taken with the
# machines at their screening values (docs/diagnose.md section 5 step 7, session 68).
scr = [s for s in rep["screening"] if s["name"] == "torque_ripple"]
if not scr or not scr[0]["at_transfer_values"]:
    sys.exit(f"the ripple was not screened at its transfer parameters' screening values: {scr}")
ripple = [c for c in rep["candidates"] if c["name"] == "torque_ripple"]
if not ripple:
    sys.exit(f"torque_ripple was not fitted: {rep['summary']}")
p = {q["name"]: q for q in ripple[0]["parameters"]}
if "stage.input_inertia_kgm2" not in p:
    sys.exit(f"the ripple's fit holds the stand-in motor: parameters {sorted(p)}")
r, J = p["torque_ripple_fraction"], p["stage.input_inertia_kgm2"]
if r["at_bound"]:
    sys.exit(f"torque_ripple_fraction at its bound ({r['value']:.4g})")
ratio, truth = r["value"] / J["value"], 0.05 / 0.12
if abs(ratio / truth - 1) > 0.2:
    sys.exit(f"fraction / motor inertia {ratio:.4g} per kg m^2, true {truth:.4g} (allowed within 20 %)")
if rep["verdict"] == "missing_physics_found" and rep["missing_physics"] != "torque_ripple":
    sys.exit(f"a wrong name: {rep['summary']}")
if rep["verdict"] == "no_missing_physics":
    sys.exit(f"the ripple was missed: {rep['summary']}")
print(f"torque ripple {rep['verdict']}: fraction {r['value']:.4g} for the fitted motor {J['value']:.4g} kg m^2, "
      f"ratio {ratio:.4g} against the truth's {truth:.4g} per kg m^2")
PY
