#!/usr/bin/python3
"""indepsim3 corpus: recordings of two gear sets on their test rigs, for `planetwear diagnose`.

    /usr/bin/python3 scripts/indepsim3/corpus.py -o DIR --seed S [--plan main] [--jobs 2] [--quick]

Writes DIR/<gearset>/gearset.toml (what the stage's drawing gives: gears, friction, design backlash),
DIR/<gearset>/recordings/rec_NN.csv + rec_NN.json (docs/recordings.md), DIR/truth.json (per recording:
role, effect, parameters, operating point, baseline, held_out, duration, carrier revolutions, noise,
sensor angle, diagnostics of the run) and DIR/corpus.log. One batch (all recordings of a gear set,
simulated together as numpy arrays) per process. README.md next to this file for the physics.
"""
import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import concurrent.futures as cf  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from dataclasses import asdict  # noqa: E402

import numpy as np  # noqa: E402

import importlib.util  # noqa: E402

# The sibling sim.py under a name of its own: the other independent simulators' tests put their own
# `sim` module into sys.modules of the same pytest run, and a plain `import sim` would return that.
# Registered in sys.modules so that pickling its dataclasses (worker processes) finds it.
if "indepsim3_sim" not in sys.modules:
    _SPEC = importlib.util.spec_from_file_location("indepsim3_sim",
                                                   os.path.join(os.path.dirname(os.path.abspath(__file__)), "sim.py"))
    sys.modules["indepsim3_sim"] = importlib.util.module_from_spec(_SPEC)
    _SPEC.loader.exec_module(sys.modules["indepsim3_sim"])
sim = sys.modules["indepsim3_sim"]
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "indepsim_common"))
import indepsim_writers as writers  # noqa: E402  (the file formats, shared with the other corpora)
import indepsim_effects as effects  # noqa: E402  (the effects' sizes, shared likewise)

GENERATOR = "indepsim3 (scripts/indepsim3/corpus.py)"
NOISE_FRACTION = 0.05

# ----------------------------------------------------------------------------------------------
# Gear sets, rigs, operating points
# ----------------------------------------------------------------------------------------------

GEARSETS = {
    # 4 planets, sequentially phased meshes (Zs/N not an integer), 23/31/85
    "setA4": dict(
        gear=sim.GearSet("setA4", Zs=23, Zp=31, Zr=85, N=4, module_m=0.0025, face_width_m=0.030,
                         friction=0.06, backlash_sp_m=20e-6, backlash_pr_m=20e-6),
        rig=sim.Rig(J_motor=0.08, J_brake=0.35, f_input_shaft_Hz=35.0, f_output_shaft_Hz=210.0, shaft_zeta=0.04,
                    motor_sag=0.04, housing_f_Hz=2600.0, housing_zeta=0.03, housing_mass_kg=20.0, window_power=4.0,
                    iepe_highpass_Hz=2.0, lines_sun=1024, lines_carrier=2048),
        ops={"op1": (500.0, 15000.0, 5000.0), "op2": (1100.0, 20000.0, 10000.0)}),
    # 5 planets, in-phase meshes (Zs/N = 7), 35/20/75
    "setB5": dict(
        gear=sim.GearSet("setB5", Zs=35, Zp=20, Zr=75, N=5, module_m=0.0025, face_width_m=0.022,
                         friction=0.07, backlash_sp_m=25e-6, backlash_pr_m=25e-6),
        rig=sim.Rig(J_motor=0.05, J_brake=0.2, f_input_shaft_Hz=45.0, f_output_shaft_Hz=280.0, shaft_zeta=0.04,
                    motor_sag=0.06, housing_f_Hz=3400.0, housing_zeta=0.03, housing_mass_kg=12.0, window_power=3.0,
                    iepe_highpass_Hz=1.5, lines_sun=1000, lines_carrier=2000),
        ops={"op1": (400.0, 18000.0, 5000.0), "op2": (900.0, 20000.0, 10000.0)}),
}

EFFECTS = ("sun_tooth_damage", "planet_tooth_damage", "ring_tooth_damage", "pin_error", "sun_runout",
           "carrier_runout", "torque_ripple", "worn_profile", "friction", "stiffness_level", "damping_level",
           "backlash", "sensor_transfer_path")
