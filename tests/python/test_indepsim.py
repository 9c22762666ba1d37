"""Physics and format tests of the independent simulator scripts/indepsim (sim.py, corpus.py).

Run: /usr/bin/python3 -m pytest -q tests/python/test_indepsim.py   (ctest: python.postprocessing)
Fast (well under 60 s on one core); numpy + scipy only, no planetwear binary needed.
"""
import csv
import json
import math
import os
import sys

import numpy as np
import pytest
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scripts", "indepsim"))

import corpus  # noqa: E402
import sim  # noqa: E402

SEED = sim.GearSet("seed3p", 3, sim.Gear(21), sim.Gear(30), sim.Gear(81))


def kvec(stage):
    N = stage.N
    return np.r_[np.full(N, stage.kmean_iso["sp"]), np.full(N, stage.kmean_iso["rp"])]


def test_static_load_sharing_is_one_over_n_and_closed_form():
    for gs in (SEED, corpus.gearsets()["four4p"]):
        st = sim.Stage(gs)
        T0 = 250.0
        x, F = st.static_state(T0, kvec(st))
        N = st.N
        expected = T0 / (N * st.rb[0])                       # F = T_s / (N r_bs)
        np.testing.assert_allclose(F[:N], expected, rtol=1e-9)
        np.testing.assert_allclose(F[N:], expected, rtol=1e-9)  # planet moment balance: F_rp = F_sp
        # a pin error redistributes the load but keeps the sun's torque balance
        e = np.zeros(2 * N)
        e[1] = e[N + 1] = 2e-6 * math.cos(st.alpha)
        x, F = st.static_state(T0, kvec(st), e)
        assert F[1] < expected and F[0] > expected
        np.testing.assert_allclose(F[:N].sum() * st.rb[0], T0, rtol=1e-9)
        # carrier torque ratio (Zs + Zr) / Zs
        Tc = (F[:N] * (st.rb[0] + st.rb[1])).sum() + (F[N:] * (st.rb[2] - st.rb[1])).sum()
        np.testing.assert_allclose(Tc, T0 * sum(st.Z[::2]) / st.Z[0], rtol=1e-9)


def test_contact_ratio_and_iso_stiffness():
    st = sim.Stage(SEED)
    # textbook contact ratios of 21/30 external and 30/81 internal, m = 3, alpha = 20 deg
    assert abs(st.eps["sp"] - 1.611) < 2e-3 and abs(st.eps["rp"] - 1.936) < 2e-3
    # ISO 6336-1: c' ~ 12-15 N/(mm um) for steel spur gears; mean of the tabulated mesh = c_gamma_alpha b
    assert 11 < st.cprime["sp"] < 16
    np.testing.assert_allclose(st.tab["sp"][:-1, 0].mean(), st.kmean_iso["sp"], rtol=2e-3)
    # the single-pair law: 0.55 at the ends of the contact (before the ramps), 1 in the middle
    assert abs(sim.pair_shape(0.5, 0.05) - 1.0) < 1e-12
    assert sim.pair_shape(-0.01, 0.05) == 0.0 and sim.pair_shape(1.01, 0.05) == 0.0


def _linear_rig():
    """Constant mesh stiffness, no friction, no damping anywhere, dyno free (no speed loop)."""
    return sim.Rig(stiffness_variation=False, input_shaft_damping_Nms=0.0, output_shaft_damping_Nms=0.0,
                   speed_loop_bandwidth_Hz=0.0)


