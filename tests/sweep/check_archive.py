#!/usr/bin/python3
"""Checks of campaign archives (docs/archive-format.md) for the sweep tests.

  check_archive.py same A.h5 B.h5
      every dataset of A and B holds the same numbers (NaN == NaN), except the
      run-dependent /design/wall_time and /design/rank; same units.
  check_archive.py partial A.h5 REF.h5
      A (possibly from a killed run) opens; every case marked done in A equals
      that case in the complete reference REF; failed cases carry REF's
      reason; pending cases hold NaN only.
  check_archive.py complete A.h5
      no case pending, root attribute complete = 1, no journal directory.

Exit status 0 = pass; a failure prints what differs.
"""
import os
import sys

import h5py
import numpy as np

RUN_DEPENDENT = {"design/wall_time", "design/rank"}


def datasets(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj) if isinstance(obj, h5py.Dataset) else None)
    return out


def value(ds):
    if ds.dtype.kind == "O":
        return ds.asstr()[()]
    return ds[()]


def equal(x, y):
    if isinstance(x, np.ndarray) and x.dtype.kind == "f":
        return x.shape == y.shape and np.array_equal(x, y, equal_nan=True)
    if isinstance(x, np.ndarray):
        return x.shape == y.shape and np.array_equal(x, y)
    return x == y


def fail(message):
    print("check_archive: FAIL:", message)
    sys.exit(1)


def same(a_path, b_path):
    with h5py.File(a_path, "r") as a, h5py.File(b_path, "r") as b:
        da, db = datasets(a), datasets(b)
        if set(da) != set(db):
            fail(f"datasets differ: only in {a_path}: {sorted(set(da) - set(db))}; "
                 f"only in {b_path}: {sorted(set(db) - set(da))}")
        for name in sorted(da):
            if name in RUN_DEPENDENT:
                continue
            if not equal(value(da[name]), value(db[name])):
                fail(f"{name} differs between {a_path} and {b_path}")
            if da[name].attrs.get("unit") != db[name].attrs.get("unit"):
                fail(f"{name}: unit differs")
        print(f"check_archive: {len(da)} datasets identical in {a_path} and {b_path}")


def row_matches(a, r, i, name):
    """Row i of dataset a equals row i of r over a's width; r's extra columns are NaN."""
    x, y = a[i], r[i]
    if np.ndim(x) == 0:
        return equal(np.asarray(x), np.asarray(y))
    w = x.shape[0]
    if y.shape[0] < w:
        return False
    return np.array_equal(x, y[:w], equal_nan=True) and bool(np.all(np.isnan(y[w:])))


def partial(a_path, ref_path):
    with h5py.File(a_path, "r") as a, h5py.File(ref_path, "r") as ref:
        status = a["design/status"].asstr()[:]
        ref_status = ref["design/status"].asstr()[:]
        message = a["design/message"].asstr()[:]
        ref_message = ref["design/message"].asstr()[:]
        if len(status) != len(ref_status):
            fail("number of cases differs")
        results = {k: v for k, v in datasets(a).items() if k.startswith("results/")}
        ref_results = datasets(ref)
        done = [i for i, s in enumerate(status) if s == "done"]
        for i, s in enumerate(status):
            if s == "pending":
                for name, ds in results.items():
                    if ds.dtype.kind == "f" and not np.all(np.isnan(ds[i])):
                        fail(f"pending case {i} has numbers in {name}")
                continue
            if s != ref_status[i] or message[i] != ref_message[i]:
                fail(f"case {i}: status {s!r} ({message[i]!r}), reference {ref_status[i]!r} ({ref_message[i]!r})")
            if s != "done":
                continue
            for name, ds in results.items():
                if name not in ref_results:
                    fail(f"{name} is not in the reference")
                if not row_matches(ds, ref_results[name], i, name):
                    fail(f"done case {i} differs from the reference in {name}")
        for col in a["design"]:
            if "design/" + col in RUN_DEPENDENT or col in ("status", "message"):
                continue
            if not equal(value(a["design"][col]), value(ref["design"][col])):
                fail(f"/design/{col} differs from the reference")
        print(f"check_archive: {a_path} opens; {len(done)} done, "
              f"{sum(s == 'failed' for s in status)} failed, {sum(s == 'pending' for s in status)} pending; "
              "finished cases match the reference")


def complete(a_path):
    with h5py.File(a_path, "r") as a:
        status = a["design/status"].asstr()[:]
        if any(s == "pending" for s in status):
            fail(f"{a_path} has pending cases")
        if a.attrs["complete"] != 1:
            fail(f"{a_path}: root attribute complete is not 1")
    if os.path.exists(a_path + ".journal"):
        fail(f"{a_path}.journal still exists")
    print(f"check_archive: {a_path} complete, no journal left")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        print(__doc__)
        sys.exit(2)
    command = sys.argv[1]
    if command == "same" and len(sys.argv) == 4:
        same(sys.argv[2], sys.argv[3])
    elif command == "partial" and len(sys.argv) == 4:
        partial(sys.argv[2], sys.argv[3])
    elif command == "complete" and len(sys.argv) == 3:
        complete(sys.argv[2])
    else:
        print(__doc__)
        sys.exit(2)
