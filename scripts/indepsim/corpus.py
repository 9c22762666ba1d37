#!/usr/bin/env python3
"""Recording corpus of the independent simulator (scripts/indepsim/sim.py).

    /usr/bin/python3 scripts/indepsim/corpus.py -o DIR [--quick] [--jobs N] [--seed S]

Writes, per gear set G:
  DIR/G/gearset.toml                 the rig documentation (planetwear TOML keys: geometry,
                                     tooth counts, module, face width, friction, design backlash)
  DIR/G/recordings/rec_NN.csv|json   recordings + sidecars (docs/recordings.md format)
and, outside the recordings, DIR/truth.json (effect, parameters, operating point, duration,
held-out flag, baseline of the same operating point, measured RMS ratios vs that baseline)
and DIR/corpus.log. Names are shuffled per gear set (seeded).
"""
import argparse
import dataclasses
import json
import math
import multiprocessing
import os
import random
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sim  # noqa: E402

G0 = 9.80665

# ----------------------------------------------------------------------------
# Gear sets (what the rig documentation says) and the corpus plan
# ----------------------------------------------------------------------------


def gearsets():
    seed = sim.GearSet("seed3p", 3, sim.Gear(21, 0.003, face_width_m=0.05), sim.Gear(30, 0.003, face_width_m=0.05),
                       sim.Gear(81, 0.003, face_width_m=0.05), friction_coefficient=0.06,
                       backlash_sun_planet_m=10e-6, backlash_planet_ring_m=10e-6)
    four = sim.GearSet("four4p", 4, sim.Gear(20, 0.002, face_width_m=0.03), sim.Gear(30, 0.002, face_width_m=0.03),
                       sim.Gear(80, 0.002, face_width_m=0.03), friction_coefficient=0.06,
                       backlash_sun_planet_m=8e-6, backlash_planet_ring_m=8e-6)
    # Added in session 37 for a final check no development run has seen (--plan fresh): five
    # planets, (Zs + Zr) / 5 = 18 (equal spacing), other module and face width.
    five = sim.GearSet("fresh5p", 5, sim.Gear(25, 0.0025, face_width_m=0.04), sim.Gear(20, 0.0025, face_width_m=0.04),
                       sim.Gear(65, 0.0025, face_width_m=0.04), friction_coefficient=0.05,
                       backlash_sun_planet_m=12e-6, backlash_planet_ring_m=12e-6)
    # Added in session 38 for the next final check (--plan fresh2), after fresh5p had been seen:
    # three planets again but another tooth set, module, face width, friction and backlash;
    # (Zs + Zr) / 3 = 36 (equal spacing).
    three = sim.GearSet("fresh3p", 3, sim.Gear(24, 0.00225, face_width_m=0.035), sim.Gear(30, 0.00225, face_width_m=0.035),
                        sim.Gear(84, 0.00225, face_width_m=0.035), friction_coefficient=0.07,
                        backlash_sun_planet_m=15e-6, backlash_planet_ring_m=15e-6)
    # Added in session 39 for the next final check (--plan fresh3), after fresh3p had been seen:
    # four planets with another tooth set (Zs 21 / Zp 27 / Zr 75, (Zs + Zr) / 4 = 24), a coarser
    # module, friction and backlash no other set uses.
    four_b = sim.GearSet("fresh4p", 4, sim.Gear(21, 0.00275, face_width_m=0.032),
                         sim.Gear(27, 0.00275, face_width_m=0.032), sim.Gear(75, 0.00275, face_width_m=0.032),
                         friction_coefficient=0.055, backlash_sun_planet_m=10e-6, backlash_planet_ring_m=10e-6)
    # Added in session 58 for the next final check (--plan fresh4), after fresh4p had been seen in
    # development: six planets (Zs 30 / Zp 21 / Zr 72, (Zs + Zr) / 6 = 17), module 2.5 mm, a
    # friction and backlash no other set uses.
    six = sim.GearSet("fresh6p", 6, sim.Gear(30, 0.0025, face_width_m=0.036), sim.Gear(21, 0.0025, face_width_m=0.036),
                      sim.Gear(72, 0.0025, face_width_m=0.036), friction_coefficient=0.065,
                      backlash_sun_planet_m=9e-6, backlash_planet_ring_m=9e-6)
    # Added in session 59 for the next final check (--plan fresh5), after fresh6p had been seen:
    # three planets with another tooth set (Zs 27 / Zp 33 / Zr 93, (Zs + Zr) / 3 = 40), module 2 mm,
    # a friction and backlash no other set uses; on a rig of its own (RIGS).
    three_b = sim.GearSet("fresh3q", 3, sim.Gear(27, 0.002, face_width_m=0.03), sim.Gear(33, 0.002, face_width_m=0.03),
                          sim.Gear(93, 0.002, face_width_m=0.03), friction_coefficient=0.045,
                          backlash_sun_planet_m=11e-6, backlash_planet_ring_m=11e-6)
    return {"seed3p": seed, "four4p": four, "fresh5p": five, "fresh3p": three, "fresh4p": four_b, "fresh6p": six,
            "fresh3q": three_b}


