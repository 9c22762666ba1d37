#!/bin/sh
# Usage: test_exit_codes.sh <planetwear> <workdir>
# Issue 19: one exit code per failure class (docs/cli.md), one error prefix,
# oversized in-range inputs refused before allocation (exit 1, the key named,
# nothing written), `keys --format json` and a `config --template` that reads
# back as the defaults.
set -u
PW=$1; W=$2
rm -rf "$W"; mkdir -p "$W"; cd "$W" || exit 1
fail=0
P="planetwear: error: "
check() {  # check <name> <expected exit> <expected substring in stderr/stdout> <output that must not exist> -- cmd...
  name=$1; code=$2; text=$3; out=$4; shift 5
  "$@" >stdout.txt 2>stderr.txt; got=$?
  if [ "$got" -ne "$code" ]; then echo "FAIL $name: exit $got, expected $code"; cat stderr.txt; fail=1; fi
  if [ -n "$text" ] && ! grep -q -- "$text" stderr.txt stdout.txt; then
    echo "FAIL $name: message lacks '$text'"; cat stderr.txt; fail=1; fi
  if [ -n "$out" ] && ls "$out"* >/dev/null 2>&1; then echo "FAIL $name: left $out behind"; fail=1; fi
}
# 0: help, version, listings.
check help 0 "docs/cli.md" "" -- "$PW" --help
check version 0 "planetwear" "" -- "$PW" --version
check keys 0 "operating.input_speed_rpm" "" -- "$PW" keys
check candidates 0 "sun_tooth_damage" "" -- "$PW" candidates

# 1: command-line parse errors (CLI11 would exit 104-109), with the one prefix.
check unknown-option 1 "${P}.*--bogus" bad.h5 -- "$PW" simulate --bogus 3 -o bad.h5
check missing-output 1 "${P}.*--output" "" -- "$PW" simulate
check not-a-number 1 "${P}.*--speed-rpm" bad.h5 -- "$PW" simulate --speed-rpm fast -o bad.h5
check no-subcommand 1 "$P" "" -- "$PW"
check bad-keys-format 1 "${P}.*--format" "" -- "$PW" keys --format yaml
check bad-candidates-format 1 "${P}.*--format" "" -- "$PW" candidates --format yaml
check bad-decimation 1 "${P}.*--time-history-decimation" bad.h5 -- "$PW" simulate --time-history-decimation 0 -o bad.h5
# 1: a range error names the key.
check range-error 1 "${P}operating.input_speed_rpm" bad.h5 -- "$PW" simulate --speed-rpm -5 -o bad.h5

# 1: in-range values whose sizes do not fit: refused before the warm-up, with the estimate and the key.
check record-cycles 1 "${P}solver.record_mesh_cycles: recording 1000000 mesh cycles" bad.h5 -- env -u PLANETWEAR_MEMORY_LIMIT \
  "$PW" simulate --set solver.record_mesh_cycles=1000000 -o bad.h5
grep -q "would need about .*more than the memory limit .*PLANETWEAR_MEMORY_LIMIT" stderr.txt ||
  { echo "FAIL record-cycles: no estimate and limit in the message"; cat stderr.txt; fail=1; }
check record-cycles-small-limit 1 "solver.record_mesh_cycles.*--time-history-decimation" bad.h5 -- \
  env PLANETWEAR_MEMORY_LIMIT=64M "$PW" simulate --set solver.record_mesh_cycles=1000 -o bad.h5
check synth-seconds 1 "${P}--seconds: 3000 s at 100 rpm" rec -- \
  env PLANETWEAR_MEMORY_LIMIT=4G "$PW" synth --seconds 3000 -q -o rec.csv
check wear-elements 1 "${P}wear.elements_per_flank" bad.h5 -- env PLANETWEAR_MEMORY_LIMIT=1M \
  "$PW" simulate --mesh-cycles 1e5 --set wear.elements_per_flank=10000 -o bad.h5
check tiny-time-step 1 "${P}solver.time_step_s" bad.h5 -- "$PW" simulate --set solver.time_step_s=1e-12 -o bad.h5
check crawling-speed 1 "${P}operating.input_speed_rpm" bad.h5 -- "$PW" simulate --speed-rpm 1e-4 -o bad.h5
check bad-limit 1 "${P}PLANETWEAR_MEMORY_LIMIT" bad.h5 -- env PLANETWEAR_MEMORY_LIMIT=lots "$PW" simulate -o bad.h5

