"""Writers of the independent simulators' corpora (indepsim3, indepsim4): the gear-set TOML, and a
recording as CSV with its JSON sidecar, in planetwear's documented formats (docs/config.md,
docs/recordings.md). Format only: each simulator's physics stays its own.

Imported by each corpus.py as `indepsim_writers` (a name no other module of the project has: their
tests load several simulators into one pytest run)."""
import json
import os

import numpy as np

def gearset_toml(gs, corpus_name, generator):
    """The gear set as docs/config.md keys: what the stage's drawing and documentation give."""
    lines = [f"# gear set {gs.name}: {corpus_name} corpus (written by {generator})",
             "# what the stage's documentation gives; speeds and powers are in the recordings' sidecars", "",
             "[stage]", f"planet_count = {gs.N}", ""]
    for body, z, x in (("sun", gs.Zs, gs.shift_s), ("planet", gs.Zp, gs.shift_p), ("ring", gs.Zr, gs.shift_r)):
        lines += [f"[stage.{body}]", f"teeth = {z}", f"module_m = {gs.module_m!r}",
                  f"pressure_angle_deg = {gs.pressure_angle_deg!r}", f"face_width_m = {gs.face_width_m!r}",
                  f"profile_shift = {float(x)!r}", f"addendum_coef = {gs.addendum_coef!r}",
                  f"dedendum_coef = {gs.dedendum_coef!r}", f"youngs_modulus_Pa = {gs.youngs_modulus_Pa:.6g}",
                  f"poisson_ratio = {gs.poisson_ratio!r}", f"density_kg_m3 = {gs.density_kg_m3!r}", ""]
    lines += ["[contact]", f"friction_coefficient = {gs.friction!r}",
              f"backlash_sun_planet_m = {gs.backlash_sp_m!r}", f"backlash_planet_ring_m = {gs.backlash_pr_m!r}", ""]
    return "\n".join(lines)


COLUMNS = [  # (csv name, unit, quantity, extra sidecar keys)
    ("sun_speed", "rpm", "sun_speed", {}),
    ("carrier_speed", "rpm", "carrier_speed", {}),
    ("acc_housing", "m/s^2", "housing_acceleration", None),   # sensor angle filled per recording
    ("acc_sun_planet0", "m/s^2", "mesh_acceleration_sun_planet", {"planet": 0}),
    ("acc_planet0_ring", "m/s^2", "mesh_acceleration_planet_ring", {"planet": 0}),
]


def write_recording(csv_path, t, channels, rpm, power_W, sensor_angle_deg, fs, generator, description="",
                    encoder_lines=None):
    """CSV (time + the COLUMNS, units in brackets) and its JSON sidecar (docs/recordings.md)."""
    header = ",".join(["time [s]"] + [f"{name} [{unit}]" for name, unit, _, _ in COLUMNS])
    data = np.column_stack([t] + [channels[name] for name, _, _, _ in COLUMNS])
    fmt = ["%.7f", "%.5f", "%.6f", "%.6e", "%.6e", "%.6e"]
    tmp = csv_path + ".tmp"
    with open(tmp, "w") as f:
        f.write(f"# {generator}: {description}\n")
        np.savetxt(f, data, fmt=fmt, delimiter=",", header=header, comments="")
    os.replace(tmp, csv_path)
    cols = {}
    for name, unit, q, extra in COLUMNS:
        d = {"quantity": q, "unit": unit}
        if extra is None:
            d["sensor_angle_deg"] = round(float(sensor_angle_deg), 6)
        else:
            d.update(extra)
        if encoder_lines and q in encoder_lines:  # what the rig's documentation gives (docs/recordings.md)
            d["encoder_lines"] = int(encoder_lines[q])
        cols[name] = d
    meta = {"description": description, "generator": generator,
            "operating": {"input_speed_rpm": float(rpm), "input_power_W": float(power_W)},
            "time_column": "time", "time_unit": "s", "columns": cols}
    side = os.path.splitext(csv_path)[0] + ".json"
    with open(side + ".tmp", "w") as f:
        json.dump(meta, f, indent=1)
        f.write("\n")
    os.replace(side + ".tmp", side)
    return side
