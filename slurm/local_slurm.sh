#!/bin/sh
# Proves the sbatch scripts on a throw-away single-node Slurm on this machine
# (slurm/README.md, docs/cluster.md):
#
#   1. installs slurm-wlm and munge with apt if they are missing (root only;
#      they are not project dependencies);
#   2. starts munged (own key and socket), slurmctld and slurmd (own slurm.conf,
#      spool, state and logs, ports 16817/16818) under WORKDIR;
#   3. submits a 6-case campaign through slurm/sweep_node.sbatch (2 ranks),
#      sends it USR1 (Slurm's time-limit warning, --signal=B:USR1@300) once its
#      first case is done, so the script requeues itself, and waits: the
#      restarted job must resume (--resume) and finish the campaign;
#   4. runs the same campaign through slurm/sweep_multinode.sbatch (1 node here)
#      with LAUNCHER=srun (srun --mpi=pmix starts the ranks) and checks the
#      archive equals the first one;
#   5. if `planetwear sweep` has --cases: submits the same campaign as an array
#      job through slurm/sweep_array.sbatch (2 tasks x 3 cases) plus its merge
#      job, and checks the merged archive equals the single-job one;
#   6. checks the archives with scripts/pwcampaign.py (every case done) and
#      tests/sweep/check_archive.py; stops the daemons it started, by pid.
#
#   slurm/local_slurm.sh [-p PLANETWEAR] [-w WORKDIR] [-k]
#
#   -p  planetwear binary (default $PLANETWEAR, else the newest build*/apps/planetwear with `sweep`)
#   -w  work directory (default: a new /tmp/pw-local-slurm.XXXXXX)
#   -k  keep the work directory (default: removed on success)
#
# Must run as root (slurmd runs jobs as any user, munged as the munge user);
# exit 77 = skipped (not root, or Slurm missing and not installable).
# Exit 0 = every check passed, 1 = a check failed.
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
PLANETWEAR=${PLANETWEAR:-}
WORK=""
KEEP=0
while getopts "p:w:kh" opt; do
  case $opt in
    p) PLANETWEAR=$OPTARG ;;
    w) WORK=$OPTARG ;;
    k) KEEP=1 ;;
    *) sed -n '2,27p' "$0"; exit 2 ;;
  esac
done
PY=/usr/bin/python3
say() { echo "[local_slurm $(date -u +%T)] $*"; }
fail() { echo "[local_slurm] FAIL: $*" >&2; exit 1; }

if [ "$(id -u)" -ne 0 ]; then
  echo "local_slurm: SKIP: needs root (slurmd and munged are started here)"; exit 77
fi
if ! command -v slurmctld >/dev/null 2>&1 || ! command -v munged >/dev/null 2>&1 || ! command -v sbatch >/dev/null 2>&1; then
  if [ "${PW_NO_INSTALL:-0}" = 1 ]; then echo "local_slurm: SKIP: slurm-wlm/munge not installed"; exit 77; fi
  say "installing slurm-wlm and munge (apt)"
  if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        slurm-wlm munge >/dev/null; }; then
    echo "local_slurm: SKIP: slurm-wlm/munge missing and apt-get install failed"; exit 77
  fi
fi
if [ -z "$PLANETWEAR" ]; then
  # shellcheck disable=SC2045  # newest first; build directory names have no blanks
  for p in $(ls -t "$SRC"/build*/apps/planetwear 2>/dev/null); do
    if "$p" sweep --help >/dev/null 2>&1; then PLANETWEAR=$p; break; fi
  done
fi
[ -n "$PLANETWEAR" ] && [ -x "$PLANETWEAR" ] || fail "no planetwear binary (build it or pass -p)"
PLANETWEAR=$(cd "$(dirname "$PLANETWEAR")" && pwd)/$(basename "$PLANETWEAR")
[ -n "$WORK" ] || WORK=$(mktemp -d /tmp/pw-local-slurm.XXXXXX)
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)
chmod 755 "$WORK"  # munged (user munge) must reach its socket directory below
ST=$WORK/state
rm -rf "$ST"
mkdir -p "$ST/ctld" "$ST/d" "$ST/log" "$ST/munge"
say "work directory $WORK; planetwear $PLANETWEAR"