# Rig internals per gear set where they differ from sim.Rig()'s (every set before fresh3q runs on
# the default rig). fresh3q's rig (session 59): a heavier motor on a softer input shaft, a heavier
# dynamometer with a faster speed loop, wider encoders, a housing path of other gain and width,
# less structural loss -- none of it in the gear-set TOML, as for every rig.
RIGS = {
    "fresh3q": sim.Rig(motor_inertia_kgm2=0.3, input_shaft_N_m_rad=1.2e5, input_shaft_damping_Nms=10.0,
                       dyno_inertia_kgm2=1.5, output_shaft_N_m_rad=6.0e5, output_shaft_damping_Nms=40.0,
                       speed_loop_bandwidth_Hz=6.0, loss_factor=0.08, encoder_bandwidth_Hz=1500.0,
                       housing_gain_m_s2_per_N=3.0e-3, housing_kappa=3.0),
}


def rig_of(gearset):
    return RIGS.get(gearset, sim.Rig())


# operating points: name -> (rpm, W, duration of its recordings [s])
OPS = {
    "seed3p": {"A": (100, 1000, 10.0), "B": (200, 1000, 6.0), "C": (400, 1000, 3.0), "D": (200, 10000, 5.0),
               "E": (300, 20000, 4.0), "F": (400, 5000, 3.0), "H1": (9500, 2000, 2.0), "H2": (9000, 5000, 2.0)},
    "four4p": {"a": (100, 1000, 10.0), "b": (250, 3000, 5.0), "c": (400, 8000, 3.0), "d": (300, 10000, 4.0)},
    "fresh5p": {"a": (150, 2000, 8.0), "b": (350, 6000, 4.0), "c": (500, 12000, 3.0)},
    "fresh3p": {"a": (120, 1500, 8.0), "b": (300, 5000, 5.0), "c": (600, 15000, 3.0)},
    "fresh4p": {"a": (180, 3000, 6.0), "b": (420, 9000, 3.0), "c": (800, 4000, 2.0)},
    "fresh6p": {"a": (250, 4000, 5.0), "b": (600, 10000, 3.0), "c": (1000, 6000, 2.0)},
    "fresh3q": {"a": (150, 2500, 6.0), "b": (450, 8000, 3.0), "c": (900, 12000, 2.0)},
}
PLANS = ("main", "fresh", "fresh2", "fresh3", "fresh4", "fresh5")
HIGH = {"H1", "H2"}


def plan_fresh():
    """A final check (session 37): a gear set, operating points and sizes no development run has
    used; every effect once, a control per operating point. Run it once per change of the
    diagnosis that is to be judged, not while developing."""
    F = "fresh5p"
    P = [
        (F, "c", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=9, tooth_stiffness_factor=0.6), None),
        (F, "b", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=3, tooth_index=8,
                                             tooth_stiffness_factor=0.55), None),
        (F, "a", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=20, tooth_stiffness_factor=0.6), None),
        (F, "b", "pin_error", dict(pin_error_m=(0.0, 0.0, 2.5e-6, 0.0, 0.0)), None),
        (F, "b", "sun_runout", dict(sun_ecc_m=2e-6, sun_ecc_phase_rad=2.5), None),
        (F, "c", "carrier_runout", dict(carrier_ecc_m=2.5e-6, carrier_ecc_phase_rad=1.0), None),
        (F, "c", "stiffness_level", dict(stiffness_scale=0.85), None),
        (F, "b", "damping_level", dict(damping_scale=2.0), None),
        (F, "b", "friction", dict(friction_coefficient=0.1), None),
        (F, "c", "torque_ripple", dict(ripple_fraction=0.06, ripple_order=1.0), None),
        (F, "c", "worn_profile", dict(worn_depth_m=2e-6), None),
        (F, "a", "sensor_transfer_path", dict(housing_gain_scale=0.6), None),
    ]
    for op in ("a", "b", "c"):
        P.append((F, op, "none", {}, None))
    return P


