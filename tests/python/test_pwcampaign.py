"""Tests of scripts/pwcampaign.py (loader), scripts/sobol_indices.py and
scripts/plot_campaign.py on archives written here with h5py following
docs/archive-format.md, and end to end on a real `planetwear sweep` run."""
import os
import subprocess
import sys

import h5py
import numpy as np
import pandas as pd
import pytest
from scipy.stats import qmc

import archive_fixture
import conftest
import plot_campaign
import pwcampaign
import sobol_indices


# ------------------------------------------------------------------ the loader
def test_design_table_has_one_row_per_case_with_decoded_strings_and_scalars(small_archive):
    c = pwcampaign.load(small_archive)
    t = c.design
    assert len(t) == 4 and list(t.index) == [0, 1, 2, 3]
    assert list(t.columns[:9]) == ["case", "operating.input_speed_rpm", "wear.coefficient_m2_N", "status",
                                   "message", "wall_time", "rank", "sample_role", "sample_row"]
    assert list(t["status"]) == ["done", "failed", "pending", "done"]
    assert isinstance(t.at[1, "message"], str) and t.at[1, "message"].startswith("solver.time_step_s")
    assert t["operating.input_speed_rpm"].tolist() == [100.0, 200.0, 300.0, 400.0]
    for name in ("efficiency", "sun_planet/0/acceleration_rms", "max_wear/sun", "load_sharing_factor/3"):
        assert name in t.columns and name in c.scalar_names
    assert t.at[0, "sun_planet/0/acceleration_rms"] == 10.0
    assert np.isnan(t.at[1, "efficiency"]) and np.isnan(t.at[2, "efficiency"])   # NaN = no result
    assert np.isnan(t.at[0, "load_sharing_factor/3"]) and t.at[3, "load_sharing_factor/3"] == 1.01
    assert t["rank"].tolist() == [1, 1, -1, 1]


def test_units_factors_and_masks(small_archive):
    c = pwcampaign.load(small_archive)
    assert c.units["operating.input_speed_rpm"] == "rpm"
    assert c.units["wall_time"] == "s"
    assert c.units["sun_planet/0/acceleration_rms"] == "m/s^2"
    assert c.units["max_wear/sun"] == "m"
    assert c.unit("spectra/sun_planet/0/acceleration") == "m/s^2"
    assert c.unit("wear/sun/depth_final") == "m"
    assert c.factor_names == ["operating.input_speed_rpm", "wear.coefficient_m2_N"]
    assert c.factors.loc["wear.coefficient_m2_N", "scale"] == "log"
    assert c.factors.loc["operating.input_speed_rpm", "unit"] == "rpm"
    assert c.factors.loc["operating.input_speed_rpm", "min"] == 100.0
    assert c.factors.loc["operating.input_speed_rpm", "max"] == 400.0
    assert c.done.tolist() == [True, False, False, True]
    assert c.failed.tolist() == [False, True, False, False]
    assert c.pending.tolist() == [False, False, True, False]
    assert c.label("operating.input_speed_rpm") == "operating.input_speed_rpm [rpm]"
    assert c.overrides(3) == ["operating.input_speed_rpm=400", "wear.coefficient_m2_N=1e-16"]


