"""Checks of the second independent simulator scripts/indepsim2/sim.py (pytest, < 30 s)."""
import importlib.util
import json
import math
import os

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
# Loaded under a name of its own: test_indepsim.py puts the first simulator's `sim` module into
# sys.modules of the same pytest run, and a plain `import sim` would return that one.
_SPEC = importlib.util.spec_from_file_location("indepsim2_sim",
                                               os.path.join(HERE, "..", "..", "scripts", "indepsim2", "sim.py"))
sim = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(sim)


def gearset(N=3, Zs=19, Zp=35, Zr=89, m=0.0025, b=0.04, mu=0.06, backlash=1.2e-5):
    body = lambda Z: dict(teeth=Z, module_m=m, pressure_angle_deg=20, face_width_m=b)
    return sim.gearset_from_dict({"stage": {"planet_count": N, "sun": body(Zs), "planet": body(Zp), "ring": body(Zr)},
                                  "contact": {"friction_coefficient": mu, "backlash_sun_planet_m": backlash,
                                              "backlash_planet_ring_m": backlash}})


GS_A = gearset()
GS_B = gearset(5, 25, 20, 65, 0.003, 0.035, 0.05, 1.5e-5)


# ---------------------------------------------------------------------------------------------
# static torque balance
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("gs", [GS_A, GS_B], ids=["3planets", "5planets"])
def test_static_torque_ratio(gs):
    bt = sim.Batch(gs, [dict(rpm=300.0, power_W=4000.0, mu=0.0)])
    L = bt.lin
    q = bt.static_state()[:L["nd"], 0]
    T_sun = bt.par["kin"] * (q[L["IM"]] - q[L["IS"] + 2])
    T_car = bt.par["kout"] * (q[L["IC"] + 2] - q[L["IB"]])
    T_ring = bt.par["krt"] * q[L["IR"] + 2]
    Zs, Zr = gs["sun"]["Z"], gs["ring"]["Z"]
    assert T_sun == pytest.approx(4000.0 / (300 * 2 * math.pi / 60), rel=1e-9)
    assert T_car / T_sun == pytest.approx((Zs + Zr) / Zs, rel=1e-9)
    # the ring reacts the difference: T_sun + T_ring_on_stage = T_carrier (torque balance of the stage)
    assert -T_ring == pytest.approx(T_sun * Zr / Zs, rel=1e-6)
    # each planet carries the same share, F = T_sun / (N r_bs) on every mesh at mean stiffness
    F = bt.lin["kbar"] * (bt.lin["G"].T @ q)
    assert np.allclose(F, T_sun / (gs["N"] * bt.par["rbs"]), rtol=1e-9)


# ---------------------------------------------------------------------------------------------
# natural frequencies of the linear time-invariant model
# ---------------------------------------------------------------------------------------------
def test_lin_parker_1999_example():
    """Lin & Parker 1999 (J. Vib. Acoust. 121:316) Table 1 example, 3 planets: the published
    rotational and (double) translational natural frequencies."""
    rb = dict(s=0.0774 / 2, r=0.275 / 2, c=0.1768 / 2, p=0.1003 / 2)
    par = dict(N=3, alpha=math.radians(24.6), rbs=rb["s"], rbp=rb["p"], rbr=rb["r"], rc=rb["c"],
               ms=0.4, Is=0.39 * rb["s"] ** 2, mr=2.35, Ir=3.0 * rb["r"] ** 2, mc=5.43, Ic=6.29 * rb["c"] ** 2,
               mp=0.66, Ip=0.61 * rb["p"] ** 2, ksp=5e8, krp=5e8, ks=1e8, kc=1e8, kr=1e8, kpr=1e8, kpt=1e8,
               kst=0.0, kct=0.0, krt=1e9 * rb["r"] ** 2, rig=False)
    f, _ = sim.natural_frequencies(sim.build_linear(par))
    rot = [0.0, 1475.7, 1930.3, 2658.3, 7462.8, 11775.3]
    tr = [743.2, 1102.4, 1896.0, 2276.4, 6986.3, 9647.9]
    expect = np.sort(np.r_[rot, tr, tr])
    assert f[0] < 1e-3 * f[1]
    assert np.allclose(f[1:], expect[1:], rtol=2e-4, atol=0.15)