def plan_fresh2():
    """The next final check (session 38), made after plan_fresh had been diagnosed: a gear set,
    operating points and sizes no development run has used; every effect once, one of them
    also in a recording under two carrier revolutions (1.5 s at 300 rpm: 1.67 revolutions), a
    control per operating point. Run it once per change of the diagnosis that is to be judged."""
    F = "fresh3p"
    P = [
        (F, "a", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=17, tooth_stiffness_factor=0.65), None),
        (F, "b", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=4, tooth_stiffness_factor=0.55), 1.5),
        (F, "c", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=1, tooth_index=12,
                                             tooth_stiffness_factor=0.6), None),
        (F, "b", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=41, tooth_stiffness_factor=0.5), None),
        (F, "c", "pin_error", dict(pin_error_m=(0.0, 3e-6, 0.0)), None),
        (F, "a", "sun_runout", dict(sun_ecc_m=2.5e-6, sun_ecc_phase_rad=0.8), None),
        (F, "b", "carrier_runout", dict(carrier_ecc_m=3e-6, carrier_ecc_phase_rad=2.2), None),
        (F, "b", "stiffness_level", dict(stiffness_scale=1.2), None),
        (F, "c", "damping_level", dict(damping_scale=0.5), None),
        (F, "c", "friction", dict(friction_coefficient=0.035), None),
        (F, "a", "torque_ripple", dict(ripple_fraction=0.08, ripple_order=2.0, ripple_phase_rad=1.1), None),
        (F, "b", "worn_profile", dict(worn_depth_m=2.5e-6), None),
        (F, "c", "sensor_transfer_path", dict(housing_gain_scale=1.5), None),
    ]
    for op in ("a", "b", "c"):
        P.append((F, op, "none", {}, None))
    return P


def plan_fresh3():
    """The next final check (session 39), made after plan_fresh2 had been diagnosed: four planets
    with a tooth set, module, speeds and sizes no development run has used; every effect once, a
    sun tooth also in a recording under two carrier revolutions (1.2 s at 420 rpm: 1.84
    revolutions), a control per operating point. Run it once per change of the diagnosis that is
    to be judged."""
    F = "fresh4p"
    P = [
        (F, "b", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=11, tooth_stiffness_factor=0.6), None),
        (F, "b", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=2, tooth_stiffness_factor=0.5), 1.2),
        (F, "a", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=2, tooth_index=19,
                                             tooth_stiffness_factor=0.55), None),
        (F, "c", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=58, tooth_stiffness_factor=0.6), None),
        (F, "a", "pin_error", dict(pin_error_m=(0.0, 0.0, 0.0, 3.5e-6)), None),
        (F, "c", "sun_runout", dict(sun_ecc_m=3.5e-6, sun_ecc_phase_rad=0.3), None),
        (F, "a", "carrier_runout", dict(carrier_ecc_m=3.5e-6, carrier_ecc_phase_rad=1.7), None),
        (F, "c", "stiffness_level", dict(stiffness_scale=0.75), None),
        (F, "a", "damping_level", dict(damping_scale=3.0), None),
        (F, "b", "friction", dict(friction_coefficient=0.11), None),
        (F, "b", "torque_ripple", dict(ripple_fraction=0.05, ripple_order=3.0, ripple_phase_rad=0.4), None),
        (F, "a", "worn_profile", dict(worn_depth_m=3.5e-6), None),
        (F, "b", "sensor_transfer_path", dict(housing_kappa_scale=0.5), None),
    ]
    for op in ("a", "b", "c"):
        P.append((F, op, "none", {}, None))
    return P


def plan_fresh4():
    """The next final check (session 58), made after plan_fresh3 had been seen in development: six
    planets, a tooth set, module, speeds and sizes no development run has used; every effect once,
    a sun tooth also in a recording under two carrier revolutions (1.5 s at 250 rpm: 1.84
    revolutions), a control per operating point. Run it once per change of the diagnosis that is
    to be judged."""
    F = "fresh6p"
    P = [
        (F, "b", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=7, tooth_stiffness_factor=0.55), None),
        (F, "a", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=22, tooth_stiffness_factor=0.6), 1.5),
        (F, "c", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=4, tooth_index=9,
                                             tooth_stiffness_factor=0.6), None),
        (F, "a", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=47, tooth_stiffness_factor=0.55), None),
        (F, "b", "pin_error", dict(pin_error_m=(0.0, 0.0, 0.0, 0.0, 3e-6, 0.0)), None),
        (F, "a", "sun_runout", dict(sun_ecc_m=3e-6, sun_ecc_phase_rad=1.9), None),
        (F, "c", "carrier_runout", dict(carrier_ecc_m=3e-6, carrier_ecc_phase_rad=0.6), None),
        (F, "b", "stiffness_level", dict(stiffness_scale=1.3), None),
        (F, "c", "damping_level", dict(damping_scale=0.35), None),
        (F, "a", "friction", dict(friction_coefficient=0.12), None),
        (F, "c", "torque_ripple", dict(ripple_fraction=0.06, ripple_order=2.0, ripple_phase_rad=2.3), None),
        (F, "b", "worn_profile", dict(worn_depth_m=3e-6), None),
        (F, "a", "sensor_transfer_path", dict(housing_gain_scale=0.65), None),
    ]
    for op in ("a", "b", "c"):
        P.append((F, op, "none", {}, None))
    return P


