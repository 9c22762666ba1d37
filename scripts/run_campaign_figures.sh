#!/bin/sh
# Runs the small campaigns behind docs/figures/campaign_*.png and draws them
# (docs/postprocessing.md):
#   * sweep/campaigns/demo_lhs.toml (16-case Latin hypercube: speed x power x
#     wear coefficient)             -> main effects, response surface,
#                                      spectra waterfall over speed, wear profiles
#   * a saltelli design over the same three factors (N = 128 rows, 640 cases, 1 recorded mesh cycle)
#                                   -> Sobol' indices
#   * one `planetwear simulate` wear run at 400 rpm with 5 snapshots
#                                   -> spectra waterfall over mesh cycles
#
#   scripts/run_campaign_figures.sh [-b BUILD_DIR] [-o OUTDIR] [-f FIGDIR] [-n RANKS]
#
# Defaults: -b build, -o /tmp/planetwear-campaigns, -f docs/figures, -n 2.
# About 4 minutes on 2 cores. Uses Debian's /usr/bin/python3.
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$SRC/build
OUT=/tmp/planetwear-campaigns
FIG=$SRC/docs/figures
NP=2
while getopts "b:o:f:n:h" opt; do
  case $opt in
    b) BUILD=$OPTARG ;;
    o) OUT=$OPTARG ;;
    f) FIG=$OPTARG ;;
    n) NP=$OPTARG ;;
    *) sed -n '2,16p' "$0"; exit 2 ;;
  esac
done
PW=$BUILD/apps/planetwear
[ -x "$PW" ] || { echo "no $PW: build it (cmake --build $BUILD --target planetwear) or pass -b" >&2; exit 1; }
PY=${PYTHON:-/usr/bin/python3}
mkdir -p "$OUT" "$FIG"
MPIRUN="mpirun -np $NP --oversubscribe"
if [ "$(id -u)" -eq 0 ]; then MPIRUN="$MPIRUN --allow-run-as-root"; fi
export OMP_NUM_THREADS=1

echo "== demo_lhs.toml ($NP ranks)"
# shellcheck disable=SC2086
$MPIRUN "$PW" sweep "$SRC/sweep/campaigns/demo_lhs.toml" -o "$OUT/demo.h5" --force

cat > "$OUT/saltelli.toml" <<EOF
[campaign]
name = "saltelli demo"
description = "Sobol' indices of wear and acceleration: speed, power, wear coefficient (as demo_lhs.toml)"
[base]
config = "$SRC/config/seed.toml"
[base.set]
solver.record_mesh_cycles = 1
wear.mesh_cycles = 1000
wear.window_mesh_cycles = 5
wear.elements_per_flank = 16
[[factors]]
key = "operating.input_speed_rpm"
unit = "rpm"
min = 150.0
max = 400.0
[[factors]]
key = "operating.input_power_W"
unit = "W"
min = 500.0
max = 2000.0
[[factors]]
key = "wear.coefficient_m2_N"
unit = "m^2/N"
min = 2e-17
max = 1e-16
scale = "log"
[design]
type = "saltelli"
base_samples = 128
seed = 1
[output]
spectrum_max_frequency_Hz = 5000.0
EOF
echo "== saltelli design ($NP ranks)"
# shellcheck disable=SC2086
$MPIRUN "$PW" sweep "$OUT/saltelli.toml" -o "$OUT/saltelli.h5" --force

echo "== simulate with wear snapshots"
"$PW" simulate -q --speed-rpm 400 --mesh-cycles 2e5 \
  --set 'wear.snapshot_mesh_cycles=[0,50000,100000,150000,200000]' -o "$OUT/w400.h5"

P="$PY $SRC/scripts/plot_campaign.py"
$P main-effects "$OUT/demo.h5" -y max_wear/sun -y sun_planet/0/acceleration_rms -o "$FIG/campaign_main_effects.png"
$P surface "$OUT/demo.h5" -x operating.input_speed_rpm -y operating.input_power_W -z max_wear/sun \
  -o "$FIG/campaign_surface.png"
$P waterfall "$OUT/demo.h5" --by operating.input_speed_rpm --fmax 2500 -o "$FIG/campaign_waterfall_speed.png"
$P wear-profiles "$OUT/demo.h5" --family sun --by operating.input_speed_rpm -o "$FIG/campaign_wear_profiles.png"
$P snapshots "$OUT/w400.h5" --fmax 2500 -o "$FIG/campaign_waterfall_mesh_cycles.png"
$P sobol "$OUT/saltelli.h5" -y max_wear/sun -y sun_planet/0/acceleration_rms --bootstrap 1000 \
  -o "$FIG/campaign_sobol.png"
