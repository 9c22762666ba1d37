#!/bin/sh
# Quick corpus end to end (label "corpus"): scripts/make_corpus.py --quick
# (6 recordings: 2 controls, a damaged sun tooth, a pin error, a stiffness
# level, a worn profile; 800/1200 rpm), then scripts/run_corpus.py asserting:
# every control "no missing physics", every correctly named parameter within
# 20 %, no effect named wrongly with confidence, >= 3 of the 4 effects named right. The
# fourth, a 1 um pin error in 0.78 s at 1200 rpm, fits as well as a carrier runout (BIC
# 0.04 apart, docs/diagnose-log.md session 12): naming either would be a coin toss, so the
# verdict names their class, planet_position_error (docs/diagnose.md section 5, "Class
# findings"), which run_corpus.py counts as right "as a class" (before session 36: "unexplained"
# with both as the lead and its rival).
# Usage: test_quick_corpus.sh <planetwear> <workdir> <scripts dir>
set -u
PW=$1; W=$2; S=$3
rm -rf "$W"; mkdir -p "$W"
/usr/bin/python3 "$S/make_corpus.py" --quick -o "$W/corpus" --planetwear "$PW" --jobs 2 || exit 1
exec /usr/bin/python3 "$S/run_corpus.py" "$W/corpus" --planetwear "$PW" --jobs 1 --threads 1 \
  --min-accuracy 0.75 --max-wrong-names 0 --require-controls --max-parameter-error 0.2
