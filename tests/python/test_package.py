"""Tests of the Python package python/planetwear (docs/postprocessing.md) and
of the CF metadata the C++ writers put into their HDF5 files (`units`,
dimension scales; docs/output-format.md, docs/archive-format.md).

Real files are made with this build's planetwear (conftest.find_planetwear):
a short simulation, a short wear run, the tiny campaign of conftest and a
diagnosis of a short synthetic recording. Every loader value is compared
with what h5py (or json) reads from the file directly.

Run: /usr/bin/python3 -m pytest -q tests/python/test_package.py   (ctest: python.package)
"""
import json
import os
import re
import subprocess
import sys
import tomllib

import h5py
import numpy as np
import pytest

import conftest

sys.path.insert(0, os.path.join(conftest.SOURCE_DIR, "python"))

import planetwear  # noqa: E402
from planetwear import FormatError, load_campaign, load_diagnosis, load_simulation, load_wear_snapshots  # noqa: E402

EXAMPLES = os.path.join(conftest.SOURCE_DIR, "examples")
ENV = dict(os.environ, OMP_NUM_THREADS="1", MPLBACKEND="Agg")
# Short runs: 4 recorded mesh periods stored at every 4th step; the planet
# count is set (not the default) so that the planet dimension is checked
# against a number the test chose.
PLANETS = 3
SMALL = ["--set", "solver.record_mesh_cycles=4", "--set", "solver.warmup_max_mesh_cycles=10",
         "--set", f"stage.planet_count={PLANETS}", "--time-history-decimation", "4"]
WEAR = ["--mesh-cycles", "100", "--set", "wear.window_mesh_cycles=5", "--set", "wear.elements_per_flank=8"]


def run(cmd, cwd=None):
    r = subprocess.run(cmd, capture_output=True, text=True, env=ENV, cwd=cwd, timeout=600)
    assert r.returncode == 0, f"{cmd}: exit {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


@pytest.fixture(scope="session")
def simulation(tmp_path_factory, planetwear):
    out = tmp_path_factory.mktemp("sim") / "run.h5"
    run([planetwear, "simulate", "-q", *SMALL, "-o", str(out)])
    return str(out)


@pytest.fixture(scope="session")
def wear_run(tmp_path_factory, planetwear):
    out = tmp_path_factory.mktemp("wear") / "worn.h5"
    run([planetwear, "simulate", "-q", *SMALL, *WEAR, "-o", str(out)])
    return str(out)


@pytest.fixture(scope="session")
def diagnosis(tmp_path_factory, planetwear):
    """A diagnosis of 2 s of a synthetic recording at 200 rpm (as
    tests/diagnose/test_short_recording.sh, control case)."""
    d = tmp_path_factory.mktemp("diag")
    run([planetwear, "synth", "-q", "--speed-rpm", "200", "--seconds", "2", "--seed", "21", "--power-w", "10000",
         "--noise", "0.05", "--decimate", "40", "--start-mesh-cycle", "120", "--set", "solver.time_step_s=2.5e-6",
         "--set", "solver.periodicity_tolerance=1e-3", "-o", str(d / "rec.csv")], cwd=d)
    run([planetwear, "diagnose", "-q", "-r", str(d / "rec.csv"), "-o", str(d / "report"), "--threads", "1",
         "--no-plots"], cwd=d)
    return str(d / "report")


def h5_path(pattern, **index):
    """The dataset a stacked variable's `hdf5_path` pattern names for one index."""
    return pattern.format(**index)


def is_scale(ds):
    return h5py.h5ds.is_scale(ds.id)


def test_package_version_is_the_projects():
    text = open(os.path.join(conftest.SOURCE_DIR, "CMakeLists.txt")).read()
    assert re.search(r"project\(planetwear VERSION ([0-9.]+)", text).group(1) == planetwear.__version__


