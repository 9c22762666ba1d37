#!/usr/bin/env python3
"""Merges campaign archives of one campaign by case index (docs/archive-format.md).

    merge_archives.py -o results.h5 results.cases-000000-000100.h5 results.cases-000100-000200.h5 ...

The inputs are archives of the *same* campaign (equal /campaign attributes
input_hash and design_hash), e.g. the per-slice archives of an array job
(slurm/sweep_array.sbatch, `planetwear sweep --cases BEGIN:END`), or two
partial runs. Row r of an input belongs to case /design/case[r], so both
layouts work: full-table archives (every case a row, cases outside the
slice `pending`) and archives holding only their slice's rows.

For each case the row is taken from the input where the case is done or
failed; a case pending everywhere stays pending (NaN results). A case done
or failed in several inputs must agree (status, message and every result
number), else the merge stops. The factor values, sample_role and
sample_row of a case must be equal in every input that has the case. The
output follows the format exactly: every dataset of any input (scalars only
some cases have are NaN elsewhere; padded arrays are padded to the widest
input with NaN; bins / elements / samples are 0 where no input has data;
rank -1, wall_time NaN, status "pending" for cases no input ran), with the
root counters and `complete` recomputed, `merged_from` (the input file
names) added, and the other attributes and /campaign taken from the first
input. Written to a temporary file and renamed onto the output (an existing
output is only replaced with --force).

Exit status: 0 merged, 1 bad input (different campaigns, conflicting cases,
not archives), 2 usage.
"""

import os
import sys

if __name__ == "__main__":
    try:
        import h5py  # noqa: F401
        import numpy  # noqa: F401
    except ImportError:
        if os.path.exists("/usr/bin/python3") and not os.environ.get("PWPLOT_REEXEC") \
                and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
            os.environ["PWPLOT_REEXEC"] = "1"
            os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
        raise

import datetime  # noqa: E402

import h5py  # noqa: E402
import numpy as np  # noqa: E402

FORMAT = "planetwear.campaign"
STR = h5py.string_dtype("utf-8")
# /design columns produced by running a case (taken from the input that ran it);
# every other /design column describes the case (must agree between inputs).
RUN_COLUMNS = ("status", "message", "wall_time", "rank")
LENGTHS = ("bins", "elements", "samples")


# Attributes of HDF5 dimension scales (the archive's /case is the scale
# of every dataset's case dimension): they hold object references into their
# own file, so a copy would point nowhere; copy_dimension_scales re-creates them.
DIMENSION_SCALE_ATTRIBUTES = frozenset({"CLASS", "NAME", "REFERENCE_LIST", "DIMENSION_LIST"})


class MergeError(Exception):
    pass


def copy_attributes(src, dst):
    """The attributes of `src` onto `dst`, except the dimension-scale ones."""
    for key, v in src.attrs.items():
        if key not in DIMENSION_SCALE_ATTRIBUTES:
            dst.attrs[key] = v


def copy_dimension_scales(source_of, out):
    """Makes the datasets of `out` dimension scales, attaches them and labels
    dimensions as the dataset `source_of[name]` (an input's dataset of the
    same name) is; datasets of inputs without scales stay without."""
    for name, src in source_of.items():
        if h5py.h5ds.is_scale(src.id):
            out[name].make_scale(_text(src.attrs.get("NAME", name.rsplit("/", 1)[-1])).rstrip("\0"))
    for name, src in source_of.items():
        for k, dim in enumerate(src.dims):
            for scale in dim.values():
                out[name].dims[k].attach_scale(out[scale.name])
            if dim.label:
                out[name].dims[k].label = dim.label


def _text(v):
    if isinstance(v, bytes):
        return v.decode("utf-8")
    if isinstance(v, np.ndarray) and v.shape == ():
        return _text(v[()])
    return v


def _is_str(ds):
    return h5py.check_string_dtype(ds.dtype) is not None or ds.dtype.kind == "O"


def _read(ds):
    return np.asarray(ds.asstr()[()], dtype=object) if _is_str(ds) else ds[()]


def _datasets(f):
    out = {}
    f.visititems(lambda n, o: out.__setitem__(n, o) if isinstance(o, h5py.Dataset) else None)
    return out


def _groups(f):
    out = []
    f.visititems(lambda n, o: out.append(n) if isinstance(o, h5py.Group) else None)
    return out


def _fill(name, dtype, n):
    base = name.rsplit("/", 1)[-1]
    if dtype == "str":
        return np.array(["pending" if name == "design/status" else ""] * n, dtype=object)
    if np.dtype(dtype).kind == "f":
        return np.full(n, np.nan, dtype=dtype)
    if name in ("design/rank", "design/sample_row"):
        return np.full(n, -1, dtype=dtype)
    if name in ("design/case", "case"):  # /case: the dimension scale of the case dimension
        return np.arange(n, dtype=dtype)
    if base in LENGTHS:
        return np.zeros(n, dtype=dtype)
    return np.zeros(n, dtype=dtype)


