#!/usr/bin/env python3
"""Build a corpus of synthetic test recordings for `planetwear diagnose`.

Each recording is made by `planetwear synth`: the stage of GEARSET (default
config/seed.toml) at one operating point, with one concealed effect (or none,
for the control cases), measurement noise of 5-10 % of each channel's RMS and
a DC offset on the accelerometers. The answers are kept apart from the
recordings:

    OUT/gearset.toml              the nominal gear set the diagnosis is given
    OUT/recordings/rec_NN.csv     samples (time [s], speeds, accelerations, tacho)
    OUT/recordings/rec_NN.json    sidecar: operating point and columns only
    OUT/truth.json                per recording: effect, its parameters, the
                                  --set overrides, noise, offsets, sensor angle
    OUT/corpus.log                the synth commands and their wall times

Give the diagnosis OUT/gearset.toml and OUT/recordings/ only.

Effects (two variants each, differing in parameters and operating point):
damaged sun / planet / ring tooth (stiffness factor 0.55-0.8), planet pin
error, sun and carrier eccentricity (runout), mesh-stiffness level
(stiffness.scale 0.8 / 1.25), mesh damping (0.02 / 0.1), friction (0.05 /
0.15), input torque ripple, pre-existing worn profile (0.5 / 2 um), backlash
(19 500 / 21 000 rpm, near the primary mesh resonance, where the teeth
separate), housing transfer path
(window width / gain off by 2x); plus five control cases without effect.
Magnitudes of the geometric errors are kept below the static mesh deflection
at their load (2.7-7 um at 10-20 kW): larger errors with zero backlash jam
the unloaded planet against its coast flanks, which no real gearbox does
(docs/recordings.md, "Corpus").

Usage:
    scripts/make_corpus.py -o corpus            # full corpus (~31 recordings)
    scripts/make_corpus.py -o corpus-quick --quick   # 6 short recordings (ctest)
    scripts/make_corpus.py -o corpus-bl --only backlash,none   # a subset of the effects
    scripts/make_corpus.py -o corpus --planetwear build/apps/planetwear --jobs 2 --seed 7

Runs with Debian's /usr/bin/python3 (standard library only).
"""

import os
import sys


def ensure_system_python():
    """Re-exec under Debian's /usr/bin/python3 (like scripts/pwplot.py) so the
    script behaves the same whichever python3 is first on PATH."""
    system_python = "/usr/bin/python3"
    if os.path.realpath(sys.executable) != os.path.realpath(system_python) and os.path.exists(system_python) \
            and not os.environ.get("PW_CORPUS_REEXEC"):
        os.environ["PW_CORPUS_REEXEC"] = "1"
        os.execv(system_python, [system_python] + sys.argv)


ensure_system_python()

import argparse  # noqa: E402
import json  # noqa: E402
import random  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import time  # noqa: E402
import tomllib  # noqa: E402
from concurrent.futures import ThreadPoolExecutor  # noqa: E402
from pathlib import Path  # noqa: E402

REPO = Path(__file__).resolve().parent.parent

# Operating points (input speed [rpm], input power [W]). Every effect and the
# controls share them, so the operating point says nothing about the effect.
# 10-20 kW load the seed gears to 2.7-7 um static deflection. F and G lie near
# the primary mesh resonance (mesh frequency 5.35-5.42 kHz), where the dynamic
# mesh force exceeds the static one and teeth with play separate: the only
# regime in which backlash shows (sun-planet acceleration RMS with 20 um play
# vs none, `planetwear simulate --set contact.backlash_*=...`: +12 % at 19 500
# rpm / 2 kW, +14 % at 19 250 rpm / 5 kW (50 um); at the old points 1800 / 2200 rpm,
# 1 kW it was 0.05 % and 0.2 %, far below the noise, measured 2026-11-25).
OPERATING = {
    "A": (400.0, 10000.0),
    "B": (200.0, 10000.0),
    "C": (300.0, 20000.0),
    "F": (19500.0, 2000.0),
    "G": (19250.0, 5000.0),
}
QUICK_OPERATING = {"Q1": (800.0, 20000.0), "Q2": (1200.0, 20000.0)}

