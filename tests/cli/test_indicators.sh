#!/bin/sh
# Usage: test_indicators.sh <planetwear> <workdir> <check_indicators.py> <plot_indicator_trend.py>
# planetwear indicators (docs/indicators.md): help, bad input (message naming the
# option, exit code 1, nothing left behind), a healthy and a cracked-sun-tooth
# synthetic recording (the cracked one's sun averages have the larger FM4 and
# kurtosis: check_indicators.py), JSON and CSV agree, and the trend of a short
# wear run (one row per snapshot, channel and gear; the plot script draws it).
set -u
PW=$1; W=$2; CHECK=$3; PLOT=$4
rm -rf "$W"; mkdir -p "$W"; cd "$W" || exit 1
fail=0
check() {  # check <name> <expected exit|nz> <text in stderr/stdout> <output that must not exist> -- cmd...
  name=$1; code=$2; text=$3; out=$4; shift 5
  "$@" >stdout.txt 2>stderr.txt; got=$?
  if { [ "$code" = nz ] && [ "$got" -eq 0 ]; } || { [ "$code" != nz ] && [ "$got" -ne "$code" ]; }; then
    echo "FAIL $name: exit $got, expected $code"; cat stderr.txt; fail=1; fi
  if [ -n "$text" ] && ! grep -q -- "$text" stderr.txt stdout.txt; then
    echo "FAIL $name: message lacks '$text'"; cat stderr.txt; fail=1; fi
  if [ -n "$out" ] && ls "$out"* >/dev/null 2>&1; then echo "FAIL $name: left $out behind"; fail=1; fi
}
for opt in --recording --simulation --meta --column --samples-per-mesh --shaft-harmonics --planet-window-deg --output; do
  check "help $opt" 0 "$opt" "" -- "$PW" indicators --help
done

# 1200 rpm, 20 kW, 1 s: 4.1 carrier revolutions (the planet-separated averages need about 3).
Q="--speed-rpm 1200 --power-w 20000 --seconds 1.0 --decimate 40 --noise 0.05 --dc-offset 0.2 --sensor-angle-deg 30
   --start-mesh-cycle 450 --set solver.time_step_s=2.5e-6 --set solver.periodicity_tolerance=1e-3"
"$PW" synth -q $Q --seed 3 -o healthy.csv || { echo "FAIL synth healthy"; exit 1; }
"$PW" synth -q $Q --seed 4 --set 'imperfections.teeth=[{body="sun",tooth=5,stiffness_factor=0.6}]' -o cracked.csv ||
  { echo "FAIL synth cracked"; exit 1; }

check no-input 1 "--recording" "" -- "$PW" indicators
check both-inputs nz "excludes" "" -- "$PW" indicators -r healthy.csv --simulation healthy.csv
check shaft-harmonics 1 "--shaft-harmonics" bad -- "$PW" indicators -r healthy.csv --shaft-harmonics 99 -o bad.json
check samples-per-mesh 1 "--samples-per-mesh" bad -- "$PW" indicators -r healthy.csv --samples-per-mesh 3 -o bad.json
check planet-window 1 "--planet-window-deg" bad -- "$PW" indicators -r healthy.csv --planet-window-deg 200 -o bad.csv
check output-extension 1 "-o" bad -- "$PW" indicators -r healthy.csv -o bad.txt
check missing-dir 3 "does not exist" "" -- "$PW" indicators -r healthy.csv -o nodir/x.json
cp healthy.csv nosidecar.csv
check no-sidecar 1 "--meta" bad -- "$PW" indicators -r nosidecar.csv -o bad.json
check not-hdf5 1 "--simulation" bad -- "$PW" indicators --simulation healthy.csv -o bad.json
"$PW" simulate -q --speed-rpm 1200 --power-w 20000 --set solver.record_mesh_cycles=4 -o nowear.h5 ||
  { echo "FAIL simulate"; fail=1; }
check not-a-wear-run 1 "/wear/snapshots" bad -- "$PW" indicators --simulation nowear.h5 -o bad.json
check config-with-simulation 1 "--config" bad -- "$PW" indicators --simulation nowear.h5 --set a.b=1 -o bad.json
cp healthy.json sidecar.bak
check onto-sidecar 1 "is an input" "" -- "$PW" indicators -r healthy.csv -o healthy.json
cmp -s healthy.json sidecar.bak || { echo "FAIL the sidecar was overwritten"; fail=1; }
ls ./*partial* >/dev/null 2>&1 && { echo "FAIL partial files left"; fail=1; }

"$PW" indicators -r healthy.csv -o healthy.ind.json > healthy.txt || { echo "FAIL indicators healthy"; fail=1; }
"$PW" indicators -r cracked.csv -o cracked.ind.json > cracked.txt || { echo "FAIL indicators cracked"; fail=1; }
"$PW" indicators -q -r cracked.csv -o cracked.ind.csv || { echo "FAIL indicators cracked CSV"; fail=1; }
cat healthy.txt cracked.txt

# A short wear run with snapshots long enough for every average (3 carrier revolutions).
"$PW" simulate -q --speed-rpm 1200 --power-w 20000 --mesh-cycles 4e4 --kappa 5e-15 --time-history-decimation 64 \
  --set wear.snapshot_record_mesh_cycles=250 --set 'wear.snapshot_mesh_cycles=[0,2e4,4e4]' \
  --set solver.time_step_s=2.5e-6 -o worn.h5 || { echo "FAIL simulate wear"; fail=1; }
"$PW" indicators --simulation worn.h5 -o trend.csv > trend.txt || { echo "FAIL indicators --simulation"; fail=1; }
cat trend.txt
/usr/bin/python3 "$CHECK" healthy.ind.json cracked.ind.json cracked.ind.csv trend.csv || fail=1
/usr/bin/python3 "$PLOT" trend.csv -o trend.png || { echo "FAIL plot script"; fail=1; }
[ -s trend.png ] || { echo "FAIL no trend.png"; fail=1; }
check plot-not-a-trend 1 "mesh_cycles" nottrend.png -- /usr/bin/python3 "$PLOT" cracked.ind.csv -o nottrend.png
[ $fail -eq 0 ] && echo "all indicators checks passed"
exit $fail
