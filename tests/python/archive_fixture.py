"""Writes small campaign archives with h5py, following docs/archive-format.md
(the contract between `planetwear sweep` and the Python post-processing), for
the tests of scripts/pwcampaign.py and scripts/merge_archives.py.

    write_archive(path, factors, values, status, scalars=..., spectra=..., wear=..., time_history=...)

* factors: list of dicts {key, unit, scale, min, max} (min/max optional);
* values: [cases, d] factor values; status: list of "done"/"failed"/"pending";
* scalars: {name: [cases]} (NaN is written for cases that are not done);
* spectra: {case: (frequency [bins], {channel: amplitude [bins]})};
* wear: {family: {case: (distance [elements], depth [elements])}};
* time_history: {case: (time [samples], {channel: values [samples]})}.
Arrays of different lengths are padded with NaN to the longest, the valid
length goes to bins / elements / samples (0 = none), as the writer does.
"""
import h5py
import numpy as np

STR = h5py.string_dtype("utf-8")


def _attrs(obj, unit=None, description=""):
    if unit is not None:
        obj.attrs["unit"] = unit
    obj.attrs["description"] = description


def _padded(group, name, rows, n_cases, unit, description):
    width = max([len(v) for v in rows.values()] + [0])
    data = np.full((n_cases, width), np.nan)
    lengths = np.zeros(n_cases, dtype=np.int32)
    for i, v in rows.items():
        data[i, :len(v)] = v
        lengths[i] = len(v)
    ds = group.create_dataset(name, data=data, chunks=(1, max(width, 1)) if width else None,
                              shuffle=bool(width), compression="gzip" if width else None)
    _attrs(ds, unit, description)
    return lengths


def write_archive(path, factors, values, status, messages=None, scalars=None, scalar_units=None, spectra=None,
                  wear=None, time_history=None, design_type="full_factorial", roles=None, rows=None,
                  name="fixture", input_hash="00112233445566aa", design_hash="8899aabbccddeeff", case_index=None,
                  root_extra=None):
    values = np.asarray(values, dtype=float)
    n = len(status)
    assert values.shape == (n, len(factors))
    messages = messages or [""] * n
    scalars = scalars or {}
    scalar_units = scalar_units or {}
    done = np.array([s == "done" for s in status])
    case = np.arange(n, dtype=np.int32) if case_index is None else np.asarray(case_index, dtype=np.int32)
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "planetwear.campaign"
        f.attrs["format_version"] = np.int64(1)
        f.attrs["software_version"] = "0.1.0"
        f.attrs["build_flags"] = "test fixture"
        f.attrs["created_utc"] = "2026-01-01T00:00:00Z"
        f.attrs["units_convention"] = "SI"
        f.attrs["cases"] = np.int64(n)
        f.attrs["cases_done"] = np.int64(sum(s == "done" for s in status))
        f.attrs["cases_failed"] = np.int64(sum(s == "failed" for s in status))
        f.attrs["cases_pending"] = np.int64(sum(s == "pending" for s in status))
        f.attrs["complete"] = np.int64(0 if "pending" in status else 1)
        f.attrs["mpi_ranks"] = np.int64(2)
        for k, v in (root_extra or {}).items():
            f.attrs[k] = v
        c = f.create_group("campaign")
        c["toml"] = "[campaign]\nname = \"fixture\"\n"
        c["toml"].attrs["description"] = "the campaign file, verbatim"
        c["base_config_toml"] = "[operating]\ninput_speed_rpm = 100.0\n"
        for k, v in dict(name=name, description="test fixture", campaign_file="fixture.toml",
                         base_config_file="", design_type=design_type,
                         factors=",".join(fa["key"] for fa in factors), input_hash=input_hash,
                         design_hash=design_hash).items():
            c.attrs[k] = v
        for k in ("seed", "points", "samples", "base_samples", "time_history_decimation"):
            c.attrs[k] = np.int64(0)
        c.attrs["spectrum_max_frequency_Hz"] = 0.0
        d = f.create_group("design")
        cols = ["case"] + [fa["key"] for fa in factors] + ["status", "message", "wall_time", "rank",
                                                            "sample_role", "sample_row"]
        d.attrs["columns"] = ",".join(cols)
        d.attrs["description"] = "one row per case"
        _attrs(d.create_dataset("case", data=case), None, "case index (row of every /results dataset)")
        for j, fa in enumerate(factors):
            ds = d.create_dataset(fa["key"], data=values[:, j])
            _attrs(ds, fa["unit"], f"factor {j}: configuration key {fa['key']}")
            ds.attrs["scale"] = fa.get("scale", "linear")
            for b in ("min", "max"):
                if b in fa:
                    ds.attrs[b] = float(fa[b])
        _attrs(d.create_dataset("status", data=np.array(status, dtype=object), dtype=STR), None, "pending, done or failed")
        _attrs(d.create_dataset("message", data=np.array(messages, dtype=object), dtype=STR), None, "reason")
        wall = np.where(np.array([s != "pending" for s in status]), 1.5, np.nan)
        _attrs(d.create_dataset("wall_time", data=wall), "s", "wall time")
        rank = np.where(np.array([s != "pending" for s in status]), 1, -1).astype(np.int32)
        _attrs(d.create_dataset("rank", data=rank), None, "MPI rank; -1 = not run")
        _attrs(d.create_dataset("sample_role", data=np.array(roles or [""] * n, dtype=object), dtype=STR), None,
               "saltelli role")
        _attrs(d.create_dataset("sample_row", data=np.asarray(rows if rows is not None else [-1] * n,
                                                              dtype=np.int32)), None, "saltelli row")
        r = f.create_group("results")
        s = r.create_group("scalars")
        for k, v in scalars.items():
            v = np.where(done, np.asarray(v, dtype=float), np.nan)
            _attrs(s.create_dataset(k, data=v), scalar_units.get(k, "1"), f"scalar {k}")
        if spectra is not None:
            g = r.create_group("spectra")
            freq = {i: fr for i, (fr, _) in spectra.items()}
            bins = _padded(g, "frequency", freq, n, "Hz", "frequency of each bin")
            channels = sorted({ch for _, chans in spectra.values() for ch in chans})
            for ch in channels:
                _padded(g, ch, {i: chans[ch] for i, (_, chans) in spectra.items()}, n, "m/s^2",
                        f"amplitude spectrum of {ch}")
            _attrs(g.create_dataset("bins", data=bins), None, "valid bins; 0 = not done")
        if wear is not None:
            for fam, per_case in wear.items():
                g = r.create_group(f"wear/{fam}")
                el = _padded(g, "distance_from_pitch_point", {i: x for i, (x, _) in per_case.items()}, n, "m",
                             "distance from pitch point")
                _padded(g, "depth_final", {i: h for i, (_, h) in per_case.items()}, n, "m", "mean over teeth")
                _padded(g, "depth_final_max", {i: 1.1 * h for i, (_, h) in per_case.items()}, n, "m", "max")
                _attrs(g.create_dataset("elements", data=el), None, "elements; 0 = no wear data")
        if time_history is not None:
            g = r.create_group("time_history")
            g.attrs["decimation"] = np.int64(4)
            sm = _padded(g, "time", {i: t for i, (t, _) in time_history.items()}, n, "s", "time")
            channels = sorted({ch for _, chans in time_history.values() for ch in chans})
            for ch in channels:
                _padded(g, ch, {i: chans[ch] for i, (_, chans) in time_history.items()}, n, "m", ch)
            _attrs(g.create_dataset("samples", data=sm), None, "valid samples")