def test_pip_installs_the_package_without_downloading(tmp_path):
    """`pip install --no-build-isolation -e python/` with Debian's pip and
    setuptools, offline (--no-index: every dependency must already be
    installed), into a throw-away venv that sees the system packages."""
    venv = tmp_path / "venv"
    run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)])
    python = str(venv / "bin" / "python")
    run([python, "-m", "pip", "install", "-q", "--no-index", "--no-build-isolation", "-e",
         os.path.join(conftest.SOURCE_DIR, "python")])
    where = run([python, "-c", "import planetwear; print(planetwear.__file__, planetwear.__version__)"],
                cwd=tmp_path).stdout.split()
    assert where == [os.path.join(conftest.SOURCE_DIR, "python", "planetwear", "__init__.py"), planetwear.__version__]


# --- simulation files ---------------------------------------------------------

def test_simulation_time_histories_stack_planets_with_the_files_values(simulation):
    ds = load_simulation(simulation)
    with h5py.File(simulation, "r") as f:
        np.testing.assert_array_equal(ds.time.values, f["time_history/time"][:])
        assert ds.time.attrs["units"] == "s"
        assert list(ds.planet.values) == list(range(PLANETS))
        d = ds.sun_planet_deflection
        assert d.dims == ("planet", "time")
        assert d.shape == (PLANETS, f["time_history/time"].shape[0])
        assert d.attrs["units"] == "m"
        for i in range(PLANETS):
            path = h5_path(d.attrs["hdf5_path"], planet=i)
            assert path == f"/time_history/sun_planet/{i}/deflection"
            np.testing.assert_array_equal(d.sel(planet=i).values, f[path][:])
        # A channel that is no family keeps its name; the load shares are a planet family.
        np.testing.assert_array_equal(ds.sun_speed.values, f["time_history/sun/speed"][:])
        assert ds.sun_speed.attrs["units"] == "rad/s"
        np.testing.assert_array_equal(ds.load_sharing.sel(planet=2).values, f["time_history/load_sharing/2"][:])
        # The stored step is the integration step times the decimation.
        np.testing.assert_allclose(np.diff(ds.time.values), ds.attrs["time_step_s"], rtol=1e-9)


def test_simulation_spectra_scalars_and_config(simulation):
    ds = load_simulation(simulation)
    with h5py.File(simulation, "r") as f:
        s = ds.sun_planet_acceleration_spectrum
        assert s.dims == ("planet", "frequency")
        assert ds.frequency.attrs["units"] == "Hz"
        for i in range(PLANETS):
            g = f[f"spectra/sun_planet/{i}/acceleration"]
            np.testing.assert_array_equal(ds.frequency.values, g["frequency"][:])
            np.testing.assert_array_equal(s.sel(planet=i).values, g["amplitude"][:])
        assert s.attrs["units"] == f["spectra/sun_planet/0/acceleration/amplitude"].attrs["unit"] == "m/s^2"
        assert float(ds.mesh_frequency) == f["scalars/mesh_frequency"][()]
        assert ds.mesh_frequency.attrs["units"] == "Hz"
        nf = ds.natural_frequency
        assert nf.dims == ("mode",)
        for k in ds.mode.values:
            assert float(nf.sel(mode=k)) == f[f"scalars/natural_frequency/{k}"][()]
        toml = f["config/toml"].asstr()[()]
    assert ds.attrs["config_toml"] == toml
    assert tomllib.loads(ds.attrs["config_toml"])["stage"]["planet_count"] == PLANETS
    assert ds.attrs["format"] == "planetwear.simulation" and ds.attrs["units_convention"] == "SI"


def test_every_variable_and_coordinate_has_units_matching_the_file(simulation):
    ds = load_simulation(simulation)
    with h5py.File(simulation, "r") as f:
        for name, v in list(ds.data_vars.items()) + list(ds.coords.items()):
            assert v.attrs.get("units"), f"{name} has no units"
            if "hdf5_path" in v.attrs:
                path = h5_path(v.attrs["hdf5_path"], planet=int(ds.planet[0]), mode=int(ds.mode[0]))
                assert v.attrs["units"] == f[path].attrs["unit"], name
    assert len(ds.data_vars) > 20, "too few variables: channels or scalars were dropped"