def test_per_case_arrays_are_cut_to_their_valid_length(small_archive):
    c = pwcampaign.load(small_archive)
    np.testing.assert_array_equal(c.frequency(0), np.arange(5) * 10.0)
    np.testing.assert_array_equal(c.frequency(3), np.arange(3) * 40.0)        # padded with NaN in the file
    f, a = c.spectrum("sun_planet/0/acceleration", 3)
    np.testing.assert_array_equal(a, [5, 6, 7.0])
    assert c.array("spectra/planet_ring/0/acceleration", 0).tolist() == [4, 3, 2, 1, 0]
    assert c.array("results/spectra/sun_planet/0/acceleration", 1).size == 0  # failed: 0 bins
    assert c.array("spectra/sun_planet/0/acceleration", 2).size == 0          # pending
    x, h = c.wear_profile("sun", 3)
    assert len(x) == len(h) == 3 and np.all(np.isfinite(h))
    x, h = c.wear_profile("sun", 0, "depth_final_max")
    np.testing.assert_allclose(h, 1.1e-8 * np.arange(1, 5))
    t, y = c.time_history("sun_planet/0/deflection", 3)
    np.testing.assert_array_equal(y, [7e-6, 8e-6])
    assert c.valid_length("time_history/sun_planet/0/deflection", 0) == 6
    assert c.array("spectra/bins", 3) == 3                                       # 1-D: the number
    assert set(c.wear_families()) == {"sun", "planet_0/sun_side"}
    assert set(c.spectrum_channels()) == {"sun_planet/0/acceleration", "planet_ring/0/acceleration"}
    assert set(c.arrays("spectra/frequency")) == {0, 3}                          # done cases only
    with h5py.File(small_archive, "r") as f:                                     # the padding really is there
        assert np.all(np.isnan(f["results/spectra/frequency"][3, 3:]))
        assert np.all(np.isnan(f["results/spectra/frequency"][2]))


def test_errors_name_the_file_and_dataset(small_archive, tmp_path):
    with pytest.raises(pwcampaign.CampaignError, match="no such file"):
        pwcampaign.load(tmp_path / "missing.h5")
    other = tmp_path / "simulate.h5"
    with h5py.File(other, "w") as f:
        f.attrs["format"] = "planetwear.result"
    with pytest.raises(pwcampaign.CampaignError, match="not 'planetwear.campaign'"):
        pwcampaign.load(other)
    c = pwcampaign.load(small_archive)
    with pytest.raises(pwcampaign.CampaignError, match="/results/spectra/sun_planet/0/velocity not found.*holds"):
        c.array("spectra/sun_planet/0/velocity", 0)
    with pytest.raises(pwcampaign.CampaignError, match="out of range"):
        c.array("spectra/frequency", 4)
    with pytest.raises(pwcampaign.CampaignError, match="not 'saltelli'"):
        c.saltelli()


def test_one_line_pandas_read_of_the_docs_matches_the_loader(small_archive):
    design = pd.DataFrame({k: (v.asstr()[:] if v.dtype.kind == "O" else v[:])
                           for k, v in h5py.File(small_archive)["design"].items()})
    c = pwcampaign.load(small_archive)
    for k in design.columns:
        assert design[k].tolist() == c.design[k].tolist() or np.allclose(design[k], c.design[k], equal_nan=True)


def test_command_line_summary_and_csv(small_archive, tmp_path):
    script = os.path.join(conftest.SCRIPTS, "pwcampaign.py")
    r = subprocess.run([sys.executable, script, small_archive], capture_output=True, text=True, check=True)
    assert "2 done, 1 failed, 1 pending" in r.stdout and "case 1 failed" in r.stdout
    csv = tmp_path / "t.csv"
    subprocess.run([sys.executable, script, small_archive, "--csv", str(csv)], check=True, capture_output=True)
    t = pd.read_csv(csv)
    assert len(t) == 4 and "max_wear/sun" in t.columns


# ------------------------------------------------------------------ Sobol'
def _ishigami_samples(n, kind, seed):
    if kind == "sobol":
        u = qmc.Sobol(6, scramble=True, seed=seed).random(n)
    else:
        u = np.random.default_rng(seed).random((n, 6))
    A, B = -np.pi + 2 * np.pi * u[:, :3], -np.pi + 2 * np.pi * u[:, 3:]
    fAB = np.column_stack([sobol_indices.ishigami(np.where(np.arange(3) == i, B, A)) for i in range(3)])
    return A, B, sobol_indices.ishigami(A), sobol_indices.ishigami(B), fAB


def test_ishigami_analytic_indices():
    s1, st = sobol_indices.ishigami_indices(7.0, 0.1)
    np.testing.assert_allclose(s1, [0.3139, 0.4424, 0.0], atol=5e-5)
    np.testing.assert_allclose(st, [0.5576, 0.4424, 0.2437], atol=5e-5)


