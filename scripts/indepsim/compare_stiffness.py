#!/usr/bin/env python3
"""Mesh-stiffness harmonics of the independent simulator's law against planetwear's.

    /usr/bin/python3 scripts/indepsim/compare_stiffness.py --planetwear build/apps/planetwear \
        DIR/seed3p/gearset.toml DIR/four4p/gearset.toml

For each gear-set file: the combined mesh stiffness over one mesh cycle of both mesh families,
from this simulator's tables (sim.Stage.tab, before its ISO load factor, which scales the mean
only) and from `planetwear stiffness --csv`; prints the ratio of the means and the first
harmonics relative to each mean (docs/diagnose-log.md, session 21). A comparison tool for the
two models, not part of the independent simulator.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import pandas as pd

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sim  # noqa: E402

FAMILIES = (("sp", "sun_planet"), ("rp", "planet_ring"))


def relative_harmonics(x, count):
    c = np.fft.rfft(x) / len(x)
    mean = np.abs(c[0])
    return mean, 2 * np.abs(c[1:count + 1]) / mean


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("gearsets", nargs="+", help="gear-set TOML files of the independent corpus")
    ap.add_argument("--planetwear", required=True, help="path of the planetwear executable")
    ap.add_argument("--harmonics", type=int, default=5, help="harmonics to print (default 5)")
    a = ap.parse_args(argv)
    for path in a.gearsets:
        stage = sim.Stage(sim.read_gearset_toml(path))
        with tempfile.TemporaryDirectory() as tmp:
            csv = os.path.join(tmp, "k.csv")
            subprocess.run([a.planetwear, "stiffness", "-c", path, "--csv", csv], check=True,
                           stdout=subprocess.DEVNULL)
            ours_all = pd.read_csv(csv)
        for key, name in FAMILIES:
            theirs = stage.tab[key][:-1, 0]  # the table's last point repeats its first
            ours = ours_all[ours_all.curve == f"{name}/combined"].stiffness_N_m.values[:-1]
            m1, h1 = relative_harmonics(theirs, a.harmonics)
            m2, h2 = relative_harmonics(ours, a.harmonics)
            print(f"{path} {name}: mean independent / planetwear {m1 / m2:.3f}")
            print("  harmonics / mean, independent:", " ".join(f"{v:.3f}" for v in h1))
            print("  harmonics / mean, planetwear: ", " ".join(f"{v:.3f}" for v in h2))


if __name__ == "__main__":
    main()