def test_natural_frequency_of_free_vibration_matches_eigenvalues():
    st = sim.Stage(SEED, _linear_rig())
    case = sim.Case(60.0, 200.0, 0.01, faults=sim.Faults(friction_coefficient=0.0, damping_scale=0.0))
    K = st.stiffness_matrix(kvec(st))
    Mi = 1 / np.sqrt(st.M)
    w2 = np.linalg.eigvalsh(Mi[:, None] * K * Mi[None, :])
    np.testing.assert_allclose(np.sqrt(np.clip(w2, 0, None)) / (2 * math.pi), st.natural_frequencies(), atol=1e-6)
    lf = st.load_factor(case)                          # ISO light-load reduction of c' applies in the run
    K = st.stiffness_matrix(kvec(st) * lf)
    w2, V = np.linalg.eigh(Mi[:, None] * K * Mi[None, :])
    f = np.sqrt(np.clip(w2, 0, None)) / (2 * math.pi)
    # pick the gear mode with the largest sun-planet mesh participation
    modes = Mi[:, None] * V
    part = np.abs(st.A[0] @ modes) * (f > 1000)
    j = int(np.argmax(part))
    phi = modes[:, j] / np.max(np.abs(st.A @ modes[:, j])) * 1e-7   # at most 0.1 um of mesh deflection
    off = np.zeros((1, 2 * st.n))
    off[0, :st.n] = phi
    fs, res, info = sim.simulate_batch(st, [case], warmup_s=0.001, fs=20000.0, D=12, keep_fine=True,
                                       initial_offset=off, chunk=512)
    a = info["fine"][0, 2, :2048]                      # sun-planet acceleration of planet 0, every step
    t = np.arange(a.size) * info["dt"]
    # frequency from zero crossings (linear interpolation)
    s = np.signbit(a)
    idx = np.nonzero(s[1:] != s[:-1])[0]
    tz = t[idx] - a[idx] * (t[idx + 1] - t[idx]) / (a[idx + 1] - a[idx])
    f_meas = (len(tz) - 1) / (2 * (tz[-1] - tz[0]))
    assert abs(f_meas / f[j] - 1) < 2e-3, (f_meas, f[j])


def test_rk4_converges_at_fourth_order():
    st = sim.Stage(SEED, _linear_rig())
    case = sim.Case(300.0, 20000.0, 0.01, faults=sim.Faults(friction_coefficient=0.0, ripple_fraction=0.2,
                                                         ripple_order=40.0, damping_scale=0.0))
    # start off equilibrium so that every mode rings
    rng = np.random.default_rng(3)
    off = np.zeros((1, 2 * st.n))
    off[0, st.ip] = rng.normal(0, 2e-6, st.N)      # < static deflection: no contact loss (a kink)
    sig = {}
    for D in (6, 12, 24, 96):                          # omega_max dt = 0.59 ... 0.04
        fs, res, info = sim.simulate_batch(st, [case], warmup_s=0.001, fs=20000.0, D=D, keep_fine=True,
                                           initial_offset=off, chunk=512)
        x = info["fine"][0, 2]
        k = D // 6
        sig[D] = x[::k][:1000]                         # common times, 1000 x 8.3 us
    e1 = np.max(np.abs(sig[6] - sig[96]))
    e2 = np.max(np.abs(sig[12] - sig[96]))
    e3 = np.max(np.abs(sig[24] - sig[96]))
    order = math.log2(e2 / e3)
    assert e1 > e2 > e3
    assert 3.5 < order < 4.6, (e1, e2, e3, order)


def test_encoder_filter_minus_3dB_at_its_bandwidth():
    rig = sim.Rig()
    fsf = 75000.0
    sos = sim.encoder_sos(rig, fsf)
    w, h = signal.sosfreqz(sos, worN=[rig.encoder_bandwidth_Hz, 10.0, 4 * rig.encoder_bandwidth_Hz], fs=fsf)
    mag = np.abs(h)
    assert abs(20 * np.log10(mag[0]) + 3.01) < 0.05
    assert abs(mag[1] - 1) < 1e-3
    assert mag[2] < 0.07                               # 2nd order: ~ -24 dB two octaves up
    # on a sampled sine
    t = np.arange(30000) / fsf
    y = signal.sosfilt(sos, np.sin(2 * np.pi * rig.encoder_bandwidth_Hz * t))
    amp = np.std(y[10000:]) * math.sqrt(2)
    assert abs(amp - 1 / math.sqrt(2)) < 0.01


def test_speed_control_holds_the_mean_speed():
    st = sim.Stage(SEED)
    cases = [sim.Case(600.0, 5000.0, 0.25, faults=sim.Faults(friction_coefficient=0.15)),
             sim.Case(600.0, 5000.0, 0.25, faults=sim.Faults(ripple_fraction=0.1, ripple_order=2.0))]
    fs, res, info = sim.simulate_batch(st, cases, warmup_s=0.5, fs=5000.0, D=15, chunk=1024)
    Ws, Wc, _ = st.nominal(cases[0])
    for r in res:
        # whole number of ripple periods: 0.25 s at 10 Hz sun speed = 2.5 sun revs -> use 0.2 s
        n = int(0.2 * fs)
        assert abs(r["sun_speed"][:n].mean() / Ws - 1) < 2e-3
        assert abs(r["carrier_speed"][:n].mean() / Wc - 1) < 2e-3
    # friction loses power: the planet-ring forces fall short of the frictionless T/(N r_bs) by < 5 %
    F = res[0]["mean_planet_ring_force"]
    T0 = cases[0].power_W / Ws
    assert np.all(F < T0 / (st.N * st.rb[0])) and np.all(F > 0.95 * T0 / (st.N * st.rb[0]))


