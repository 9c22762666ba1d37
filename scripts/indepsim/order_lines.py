#!/usr/bin/python3
"""Carrier-order line amplitudes of recordings and of planetwear simulations, side by side.

    /usr/bin/python3 scripts/indepsim/order_lines.py \
        --recording BASE.csv:acc_housing --recording FAULT.csv:acc_housing \
        --simulation healthy.h5:housing/acceleration --simulation fault.h5:housing/acceleration \
        --orders 77-85,158-166 [--revolutions 3]

A recording is an indepsim CSV (first line a comment, then a header with `time` [s] and
`w_carrier` [rad/s]); its carrier angle is the trapezoidal integral of w_carrier. A simulation
is a `planetwear simulate` HDF5 file recorded over at least --revolutions carrier revolutions
(solver.record_mesh_cycles >= revolutions x ring teeth) with its carrier/angle channel stored
(`--channels carrier/,<channel>`). Each signal is resampled to 4096 points per carrier
revolution over the first --revolutions whole revolutions, its mean removed, and its one-sided
DFT amplitude (units of the column) printed at each integer carrier order: one line per order,
one column per signal, and for each consecutive pair of signals (healthy, fault) their ratio.
No window: whole revolutions put every carrier-order line on a bin.
"""
import argparse
import sys

import numpy as np

POINTS_PER_REVOLUTION = 4096


def order_amplitudes(theta, x, revolutions):
    """One-sided DFT amplitude per 1/revolutions carrier order over whole revolutions."""
    grid = theta[0] + np.arange(revolutions * POINTS_PER_REVOLUTION) * 2 * np.pi / POINTS_PER_REVOLUTION
    if grid[-1] > theta[-1]:
        sys.exit(f"error: the signal covers {(theta[-1] - theta[0]) / (2 * np.pi):.2f} carrier revolutions, "
                 f"fewer than --revolutions {revolutions}")
    y = np.interp(grid, theta, x)
    y = y - y.mean()
    return np.abs(np.fft.rfft(y)) * 2 / len(y)


def recording(spec, revolutions):
    path, column = spec.rsplit(":", 1)
    d = np.genfromtxt(path, delimiter=",", names=True, skip_header=1)
    t, wc = d["time"], d["w_carrier"]
    theta = np.concatenate([[0.0], np.cumsum(0.5 * (wc[1:] + wc[:-1]) * np.diff(t))])
    return order_amplitudes(theta, d[column], revolutions)


def simulation(spec, revolutions):
    import h5py
    path, channel = spec.rsplit(":", 1)
    with h5py.File(path, "r") as f:
        th = f["time_history"]
        return order_amplitudes(th["carrier/angle"][()], th[channel][()], revolutions)


def parse_orders(text):
    out = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out.extend(range(int(lo), int(hi or lo) + 1))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--recording", action="append", default=[], help="CSV:column")
    ap.add_argument("--simulation", action="append", default=[], help="HDF5:time-history channel")
    ap.add_argument("--orders", required=True, help="carrier orders, e.g. 77-85,158-166")
    ap.add_argument("--revolutions", type=int, default=3, help="whole carrier revolutions analysed (default 3)")
    a = ap.parse_args()
    if a.revolutions < 1:
        sys.exit("error: --revolutions must be >= 1")
    label = lambda s: s.rsplit(":", 1)[0].rsplit("/", 1)[-1]  # the file's name
    names = [(label(s), recording(s, a.revolutions)) for s in a.recording]
    names += [(label(s), simulation(s, a.revolutions)) for s in a.simulation]
    if not names:
        sys.exit("error: give at least one --recording or --simulation")
    head = "order " + " ".join(f"{n[-16:]:>16s}" for n, _ in names)
    pairs = [(i, i + 1) for i in range(0, len(names) - 1, 2)]
    head += " " + " ".join(f"{'ratio ' + str(i + 2) + '/' + str(i + 1):>12s}" for i, _ in pairs)
    print(head)
    for o in parse_orders(a.orders):
        k = o * a.revolutions
        row = f"{o:5d} " + " ".join(f"{amp[k]:16.5g}" for _, amp in names)
        row += " " + " ".join(f"{names[j][1][k] / max(names[i][1][k], 1e-300):12.4g}" for i, j in pairs)
        print(row)


if __name__ == "__main__":
    main()