# Recording settings per operating point (not effects; also in truth.json):
#  * a fixed time step, so the sample rate depends on the speed only (the
#    automatic step follows the highest natural frequency, i.e. the stiffness);
#  * a common start time (--start-mesh-cycle W), so the start of the time
#    axis does not tell how long the warm-up took;
#  * at 200-1200 rpm a warm-up to periodicity 1e-3 (the diagnosis's own model
#    warms up to 1e-4 or tighter): the recording is of steady operation. With
#    0.05 a slowly decaying start-up transient stays in the file, and the
#    diagnosis rightly calls the controls "unexplained residual" (chi2 2440 vs
#    bound 2427 on the quick corpus's 800 rpm control, 2396 <= 2429 at 1e-3);
#  * at 19 500 / 21 000 rpm: warm up for up to 380 mesh cycles and start the
#    file at mesh cycle 1500 (0.26-0.28 s), when the load-torque update's speed
#    transient has died out; sample at 50 kHz (decimation by 8), 8.6 x the
#    mesh frequency; record 40 carrier revolutions (0.6 s: 3.5 would be 52 ms,
#    82 lines per channel, too few to tell a softened mesh from a stiffness level).
SLOW = {"sets": ["solver.time_step_s=2.5e-6", "solver.periodicity_tolerance=1e-3"], "start_mesh_cycle": 120}
FAST = {"sets": ["solver.time_step_s=2.5e-6", "solver.warmup_max_mesh_cycles=380"], "start_mesh_cycle": 1500,
        "decimate": 8, "carrier_revolutions": 40}
# The quick set's 800/1200 rpm: 120 mesh cycles are 0.03-0.05 s, less than a pinned planet's
# warm-up may take (up to the 400-cycle cap); start after it.
QUICK = {"sets": SLOW["sets"], "start_mesh_cycle": 450}
SETTINGS = {"A": SLOW, "B": SLOW, "C": SLOW, "F": FAST, "G": FAST, "Q1": QUICK, "Q2": QUICK}


BACKLASH_NOTE = ("the teeth separate by less than 0.1 um, so any play beyond that acts alike: only a lower "
                 "limit of the size is identifiable (docs/diagnose.md)")
RIPPLE_NOTE = ("the sun speed swings by about the ripple fraction at its order (no input inertia); the mean speed "
               "holds the nominal (400 rpm case: 399.94 rpm, 300 rpm case: 300.004 rpm, measured 2026-11-24)")


def pin_case(n, which, offset_m):
    """(--set list, truth parameters) for a pin error of offset_m on planet `which` (modulo the
    planet count), 0 on the others."""
    p = [0.0] * n["planets"]
    p[which % n["planets"]] = offset_m
    return ["imperfections.pin_error_m=[" + ",".join(f"{v:g}" for v in p) + "]"], {"pin_error_m": p}


def tooth_case(n, body, tooth, factor, planet=0):
    """(--set list, truth parameters) for a damaged tooth, indices modulo the gear set's counts."""
    tooth %= n[body]
    planet %= n["planets"]
    truth = {"tooth": tooth, "stiffness_factor": factor}
    if body == "planet":
        truth = {"planet": planet, **truth}
    return [teeth(body, tooth, factor, planet)], truth


def teeth(body, tooth, factor, planet=0):
    t = f'{{body="{body}",tooth={tooth},stiffness_factor={factor}' + (f",planet={planet}" if body == "planet" else "")
    return f"imperfections.teeth=[{t}}}]"