def plan_fresh5():
    """The next final check (session 59), made after plan_fresh4 had been seen: three planets, a
    tooth set, module, speeds, sizes and a rig (RIGS) no development run has used; every effect
    once, a sun tooth also in a recording under two carrier revolutions (1.0 s at 450 rpm: 1.69
    revolutions), a control per operating point. Run it once per change of the diagnosis that is
    to be judged."""
    F = "fresh3q"
    P = [
        (F, "a", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=13, tooth_stiffness_factor=0.5), None),
        (F, "b", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=3, tooth_stiffness_factor=0.6), 1.0),
        (F, "b", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=2, tooth_index=20,
                                             tooth_stiffness_factor=0.5), None),
        (F, "c", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=66, tooth_stiffness_factor=0.6), None),
        (F, "a", "pin_error", dict(pin_error_m=(0.0, 4e-6, 0.0)), None),
        (F, "c", "sun_runout", dict(sun_ecc_m=4e-6, sun_ecc_phase_rad=4.0), None),
        (F, "b", "carrier_runout", dict(carrier_ecc_m=4e-6, carrier_ecc_phase_rad=5.1), None),
        (F, "a", "stiffness_level", dict(stiffness_scale=0.7), None),
        (F, "b", "damping_level", dict(damping_scale=2.5), None),
        (F, "c", "friction", dict(friction_coefficient=0.09), None),
        (F, "b", "torque_ripple", dict(ripple_fraction=0.04, ripple_order=1.0, ripple_phase_rad=0.7), None),
        (F, "c", "worn_profile", dict(worn_depth_m=4e-6), None),
        (F, "a", "sensor_transfer_path", dict(housing_gain_scale=1.4), None),
    ]
    for op in ("a", "b", "c"):
        P.append((F, op, "none", {}, None))
    return P


