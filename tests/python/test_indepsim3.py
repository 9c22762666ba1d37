"""scripts/indepsim3 (the third independent simulator): physics and format checks.

Run: /usr/bin/python3 -m pytest -q tests/python/test_indepsim3.py   (part of ctest python.postprocessing)
About 6 s on one core; no planetwear binary needed.
"""
import csv
import importlib.util
import json
import math
import os
import tomllib

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SIM_DIR = os.path.join(HERE, "..", "..", "scripts", "indepsim3")
SIZES = os.path.join(HERE, "..", "..", "scripts", "indepsim", "sizes.py")
# Loaded under names of their own: the other simulators' tests put their `sim` and `corpus`
# modules into sys.modules of the same pytest run, where a plain import would return those.
_SPEC = importlib.util.spec_from_file_location("indepsim3_corpus", os.path.join(SIM_DIR, "corpus.py"))
corpus = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(corpus)
sim = corpus.sim


def stage(name="setA4"):
    g = corpus.GEARSETS[name]
    return sim.Stage(g["gear"], g["rig"])


# ---------------------------------------------------------------------------------------------
# (i) ISO 6336-1 single stiffness and mesh stiffness against a hand calculation
# ---------------------------------------------------------------------------------------------

def test_iso_single_stiffness_matches_a_hand_calculation():
    """Spur pair z1 = 23, z2 = 31, x = 0, ISO 53 rack (h_fP = 1.25 m), 20 deg, solid discs.
    By hand (ISO 6336-1 method B, Table 8 coefficients):
      q' = 0.04723 + 0.15551/23 + 0.25791/31 = 0.04723 + 0.0067613 + 0.0083197 = 0.0623110 mm um/N
      c'_th = 1/q' = 16.0485 N/(mm um); C_B = (1 + 0.5 (1.2 - 1.25)) (1 - 0) = 0.975
      c' = 16.0485 x 0.8 (C_M) x 1.0 (C_R) x 0.975 = 12.518 N/(mm um)
    Internal mesh z1 = 31 with a ring (zn2 = inf): q' = 0.04723 + 0.15551/31 = 0.0522465, c' = 14.929.
    Tolerance 0.05 %: the hand values are rounded to 5 significant digits."""
    assert sim.iso_q_prime(23, 31) == pytest.approx(0.0623110, rel=5e-5)
    assert sim.iso_single_stiffness(23, 31) == pytest.approx(12.518, rel=5e-4)
    assert sim.iso_single_stiffness(31, math.inf) == pytest.approx(14.929, rel=5e-4)
    # mesh stiffness c_gamma_alpha = c' (0.75 eps + 0.25): eps = 1.6 -> 12.518 x 1.45 = 18.151
    assert sim.iso_mesh_stiffness(12.518, 1.6) == pytest.approx(18.151, rel=5e-4)
    # below 100 N/mm line load: x (w/100)^0.25, at 50 N/mm 0.5^0.25 = 0.84090
    assert sim.iso_single_stiffness(23, 31, line_load_N_mm=50.0) == pytest.approx(12.518 * 0.84090, rel=5e-4)
    assert sim.iso_single_stiffness(23, 31, line_load_N_mm=150.0) == pytest.approx(12.518, rel=5e-4)


def test_the_pair_stiffness_parabola_reproduces_isos_peak_and_mean():
    """The single-pair curve peaks at c' b at the pitch point and the mesh stiffness averages
    c_gamma_alpha b over a mesh cycle (the parabola's curvature is fixed by that), within 0.2 %
    (the cycle is sampled at 2000 points)."""
    st = stage()
    kpk, kmean = st.mesh_levels(1000.0, 150000.0)      # line load above 100 N/mm: no load correction
    b = st.gs.face_width_m
    for m, cp in ((0, st.cprime0_s), (st.gs.N, st.cprime0_r)):
        assert kpk[m] == pytest.approx(cp * 1e9 * b, rel=1e-12)
        u, K = st.mesh_stiffness_cycle(m, kpk[m])
        assert K.mean() == pytest.approx(sim.iso_mesh_stiffness(cp, st.eps[m]) * 1e9 * b, rel=2e-3)
        assert st.pair_shape(m, np.array([0.0]))[0] == pytest.approx(1.0)
        assert 0.5 < st.pair_shape(m, np.array([-st.AP[m] + 1e-9]))[0] < 1.0


