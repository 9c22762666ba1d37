#!/bin/sh
# Usage: test_output.sh <planetwear> <workdir> <check_output.py>
set -eu
PW=$1; W=$2; CHECK=$3
rm -rf "$W"; mkdir -p "$W"; cd "$W"
"$PW" simulate --quiet --speed-rpm 400 --set solver.record_mesh_cycles=3 -o out.h5 --csv out.csv
/usr/bin/python3 "$CHECK" out.h5 out.csv
