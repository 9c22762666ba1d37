#!/bin/sh
# Benchmark of `planetwear diagnose`: time to diagnose 2 s recordings at 800 rpm on
# 1 rank x 1 thread, 1 rank x 2 threads and 2 MPI ranks x 1 thread (mpirun -np 2:
# rank 1 serves simulations), and where the time goes, from the report's "timing"
# block (docs/diagnose.md, "Status and measured results").
#
#   bench/bench_diagnose.sh [BUILD_DIR] [SECONDS]      (defaults: build, 2.0)
#   RUNS="1x1" bench/bench_diagnose.sh build            (only some of the ranks x threads runs)
#
# Two recordings are synthesized with `planetwear synth` as the corpus makes
# them (seed gear set, 800 rpm, 20 kW, 2 s = 5.5 carrier revolutions, 7 %
# noise, 30 % accelerometer offsets, solver.time_step_s = 2.5e-6 and a warm-up
# to periodicity 1e-3): a control (baseline, nuisance fit and noise test only) and a
# damaged sun tooth (screening, candidate fits, phase variants).
# MPIEXEC (default: mpiexec on PATH) launches the 2-rank runs; as root Open MPI needs
# --allow-run-as-root, added here only when we are root.
set -eu
BUILD=${1:-build}
SECONDS_REC=${2:-2.0}
PW="$BUILD/apps/planetwear"
[ -x "$PW" ] || { echo "bench_diagnose: no $PW (build first)" >&2; exit 1; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
COMMON="--speed-rpm 800 --power-w 20000 --seconds $SECONDS_REC --noise 0.07 --dc-offset 0.3 --sensor-angle-deg 35
  --decimate 40 --start-mesh-cycle 450 --set solver.time_step_s=2.5e-6 --set solver.periodicity_tolerance=1e-3"
# shellcheck disable=SC2086
"$PW" synth -q $COMMON --seed 5 -o "$WORK/control.csv"
# shellcheck disable=SC2086
"$PW" synth -q $COMMON --seed 6 --set 'imperfections.teeth=[{body="sun",tooth=5,stiffness_factor=0.6}]' \
  -o "$WORK/sun_tooth.csv"
MPIRUN=${MPIEXEC:-mpiexec}
if "$MPIRUN" --version 2>&1 | grep -q -i -e "Open MPI" -e "OpenRTE" -e "open-mpi.org"; then
  MPIRUN="$MPIRUN --oversubscribe"
  [ "$(id -u)" -ne 0 ] || MPIRUN="$MPIRUN --allow-run-as-root"
fi
for REC in control sun_tooth; do
  for RUN in ${RUNS:-1x1 1x2 2x1}; do
    P=${RUN%x*}; T=${RUN#*x}
    LAUNCH=""
    [ "$P" -eq 1 ] || LAUNCH="$MPIRUN -x OMP_NUM_THREADS -np $P"
    start=$(date +%s.%N)
    # shellcheck disable=SC2086
    OMP_NUM_THREADS=$T $LAUNCH "$PW" diagnose -q --recording "$WORK/$REC.csv" -o "$WORK/report_${REC}_$RUN" \
      --threads "$T" --no-plots >/dev/null
    end=$(date +%s.%N)
    /usr/bin/python3 - "$WORK/report_${REC}_$RUN/report.json" "$REC" "$P" "$T" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); t = r["timing"]
wall = float(sys.argv[6]) - float(sys.argv[5])
phases = ["analysis_s", "baseline_s", "nuisance_s", "screening_s", "candidates_s", "phase_s"]
split = " ".join(f"{p[:-2]} {t.get(p, 0):.1f}" for p in phases)
print(f"{sys.argv[2]:9s} ranks {sys.argv[3]} x threads {sys.argv[4]}: wall {wall:6.1f} s | {t['simulations']} "
      f"simulations, {t['simulate_s_summed']:.1f} s summed over slots | {split} | {r['verdict']} "
      f"({r.get('missing_physics')})", flush=True)
PY
  done
done