# ---------------------------------------------------------------------------------------------
# (ii) natural frequencies against an eigen-solution built independently here
# ---------------------------------------------------------------------------------------------

def potential_energy(st, q, k_sp, k_pr):
    """Strain energy of the torsional model written out in this test (not the simulator's G matrix):
    sun-planet compression rb_s th_s - (rb_s + rb_p) th_c + rb_p th_p, planet-ring compression
    -(rb_r - rb_p) th_c - rb_p th_p (fixed ring), two shafts."""
    N = st.gs.N
    thm, ths, thc, thp, thb = q[0], q[1], q[2], q[3:3 + N], q[3 + N]
    e = 0.5 * st.k_in * (thm - ths) ** 2 + 0.5 * st.k_out * (thc - thb) ** 2
    for i in range(N):
        d_sp = st.rb_s * ths - (st.rb_s + st.rb_p) * thc + st.rb_p * thp[i]
        d_pr = -(st.rb_r - st.rb_p) * thc - st.rb_p * thp[i]
        e += 0.5 * k_sp * d_sp ** 2 + 0.5 * k_pr * d_pr ** 2
    return e


@pytest.mark.parametrize("name", ["setA4", "setB5"])
def test_natural_frequencies_match_an_independent_eigen_solution(name):
    st = stage(name)
    n = st.n
    kmean = np.empty(st.Mm)
    kmean[:st.gs.N], kmean[st.gs.N:] = 4.0e8, 6.0e8
    # Hessian of the energy by central differences (exact for a quadratic form up to rounding)
    h = 1e-6
    K = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            def E(di, dj):
                q = np.zeros(n)
                q[i] += di
                q[j] += dj
                return potential_energy(st, q, 4.0e8, 6.0e8)
            K[i, j] = (E(h, h) - E(h, -h) - E(-h, h) + E(-h, -h)) / (4 * h * h)
    J = np.zeros(n)
    J[0], J[1], J[2], J[-1] = st.rig.J_motor, st.J_s, st.J_c, st.rig.J_brake
    J[3:3 + st.gs.N] = st.J_p
    lam = np.sort(np.linalg.eigvals(np.diag(1 / J) @ K).real)
    f_test = np.sqrt(np.maximum(lam, 0)) / (2 * math.pi)
    f_sim = st.modes(st.linear_K(kmean))[0]
    assert f_sim[0] < 1e-2 * f_sim[1]                      # the rigid-body rotation of the whole train
    np.testing.assert_allclose(f_sim[1:], f_test[1:], rtol=1e-6)
    # the shaft modes sit where the rig asks for them (at the ISO levels without load correction)
    assert st.f_modes_ref[1] == pytest.approx(st.rig.f_input_shaft_Hz, rel=1e-6)
    assert st.f_modes_ref[2] == pytest.approx(st.rig.f_output_shaft_Hz, rel=1e-6)
    assert 20.0 <= st.f_modes_ref[1] and st.f_modes_ref[2] <= 300.0


def test_mesh_phasing_follows_the_planet_positions():
    """Parker & Lin 2004: with (Zs + Zr)/N an integer, planet i's sun mesh lags planet 0's by Zs psi_i/2pi
    mesh cycles and its ring mesh leads by Zr psi_i/2pi; both are the same fraction, so the meshes are in
    phase when Zs/N is an integer and sequentially phased otherwise."""
    for name, in_phase in (("setA4", False), ("setB5", True)):
        st = stage(name)
        N, pb = st.gs.N, st.pb
        sun_phase = (-st.u0[:N] / pb) % 1.0                                  # lag of the sun meshes
        ring_phase = ((st.u0[N:] + st.ring_lag * pb) / pb) % 1.0             # lead of the ring meshes
        frac = lambda x: np.minimum(x % 1.0, 1 - x % 1.0)  # noqa: E731
        assert np.all(frac(sun_phase + ring_phase) < 1e-9)  # lag of one = lead of the other, mod 1
        assert np.all(frac(sun_phase) < 1e-9) == in_phase
        if not in_phase:
            k = st.gs.Zs % N
            np.testing.assert_allclose(np.sort(sun_phase), np.sort((k * np.arange(N) / N) % 1.0), atol=1e-9)


