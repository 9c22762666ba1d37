#!/bin/sh
# Short recordings (docs/diagnose.md §2 "Short recordings"): 2 s of the seed gears.
#   control200: 200 rpm, 10 kW, no effect (1.37 carrier revolutions, halves of 42 mesh cycles):
#     accepted, "no_missing_physics", the planet/carrier/input-shaft families and their
#     candidates listed as unresolved (report.json, report.md, the summary on stdout).
#   control100: 100 rpm, 10 kW, no effect (0.69 carrier revolutions, halves of 21 mesh cycles,
#     the second ending at the record's last sample): "no_missing_physics". Until session 43 the
#     angle reference's mesh-period average was clipped at the record's ends and this control
#     failed on its held-out half (3804 against a bound of 3124; now 2843 against 3145).
#   sun200: the same with sun tooth 5 at stiffness factor 0.6: named sun_tooth_damage or
#     unexplained, never another name.
#   sun400: 400 rpm, 10 kW, sun tooth at 0.6 (2.75 carrier revolutions: halves of one whole
#     revolution): named sun_tooth_damage or unexplained, never another name.
#   refused: 0.3 s at 100 rpm (8.3 mesh cycles) is refused with exit code 1, the minimum
#     (2 Zs = 42 mesh cycles) and the recording's own count in the message.
# Usage: test_short_recording.sh <planetwear> <workdir> control200|control100|sun200|sun400|refused
set -eu
PW=$1
CASE=$3
rm -rf "$2"; mkdir -p "$2"; cd "$2"
SYNTH="--power-w 10000 --noise 0.05 --dc-offset 0.2 --sensor-angle-deg 40 --decimate 40 --start-mesh-cycle 120
  --set solver.time_step_s=2.5e-6 --set solver.periodicity_tolerance=1e-3"
SUN='imperfections.teeth=[{body="sun",tooth=5,stiffness_factor=0.6}]'
case $CASE in
  control200) "$PW" synth -q --speed-rpm 200 --seconds 2 --seed 21 $SYNTH -o rec.csv ;;
  control100) "$PW" synth -q --speed-rpm 100 --seconds 2 --seed 23 $SYNTH -o rec.csv ;;
  sun200) "$PW" synth -q --speed-rpm 200 --seconds 2 --seed 13 $SYNTH --set "$SUN" -o rec.csv ;;
  sun400) "$PW" synth -q --speed-rpm 400 --seconds 2 --seed 12 $SYNTH --set "$SUN" -o rec.csv ;;
  refused)
    "$PW" synth -q --speed-rpm 100 --seconds 0.3 --seed 1 $SYNTH -o rec.csv 2>/dev/null
    set +e
    "$PW" diagnose -q -r rec.csv -o report --threads 1 --no-plots 2>err.txt
    rc=$?
    set -e
    cat err.txt
    [ $rc -eq 1 ] || { echo "exit code $rc, expected 1"; exit 1; }
    grep -q "needs at least 42 mesh cycles" err.txt || { echo "minimum not in the message"; exit 1; }
    grep -q "holds 8.3" err.txt || { echo "the recording's mesh cycles not in the message"; exit 1; }
    exit 0 ;;
  *) echo "unknown case $CASE"; exit 2 ;;
esac
OMP_NUM_THREADS=1 "$PW" diagnose -q -r rec.csv -o report --threads 1 --no-plots > summary.txt
cat summary.txt
CASE=$CASE /usr/bin/python3 - <<'PY'
import json, os, sys
case = os.environ["CASE"]
r = json.load(open("report/report.json"))
md = open("report/report.md").read()
summary = open("summary.txt").read()
un = r["unresolved"]
if case == "control200":
    if r["verdict"] != "no_missing_physics":
        sys.exit(f"control: verdict {r['verdict']}, expected no_missing_physics")
    if r["halves"].get("mesh_cycles_each") != 42:
        sys.exit(f"halves {r['halves']}: expected 42 mesh cycles each")
    if set(un["families"]) != {"planet", "carrier", "input_shaft"}:
        sys.exit(f"unresolved families {un['families']}")
    for c in ("pin_error", "carrier_runout", "ring_tooth_damage", "planet_tooth_damage", "torque_ripple"):
        if c not in un["candidates"]:
            sys.exit(f"{c} not listed as unresolved: {un['candidates']}")
    fitted = {c["name"] for c in r["candidates"]} | {s["name"] for s in r["screening"]}
    if fitted & set(un["candidates"]):
        sys.exit(f"unresolved candidates screened or fitted: {fitted & set(un['candidates'])}")
    if "Could not be resolved in 1.37 carrier revolutions" not in summary or "pin_error" not in summary:
        sys.exit("the summary does not list what could not be resolved")
    if "Could not be resolved in 1.37 carrier revolutions" not in md:
        sys.exit("report.md does not list what could not be resolved")
elif case == "control100":
    if r["verdict"] != "no_missing_physics":
        sys.exit(f"control at 100 rpm: verdict {r['verdict']}, expected no_missing_physics: {r['summary'][:300]}")
    if r["halves"].get("mesh_cycles_each") != 21:
        sys.exit(f"halves {r['halves']}: expected 21 mesh cycles each")
else:
    named = r["missing_physics"]
    if r["verdict"] == "missing_physics_found" and named != "sun_tooth_damage":
        sys.exit(f"sun tooth named {named}: a wrong confident name")
    if r["verdict"] not in ("missing_physics_found", "unexplained_residual"):
        sys.exit(f"sun tooth: verdict {r['verdict']}")
    if case == "sun200" and "sun_tooth_damage" in un["candidates"]:
        sys.exit("sun_tooth_damage listed as unresolved")
print(case, r["verdict"], r["missing_physics"], "unresolved:", un)
PY
