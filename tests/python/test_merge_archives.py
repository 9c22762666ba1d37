"""Tests of scripts/merge_archives.py: per-slice archives of one campaign
(as the array job slurm/sweep_array.sbatch leaves them) merged by case index
give the archive of the whole campaign (docs/archive-format.md)."""
import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

import archive_fixture
import conftest
import merge_archives
import pwcampaign

CHECK_ARCHIVE = os.path.join(conftest.SOURCE_DIR, "tests", "sweep", "check_archive.py")


def slice_archive(src, dst, begin, end, layout="full"):
    """Writes the archive a run of only cases begin <= i < end would leave:
    layout "full" keeps every row (cases outside the slice pending: NaN
    results, lengths 0, rank -1, status pending); layout "rows" keeps only the
    slice's rows (with their global /design/case)."""
    with h5py.File(src, "r") as s, h5py.File(dst, "w") as d:
        n = int(s.attrs["cases"])
        keep = np.zeros(n, dtype=bool)
        keep[begin:end] = True
        rows = np.nonzero(keep)[0] if layout == "rows" else np.arange(n)
        for k, v in s.attrs.items():
            d.attrs[k] = v

        def copy(name, obj):
            if isinstance(obj, h5py.Group):
                g = d.require_group(name)
                for k, v in obj.attrs.items():
                    g.attrs[k] = v
                return
            is_str = h5py.check_string_dtype(obj.dtype) is not None
            if name.startswith("campaign/") or obj.ndim == 0:
                data = obj.asstr()[()] if is_str else obj[()]
            else:
                data = np.asarray(obj.asstr()[()], dtype=object) if is_str else obj[()]
                base = name.rsplit("/", 1)[-1]
                out_of_slice = ~keep
                if name.startswith("results/") or base in merge_archives.RUN_COLUMNS:
                    if name == "design/status":
                        data[out_of_slice] = "pending"
                    elif name == "design/message":
                        data[out_of_slice] = ""
                    elif name == "design/rank":
                        data[out_of_slice] = -1
                    elif data.dtype.kind == "f":
                        data[out_of_slice] = np.nan
                    elif base in merge_archives.LENGTHS:
                        data[out_of_slice] = 0
                data = data[rows]
            ds = d.create_dataset(name, data=data, dtype=archive_fixture.STR if is_str else None)
            merge_archives.copy_attributes(obj, ds)
        s.visititems(copy)
        merge_archives.copy_dimension_scales(merge_archives._datasets(s), d)
        st = d["design/status"].asstr()[()]
        d.attrs["cases_done"] = np.int64(np.sum(st == "done"))
        d.attrs["cases_pending"] = np.int64(np.sum(st == "pending"))
        d.attrs["complete"] = np.int64(0 if "pending" in set(st) else 1)
        if layout == "rows":
            d.attrs["cases"] = np.int64(len(rows))


def _spec():
    return conftest.small_archive_spec()


def _write(path, status, **over):
    spec = _spec()
    spec["status"] = status
    spec.update(over)
    archive_fixture.write_archive(str(path), **spec)
    return str(path)


def test_slices_merge_into_the_whole(tmp_path):
    whole = _write(tmp_path / "whole.h5", ["done", "failed", "done", "done"],
                   spectra={**_spec()["spectra"], 2: (np.arange(7) * 5.0, {"sun_planet/0/acceleration": np.ones(7), "planet_ring/0/acceleration": np.zeros(7)})})
    for layout in ("full", "rows"):
        parts = []
        for b, e in ((0, 2), (2, 3), (3, 4)):
            p = str(tmp_path / f"{layout}.cases-{b}-{e}.h5")
            slice_archive(whole, p, b, e, layout)
            parts.append(p)
        out = str(tmp_path / f"merged-{layout}.h5")
        r = merge_archives.merge(parts[::-1], out)                 # input order does not matter
        assert r == dict(cases=4, done=3, failed=1, pending=0)
        res = subprocess.run([sys.executable, CHECK_ARCHIVE, "same", out, whole], capture_output=True, text=True)
        assert res.returncode == 0, res.stdout + res.stderr
        c = pwcampaign.load(out)
        assert c.attrs["complete"] == 1 and c.attrs["cases_done"] == 3
        assert c.attrs["merged_from"].count(".h5") == 3
        assert c.array("spectra/sun_planet/0/acceleration", 2).tolist() == [1.0] * 7
        with h5py.File(out) as f:
            assert f["results/spectra/frequency"].shape == (4, 7)          # widest slice
            assert f["design/rank"][:].tolist() == [1, 1, 1, 1]