def _same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind == "f" or b.dtype.kind == "f":
        return a.shape == b.shape and np.array_equal(a.astype(float), b.astype(float), equal_nan=True)
    return a.shape == b.shape and np.array_equal(a, b)


def merge(inputs, output, force=False, expect_cases=None, log=print):
    if not inputs:
        raise MergeError("no input archives")
    if os.path.exists(output) and not force:
        raise MergeError(f"{output} exists (use --force to replace it)")
    files = []
    try:
        for p in inputs:
            if not os.path.exists(p):
                raise MergeError(f"{p}: no such file")
            try:
                f = h5py.File(p, "r")
            except OSError as exc:
                raise MergeError(f"{p}: not a readable HDF5 file ({exc})") from exc
            files.append(f)
            if _text(f.attrs.get("format", "")) != FORMAT:
                raise MergeError(f"{p}: not a campaign archive (format attribute "
                                 f"{_text(f.attrs.get('format', ''))!r})")
        first = files[0]
        for key in ("input_hash", "design_hash"):
            ref = _text(first["campaign"].attrs.get(key, ""))
            for p, f in zip(inputs[1:], files[1:]):
                v = _text(f["campaign"].attrs.get(key, ""))
                if v != ref:
                    raise MergeError(f"{p}: campaign {key} {v} differs from {inputs[0]}'s {ref}: "
                                     f"not the same campaign (or not the same planetwear)")
        # Global case index of every row of every input.
        row_case = [f["design/case"][()].astype(np.int64) for f in files]
        status = [f["design/status"].asstr()[()] for f in files]
        n = max(int(rc.max()) + 1 if len(rc) else 0 for rc in row_case)
        for f in files:
            n = max(n, int(f.attrs.get("cases", 0)) if len(f["design/case"]) == int(f.attrs.get("cases", -1)) else 0)
        if expect_cases is not None:
            if n > expect_cases:
                raise MergeError(f"inputs hold case {n - 1}, more than --cases {expect_cases}")
            n = expect_cases
        # Which input supplies each case's results (first with done/failed).
        source = np.full(n, -1, dtype=np.int64)
        source_row = np.full(n, -1, dtype=np.int64)
        for k, (rc, st) in enumerate(zip(row_case, status)):
            for r, (c, s) in enumerate(zip(rc, st)):
                if s == "pending":
                    continue
                if source[c] < 0:
                    source[c], source_row[c] = k, r
                else:
                    _check_duplicate(files, inputs, source[c], source_row[c], k, r, int(c))
        # Which input describes each case (any input holding its row).
        desc = np.full(n, -1, dtype=np.int64)
        desc_row = np.full(n, -1, dtype=np.int64)
        for k, rc in enumerate(row_case):
            for r, c in enumerate(rc):
                if desc[c] < 0:
                    desc[c], desc_row[c] = k, r
        missing = int(np.sum(desc < 0))
        if missing:
            log(f"merge_archives: warning: {missing} cases are in no input (left pending with NaN factor values)")

        names = {}
        for k, f in enumerate(files):
            for name, ds in _datasets(f).items():
                names.setdefault(name, k)
        tmp = f"{output}.partial-{os.getpid()}"
        try:
            with h5py.File(tmp, "w") as out:
                for key, v in first.attrs.items():
                    out.attrs[key] = v
                for g in _groups(first):
                    out.require_group(g)
                    for key, v in first[g].attrs.items():
                        out[g].attrs[key] = v
                for f in files[1:]:
                    for g in _groups(f):
                        if g not in out:
                            out.require_group(g)
                            for key, v in f[g].attrs.items():
                                out[g].attrs[key] = v
                for name in sorted(names):
                    _merge_dataset(out, name, files, names[name], row_case, n, source, source_row, desc, desc_row,
                                   inputs)
                copy_dimension_scales({name: files[k][name] for name, k in names.items()}, out)
                st = out["design/status"].asstr()[()]
                done = int(np.sum(st == "done"))
                failed = int(np.sum(st == "failed"))
                pending = int(np.sum(st == "pending"))
                out.attrs["cases"] = np.int64(n)
                out.attrs["cases_done"] = np.int64(done)
                out.attrs["cases_failed"] = np.int64(failed)
                out.attrs["cases_pending"] = np.int64(pending)
                out.attrs["complete"] = np.int64(1 if pending == 0 else 0)
                out.attrs["mpi_ranks"] = np.int64(max(int(f.attrs.get("mpi_ranks", 1)) for f in files))
                out.attrs["created_utc"] = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
                out.attrs["merged_from"] = ",".join(os.path.basename(p) for p in inputs)
                for key in ("case_begin", "case_end"):
                    if key in out.attrs:
                        del out.attrs[key]
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
            os.replace(tmp, output)
        finally:
            if os.path.exists(tmp):
                os.remove(tmp)
        log(f"merge_archives: {output}: {n} cases from {len(inputs)} archives: {done} done, {failed} failed, "
            f"{pending} pending")
        return dict(cases=n, done=done, failed=failed, pending=pending)
    finally:
        for f in files:
            f.close()


