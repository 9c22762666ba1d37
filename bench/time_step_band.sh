#!/bin/sh
# How much the in-band order lines move with the model time step (docs/diagnose.md §2,
# "Model time step"): spectra below 2.5 kHz (a 5 kHz recording's band) of
# sun_planet/0/acceleration, planet_ring/0/acceleration and transmission_error at
# solver.steps_per_mode_period = 8, 16, 32 against 64, for three stages.
#
#   bench/time_step_band.sh [BUILD_DIR] [WORK_DIR]      (defaults: build, a temporary directory)
#
# Prints per case, channel and N the largest |amplitude difference| over the band, relative to
# the band's largest line, and the wall time of each run.
set -eu
BUILD=${1:-build}
W=${2:-$(mktemp -d)}
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3
HERE=$(cd "$(dirname "$0")/.." && pwd)
PW="$BUILD/apps/planetwear"
mkdir -p "$W"
run() {  # CASE N ARGS...
  c=$1; n=$2; shift 2
  t0=$(date +%s.%N)
  "$PW" simulate -q "$@" --set solver.steps_per_mode_period="$n" --set solver.record_mesh_cycles=60 \
    --channels sun_planet/0/acceleration,planet_ring/0/acceleration,transmission_error -o "$W/${c}_$n.h5"
  echo "$c N=$n: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }') s wall"
}
for n in 8 16 32 64; do
  run seed "$n" --speed-rpm 200
  run seed_sun_tooth "$n" --speed-rpm 800 --power-w 20000 \
    --set 'imperfections.teeth=[{body="sun",tooth=3,stiffness_factor=0.6}]'
  run four_planets_stiff "$n" -c "$HERE/config/four_planets.toml" --speed-rpm 300 --power-w 10000 \
    --set stiffness.scale=2 --set contact.mesh_damping_ratio=0.25
done
"$PY" - "$W" <<'PY'
import sys, h5py, numpy as np
w = sys.argv[1]
for case in ["seed", "seed_sun_tooth", "four_planets_stiff"]:
    ref = h5py.File(f"{w}/{case}_64.h5", "r")
    for n in [32, 16, 8]:
        f = h5py.File(f"{w}/{case}_{n}.h5", "r")
        row = []
        for ch in ["sun_planet/0/acceleration", "planet_ring/0/acceleration", "transmission_error"]:
            fr = ref[f"spectra/{ch}/frequency"][()]
            a0 = ref[f"spectra/{ch}/amplitude"][()]
            a = f[f"spectra/{ch}/amplitude"][()]
            m = fr <= 2500.0
            k = min(len(a), len(a0), int(m.sum()))
            row.append(np.max(np.abs(a[:k] - a0[:k])) / np.max(a0[:k]))
        print(f"{case:20s} N={n:2d}  max|dA|/max A: " + "  ".join(f"{x:.1e}" for x in row))
PY
