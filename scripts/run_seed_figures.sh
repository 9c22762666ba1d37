#!/usr/bin/env bash
# Reproduces the seed-paper figures (Bai & Ning 2023, Figs. 8, 10, 11, 12) for
# the seed case: builds planetwear if needed, runs 'planetwear stiffness' and
# 'planetwear simulate' at 100, 200 and 400 rpm (1 kW input), then plots.
#
#   scripts/run_seed_figures.sh [-o OUTDIR] [-f FIGDIR] [-b BUILDDIR] [-s "100 200 400"] [-P POWER_W] [-j JOBS]
#
#   -o OUTDIR    where the .h5 results go            (default: /tmp/planetwear-seed)
#   -f FIGDIR    where the PNGs go                   (default: <repo>/docs/figures)
#   -b BUILDDIR  CMake build directory (Release)     (default: <repo>/build-plot)
#   -s SPEEDS    input speeds [rpm]                  (default: "100 200 400")
#   -P POWER_W   input power [W]                     (default: 1000)
#   -j JOBS      parallel builds / simulations (<= cores; default 2)
#   -h           this help
#
# Python: the plots need numpy, h5py and matplotlib, which only Debian's
# /usr/bin/python3 has on these machines; PYTHON overrides it.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
outdir=/tmp/planetwear-seed
figdir="$repo/docs/figures"
build="$repo/build-plot"
speeds="100 200 400"
power=1000
jobs=2
py="${PYTHON:-/usr/bin/python3}"

usage() { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; }
while getopts "o:f:b:s:P:j:h" opt; do
  case "$opt" in
    o) outdir="$OPTARG" ;;
    f) figdir="$OPTARG" ;;
    b) build="$OPTARG" ;;
    s) speeds="$OPTARG" ;;
    P) power="$OPTARG" ;;
    j) jobs="$OPTARG" ;;
    h) usage; exit 0 ;;
    *) usage >&2; exit 1 ;;
  esac
done

[[ -x "$py" ]] || { echo "error: python interpreter '$py' not found (set PYTHON)" >&2; exit 1; }
exe="$build/apps/planetwear"
# Build (or bring up to date) in Release.
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" -j"$jobs" --target planetwear
[[ -x "$exe" ]] || { echo "error: $exe was not built" >&2; exit 1; }

mkdir -p "$outdir" "$figdir"
echo "== stiffness curves"
"$exe" stiffness -o "$outdir/stiffness.h5"

echo "== simulate at ${speeds} rpm, ${power} W (up to $jobs at a time)"
files=()
pids=()
for s in $speeds; do
  f="$outdir/s${s}.h5"
  files+=("$f")
  "$exe" simulate --speed-rpm "$s" --power-w "$power" -q -o "$f" &
  pids+=($!)
  if (( ${#pids[@]} >= jobs )); then
    wait "${pids[0]}" || { echo "error: simulate failed" >&2; exit 1; }
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do wait "$p" || { echo "error: simulate failed" >&2; exit 1; }; done

echo "== plots into $figdir"
"$py" "$repo/scripts/plot_stiffness.py" "$outdir/stiffness.h5" -o "$figdir/fig8_mesh_stiffness.png"
"$py" "$repo/scripts/plot_dynamics.py" "${files[@]}" -d "$figdir"
echo "done: results in $outdir, figures in $figdir"