# (effect, operating point, --set overrides, parameters for truth.json). Planet and tooth
# indices are taken modulo the gear set's counts (n), so any gear set gets the same kinds
# of cases; for the seed set (3 planets; 21, 30, 81 teeth) they are as written.
def full_cases(n):
    return [
        ("sun_tooth_damage", "A", *tooth_case(n, "sun", 5, 0.6)),
        ("sun_tooth_damage", "B", *tooth_case(n, "sun", 14, 0.75)),
        ("planet_tooth_damage", "C", *tooth_case(n, "planet", 7, 0.55, planet=1)),
        ("planet_tooth_damage", "A", *tooth_case(n, "planet", 20, 0.8, planet=2)),
        ("ring_tooth_damage", "B", *tooth_case(n, "ring", 30, 0.6)),
        ("ring_tooth_damage", "C", *tooth_case(n, "ring", 61, 0.7)),
        ("planet_pin_error", "B", *pin_case(n, 1, 3e-6)),
        ("planet_pin_error", "C", *pin_case(n, 2, 5e-6)),
        ("sun_eccentricity", "A", ["imperfections.sun_eccentricity_m=1.5e-6",
                                   "imperfections.sun_eccentricity_phase_rad=0.7"],
         {"sun_eccentricity_m": 1.5e-6, "sun_eccentricity_phase_rad": 0.7}),
        ("sun_eccentricity", "C", ["imperfections.sun_eccentricity_m=5e-6",
                                   "imperfections.sun_eccentricity_phase_rad=2.0"],
         {"sun_eccentricity_m": 5e-6, "sun_eccentricity_phase_rad": 2.0}),
        ("carrier_eccentricity", "B", ["imperfections.carrier_eccentricity_m=2e-6",
                                       "imperfections.carrier_eccentricity_phase_rad=1.0"],
         {"carrier_eccentricity_m": 2e-6, "carrier_eccentricity_phase_rad": 1.0}),
        ("carrier_eccentricity", "C", ["imperfections.carrier_eccentricity_m=3e-6",
                                       "imperfections.carrier_eccentricity_phase_rad=4.0"],
         {"carrier_eccentricity_m": 3e-6, "carrier_eccentricity_phase_rad": 4.0}),
        ("mesh_stiffness_level", "A", *level_case(n, "stiffness_scale", "stiffness.scale", 0.8)),
        ("mesh_stiffness_level", "C", *level_case(n, "stiffness_scale", "stiffness.scale", 1.25)),
        ("mesh_damping_level", "A", *level_case(n, "mesh_damping_ratio", "contact.mesh_damping_ratio", 0.4)),
        ("mesh_damping_level", "B", *level_case(n, "mesh_damping_ratio", "contact.mesh_damping_ratio", 2.0)),
        ("friction_coefficient", "B", *level_case(n, "friction_coefficient", "contact.friction_coefficient", 0.5)),
        ("friction_coefficient", "A", *level_case(n, "friction_coefficient", "contact.friction_coefficient", 1.5)),
        ("input_torque_ripple", "C", ["imperfections.torque_ripple_fraction=0.05", "imperfections.torque_ripple_order=1"],
         {"torque_ripple_fraction": 0.05, "torque_ripple_order": 1, "note": RIPPLE_NOTE}),
        ("input_torque_ripple", "A", ["imperfections.torque_ripple_fraction=0.1", "imperfections.torque_ripple_order=2"],
         {"torque_ripple_fraction": 0.1, "torque_ripple_order": 2, "note": RIPPLE_NOTE}),
        ("worn_profile", "A", ["imperfections.worn_profile_depth_m=0.5e-6"], {"worn_profile_depth_m": 0.5e-6}),
        ("worn_profile", "B", ["imperfections.worn_profile_depth_m=2e-6"], {"worn_profile_depth_m": 2e-6}),
        ("backlash", "F", ["contact.backlash_sun_planet_m=2e-5", "contact.backlash_planet_ring_m=2e-5"],
         {"backlash_sun_planet_m": 2e-5, "backlash_planet_ring_m": 2e-5, "note": BACKLASH_NOTE}),
        ("backlash", "G", ["contact.backlash_sun_planet_m=5e-5", "contact.backlash_planet_ring_m=5e-5"],
         {"backlash_sun_planet_m": 5e-5, "backlash_planet_ring_m": 5e-5, "note": BACKLASH_NOTE}),
        sensor_case(n, "C", "window_width_rad", 2.0),
        sensor_case(n, "B", "gain_m_s2_per_N", 0.5),
    ] + [("none", op, [], {}) for op in "ABCFG"]


def sensor_case(n, op, key, factor):
    sets, truth = level_case(n, key, "sensor." + key, factor)
    return ("sensor_transfer_path", op, sets, {**truth, "nominal_" + key: n[key]})


def quick_cases(n):
    return [
        ("none", "Q1", [], {}),
        ("none", "Q2", [], {}),
        ("sun_tooth_damage", "Q1", *tooth_case(n, "sun", 5, 0.6)),
        ("planet_pin_error", "Q2", *pin_case(n, 1, 1e-6)),
        ("mesh_stiffness_level", "Q2", *level_case(n, "stiffness_scale", "stiffness.scale", 0.8)),
        ("worn_profile", "Q1", ["imperfections.worn_profile_depth_m=1e-6"], {"worn_profile_depth_m": 1e-6}),
    ]


