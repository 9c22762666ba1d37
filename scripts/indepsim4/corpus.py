#!/usr/bin/python3
"""indepsim4 corpus: recordings of two gear sets on their test rigs, for `planetwear diagnose`.

    /usr/bin/python3 scripts/indepsim4/corpus.py -o DIR --seed S [--jobs 2] [--quick | --plan offpoint]

Writes DIR/<gearset>/gearset.toml (what the stage's drawing gives: gears, friction, design backlash),
DIR/<gearset>/recordings/rec_NN.csv + rec_NN.json (docs/recordings.md), DIR/truth.json (per recording:
role, effect, parameters, operating point, baseline, held_out, duration, carrier revolutions, noise,
sensor angle, diagnostics of the run) and DIR/corpus.log. One batch (all recordings of a gear set,
simulated together as numpy arrays) per process. The physics (the literature's k(t) model) is in
sim.py and README.md next to this file. File writers and truth layout follow scripts/indepsim3/corpus.py.
"""
import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import concurrent.futures as cf  # noqa: E402
import importlib.util  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from dataclasses import asdict  # noqa: E402

import numpy as np  # noqa: E402

# The sibling sim.py under a name of its own (other simulators' tests load their own `sim`).
if "indepsim4_sim" not in sys.modules:
    _SPEC = importlib.util.spec_from_file_location("indepsim4_sim",
                                                   os.path.join(os.path.dirname(os.path.abspath(__file__)), "sim.py"))
    sys.modules["indepsim4_sim"] = importlib.util.module_from_spec(_SPEC)
    _SPEC.loader.exec_module(sys.modules["indepsim4_sim"])
sim = sys.modules["indepsim4_sim"]
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "indepsim_common"))
import indepsim_writers as writers  # noqa: E402  (the file formats, shared with the other corpora)
import indepsim_effects as effects  # noqa: E402  (the effects' sizes, shared likewise)

GENERATOR = "indepsim4 (scripts/indepsim4/corpus.py)"
NOISE_FRACTION = 0.05
# Absolute noise floor of the accelerometer channels [m/s^2 RMS over the DAQ band]: a general-purpose
# 100 mV/g IEPE accelerometer with its DAQ, about 200 ug RMS broadband (session 66: without a floor, the
# housing channel of setC3's healthy recordings, whose ring force cancels, carried noise of 1e-12 m/s^2).
ACC_NOISE_FLOOR_M_S2 = 2e-3
WARMUP_S = 0.35

# ----------------------------------------------------------------------------------------------
# Gear sets, rigs, operating points (rpm, input power W, DAQ rate Hz)
# ----------------------------------------------------------------------------------------------

GEARSETS = {
    # 3 planets, in-phase meshes (Zs/N = 7, Zr/N = 27), module 2 mm
    "setC3": dict(
        gear=sim.GearSet("setC3", Zs=21, Zp=30, Zr=81, N=3, module_m=0.002, face_width_m=0.025,
                         friction=0.05, backlash_sp_m=30e-6, backlash_pr_m=30e-6),
        rig=sim.Rig(J_motor=0.05, J_load=0.3, f_input_shaft_Hz=40.0, f_output_shaft_Hz=220.0, shaft_zeta=0.03,
                    speed_loop_bw_Hz=10.0, tacho_bw_Hz=1500.0),
        ops={"op1": (600.0, 12000.0, 5000.0), "op2": (1200.0, 18000.0, 10000.0)},
        off_ops={"op3": (900.0, 15000.0, 10000.0), "op4": (750.0, 9000.0, 5000.0), "op5": (1500.0, 18000.0, 10000.0)}),
    # 4 planets, sequentially phased meshes (Zs/N = 6.75), module 3 mm. Session 66: was 28/17/62 with 5
    # planets, which planetwear refuses as involute interference (a standard internal ring's tips reach
    # 1.6 mm below the 17-tooth planet's base circle); this simulator has no interference check.
    "setD4": dict(
        gear=sim.GearSet("setD4", Zs=27, Zp=21, Zr=69, N=4, module_m=0.003, face_width_m=0.030,
                         friction=0.07, backlash_sp_m=40e-6, backlash_pr_m=40e-6),
        rig=sim.Rig(J_motor=0.08, J_load=0.5, f_input_shaft_Hz=50.0, f_output_shaft_Hz=180.0, shaft_zeta=0.03,
                    speed_loop_bw_Hz=12.0, tacho_bw_Hz=1200.0),
        ops={"op1": (600.0, 40000.0, 5000.0), "op2": (1200.0, 50000.0, 10000.0)},
        off_ops={"op3": (900.0, 45000.0, 10000.0), "op4": (750.0, 25000.0, 5000.0), "op5": (1500.0, 50000.0, 10000.0)}),
}