def test_mode_multiplicities_six_planets():
    """Lin & Parker mode structure for N = 6 equally spaced planets (stage alone): 6 distinct
    translational frequencies, each double; 3 planet-mode frequencies of multiplicity N - 3 = 3
    in which sun, ring and carrier do not move; the remaining rotational modes simple."""
    gs = gearset(6, 24, 24, 72, 0.002, 0.03)
    par, geo, rig = sim.lumped_parameters(gs)
    lin = sim.build_linear(par)
    f, V = sim.natural_frequencies(lin, exclude_rig=True)
    groups = []
    for x in f:
        if groups and abs(x - groups[-1][0]) <= 1e-6 * max(x, 1.0):
            groups[-1].append(x)
        else:
            groups.append([x])
    mult = sorted(len(g) for g in groups)
    assert mult.count(3) == 3 and mult.count(2) == 6 and mult.count(1) == 6
    assert len(f) == 9 + 3 * 6
    # planet modes: central members at rest
    start = 0
    for g in groups:
        if len(g) == 3:
            Vg = V[:, start:start + 3]
            central = np.abs(Vg[:9]).max()
            assert central < 1e-8 * np.abs(Vg).max()
        start += len(g)


def test_torsional_planet_mode_closed_form():
    """Purely torsional reduced model (translations clamped): the planet modes have the closed form
    f = sqrt((k_sp + k_rp) r_bp^2 / I_p) / 2 pi with multiplicity N - 1."""
    gs = gearset(4, 20, 30, 80, 0.003, 0.03)
    par, geo, rig = sim.lumped_parameters(gs)
    lin = sim.build_linear(par)
    rot = [i for i in range(9 + 3 * 4) if i % 3 == 2]
    K = (lin["Kb"] + lin["Kmesh"])[np.ix_(rot, rot)]
    M = lin["M"][rot]
    from scipy import linalg
    w2 = linalg.eigh(K, np.diag(M), eigvals_only=True)
    f = np.sqrt(np.maximum(w2, 0)) / (2 * math.pi)
    f_pl = math.sqrt((par["ksp"] + par["krp"]) * par["rbp"] ** 2 / par["Ip"]) / (2 * math.pi)
    assert np.sum(np.isclose(f, f_pl, rtol=1e-9)) == 4 - 1


# ---------------------------------------------------------------------------------------------
# mesh stiffness law
# ---------------------------------------------------------------------------------------------
def test_kuang_yang_law_and_combination():
    # Kuang & Yang 1992 polynomial at the pitch point, Z = 20, X = 0: A0(20) = 25.6854 N/(mm um)
    assert sim.ky_tooth_stiffness(20, 0.0) == pytest.approx(25.6854e9, rel=1e-4)
    # tooth stiffness falls from root to tip
    h = np.linspace(-1.0, 1.0, 21)
    for Z in (19, 25, 35, 65, 89):
        k = sim.ky_tooth_stiffness(Z, h)
        assert np.all(np.diff(k) < 0)
    for gs in (GS_A, GS_B):
        geo = sim.mesh_geometry(gs)
        for key, Z1, Z2 in (("sp", gs["sun"]["Z"], gs["planet"]["Z"]), ("rp", gs["planet"]["Z"], gs["ring"]["Z"])):
            me = geo["meshes"][key]
            # mean mesh stiffness within 20 % of ISO 6336-1 method B (independent published law)
            iso = sim.iso6336_mesh_stiffness_per_width(Z1, Z2, me["eps"], internal=(key == "rp")) * geo["b"]
            assert me["kmean"] == pytest.approx(iso, rel=0.2)
            # contact ratio from the tip circles: double contact during eps - 1 of a mesh cycle
            n = np.linspace(0, 1, 20001)[:-1]
            npairs = sum((sim.pair_k(me, (n - (np.ceil(n - me["xE"] / geo["pb"]) + j)) * geo["pb"]) > 0)
                         for j in range(4))
            assert np.mean(npairs == 2) == pytest.approx(me["eps"] - 1, abs=2e-3)
            assert set(np.unique(npairs)) <= {1, 2}
            # periodic in the mesh phase
            k0 = sim.combined_stiffness(me, n, geo["pb"])
            assert np.allclose(k0, sim.combined_stiffness(me, n + 3, geo["pb"]), rtol=1e-9)


# ---------------------------------------------------------------------------------------------
# encoder
# ---------------------------------------------------------------------------------------------
def test_encoder_constant_speed():
    from scipy import signal
    fs, lines, interp, lp = 10000.0, 2048, 4096, 1000.0
    for w in (5.5268, 31.4159, 115.19):
        t = np.arange(20001) / fs
        theta = 0.3 + w * t
        est, quantum = sim.encoder_speed(theta, fs, lines, interp, lp, zi_value=w)
        assert quantum == pytest.approx(2 * math.pi / (lines * interp) * fs)
        bb, aa = signal.butter(2, lp, fs=fs)
        imp = signal.lfilter(bb, aa, np.r_[1.0, np.zeros(400)])
        bound = np.sum(np.abs(imp)) * quantum
        assert np.max(np.abs(est - w)) <= bound
        # the mean over the record is exact up to one quantum over the whole record length
        assert abs(np.mean(est) - w) < 3 * quantum / len(est) * 50


