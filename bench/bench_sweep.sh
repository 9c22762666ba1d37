#!/bin/sh
# Strong scaling of `planetwear sweep` from 1 to 2 MPI ranks (rank 0 computes
# too, so 2 ranks = 2 cores busy) on a campaign of >= 16 cases, and what the
# driver costs: rank 0's MPI + journal time and the checkpoint writes (on a
# thread of their own) against the total case time. A third run checkpoints
# after every case to show that archive writes overlap the computation
# instead of serializing it. The three archives must hold identical numbers.
#
# Usage: bench/bench_sweep.sh [campaign.toml]      (default sweep/campaigns/demo_lhs.toml)
#   BUILD_DIR=build-sweep bench/bench_sweep.sh
# Results of one run are in docs/campaigns.md ("Performance").
set -eu
cd "$(dirname "$0")/.."
PW=$(pwd)/${BUILD_DIR:-build}/apps/planetwear
CAMPAIGN=$(realpath "${1:-sweep/campaigns/demo_lhs.toml}")
[ -x "$PW" ] || { echo "bench_sweep: $PW not built (scripts/build.sh)" >&2; exit 1; }
MPIRUN=mpirun
if [ "$(id -u)" -eq 0 ]; then MPIRUN="$MPIRUN --allow-run-as-root"; fi
CORES=$(nproc)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/bench_sweep.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
export OMP_NUM_THREADS=1   # one thread per rank: the scaling is over ranks

now() { date +%s.%N; }
# run <label> <command...>: wall time of the whole command (incl. MPI start-up)
run() {
  label=$1; shift
  t0=$(now)
  "$@" 2> "$WORK/$label.log" || [ $? -eq 4 ]
  t1=$(now)
  echo "$t0 $t1" > "$WORK/$label.time"
}

echo "bench_sweep: $CAMPAIGN on $CORES cores, load average $(cut -d" " -f1-3 /proc/loadavg), OMP_NUM_THREADS=1"
run np1 "$PW" sweep --checkpoint-cases 100000 "$CAMPAIGN" -o "$WORK/np1.h5"
run np2 $MPIRUN -np 2 "$PW" sweep --checkpoint-cases 100000 "$CAMPAIGN" -o "$WORK/np2.h5"
run np2c $MPIRUN -np 2 "$PW" sweep --checkpoint-cases 1 "$CAMPAIGN" -o "$WORK/np2c.h5"

/usr/bin/python3 - "$WORK" <<'EOF'
import re, sys, h5py, numpy as np
work = sys.argv[1]
summary = re.compile(r"(\d+) cases run in ([\d.]+) s on (\d+) ranks? \(case time ([\d.]+) s\); rank-0 driver busy "
                     r"([\d.]+) s \(MPI \+ journal\), (\d+) checkpoints in ([\d.]+) s on the writer thread \(max "
                     r"([\d.]+) s\), final archive ([\d.]+) s; while checkpoints were written (\d+) case runs were "
                     r"in progress and (\d+) finished")
rows = {}
for label in ("np1", "np2", "np2c"):
    log = open(f"{work}/{label}.log").read()
    m = summary.search(log)
    if not m:
        sys.exit(f"bench_sweep: no summary in {label}.log:\n{log}")
    t0, t1 = map(float, open(f"{work}/{label}.time").read().split())
    rows[label] = dict(cases=int(m[1]), driver_wall=float(m[2]), ranks=int(m[3]), case_time=float(m[4]),
                       busy=float(m[5]), checkpoints=int(m[6]), ckpt_time=float(m[7]), ckpt_max=float(m[8]),
                       final=float(m[9]), running=int(m[10]), overlap=int(m[11]), wall=t1 - t0)
    with h5py.File(f"{work}/{label}.h5") as f:
        w = f["design/wall_time"][:]
        rows[label]["case_min"], rows[label]["case_max"] = float(np.nanmin(w)), float(np.nanmax(w))

print()
print("| run | ranks | wall [s] (mpirun incl.) | driver wall [s] | sum of case times [s] | speed-up | parallel efficiency "
      "| rank-0 MPI + journal [s] | checkpoints (writer thread) [s] | final archive [s] | case runs in progress / finished during checkpoints |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
base = rows["np1"]["wall"]
for label, name in (("np1", "-np 1 (no mpirun)"), ("np2", "mpirun -np 2"), ("np2c", "mpirun -np 2, checkpoint every case")):
    r = rows[label]
    s = base / r["wall"]
    print(f"| {name} | {r['ranks']} | {r['wall']:.2f} | {r['driver_wall']:.2f} | {r['case_time']:.2f} | {s:.2f} | "
          f"{s / r['ranks']:.0%} | {r['busy']:.3f} | {r['checkpoints']} in {r['ckpt_time']:.3f} (max {r['ckpt_max']:.3f}) | "
          f"{r['final']:.3f} | {r['running']} / {r['overlap']} |")
r1 = rows["np1"]
print()
print(f"cases: {r1['cases']}, case wall times {r1['case_min']:.2f}-{r1['case_max']:.2f} s (-np 1)")
for label in ("np2", "np2c"):
    r = rows[label]
    print(f"{label}: ranks busy with cases {r['case_time'] / (r['ranks'] * r['driver_wall']):.0%} of the driver's wall time; "
          f"a case takes {r['case_time'] / r1['case_time']:.2f}x as long as with one rank (cores shared with "
          f"other processes, memory bandwidth)")
for label in ("np2", "np2c"):
    r = rows[label]
    over = (r["busy"] + r["ckpt_time"] + r["final"]) / r["case_time"]
    print(f"{label}: driver + archive work = {over:.2%} of the case time "
          f"(rank-0 MPI + journal {r['busy']:.3f} s, checkpoints {r['ckpt_time']:.3f} s, final archive {r['final']:.3f} s)")
c = rows["np2c"]
print(f"checkpoint after every case: {c['checkpoints']} archive rewrites took {c['ckpt_time']:.2f} s on the writer "
      f"thread while {c['running']} case runs were in progress ({c['overlap']} finished meanwhile); wall time "
      f"{c['wall'] - rows['np2']['wall']:+.2f} s against no intermediate checkpoints (serialized writes would add "
      f">= {c['ckpt_time']:.2f} s)")
EOF
/usr/bin/python3 tests/sweep/check_archive.py same "$WORK/np1.h5" "$WORK/np2.h5"
/usr/bin/python3 tests/sweep/check_archive.py same "$WORK/np1.h5" "$WORK/np2c.h5"