# effects that unload planets: at the higher-torque operating point (op1) so that every mesh stays loaded
HIGH_TORQUE = ("pin_error", "sun_runout", "carrier_runout")


def carrier_hz(gs, rpm):
    return rpm / 60.0 * gs.Zs / (gs.Zs + gs.Zr)


def effect_faults(effect, gs, rng):
    """A moderate size of each effect (the brief's ranges; scripts/indepsim_common/indepsim_effects.py)
    -> (Faults, truth parameters)."""
    kwargs, params = effects.draw_effect(effect, gs, rng, sim.MESH_ZETA,
                                         worn_truth=lambda d: dict(worn_depth_end_m=0.6 * d, shape="parabolic in the distance from the pitch point"))
    return sim.Faults(**kwargs), params


def plan_entries(quick, seed, plan="main"):
    """Every recording of the corpus: list of dicts (gearset, role, effect, faults, parameters, op, duration)."""
    if plan != "main":
        raise SystemExit(f"corpus.py: unknown plan {plan!r} (only 'main')")
    rng = np.random.default_rng(seed)
    entries = []
    for gname in sorted(GEARSETS):
        g = GEARSETS[gname]
        gs = g["gear"]
        ops = g["ops"]
        if quick:
            if gname != "setA4":
                continue
            spec = [("baseline", "none", "op2", 0.8), ("control", "none", "op2", 0.8),
                    ("effect", "sun_tooth_damage", "op2", 0.8), ("effect", "friction", "op1", 1.2)]
        else:
            spec = [("baseline", "none", "op1", 4.0), ("baseline", "none", "op2", 4.0),
                    ("control", "none", "op1", 3.0), ("control", "none", "op2", 3.0)]
            other = [e for e in EFFECTS if e not in HIGH_TORQUE]
            rng.shuffle(other)
            for j, e in enumerate(other):
                spec.append(("effect", e, "op1" if j % 2 == 0 else "op2", float(rng.choice([2.5, 3.0, 3.5, 4.0]))))
            for e in HIGH_TORQUE:
                spec.append(("effect", e, "op1", float(rng.choice([2.5, 3.0, 3.5, 4.0]))))
            # one short recording (< 2 carrier revolutions): a sun-family effect, 1.5 carrier revolutions
            spec.append(("effect", "sun_tooth_damage", "op2", None))
        names = rng.permutation(len(spec)) + 1
        for (role, effect, opn, dur), num in zip(spec, names):
            rpm, P, fs = ops[opn]
            short = dur is None
            if short:
                dur = round(1.5 / carrier_hz(gs, rpm), 3)
            if effect == "none":
                faults, params = sim.Faults(), {}
            else:
                faults, params = effect_faults(effect, gs, rng)
            entries.append(dict(gearset=gname, name=f"rec_{num:02d}", role=role, effect=effect, faults=faults,
                                parameters=params, op=opn, rpm=rpm, W=P, fs=fs, duration_s=dur, short=short,
                                sensor_angle_deg=float(5 * rng.integers(72)),
                                noise_seed=int(rng.integers(2 ** 31)),
                                dc_housing=float(rng.choice([-1, 1]) * rng.uniform(0.1, 0.4)),
                                dc_sp=float(rng.choice([-1, 1]) * rng.uniform(0.1, 0.4)),
                                dc_pr=float(rng.choice([-1, 1]) * rng.uniform(0.1, 0.4))))
    return entries


# ----------------------------------------------------------------------------------------------
# Writers
# ----------------------------------------------------------------------------------------------

# gearset_toml, COLUMNS, write_recording: scripts/indepsim_common/indepsim_writers.py (`writers` above),
# shared with the other corpora: the file formats, not the physics.


# ----------------------------------------------------------------------------------------------
# Running
# ----------------------------------------------------------------------------------------------

