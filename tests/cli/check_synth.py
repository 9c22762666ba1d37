#!/usr/bin/env python3
"""Checks a `planetwear synth` recording against its noise-free twin.

Usage: check_synth.py REC.csv REC.json CLEAN.csv NOISE DC_OFFSET SENSOR_ANGLE_DEG
"""
import csv
import json
import math
import sys


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = list(zip(*[[float(x) for x in r] for r in rows[1:]]))
    return header, {h.split(" [")[0]: list(c) for h, c in zip(header, cols)}


def mean(x):
    return sum(x) / len(x)


def rms_about_mean(x):
    m = mean(x)
    return math.sqrt(sum((v - m) ** 2 for v in x) / len(x))


def main():
    rec, meta_path, clean, noise, dc, angle = sys.argv[1:7]
    noise, dc, angle = float(noise), float(dc), float(angle)
    errors = []
    header, d = read(rec)
    _, c = read(clean)
    expected = ["time [s]", "sun_speed [rad/s]", "carrier_speed [rad/s]", "sun_planet_0_acc [m/s^2]",
                "planet_ring_0_acc [m/s^2]", "housing_acc [m/s^2]", "tacho [V]"]
    if header != expected:
        errors.append(f"header {header} != {expected}")
    meta = json.load(open(meta_path))
    text = json.dumps(meta)
    for secret in ("pin_error", "imperfections", "5e-07"):
        if secret in text:
            errors.append(f"the sidecar reveals the effect ('{secret}')")
    if meta["operating"] != {"input_speed_rpm": 1200.0, "input_power_W": 20000.0}:
        errors.append(f"operating point {meta['operating']}")
    if abs(meta["columns"]["housing_acc"]["sensor_angle_deg"] - angle) > 1e-9:
        errors.append("sensor angle")
    if meta["columns"]["sun_planet_0_acc"].get("planet") != 0:
        errors.append("mesh acceleration planet")
    # Time: uniform, absolute: starts at mesh cycle 20.
    t = d["time"]
    dt = (t[-1] - t[0]) / (len(t) - 1)
    if not 7000 < 1 / dt < 12000:  # 1 / (40 x the ~2.8 us automatic time step)
        errors.append(f"sample rate {1 / dt}")
    fm = 21 * 81 / 102 * 1200 / 60
    if abs(t[0] - 20 / fm) > 1e-9:
        errors.append(f"first sample at {t[0]} s, expected mesh cycle 20 = {20 / fm} s")
    if abs(len(t) * dt - 0.8) > 2 * dt:
        errors.append(f"duration {len(t) * dt}")
    if t != c["time"]:
        errors.append("time differs from the noise-free twin")
    # Noise: std of (noisy - clean) = noise x RMS of the clean channel, offset
    # = dc x RMS on accelerometers only.
    for name in ("sun_speed", "carrier_speed", "sun_planet_0_acc", "planet_ring_0_acc", "housing_acc"):
        diff = [a - b for a, b in zip(d[name], c[name])]
        r = rms_about_mean(c[name])
        want_offset = dc * r if name.endswith("_acc") else 0.0
        if abs(mean(diff) - want_offset) > 0.05 * r:
            errors.append(f"{name}: offset {mean(diff)}, expected {want_offset}")
        if abs(rms_about_mean(diff) / (noise * r) - 1) > 0.1:
            errors.append(f"{name}: noise std {rms_about_mean(diff)}, expected {noise * r}")
    if d["tacho"] != c["tacho"] or set(d["tacho"]) != {0.0, 5.0}:
        errors.append("tacho must be noise-free 0/5 V pulses")
    if abs(mean(d["tacho"]) / 5 - 0.05) > 0.01:
        errors.append(f"tacho duty cycle {mean(d['tacho']) / 5}")
    for e in errors:
        print("FAIL", e)
    if not errors:
        print(f"{rec}: {len(t)} samples at {1 / dt:.6g} Hz, noise, offsets, sidecar ok")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