UNITS = {"sun_speed": {"rad/s", "rpm"}, "carrier_speed": {"rad/s", "rpm"},
         "mesh_acceleration_sun_planet": {"m/s^2", "g"}, "mesh_acceleration_planet_ring": {"m/s^2", "g"},
         "housing_acceleration": {"m/s^2", "g"}}


def test_quick_corpus_smoke_writes_documented_format(tmp_path):
    out = str(tmp_path / "c")
    truth = corpus.build(out, quick=True, limit=2, duration=0.5)
    recs = truth["recordings"]
    assert len(recs) == 2
    assert any(r["role"] == "baseline" for r in recs.values())
    for key, r in recs.items():
        assert os.path.exists(os.path.join(out, r["gearset"], "gearset.toml"))
        assert not os.path.exists(os.path.join(out, r["gearset"], "recordings", "truth.json"))
        csvp = os.path.join(out, r["csv"])
        meta = json.load(open(os.path.splitext(csvp)[0] + ".json"))
        assert set(meta) <= {"description", "generator", "operating", "time_column", "time_unit", "columns",
                             "sample_rate_Hz"}
        assert meta["operating"]["input_speed_rpm"] == r["input_speed_rpm"] > 0
        assert meta["operating"]["input_power_W"] > 0
        with open(csvp) as f:
            lines = [ln for ln in f if not ln.startswith("#")]
        header = next(csv.reader([lines[0]]))
        data = np.loadtxt(lines[1:], delimiter=",")
        assert header[0] == meta["time_column"] == "time"
        assert data.shape[1] == len(header) and np.all(np.isfinite(data))
        for name, c in meta["columns"].items():
            assert name in header
            assert c["unit"] in UNITS[c["quantity"]]
            if c["quantity"].startswith("mesh_acceleration"):
                assert c["planet"] == 0
            assert ("sensor_angle_deg" in c) == (c["quantity"] == "housing_acceleration")
        t = data[:, 0]
        dtt = np.diff(t)
        assert np.all(dtt > 0) and np.max(np.abs(t - t[0] - np.arange(t.size) * dtt.mean())) < 1e-7
        fs = 1 / dtt.mean()
        Zs, Zr = 21, 81
        fm = Zs * Zr / (Zs + Zr) * r["input_speed_rpm"] / 60
        assert fs >= 2.5 * 3 * fm
        # speeds near nominal in the stated units
        ws = data[:, header.index("w_sun")]
        assert abs(ws.mean() / r["input_speed_rpm"] - 1) < 0.01
        wc = data[:, header.index("w_carrier")]
        assert abs(wc.mean() / (r["input_speed_rpm"] * 2 * math.pi / 60 * Zs / (Zs + Zr)) - 1) < 0.01
        # 5 % noise + offsets present on the accelerometers: not constant, finite, plausible
        for col in ("a_sp0", "a_pr0", "acc_housing"):
            x = data[:, header.index(col)]
            assert 0 < np.std(x) < 1e4
    # gearset.toml reads back to the same geometry
    g = sim.read_gearset_toml(os.path.join(out, "seed3p", "gearset.toml"))
    assert (g.sun.teeth, g.planet.teeth, g.ring.teeth, g.planet_count) == (21, 30, 81, 3)
    assert g.friction_coefficient == 0.06


import observability  # noqa: E402


def test_deflection_of_a_sinusoid_is_its_energy_over_the_noise_variance():
    # Whole periods of A sin: sum(Delta^2) = N A^2 / 2 exactly; an added constant is removed.
    n, A, sigma = 4000, 0.3, 0.05
    t = np.arange(n)
    d = A * np.sin(2 * np.pi * 7 * t / n) + 5.0
    assert observability.deflection(d, sigma) == pytest.approx(n * A * A / 2 / sigma ** 2, rel=1e-12)


def test_unobservable_bound_is_the_squared_normal_quantile():
    # z_0.99 = 2.326348 (any normal table); z_0.95 = 1.644854
    assert observability.unobservable_below(0.01) == pytest.approx(2.326348 ** 2, rel=1e-6)
    assert observability.unobservable_below(0.05) == pytest.approx(1.644854 ** 2, rel=1e-6)


