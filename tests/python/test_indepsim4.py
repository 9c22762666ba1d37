"""scripts/indepsim4 (the fourth independent simulator, the literature's k(t) model): physics and format checks.

Run: /usr/bin/python3 -m pytest -q tests/python/test_indepsim4.py   (about 15 s on one core; no planetwear binary)
"""
import csv
import importlib.util
import json
import math
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SIM_DIR = os.path.join(HERE, "..", "..", "scripts", "indepsim4")
# Loaded under names of their own: the other simulators' tests put their `sim` and `corpus` modules
# into sys.modules of the same pytest run, where a plain import would return those.
if "indepsim4_sim" not in sys.modules:
    _S = importlib.util.spec_from_file_location("indepsim4_sim", os.path.join(SIM_DIR, "sim.py"))
    sys.modules["indepsim4_sim"] = importlib.util.module_from_spec(_S)
    _S.loader.exec_module(sys.modules["indepsim4_sim"])
_SPEC = importlib.util.spec_from_file_location("indepsim4_corpus", os.path.join(SIM_DIR, "corpus.py"))
corpus = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(corpus)
sim = sys.modules["indepsim4_sim"]


def stage(name="setC3"):
    g = corpus.GEARSETS[name]
    return sim.Stage(g["gear"], g["rig"])


# ---------------------------------------------------------------------------------------------
# Lin & Parker (1999) Table 1 example: natural frequencies
# ---------------------------------------------------------------------------------------------

def test_lin_parker_1999_natural_frequencies():
    """Three planets, k_sp = k_rp = 5e8 N/m, bearings 1e8 N/m, k_ru = 1e9 N/m, alpha = 24.6 deg,
    masses and I/r^2 of Table 1, no rig. Tolerance 0.5 %: the paper prints the frequencies to
    0.1 Hz and the inputs (masses, I/r^2, alpha) to 2-3 digits, so only that agreement is meaningful
    (the model here reproduces them to the printed digit)."""
    a = math.radians(24.6)
    K = sim.lp_stiffness(3, 5e8, 5e8, 1e8, 1e9, a, a)
    M = sim.lp_mass(3, m_c=5.43, m_r=2.35, m_s=0.4, m_p=0.66, J_c=6.29, J_r=3.00, J_s=0.39, J_p=0.61)
    f = np.sort(sim.natural_frequencies(K, M))
    rot = [0.0, 1475.7, 1930.3, 2658.3, 7462.8, 11775.3]
    tra = [743.2, 1102.4, 1896.0, 2276.4, 6986.3, 9647.9]
    expect = np.sort(np.array(rot + tra + tra))
    assert len(f) == 18
    assert f[0] < 1e-3 * f[1]   # rigid-body rotation (k_su = k_cu = 0)
    np.testing.assert_allclose(f[1:], expect[1:], rtol=5e-3)
    # the translational ones are double
    for x in tra:
        assert np.sum(np.abs(f - x) < 0.005 * x) == 2


# ---------------------------------------------------------------------------------------------
# ISO 6336-1 method B
# ---------------------------------------------------------------------------------------------

def test_iso_single_stiffness_hand_calculation():
    """z1 = 21, z2 = 30, x = 0: q' = 0.04723 + 0.15551/21 + 0.25791/30 = 0.04723 + 0.0074052 + 0.0085970
    = 0.0632322 mm um/N; c'_th = 15.8147; c' = 15.8147 x 0.8 x 1 x 0.975 = 12.3355 N/(mm um).
    Ring mesh of the 30-tooth planet (z_n2 = inf): q' = 0.04723 + 0.15551/30 = 0.0524137 -> 14.8816."""
    assert sim.iso_single_stiffness(21, 30) == pytest.approx(12.3355, rel=1e-4)
    assert sim.iso_single_stiffness(30, math.inf) == pytest.approx(14.8816, rel=1e-4)
    st = stage("setC3")
    # c_gamma_alpha b = c' (0.75 eps + 0.25) b, b = 25 mm -> N/m, and the k(t) wave has that mean
    assert st.k_mean_sp == pytest.approx(12.3355 * (0.75 * st.eps_sp + 0.25) * 25 * 1e6, rel=1e-4)
    tf = sim.TimeFunctions(st, [sim.Case(1200, 18000, 0.1)])
    fm = tf.fm[0]
    t = np.arange(4000) / (4000 * fm)       # one mesh cycle
    k = tf.eval(t)[0]
    assert np.mean(k[:, 0, 0]) == pytest.approx(st.k_mean_sp, rel=2e-3)
    assert np.mean(k[:, 0, 3]) == pytest.approx(st.k_mean_rp, rel=2e-3)
    assert k[:, 0, 0].min() == pytest.approx(st.k_single_sp, rel=2e-3)
    assert k[:, 0, 0].max() == pytest.approx(1.75 * st.k_single_sp, rel=2e-3)


