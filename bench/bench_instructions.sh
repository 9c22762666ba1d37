#!/bin/sh
# Instructions per time step, counted (valgrind's callgrind), for one build or two side by side.
# Timings on a shared or virtual machine move by 1.5x between runs of the same binary
# (docs/benchmark.md, sessions 30-32); an instruction count does not move at all, so a change to
# the step that saves 5 % shows as 5 % here. It is not a time: memory stalls and the cost of
# divisions and libm calls differ per instruction. Quote both.
#
#   bench/bench_instructions.sh [BUILD_DIR] [BASELINE_BUILD_DIR]     (default: build)
#
# Per row: bench_simulate run twice under callgrind, recording 1 and 3 mesh periods after the
# same warm-up; the difference of the two counts divided by the steps of 2 mesh periods is the
# cost of one recorded step (force evaluations, contact geometry, Newmark, storing every
# channel), with the preparation and the warm-up cancelled. Needs valgrind
# (`apt-get install valgrind`); single thread. Runs ~10-30 s per row and build.
set -eu
BUILD=${1:-build}
BASE=${2:-}
command -v valgrind >/dev/null || { echo "bench_instructions: needs valgrind (apt-get install valgrind)" >&2; exit 1; }
export OMP_NUM_THREADS=1

# count BUILD RECORD_CYCLES ARGS... -> total instructions (callgrind's "Collected")
count() {
  b=$1; rec=$2; shift 2
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$b/bench/bench_simulate" --repeat 1 \
    --record-cycles "$rec" "$@" 2>&1 >/dev/null | awk '/Collected :/ { print $NF }'
}
# steps per mesh period of a bench_simulate row (the column "steps/T_z", 12th from the end since
# the "page faults" column was added; the "dt chosen by" column holds spaces). Checked against the
# row's own steps = steps/T_z x (warm + rec): a layout change then fails loudly instead of
# dividing by another column. A baseline binary from before that column has it 11th from the end.
steps_per_mesh() {
  b=$1; shift
  "$b/bench/bench_simulate" --repeat 1 --record-cycles 1 "$@" 2>/dev/null |
    awk 'NF >= 16 && $1 ~ /^[0-9]+$/ {
           for (o = 11; o >= 10; --o) {
             spm = $(NF - o)
             if (spm * ($(NF - o + 1) + $(NF - o + 2)) == $(NF - o + 3)) { print spm; exit }
           }
           exit 1 }'
}
row() {  # BUILD ARGS... -> instructions per recorded step
  b=$1; shift
  spm=$(steps_per_mesh "$b" "$@")
  i1=$(count "$b" 1 "$@")
  i3=$(count "$b" 3 "$@")
  echo "$i1 $i3 $spm" | awk '{ printf "%.0f", ($2 - $1) / (2 * $3) }'
}
echo "machine: $(nproc --all) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%Y-%m-%dT%H:%MZ)"
printf "| case | instructions per recorded step (%s) |" "$BUILD"
[ -z "$BASE" ] || printf " baseline (%s) | ratio |" "$BASE"
echo
printf "|---|---|"
[ -z "$BASE" ] || printf "%s" "---|---|"
echo
for spec in "torsional, 200 rpm|200" "torsional, 400 rpm, mu 0.2|400 --set contact.friction_coefficient=0.2" \
  "lateral-torsional, 100 rpm|100 --set solver.level=lateral_torsional"; do
  label=${spec%%|*}
  # shellcheck disable=SC2086
  set -- ${spec#*|}
  new=$(row "$BUILD" "$@")
  if [ -z "$BASE" ]; then
    echo "| $label | $new |"
  else
    old=$(row "$BASE" "$@")
    echo "| $label | $new | $old | $(echo "$new $old" | awk '{ printf "%.3f", $1 / $2 }') |"
  fi
done