def test_simulation_file_has_cf_units_and_dimension_scales(simulation):
    """What the C++ writer adds for CF readers: `units` = `unit` on every
    object, time and frequency as the dimension scales of their datasets."""
    with h5py.File(simulation, "r") as f:
        with_unit = []
        f.visititems(lambda name, obj: with_unit.append(obj) if "unit" in obj.attrs else None)
        assert len(with_unit) > 20
        for obj in with_unit:
            assert obj.attrs["units"] == obj.attrs["unit"], obj.name
        assert is_scale(f["time_history/time"])
        channel = f["time_history/sun_planet/1/force"]
        assert [s.name for s in channel.dims[0].values()] == ["/time_history/time"]
        amplitude = f["spectra/sun_planet/0/acceleration/amplitude"]
        assert [s.name for s in amplitude.dims[0].values()] == ["/spectra/sun_planet/0/acceleration/frequency"]


def test_xarray_reads_the_dimension_scales_as_coordinates(simulation):
    """Without the package: xarray's h5netcdf engine opens a spectrum group
    and finds the frequency coordinate and units the file declares."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    group = "spectra/sun_planet/0/acceleration"
    with xr.open_dataset(simulation, engine="h5netcdf", group=group) as s, h5py.File(simulation, "r") as f:
        assert s.amplitude.dims == ("frequency",)
        assert "frequency" in s.coords
        np.testing.assert_array_equal(s.frequency.values, f[group + "/frequency"][:])
        np.testing.assert_array_equal(s.amplitude.values, f[group + "/amplitude"][:])
        assert s.amplitude.attrs["units"] == "m/s^2" and s.frequency.attrs["units"] == "Hz"
    with xr.open_dataset(simulation, engine="h5netcdf", group="time_history/sun_planet/0") as th:
        assert th.deflection.dims == ("time",)


def test_wear_results_per_update_tooth_and_element(wear_run):
    ds = load_simulation(wear_run)
    with h5py.File(wear_run, "r") as f:
        w = f["wear"]
        np.testing.assert_array_equal(ds.mesh_cycles.values, w["mesh_cycles"][:])
        sun = ds.wear_sun_depth
        assert sun.dims == ("mesh_cycles", "sun_tooth", "sun_element")
        assert sun.shape == w["sun/depth"].shape
        assert sun.shape[1:] == (w["sun"].attrs["teeth"], w["sun"].attrs["elements"])
        np.testing.assert_array_equal(sun.values, w["sun/depth"][:])
        np.testing.assert_array_equal(ds.sun_distance_from_pitch_point.values, w["sun/distance_from_pitch_point"][:])
        assert sun.attrs["units"] == "m" and ds.sun_distance_from_pitch_point.attrs["units"] == "m"
        planet = ds.wear_planet_sun_side_depth
        assert planet.dims == ("planet", "mesh_cycles", "planet_sun_side_tooth", "planet_sun_side_element")
        for i in range(PLANETS):
            np.testing.assert_array_equal(planet.sel(planet=i).values, w[f"planet_{i}/sun_side/depth"][:])
            np.testing.assert_array_equal(ds.wear_planet_ring_side_max_depth.sel(planet=i).values,
                                          w[f"planet_{i}/ring_side/max_depth"][:])
        np.testing.assert_array_equal(ds.wear_backlash.sel(mesh="planet_ring").values, w["backlash"][:, 1])
        # The stored maximum is the maximum over teeth and elements of the stored depth.
        np.testing.assert_array_equal(ds.wear_ring_max_depth.values, ds.wear_ring_depth.max(["ring_tooth", "ring_element"]).values)
        assert ds.attrs["wear_stop_reason"] == w.attrs["stop_reason"]
        # HDF5 dimension scales of the wear layout.
        assert [s.name for s in w["sun/depth"].dims[0].values()] == ["/wear/mesh_cycles"]
        assert [s.name for s in w["sun/depth"].dims[2].values()] == ["/wear/sun/distance_from_pitch_point"]
        assert w["sun/depth"].dims[1].label == "tooth"
    assert float(ds.wear_sun_depth.isel(mesh_cycles=-1).max()) > 0, "no wear after 100 mesh cycles"


def test_wear_snapshots_in_order_of_mesh_cycles(wear_run):
    snapshots = load_wear_snapshots(wear_run)
    with h5py.File(wear_run, "r") as f:
        groups = sorted(f["wear/snapshots"].values(), key=lambda g: g.attrs["mesh_cycles"])
        first = groups[0].name
        assert len(snapshots) == len(groups) >= 2
        for s, g in zip(snapshots, groups):
            assert s.attrs["mesh_cycles"] == g.attrs["mesh_cycles"]
            np.testing.assert_array_equal(s.time.values, g["time_history/time"][:])
            np.testing.assert_array_equal(s.sun_planet_deflection.sel(planet=0).values,
                                          g["time_history/sun_planet/0/deflection"][:])
    assert snapshots[0].attrs["mesh_cycles"] == 0
    d = snapshots[0].sun_planet_deflection
    assert d.attrs["units"] == "m"
    assert d.attrs["hdf5_path"] == first + "/time_history/sun_planet/{planet}/deflection"


# --- campaign archives --------------------------------------------------------

def test_campaign_design_decoded_and_results_join_on_the_case(real_archive):
    design, results = load_campaign(real_archive)
    with h5py.File(real_archive, "r") as f:
        n = int(f.attrs["cases"])
        assert list(design.index) == list(f["design/case"][:]) == list(range(n))
        assert design.index.name == "case"
        assert list(design["status"]) == list(f["design/status"].asstr()[:])
        assert all(isinstance(s, str) for s in design["message"])
        np.testing.assert_array_equal(design["operating.input_power_W"], f["design/operating.input_power_W"][:])
        assert design.attrs["units"]["operating.input_power_W"] == "W"
        table = design.join(results.scalars)
        assert len(table) == n
        for name in ("efficiency", "sun_planet/0/acceleration_rms", "max_wear/sun"):
            np.testing.assert_array_equal(table[name].to_numpy(), f["results/scalars/" + name][:])
            assert results.units[name] == f["results/scalars/" + name].attrs["unit"]
        # Per-case arrays: the row cut to the case's valid length.
        for case in results.done_cases:
            bins = f["results/spectra/bins"][case]
            s = results.spectrum("sun_planet/0/acceleration", case)
            np.testing.assert_array_equal(s.values, f["results/spectra/sun_planet/0/acceleration"][case, :bins])
            np.testing.assert_array_equal(s.frequency.values, f["results/spectra/frequency"][case, :bins])
            assert s.attrs["units"] == "m/s^2" and s.frequency.attrs["units"] == "Hz"
            ne = f["results/wear/sun/elements"][case]
            np.testing.assert_array_equal(results.array("wear/sun/depth_final", case),
                                          f["results/wear/sun/depth_final"][case, :ne])
            ns = f["results/time_history/samples"][case]
            t = results.time_history("sun_planet/0/deflection", case)
            np.testing.assert_array_equal(t.time.values, f["results/time_history/time"][case, :ns])
    assert len(results.done_cases) == n == 3


def test_campaign_rows_are_found_by_case_in_a_slice_archive(real_archive, tmp_path):
    """An array job's slice archive holds only its cases' rows: row 0 is case 1."""
    import test_merge_archives
    part = str(tmp_path / "slice.h5")
    test_merge_archives.slice_archive(real_archive, part, 1, 3, layout="rows")
    design, results = load_campaign(part)
    whole_design, whole = load_campaign(real_archive)
    assert list(design.index) == [1, 2]
    for case in (1, 2):
        np.testing.assert_array_equal(results.array("spectra/sun_planet/0/acceleration", case),
                                      whole.array("spectra/sun_planet/0/acceleration", case))
        assert results.scalars.loc[case, "efficiency"] == whole.scalars.loc[case, "efficiency"]
    assert not np.array_equal(whole.array("spectra/sun_planet/0/acceleration", 1),
                              whole.array("spectra/sun_planet/0/acceleration", 2)), "cases 1 and 2 alike: no test"


def test_archive_has_cf_units_and_the_case_dimension_scale(real_archive):
    with h5py.File(real_archive, "r") as f:
        assert is_scale(f["case"])
        np.testing.assert_array_equal(f["case"][:], f["design/case"][:])
        found = []
        for group in ("design", "results"):
            f[group].visititems(lambda name, obj: found.append(obj) if isinstance(obj, h5py.Dataset) else None)
        assert len(found) > 10
        for ds in found:
            if "unit" in ds.attrs:
                assert ds.attrs["units"] == ds.attrs["unit"], ds.name
            assert [s.name for s in ds.dims[0].values()] == ["/case"], ds.name
        assert f["results/spectra/sun_planet/0/acceleration"].dims[1].label == "bin"


def test_xarray_sees_the_case_dimension_of_the_archive(real_archive):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    with xr.open_dataset(real_archive, engine="h5netcdf", group="results/scalars") as s, \
            h5py.File(real_archive, "r") as f:
        assert s.efficiency.dims == ("case",)  # the scale at the root is in scope of every group
        np.testing.assert_array_equal(s.efficiency.values, f["results/scalars/efficiency"][:])
    with xr.open_dataset(real_archive, engine="h5netcdf") as root, h5py.File(real_archive, "r") as f:
        np.testing.assert_array_equal(root.case.values, f["design/case"][:])


def test_loaders_refuse_the_wrong_kind_of_file(simulation, real_archive, tmp_path):
    with pytest.raises(FormatError, match="planetwear.simulation"):
        load_simulation(real_archive)
    with pytest.raises(FormatError, match="planetwear.campaign"):
        load_campaign(simulation)
    (tmp_path / "text.h5").write_text("not HDF5")
    with pytest.raises(FormatError, match="text.h5"):
        load_simulation(str(tmp_path / "text.h5"))
    with pytest.raises(FileNotFoundError, match="report.json"):
        load_diagnosis(str(tmp_path))


# --- diagnosis reports --------------------------------------------------------

def test_diagnosis_report_and_its_data_tables(diagnosis):
    report = load_diagnosis(diagnosis)
    with open(os.path.join(diagnosis, "report.json")) as fh:
        raw = json.load(fh)
    for key in ("verdict", "summary", "speed", "plots"):
        assert report[key] == raw[key]
    assert set(report["data"]) == {p["name"] for p in raw["plots"]}
    for p in raw["plots"]:
        table = report["data"][p["name"]]
        assert list(table.columns) == p["columns"]
        assert table.index.name == "x"
        numbers = np.genfromtxt(os.path.join(diagnosis, p["csv"]), delimiter=",", skip_header=2)
        np.testing.assert_array_equal(table.to_numpy(), numbers.reshape(len(table), -1)[:, 1:])


# --- examples -------------------------------------------------------------------

def test_examples_run_on_real_files(simulation, real_archive, diagnosis, tmp_path):
    png = tmp_path / "sim.png"
    out = run([sys.executable, os.path.join(EXAMPLES, "simulation_plot.py"), simulation, "-o", str(png)]).stdout
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10000
    assert f"{PLANETS} planets" in out

    out = run([sys.executable, os.path.join(EXAMPLES, "campaign_table.py"), real_archive]).stdout
    assert "3 cases: {'done': 3}" in out
    assert "mean by operating.input_speed_rpm [rpm]" in out

    out = run([sys.executable, os.path.join(EXAMPLES, "diagnosis_summary.py"), diagnosis]).stdout
    raw = json.load(open(os.path.join(diagnosis, "report.json")))
    assert f"verdict: {raw['verdict']}" in out
    assert f"{len(raw['plots'])} data tables" in out
