#!/bin/sh
# Fresh machine -> results: installs missing Debian packages, builds, and runs
# the seed paper's case (Bai & Ning 2023, Table 1: 100 rpm, 1 kW) into
# out/seed.h5. Extra arguments go to `planetwear simulate`.
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
mkdir -p out
build/apps/planetwear simulate -o out/seed.h5 "$@"
echo "quickstart: results in out/seed.h5 (open with h5py; layout in docs/output-format.md)"
