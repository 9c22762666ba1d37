#!/bin/sh
# Usage: test_cli.sh <planetwear> <workdir>
set -u
PW=$1; W=$2
rm -rf "$W"; mkdir -p "$W"; cd "$W" || exit 1
fail=0
check() {  # check <name> <expected exit> <expected substring in stderr> <output that must not exist> -- cmd...
  name=$1; code=$2; text=$3; out=$4; shift 5
  "$@" >stdout.txt 2>stderr.txt; got=$?
  # code "nz" means any non-zero exit
  if { [ "$code" = nz ] && [ "$got" -eq 0 ]; } || { [ "$code" != nz ] && [ "$got" -ne "$code" ]; }; then
    echo "FAIL $name: exit $got, expected $code"; cat stderr.txt; fail=1; fi
  if [ -n "$text" ] && ! grep -q -- "$text" stderr.txt stdout.txt; then
    echo "FAIL $name: message lacks '$text'"; cat stderr.txt; fail=1; fi
  if [ -n "$out" ] && ls "$out"* >/dev/null 2>&1; then echo "FAIL $name: left $out behind"; fail=1; fi
}
for sub in "" simulate stiffness keys; do
  check "help $sub" 0 "Usage" "" -- "$PW" $sub --help
done
check negative-speed 1 "operating.input_speed_rpm" bad.h5 -- "$PW" simulate --speed-rpm -5 -o bad.h5
check nan-power 1 "operating.input_power_W" bad.h5 -- "$PW" simulate --power-w nan -o bad.h5
printf '[operating]\nspeed = 3\n' > unknown.toml
check unknown-key 1 "speed" bad.h5 -- "$PW" simulate -c unknown.toml -o bad.h5
printf '[stage.ring]\nteeth = 80\n' > geom.toml
check impossible-geometry 1 "teeth" bad.h5 -- "$PW" simulate -c geom.toml -o bad.h5
check coarse-time-step 1 "solver.time_step_s" bad.h5 -- "$PW" simulate --set solver.time_step_s=1e-3 -o bad.h5
check unknown-set-key 1 "nonsense" bad.h5 -- "$PW" simulate --set operating.nonsense=1 -o bad.h5
check missing-output 1 "output" "" -- "$PW" simulate
check negative-mesh-cycles 1 "--mesh-cycles" bad.h5 -- "$PW" simulate --mesh-cycles -2e5 -o bad.h5
check one-wear-element 1 "wear.elements_per_flank" bad.h5 -- "$PW" simulate --set wear.elements_per_flank=1 -o bad.h5
check unknown-channel 1 "sun/sped" bad.h5 -- "$PW" simulate --channels sun/sped -o bad.h5
check decimation-zero 1 "time-history-decimation" bad.h5 -- "$PW" simulate --time-history-decimation 0 -o bad.h5
# diagnose reads a recording described on the command line alone (no sidecar): a wrong
# quantity names --column; a right description reaches the reader's sample-rate check.
printf 'time [s],w [rpm]\n0,800\n0.001,800\n0.002,800\n' > cl.csv
check column-bad-quantity 1 "--column" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --column w=sun_sped,unit=rpm --speed-rpm 800 --power-w 2e4
check column-described-here 1 "sample rate 1000 Hz is too low" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
check column-no-sidecar 1 "--meta" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep
# a calibration-only rig element is not a finding to restrict the library to: the error says where it belongs.
check calibration-only-candidate 1 "calibrate --rig-elements output_shaft" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --candidates output_shaft --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
# calibrate: sidecars must pair with recordings; an unknown rig element and a malformed
# calibration file are input errors naming the option or key; nothing is written.
check calibrate-meta-count 1 "--meta" cal.toml -- "$PW" calibrate -r cl.csv --meta a.json --meta b.json -o cal.toml
check calibrate-rig-element 1 "--rig-elements" cal.toml -- "$PW" calibrate -r cl.csv --rig-elements encoder -o cal.toml
printf '[calibration]\nalpha = 0.01\n' > badcal.toml
# diagnose --baseline: an alternative to --calibration; its sidecar must exist; --baseline-meta needs it.
check baseline-and-calibration 1 "--baseline" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --baseline cl.csv --calibration badcal.toml --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
check baseline-meta-alone 1 "--baseline-meta" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --baseline-meta x.json --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
check baseline-no-sidecar 1 "--baseline-meta" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --baseline cl.csv --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
check baseline-transfer-alone 1 "--baseline-transfer" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --baseline-transfer line_ratio --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
check baseline-transfer-no-reference 1 "--baseline-transfer" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --calibration badcal.toml --calibration-reference none --baseline-transfer line_ratio --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
check calibration-reference-unknown 1 "--calibration-reference" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --calibration-reference nearest --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
check diagnose-bad-calibration 1 "calibration.recordings" cl_rep -- "$PW" diagnose -r cl.csv -o cl_rep --calibration badcal.toml --column w=sun_speed,unit=rpm --speed-rpm 800 --power-w 2e4
# A failing run must not touch an existing file at the destination.
echo keep > existing.h5
check keeps-existing 1 "operating.input_speed_rpm" "" -- "$PW" simulate --speed-rpm 0 -o existing.h5
[ "$(cat existing.h5)" = keep ] || { echo "FAIL existing output damaged"; fail=1; }
ls ./*partial* >/dev/null 2>&1 && { echo "FAIL partial files left"; fail=1; }
check zero-mesh-cycles 1 "--mesh-cycles" bad.h5 -- "$PW" simulate --mesh-cycles 0 -o bad.h5
# Wear beyond the safe limit: stop, say why, keep the results, exit 4.
check wear-limit 4 "wear.max_wear_fraction_of_thickness" "" -- "$PW" simulate -q --speed-rpm 400 --mesh-cycles 2e5 \
  --set wear.max_wear_fraction_of_thickness=1e-6 --set solver.record_mesh_cycles=1 -o stopped.h5 --report stopped.md
[ -f stopped.h5 ] || { echo "FAIL wear-limit: results not kept"; fail=1; }
# The engineering summary: printed on stdout, the same text in --report, nothing with -q;
# a wear run that stopped early says so in it; a non-positive allowable is an input error,
# a report into a missing directory an I/O error (as -o) before the run.
grep -q "Stopped early" stopped.md || { echo "FAIL wear-limit: summary does not say it stopped early"; fail=1; }
check report 0 "" "" -- "$PW" simulate --speed-rpm 400 --set solver.record_mesh_cycles=2 --report summary.md -o rep.h5
cmp -s summary.md stdout.txt || { echo "FAIL report: --report differs from the printed summary"; fail=1; }
grep -q "steady state" stdout.txt stderr.txt && { echo "FAIL report: a settled run was flagged unsteady"; fail=1; }
grep -q "Mesh efficiency (friction losses): 0\.9" stdout.txt || { echo "FAIL report: a settled run lacks its efficiency"; fail=1; }
for col in "dynamic factor K_v" "largest contact pressure [MPa]" "Load-sharing factor" "allowable 1500 MPa"; do
  grep -qF "$col" summary.md || { echo "FAIL report: summary lacks '$col'"; fail=1; }; done
check report-quiet 0 "" "" -- "$PW" simulate -q --speed-rpm 400 --set solver.record_mesh_cycles=2 -o rep.h5
[ -s stdout.txt ] && { echo "FAIL report-quiet: -q printed on stdout"; fail=1; }
# A warm-up cut short (one mesh period) is flagged in the summary and on stderr, not silently reported.
check unsteady-flagged 0 "did not reach a steady state" "" -- "$PW" simulate --speed-rpm 400 \
  --set solver.warmup_max_mesh_cycles=1 --set solver.record_mesh_cycles=2 -o unsteady.h5
grep -q "not a steady state" stdout.txt || { echo "FAIL unsteady-flagged: summary lacks the warning"; fail=1; }
grep -q "Mesh efficiency: not given" stdout.txt || { echo "FAIL unsteady-flagged: a transient's efficiency was given"; fail=1; }
check report-allowable 1 "allowable-contact-stress-pa" bad.h5 -- "$PW" simulate --allowable-contact-stress-pa -1 -o bad.h5
check report-bad-dir 3 "no_such_dir" bad.h5 -- "$PW" simulate --report no_such_dir/s.md -o bad.h5
[ $fail -eq 0 ] && echo "all CLI checks passed"
exit $fail
