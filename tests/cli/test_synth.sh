#!/bin/sh
# Usage: test_synth.sh <planetwear> <workdir> <check_synth.py>
# planetwear synth: help, bad input (message, exit code, nothing left behind),
# determinism of the seeded noise, and what the files hold (check_synth.py).
set -u
PW=$1; W=$2; CHECK=$3
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
for opt in --seconds --noise --dc-offset --seed --sensor-angle-deg --decimate --start-mesh-cycle --tacho --set; do
  check "help $opt" 0 "$opt" "" -- "$PW" synth --help
done
Q="--speed-rpm 1200 --power-w 20000 --seconds 0.8 --decimate 40 -q --set solver.periodicity_tolerance=0.05"
check negative-noise 1 "--noise" bad -- "$PW" synth $Q --noise -0.1 -o bad.csv
check nan-offset 1 "--dc-offset" bad -- "$PW" synth $Q --dc-offset nan -o bad.csv
check zero-decimate 1 "decimate" bad -- "$PW" synth $Q --decimate 0 -o bad.csv
check huge-decimate 1 "--decimate: must be an integer in \[1, 1000000\]" bad -- "$PW" synth --seconds 0.8 -q --decimate 200000000 -o bad.csv
check unknown-key 1 "imperfections.pin_eror_m" bad -- "$PW" synth $Q --set imperfections.pin_eror_m=[0,0,0] -o bad.csv
check bad-speed 1 "operating.input_speed_rpm" bad -- "$PW" synth --speed-rpm -3 -o bad.csv
check missing-dir 3 "does not exist" "" -- "$PW" synth $Q -o nodir/rec.csv
check json-output 3 ".json" bad -- "$PW" synth $Q -o bad.json
check early-start 1 "--start-mesh-cycle" bad -- "$PW" synth $Q --start-mesh-cycle 2 -o bad.csv
check missing-output 1 "output" "" -- "$PW" synth $Q
ls ./*partial* >/dev/null 2>&1 && { echo "FAIL partial files left"; fail=1; }

# Same seed, same file; another seed, another file. A concealed effect and a
# noise-free twin for check_synth.py.
E="--set imperfections.pin_error_m=[0,5e-7,0] --sensor-angle-deg 30 --start-mesh-cycle 20 --tacho"
"$PW" synth $Q $E --noise 0.05 --dc-offset 0.2 --seed 7 -o a.csv || fail=1
"$PW" synth $Q $E --noise 0.05 --dc-offset 0.2 --seed 7 -o b.csv || fail=1
"$PW" synth $Q $E --noise 0.05 --dc-offset 0.2 --seed 8 -o c.csv || fail=1
"$PW" synth $Q $E --noise 0 -o clean.csv || fail=1
cmp -s a.csv b.csv || { echo "FAIL same seed gave different files"; fail=1; }
cmp -s a.csv c.csv && { echo "FAIL different seeds gave the same file"; fail=1; }
/usr/bin/python3 "$CHECK" a.csv a.json clean.csv 0.05 0.2 30 || fail=1
[ $fail -eq 0 ] && echo "all synth checks passed"
exit $fail