def test_signature_of_an_effect_free_twin_is_zero_and_grows_with_the_effect(tmp_path):
    # The twin of a recording without effect is itself (d2 = 0 exactly: the batch's cases are
    # integrated independently); a stiffer tooth fault is more visible than a milder one.
    st = sim.Stage(SEED)
    base = dict(speed_rpm=600.0, power_W=5000.0, duration_s=0.05, sensor_angle_deg=40.0, seed=3)
    cases = [sim.Case(**base), sim.Case(**base),
             sim.Case(**base, faults=sim.Faults(tooth_body="sun", tooth_index=2, tooth_stiffness_factor=0.9)),
             sim.Case(**base, faults=sim.Faults(tooth_body="sun", tooth_index=2, tooth_stiffness_factor=0.5))]
    fs, res, _ = sim.simulate_batch(st, cases, warmup_s=0.02, fs=20000.0, D=6)
    same = observability.signature(res[0], res[1], 0.05)
    assert all(v["d2_model"] == 0 and v["d2_baseline"] == 0 for v in same.values())
    mild = observability.signature(res[2], res[0], 0.05)
    severe = observability.signature(res[3], res[0], 0.05)
    total = lambda s, k: sum(s[c][k] for c in observability.RIG_CHANNELS)  # noqa: E731
    assert 0 < total(mild, "d2_model") < total(severe, "d2_model")
    # against a noisy baseline the variance doubles (nearly: the two channels' sigmas differ a little)
    assert total(mild, "d2_baseline") == pytest.approx(total(mild, "d2_model") / 2, rel=0.05)


import confusion  # noqa: E402


def test_scoring_counts_a_class_right_only_for_its_members_and_an_invisible_effect_apart():
    s = confusion.score
    assert s("sun_runout", "sun_runout") == "named_right"
    assert s("class:carrier_runout|pin_error", "pin_error") == "named_right_as_class"
    assert s("class:carrier_runout|pin_error", "sun_runout") == "wrong_name"
    assert s("none", "friction") == "missed" and s("unexplained", "friction") == "unexplained"
    assert s("friction", "none") == "control_false_name" and s("none", "none") == "control_clean"
    # an effect without a signature: "no missing physics" is right, a name is wrong, even the true one
    assert s("none", "backlash", unobservable=True) == "unobservable_clean"
    assert s("backlash", "backlash", unobservable=True) == "unobservable_named"
    assert s("refused", "backlash", unobservable=True) == "refused"


def test_a_backlash_no_flank_reached_is_inert_by_the_generators_own_record_and_nothing_else_is():
    def rec(effect, **diag):
        return {"role": "effect", "effect": effect, "diagnostics": diag}
    inert = confusion.inert_by_truth
    # indepsim4's and indepsim3's separation fractions: no separation, the play never traversed
    assert inert(rec("backlash", fraction_of_steps_a_mesh_in_backlash=0.0))
    assert inert(rec("backlash", fraction_of_time_a_mesh_separated=0.0))
    # a single separated step makes the clearance matter, and without the record nothing is proven
    assert not inert(rec("backlash", fraction_of_steps_a_mesh_in_backlash=1e-5))
    assert not inert(rec("backlash"))
    assert not inert({"role": "effect", "effect": "backlash"})
    # only the clearance is inert without separation: friction acts on every loaded flank
    assert not inert(rec("friction", fraction_of_steps_a_mesh_in_backlash=0.0))
    assert not inert({"role": "control", "effect": "backlash",
                      "diagnostics": {"fraction_of_steps_a_mesh_in_backlash": 0.0}})


def final_check_plan(variant, seed, gearset):
    """A final-check plan's entries after the checks every such plan must pass: each effect once,
    a baseline and a control at every operating point, a gear set with equally spaced planets
    that no other plan uses."""
    entries, _, _, _ = corpus.plan_entries(seed=seed, variant=variant)
    effects = [e["effect"] for e in entries if e["role"] == "effect"]
    assert len(set(effects)) == 12
    ops = {e["op"] for e in entries}
    assert {e["op"] for e in entries if e["role"] == "baseline"} == ops == {e["op"] for e in entries
                                                                           if e["role"] == "control"}
    gs = corpus.gearsets()[gearset]
    assert (gs.sun.teeth + gs.ring.teeth) % gs.planet_count == 0
    assert gs.ring.teeth == gs.sun.teeth + 2 * gs.planet.teeth
    for other in corpus.PLANS:
        if other != variant:
            assert all(g != gearset for (g, *_rest) in corpus.plan(variant=other))
    return entries, effects, gs