def test_contact_ratio_and_path_geometry():
    st = stage("setC3")
    # external 21/30, m 2, 20 deg, x = 0 (hand: (sqrt(23^2-19.734^2)+sqrt(32^2-28.191^2)-51 sin20)/pi 2 cos20)
    r1, r2, a = 21e-3, 30e-3, math.radians(20)
    g = (math.sqrt(23e-3 ** 2 - (r1 * math.cos(a)) ** 2) + math.sqrt(32e-3 ** 2 - (r2 * math.cos(a)) ** 2)
         - 51e-3 * math.sin(a))
    assert st.eps_sp == pytest.approx(g / (math.pi * 2e-3 * math.cos(a)), rel=1e-9)
    assert 1.0 < st.eps_sp < 2.0 and 1.0 < st.eps_rp < 2.0
    np.testing.assert_allclose((st.gf + st.ga) / st.pb, np.r_[[st.eps_sp] * 3, [st.eps_rp] * 3], rtol=1e-3)


# ---------------------------------------------------------------------------------------------
# Mesh phasing (Parker & Lin 2004)
# ---------------------------------------------------------------------------------------------

def test_mesh_phasing_in_phase_and_sequential():
    """setC3 (Zs/N = 7): all sun meshes in phase, the net translational force of the k(t) waves cancels,
    the torsional one adds up. setD4 (Zs/N = 6.75, Zs+Zr = 96 = 24 N): sequentially phased, the phases
    sum to zero at mesh harmonics h = 1..4 and to N at h = 5, so the net torsional stiffness variation
    cancels at the first harmonics and the translational one does not (Parker & Lin 2004)."""
    for name, in_phase in (("setC3", True), ("setD4", False)):
        st = stage(name)
        N = st.gs.N
        gs_ = np.array(st.gamma[:N]) % 1.0
        gr_ = np.array(st.gamma[N:]) % 1.0
        if in_phase:
            assert np.allclose(gs_, gs_[0]) and np.allclose(gr_, gr_[0])
        else:
            for h in range(1, N):
                assert abs(np.sum(np.exp(2j * math.pi * h * st.gamma[:N]))) < 1e-9
            assert abs(np.sum(np.exp(2j * math.pi * N * st.gamma[:N]))) == pytest.approx(N)
        tf = sim.TimeFunctions(st, [sim.Case(1200, 18000, 0.1)])
        t = np.arange(4000) / (4000 * tf.fm[0])
        k = tf.eval(t)[0][:, 0, :N]
        fx = k @ st.G[:N, 6]                 # net sun x force per unit mesh deflection
        tor = k.sum(axis=1)                  # net torsional stiffness on the sun
        f1 = lambda x: abs(np.mean(x * np.exp(-2j * math.pi * np.arange(len(x)) / len(x))))  # noqa: E731
        if in_phase:
            assert np.std(fx) < 1e-9 * st.k_mean_sp
            assert f1(tor) > 0.05 * st.k_mean_sp
        else:
            assert np.std(fx) > 0.02 * st.k_mean_sp
            assert f1(tor) < 1e-6 * st.k_mean_sp


# ---------------------------------------------------------------------------------------------
# Dynamics: power balance, step halving, speeds
# ---------------------------------------------------------------------------------------------