def test_a_damaged_planet_tooth_meets_the_ring_half_a_planet_turn_after_the_sun():
    st = stage("setA4")
    cases = [sim.Case(500.0, 15000.0, 0.1, faults=sim.Faults(tooth_body="planet", tooth_planet=2, tooth_index=5,
                                                             tooth_stiffness_factor=0.5))]
    op = sim._Op(st, cases)
    N, Zp = st.gs.N, st.gs.Zp
    q_sun = [q for q in range(op.Ltab[2]) if op.table[0, op.offtab[2] + q] < 1]       # planet 2's sun mesh
    q_ring = [q for q in range(op.Ltab[N + 2]) if op.table[0, op.offtab[N + 2] + q] < 1]
    assert q_sun and q_ring and all(q % Zp == 5 for q in q_sun)
    # in time: sun pass q at (Zs i/N + q) T_m, ring pass q' at (q' + lag - Zr i/N) T_m; the difference is
    # (Zp - 1)/2 mesh cycles (the tooth turns by pi - pi/Zp from the sun side to the ring side)
    t_sun = st.gs.Zs * 2 / N + q_sun[0]
    dt = [(qr + st.ring_lag - st.gs.Zr * 2 / N) - t_sun for qr in q_ring]
    assert min(d % Zp for d in dt) == pytest.approx((Zp - 1) / 2, abs=1e-9)
    # the other planets are healthy
    for i in (0, 1, 3):
        assert np.all(op.table[0, op.offtab[i]:op.offtab[i] + op.Ltab[i]] == 1.0)


# ---------------------------------------------------------------------------------------------
# (iii) power balance in steady state
# ---------------------------------------------------------------------------------------------

def test_input_minus_brake_power_is_the_friction_loss():
    """Healthy stage and the same stage with friction x 2, 500 rpm / 15 kW, 0.1 s after 0.12 s of warm-up,
    at a coarse internal rate (50 kHz: the balance is a property of the model, not of the step).
    P_in - P_brake - dE/dt = P_friction + P_mesh damping + P_shaft damping + P_bearings up to the work of
    the time-varying mesh stiffness, which a lumped model with k(t) does not conserve (Oh, Grosh & Barber
    2005): of order (1/2) dk delta^2 per pair entry and exit, here 2 pairs x 8 meshes x 150 Hz x
    (1/2)(3e8 N/m)(4 um)^2 = 6 W at most, i.e. 4 % of the friction loss (150 W; measured: -1.5 %).
    The friction change of the second case must appear one for one in P_in - P_brake (within 1 %)."""
    st = stage("setA4")
    cases = [sim.Case(500.0, 15000.0, 0.1, fs_daq=5000.0),
             sim.Case(500.0, 15000.0, 0.1, fs_daq=5000.0, faults=sim.Faults(friction_factor=2.0))]
    res, info = sim.simulate_batch(st, cases, f_int=50000, warmup_s=0.12, energy=True)
    en = info["energy"]
    T = en["T"]
    bal = []
    for k in range(2):
        Pin, Pb, Pf = en["P_in"][k] / T, en["P_b"][k] / T, en["P_fric"][k] / T
        other = (en["P_mdamp"][k] + en["P_lin"][k]) / T
        dE = (en["E1"][k] - en["E0"][k]) / T
        assert Pf > 100.0
        assert abs(Pin - Pb - dE - Pf - other) < 0.04 * Pf, (Pin, Pb, dE, Pf, other)
        # the quasi-static estimate the rig is set up with agrees with the dynamic loss within 10 %
        bal.append(Pin - Pb - dE)
    assert (bal[1] - bal[0]) == pytest.approx(en["P_fric"][1] / T - en["P_fric"][0] / T, rel=0.01)
    qs = st.quasi_static_loss(500.0, 15000.0, st.gs.friction)
    assert res[0]["mean_P_friction_W"] == pytest.approx(qs, rel=0.1)
    # the motor and brake hold the operating point: mean speeds within 0.2 % of nominal
    assert res[0]["mean_sun_rpm"] == pytest.approx(500.0, rel=2e-3)


