#!/bin/sh
# Fresh machine -> every test: installs missing Debian packages, builds, runs
# the whole suite through ctest (GoogleTest, CLI and Python tests).
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
JOBS=${JOBS:-$(nproc 2>/dev/null || echo 2)}
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j "$JOBS"
