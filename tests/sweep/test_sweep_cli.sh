#!/bin/sh
# `planetwear sweep` input checking: bad campaigns and refused runs stop with
# a clear message and exit 1 before anything runs, write nothing, and never
# touch an existing archive; --resume of a finished archive changes no number;
# a second run on an archive in use is refused.
# Usage: test_sweep_cli.sh <planetwear> <mpiexec> <workdir> <tests/sweep>
set -eu
PW=$1; T=$4
. "$T/mpi.sh"
mpi_launcher "$2"
rm -rf "$3"; mkdir -p "$3"; cd "$3"
CHECK="/usr/bin/python3 $T/check_archive.py"
export OMP_NUM_THREADS=1

# expect_error <expected text> <campaign> [options...]: exit 1, message, no output files.
expect_error() {
  want=$1; shift
  before=$(ls -A | sort | tr '\n' ' ')
  run "$PW" sweep "$@" 2> err.txt
  [ "$RC" -eq 1 ] || { cat err.txt; fail "sweep $*: exit $RC, expected 1"; }
  grep -q -F -- "$want" err.txt || { cat err.txt; fail "sweep $*: message lacks '$want'"; }
  rm -f err.txt
  after=$(ls -A | sort | tr '\n' ' ')
  [ "$before" = "$after" ] || fail "sweep $*: files changed: '$before' -> '$after'"
  echo "ok: $want"
}

campaign() {  # campaign <file> <factor table lines...>
  out=$1; shift
  { printf '[base.set]\nsolver.record_mesh_cycles = 1\nsolver.warmup_max_mesh_cycles = 5\n\n'
    for line in "$@"; do printf '%s\n' "$line"; done; } > "$out"
}

campaign unknown.toml '[[factors]]' 'key = "operating.input_sped_rpm"' 'unit = "rpm"' 'levels = [400]' \
  '[design]' 'type = "full_factorial"'
expect_error "unknown configuration key 'operating.input_sped_rpm'" unknown.toml -o out.h5
campaign reversed.toml '[[factors]]' 'key = "operating.input_speed_rpm"' 'unit = "rpm"' 'min = 400.0' 'max = 100.0' \
  '[design]' 'type = "latin_hypercube"' 'samples = 4'
expect_error "bounds reversed" reversed.toml -o out.h5
campaign unit.toml '[[factors]]' 'key = "operating.input_power_W"' 'unit = "kW"' 'levels = [1.0]' \
  '[design]' 'type = "full_factorial"'
expect_error '"kW" does not match the unit of operating.input_power_W, which is "W"' unit.toml -o out.h5
campaign outside.toml '[[factors]]' 'key = "operating.input_speed_rpm"' 'unit = "rpm"' 'min = 100.0' 'max = 400.0' \
  'levels = [200.0, 500.0]' '[design]' 'type = "full_factorial"'
expect_error "is above max" outside.toml -o out.h5
campaign zero.toml '[[factors]]' 'key = "operating.input_speed_rpm"' 'unit = "rpm"' 'min = 100.0' 'max = 400.0' \
  '[design]' 'type = "latin_hypercube"' 'samples = 0'
expect_error "design.samples: must be > 0" zero.toml -o out.h5
campaign badcase.toml '[[factors]]' 'key = "stage.planet_count"' 'unit = "-"' 'levels = [3, 4]' \
  '[design]' 'type = "full_factorial"'
expect_error "case 1 (stage.planet_count = 4 -)" badcase.toml -o out.h5

# A good campaign: 2 cases.
campaign good.toml '[[factors]]' 'key = "operating.input_speed_rpm"' 'unit = "rpm"' 'levels = [400.0, 500.0]' \
  '[design]' 'type = "full_factorial"'
run "$PW" sweep --dry-run good.toml
[ "$RC" -eq 0 ] && [ ! -e out.h5 ] || fail "--dry-run: exit $RC or wrote a file"
run "$PW" sweep --quiet good.toml -o out.h5
[ "$RC" -eq 0 ] || fail "good campaign: exit $RC"
$CHECK complete out.h5
cp out.h5 keep.h5

expect_error "out.h5 exists; use --resume" good.toml -o out.h5
cmp -s out.h5 keep.h5 || fail "refused run changed the archive"
expect_error "unknown configuration key" unknown.toml -o out.h5 --force
cmp -s out.h5 keep.h5 || fail "failed --force run changed the archive"
cp good.toml changed.toml; echo "# edited" >> changed.toml
expect_error "Refusing to resume" changed.toml -o out.h5 --resume
cmp -s out.h5 keep.h5 || fail "refused --resume changed the archive"

# Resuming a finished archive runs nothing and keeps every number.
run "$PW" sweep --quiet --resume good.toml -o out.h5
[ "$RC" -eq 0 ] || fail "--resume of a finished archive: exit $RC"
$CHECK same out.h5 keep.h5
cp out.h5 keep.h5

# Same through mpirun: refusal with exit 1 from the job.
run $MPIRUN -np 2 "$PW" sweep --quiet good.toml -o out.h5 2> err.txt
[ "$RC" -eq 1 ] && grep -q "exists; use --resume" err.txt || { cat err.txt; fail "mpirun refusal: exit $RC"; }
cmp -s out.h5 keep.h5 || fail "refused MPI run changed the archive"

# A second run on an archive in use is refused (journal lock). The busy campaign records 200
# mesh periods per case (kill.toml: 2) so that it is still running, on any machine, when the
# second run starts: with 2 the whole campaign took ~1.5 s and could finish first.
sed 's/^solver.record_mesh_cycles = 2$/solver.record_mesh_cycles = 200/' "$T/data/kill.toml" > busy.toml
grep -q "record_mesh_cycles = 200" busy.toml || fail "busy.toml: kill.toml's record_mesh_cycles line changed"
cp "$T/data/kill_cases.csv" .
start_session "$PW" sweep --quiet --force busy.toml -o busy.h5
# Wait for its journal lock (created, then flock'ed at once): a fixed sleep was too short on a
# loaded machine (the second run then took the lock itself).
waited=0
while [ ! -e busy.h5.journal/lock ]; do
  sleep 0.05; waited=$((waited + 1))
  [ "$waited" -lt 1200 ] || { kill_session "$SESSION"; fail "the first sweep never locked its journal (60 s)"; }
done
sleep 0.2
run "$PW" sweep --quiet --resume busy.toml -o busy.h5 2> err.txt
kill_session "$SESSION"
[ "$RC" -eq 3 ] && grep -q "another planetwear sweep is running" err.txt || { cat err.txt; fail "concurrent run: exit $RC"; }
echo "ok: concurrent run refused"
echo "PASS"