def nominal(gearset):
    """Planet and tooth counts and the nominal values the level cases scale, of a gear set
    (TOML as a dict; a missing key takes its default, config/seed.toml)."""
    stage, contact = gearset.get("stage", {}), gearset.get("contact", {})
    sensor = gearset.get("sensor", {})
    return {"planets": stage.get("planet_count", 3), "sun": stage.get("sun", {}).get("teeth", 21),
            "planet": stage.get("planet", {}).get("teeth", 30), "ring": stage.get("ring", {}).get("teeth", 81),
            "stiffness_scale": gearset.get("stiffness", {}).get("scale", 1.0),
            "mesh_damping_ratio": contact.get("mesh_damping_ratio", 0.05),
            "friction_coefficient": contact.get("friction_coefficient", 0.1),
            "window_width_rad": sensor.get("window_width_rad", 0.5),
            "gain_m_s2_per_N": sensor.get("gain_m_s2_per_N", 1e-3)}


def level_case(n, key, setting, factor):
    """(--set list, truth parameters) for a nuisance-level effect: the nominal value times factor."""
    v = float(f"{n[key] * factor:.6g}")
    return [f"{setting}={v!r}"], {key: v}

# Decimation by 40 (default; SETTINGS may override): ~10 kHz, 12 x the mesh frequency at 400 rpm.
DECIMATE = 40
CARRIER_REVOLUTIONS = 3.5  # halves of one whole carrier revolution (R = 1; docs/diagnose.md §2)
QUICK_CARRIER_REVOLUTIONS = 3.2


def find_planetwear(given):
    if given:
        return str(Path(given).resolve())
    for candidate in sorted(REPO.glob("build*/apps/planetwear")):
        if os.access(candidate, os.X_OK):
            return str(candidate)
    found = shutil.which("planetwear")
    if found:
        return found
    sys.exit("make_corpus: no planetwear executable; build it (cmake --build build) or pass --planetwear PATH")