EFFECTS = ("sun_tooth_damage", "planet_tooth_damage", "ring_tooth_damage", "pin_error", "sun_runout",
           "carrier_runout", "torque_ripple", "worn_profile", "friction", "stiffness_level", "damping_level",
           "backlash", "sensor_transfer_path")
# effects that unload planets: at the higher-torque operating point (op1)
HIGH_TORQUE = ("pin_error", "sun_runout", "carrier_runout")


def carrier_hz(gs, rpm):
    return rpm / 60.0 * gs.Zs / (gs.Zs + gs.Zr)


WORN_SHAPE = ("parabolic in the distance from the pitch point: 0 there, worn_depth_m at the end of the path of "
              "contact farther from it; every mesh")


def effect_faults(effect, gs, rng):
    """A moderate size of each effect (the brief's ranges; scripts/indepsim_common/indepsim_effects.py)
    -> (Faults, truth parameters)."""
    kwargs, params = effects.draw_effect(effect, gs, rng, sim.MESH_ZETA, worn_truth=lambda d: dict(shape=WORN_SHAPE))
    return sim.Faults(**kwargs), params


# The offpoint plan: operating points none of the main plan's recordings has (so no calibration made
# on the main plan's baselines holds a reference there), a healthy control at each, and effects that
# change the mesh lines alike (stiffness, friction) or one part (a planet tooth, a sun tooth, a pin)
# or the input (torque ripple). Diagnosed with the main plan's calibration of the same rig.
OFFPOINT_EFFECTS = ("pin_error", "friction", "planet_tooth_damage", "stiffness_level", "torque_ripple",
                    "sun_tooth_damage")  # in turn at op3, op4, op5: the pin error at the higher torque


def plan_entries(quick, seed, plan="main"):
    """Every recording of the corpus: list of dicts (gearset, role, effect, faults, parameters, op, duration)."""
    rng = np.random.default_rng(seed)
    entries = []
    for gname in sorted(GEARSETS):
        g = GEARSETS[gname]
        gs = g["gear"]
        ops = dict(g["ops"], **g["off_ops"]) if plan == "offpoint" else g["ops"]
        if plan == "offpoint":
            off = sorted(g["off_ops"])
            spec = [("control", "none", op, 2.5) for op in off]
            spec += [("effect", e, off[j % len(off)], float(rng.choice([2.5, 3.0])))
                     for j, e in enumerate(OFFPOINT_EFFECTS)]
        elif quick:
            if gname != "setC3":
                continue
            spec = [("baseline", "none", "op2", 0.6), ("control", "none", "op2", 0.6),
                    ("effect", "sun_tooth_damage", "op2", 0.6)]
        else:
            spec = [("baseline", "none", "op1", 3.0), ("baseline", "none", "op2", 3.0),
                    ("control", "none", "op2", 2.5)]
            other = [e for e in EFFECTS if e not in HIGH_TORQUE]
            rng.shuffle(other)
            for j, e in enumerate(other):
                spec.append(("effect", e, "op1" if j % 2 == 0 else "op2", float(rng.choice([2.5, 3.0]))))
            for e in HIGH_TORQUE:
                spec.append(("effect", e, "op1", float(rng.choice([2.5, 3.0]))))
        names = rng.permutation(len(spec)) + 1
        for (role, effect, opn, dur), num in zip(spec, names):
            rpm, P, fs = ops[opn]
            if effect == "none":
                faults, params = sim.Faults(), {}
            else:
                faults, params = effect_faults(effect, gs, rng)
            entries.append(dict(gearset=gname, name=f"rec_{num:02d}", role=role, effect=effect, faults=faults,
                                parameters=params, op=opn, rpm=rpm, W=P, fs=fs, duration_s=dur,
                                held_out=(role == "control"),
                                sensor_angle_deg=float(5 * rng.integers(72)),
                                noise_seed=int(rng.integers(2 ** 31)),
                                dc_housing=float(rng.choice([-1, 1]) * rng.uniform(0.1, 0.4)),
                                dc_sp=float(rng.choice([-1, 1]) * rng.uniform(0.1, 0.4)),
                                dc_pr=float(rng.choice([-1, 1]) * rng.uniform(0.1, 0.4))))
    return entries