def plan(quick=False, variant="main"):
    """List of (gearset, op, effect, faults kwargs, parameters for truth, duration override)."""
    if variant == "fresh":
        return plan_fresh()
    if variant == "fresh2":
        return plan_fresh2()
    if variant == "fresh3":
        return plan_fresh3()
    if variant == "fresh4":
        return plan_fresh4()
    if variant == "fresh5":
        return plan_fresh5()
    P = []
    if quick:
        for eff, kw in (("none", {}), ("sun_tooth_damage", dict(tooth_body="sun", tooth_index=5,
                                                                             tooth_stiffness_factor=0.5)),
                        ("pin_error", dict(pin_error_m=(0.0, 1.5e-6, 0.0))), ("stiffness_level", dict(stiffness_scale=0.8)),
                        ("torque_ripple", dict(ripple_fraction=0.08, ripple_order=2.0))):
            P.append(("seed3p", "Q", eff, kw, None))
        return P
    S = "seed3p"
    P += [
        (S, "C", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=5, tooth_stiffness_factor=0.5), None),
        (S, "D", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=14, tooth_stiffness_factor=0.7), None),
        (S, "A", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=3, tooth_stiffness_factor=0.6), 2.0),
        (S, "E", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=1, tooth_index=7,
                                             tooth_stiffness_factor=0.5), None),
        (S, "B", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=2, tooth_index=20,
                                             tooth_stiffness_factor=0.7), None),
        (S, "A", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=0, tooth_index=11,
                                             tooth_stiffness_factor=0.6), None),
        (S, "D", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=30, tooth_stiffness_factor=0.5), None),
        (S, "F", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=61, tooth_stiffness_factor=0.7), None),
        (S, "E", "pin_error", dict(pin_error_m=(0.0, 5e-6, 0.0)), None),
        (S, "D", "pin_error", dict(pin_error_m=(0.0, 0.0, 2e-6)), None),
        (S, "A", "pin_error", dict(pin_error_m=(0.0, 1e-6, 0.0)), 4.0),
        (S, "E", "sun_runout", dict(sun_ecc_m=3e-6, sun_ecc_phase_rad=1.0), None),
        (S, "F", "sun_runout", dict(sun_ecc_m=1.5e-6, sun_ecc_phase_rad=2.0), None),
        (S, "E", "carrier_runout", dict(carrier_ecc_m=4e-6, carrier_ecc_phase_rad=0.5), None),
        (S, "D", "carrier_runout", dict(carrier_ecc_m=2e-6, carrier_ecc_phase_rad=3.0), None),
        (S, "C", "stiffness_level", dict(stiffness_scale=0.8), None),
        (S, "E", "stiffness_level", dict(stiffness_scale=1.25), None),
        (S, "F", "damping_level", dict(damping_scale=0.4), None),
        (S, "B", "damping_level", dict(damping_scale=2.5), None),
        (S, "D", "friction", dict(friction_coefficient=0.03), None),
        (S, "C", "friction", dict(friction_coefficient=0.12), None),
        (S, "A", "friction", dict(friction_coefficient=0.10), None),
        (S, "E", "torque_ripple", dict(ripple_fraction=0.05, ripple_order=1.0), None),
        (S, "C", "torque_ripple", dict(ripple_fraction=0.10, ripple_order=2.0, ripple_phase_rad=0.7), None),
        (S, "D", "worn_profile", dict(worn_depth_m=3e-6), None),
        (S, "F", "worn_profile", dict(worn_depth_m=1.5e-6), None),
        (S, "H1", "backlash", dict(backlash_m=100e-6), None),
        (S, "H2", "backlash", dict(backlash_m=60e-6), None),
        (S, "B", "sensor_transfer_path", dict(housing_kappa_scale=0.4), None),
        (S, "F", "sensor_transfer_path", dict(housing_gain_scale=0.5), None),
    ]
    for op in ("A", "C", "D", "E", "H1"):
        P.append((S, op, "none", {}, None))
    P.append((S, "B", "none", {}, 2.0))
    F4 = "four4p"
    P += [
        (F4, "c", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=4, tooth_stiffness_factor=0.55), None),
        (F4, "d", "sun_tooth_damage", dict(tooth_body="sun", tooth_index=17, tooth_stiffness_factor=0.75), None),
        (F4, "d", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=3, tooth_index=12,
                                              tooth_stiffness_factor=0.5), None),
        (F4, "b", "planet_tooth_damage", dict(tooth_body="planet", tooth_planet=1, tooth_index=25,
                                              tooth_stiffness_factor=0.7), None),
        (F4, "c", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=44, tooth_stiffness_factor=0.5), None),
        (F4, "a", "ring_tooth_damage", dict(tooth_body="ring", tooth_index=9, tooth_stiffness_factor=0.65), None),
        (F4, "d", "pin_error", dict(pin_error_m=(0.0, 0.0, 3e-6, 0.0)), None),
        (F4, "c", "pin_error", dict(pin_error_m=(0.0, 2e-6, 0.0, -1e-6)), None),
        (F4, "d", "sun_runout", dict(sun_ecc_m=2e-6, sun_ecc_phase_rad=0.3), None),
        (F4, "b", "sun_runout", dict(sun_ecc_m=1e-6, sun_ecc_phase_rad=4.0), None),
        (F4, "c", "carrier_runout", dict(carrier_ecc_m=3e-6, carrier_ecc_phase_rad=2.0), None),
        (F4, "d", "carrier_runout", dict(carrier_ecc_m=2e-6, carrier_ecc_phase_rad=5.0), None),
        (F4, "b", "stiffness_level", dict(stiffness_scale=0.75), None),
        (F4, "d", "stiffness_level", dict(stiffness_scale=1.3), None),
        (F4, "c", "damping_level", dict(damping_scale=0.3), None),
        (F4, "a", "damping_level", dict(damping_scale=3.0), None),
        (F4, "b", "friction", dict(friction_coefficient=0.15), None),
        (F4, "d", "friction", dict(friction_coefficient=0.02), None),
        (F4, "c", "torque_ripple", dict(ripple_fraction=0.04, ripple_order=1.0), None),
        (F4, "b", "torque_ripple", dict(ripple_fraction=0.12, ripple_order=2.0), 2.0),
        (F4, "d", "torque_ripple", dict(ripple_fraction=0.08, ripple_order=2.0, ripple_phase_rad=1.3), None),
        (F4, "c", "worn_profile", dict(worn_depth_m=2e-6), None),
        (F4, "a", "worn_profile", dict(worn_depth_m=0.6e-6), None),
        (F4, "d", "sensor_transfer_path", dict(housing_kappa_scale=2.0), None),
        (F4, "a", "sensor_transfer_path", dict(housing_gain_scale=1.8), None),
    ]
    for op in ("a", "b", "c", "d"):
        P.append((F4, op, "none", {}, None))
    return P


QUICK_OPS = {"Q": (600, 5000, 2.0)}

# ----------------------------------------------------------------------------
# Writing recordings
# ----------------------------------------------------------------------------

