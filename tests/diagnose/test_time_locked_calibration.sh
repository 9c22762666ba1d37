#!/bin/sh
# A calibration chooses the mesh form of its model (docs/diagnose.md §6a item 9): healthy recordings
# of the seed stage from a simulator that excites the mesh with k(t) (stiffness.mesh_phase =
# nominal_time) at 300 and 400 rpm, 20 kW, 2 s, 5 % noise; and the same stage meshing by roll.
#  * the k(t) calibration's model is time-locked (calibration.mesh_phase = "nominal_time", printed as
#    a --set line); the roll-locked one stays "rotation" (its healthy fits pass the noise test: no
#    probe, no refit);
#  * a held-out k(t) healthy recording at 350 rpm diagnosed with the k(t) calibration: "no missing
#    physics", its nuisance model in that form (report.json nuisance_mesh_phase);
#  * an 8 um pin error on planet 1 at 350 rpm (k(t)), with that calibration: pin_error or its class
#    planet_position_error (on three planets a carrier runout displaces the planets as two pin
#    errors do: a near-alias, docs/diagnose.md §4).
# About 70 s at 1 thread. Usage: test_time_locked_calibration.sh <planetwear> <workdir>
set -eu
PW=$1
rm -rf "$2"; mkdir -p "$2"; cd "$2"
synth() {  # name rpm seed phase [--set ...]
  name=$1; rpm=$2; seed=$3; phase=$4; shift 4
  "$PW" synth -q --speed-rpm "$rpm" --power-w 20000 --seconds 2 --noise 0.05 --dc-offset 0.2 --seed "$seed" \
    --sensor-angle-deg 40 --decimate 40 --set stiffness.mesh_phase="$phase" "$@" -o "$name.csv"
}
synth kt_300 300 300 nominal_time
synth kt_400 400 400 nominal_time
synth kt_350 350 350 nominal_time
synth kt_pin 350 6 nominal_time --set "imperfections.pin_error_m=[0,8e-6,0]"
synth roll_300 300 300 rotation
synth roll_400 400 400 rotation
export OMP_NUM_THREADS=1
"$PW" calibrate -q -r kt_300.csv -r kt_400.csv -o cal_kt.toml --threads 1 > cal_kt.txt
"$PW" calibrate -q -r roll_300.csv -r roll_400.csv -o cal_roll.toml --threads 1 > cal_roll.txt
grep -q "^ *mesh_phase = 'nominal_time'" cal_kt.toml || { echo "k(t) calibration: not time-locked"; grep mesh_phase cal_kt.toml; exit 1; }
grep -q -- "--set stiffness.mesh_phase=nominal_time" cal_kt.txt || { echo "k(t) calibration: the printed model lacks the form"; exit 1; }
grep -q "^ *mesh_phase = 'rotation'" cal_roll.toml || { echo "roll calibration: not roll-locked"; grep mesh_phase cal_roll.toml; exit 1; }
for r in kt_350 kt_pin; do
  "$PW" diagnose -q -r $r.csv --calibration cal_kt.toml -o report_$r --threads 1 --no-plots
done
/usr/bin/python3 - <<'PY'
import json, sys
r = json.load(open("report_kt_350/report.json"))
if r["verdict"] != "no_missing_physics" or r["nuisance_mesh_phase"] != "nominal_time":
    sys.exit(f"held-out k(t) healthy: {r['verdict']}, mesh {r['nuisance_mesh_phase']}: " + r["summary"][:300])
print("held-out k(t) healthy:", r["summary"][:160])
r = json.load(open("report_kt_pin/report.json"))
if r["verdict"] != "missing_physics_found" or r["missing_physics"] not in ("pin_error", "planet_position_error"):
    sys.exit(f"k(t) pin error: {r['verdict']} ({r['missing_physics']}): " + r["summary"][:300])
print("k(t) pin error:", r["summary"][:160])
PY