# ---------------------------------------------------------------------------------------------
# energy conservation of a free vibration (no damping, friction, input)
# ---------------------------------------------------------------------------------------------
def test_free_vibration_energy():
    bt = sim.Batch(GS_A, [dict(static=True, rpm=0.0, power_W=0.0, mu=0.0, damping_scale=0.0, undamped=True)])
    nd = bt.lin["nd"]
    rng = np.random.default_rng(3)
    Y0 = np.zeros((2 * nd, 1))
    Y0[:nd, 0] = 2e-7 * rng.standard_normal(nd)
    Y0[nd:, 0] = 1e-4 * rng.standard_normal(nd)
    E0 = bt.energy(Y0)[0]
    Y1 = bt.integrate(0.004, 2000.0, y0=Y0, rtol=1e-11, atol_scale=1e-7)
    E1 = bt.energy(Y1)[0]
    assert abs(E1 - E0) / E0 < 1e-6
    # and with damping the energy decays
    bt2 = sim.Batch(GS_A, [dict(static=True, rpm=0.0, power_W=0.0, mu=0.0)])
    Y2 = bt2.integrate(0.004, 2000.0, y0=Y0, rtol=1e-9, atol_scale=1e-5)
    assert bt2.energy(Y2)[0] < 0.9 * E0


# ---------------------------------------------------------------------------------------------
# a short recording: CSV + sidecar as docs/recordings.md says
# ---------------------------------------------------------------------------------------------
def test_recording_files(tmp_path):
    rpm, P = 900.0, 10000.0
    recs = [dict(case=dict(rpm=rpm, power_W=P), start_s=0.02, duration_s=0.03, noise_seed=5,
                 dc_offset_fraction=0.2, sensor_angle_housing_deg=75.0)]
    out, bt = sim.simulate_batch(GS_A, recs, fs=10000.0, rtol=1e-6, log=lambda s: None)
    o = out[0]
    csvp = str(tmp_path / "rec_01.csv")
    jp = sim.write_recording(csvp, o["t"], o["w_sun_rpm"], o["w_carrier"], o["acc_g"], rpm, P,
                             o["sensor_angle_deg"], "test")
    meta = json.load(open(jp))
    assert set(meta) <= {"description", "generator", "operating", "time_column", "time_unit", "sample_rate_Hz",
                         "columns"}
    assert meta["operating"] == {"input_speed_rpm": rpm, "input_power_W": P}
    cols = meta["columns"]
    assert cols["w_sun"] == {"quantity": "sun_speed", "unit": "rpm"}
    assert cols["w_carrier"] == {"quantity": "carrier_speed", "unit": "rad/s"}
    assert cols["acc_housing"]["quantity"] == "housing_acceleration" and cols["acc_housing"]["unit"] == "g"
    ang = cols["acc_housing"]["sensor_angle_deg"]
    assert 0 <= ang < 360
    # angle convention: measured from planet 0's position at the record's t = 0
    assert ang == pytest.approx((75.0 - math.degrees(o["theta_c0"])) % 360.0, abs=1e-3)
    lines = open(csvp).read().splitlines()
    assert lines[0].startswith("#")
    header = lines[1].split(",")
    assert header == ["time", "w_sun", "w_carrier", "acc_housing"]
    data = np.loadtxt(csvp, delimiter=",", skiprows=2)
    assert data.shape == (300, 4) and np.all(np.isfinite(data))
    t = data[:, 0]
    assert t[0] == 0.0 and np.allclose(np.diff(t), 1e-4, atol=1e-9)
    Zs, Zr = GS_A["sun"]["Z"], GS_A["ring"]["Z"]
    assert 10000.0 >= 7.5 * sim.mesh_frequency(GS_A, rpm)
    assert np.mean(data[:, 1]) == pytest.approx(rpm, rel=0.01)
    assert np.mean(data[:, 2]) == pytest.approx(rpm * 2 * math.pi / 60 * Zs / (Zs + Zr), rel=0.01)
    acc = data[:, 3]
    assert 1e-4 < np.std(acc) < 1e4 / 9.81