COLUMNS = [  # csv name, quantity, unit, source key, factor (SI -> unit)
    ("w_sun", "sun_speed", "rpm", "sun_speed", 60.0 / (2 * math.pi)),
    ("w_carrier", "carrier_speed", "rad/s", "carrier_speed", 1.0),
    ("a_sp0", "mesh_acceleration_sun_planet", "m/s^2", "acc_sp0", 1.0),
    ("a_pr0", "mesh_acceleration_planet_ring", "g", "acc_pr0", 1.0 / G0),
    ("acc_housing", "housing_acceleration", "g", "housing", 1.0 / G0),
]


def add_noise(res, case, rng):
    """5 % white noise of each channel's RMS about its mean; DC offsets on accelerometers."""
    out = {}
    for key in ("sun_speed", "carrier_speed", "acc_sp0", "acc_pr0", "housing"):
        x = np.asarray(res[key], float)
        sd = float(np.std(x))
        y = x + rng.normal(0.0, case.noise_fraction * sd, x.size)
        if key.startswith("acc") or key == "housing":
            rms = float(np.sqrt(np.mean(x ** 2)))
            y = y + rng.choice([-1.0, 1.0]) * rng.uniform(0.1, 0.5) * rms
        out[key] = y
    return out


def write_recording(path_csv, res, case, fs, sensor_angle_deg, description):
    rng = np.random.default_rng(case.seed)
    noisy = add_noise(res, case, rng)
    t = res["time"]
    cols = [t] + [noisy[src] * f for (_, _, _, src, f) in COLUMNS]
    data = np.column_stack(cols)
    tmp = path_csv + ".tmp"
    with open(tmp, "w") as fh:
        fh.write("# indepsim DAQ export\n")
        fh.write("time," + ",".join(c[0] for c in COLUMNS) + "\n")
        fmt = "%.8f" + ",%.9g" * len(COLUMNS)
        np.savetxt(fh, data, fmt=fmt)
    os.replace(tmp, path_csv)
    meta = {
        "description": description,
        "generator": "scripts/indepsim/sim.py (independent simulator)",
        "operating": {"input_speed_rpm": case.speed_rpm, "input_power_W": case.power_W},
        "time_column": "time",
        "time_unit": "s",
        "columns": {},
    }
    for (name, q, unit, _, _) in COLUMNS:
        e = {"quantity": q, "unit": unit}
        if q.startswith("mesh_acceleration"):
            e["planet"] = 0
        if q == "housing_acceleration":
            e["sensor_angle_deg"] = round(float(sensor_angle_deg), 6)
        meta["columns"][name] = e
    js = os.path.splitext(path_csv)[0] + ".json"
    with open(js + ".tmp", "w") as fh:
        json.dump(meta, fh, indent=2)
    os.replace(js + ".tmp", js)


def rms_ratios(res, base):
    r = {}
    for key in ("sun_speed", "carrier_speed", "acc_sp0", "acc_pr0", "housing"):
        a, b = np.asarray(res[key]), np.asarray(base[key])
        n = min(a.size, b.size)
        r[key] = round(float(np.std(a[:n]) / max(np.std(b[:n]), 1e-300)), 4)
    return r


# ----------------------------------------------------------------------------
# Batches
# ----------------------------------------------------------------------------


def run_batch(job):
    """job: dict(gearset, entries=[...]); returns per entry (result dict, fs) and info."""
    gs = gearsets()[job["gearset"]]
    stage = sim.Stage(gs, rig_of(job["gearset"]))
    cases = [sim.Case(**e["case"], faults=sim.Faults(**e["faults"])) for e in job["entries"]]
    t0 = time.time()
    fs, res, info = sim.simulate_batch(stage, cases, warmup_s=job["warmup_s"], dt_factor=job["dt_factor"],
                                       fs=job.get("fs"), D=job.get("D"))
    info.pop("fine", None)
    info["wall_s"] = time.time() - t0
    return job["name"], fs, res, info