# ----------------------------------------------------------------------------------------------
# Writers (format as scripts/indepsim3/corpus.py writes it)
# ----------------------------------------------------------------------------------------------

# gearset_toml, COLUMNS, write_recording: scripts/indepsim_common/indepsim_writers.py (`writers` above),
# shared with the other corpora: the file formats, not the physics.


# ----------------------------------------------------------------------------------------------
# Running
# ----------------------------------------------------------------------------------------------

def make_channels(r, e):
    rng = np.random.default_rng(e["noise_seed"])
    return {"sun_speed": sim.add_daq_noise(r["sun_rpm"], rng, NOISE_FRACTION),
            "carrier_speed": sim.add_daq_noise(r["carrier_rpm"], rng, NOISE_FRACTION),
            "acc_housing": sim.add_daq_noise(r["housing"], rng, NOISE_FRACTION, e["dc_housing"], ACC_NOISE_FLOOR_M_S2),
            "acc_sun_planet0": sim.add_daq_noise(r["a_sp0"], rng, NOISE_FRACTION, e["dc_sp"], ACC_NOISE_FLOOR_M_S2),
            "acc_planet0_ring": sim.add_daq_noise(r["a_pr0"], rng, NOISE_FRACTION, e["dc_pr"], ACC_NOISE_FLOOR_M_S2)}


