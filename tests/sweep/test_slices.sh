#!/bin/sh
# Array-job slices: two `--cases` slices merged with scripts/merge_archives.py
# hold the same numbers as one run of the whole campaign; a resume with a
# different range is refused and leaves the slice archive untouched.
# Usage: test_slices.sh <planetwear> <mpiexec> <workdir> <tests/sweep>
set -eu
PW=$1; T=$4
. "$T/mpi.sh"
mpi_launcher "$2"
rm -rf "$3"; mkdir -p "$3"; cd "$3"
CAMPAIGN=$T/data/identity.toml
CHECK="/usr/bin/python3 $T/check_archive.py"

run env OMP_NUM_THREADS=1 "$PW" sweep --quiet "$CAMPAIGN" -o full.h5
run env OMP_NUM_THREADS=1 "$PW" sweep --quiet "$CAMPAIGN" -o part0.h5 --cases 0:2
run env OMP_NUM_THREADS=1 "$PW" sweep --quiet "$CAMPAIGN" -o part1.h5 --cases 2:
/usr/bin/python3 -c "
import h5py, sys
f = h5py.File('part0.h5')
st = list(f['design/status'].asstr()[:])
print('part0:', st, f.attrs['case_begin'], f.attrs['case_end'])
sys.exit(0 if st[2:] == ['pending'] * (len(st) - 2) and f.attrs['case_end'] == 2 else 1)" || fail "slice 0:2 ran cases outside its range"
cp part0.h5 before.h5
run "$PW" sweep --quiet "$CAMPAIGN" -o part0.h5 --resume --cases 0:3
[ "$RC" -eq 1 ] || fail "resume with another range: exit $RC, expected 1"
cmp -s part0.h5 before.h5 || fail "a refused resume changed the slice archive"
/usr/bin/python3 "$T/../../scripts/merge_archives.py" -o merged.h5 part0.h5 part1.h5
$CHECK same merged.h5 full.h5
echo "PASS"