# ---------------------------------------------------------------------------------------------
# (iv) encoder
# ---------------------------------------------------------------------------------------------

def test_encoder_speed_of_a_constant_rotation_is_exact_to_one_lines_quantization():
    w = 52.3        # rad/s
    lines = 1024
    t = np.arange(1, 20001) / 150000.0
    enc = sim.Encoder(lines, 0.0, 0.0, w)
    s = enc.run(t, w * t)
    T_line = 2 * math.pi / lines / w
    quant = w * (1.0 / sim.COUNTER_CLOCK_HZ) / T_line      # one count of the edge-timer in one line's interval
    assert np.max(np.abs(s - w)) <= quant + 1e-12
    # in chunks the result is the same
    enc2 = sim.Encoder(lines, 0.0, 0.0, w)
    s2 = np.concatenate([enc2.run(t[:7777], w * t[:7777]), enc2.run(t[7777:], w * t[7777:])])
    np.testing.assert_allclose(s2, s, rtol=0, atol=1e-12)


def test_encoder_reports_the_mean_speed_over_each_line():
    w0, a, f = 40.0, 2.0, 30.0
    t = np.arange(1, 60001) / 200000.0
    th = w0 * t + a / (2 * math.pi * f) * (1 - np.cos(2 * math.pi * f * t))
    enc = sim.Encoder(512, 0.0, 0.0, w0, clock=1e12)
    s = enc.run(t, th)
    # an edge at t_e: the held value from there on is d / (t_e - t_{e-1}); compare at the edges
    k = np.nonzero(np.diff(s) != 0)[0] + 1
    assert len(k) > 100
    # between two edges the angle advanced by exactly one line: s = d / interval, and the speed varies
    assert np.ptp(s[k]) == pytest.approx(2 * a, rel=0.05)
    assert np.mean(s[k]) == pytest.approx(w0, rel=2e-3)
    assert np.all(np.abs(s[k] - w0) <= a * 1.001)


# ---------------------------------------------------------------------------------------------
# (v) the corpus writer: docs/recordings.md format
# ---------------------------------------------------------------------------------------------

CONFIG_KEYS = {  # docs/config.md keys the gear set may use
    "stage": {"planet_count"},
    "gear": {"teeth", "module_m", "pressure_angle_deg", "face_width_m", "profile_shift", "addendum_coef",
             "dedendum_coef", "youngs_modulus_Pa", "poisson_ratio", "density_kg_m3", "shear_modulus_Pa",
             "root_fillet_coef", "pressure_angle_rad"},
    "contact": {"friction_coefficient", "backlash_sun_planet_m", "backlash_planet_ring_m"},
}
QUANTITIES = {"sun_speed", "carrier_speed", "mesh_acceleration_sun_planet", "mesh_acceleration_planet_ring",
              "housing_acceleration", "tacho"}


