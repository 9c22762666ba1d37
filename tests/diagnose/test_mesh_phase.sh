#!/bin/sh
# A recording whose mesh lines are locked to time (a simulator exciting the mesh with k(t),
# stiffness.mesh_phase = nominal_time) under a 3 % torque ripple is named torque_ripple with its
# mesh stiffness locked to nominal time and its fraction within 20 %; the same ripple recorded
# from gears that mesh by their roll (the default) is named torque_ripple without that variant.
# Seed stage, 1200 rpm, 20 kW, 0.78 s, 5 % noise (docs/diagnose.md §5, the lead's mesh phase;
# measured 2026-11-28: 0.0298 and 0.0300, about 35 s each at 1 thread).
# Usage: test_mesh_phase.sh <planetwear> <workdir>
set -eu
PW=$1
rm -rf "$2"; mkdir -p "$2"; cd "$2"
for phase in nominal_time rotation; do
  "$PW" synth -q --speed-rpm 1200 --power-w 20000 --seconds 0.78 --noise 0.05 --dc-offset 0.2 --seed 5 \
    --sensor-angle-deg 40 --decimate 40 --start-mesh-cycle 450 --set imperfections.torque_ripple_fraction=0.03 \
    --set stiffness.mesh_phase=$phase --set solver.periodicity_tolerance=1e-3 -o ripple_$phase.csv
  OMP_NUM_THREADS=1 "$PW" diagnose -q -r ripple_$phase.csv -o report_$phase --threads 1 --no-plots
done
/usr/bin/python3 - <<'PY'
import json, sys
for phase in ("nominal_time", "rotation"):
    r = json.load(open(f"report_{phase}/report.json"))
    if r["verdict"] != "missing_physics_found" or r["missing_physics"] != "torque_ripple":
        sys.exit(f"{phase}: verdict {r['verdict']} ({r['missing_physics']}), expected torque_ripple: " + r["summary"][:300])
    lead = r["candidates"][0]
    locked = "nominal_time" in lead["variant"]
    if locked != (phase == "nominal_time"):
        sys.exit(f"{phase}: variant '{lead['variant']}' says the mesh is {'' if locked else 'not '}locked to time")
    if locked and "stiffness.mesh_phase=nominal_time" not in " ".join(r["final_overrides"]):
        sys.exit(f"{phase}: final_overrides lack stiffness.mesh_phase=nominal_time: {r['final_overrides']}")
    f = next(p["value"] for p in lead["parameters"] if p["name"] == "torque_ripple_fraction")
    if abs(f / 0.03 - 1) > 0.2:
        sys.exit(f"{phase}: torque_ripple_fraction {f} not within 20 % of 0.03")
    print(f"{phase}: {r['summary'][:160]}")
PY