def _check_duplicate(files, inputs, k1, r1, k2, r2, case):
    a, b = files[k1], files[k2]
    for col in ("status", "message"):
        x, y = a["design/" + col].asstr()[r1], b["design/" + col].asstr()[r2]
        if x != y:
            raise MergeError(f"case {case}: {col} {x!r} in {inputs[k1]} but {y!r} in {inputs[k2]}")
    da = {k: v for k, v in _datasets(a).items() if k.startswith("results/")}
    db = {k: v for k, v in _datasets(b).items() if k.startswith("results/")}
    for name in set(da) | set(db):
        if name not in da or name not in db:
            continue
        x, y = np.asarray(da[name][r1]), np.asarray(db[name][r2])
        if x.ndim == 1:
            w = min(len(x), len(y))
            if not (_same(x[:w], y[:w]) and np.all(np.isnan(x[w:])) and np.all(np.isnan(y[w:]))):
                raise MergeError(f"case {case}: /{name} differs between {inputs[k1]} and {inputs[k2]}")
        elif not _same(x, y):
            raise MergeError(f"case {case}: /{name} differs between {inputs[k1]} and {inputs[k2]}")


def _merge_dataset(out, name, files, k0, row_case, n, source, source_row, desc, desc_row, inputs):
    ref = files[k0][name]
    if name.startswith("campaign/") or ref.ndim == 0:
        if _is_str(ref):
            out.create_dataset(name, data=ref.asstr()[()], dtype=STR)
        else:
            out.create_dataset(name, data=ref[()])
        copy_attributes(ref, out[name])
        return
    is_str = _is_str(ref)
    is_design = name.startswith("design/")
    per_case = is_design and name.rsplit("/", 1)[-1] not in RUN_COLUMNS
    if ref.ndim == 1:
        data = _fill(name, "str" if is_str else ref.dtype, n)
        if per_case:
            for k, f in enumerate(files):
                if name not in f:
                    continue
                v = _read(f[name])
                for r, c in enumerate(row_case[k]):
                    if desc[c] == k and desc_row[c] == r:
                        data[c] = v[r]
                    elif not _same(v[r], data[c]) and desc[c] >= 0 and name in files[desc[c]]:
                        raise MergeError(f"case {c}: /{name} is {v[r]!r} in {inputs[k]} but {data[c]!r} in "
                                         f"{inputs[desc[c]]}")
        else:
            for k, f in enumerate(files):
                if name not in f:
                    continue
                v = _read(f[name])
                sel = np.nonzero(source == k)[0]
                data[sel] = v[source_row[sel]]
        if is_str:
            ds = out.create_dataset(name, data=data, dtype=STR)
        else:
            ds = out.create_dataset(name, data=data)
    else:
        width = max(f[name].shape[1] for f in files if name in f)
        kind = ref.dtype
        data = np.full((n, width), np.nan if kind.kind == "f" else 0, dtype=kind)
        for k, f in enumerate(files):
            if name not in f:
                continue
            sel = np.nonzero(source == k)[0]
            if len(sel):
                rows = f[name][()]
                data[sel, :rows.shape[1]] = rows[source_row[sel]]
        kw = {}
        if width > 0 and n > 0:
            kw = dict(chunks=(1, width), shuffle=True, compression="gzip", compression_opts=4)
        ds = out.create_dataset(name, data=data, **kw)
    copy_attributes(ref, ds)


def main(argv=None):
    import argparse
    p = argparse.ArgumentParser(description="Merge campaign archives of one campaign (e.g. the slices of a SLURM "
                                            "array job) by case index into one archive (docs/archive-format.md).")
    p.add_argument("inputs", nargs="+", help="archives of the same campaign")
    p.add_argument("-o", "--output", required=True, help="merged archive to write")
    p.add_argument("--force", action="store_true", help="replace an existing output")
    p.add_argument("--cases", type=int, help="number of cases of the campaign (default: from the inputs)")
    a = p.parse_args(argv)
    try:
        merge(a.inputs, a.output, a.force, a.cases)
    except MergeError as exc:
        print(f"merge_archives: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