def run_gearset(gname, entries, outdir, warmup_s=None, log=None):
    """Simulate every recording of one gear set in one batch and write them. -> (truth rows, batch info)."""
    g = GEARSETS[gname]
    st = sim.Stage(g["gear"], g["rig"])
    cases = [sim.Case(e["rpm"], e["W"], e["duration_s"], fs_daq=e["fs"],
                      sensor_angle_rad=math.radians(e["sensor_angle_deg"]), faults=e["faults"]) for e in entries]
    last = [0.0]

    def progress(step, nsteps, wall):
        if wall - last[0] > 30 or step == nsteps:
            last[0] = wall
            print(f"  {gname}: {100 * step / nsteps:5.1f} % of {nsteps} steps, {wall:.0f} s", flush=True)

    res, info = sim.simulate_batch(st, cases, warmup_s=warmup_s, progress=progress)
    gdir = os.path.join(outdir, gname)
    os.makedirs(os.path.join(gdir, "recordings"), exist_ok=True)
    with open(os.path.join(gdir, "gearset.toml"), "w") as f:
        f.write(writers.gearset_toml(g["gear"], "indepsim3", GENERATOR))
    rows = {}
    for e, r in zip(entries, res):
        rng = np.random.default_rng(e["noise_seed"])
        ch = {"sun_speed": sim.add_daq_noise(r["sun_rpm"], rng, NOISE_FRACTION),
              "carrier_speed": sim.add_daq_noise(r["carrier_rpm"], rng, NOISE_FRACTION),
              "acc_housing": sim.add_daq_noise(r["housing"], rng, NOISE_FRACTION, e["dc_housing"]),
              "acc_sun_planet0": sim.add_daq_noise(r["a_sp0"], rng, NOISE_FRACTION, e["dc_sp"]),
              "acc_planet0_ring": sim.add_daq_noise(r["a_pr0"], rng, NOISE_FRACTION, e["dc_pr"])}
        csv_rel = os.path.join(gname, "recordings", e["name"] + ".csv")
        desc = (f"test rig recording, {e['fs']:.0f} Hz DAQ, encoders {g['rig'].lines_sun}/{g['rig'].lines_carrier} lines, "
                f"housing accelerometer (IEPE)")
        writers.write_recording(os.path.join(outdir, csv_rel), r["time"], ch, e["rpm"], e["W"], r["sensor_angle_deg"],
                                e["fs"], GENERATOR, desc, encoder_lines={"sun_speed": g["rig"].lines_sun,
                                                                         "carrier_speed": g["rig"].lines_carrier})
        key = f"{gname}/{e['name']}"
        notes = []
        if e["effect"] == "backlash" and r["separated_fraction"] == 0 and r["coast_contact_fraction"] == 0:
            notes.append("no flank separated in this run: the larger play is never traversed, so the recording "
                         "is a healthy one up to noise (an unobservable effect)")
        if e["effect"] == "sensor_transfer_path":
            notes.append("a pure gain of the housing accelerometer channel (no change of the transfer-path shape)")
        if r["separated_fraction"] > 0:
            notes.append(f"a mesh was fully separated {100 * r['separated_fraction']:.2f} % of the recorded time")
        fc = carrier_hz(g["gear"], e["rpm"])
        rows[key] = dict(
            gearset=gname, name=e["name"], csv=csv_rel, sidecar=os.path.splitext(csv_rel)[0] + ".json",
            role=e["role"], effect=e["effect"], parameters=e["parameters"], faults=asdict(e["faults"]),
            operating_point=e["op"], input_speed_rpm=e["rpm"], input_power_W=e["W"], fs_Hz=e["fs"],
            duration_s=float(r["time"][-1] + 1.0 / e["fs"]), carrier_revolutions=round(e["duration_s"] * fc, 3),
            short_recording=e["short"], held_out=False, baseline=None, notes=notes,
            noise_seed=e["noise_seed"], noise_fraction=NOISE_FRACTION,
            dc_offset_fraction={"acc_housing": e["dc_housing"], "acc_sun_planet0": e["dc_sp"],
                                "acc_planet0_ring": e["dc_pr"]},
            sensor_angle_deg=r["sensor_angle_deg"], sensor_angle_wanted_deg=e["sensor_angle_deg"],
            diagnostics=dict(mean_sun_rpm=r["mean_sun_rpm"], mean_carrier_rpm=r["mean_carrier_rpm"],
                             mean_input_power_W=r["mean_P_in_W"], mean_brake_power_W=r["mean_P_brake_W"],
                             mean_friction_loss_W=r["mean_P_friction_W"],
                             fraction_of_time_a_mesh_separated=r["separated_fraction"],
                             fraction_of_time_a_coast_flank_in_contact=r["coast_contact_fraction"],
                             iso_line_load_N_mm=r["line_load_N_mm"],
                             mean_mesh_stiffness_sp_pr_N_m=r["mesh_stiffness_mean_N_m"],
                             motor_stall_torque_Nm=r["T_stall_Nm"], motor_noload_speed_rad_s=r["w_noload_rad_s"],
                             brake_coefficient_Nms2=r["brake_c_Nms2"]))
    binfo = dict(gearset=gname, cls="all", fs_Hz=sorted({e["fs"] for e in entries}),
                 **{k: v for k, v in info.items() if k not in ("states", "energy")})
    return rows, binfo, sim.describe(st)


