#!/usr/bin/env python3
"""Writes an indepsim2 recording corpus (second independent simulator, sim.py).

    /usr/bin/python3 scripts/indepsim2/corpus.py -o /work/indep_sim2 --seed 21 [--jobs 2] [--quick]

Layout: DIR/<gearset>/gearset.toml (documentation keys only), DIR/<gearset>/recordings/rec_NN.{csv,json}
(docs/recordings.md), DIR/truth.json (outside recordings/), DIR/corpus.log.
One batch (all recordings of a gear set simulated together, vectorised) per process.
"""
import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse
import concurrent.futures as cf
import json
import math
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sim  # noqa: E402

GEARSETS = {
    # name: (Zs, Zp, Zr, N, module, face width, friction, design backlash)
    "rigA3": dict(Zs=19, Zp=35, Zr=89, N=3, module=0.0025, width=0.040, mu=0.06, backlash=1.2e-5,
                  sensor_angle_housing_deg=75.0),
    "rigB5": dict(Zs=25, Zp=20, Zr=65, N=5, module=0.003, width=0.035, mu=0.05, backlash=1.5e-5,
                  sensor_angle_housing_deg=200.0),
}
OPS = {
    "rigA3": {"a": (300.0, 4000.0), "b": (900.0, 10000.0)},
    "rigB5": {"c": (400.0, 8000.0), "d": (1100.0, 18000.0)},
}
# (role, effect, op, duration_s, parameters)
PLAN = {
    "rigA3": [
        ("baseline", "none", "a", 4.0, {}),
        ("baseline", "none", "b", 3.0, {}),
        ("control", "none", "a", 3.8, {}),
        ("control", "none", "b", 2.8, {}),
        ("effect", "sun_tooth_damage", "a", 3.8, {"tooth_body": "sun", "tooth_index": 7, "tooth_stiffness_factor": 0.6}),
        ("effect", "planet_tooth_damage", "b", 3.0,
         {"tooth_body": "planet", "tooth_planet": 1, "tooth_index": 12, "tooth_stiffness_factor": 0.55}),
        ("effect", "ring_tooth_damage", "a", 4.0, {"tooth_body": "ring", "tooth_index": 40, "tooth_stiffness_factor": 0.65}),
        ("effect", "pin_error", "b", 2.5, {"pin_error_m": [0.0, 3.0e-6, 0.0]}),
        ("effect", "sun_runout", "a", 2.0, {"sun_ecc_m": 2.5e-6, "sun_ecc_phase_rad": 0.8}),
        ("effect", "torque_ripple", "b", 2.5, {"ripple_fraction": 0.05, "ripple_order": 2.0, "ripple_phase_rad": 0.3}),
        ("effect", "worn_profile", "a", 3.5, {"worn_depth_m": 3.0e-6}),
        ("effect", "sensor_transfer_path", "b", 2.5, {"housing_gain_scale": 0.6}),
    ],
    "rigB5": [
        ("baseline", "none", "c", 3.5, {}),
        ("baseline", "none", "d", 2.5, {}),
        ("control", "none", "c", 3.2, {}),
        ("control", "none", "d", 2.2, {}),
        ("effect", "sun_tooth_damage", "d", 2.5, {"tooth_body": "sun", "tooth_index": 17, "tooth_stiffness_factor": 0.65}),
        ("effect", "planet_tooth_damage", "c", 3.5,
         {"tooth_body": "planet", "tooth_planet": 3, "tooth_index": 5, "tooth_stiffness_factor": 0.6}),
        ("effect", "ring_tooth_damage", "d", 2.5, {"tooth_body": "ring", "tooth_index": 22, "tooth_stiffness_factor": 0.55}),
        ("effect", "carrier_runout", "c", 3.5, {"carrier_ecc_m": 2.5e-6, "carrier_ecc_phase_rad": 1.2}),
        ("effect", "stiffness_level", "d", 2.2, {"stiffness_scale": 0.8}),
        ("effect", "damping_level", "c", 3.0, {"damping_scale": 3.0}),
        ("effect", "friction", "c", 3.0, {"friction_coefficient": 0.10}),
        ("effect", "backlash", "d", 2.5, {"backlash_m": 6.0e-5}),
    ],
}
FS = 10000.0
NOISE = 0.05