def test_power_balance_in_steady_state():
    """Mean input power = output power + friction + damping losses within 2 % (0.04 s after 0.04 s)."""
    st = stage("setC3")
    res, info = sim.simulate_batch(st, [sim.Case(1200, 18000, 0.04, 10000.0)], warmup_s=0.04, record=False)
    r = res[0]
    lhs = r["mean_P_in_W"]
    rhs = r["mean_P_out_W"] + r["mean_P_friction_W"] + r["mean_P_damping_W"]
    assert r["mean_P_friction_W"] > 0.002 * lhs          # friction takes a visible share
    assert abs(lhs - rhs) < 0.02 * lhs, (lhs, rhs)
    assert abs(r["mean_P_out_W"] - 18000) < 0.005 * 18000
    assert abs(r["mean_sun_rpm"] - 1200) < 0.005 * 1200
    assert r["backlash_fraction"] == 0.0
    assert info["steps_per_highest_period"] >= 10 and info["steps_per_mesh_cycle_min"] >= 40


def test_step_halving_convergence():
    """The RMS of the sun-planet mesh acceleration differs by < 1 % between h and h/2."""
    st = stage("setC3")
    h, _, _ = sim.choose_step(st, [10000.0])
    cases = [sim.Case(1200, 18000, 0.012, 10000.0)]
    a, _ = sim.simulate_batch(st, cases, warmup_s=0.01, h=h)
    b, _ = sim.simulate_batch(st, cases, warmup_s=0.01, h=h / 2)
    for ch in ("a_sp0", "a_pr0"):
        ra, rb = np.sqrt(np.mean(a[0][ch] ** 2)), np.sqrt(np.mean(b[0][ch] ** 2))
        assert abs(ra - rb) < 0.01 * rb, (ch, ra, rb)


# ---------------------------------------------------------------------------------------------
# File format of a tiny recording
# ---------------------------------------------------------------------------------------------

def test_file_format_of_a_tiny_recording(tmp_path):
    entries = [e for e in corpus.plan_entries(True, 3) if e["role"] == "baseline"]
    for e in entries:
        e["duration_s"] = 0.13
    rows, binfo, desc = corpus.run_gearset("setC3", entries, str(tmp_path), warmup_s=0.01)
    (key, row), = rows.items()
    for k in ("gearset", "name", "csv", "sidecar", "role", "effect", "parameters", "operating_point",
              "input_speed_rpm", "input_power_W", "fs_Hz", "duration_s", "held_out", "baseline",
              "sensor_angle_deg", "noise_fraction", "diagnostics"):
        assert k in row
    meta = json.loads((tmp_path / row["sidecar"]).read_text())
    assert set(meta) == {"description", "generator", "operating", "time_column", "time_unit", "columns"}
    assert meta["operating"] == {"input_speed_rpm": 1200.0, "input_power_W": 18000.0}
    cols = meta["columns"]
    assert [c["quantity"] for c in cols.values()] == ["sun_speed", "carrier_speed", "housing_acceleration",
                                                      "mesh_acceleration_sun_planet", "mesh_acceleration_planet_ring"]
    assert "sensor_angle_deg" in cols["acc_housing"]
    assert cols["acc_sun_planet0"]["planet"] == 0
    with open(tmp_path / row["csv"]) as f:
        lines = f.read().splitlines()
    assert lines[0].startswith("#")
    header = next(csv.reader([lines[1]]))
    assert header == ["time [s]", "sun_speed [rpm]", "carrier_speed [rpm]", "acc_housing [m/s^2]",
                      "acc_sun_planet0 [m/s^2]", "acc_planet0_ring [m/s^2]"]
    data = np.loadtxt(lines[2:], delimiter=",")
    assert data.shape == (1300, 6)
    np.testing.assert_allclose(np.diff(data[:, 0]), 1e-4, atol=1e-9)
    assert np.all(np.isfinite(data))
    assert abs(np.mean(data[:, 1]) - 1200) < 0.005 * 1200
    assert abs(np.mean(data[:, 2]) - 1200 * 21 / 102) < 0.005 * 1200 * 21 / 102
    for j in range(1, 6):
        assert np.std(data[:, j]) > 0
