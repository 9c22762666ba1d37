#!/usr/bin/python3
"""Largest relative difference between two `planetwear simulate` outputs (docs/benchmark.md).

    compare_outputs.py OLD.h5 NEW.h5            same time step: max |new - old| / max |old| per dataset
    compare_outputs.py --halved DT.h5 DT2.h5    DT2 run with half the step: every other sample of DT2

Prints the largest ratio over the time histories and curves, the three largest over the scalars,
and, separately, the argmax scalars (`*_planet`, an index: a tie between symmetric planets may
flip with round-off). --halved compares the time histories only (the discretization error).
"""
import sys

import h5py
import numpy as np


def same_step(old, new):
    worst, scalars = (0.0, ""), []

    def visit(name, obj):
        nonlocal worst
        if not isinstance(obj, h5py.Dataset) or name not in new:
            return
        x, y = np.asarray(obj[()]), np.asarray(new[name][()])
        if x.dtype.kind not in "fiu" or x.size == 0:
            return
        if name.endswith("_planet"):
            if not np.array_equal(x, y):
                print(f"  argmax index {name}: {x} -> {y}")
            return
        if x.shape != y.shape:
            print(f"  shape {name}: {x.shape} -> {y.shape}")
            return
        m = float(np.max(np.abs(x)))
        d = float(np.max(np.abs(x.astype(float) - y.astype(float))))
        r = d / m if m > 0 else d
        if name.startswith("scalars/"):
            scalars.append((r, name))
        elif r > worst[0]:
            worst = (r, name)

    old.visititems(visit)
    print(f"time histories and curves: largest relative difference {worst[0]:.3g} ({worst[1]})")
    scalars.sort(reverse=True)
    print("scalars: " + ", ".join(f"{n} {r:.2g}" for r, n in scalars[:3]))


def halved(coarse, fine):
    res = []

    def visit(name, obj):
        if not isinstance(obj, h5py.Dataset) or not name.startswith("time_history/") or name not in fine:
            return
        x, y = np.asarray(obj[()], float), np.asarray(fine[name][()], float)
        # A torque ripple rounds the recorded window to whole ripple periods: lengths may differ slightly.
        if x.ndim != 1 or abs(len(y) - 2 * len(x)) > 64:
            return
        y = y[::2]
        n = min(len(x), len(y))
        m = float(np.max(np.abs(x[:n])))
        if m > 0:
            res.append((float(np.max(np.abs(x[:n] - y[:n]))) / m, name))

    coarse.visititems(visit)
    res.sort()
    r = np.array([v for v, _ in res])
    print(f"{len(res)} time histories, dt vs dt/2: median {np.median(r):.3g}, largest {r.max():.3g} ({res[-1][1]})")


def main(argv):
    if len(argv) == 4 and argv[1] == "--halved":
        halved(h5py.File(argv[2], "r"), h5py.File(argv[3], "r"))
    elif len(argv) == 3:
        same_step(h5py.File(argv[1], "r"), h5py.File(argv[2], "r"))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
