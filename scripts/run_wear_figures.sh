#!/usr/bin/env bash
# Wear figures of the seed case (Bai & Ning 2023, Figs. 9-12 "as mesh cycles
# increase"): builds planetwear if needed, runs 'planetwear simulate' with wear
# at 100, 200 and 400 rpm (1 kW input, 2e5 mesh cycles, dynamic snapshots at
# 0, 1/4, 1/2, 3/4 and all of the mesh cycles), then plots with plot_wear.py.
# By default every speed runs twice: at our potential-energy (ISO-level) mesh
# stiffness and at the seed's Table 2 level (stiffness.scale = 0.01,
# docs/validation.md §1-2); the second set's PNGs carry the suffix _k0.01.
#
#   scripts/run_wear_figures.sh [-o OUTDIR] [-f FIGDIR] [-b BUILDDIR] [-s "100 200 400"] [-P POWER_W]
#                               [-n MESH_CYCLES] [-k "1 0.01"] [-j JOBS]
#
#   -o OUTDIR       where the .h5 results and summaries go   (default: /tmp/planetwear-wear)
#   -f FIGDIR       where the PNGs go                        (default: <repo>/docs/figures)
#   -b BUILDDIR     CMake build directory (Release)          (default: <repo>/build-wfig)
#   -s SPEEDS       input speeds [rpm]                       (default: "100 200 400")
#   -P POWER_W      input power [W]                          (default: 1000)
#   -n MESH_CYCLES  mesh cycles worn through                 (default: 2e5)
#   -k SCALES       stiffness.scale values, one run set each (default: "1 0.01")
#   -j JOBS         parallel builds / simulations (<= cores; default 2)
#   -h              this help
#
# Outputs: OUTDIR/w<rpm>.h5 (scale 1) or OUTDIR/w<rpm>_k<scale>.h5, the
# numbers behind the figures in OUTDIR/summary[_k<scale>].md, and in FIGDIR
# fig9_wear_distribution[_k<scale>].png and wear_*[_k<scale>].png
# (scripts/README.md lists them).
# Python: the plots need numpy, h5py and matplotlib, which only Debian's
# /usr/bin/python3 has on these machines; PYTHON overrides it.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
outdir=/tmp/planetwear-wear
figdir="$repo/docs/figures"
build="$repo/build-wfig"
speeds="100 200 400"
power=1000
cycles=2e5
scales="1 0.01"
jobs=2
py="${PYTHON:-/usr/bin/python3}"

usage() { sed -n '2,28p' "$0" | sed 's/^# \{0,1\}//'; }
while getopts "o:f:b:s:P:n:k:j:h" opt; do
  case "$opt" in
    o) outdir="$OPTARG" ;;
    f) figdir="$OPTARG" ;;
    b) build="$OPTARG" ;;
    s) speeds="$OPTARG" ;;
    P) power="$OPTARG" ;;
    n) cycles="$OPTARG" ;;
    k) scales="$OPTARG" ;;
    j) jobs="$OPTARG" ;;
    h) usage; exit 0 ;;
    *) usage >&2; exit 1 ;;
  esac
done
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "error: -j needs a positive integer" >&2; exit 1; }
[[ -x "$py" ]] || { echo "error: python interpreter '$py' not found (set PYTHON)" >&2; exit 1; }

# Snapshots at 0, 1/4, 1/2, 3/4 and all of the mesh cycles.
snaps="$(awk -v n="$cycles" 'BEGIN { if (!(n > 0)) exit 1;
  printf "[%.17g,%.17g,%.17g,%.17g,%.17g]", 0, n / 4, n / 2, 3 * n / 4, n }')" \
  || { echo "error: -n needs a positive number of mesh cycles" >&2; exit 1; }

exe="$build/apps/planetwear"
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" -j"$jobs" --target planetwear
[[ -x "$exe" ]] || { echo "error: $exe was not built" >&2; exit 1; }
mkdir -p "$outdir" "$figdir"

suffix_of() { [[ "$1" == "1" ]] && echo "" || echo "_k$1"; }

echo "== simulate with wear: ${speeds} rpm x stiffness.scale ${scales}, ${power} W, ${cycles} mesh cycles," \
     "snapshots ${snaps} (up to $jobs at a time)"
pids=()
names=()
wait_first() {
  local pid="${pids[0]}" name="${names[0]}"
  pids=("${pids[@]:1}")
  names=("${names[@]:1}")
  if ! wait "$pid"; then
    echo "error: simulate failed for $name (log: $outdir/$name.log)" >&2
    exit 1
  fi
  echo "   done: $name"
}
for k in $scales; do
  sfx="$(suffix_of "$k")"
  for s in $speeds; do
    name="w${s}${sfx}"
    "$exe" simulate -q --speed-rpm "$s" --power-w "$power" --mesh-cycles "$cycles" \
      --set "stiffness.scale=$k" --set "wear.snapshot_mesh_cycles=$snaps" \
      -o "$outdir/$name.h5" > "$outdir/$name.log" 2>&1 &
    pids+=($!)
    names+=("$name")
    if (( ${#pids[@]} >= jobs )); then wait_first; fi
  done
done
while (( ${#pids[@]} > 0 )); do wait_first; done

echo "== plots into $figdir"
for k in $scales; do
  sfx="$(suffix_of "$k")"
  files=()
  for s in $speeds; do files+=("$outdir/w${s}${sfx}.h5"); done
  "$py" "$repo/scripts/plot_wear.py" "${files[@]}" -d "$figdir" --suffix "$sfx" \
    --summary "$outdir/summary${sfx}.md"
done
echo "done: results and summary*.md in $outdir, figures in $figdir"