def case_for(effect, params, rpm, power):
    c = dict(rpm=rpm, power_W=power)
    p = params
    if effect == "sun_tooth_damage":
        c["sun_tooth"] = {p["tooth_index"]: p["tooth_stiffness_factor"]}
    elif effect == "planet_tooth_damage":
        c["planet_tooth"] = {(p["tooth_planet"], p["tooth_index"]): p["tooth_stiffness_factor"]}
    elif effect == "ring_tooth_damage":
        c["ring_tooth"] = {p["tooth_index"]: p["tooth_stiffness_factor"]}
    elif effect == "pin_error":
        c["pin_error_m"] = list(p["pin_error_m"])
    elif effect == "sun_runout":
        c["sun_ecc_m"], c["sun_ecc_phase_rad"] = p["sun_ecc_m"], p["sun_ecc_phase_rad"]
    elif effect == "carrier_runout":
        c["carrier_ecc_m"], c["carrier_ecc_phase_rad"] = p["carrier_ecc_m"], p["carrier_ecc_phase_rad"]
    elif effect == "stiffness_level":
        c["stiffness_scale"] = p["stiffness_scale"]
    elif effect == "damping_level":
        c["damping_scale"] = p["damping_scale"]
    elif effect == "friction":
        c["mu"] = p["friction_coefficient"]
    elif effect == "torque_ripple":
        c["ripple_fraction"], c["ripple_order"], c["ripple_phase_rad"] = (p["ripple_fraction"], p["ripple_order"],
                                                                          p["ripple_phase_rad"])
    elif effect == "worn_profile":
        c["worn_depth_m"] = p["worn_depth_m"]
    elif effect == "backlash":
        c["backlash_m"] = p["backlash_m"]
    elif effect in ("none", "sensor_transfer_path"):
        pass
    else:
        raise ValueError(effect)
    return c


def make_plan(seed, quick=False):
    rng = np.random.default_rng(seed)
    plan = {}
    for g, items in PLAN.items():
        if quick:
            items = [it for it in items if it[0] == "baseline"] + [it for it in items if it[0] != "baseline"][:2]
        n = len(items)
        names = [f"rec_{k + 1:02d}" for k in rng.permutation(n)]
        recs = []
        for (role, eff, op, dur, params), name in zip(items, names):
            if quick:
                dur = min(dur, 0.4)
            start = 0.55 if role == "baseline" else float(rng.uniform(0.5, 0.65))
            start = round(start * FS) / FS
            recs.append(dict(name=name, role=role, effect=eff, op=op, duration_s=dur, parameters=params,
                             start_s=start, noise_seed=int(rng.integers(1, 2 ** 31 - 1)),
                             dc_offset_fraction=float(rng.choice([-1, 1]) * rng.uniform(0.1, 0.5))))
        plan[g] = recs
    return plan