def carrier_revolution_s(gearset, rpm):
    n = nominal(gearset)
    zs, zr = n["sun"], n["ring"]
    return 60.0 / (rpm * zs / (zs + zr))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--output", required=True, help="corpus directory (created; must not hold recordings yet)")
    ap.add_argument("--gearset", default=str(REPO / "config" / "seed.toml"),
                    help="nominal gear set (TOML); copied to OUTPUT/gearset.toml")
    ap.add_argument("--planetwear", help="the planetwear executable (default: build*/apps/planetwear, then PATH)")
    ap.add_argument("--quick", action="store_true", help="6 short recordings (for ctest)")
    ap.add_argument("--jobs", type=int, default=2, help="synth runs in parallel (default 2)")
    ap.add_argument("--seed", type=int, default=1, help="seed of noise levels, offsets, angles and naming")
    ap.add_argument("--force", action="store_true", help="replace an existing corpus in OUTPUT")
    ap.add_argument("--only", default="",
                    help="comma-separated effects to keep (e.g. backlash,none); default: every case")
    args = ap.parse_args()

    out = Path(args.output)
    rec_dir = out / "recordings"
    if rec_dir.exists() and any(rec_dir.iterdir()):
        if not args.force:
            sys.exit(f"make_corpus: {rec_dir} is not empty; use --force to replace it")
        shutil.rmtree(rec_dir)
    rec_dir.mkdir(parents=True, exist_ok=True)
    planetwear = find_planetwear(args.planetwear)
    gearset_text = Path(args.gearset).read_text()
    gearset = tomllib.loads(gearset_text)
    (out / "gearset.toml").write_text(gearset_text)

    cases = (quick_cases if args.quick else full_cases)(nominal(gearset))
    if args.only:
        keep = {e.strip() for e in args.only.split(",") if e.strip()}
        known = {c[0] for c in cases}
        if not keep <= known:
            sys.exit(f"make_corpus: --only: unknown effect(s) {sorted(keep - known)}; allowed: {sorted(known)}")
    else:
        keep = None
    operating = QUICK_OPERATING if args.quick else OPERATING
    revolutions = QUICK_CARRIER_REVOLUTIONS if args.quick else CARRIER_REVOLUTIONS
    rng = random.Random(args.seed)
    order = list(range(len(cases)))
    rng.shuffle(order)  # recording names say nothing about the effect
    jobs = []
    for number, index in enumerate(order, start=1):
        effect, op, sets, parameters = cases[index]
        rpm, power = operating[op]
        name = f"rec_{number:02d}"
        job = {
            "name": name,
            "effect": effect,
            "parameters": parameters,
            "set": sets,
            "speed_rpm": rpm,
            "power_W": power,
            "seconds": round(SETTINGS[op].get("carrier_revolutions", revolutions) * carrier_revolution_s(gearset, rpm),
                             6),
            "noise_fraction_of_rms": round(rng.uniform(0.05, 0.10), 4),
            "dc_offset_fraction_of_rms": round(rng.choice([-1, 1]) * rng.uniform(0.1, 0.5), 4),
            "sensor_angle_deg": float(rng.randrange(0, 360, 5)),
            "noise_seed": rng.randrange(1, 2**31),
            "tacho": rng.random() < 0.5,
        }
        job["command"] = [planetwear, "synth", "-q", "-c", str(out / "gearset.toml"),
                          "--speed-rpm", repr(rpm), "--power-w", repr(power),
                          "--seconds", repr(job["seconds"]), "--noise", repr(job["noise_fraction_of_rms"]),
                          "--dc-offset", repr(job["dc_offset_fraction_of_rms"]), "--seed", str(job["noise_seed"]),
                          "--sensor-angle-deg", repr(job["sensor_angle_deg"]),
                          "--decimate", str(SETTINGS[op].get("decimate", DECIMATE)),
                          "--start-mesh-cycle", str(SETTINGS[op]["start_mesh_cycle"])]
        job["command"] += ["--tacho"] if job["tacho"] else []
        job["recording_settings"] = SETTINGS[op]
        for s in SETTINGS[op]["sets"] + sets:
            job["command"] += ["--set", s]
        job["command"] += ["-o", str(rec_dir / f"{name}.csv")]
        if keep is None or effect in keep:  # drawn for every case: a subset's recordings equal the full corpus's
            jobs.append(job)

    def run(job):
        t0 = time.monotonic()
        p = subprocess.run(job["command"], capture_output=True, text=True)
        job["wall_s"] = round(time.monotonic() - t0, 2)
        job["returncode"] = p.returncode
        job["stderr"] = p.stderr.strip()
        print(f"{job['name']}: {job['wall_s']:6.2f} s  {'ok' if p.returncode == 0 else 'FAILED'}", flush=True)
        return job

    t0 = time.monotonic()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        done = list(pool.map(run, jobs))
    wall = time.monotonic() - t0

    with open(out / "corpus.log", "w") as log:
        for job in done:
            log.write(" ".join(job["command"]) + f"\n  -> exit {job['returncode']}, {job['wall_s']} s\n")
            if job["stderr"]:
                log.write("  " + job["stderr"].replace("\n", "\n  ") + "\n")
    failed = [j for j in done if j["returncode"] != 0]
    truth = {
        "description": "answers for the recordings in recordings/ (keep away from the diagnosis)",
        "gearset": "gearset.toml",
        "settings": {"decimate_default": DECIMATE, "carrier_revolutions": revolutions, "seed": args.seed,
                     "quick": args.quick},
        "recordings": {
            j["name"]: {k: j[k] for k in ("effect", "parameters", "set", "speed_rpm", "power_W", "seconds",
                                          "noise_fraction_of_rms", "dc_offset_fraction_of_rms", "sensor_angle_deg",
                                          "noise_seed", "tacho", "recording_settings", "wall_s")}
            for j in sorted(done, key=lambda j: j["name"])
        },
    }
    (out / "truth.json").write_text(json.dumps(truth, indent=2) + "\n")
    print(f"make_corpus: {len(done) - len(failed)}/{len(done)} recordings in {rec_dir}, truth in "
          f"{out / 'truth.json'}, {wall:.1f} s wall with {args.jobs} jobs")
    if failed:
        for j in failed:
            print(f"make_corpus: {j['name']} ({j['effect']}) failed:\n{j['stderr']}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
