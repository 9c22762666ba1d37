#!/bin/sh
# The table of docs/benchmark.md ("Fast core"), measured again: re-run it whenever
# the time step changes. Prints Markdown rows for one build, or for two side by
# side (e.g. a build of the previous commit as the baseline).
#
#   bench/bench_table.sh [BUILD_DIR] [BASELINE_BUILD_DIR]     (default: build)
#
# Rows: torsional ns/step and force evaluations/step at 100, 200, 400 rpm
# (warm-up dominated: 1 recorded mesh period, so storing channels does not
# enter), lateral-torsional at 100 rpm, the seed wear case (2e5 mesh cycles,
# 100 rpm, 1 thread), `planetwear simulate` of 1 s of physics at 200 rpm with
# the default output (every channel at every step) and with
# --time-history-decimation 32, and the numpy RK4 peer (bench/peer_rk4.py).
# Single-threaded throughout; the machine's load is printed first, since
# figures from a loaded machine are slower by up to the load / cores.
set -eu
BUILD=${1:-build}
BASE=${2:-}
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3
export OMP_NUM_THREADS=1
echo "machine: $(nproc --all) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%Y-%m-%dT%H:%MZ)"

# ns/step, force evaluations per step and simulated mesh cycles (warm-up + recording) per core-second
# from bench_simulate's table: the 3rd, 2nd and 4th columns from the end since the page-fault column
# (session 45); a binary from before it has them one column further right.
step_cost() {  # BUILD RPM [extra args]
  b=$1; rpm=$2; shift 2
  "$b/bench/bench_simulate" "$rpm" --record-cycles 1 --repeat 3 "$@" 2>/dev/null |
    awk -v r="$rpm" '$1 == r && NF >= 17 && $NF ~ /^[0-9]+$/ && $(NF - 1) ~ /\./ {
                       printf "%s ns/step, %s evals/step, %s mesh cycles/core-s, %s page faults", $(NF - 2), $(NF - 1),
                              $(NF - 3), $NF; exit }
                     $1 == r && NF >= 16 { printf "%s ns/step, %s evals/step, %s mesh cycles/core-s", $(NF - 1), $NF,
                              $(NF - 2); exit }'
}
wear_case() {  # BUILD -> CPU seconds of the 100 rpm seed wear case, 1 thread
  "$1/bench/bench_wear" --threads 1 --repeat 1 100 2>/dev/null |
    awk '$1 == 100 && $2 == 1 { printf "%s s CPU (%s s wall)", $4, $3; exit }'
}
simulate_1s() {  # BUILD [extra args] -> whole-command wall and CPU time
  b=$1; shift
  out=$(mktemp -d)
  "$PY" - "$b/apps/planetwear" "$out/s.h5" "$@" <<'PY'
import resource, subprocess, sys, time
exe, out, extra = sys.argv[1], sys.argv[2], sys.argv[3:]
t0 = time.perf_counter()
subprocess.run([exe, "simulate", "-q", "--speed-rpm", "200", "--set", "solver.record_mesh_cycles=56", "-o", out] + extra,
               check=True)
wall = time.perf_counter() - t0
ru = resource.getrusage(resource.RUSAGE_CHILDREN)
print(f"{ru.ru_utime + ru.ru_stime:.2f} s CPU ({wall:.2f} s wall)", end="")
PY
  rm -rf "$out"
}
row() {  # LABEL COMMAND...
  label=$1; shift
  new=$("$@" "$BUILD")
  if [ -n "$BASE" ]; then
    old=$("$@" "$BASE")
    echo "| $label | $old | $new |"
  else
    echo "| $label | $new |"
  fi
}
t100() { step_cost "$1" 100; }
t200() { step_cost "$1" 200; }
t400() { step_cost "$1" 400; }
lt100() { step_cost "$1" 100 --set solver.level=lateral_torsional; }
sim_default() { simulate_1s "$1"; }
sim_dec() { simulate_1s "$1" --time-history-decimation 32; }

if [ -n "$BASE" ]; then
  echo "| quantity | $BASE | $BUILD |"
  echo "|---|---|---|"
else
  echo "| quantity | $BUILD |"
  echo "|---|---|"
fi
row "torsional, 100 rpm" t100
row "torsional, 200 rpm" t200
row "torsional, 400 rpm" t400
row "lateral-torsional, 100 rpm" lt100
row "seed wear case, 2e5 cycles, 100 rpm, 1 thread" wear_case
row "simulate 1 s at 200 rpm, all channels every step" sim_default
if [ -z "$BASE" ] || "$BASE/apps/planetwear" simulate --help 2>/dev/null | grep -q time-history-decimation; then
  row "simulate 1 s at 200 rpm, --time-history-decimation 32" sim_dec
fi
echo
"$PY" "$(dirname "$0")/peer_rk4.py" --seconds 0.1