def run_gearset(gname, entries, outdir, warmup_s=WARMUP_S, log=None):
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
        f.write(writers.gearset_toml(g["gear"], "indepsim4", GENERATOR))
    rows = {}
    for e, r in zip(entries, res):
        ch = make_channels(r, e)
        csv_rel = os.path.join(gname, "recordings", e["name"] + ".csv")
        desc = (f"test rig recording, {e['fs']:.0f} Hz DAQ, analogue tachometers ({g['rig'].tacho_bw_Hz:.0f} Hz), "
                f"housing accelerometer (radial)")
        writers.write_recording(os.path.join(outdir, csv_rel), r["time"], ch, e["rpm"], e["W"], r["sensor_angle_deg"],
                                e["fs"], GENERATOR, desc)
        key = f"{gname}/{e['name']}"
        notes = []
        if e["effect"] == "backlash" and r["backlash_fraction"] == 0 and r["coast_contact_fraction"] == 0:
            notes.append("no mesh left its drive flank in this run: the larger play is never traversed, so the "
                         "recording is a healthy one up to noise (an unobservable effect)")
        if e["effect"] == "sensor_transfer_path":
            notes.append("a pure gain of the housing accelerometer channel")
        if r["backlash_fraction"] > 0:
            notes.append(f"a mesh was in its backlash (or coast contact) {100 * r['backlash_fraction']:.3f} % of the "
                         "recorded steps")
        fc = carrier_hz(g["gear"], e["rpm"])
        rows[key] = dict(
            gearset=gname, name=e["name"], csv=csv_rel, sidecar=os.path.splitext(csv_rel)[0] + ".json",
            role=e["role"], effect=e["effect"], parameters=e["parameters"], faults=asdict(e["faults"]),
            operating_point=e["op"], input_speed_rpm=e["rpm"], input_power_W=e["W"], fs_Hz=e["fs"],
            duration_s=float(r["time"][-1] + 1.0 / e["fs"]), carrier_revolutions=round(e["duration_s"] * fc, 3),
            short_recording=False, held_out=e["held_out"], baseline=None, notes=notes,
            noise_seed=e["noise_seed"], noise_fraction=NOISE_FRACTION, acc_noise_floor_m_s2=ACC_NOISE_FLOOR_M_S2,
            dc_offset_fraction={"acc_housing": e["dc_housing"], "acc_sun_planet0": e["dc_sp"],
                                "acc_planet0_ring": e["dc_pr"]},
            sensor_angle_deg=r["sensor_angle_deg"], sensor_angle_abs_deg=r["sensor_angle_abs_deg"],
            diagnostics=dict(mean_sun_rpm=r["mean_sun_rpm"], mean_carrier_rpm=r["mean_carrier_rpm"],
                             mean_input_power_W=r["mean_P_in_W"], mean_output_power_W=r["mean_P_out_W"],
                             mean_friction_loss_W=r["mean_P_friction_W"], mean_damping_loss_W=r["mean_P_damping_W"],
                             fraction_of_steps_a_mesh_in_backlash=r["backlash_fraction"],
                             fraction_of_steps_a_coast_flank_in_contact=r["coast_contact_fraction"],
                             rms_noise_free={k: float(np.sqrt(np.mean((r[k] - np.mean(r[k])) ** 2)))
                                             for k in ("a_sp0", "a_pr0", "housing")}))
    binfo = dict(gearset=gname, fs_Hz=sorted({e["fs"] for e in entries}), **info)
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
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--quick", action="store_true", help="3 short recordings of one gear set (smoke test)")
    ap.add_argument("--plan", choices=("main", "offpoint"), default="main",
                    help="offpoint: healthy controls and six effects at three operating points the main plan "
                         "has no recording at, to be diagnosed with the main plan's calibration of the same rig")
    a = ap.parse_args(argv)
    t0 = time.time()
    if os.path.exists(a.out) and os.listdir(a.out):
        sys.exit(f"corpus.py: {a.out} exists and is not empty")
    os.makedirs(a.out, exist_ok=True)
    entries = plan_entries(a.quick, a.seed, a.plan)
    by_gs = {}
    for e in entries:
        by_gs.setdefault(e["gearset"], []).append(e)
    warm = 0.3 if a.quick else WARMUP_S
    jobs = [(g, es, a.out, warm) for g, es in sorted(by_gs.items())]
    print(f"indepsim4 corpus: {len(entries)} recordings of {len(jobs)} gear sets, {a.jobs} process(es)", flush=True)
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
                                              for k, v in dict(g["ops"], **g["off_ops"]).items()})
    for k, r in recs.items():
        base = [kk for kk, rr in recs.items() if rr["gearset"] == r["gearset"] and rr["role"] == "baseline"
                and rr["operating_point"] == r["operating_point"]]
        r["baseline"] = base[0] if base else None
    wall = time.time() - t0
    truth = dict(generator=GENERATOR, seed=a.seed, plan=a.plan, quick=a.quick, noise_fraction=NOISE_FRACTION, acc_noise_floor_m_s2=ACC_NOISE_FLOOR_M_S2,
                 gearsets=gsets, batches=batches, generation_wall_s=round(wall, 1), jobs=a.jobs,
                 notes=("roles: baseline (healthy, one per operating point, the reference of the others), control "
                        "(healthy, held out), effect. parameters: the effect's true size (keys as "
                        "scripts/indepsim/sizes.py reads them). diagnostics: measured in the simulation over the "
                        "recorded window. Physics: the literature's k(t) lumped model (scripts/indepsim4/README.md)."),
                 recordings=dict(sorted(recs.items())))
    with open(os.path.join(a.out, "truth.json"), "w") as f:
        json.dump(truth, f, indent=1, default=float)
        f.write("\n")
    with open(os.path.join(a.out, "corpus.log"), "w") as f:
        f.write(f"{' '.join(sys.argv)}\n")
        for b in batches:
            f.write(json.dumps(b, default=float) + "\n")
        for k, r in sorted(recs.items()):
            f.write(f"{k}: {r['role']:8s} {r['effect']:20s} {r['operating_point']} {r['input_speed_rpm']:.0f} rpm "
                    f"{r['input_power_W']:.0f} W {r['duration_s']:.3f} s ({r['carrier_revolutions']} carrier rev) "
                    f"held_out={r['held_out']} {json.dumps(r['parameters'])}\n")
        f.write(f"generation wall time {wall:.1f} s ({a.jobs} process(es))\n")
    print(f"wrote {len(recs)} recordings to {a.out} in {wall:.1f} s wall ({a.jobs} process(es))", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