# 2: the solver fails (one Newton iteration cannot meet a tight tolerance).
check solver-failure 2 "${P}solver failed" bad.h5 -- "$PW" simulate -q --speed-rpm 400 \
  --set solver.newton_max_iterations=1 --set solver.newton_tolerance=1e-14 -o bad.h5
# 3: output into a directory that does not exist.
check io-failure 3 "${P}I/O" "" -- "$PW" simulate -q --speed-rpm 400 --set solver.record_mesh_cycles=1 -o nodir/x.h5
# 4: wear stopped early (results kept).
check wear-stopped 4 "${P}wear stopped.*wear.max_wear_fraction_of_thickness" "" -- "$PW" simulate -q --speed-rpm 400 \
  --mesh-cycles 2e5 --set wear.max_wear_fraction_of_thickness=1e-6 --set solver.record_mesh_cycles=1 -o stopped.h5
[ -f stopped.h5 ] || { echo "FAIL wear-stopped: results not kept"; fail=1; }

# keys --format json: every key of the text listing, with type, unit, default, range and doc.
"$PW" keys > keys.txt || fail=1
"$PW" keys --format json > keys.json || fail=1
/usr/bin/python3 - keys.txt keys.json <<'PY' || fail=1
import json, sys
text = [line.split()[0] for line in open(sys.argv[1]) if line.strip()]
keys = json.load(open(sys.argv[2]))
assert [k["key"] for k in keys] == text, "json keys differ from the text listing"
for k in keys:
    assert set(k) == {"key", "type", "unit", "default", "range", "doc"}, k
speed = next(k for k in keys if k["key"] == "operating.input_speed_rpm")
assert speed["unit"] == "rpm" and speed["default"] == "100.0" and speed["type"] == "float", speed
assert speed["range"] == "in (0, 100000]", speed
PY

# candidates --format json: the rows of the text table, each with a role, at least one line family
# of the five a report locates, and the families a scorer maps a located family with.
"$PW" candidates > candidates.txt || fail=1
"$PW" candidates --format json > candidates.json || fail=1
/usr/bin/python3 - candidates.txt candidates.json <<'PY' || fail=1
import json, sys
text = [line.split()[0] for line in open(sys.argv[1]).read().splitlines()[1:] if line.strip()]
rows = json.load(open(sys.argv[2]))
assert [r["name"] for r in rows] == text, "json candidates differ from the text listing"
families = {"mesh", "sun", "planet", "carrier", "input_shaft"}
for r in rows:
    assert set(r) == {"name", "role", "families", "finding_class", "physics"}, r
    assert r["role"] in {"fault", "nuisance", "rig element", "calibration only"}, r
    assert r["families"] and set(r["families"]) <= families, r
    assert r["physics"], r
by = {r["name"]: r for r in rows}
assert by["sun_tooth_damage"]["families"][0] == "sun" and by["sun_tooth_damage"]["role"] == "fault", by["sun_tooth_damage"]
assert by["stiffness_level"]["role"] == "nuisance", by["stiffness_level"]
assert by["torque_ripple"]["families"] == ["input_shaft"], by["torque_ripple"]
assert by["pin_error"]["finding_class"] == "planet_position_error", by["pin_error"]
PY

# config --template: commented, accepted by simulate, equal to the defaults.
"$PW" config --template > template.toml || fail=1
grep -q "^# sun speed \[rpm\]" template.toml || { echo "FAIL template: no doc comments"; fail=1; }
check template-runs 0 "" "" -- "$PW" simulate -q -c template.toml --speed-rpm 400 --set solver.record_mesh_cycles=1 -o t.h5
"$PW" config > defaults.toml || fail=1
"$PW" config -c template.toml > resolved.toml || fail=1
cmp -s defaults.toml resolved.toml || { echo "FAIL template: does not resolve to the defaults"; diff defaults.toml resolved.toml | head; fail=1; }
check template-no-set 1 "${P}--template" "" -- "$PW" config --template --set operating.input_speed_rpm=3
[ $fail -eq 0 ] && echo "all exit-code checks passed"
exit $fail