def _job(args):
    gname, entries, outdir, warmup_s = args
    t0 = time.time()
    rows, binfo, desc = run_gearset(gname, entries, outdir, warmup_s)
    binfo["process_wall_s"] = time.time() - t0
    return gname, rows, binfo, desc


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--plan", default="main")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--quick", action="store_true", help="4 short recordings of one gear set (smoke test)")
    a = ap.parse_args(argv)
    t0 = time.time()
    if os.path.exists(a.out) and os.listdir(a.out):
        sys.exit(f"corpus.py: {a.out} exists and is not empty")
    os.makedirs(a.out, exist_ok=True)
    entries = plan_entries(a.quick, a.seed, a.plan)
    by_gs = {}
    for e in entries:
        by_gs.setdefault(e["gearset"], []).append(e)
    warm = 0.3 if a.quick else None
    jobs = [(g, es, a.out, warm) for g, es in sorted(by_gs.items())]
    print(f"indepsim3 corpus: {len(entries)} recordings of {len(jobs)} gear sets, {a.jobs} process(es)", flush=True)
    results = []
    if a.jobs > 1 and len(jobs) > 1:
        with cf.ProcessPoolExecutor(max_workers=min(a.jobs, len(jobs), 2)) as ex:
            results = list(ex.map(_job, jobs))
    else:
        results = [_job(j) for j in jobs]
    recs, batches, gsets = {}, [], {}
    for gname, rows, binfo, desc in results:
        recs.update(rows)
        batches.append(binfo)
        g = GEARSETS[gname]
        gsets[gname] = dict(gear=asdict(g["gear"]), rig=asdict(g["rig"]), derived=desc,
                            operating_points={k: dict(input_speed_rpm=v[0], input_power_W=v[1], fs_Hz=v[2])
                                              for k, v in g["ops"].items()})
    # the healthy baseline of each operating point
    for k, r in recs.items():
        base = [kk for kk, rr in recs.items() if rr["gearset"] == r["gearset"] and rr["role"] == "baseline"
                and rr["operating_point"] == r["operating_point"]]
        r["baseline"] = base[0] if base else None
    wall = time.time() - t0
    truth = dict(generator=GENERATOR, seed=a.seed, plan=a.plan, quick=a.quick, noise_fraction=NOISE_FRACTION,
                 gearsets=gsets, batches=batches, generation_wall_s=round(wall, 1), jobs=a.jobs,
                 notes=("roles: baseline (healthy, one per operating point, the reference of the others), control "
                        "(healthy), effect. parameters: the effect's true size (keys as scripts/indepsim/sizes.py "
                        "reads them). diagnostics: measured in the simulation over the recorded window."),
                 recordings=dict(sorted(recs.items())))
    with open(os.path.join(a.out, "truth.json"), "w") as f:
        json.dump(truth, f, indent=1)
        f.write("\n")
    with open(os.path.join(a.out, "corpus.log"), "w") as f:
        f.write(f"{' '.join(sys.argv)}\n")
        for b in batches:
            f.write(json.dumps(b) + "\n")
        for k, r in sorted(recs.items()):
            f.write(f"{k}: {r['role']:8s} {r['effect']:20s} {r['operating_point']} {r['input_speed_rpm']:.0f} rpm "
                    f"{r['input_power_W']:.0f} W {r['duration_s']:.3f} s ({r['carrier_revolutions']} carrier rev) "
                    f"{json.dumps(r['parameters'])}\n")
        f.write(f"generation wall time {wall:.1f} s ({a.jobs} process(es))\n")
    print(f"wrote {len(recs)} recordings to {a.out} in {wall:.1f} s wall ({a.jobs} process(es))", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