def test_missing_slice_leaves_cases_pending_and_union_of_datasets(tmp_path):
    a = _write(tmp_path / "a.h5", ["done", "pending", "pending", "pending"],
               scalars={"efficiency": [0.9, 0, 0, 0]})                       # no load_sharing_factor/3 here
    b = _write(tmp_path / "b.h5", ["pending", "pending", "pending", "done"])
    out = str(tmp_path / "m.h5")
    merge_archives.merge([a, b], out)
    c = pwcampaign.load(out)
    assert c.status.tolist() == ["done", "pending", "pending", "done"]
    assert c.attrs["complete"] == 0 and c.attrs["cases_pending"] == 2
    assert c.design.at[0, "efficiency"] == 0.9 and c.design.at[3, "efficiency"] == 0.97
    assert np.isnan(c.design.at[0, "load_sharing_factor/3"]) and c.design.at[3, "load_sharing_factor/3"] == 1.01
    assert c.design["rank"].tolist() == [1, -1, -1, 1]
    assert np.isnan(c.design.at[1, "wall_time"])
    assert c.array("spectra/frequency", 1).size == 0 and c.valid_length("wear/sun/elements", 2) == 0
    with pytest.raises(merge_archives.MergeError, match="exists"):
        merge_archives.merge([a, b], out)
    merge_archives.merge([a, b], out, force=True)


def test_refuses_different_campaigns_and_conflicting_cases(tmp_path):
    a = _write(tmp_path / "a.h5", ["done", "pending", "pending", "pending"])
    b = _write(tmp_path / "b.h5", ["pending", "done", "pending", "pending"], design_hash="ffffffffffffffff")
    with pytest.raises(merge_archives.MergeError, match="design_hash"):
        merge_archives.merge([a, b], str(tmp_path / "m.h5"))
    c = _write(tmp_path / "c.h5", ["done", "pending", "pending", "pending"],
               scalars={**_spec()["scalars"], "efficiency": [0.5, 0, 0, 0]})
    with pytest.raises(merge_archives.MergeError, match="case 0: /results/scalars/efficiency differs"):
        merge_archives.merge([a, c], str(tmp_path / "m.h5"))
    d = _write(tmp_path / "d.h5", ["failed", "pending", "pending", "pending"])
    with pytest.raises(merge_archives.MergeError, match="case 0: status"):
        merge_archives.merge([a, d], str(tmp_path / "m.h5"))
    e = _write(tmp_path / "e.h5", ["pending", "done", "pending", "pending"],
               values=[[100.0, 1e-17], [250.0, 3e-17], [300.0, 5e-17], [400.0, 1e-16]])
    with pytest.raises(merge_archives.MergeError, match="case 1: /design/operating.input_speed_rpm"):
        merge_archives.merge([a, e], str(tmp_path / "m.h5"))
    same = merge_archives.merge([a, a], str(tmp_path / "aa.h5"))        # a case done twice, identically
    assert same["done"] == 1
    assert not os.path.exists(tmp_path / "m.h5")                       # nothing written on refusal
    assert not [p for p in os.listdir(tmp_path) if ".partial-" in p]
    r = subprocess.run([sys.executable, os.path.join(conftest.SCRIPTS, "merge_archives.py"), "-o",
                        str(tmp_path / "m.h5"), a, b], capture_output=True, text=True)
    assert r.returncode == 1 and "design_hash" in r.stderr


def test_real_campaign_split_and_merged_is_identical(real_archive, tmp_path):
    parts = []
    for b, e in ((0, 1), (1, 3)):
        p = str(tmp_path / f"part-{b}-{e}.h5")
        slice_archive(real_archive, p, b, e, "full")
        parts.append(p)
    out = str(tmp_path / "merged.h5")
    subprocess.run([sys.executable, os.path.join(conftest.SCRIPTS, "merge_archives.py"), "-o", out] + parts,
                   check=True, capture_output=True)
    res = subprocess.run([sys.executable, CHECK_ARCHIVE, "same", out, real_archive], capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    res = subprocess.run([sys.executable, CHECK_ARCHIVE, "complete", out], capture_output=True, text=True)
    assert res.returncode == 0, res.stdout
    # The dimension scales are re-created, not copied as references into the inputs.
    with h5py.File(out, "r") as m, h5py.File(real_archive, "r") as ref:
        assert h5py.h5ds.is_scale(m["case"].id)
        for name in ("design/status", "results/scalars/efficiency", "results/spectra/frequency"):
            assert [s.name for s in m[name].dims[0].values()] == ["/case"], name
            assert [d.label for d in m[name].dims] == [d.label for d in ref[name].dims], name