def test_recording_csv_and_sidecar_have_the_documented_columns_and_keys(tmp_path):
    fs, n = 5000.0, 2500
    t = np.arange(n) / fs
    rng = np.random.default_rng(0)
    ch = {"sun_speed": 500 + rng.normal(size=n), "carrier_speed": 106 + rng.normal(size=n),
          "acc_housing": rng.normal(size=n), "acc_sun_planet0": rng.normal(size=n),
          "acc_planet0_ring": rng.normal(size=n)}
    path = str(tmp_path / "rec_01.csv")
    side = corpus.writers.write_recording(path, t, ch, 500.0, 15000.0, 37.5, fs, corpus.GENERATOR, "test")
    with open(path) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    rows = list(csv.reader(lines))
    header = rows[0]
    assert header[0] == "time [s]"
    names = [h.split(" [")[0] for h in header]
    units = [h.split(" [")[1].rstrip("]") for h in header]
    assert len(rows) == n + 1 and all(len(r) == len(header) for r in rows)
    tt = np.array([float(r[0]) for r in rows[1:]])
    assert np.max(np.abs(tt - t)) < min(1e-6 * t[-1], 0.05 / fs)        # the reader's uniform-grid rule
    meta = json.load(open(side))
    assert set(meta) <= {"description", "generator", "operating", "time_column", "time_unit", "sample_rate_Hz",
                         "columns"}
    assert meta["operating"] == {"input_speed_rpm": 500.0, "input_power_W": 15000.0}
    assert meta["time_column"] == "time" and meta["time_unit"] == "s"
    assert list(meta["columns"]) == names[1:]
    for name, unit in zip(names[1:], units[1:]):
        c = meta["columns"][name]
        assert c["quantity"] in QUANTITIES and c["unit"] == unit
        assert set(c) <= {"quantity", "unit", "planet", "sensor_angle_deg", "scale"}
        if c["quantity"] == "housing_acceleration":
            assert c["sensor_angle_deg"] == 37.5
        elif c["quantity"].startswith("mesh_acceleration"):
            assert c["planet"] == 0 and "sensor_angle_deg" not in c
        else:
            assert "planet" not in c and "sensor_angle_deg" not in c
    for name in names[1:]:
        col = np.array([float(r[names.index(name)]) for r in rows[1:]])
        np.testing.assert_allclose(col, ch[name], rtol=1e-5, atol=1e-6)


def test_gearset_toml_uses_only_documented_keys():
    for g in corpus.GEARSETS.values():
        cfg = tomllib.loads(corpus.writers.gearset_toml(g["gear"], "test", corpus.GENERATOR))
        assert set(cfg) == {"stage", "contact"}
        st = cfg["stage"]
        assert set(st) - {"sun", "planet", "ring"} <= CONFIG_KEYS["stage"]
        for body in ("sun", "planet", "ring"):
            assert set(st[body]) <= CONFIG_KEYS["gear"]
            assert isinstance(st[body]["teeth"], int)
        assert set(cfg["contact"]) <= CONFIG_KEYS["contact"]
        gs = g["gear"]
        assert st["ring"]["teeth"] == st["sun"]["teeth"] + 2 * st["planet"]["teeth"]
        assert (gs.Zs + gs.Zr) % gs.N == 0


def test_plan_covers_every_scored_effect_with_the_scorers_truth_keys():
    """Every fault of planetwear's library that scripts/indepsim/confusion.py scores appears once per gear
    set, with the truth key scripts/indepsim/sizes.py reads for its size; two baselines and two controls
    per gear set; one short recording (< 2 carrier revolutions) per gear set; nothing held out."""
    spec = {}
    exec(compile(open(SIZES).read().split("def size_range")[0], SIZES, "exec"), spec)
    main_keys = spec["MAIN"]
    entries = corpus.plan_entries(False, 61)
    for g in corpus.GEARSETS:
        es = [e for e in entries if e["gearset"] == g]
        effects = sorted(e["effect"] for e in es if e["role"] == "effect" and not e["short"])
        assert effects == sorted(corpus.EFFECTS)
        assert sum(e["role"] == "baseline" for e in es) == 2 and sum(e["role"] == "control" for e in es) == 2
        shorts = [e for e in es if e["short"]]
        assert len(shorts) == 1
        fc = corpus.carrier_hz(corpus.GEARSETS[g]["gear"], shorts[0]["rpm"])
        assert shorts[0]["duration_s"] * fc < 2.0
        for e in es:
            if e["effect"] in main_keys:
                assert main_keys[e["effect"]][1] in e["parameters"]
            if e["effect"] == "pin_error":
                assert len(e["parameters"]["pin_error_m"]) == corpus.GEARSETS[g]["gear"].N
            if e["effect"] == "carrier_runout":
                assert {"carrier_ecc_m", "carrier_ecc_phase_rad"} <= set(e["parameters"])
            assert 2.0 <= e["duration_s"] <= 6.0 or e["short"]
        assert len({e["name"] for e in es}) == len(es)
