"""Shared fixtures of the Python post-processing tests (scripts/pwcampaign.py,
scripts/sobol_indices.py, scripts/merge_archives.py, scripts/plot_campaign.py).

Run: /usr/bin/python3 -m pytest -q tests/python   (ctest: python.postprocessing)
The end-to-end tests need a built `planetwear`: $PLANETWEAR, else the newest
build*/apps/planetwear of the source tree that has the `sweep` command; they
are skipped (not failed) only when there is none.
"""
import glob
import os
import subprocess
import sys

import numpy as np
import pytest

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPTS = os.path.join(SOURCE_DIR, "scripts")
sys.path.insert(0, SCRIPTS)
sys.path.insert(0, os.path.dirname(__file__))

import archive_fixture  # noqa: E402

FACTORS = [
    {"key": "operating.input_speed_rpm", "unit": "rpm", "scale": "linear", "min": 100.0, "max": 400.0},
    {"key": "wear.coefficient_m2_N", "unit": "m^2/N", "scale": "log", "min": 1e-17, "max": 1e-16},
]


def _has_sweep(exe):
    try:
        return subprocess.run([exe, "sweep", "--help"], capture_output=True, timeout=60).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


def find_planetwear():
    exe = os.environ.get("PLANETWEAR")
    if exe:
        return exe if os.access(exe, os.X_OK) else None
    found = [p for p in glob.glob(os.path.join(SOURCE_DIR, "build*", "apps", "planetwear")) if os.access(p, os.X_OK)]
    for p in sorted(found, key=os.path.getmtime, reverse=True):
        if _has_sweep(p):
            return p
    return None


@pytest.fixture(scope="session")
def planetwear():
    exe = find_planetwear()
    if exe is None:
        pytest.skip("no planetwear binary with the sweep command (set PLANETWEAR or build build*/apps/planetwear)")
    return exe


def small_archive_spec():
    """4 cases: 0 done, 1 failed, 2 pending, 3 done; case 3 has fewer spectrum
    bins, wear elements and time samples than case 0 (padded with NaN)."""
    values = [[100.0, 1e-17], [200.0, 3e-17], [300.0, 5e-17], [400.0, 1e-16]]
    status = ["done", "failed", "pending", "done"]
    messages = ["", "solver.time_step_s: fewer than 8 steps per period of the stiffest mode", "", "wear stopped early"]
    scalars = {"efficiency": [0.98, 0.0, 0.0, 0.97],
               "sun_planet/0/acceleration_rms": [10.0, 0.0, 0.0, 40.0],
               "max_wear/sun": [1.2e-7, 0.0, 0.0, 2.0e-8],
               "load_sharing_factor/3": [np.nan, 0.0, 0.0, 1.01]}
    units = {"efficiency": "1", "sun_planet/0/acceleration_rms": "m/s^2", "max_wear/sun": "m",
             "load_sharing_factor/3": "1"}
    spectra = {0: (np.arange(5) * 10.0, {"sun_planet/0/acceleration": np.array([0, 1, 2, 3, 4.0]),
                                          "planet_ring/0/acceleration": np.array([4, 3, 2, 1, 0.0])}),
               3: (np.arange(3) * 40.0, {"sun_planet/0/acceleration": np.array([5, 6, 7.0]),
                                          "planet_ring/0/acceleration": np.array([7, 6, 5.0])})}
    x = np.linspace(-2e-3, 2e-3, 4)
    wear = {"sun": {0: (x, np.array([1, 2, 3, 4.0]) * 1e-8), 3: (x[:3], np.array([5, 6, 7.0]) * 1e-9)},
            "planet_0/sun_side": {0: (x, np.ones(4) * 1e-8), 3: (x, np.ones(4) * 2e-9)}}
    th = {0: (np.arange(6) * 1e-4, {"sun_planet/0/deflection": np.arange(6) * 1e-6}),
          3: (np.arange(2) * 1e-4, {"sun_planet/0/deflection": np.array([7e-6, 8e-6])})}
    return dict(factors=FACTORS, values=values, status=status, messages=messages, scalars=scalars,
                scalar_units=units, spectra=spectra, wear=wear, time_history=th)


@pytest.fixture
def small_archive(tmp_path):
    path = str(tmp_path / "small.h5")
    archive_fixture.write_archive(path, **small_archive_spec())
    return path


# A tiny real campaign (3 short cases at 400 rpm, a little wear), run once per session.
TINY = """
[campaign]
name = "pytest tiny"
[base]
config = "{config}"
[base.set]
solver.record_mesh_cycles = 1
solver.warmup_max_mesh_cycles = 10
wear.mesh_cycles = 100
wear.window_mesh_cycles = 5
wear.elements_per_flank = 8
[[factors]]
key = "operating.input_speed_rpm"
unit = "rpm"
levels = [400.0]
[[factors]]
key = "operating.input_power_W"
unit = "W"
min = 500.0
max = 1500.0
points = 3
[design]
type = "full_factorial"
[output]
time_history_decimation = 4
spectrum_max_frequency_Hz = 3000.0
"""


@pytest.fixture(scope="session")
def real_archive(tmp_path_factory, planetwear):
    d = tmp_path_factory.mktemp("e2e")
    toml = d / "tiny.toml"
    toml.write_text(TINY.format(config=os.path.join(SOURCE_DIR, "config", "seed.toml")))
    out = d / "tiny.h5"
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if os.getuid() == 0:  # an MPI singleton as root (Open MPI)
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    r = subprocess.run([planetwear, "sweep", str(toml), "-o", str(out), "-q"], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0, r.stderr
    return str(out)