@pytest.mark.parametrize("kind,n", [("sobol", 2 ** 13), ("random", 2 ** 14)])
def test_ishigami_indices_within_bootstrap_error(kind, n):
    """Tolerance: the estimators' standard error shrinks as 1/sqrt(N); the
    bootstrap standard error (rows resampled) measures it for this N. Each
    estimate must lie within 4 bootstrap standard errors of the analytic value
    (a 4-sigma event has probability 6e-5 for a Gaussian estimator), the
    standard errors must be of the size expected at this N (< 2.5/sqrt(N),
    i.e. about 0.03 at N = 8192: the test is not vacuous), and the 99 %
    percentile interval must cover the truth. For the scrambled Sobol'
    sequence the bootstrap (which assumes independent rows) overstates the
    error, so the checks are conservative there."""
    s1_true, st_true = sobol_indices.ishigami_indices()
    _, _, fA, fB, fAB = _ishigami_samples(n, kind, seed=12345)
    r = sobol_indices.sobol_indices(fA, fB, fAB, n_bootstrap=400, confidence=0.99, seed=7)
    assert r.attrs["N"] == n
    for col, truth in (("S1", s1_true), ("ST", st_true)):
        se = r[col + "_se"].to_numpy()
        assert np.all(se < 2.5 / np.sqrt(n)), (col, se)
        err = np.abs(r[col].to_numpy() - truth)
        assert np.all(err < 4 * se), (col, r[col].to_numpy(), truth, se)
        assert np.all((r[col + "_lo"] <= truth) & (truth <= r[col + "_hi"])), (col, r, truth)


def test_bootstrap_is_reproducible_and_drops_rows_with_nan():
    _, _, fA, fB, fAB = _ishigami_samples(512, "random", seed=1)
    a = sobol_indices.sobol_indices(fA, fB, fAB, n_bootstrap=50, seed=3)
    b = sobol_indices.sobol_indices(fA, fB, fAB, n_bootstrap=50, seed=3)
    pd.testing.assert_frame_equal(a, b)
    fA2 = fA.copy()
    fA2[5] = np.nan
    c = sobol_indices.sobol_indices(fA2, fB, fAB, n_bootstrap=0)
    d = sobol_indices.sobol_indices(np.delete(fA, 5), np.delete(fB, 5), np.delete(fAB, 5, axis=0), n_bootstrap=0)
    assert c.attrs["N"] == 511
    np.testing.assert_allclose(c[["S1", "ST"]], d[["S1", "ST"]])


def _saltelli_archive(path, n, failed_case=None):
    """A saltelli-design archive of the Ishigami function in SALib's case order
    (per row j: A_j, AB_0,j, AB_1,j, AB_2,j, B_j), docs/campaigns.md."""
    A, B, fA, fB, fAB = _ishigami_samples(n, "sobol", seed=5)
    d = 3
    values, roles, rows, y = [], [], [], []
    for j in range(n):
        values.append(A[j]); roles.append("A"); rows.append(j); y.append(fA[j])
        for i in range(d):
            values.append(np.where(np.arange(d) == i, B[j], A[j])); roles.append(f"AB_{i}"); rows.append(j)
            y.append(fAB[j, i])
        values.append(B[j]); roles.append("B"); rows.append(j); y.append(fB[j])
    status = ["done"] * len(y)
    if failed_case is not None:
        status[failed_case] = "failed"
    factors = [{"key": f"x{i}", "unit": "1", "min": -np.pi, "max": np.pi} for i in range(d)]
    archive_fixture.write_archive(path, factors, values, status, scalars={"y": y}, design_type="saltelli",
                                  roles=roles, rows=rows)
    return fA, fB, fAB


