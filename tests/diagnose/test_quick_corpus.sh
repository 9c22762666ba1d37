#!/bin/sh
# Quick corpus end to end (label "corpus"): scripts/make_corpus.py --quick
# (6 recordings: 2 controls, a damaged sun tooth, a pin error, a stiffness
# level, a worn profile; 800/1200 rpm), then scripts/run_corpus.py asserting:
# every control "no missing physics", every correctly named parameter within
# 20 %, >= 90 % named right.
# Usage: test_quick_corpus.sh <planetwear> <workdir> <scripts dir>
set -u
PW=$1; W=$2; S=$3
rm -rf "$W"; mkdir -p "$W"
/usr/bin/python3 "$S/make_corpus.py" --quick -o "$W/corpus" --planetwear "$PW" --jobs 2 || exit 1
exec /usr/bin/python3 "$S/run_corpus.py" "$W/corpus" --planetwear "$PW" --jobs 1 --threads 2 \
  --min-accuracy 0.9 --require-controls --max-parameter-error 0.2