def run_gearset(out, g, recs, rtol, quick):
    t0 = time.time()
    spec = GEARSETS[g]
    gdir = os.path.join(out, g)
    os.makedirs(os.path.join(gdir, "recordings"), exist_ok=True)
    toml = sim.gearset_toml(g, spec["Zs"], spec["Zp"], spec["Zr"], spec["N"], spec["module"], spec["width"],
                            spec["mu"], spec["backlash"])
    with open(os.path.join(gdir, "gearset.toml"), "w") as f:
        f.write(toml)
    gs = sim.read_gearset(os.path.join(gdir, "gearset.toml"))
    sim_recs = []
    for r in recs:
        rpm, power = OPS[g][r["op"]]
        sim_recs.append(dict(case=case_for(r["effect"], r["parameters"], rpm, power), start_s=r["start_s"],
                             duration_s=r["duration_s"], noise_seed=r["noise_seed"], noise_fraction=NOISE,
                             dc_offset_fraction=r["dc_offset_fraction"],
                             housing_gain_scale=r["parameters"].get("housing_gain_scale", 1.0),
                             sensor_angle_housing_deg=spec["sensor_angle_housing_deg"]))
    logs = []
    res, bt = sim.simulate_batch(gs, sim_recs, fs=FS, rtol=rtol, log=logs.append)
    info = {}
    base_clean = {}
    for r, o in zip(recs, res):
        rpm, power = OPS[g][r["op"]]
        csvp = os.path.join(gdir, "recordings", r["name"] + ".csv")
        desc = (f"indepsim2 rig, gear set {g}, {FS:.0f} Hz DAQ, encoders on sun and carrier shafts, "
                f"one housing accelerometer; {NOISE * 100:.0f} % noise")
        sim.write_recording(csvp, o["t"], o["w_sun_rpm"], o["w_carrier"], o["acc_g"], rpm, power,
                            o["sensor_angle_deg"], desc)
        info[r["name"]] = o
        if r["role"] == "baseline":
            base_clean[r["op"]] = o["clean"]
    # per-recording extra truth: mean mesh forces at the static state, rms ratios vs baseline (noise free)
    extra = {}
    Y0 = bt.static_state()
    C = bt._self_cols()
    ms = bt.mesh_state(0.0, Y0[:bt.lin["nd"]], None, C)
    for b, r in enumerate(recs):
        o = info[r["name"]]
        bc = base_clean[r["op"]]
        rr = {}
        for k, lab in (("w_s", "sun_speed"), ("w_c", "carrier_speed"), ("acc", "housing")):
            rr[lab] = round(float(np.std(o["clean"][k]) / max(np.std(bc[k]), 1e-30)), 4)
        theta_c0 = o["theta_c0"]
        e = dict(sensor_angle_deg_sidecar=round(o["sensor_angle_deg"], 4),
                 sensor_angle_deg_housing=spec["sensor_angle_housing_deg"],
                 carrier_angle_at_t0_rad=round(float(theta_c0), 6),
                 sim_start_s=r["start_s"], noise_seed=r["noise_seed"], noise_fraction=NOISE,
                 dc_offset_fraction=round(r["dc_offset_fraction"], 4),
                 static_mesh_force_N_sp=[round(float(x), 1) for x in ms["f"][:bt.N, :, b].sum(1)],
                 static_mesh_force_N_rp=[round(float(x), 1) for x in ms["f"][bt.N:, :, b].sum(1)],
                 rms_ratio_vs_baseline_noise_free=rr)
        if r["effect"] == "ring_tooth_damage":
            k = r["parameters"]["tooth_index"]
            ang = math.degrees(2 * math.pi * (k + bt.c_r) / bt.Zr - theta_c0) % 360.0
            e["ring_tooth_angle_deg_housing"] = round(ang, 3)
        extra[r["name"]] = e
    f_nat, _ = sim.natural_frequencies(bt.lin)
    ginfo = dict(
        toml=f"{g}/gearset.toml", planet_count=spec["N"], teeth=[spec["Zs"], spec["Zp"], spec["Zr"]],
        module_m=spec["module"], face_width_m=spec["width"],
        contact_ratio={k: round(bt.geo["meshes"][k]["eps"], 4) for k in ("sp", "rp")},
        mean_mesh_stiffness_N_m={k: round(bt.geo["meshes"][k]["kmean"], -5) for k in ("sp", "rp")},
        natural_frequencies_Hz=[round(float(x), 1) for x in f_nat],
        rayleigh={"alpha_1_s": round(bt.alpha0, 3), "beta_s": float(f"{bt.beta0:.4g}"),
                  "zeta": bt.rig["zeta_rayleigh"], "f1_f2_Hz": [round(x, 1) for x in bt.f_rayleigh]},
        rig={k: v for k, v in bt.rig.items()},
        lumped={k: (round(v, 6) if isinstance(v, float) else v) for k, v in bt.par.items() if k != "rig"},
        design_backlash_m=spec["backlash"], friction_coefficient=spec["mu"],
        ring_phase_offset_pitches=bt.c_r, planet_ring_tooth_offsets=[int(x) for x in bt.Joff],
        wall_s=round(time.time() - t0, 1), log=logs)
    return g, ginfo, extra


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--seed", type=int, default=21)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--quick", action="store_true", help="4 short recordings per gear set (smoke test)")
    a = ap.parse_args(argv)
    t0 = time.time()
    os.makedirs(a.out, exist_ok=True)
    plan = make_plan(a.seed, a.quick)
    results = {}
    with cf.ProcessPoolExecutor(max_workers=max(1, min(a.jobs, 2))) as ex:
        futs = [ex.submit(run_gearset, a.out, g, recs, a.rtol, a.quick) for g, recs in plan.items()]
        for fu in cf.as_completed(futs):
            g, ginfo, extra = fu.result()
            results[g] = (ginfo, extra)
            print(f"{g}: {len(plan[g])} recordings in {ginfo['wall_s']} s; " + "; ".join(ginfo["log"]), flush=True)
    truth = dict(generator="scripts/indepsim2/corpus.py (second independent simulator, sim.py)", seed=a.seed,
                 quick=a.quick, plan="sim2",
                 noise=f"{NOISE * 100:.0f} % of each channel's RMS about its mean (white Gaussian, after the "
                       "sensor chain); accelerometer DC offsets +-(10-50) % of its RMS",
                 gearsets={}, recordings={})
    for g in plan:
        ginfo, extra = results[g]
        truth["gearsets"][g] = ginfo
        base_of = {r["op"]: f"{g}/{r['name']}" for r in plan[g] if r["role"] == "baseline"}
        for r in sorted(plan[g], key=lambda r: r["name"]):
            rpm, power = OPS[g][r["op"]]
            Zs, Zr = GEARSETS[g]["Zs"], GEARSETS[g]["Zr"]
            fc = rpm / 60.0 * Zs / (Zs + Zr)
            params = dict(r["parameters"])
            if r["effect"] == "ring_tooth_damage":
                params["ring_tooth_angle_deg_housing"] = extra[r["name"]]["ring_tooth_angle_deg_housing"]
            rec = dict(gearset=g, name=r["name"], csv=f"{g}/recordings/{r['name']}.csv", effect=r["effect"],
                       role=r["role"], parameters=params, operating_point=r["op"], input_speed_rpm=rpm,
                       input_power_W=power, duration_s=r["duration_s"],
                       carrier_revolutions=round(r["duration_s"] * fc, 3), reader_should_refuse=False,
                       held_out=False, baseline=base_of[r["op"]], fs_Hz=FS,
                       mesh_frequency_Hz=round(Zs * Zr / (Zs + Zr) * rpm / 60.0, 3))
            if r["effect"] == "backlash":
                rec["note"] = ("backlash only matters where a flank would separate; at this load the teeth may "
                               "never separate, so the effect can be unobservable")
            rec.update({k: v for k, v in extra[r["name"]].items() if k != "ring_tooth_angle_deg_housing"})
            truth["recordings"][f"{g}/{r['name']}"] = rec
    truth["wall_s"] = round(time.time() - t0, 1)
    with open(os.path.join(a.out, "truth.json"), "w") as f:
        json.dump(truth, f, indent=1)
    with open(os.path.join(a.out, "corpus.log"), "a") as f:
        f.write(f"{time.ctime()}: corpus.py -o {a.out} --seed {a.seed}{' --quick' if a.quick else ''}: "
                f"{sum(len(v) for v in plan.values())} recordings, {truth['wall_s']} s wall\n")
        for g in plan:
            f.write(f"  {g}: " + "; ".join(results[g][0]["log"]) + f" ({results[g][0]['wall_s']} s)\n")
    print(f"wrote {sum(len(v) for v in plan.values())} recordings to {a.out} in {truth['wall_s']} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
