#!/usr/bin/env python3
"""A corpus's recordings with the rig documented: what a rig's documentation would add to each gear set's TOML.

    /usr/bin/python3 scripts/indepsim2/document_rig.py SRC DST [--bodies | --machines-only]

SRC is an indepsim2 corpus (corpus.py). DST gets the same recordings (symlinked), truth.json and
observability.json, and per gear set a TOML of SRC's plus the rig's internals as sim.py's RIG_DEFAULTS
give them: the motor (inertia, input shaft, its PI speed loop with sim.py's gains), the brake (inertia,
output shaft; constant torque, planetwear's default load control), the bearings (the planets' radial and
tangential stiffness averaged: planetwear has one), and solver.level = "lateral_torsional". With
--bodies also the sun (with its hub), ring (with its housing) and carrier masses and inertias of
sim.lumped_parameters. With --machines-only only the machines, their shafts and the speed loop, at planetwear's
default (torsional) level: no bearings, no bodies (docs/diagnose-log.md, session 45: what of the documentation
the faults' signatures need). Damping is not stated (indepsim2's is Rayleigh; planetwear fits its own). Used for
docs/diagnose-log.md, sessions 41 and 45: an upper bound on what documentation buys, not a blind check.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sim  # noqa: E402


def rig_toml(gs, bodies, machines_only=False):
    par, geo, rig = sim.lumped_parameters(gs)
    Zs, Zr = gs["sun"]["Z"], gs["ring"]["Z"]
    # sim.Batch's loop: Kp = 2 0.8 w_bw J_eq, Ki = w_bw^2 J_eq, J_eq the train reflected to the motor.
    Jeq = par["Jm"] + par["Is"] + (par["Ic"] + par["Jb"] + gs["N"] * par["mp"] * par["rc"] ** 2) * (Zs / (Zs + Zr)) ** 2
    wbw = 2 * math.pi * rig["speed_loop_bw_Hz"]
    stage = {"input_inertia_kgm2": rig["motor_inertia"], "output_inertia_kgm2": rig["brake_inertia"]}
    if bodies:
        stage.update(sun_mass_kg=par["ms"], sun_inertia_kgm2=par["Is"], ring_mass_kg=par["mr"],
                     ring_inertia_kgm2=par["Ir"], carrier_mass_kg=par["mc"], carrier_inertia_kgm2=par["Ic"])
    tables = {
        "rig": {"input_control": '"speed_loop"', "input_shaft_stiffness_N_m_rad": rig["input_shaft_k"],
                "input_shaft_damping_N_m_s_rad": rig["input_shaft_c"],
                "input_speed_loop_proportional_N_m_s_rad": 2 * 0.8 * wbw * Jeq,
                "input_speed_loop_integral_N_m_rad": wbw ** 2 * Jeq,
                "output_shaft_stiffness_N_m_rad": rig["output_shaft_k"],
                "output_shaft_damping_N_m_s_rad": rig["output_shaft_c"]},
        "bearings": {"sun_N_m": rig["k_sun_bearing"], "carrier_N_m": rig["k_carrier_bearing"],
                     "planet_N_m": 0.5 * (rig["k_planet_radial"] + rig["k_planet_tangential"]),
                     "ring_N_m": rig["k_ring_mount"], "ring_torsional_N_m": rig["k_ring_torsion_per_rb2"]},
        "solver": {"level": '"lateral_torsional"'},
    }
    if machines_only:
        tables = {"rig": tables["rig"]}
    return stage, tables


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("src")
    ap.add_argument("dst")
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--bodies", action="store_true", help="also the sun, ring and carrier masses and inertias")
    mode.add_argument("--machines-only", action="store_true",
                      help="only the machines, shafts and speed loop, torsional level (no bearings, no bodies)")
    a = ap.parse_args()
    os.makedirs(a.dst, exist_ok=True)
    for f in ("truth.json", "observability.json"):
        if os.path.exists(os.path.join(a.src, f)) and not os.path.exists(os.path.join(a.dst, f)):
            os.symlink(os.path.abspath(os.path.join(a.src, f)), os.path.join(a.dst, f))
    for g in sorted(d for d in os.listdir(a.src) if os.path.exists(os.path.join(a.src, d, "gearset.toml"))):
        os.makedirs(os.path.join(a.dst, g), exist_ok=True)
        rec = os.path.join(a.dst, g, "recordings")
        if not os.path.exists(rec):
            os.symlink(os.path.abspath(os.path.join(a.src, g, "recordings")), rec)
        src_toml = os.path.join(a.src, g, "gearset.toml")
        text = open(src_toml).read()
        stage, tables = rig_toml(sim.read_gearset(src_toml), a.bodies, a.machines_only)
        lines = "".join(f"{k} = {v!r}\n" for k, v in stage.items())
        text = text.replace("[stage]\n", "[stage]\n# the rig as documented (scripts/indepsim2/document_rig.py)\n" + lines, 1)
        for name, kv in tables.items():
            text += f"\n[{name}]\n" + "".join(f"{k} = {v}\n" for k, v in kv.items())
        open(os.path.join(a.dst, g, "gearset.toml"), "w").write(text)
        print(f"wrote {os.path.join(a.dst, g, 'gearset.toml')}")


if __name__ == "__main__":
    main()