def test_saltelli_matrices_by_sample_row_and_indices_from_an_archive(tmp_path):
    path = str(tmp_path / "saltelli.h5")
    n = 256
    fA, fB, fAB = _saltelli_archive(path, n, failed_case=5 * 7 + 2)   # AB_1 of row 7 failed
    c = pwcampaign.load(path)
    s = c.saltelli()
    assert list(s.A.index) == list(range(n)) and s.A.index.name == "sample_row"
    np.testing.assert_array_equal(s.A["y"], fA)
    np.testing.assert_array_equal(s.B["y"], fB)
    np.testing.assert_array_equal(s.AB[0]["y"], fAB[:, 0])
    assert np.isnan(s.AB[1].at[7, "y"])                               # failed case: NaN result
    assert not s.complete[7] and s.complete.sum() == n - 1
    np.testing.assert_array_equal(s.XA.columns, ["x0", "x1", "x2"])
    a, b, ab = s.matrices("y")
    assert len(a) == n - 1
    r = c.sobol("y", n_bootstrap=100, seed=1)
    keep = np.arange(n) != 7
    direct = sobol_indices.sobol_indices(fA[keep], fB[keep], fAB[keep], n_bootstrap=100, seed=1)
    np.testing.assert_allclose(r[["S1", "ST", "S1_lo", "ST_hi"]].to_numpy(),
                               direct[["S1", "ST", "S1_lo", "ST_hi"]].to_numpy())
    assert list(r.index) == ["x0", "x1", "x2"] and r.attrs["rows_used"] == n - 1
    out = subprocess.run([sys.executable, os.path.join(conftest.SCRIPTS, "sobol_indices.py"), path, "-y", "y",
                          "--bootstrap", "50", "--csv", str(tmp_path / "s.csv")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "255 of 256 rows complete" in out.stdout
    assert len(pd.read_csv(tmp_path / "s.csv")) == 3
    plot_campaign.main(["sobol", path, "-y", "y", "--bootstrap", "50", "-o", str(tmp_path / "sobol.png")])
    assert os.path.getsize(tmp_path / "sobol.png") > 1000


# ------------------------------------------------------------------ plots
@pytest.fixture
def lhs_archive(tmp_path):
    """25 done cases over speed x wear coefficient (log) with an analytic
    response, spectra, wear profiles; one failed case."""
    rng = np.random.default_rng(0)
    n = 26
    speed = rng.uniform(100, 400, n)
    k = np.exp(rng.uniform(np.log(1e-17), np.log(1e-16), n))
    status = ["done"] * (n - 1) + ["failed"]
    wear_max = 1e-7 * (k / 1e-17) * (100 / speed)
    acc = 0.001 * speed ** 2
    spectra, wear = {}, {"sun": {}}
    for i in range(n - 1):
        fz = speed[i] / 60 * 21 * 81 / 102
        fr = np.arange(0, 3000, fz / 4)
        spectra[i] = (fr, {"sun_planet/0/acceleration": np.exp(-fr / 1000) * (1 + (np.round(fr / fz, 6) % 1 == 0))})
        x = np.linspace(-3e-3, 3e-3, 12)
        wear["sun"][i] = (x, wear_max[i] * (np.abs(x) / 3e-3))
    spec = dict(factors=conftest.FACTORS, values=np.column_stack([speed, k]), status=status,
                scalars={"max_wear/sun": wear_max, "sun_planet/0/acceleration_rms": acc,
                         "mesh_frequency": speed / 60 * 21 * 81 / 102},
                scalar_units={"max_wear/sun": "m", "sun_planet/0/acceleration_rms": "m/s^2", "mesh_frequency": "Hz"},
                spectra=spectra, wear=wear)
    path = str(tmp_path / "lhs.h5")
    archive_fixture.write_archive(path, **spec)
    return path


@pytest.mark.parametrize("args", [
    ["main-effects"],
    ["main-effects", "-y", "efficiency"],
    ["surface", "-x", "operating.input_speed_rpm", "-y", "wear.coefficient_m2_N"],
    ["surface", "-x", "operating.input_speed_rpm", "-y", "wear.coefficient_m2_N", "--method", "griddata",
     "-z", "sun_planet/0/acceleration_rms"],
    ["waterfall"],
    ["waterfall", "--orders", "--style", "map", "--by", "wear.coefficient_m2_N"],
    ["wear-profiles", "--by", "wear.coefficient_m2_N"],
])
def test_plot_commands_write_pngs(lhs_archive, tmp_path, args):
    png = tmp_path / "out.png"
    cmd = [args[0], lhs_archive] + args[1:] + ["-o", str(png)]
    if args == ["main-effects", "-y", "efficiency"]:
        assert plot_campaign.main(cmd) == 1          # missing output: a message, exit 1
        return
    assert plot_campaign.main(cmd) == 0
    assert os.path.getsize(png) > 5000


def test_quadratic_surface_recovers_a_quadratic(lhs_archive):
    c = pwcampaign.load(lhs_archive)
    fig = plot_campaign.surface(c, "operating.input_speed_rpm", "wear.coefficient_m2_N",
                                "sun_planet/0/acceleration_rms")
    assert "R² = 1.000" in fig.axes[0].get_title()


def test_plot_all_and_help(lhs_archive, tmp_path):
    assert plot_campaign.main(["all", lhs_archive, "-d", str(tmp_path / "figs")]) == 0
    made = sorted(os.listdir(tmp_path / "figs"))
    assert made == ["campaign_main_effects.png", "campaign_surface.png", "campaign_waterfall.png",
                    "campaign_wear_profiles.png"]
    r = subprocess.run([sys.executable, os.path.join(conftest.SCRIPTS, "plot_campaign.py"), "--help"],
                       capture_output=True, text=True)
    assert r.returncode == 0 and "main-effects" in r.stdout and "snapshots" in r.stdout


def test_snapshot_waterfall_of_a_single_run(tmp_path):
    path = tmp_path / "run.h5"
    with h5py.File(path, "w") as f:
        f["scalars/mesh_frequency"] = 100.0
        f["scalars/mesh_frequency"].attrs["unit"] = "Hz"
        f["scalars/sun_speed"] = 400 * 2 * np.pi / 60
        f["scalars/sun_speed"].attrs["unit"] = "rad/s"
        for k, cycles in enumerate([0.0, 1e5, 2e5]):
            g = f.create_group(f"wear/snapshots/{k}")
            g.attrs["mesh_cycles"] = cycles
            s = g.create_group("spectra/sun_planet/0/acceleration")
            s.attrs["unit"] = "m/s^2"
            s["frequency"] = np.arange(0, 1000, 25.0)
            s["amplitude"] = np.exp(-s["frequency"][()] / 300) * (1 + k)
    png = tmp_path / "snap.png"
    assert plot_campaign.main(["snapshots", str(path), "-o", str(png)]) == 0
    assert os.path.getsize(png) > 5000
    assert plot_campaign.main(["snapshots", str(path), "--orders", "--style", "map", "-o", str(png)]) == 0


# ------------------------------------------------------------------ end to end
def test_end_to_end_real_campaign_loads(real_archive, tmp_path):
    c = pwcampaign.load(real_archive)
    assert c.cases == 3 and c.done.all()
    assert c.design["operating.input_power_W"].tolist() == [500.0, 1000.0, 1500.0]
    assert c.units["operating.input_power_W"] == "W"
    assert (c.design["efficiency"] > 0.9).all() and (c.design["efficiency"] < 1).all()
    assert c.units["sun_planet/0/acceleration_rms"] == "m/s^2"
    assert (np.diff(c.design["input_torque"]) > 0).all()                  # torque grows with power
    assert (np.diff(c.design["max_wear/sun"]) > 0).all()                  # so does wear
    for i in range(3):
        f, a = c.spectrum("sun_planet/0/acceleration", i)
        assert len(f) == c.valid_length("spectra/frequency", i) > 0 and np.all(np.isfinite(a))
        x, h = c.wear_profile("sun", i)
        assert len(x) == 8 and np.all(h >= 0) and np.nanmax(h) > 0
        t, y = c.time_history("sun_planet/0/deflection", i)
        assert len(t) == len(y) > 10 and np.all(np.diff(t) > 0)
    assert "sun" in c.wear_families()
    assert plot_campaign.main(["all", real_archive, "-d", str(tmp_path), "--prefix", "e2e_"]) == 0
    assert os.path.exists(tmp_path / "e2e_waterfall.png") and os.path.exists(tmp_path / "e2e_wear_profiles.png")
