#!/bin/sh
# Crash safety of `planetwear sweep` (docs/archive-format.md): kill -9 the
# whole job (mpirun and every rank at once, as a node failure would) at
# several moments, with a checkpoint after every case so that kills land
# while cases run, while results are journaled and while the archive is
# rewritten and renamed. After each kill the archive must open with h5py and
# every case it marks done or failed must equal the uninterrupted reference;
# --resume (killed once more, then run to the end) must give exactly the
# reference's numbers and leave no journal. Also with one process (no mpirun).
# Usage: test_kill_resume.sh <planetwear> <mpiexec> <workdir> <tests/sweep>
set -eu
PW=$1; T=$4
. "$T/mpi.sh"
mpi_launcher "$2"
rm -rf "$3"; mkdir -p "$3"; cd "$3"
CAMPAIGN=$T/data/kill.toml
CHECK="/usr/bin/python3 $T/check_archive.py"
export OMP_NUM_THREADS=1

# Uninterrupted reference (one case of the campaign fails: exit 4).
run $MPIRUN -np 2 "$PW" sweep --quiet "$CAMPAIGN" -o ref.h5
[ "$RC" -ne 0 ] || fail "reference run: exit 0, expected 4 (one case fails)"
$CHECK complete ref.h5

# Kill moments follow the run's progress, not the clock, so that they spread
# over the run on a fast or a loaded machine: after the archive has been
# replaced $1 times (with --checkpoint-cases 1: the initial archive, then
# once per finished case) plus $2 seconds; $1 = 0: after $2 seconds.
wait_and_kill() {
  n=0; last=""
  while [ "$n" -lt "$1" ] && kill -0 "$SESSION" 2>/dev/null; do
    cur=$(stat -c %i run.h5 2>/dev/null || echo none)
    if [ "$cur" != none ] && [ "$cur" != "$last" ]; then n=$((n + 1)); last=$cur; fi
    sleep 0.005
  done
  sleep "$2"
  kill_session "$SESSION"
}

# After a kill: whatever is on disk must be consistent.
check_killed() {
  if [ -f run.h5 ]; then
    $CHECK partial run.h5 ref.h5 || fail "$1: archive inconsistent after kill -9"
  else
    echo "check_archive: $1: killed before the first archive was written"
  fi
}

# scenario <checkpoints> <delay> <checkpoints on resume> <delay> <launcher>:
# kill, check, resume and kill again, check, resume to the end, compare.
scenario() {
  rm -rf run.h5 run.h5.*
  start_session $5 "$PW" sweep --quiet --checkpoint-cases 1 "$CAMPAIGN" -o run.h5
  wait_and_kill "$1" "$2"
  check_killed "kill after $1 checkpoints + $2 s"
  start_session $5 "$PW" sweep --quiet --checkpoint-cases 1 --resume "$CAMPAIGN" -o run.h5
  wait_and_kill "$3" "$4"
  check_killed "resume killed after $3 checkpoints + $4 s"
  run $5 "$PW" sweep --quiet --resume "$CAMPAIGN" -o run.h5
  [ "$RC" -ne 0 ] || fail "final resume: exit 0, expected 4 (one case fails)"
  $CHECK complete run.h5
  $CHECK same run.h5 ref.h5 || fail "resumed archive differs from the reference"
}

scenario 0 0.2 1 0 "$MPIRUN -np 2"      # before/at the first archive; resume killed at once
scenario 2 0 2 0.03 "$MPIRUN -np 2"     # right after a checkpoint
scenario 5 0.05 3 0.1 "$MPIRUN -np 2"   # while cases, journal entries and checkpoints overlap
scenario 9 0.02 2 0 "$MPIRUN -np 2"
scenario 13 0 1 0.05 "$MPIRUN -np 2"    # near the end
scenario 4 0.03 2 0.02 ""               # one process, no mpirun
ls
echo "PASS"