def plan_entries(quick=False, seed=1, limit=None, duration=None, variant="main"):
    """The corpus's recordings before simulation: (entries, held-out indices, batches, job list).

    Every random choice of the corpus (sensor angles, noise seeds, held-out set, names) is made
    here, in a fixed order, so that another script (observability.py) can rebuild the same cases."""
    rnd = random.Random(seed)
    gsets = gearsets()
    P = plan(quick, variant)
    ops = dict(OPS)
    if quick:
        ops = {"seed3p": QUICK_OPS}
    # every operating point used gets a baseline
    entries = []
    used = sorted({(g, op) for (g, op, _, _, _) in P})
    for (g, op) in used:
        entries.append(dict(gearset=g, op=op, effect="none", role="baseline", fk={}, dur=None))
    for (g, op, eff, kw, dur) in P:
        entries.append(dict(gearset=g, op=op, effect=eff, role="effect" if eff != "none" else "control", fk=kw,
                            dur=dur))
    if limit:
        entries = entries[:limit]
    # per-entry randomness: sensor angle (5 deg steps), noise seed
    for e in entries:
        rpm, W, dur = ops[e["gearset"]][e["op"]]
        e["rpm"], e["W"] = rpm, W
        e["duration_s"] = min(e["dur"] or dur, 2.0) if quick else (e["dur"] or dur)
        if duration:
            e["duration_s"] = duration
        e["sensor_angle_phys_deg"] = 5.0 * rnd.randrange(72)
        e["seed"] = rnd.randrange(2 ** 31)
    # held out: ~25 % of effect recordings + one control per gear set
    held = set()
    if not quick:
        eff_idx = [i for i, e in enumerate(entries) if e["role"] == "effect"]
        held |= set(rnd.sample(eff_idx, round(0.25 * len(eff_idx))))
        for g in gsets:
            ctl = [i for i, e in enumerate(entries) if e["role"] == "control" and e["gearset"] == g]
            if ctl:
                held.add(rnd.choice(ctl))
    # names: shuffled per gear set
    for g in gsets:
        idx = [i for i, e in enumerate(entries) if e["gearset"] == g]
        names = list(range(1, len(idx) + 1))
        rnd.shuffle(names)
        for i, nm in zip(idx, names):
            entries[i]["name"] = f"rec_{nm:02d}"
    # batches: per gear set, low-speed and high-speed
    batches = {}
    for i, e in enumerate(entries):
        key = (e["gearset"], "high" if e["op"] in HIGH else ("long" if e["duration_s"] >= 8.0 else "mid"))
        batches.setdefault(key, []).append(i)
    joblist = []
    for (g, cls), idx in batches.items():
        joblist.append(dict(name=(g, cls), gearset=g, warmup_s=0.3 if cls == "high" else 0.6,
                            dt_factor=0.5 if cls == "high" else 1.0,
                            entries=[dict(case=dict(speed_rpm=entries[i]["rpm"], power_W=entries[i]["W"],
                                                    duration_s=entries[i]["duration_s"],
                                                    sensor_angle_deg=entries[i]["sensor_angle_phys_deg"],
                                                    seed=entries[i]["seed"]),
                                          faults=entries[i]["fk"]) for i in idx], idx=idx))
    return entries, held, batches, joblist


