#!/bin/sh
# A calibrated reference holds the rig-design elements the calibration measured on it
# (docs/diagnose.md section 6a item 6, `reference_design_settings`): the seed stage at 400 rpm,
# 1 kW, 1 s, 5 % noise, with speed encoders of 250 Hz bandwidth (2.2 mesh frequencies: the
# mesh harmonics of the speed channels are cut), calibrated with `--rig-elements
# encoder_bandwidth` on one healthy recording; a second healthy recording at the same operating
# point is diagnosed against that calibration. The reference must hold the encoder's low-pass at
# the calibration's own fit of it (within 1e-9 relative: the value is copied, not refitted), that
# fit must be a measurement (inside the box, within 30 % of the 250 Hz the recordings were made
# with; measured 2026-12-05: 250.5 Hz, 11 s for the whole script on 2 threads), and the healthy
# recording must stay "no missing physics". Fails on the binary before 8020ead: its reference held
# no encoder.
# Usage: test_calibration_reference_design.sh <planetwear> <workdir>
set -eu
PW=$1
rm -rf "$2"; mkdir -p "$2"; cd "$2"
S="--speed-rpm 400 --power-w 1000 --seconds 1.0 --noise 0.05 --decimate 32 --set sensor.encoder_bandwidth_Hz=250"
# shellcheck disable=SC2086
"$PW" synth -q $S --seed 11 -o cal.csv
# shellcheck disable=SC2086
"$PW" synth -q $S --seed 12 -o healthy.csv
OMP_NUM_THREADS=1 "$PW" calibrate -q -r cal.csv --rig-elements encoder_bandwidth -o cal.toml --threads 1 \
    > cal.txt 2> cal.err
OMP_NUM_THREADS=1 "$PW" diagnose -q -r healthy.csv --calibration cal.toml -o diag --threads 1 --no-plots \
    > diag.txt 2> diag.err
/usr/bin/python3 - <<'PY'
import json, re, sys, tomllib
cal = tomllib.load(open("cal.toml", "rb"))
fit = cal["fit"][0]
values = dict(v.split("=", 1) for v in fit["values"])
if "sensor.encoder_bandwidth_Hz" not in values:
    sys.exit(f"the calibration did not fit the encoder: {fit['values']}")
f_cal = float(values["sensor.encoder_bandwidth_Hz"])
if "sensor.encoder_bandwidth_Hz" in fit.get("at_bound", []):
    sys.exit(f"the calibration's encoder ended at a bound of its box ({f_cal:.4g} Hz): not a measurement")
if not 175 <= f_cal <= 325:
    sys.exit(f"the calibration fitted the encoder at {f_cal:.4g} Hz, true 250 Hz (allowed 175 .. 325)")
rep = json.load(open("diag/report.json"))
note = rep.get("calibration_reference", "")
if "is the reference" not in note:
    sys.exit(f"the calibration's recording was not the reference: {note}")
m = re.search(r"sensor\.encoder_bandwidth_Hz=([0-9.eE+-]+)", note)
if not m:
    sys.exit(f"the reference does not hold the calibrated encoder: {note}")
f_ref = float(m.group(1))
if abs(f_ref - f_cal) > 1e-9 * f_cal:
    sys.exit(f"the reference holds the encoder at {f_ref:.10g} Hz, the calibration fitted {f_cal:.10g} Hz")
if rep["verdict"] != "no_missing_physics":
    sys.exit(f"healthy recording came out {rep['verdict']}: {rep['summary']}")
print(f"calibration's encoder {f_cal:.4g} Hz (true 250), held at the reference; healthy: no missing physics")
PY
