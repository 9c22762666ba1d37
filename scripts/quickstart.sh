#!/bin/sh
# Fresh machine -> results: installs missing Debian packages, builds, and runs
# the default campaign -- the seed paper's stage (Bai & Ning 2023, Table 1) at
# its three speeds 100, 200 and 400 rpm, 1 kW, with wear over 2e5 mesh cycles
# -- through mpirun on all local cores, into out/seed_speeds.h5. A second run
# resumes (and finds nothing left to do). Extra arguments go to
# `planetwear sweep`.
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
mkdir -p out
NP=${NP:-$(nproc 2>/dev/null || echo 2)}
MPIRUN_FLAGS=""
[ "$(id -u)" -eq 0 ] && MPIRUN_FLAGS="--allow-run-as-root"
OUT=out/seed_speeds.h5
RESUME=""
[ -e "$OUT" ] && RESUME="--resume"
# One OpenMP thread per rank: the cases are the parallel work.
OMP_NUM_THREADS=1 mpirun $MPIRUN_FLAGS -np "$NP" -x OMP_NUM_THREADS \
  build/apps/planetwear sweep sweep/campaigns/seed_speeds.toml -o "$OUT" $RESUME "$@"
echo "quickstart: archive in $OUT -- design table in Python:"
echo "  /usr/bin/python3 -c \"import sys; sys.path.insert(0, 'scripts'); import pwcampaign as p; print(p.load('$OUT').design)\""