def test_fresh_plan_has_every_effect_once_a_baseline_per_operating_point_and_equal_planet_spacing():
    _, effects, _ = final_check_plan("fresh", 7, "fresh5p")
    assert len(effects) == 12


def test_second_fresh_plan_has_every_effect_a_short_recording_and_a_gear_set_no_other_plan_uses():
    entries, effects, gs = final_check_plan("fresh2", 11, "fresh3p")
    assert set(effects) == {eff for (_g, _op, eff, _kw, _d) in corpus.plan_fresh() if eff != "none"}
    # one recording under two carrier revolutions (the short recordings)
    carrier_rev_s = [60.0 / (e["rpm"] * gs.sun.teeth / (gs.sun.teeth + gs.ring.teeth)) for e in entries]
    assert any(e["duration_s"] < 2 * t for e, t in zip(entries, carrier_rev_s))


def test_third_fresh_plan_has_every_effect_a_short_recording_and_four_planets_no_other_plan_uses():
    entries, effects, gs = final_check_plan("fresh3", 13, "fresh4p")
    assert set(effects) == {eff for (_g, _op, eff, _kw, _d) in corpus.plan_fresh() if eff != "none"}
    assert gs.planet_count == 4
    carrier_rev_s = [60.0 / (e["rpm"] * gs.sun.teeth / (gs.sun.teeth + gs.ring.teeth)) for e in entries]
    assert any(e["duration_s"] < 2 * t for e, t in zip(entries, carrier_rev_s))


def test_a_class_finding_is_scored_right_for_what_it_covers_and_wrong_for_anything_else(tmp_path):
    rep = {"verdict": "missing_physics_found", "missing_physics": "tooth_contact_change", "summary": "",
           "finding_class": {"name": "tooth_contact_change", "members": ["friction", "worn_profile"],
                             "covers": ["friction", "worn_profile", "tip_relief", "backlash", "stiffness_level",
                                        "damping_level"]}}
    p = tmp_path / "report.json"
    p.write_text(json.dumps(rep))
    label = confusion.read_report(str(p))[0]
    assert confusion.score(label, "stiffness_level") == "named_right_as_class"
    assert confusion.score(label, "worn_profile") == "named_right_as_class"
    assert confusion.score(label, "torque_ripple") == "wrong_name"
    assert confusion.score(label, "none") == "control_false_name"
    # a report without "covers" (before session 38) is scored by its members alone
    del rep["finding_class"]["covers"]
    p.write_text(json.dumps(rep))
    label = confusion.read_report(str(p))[0]
    assert confusion.score(label, "stiffness_level") == "wrong_name"
    assert confusion.score(label, "friction") == "named_right_as_class"


def test_located_family_is_read_from_the_report_and_missing_when_nothing_was_located(tmp_path):
    p = tmp_path / "report.json"
    p.write_text(json.dumps({"verdict": "unexplained_residual",
                             "location": {"screened_family": "sun", "screened_candidate": "sun_tooth_damage"}}))
    assert confusion.located_family(str(p)) == "sun"
    p.write_text(json.dumps({"verdict": "no_missing_physics"}))
    assert confusion.located_family(str(p)) is None
    assert confusion.located_family(str(tmp_path / "absent.json")) is None
    # a binary without the `candidates` command gives no table, so no located_right is scored
    assert confusion.candidate_families("/bin/false") == {}


def test_confusion_reads_the_coverage_gap_share_and_none_where_nothing_was_tested(tmp_path):
    # report.json's coverage_gap (docs/diagnose.md section 6a item 13): null without a calibration
    # or baseline, a share otherwise; a missing or broken report reads as not known.
    import json
    p = tmp_path / "report.json"
    p.write_text(json.dumps({"coverage_gap": {"share": 0.978, "lines": [], "tested": []}}))
    assert confusion.coverage_gap_share(str(p)) == 0.978
    p.write_text(json.dumps({"coverage_gap": None}))
    assert confusion.coverage_gap_share(str(p)) is None
    p.write_text("{not json")
    assert confusion.coverage_gap_share(str(p)) is None
    assert confusion.coverage_gap_share(str(tmp_path / "missing.json")) is None
