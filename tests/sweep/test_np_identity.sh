#!/bin/sh
# The archive's numbers do not depend on the number of ranks or OpenMP
# threads: -np 1 (no mpirun, 1 thread), mpirun -np 2 x 2 threads and
# mpirun -np 3 (more ranks than cores) must agree exactly (wall times and
# ranks aside). The campaign has a failing case, so the exit code is 4.
# Usage: test_np_identity.sh <planetwear> <mpiexec> <workdir> <tests/sweep>
set -eu
PW=$1; T=$4
. "$T/mpi.sh"
mpi_launcher "$2"
rm -rf "$3"; mkdir -p "$3"; cd "$3"
CAMPAIGN=$T/data/identity.toml

run env OMP_NUM_THREADS=1 "$PW" sweep --quiet "$CAMPAIGN" -o np1.h5
[ "$RC" -eq 4 ] || fail "-np 1: exit $RC, expected 4 (one case fails)"
run env OMP_NUM_THREADS=2 $MPIRUN -x OMP_NUM_THREADS -np 2 "$PW" sweep --quiet "$CAMPAIGN" -o np2.h5
[ "$RC" -ne 0 ] || fail "-np 2: exit 0, expected non-zero (one case fails)"
run env OMP_NUM_THREADS=1 $MPIRUN -x OMP_NUM_THREADS -np 3 "$PW" sweep --quiet "$CAMPAIGN" -o np3.h5
[ "$RC" -ne 0 ] || fail "-np 3: exit 0, expected non-zero (one case fails)"

CHECK="/usr/bin/python3 $T/check_archive.py"
$CHECK complete np1.h5
$CHECK same np1.h5 np2.h5
$CHECK same np1.h5 np3.h5
# Rank 0 computes too, and work is shared.
/usr/bin/python3 -c "
import h5py, sys
ranks = sorted(set(h5py.File('np2.h5')['design/rank'][:]))
print('ranks used with -np 2:', ranks)
sys.exit(0 if ranks == [0, 1] else 1)" || fail "-np 2 did not use both ranks"
echo "PASS"
