#!/bin/sh
# Usage: test_corpus.sh <planetwear> <workdir> <make_corpus.py>
# The quick corpus: 6 recordings + sidecars in recordings/, the answers in
# truth.json outside it, and no sidecar that names its effect.
set -u
PW=$1; W=$2; MAKE=$3
rm -rf "$W"; mkdir -p "$W"
/usr/bin/python3 "$MAKE" --quick -o "$W/corpus" --planetwear "$PW" --jobs 2 || exit 1
/usr/bin/python3 - "$W/corpus" <<'PY'
import json, os, sys
root = sys.argv[1]
rec = os.path.join(root, "recordings")
files = sorted(os.listdir(rec))
errors = []
if len(files) != 12 or len([f for f in files if f.endswith(".csv")]) != 6:
    errors.append(f"expected 6 recordings with sidecars, got {files}")
if any("truth" in f for f in files) or not os.path.exists(os.path.join(root, "truth.json")):
    errors.append("truth.json must be beside recordings/, not in it")
truth = json.load(open(os.path.join(root, "truth.json")))["recordings"]
effects = {v["effect"] for v in truth.values()}
if "none" not in effects or len(effects) < 4:
    errors.append(f"effects {effects}")
for name, t in truth.items():
    text = open(os.path.join(rec, name + ".json")).read()
    for word in ("imperfections", "stiffness", "effect", "worn", "pin_error", t["effect"]):
        if word in text:
            errors.append(f"{name}.json mentions '{word}'")
    meta = json.loads(text)
    if meta["operating"]["input_speed_rpm"] != t["speed_rpm"]:
        errors.append(f"{name}: speed")
    if not 0.05 <= t["noise_fraction_of_rms"] <= 0.10 or t["dc_offset_fraction_of_rms"] == 0:
        errors.append(f"{name}: noise / offset settings {t}")
print("\n".join("FAIL " + e for e in errors) or "corpus ok")
sys.exit(1 if errors else 0)
PY