def build(out, quick=False, jobs=1, seed=1, limit=None, duration=None, variant="main"):
    gsets = gearsets()
    entries, held, batches, joblist = plan_entries(quick, seed, limit, duration, variant)
    os.makedirs(out, exist_ok=True)
    log = open(os.path.join(out, "corpus.log"), "a")

    def say(msg):
        print(msg, flush=True)
        log.write(msg + "\n")
        log.flush()

    say(f"indepsim corpus: {len(entries)} recordings in {len(joblist)} batches, seed {seed}, quick={quick}")
    t0 = time.time()
    results = {}
    if jobs > 1 and len(joblist) > 1:
        with multiprocessing.Pool(min(jobs, len(joblist))) as pool:
            for name, fs, res, info in pool.imap_unordered(run_batch, sorted(joblist, key=lambda j: -len(j["idx"]))):
                results[name] = (fs, res, info)
                say(f"  batch {name}: {info['batch']} recordings, {info['simulated_s']:.2f} s simulated, "
                    f"dt {info['dt'] * 1e6:.2f} us, fs {fs:.0f} Hz, cpu {info['cpu_s']:.0f} s, wall {info['wall_s']:.0f} s")
    else:
        for j in joblist:
            name, fs, res, info = run_batch(j)
            results[name] = (fs, res, info)
            say(f"  batch {name}: {info['batch']} recordings, {info['simulated_s']:.2f} s simulated, "
                f"dt {info['dt'] * 1e6:.2f} us, fs {fs:.0f} Hz, cpu {info['cpu_s']:.0f} s, wall {info['wall_s']:.0f} s")
    # write
    truth = {"generator": "scripts/indepsim/corpus.py", "seed": seed, "quick": quick, "plan": variant,
             "noise": "5 % of each channel's RMS about its mean; accelerometer DC offsets +-(10-50) % of RMS",
             "gearsets": {}, "recordings": {}, "batches": []}
    for g, gs in gsets.items():
        if not any(e["gearset"] == g for e in entries):
            continue
        rig = rig_of(g)
        st = sim.Stage(gs, rig)
        d = os.path.join(out, g, "recordings")
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(out, g, "gearset.toml"), "w") as fh:
            fh.write(sim.gearset_toml_text(gs))
        truth["gearsets"][g] = dict(
            toml=f"{g}/gearset.toml", planet_count=gs.planet_count, teeth=list(st.Z), module_m=gs.sun.module_m,
            contact_ratio={k: round(v, 4) for k, v in st.eps.items()},
            mean_mesh_stiffness_N_m={k: float(f"{v:.4g}") for k, v in st.kmean_iso.items()},
            natural_frequencies_Hz=[round(float(f), 1) for f in st.natural_frequencies()[1:]],
            rig=dataclasses.asdict(rig), design_backlash_m=gs.backlash_sun_planet_m,
            friction_coefficient=gs.friction_coefficient)
    base_of = {}
    for i, e in enumerate(entries):
        if e["role"] == "baseline":
            base_of[(e["gearset"], e["op"])] = i
    where = {}
    for (g, cls), idx in batches.items():
        fs, res, info = results[(g, cls)]
        truth["batches"].append(dict(gearset=g, cls=cls, recordings=len(idx), dt_s=info["dt"], fs_Hz=fs,
                                     simulated_s=info["simulated_s"], cpu_s=round(info["cpu_s"], 1),
                                     wall_s=round(info["wall_s"], 1),
                                     cpu_s_per_recording_second=round(info["cpu_s"] / sum(
                                         entries[i]["duration_s"] for i in idx), 3)))
        for k, i in enumerate(idx):
            where[i] = (fs, res[k])
    for i, e in enumerate(entries):
        g = e["gearset"]
        st = sim.Stage(gsets[g])
        fs, r = where[i]
        # the sidecar angle is measured from planet 0's position at the time column's zero
        ang = (e["sensor_angle_phys_deg"] - math.degrees(r["carrier_angle_start"])) % 360.0
        case = sim.Case(e["rpm"], e["W"], e["duration_s"], seed=e["seed"])
        path = os.path.join(out, g, "recordings", e["name"] + ".csv")
        write_recording(path, r, case, fs, ang, f"indepsim rig, gear set {g}, {fs:.0f} Hz DAQ, 5 % noise")
        bi = base_of[(g, e["op"])]
        Wc = st.nominal(case)[1]
        revs = e["duration_s"] * Wc / (2 * math.pi)
        params = dict(e["fk"])
        if "pin_error_m" in params:
            params["pin_error_m"] = list(params["pin_error_m"])
        if e["effect"] == "ring_tooth_damage":
            Zp, Zr = st.Z[1], st.Z[2]
            params["ring_tooth_angle_deg_housing"] = round(
                (360.0 * (params["tooth_index"] + (Zp - 1) / 2.0) / Zr) % 360.0, 3)
        fm = st.mesh_frequency(e["rpm"])
        truth["recordings"][f"{g}/{e['name']}"] = dict(
            gearset=g, name=e["name"], csv=f"{g}/recordings/{e['name']}.csv", effect=e["effect"], role=e["role"],
            parameters=params, operating_point=e["op"], input_speed_rpm=e["rpm"], input_power_W=e["W"],
            duration_s=e["duration_s"], carrier_revolutions=round(revs, 3),
            reader_should_refuse=bool(revs < 3.0), held_out=i in held,
            baseline=f"{g}/{entries[bi]['name']}", fs_Hz=fs, mesh_frequency_Hz=round(fm, 3),
            sensor_angle_deg_sidecar=round(ang, 6), sensor_angle_deg_at_t0_sim=e["sensor_angle_phys_deg"],
            noise_seed=e["seed"], load_stiffness_factor_iso=round(st.load_factor(case), 4),
            mean_planet_ring_force_N=[round(float(x), 2) for x in r["mean_planet_ring_force"]],
            rms_ratio_vs_baseline_noise_free=rms_ratios(r, where[bi][1]))
    with open(os.path.join(out, "truth.json"), "w") as fh:
        json.dump(truth, fh, indent=1)
    say(f"done: {len(entries)} recordings, {time.time() - t0:.0f} s wall, "
        f"cpu {sum(b['cpu_s'] for b in truth['batches']):.0f} s")
    return truth


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--quick", action="store_true", help="6 recordings of 2 s (CI)")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--plan", choices=PLANS, default="main",
                    help="main: the development corpus (two gear sets, 77 recordings); fresh: a final check on a "
                         "five-planet gear set (18 recordings, seen in sessions 37-38); fresh2: a three-planet gear set "
                         "(19 recordings, seen in session 38); fresh3: a four-planet gear set "
                         "(19 recordings, seen in sessions 39-58); fresh4: a six-planet gear set "
                         "(19 recordings, seen in session 58); fresh5: the next final check, a three-planet gear set on a "
                         "rig of its own (19 recordings, one under two carrier revolutions)")
    a = ap.parse_args(argv)
    if a.quick and a.plan != "main":
        ap.error("--quick is a variant of the main plan")
    build(a.out, a.quick, a.jobs, a.seed, variant=a.plan)


if __name__ == "__main__":
    main()
