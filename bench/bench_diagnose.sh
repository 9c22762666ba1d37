#!/bin/sh
# Benchmark of `planetwear diagnose`: time to diagnose one 400 rpm recording
# on 1 and 2 OpenMP threads, and where the time goes (simulations, features,
# locate, fitting overhead), from the report's "timing" block.
#
#   bench/bench_diagnose.sh [BUILD_DIR] [SECONDS]      (defaults: build-diag, 2.2)
#
# The recording is synthesized with `planetwear synth` (seed gear set, 400 rpm,
# 10 kW, a damaged sun tooth so that the candidate fits run too, 5 % noise).
# SECONDS defaults to 2.2 s: the recording reader needs >= 3 carrier revolutions
# (2.19 s at 400 rpm), so a 2 s recording is rejected. MPI ranks: not
# implemented (the diagnosis parallelizes over OpenMP threads only).
set -eu
BUILD=${1:-build-diag}
SECONDS_REC=${2:-2.2}
PW="$BUILD/apps/planetwear"
[ -x "$PW" ] || { echo "bench_diagnose: no $PW (build first)" >&2; exit 1; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
"$PW" synth -q --speed-rpm 400 --power-w 10000 --seconds "$SECONDS_REC" --noise 0.05 --dc-offset 0.2 --seed 3 \
  --sensor-angle-deg 30 --decimate 40 --set 'imperfections.teeth=[{body="sun",tooth=5,stiffness_factor=0.6}]' \
  -o "$WORK/rec.csv"
for T in 1 2; do
  start=$(date +%s.%N)
  OMP_NUM_THREADS=$T "$PW" diagnose -q --recording "$WORK/rec.csv" -o "$WORK/report_$T" --threads "$T" --no-plots >/dev/null
  end=$(date +%s.%N)
  /usr/bin/python3 - "$WORK/report_$T/report.json" "$T" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); t = r["timing"]
wall = float(sys.argv[4]) - float(sys.argv[3])
print(f"threads {sys.argv[2]}: wall {wall:6.1f} s | {t['simulations']} simulations, {t['simulate_s_summed']:.1f} s "
      f"summed | features {t['features_s']:.1f} s | locate {t['locate_s']:.1f} s | fit overhead "
      f"{t['fit_overhead_s']:.1f} s | verdict {r['verdict']} ({r.get('missing_physics')})")
PY
done
