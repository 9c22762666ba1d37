#!/bin/sh
# A diagnosis does not depend on how many MPI ranks simulate: a damaged-sun-tooth
# recording (1200 rpm, 20 kW, 5 % noise) diagnosed without mpirun on one thread and
# with `mpirun -np 2 --threads 1` (rank 1 serves simulations) gives identical
# report.json files (timing and command line aside), the -np 2 run reports 2 ranks,
# and the fault is found (so candidate screening and fits ran across ranks). Bad input
# under mpirun: rank 0 names the option, the job exits non-zero, nothing is written
# and no rank hangs.
# Usage: test_ranks.sh <planetwear> <mpiexec> <workdir> <tests/sweep>
set -eu
PW=$1; T=$4
. "$T/mpi.sh"
mpi_launcher "$2"
rm -rf "$3"; mkdir -p "$3"; cd "$3"

"$PW" synth -q --speed-rpm 1200 --power-w 20000 --seconds 0.78 --noise 0.05 --dc-offset 0.2 --seed 3 \
  --sensor-angle-deg 40 --decimate 40 --start-mesh-cycle 450 --set solver.time_step_s=2.5e-6 \
  --set solver.periodicity_tolerance=1e-3 --set 'imperfections.teeth=[{body="sun",tooth=5,stiffness_factor=0.6}]' \
  -o rec.csv
run $MPIRUN -np 2 "$PW" diagnose -q -r rec.csv --meta missing.json -o bad > bad.log 2>&1
[ "$RC" -ne 0 ] || fail "missing sidecar under mpirun: exit 0"
grep -q -- "--meta" bad.log || fail "missing sidecar under mpirun: no message naming --meta"
[ ! -e bad ] || fail "missing sidecar under mpirun: the report directory was written"
D="diagnose -r rec.csv --candidates stiffness_level,damping_level,sun_tooth_damage --no-plots -q --threads 1"
run env OMP_NUM_THREADS=1 "$PW" $D -o np1
[ "$RC" -eq 0 ] || fail "-np 1: exit $RC"
run env OMP_NUM_THREADS=1 $MPIRUN -x OMP_NUM_THREADS -np 2 "$PW" $D -o np2
[ "$RC" -eq 0 ] || fail "-np 2: exit $RC"
/usr/bin/python3 - <<'PY' || fail "reports differ between 1 and 2 ranks"
import json, sys
a, b = (json.load(open(f"{d}/report.json")) for d in ("np1", "np2"))
if (a["timing"]["ranks"], b["timing"]["ranks"]) != (1, 2):
    sys.exit(f"ranks reported: {a['timing']['ranks']}, {b['timing']['ranks']}")
if a["verdict"] != "missing_physics_found":
    sys.exit(f"verdict {a['verdict']}: the fault should be found")
for r in (a, b):
    r.pop("timing"); r.pop("command_line", None)
    for c in r.get("candidates", []):
        c.pop("seconds", None)
if a != b:
    keys = [k for k in a if a.get(k) != b.get(k)]
    sys.exit(f"differ in {keys}")
print("identical reports on 1 and 2 ranks;", a["summary"][:120])
PY