# ---- daemons (stopped on exit, by pid) ----------------------------------------
PIDS=""
JOBS=""
cleanup() {
  rc=$?
  trap - EXIT INT TERM
  if [ -n "$JOBS" ]; then
    # shellcheck disable=SC2086
    SLURM_CONF=$ST/slurm.conf scancel $JOBS 2>/dev/null || true
    sleep 1
  fi
  for pid in $PIDS; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in $PIDS; do
    i=0
    while kill -0 "$pid" 2>/dev/null && [ $i -lt 50 ]; do sleep 0.2; i=$((i + 1)); done
    kill -KILL "$pid" 2>/dev/null || true
  done
  [ -n "$PIDS" ] && say "stopped the daemons (pids$(printf ' %s' $PIDS))"
  if [ "$rc" -eq 0 ] && [ "$KEEP" -eq 0 ]; then rm -rf "$WORK"; fi
  if [ "$rc" -ne 0 ]; then
    echo "--- logs in $ST/log:"; tail -n 20 "$ST"/log/*.log 2>/dev/null || true
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# munged: a key of our own (1024 random bytes, owner munge, mode 400) and a socket of our own.
chown munge:munge "$ST/munge"
chmod 755 "$ST/munge"  # munged needs clients (root here) to reach the socket
dd if=/dev/urandom of="$ST/munge/munge.key" bs=1024 count=1 2>/dev/null
chown munge:munge "$ST/munge/munge.key"
chmod 400 "$ST/munge/munge.key"
SOCK=$ST/munge/munge.socket
setpriv --reuid=munge --regid=munge --init-groups munged -F --force --key-file="$ST/munge/munge.key" \
  --socket="$SOCK" --pid-file="$ST/munge/munged.pid" --seed-file="$ST/munge/munge.seed" \
  --log-file="$ST/log/munged.log" >>"$ST/log/munged.log" 2>&1 &
PIDS="$PIDS $!"
i=0; while [ ! -S "$SOCK" ] && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
[ -S "$SOCK" ] || fail "munged did not start (see $ST/log/munged.log)"

CPUS=$(nproc)
cat > "$ST/slurm.conf" <<EOF
# Single-node Slurm for slurm/local_slurm.sh (throw-away).
ClusterName=pwlocal
SlurmctldHost=localhost
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SOCK,cred_expire=10
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
MpiDefault=none
SwitchType=switch/none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
StateSaveLocation=$ST/ctld
SlurmdSpoolDir=$ST/d
SlurmctldPidFile=$ST/slurmctld.pid
SlurmdPidFile=$ST/slurmd.pid
SlurmctldLogFile=$ST/log/slurmctld.log
SlurmdLogFile=$ST/log/slurmd.log
ReturnToService=2
KillWait=5
MinJobAge=600
NodeName=localhost CPUs=$CPUS State=UNKNOWN
PartitionName=local Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$ST/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >>"$ST/log/slurmctld.out" 2>&1 &
PIDS="$PIDS $!"
slurmd -D -f "$SLURM_CONF" >>"$ST/log/slurmd.out" 2>&1 &
PIDS="$PIDS $!"
i=0
until sinfo -h -o '%T' 2>/dev/null | grep -q -e idle -e mixed; do
  i=$((i + 1)); [ $i -lt 120 ] || fail "the node did not come up (sinfo: $(sinfo 2>&1 | tail -1))"; sleep 0.5
done
say "Slurm is up: $(sinfo -h -o '%P %D %c %T' | head -1) (partition nodes cpus state)"

# ---- a small campaign ------------------------------------------------------
cat > "$WORK/small.toml" <<EOF
[campaign]
name = "local slurm check"
description = "6 short cases: speed x power at 1 recorded mesh cycle, a little wear"
[base]
config = "$SRC/config/seed.toml"
[base.set]
solver.record_mesh_cycles = 1
solver.warmup_max_mesh_cycles = 10
wear.mesh_cycles = 200
wear.window_mesh_cycles = 5
wear.elements_per_flank = 8
[[factors]]
key = "operating.input_speed_rpm"
unit = "rpm"
levels = [300.0, 400.0, 500.0]
[[factors]]
key = "operating.input_power_W"
unit = "W"
levels = [500.0, 1500.0]
[design]
type = "full_factorial"
[output]
time_history_decimation = 8
spectrum_max_frequency_Hz = 3000.0
EOF
cd "$WORK"

job_state() { scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -1; }
wait_jobs() {  # wait until none of the job ids $* is pending or running
  t=0
  while :; do
    busy=0
    for j in "$@"; do
      case $(squeue -h -j "$j" -o '%T' 2>/dev/null | head -1) in ?*) busy=1 ;; esac
    done
    [ $busy -eq 0 ] && return 0
    t=$((t + 1)); [ $t -lt 1200 ] || fail "jobs $* still running after 10 minutes"
    sleep 0.5
  done
}

# ---- 1. one node, 2 ranks, requeued in the middle ---------------------------------
T0=$(date +%s)
JOB=$(sbatch --parsable --ntasks-per-node=2 --cpus-per-task=1 --time=00:10:00 --output="$WORK/node-%j.log" \
  --export=ALL,CAMPAIGN=small.toml,ARCHIVE=node.h5,PLANETWEAR="$PLANETWEAR",SWEEP_ARGS=--checkpoint-cases=1 \
  "$SRC/slurm/sweep_node.sbatch")
JOBS="$JOBS $JOB"
say "submitted sweep_node.sbatch as job $JOB"
cases_done() {  # finished cases of archive $1: in the journal or in the archive
  n=$(ls "$1".journal/case-*.rec 2>/dev/null | wc -l)
  if [ "$n" -eq 0 ] && [ -e "$1" ]; then
    n=$($PY -c "import h5py; print(list(h5py.File('$1')['design/status'].asstr()[:]).count('done'))" 2>/dev/null || echo 0)
  fi
  echo "$n"
}
i=0
until [ "$(cases_done node.h5)" -gt 0 ]; do
  i=$((i + 1)); [ $i -lt 1200 ] || fail "job $JOB journaled no case in 10 minutes"
  [ -n "$(squeue -h -j "$JOB" 2>/dev/null)" ] || break
  sleep 0.2
done
if [ -n "$(squeue -h -j "$JOB" -t RUNNING 2>/dev/null)" ]; then
  # What Slurm does 300 s before the time limit (--signal=B:USR1@300): USR1 to
  # the batch shell, whose trap requeues the job.
  scancel --batch --signal=USR1 "$JOB"
  say "sent USR1 (the time-limit warning) to job $JOB after its first finished case: it requeued itself"
  # A requeued job waits about a minute before it may start again. It must not
  # start before slurmd forgets the killed run's credential (cred_expire = 10 s
  # in slurm.conf above), else it is killed as "Job credential revoked": wait
  # 12 s, then let it start.
  i=0
  until [ "$(job_state "$JOB")" = PENDING ] || [ $i -ge 100 ]; do sleep 0.2; i=$((i + 1)); done
  sleep 12
  scontrol update JobId="$JOB" StartTime=now || true
  REQUEUED=1
else
  say "job $JOB finished before it could be requeued"
  REQUEUED=0
fi
wait_jobs "$JOB"
say "job $JOB: $(job_state "$JOB") after $(( $(date +%s) - T0 )) s; restarts: $(grep -c 'restart [1-9]' "$WORK/node-$JOB.log" || true)"
[ "$(job_state "$JOB")" = COMPLETED ] || { cat "$WORK/node-$JOB.log"; fail "job $JOB did not complete"; }
if [ "$REQUEUED" -eq 1 ]; then
  grep -q -e 'time limit near: requeueing' "$WORK/node-$JOB.log" || { cat "$WORK/node-$JOB.log"; fail "USR1 did not requeue the job"; }
  grep -q -e '--resume' "$WORK/node-$JOB.log" || { cat "$WORK/node-$JOB.log"; fail "the requeued job did not resume"; }
fi
echo "--- node-$JOB.log:"; grep -e '^\[' -e '^+ ' -e 'sweep:' "$WORK/node-$JOB.log" | grep -v '^\[sweep\]' || true
$PY "$SRC/tests/sweep/check_archive.py" complete node.h5 || fail "node.h5 is not complete"
$PY - <<EOF || fail "node.h5 does not load with all cases done"
import sys; sys.path.insert(0, "$SRC/scripts")
import pwcampaign
c = pwcampaign.load("node.h5")
print(pwcampaign.summary(c))
assert c.cases == 6 and c.done.all(), c.design["status"].tolist()
print(c.design[["operating.input_speed_rpm", "operating.input_power_W", "rank", "max_wear/sun",
                "sun_planet/0/acceleration_rms"]].to_string())
EOF

# ---- 2. the multi-node script (on this one node), ranks started by srun (PMIx) ----
T0=$(date +%s)
MNJOB=$(sbatch --parsable --nodes=1 --ntasks-per-node=2 --cpus-per-task=1 --time=00:10:00 \
  --output="$WORK/multinode-%j.log" \
  --export=ALL,CAMPAIGN=small.toml,ARCHIVE=multinode.h5,PLANETWEAR="$PLANETWEAR",LAUNCHER=srun \
  "$SRC/slurm/sweep_multinode.sbatch")
JOBS="$JOBS $MNJOB"
say "submitted sweep_multinode.sbatch (LAUNCHER=srun) as job $MNJOB"
wait_jobs "$MNJOB"
say "job $MNJOB: $(job_state "$MNJOB") after $(( $(date +%s) - T0 )) s"
grep -e '^\[' -e '^+ ' -e 'sweep:' "$WORK/multinode-$MNJOB.log" | grep -v '^\[sweep\]' || true
[ "$(job_state "$MNJOB")" = COMPLETED ] || { cat "$WORK/multinode-$MNJOB.log"; fail "job $MNJOB did not complete"; }
$PY "$SRC/tests/sweep/check_archive.py" same multinode.h5 node.h5 || fail "multinode.h5 differs from node.h5"

# ---- 3. array job + merge ----------------------------------------------------
if "$PLANETWEAR" sweep --help 2>/dev/null | grep -q -e '--cases'; then
  T0=$(date +%s)
  AJOB=$(sbatch --parsable --array=0-1 --ntasks=1 --cpus-per-task=1 --time=00:10:00 \
    --output="$WORK/array-%A_%a.log" \
    --export=ALL,CAMPAIGN=small.toml,ARCHIVE=array.h5,PLANETWEAR="$PLANETWEAR",CASES_PER_TASK=3 \
    "$SRC/slurm/sweep_array.sbatch")
  MJOB=$(sbatch --parsable --dependency=afterany:"$AJOB" --ntasks=1 --time=00:10:00 --output="$WORK/merge-%j.log" \
    --export=ALL,CAMPAIGN=small.toml,ARCHIVE=array.h5,MERGE="$SRC/scripts/merge_archives.py" \
    "$SRC/slurm/sweep_array.sbatch")
  JOBS="$JOBS $AJOB $MJOB"
  say "submitted sweep_array.sbatch as array job $AJOB (2 tasks) and its merge as job $MJOB"
  wait_jobs "$AJOB" "$MJOB"
  say "array + merge done after $(( $(date +%s) - T0 )) s: merge job $(job_state "$MJOB")"
  cat "$WORK"/array-*.log "$WORK"/merge-*.log | grep -e '^\[' -e 'merge_archives' || true
  [ "$(job_state "$MJOB")" = COMPLETED ] || fail "merge job $MJOB did not complete"
  ls -l array.cases-*.h5
  $PY "$SRC/tests/sweep/check_archive.py" same array.h5 node.h5 || fail "merged array archive differs from node.h5"
  $PY "$SRC/scripts/pwcampaign.py" array.h5
else
  say "array variant SKIPPED: $PLANETWEAR sweep has no --cases option yet (slurm/README.md)"
fi
say "all checks passed"
