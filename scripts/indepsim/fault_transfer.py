#!/usr/bin/python3
"""How a tooth fault reaches each channel in indepsim4 and in planetwear, on the same rig.

    /usr/bin/python3 scripts/indepsim/fault_transfer.py [--gearset setD4] [--op op2]
        [--body sun] [--tooth 19] [--factor 0.6] [--seconds 1.5] [--rig-inertias] [--friction-factor 1]
        [--level torsional|lateral_torsional] [--planetwear build/apps/planetwear] [-o DIR]

A diagnosis fits a fault's size to the lines the fault adds; when the model carries the fault to
a channel by a different transfer than the rig does, no size explains every channel (the
"unexplained residual, located right" verdicts of the independent corpora). This script puts the
two transfers side by side with everything else equal:

1. indepsim4 (scripts/indepsim4/sim.py, its own equations) simulates the gear set on its rig,
   healthy and with one damaged tooth, noise-free, at the operating point's speed and power;
2. planetwear synth simulates the same gear set from the same gearset.toml with indepsim4's rig
   translated into planetwear's rig keys (docs/config.md "rig"): the motor's inertia on its
   coupling (stiffness and damping from indepsim4's describe()), its PI speed loop, the output
   shaft to the load inertia under a constant load torque, first-order tachometers of the same
   bandwidth -- and, with --rig-inertias, indepsim4's sun, carrier and ring inertias and masses
   (otherwise planetwear's own estimates from the geometry, as a diagnosis has them);
3. both recordings' line amplitudes (Hann-weighted DFT at the exact frequency, speeds in rad/s)
   at the fault's family: m (f_s - f_c) for a sun tooth, m f_c for a ring tooth, m f_c Z_r/Z_p
   for a planet tooth (relative rotation frequencies), m = 1..--orders, with the ratio
   planetwear / indepsim4 where indepsim4's line is at least 1e-3 of that channel's largest.

It also prints both simulators' torsional natural frequencies below 1 kHz. Nothing is fitted:
it is a measurement of model form (docs/diagnose-log.md, session 70).
"""
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "indepsim4"))
sys.path.insert(0, os.path.join(HERE, "..", "indepsim_common"))

import corpus as sim4corpus  # noqa: E402  (indepsim4's corpus plan: gear sets, rigs, operating points)
import indepsim_writers as writers  # noqa: E402
import sim as sim4  # noqa: E402

CHANNELS = ("sun_speed", "carrier_speed", "mesh_acceleration_sun_planet", "mesh_acceleration_planet_ring",
            "housing_acceleration")
RELATIVE_FLOOR = 1e-3   # a ratio is printed only where indepsim4's line is >= this x its channel's largest


def read_csv(path):
    """-> {quantity: samples in SI}, time. Quantities from the sidecar; rpm -> rad/s."""
    meta = json.load(open(os.path.splitext(path)[0] + ".json"))
    with open(path) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    head = [h.split(" [")[0].strip() for h in lines[0].strip().split(",")]
    data = np.loadtxt(lines[1:], delimiter=",")
    out = {}
    for name, col in meta["columns"].items():
        x = data[:, head.index(name)].copy()
        if col.get("unit") == "rpm":
            x *= 2 * math.pi / 60
        out[col["quantity"]] = x
    return data[:, head.index(meta.get("time_column", "time"))], out


def line_amplitude(x, t, f):
    w = np.hanning(len(x))
    x = x - np.mean(x)
    return 2 * abs(np.sum(w * x * np.exp(-2j * math.pi * f * t))) / np.sum(w)


def family_frequency(gs, body, rpm):
    fs = rpm / 60
    fc = fs * gs.Zs / (gs.Zs + gs.Zr)
    return {"sun": fs - fc, "ring": fc, "planet": (fs - fc) * gs.Zs / gs.Zp}[body]


def rig_settings(st, rig, with_inertias):
    """indepsim4's rig (Stage.__init__, sim.py) as planetwear --set lines."""
    gs = st.gs
    ratio = gs.Zs / (gs.Zs + gs.Zr)
    J_rest = st.J_in_total - rig.J_motor
    J_ref_sun = J_rest - rig.J_load * ratio ** 2
    J_c_side = J_ref_sun / ratio ** 2
    c_in = 2 * rig.shaft_zeta * math.sqrt(st.k_in * rig.J_motor * J_rest / (rig.J_motor + J_rest))
    c_out = 2 * rig.shaft_zeta * math.sqrt(st.k_out * rig.J_load * J_c_side / (rig.J_load + J_c_side))
    s = [f"stage.input_inertia_kgm2={rig.J_motor}", "rig.input_control=speed_loop",
         f"rig.input_speed_loop_proportional_N_m_s_rad={st.Kp:.6g}", f"rig.input_speed_loop_integral_N_m_rad={st.Ki:.6g}",
         f"rig.input_shaft_stiffness_N_m_rad={st.k_in:.6g}", f"rig.input_shaft_damping_N_m_s_rad={c_in:.6g}",
         f"stage.output_inertia_kgm2={rig.J_load}", "rig.load_control=torque",
         f"rig.output_shaft_stiffness_N_m_rad={st.k_out:.6g}", f"rig.output_shaft_damping_N_m_s_rad={c_out:.6g}",
         f"sensor.encoder_bandwidth_Hz={rig.tacho_bw_Hz}", "sensor.encoder_filter_order=1"]
    if with_inertias:
        m = sim4.describe(st)["masses"]
        s += [f"stage.sun_inertia_kgm2={m['I_s']:.6g}", f"stage.sun_mass_kg={m['m_s']:.6g}",
              f"stage.carrier_inertia_kgm2={m['I_c']:.6g}", f"stage.carrier_mass_kg={m['m_c']:.6g}",
              f"stage.ring_inertia_kgm2={m['I_r']:.6g}", f"stage.ring_mass_kg={m['m_r']:.6g}"]
    return s


def indepsim4_natural_frequencies(st):
    """Damped natural frequencies [Hz] and ratios of the linear model (mean mesh stiffness and damping)."""
    N = st.gs.N
    K = st.linear_K()
    M = np.diag(st.M) if np.ndim(st.M) == 1 else st.M
    km = np.r_[np.full(N, st.k_mean_sp), np.full(N, st.k_mean_rp)]
    me = np.r_[np.full(N, st.me_sp), np.full(N, st.me_rp)]
    C = st.C_lin + (st.G.T * (2 * sim4.MESH_ZETA * np.sqrt(km * me))) @ st.G
    n = K.shape[0]
    Mi = np.linalg.inv(M)
    ev = np.linalg.eigvals(np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ K, -Mi @ C]]))
    ev = ev[ev.imag > 1e-3]
    return sorted((abs(e) / (2 * math.pi), -e.real / abs(e)) for e in ev)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gearset", default="setD4", choices=sorted(sim4corpus.GEARSETS))
    ap.add_argument("--op", default="op2", help="operating point of the gear set's plan (op1, op2)")
    ap.add_argument("--body", default="sun", choices=("sun", "planet", "ring"))
    ap.add_argument("--tooth", type=int, default=19)
    ap.add_argument("--planet", type=int, default=0, help="the damaged planet (--body planet)")
    ap.add_argument("--factor", type=float, default=0.6, help="the damaged pair's stiffness factor (0, 1]")
    ap.add_argument("--seconds", type=float, default=1.5, help="recorded seconds after each simulator's warm-up")
    ap.add_argument("--orders", type=int, default=40, help="family orders m = 1..orders")
    ap.add_argument("--friction-factor", type=float, default=1.0,
                    help="both simulators' friction coefficient x this (0: frictionless), healthy and faulty alike")
    ap.add_argument("--rig-inertias", action="store_true", help="give planetwear indepsim4's body inertias and masses")
    ap.add_argument("--level", default="torsional", choices=("torsional", "lateral_torsional"))
    ap.add_argument("--planetwear", default=os.path.join(HERE, "..", "..", "build", "apps", "planetwear"))
    ap.add_argument("-o", "--output", default="fault_transfer", help="directory for the four recordings")
    a = ap.parse_args(argv)
    if not 0 < a.factor <= 1:
        sys.exit(f"error: --factor {a.factor} is outside (0, 1]")
    g = sim4corpus.GEARSETS[a.gearset]
    if a.op not in g["ops"]:
        sys.exit(f"error: --op {a.op}: the gear set's operating points are {sorted(g['ops'])}")
    rpm, power, fs_daq = g["ops"][a.op]
    gs, rig = g["gear"], g["rig"]
    st = sim4.Stage(gs, rig)
    os.makedirs(a.output, exist_ok=True)
    if a.friction_factor < 0:
        sys.exit(f"error: --friction-factor {a.friction_factor} is negative")
    fault = sim4.Faults(tooth_body=a.body, tooth_planet=a.planet, tooth_index=a.tooth, tooth_stiffness_factor=a.factor,
                        friction_factor=a.friction_factor)
    cases = [sim4.Case(rpm, power, a.seconds, fs_daq=fs_daq, faults=f)
             for f in (sim4.Faults(friction_factor=a.friction_factor), fault)]
    print(f"indepsim4: {a.gearset} at {rpm:g} rpm, {power:g} W, {a.seconds:g} s, healthy and {a.body} tooth "
          f"{a.tooth} x{a.factor} (noise-free) ...", flush=True)
    res, _ = sim4.simulate_batch(st, cases)
    toml = os.path.join(a.output, "gearset.toml")
    with open(toml, "w") as f:
        f.write(writers.gearset_toml(gs, "indepsim4", "fault_transfer.py"))
    for name, r in zip(("indepsim4_healthy", "indepsim4_fault"), res):
        ch = {"sun_speed": r["sun_rpm"], "carrier_speed": r["carrier_rpm"], "acc_housing": r["housing"],
              "acc_sun_planet0": r["a_sp0"], "acc_planet0_ring": r["a_pr0"]}
        writers.write_recording(os.path.join(a.output, name + ".csv"), r["time"], ch, rpm, power,
                                r["sensor_angle_deg"], fs_daq, "fault_transfer.py", "noise-free")
    sets = rig_settings(st, rig, a.rig_inertias) + [f"solver.level={a.level}",
                                                    f"contact.friction_coefficient={gs.friction * a.friction_factor:.6g}"]
    tooth = (f'imperfections.teeth=[{{body="{a.body}",tooth={a.tooth},stiffness_factor={a.factor}}}]'
             if a.body != "planet" else
             f'imperfections.teeth=[{{body="planet",planet={a.planet},tooth={a.tooth},stiffness_factor={a.factor}}}]')
    for name, extra in (("planetwear_healthy", []), ("planetwear_fault", [tooth])):
        cmd = [a.planetwear, "synth", "-q", "-c", toml, "--speed-rpm", str(rpm), "--power-w", str(power),
               "--noise", "0", "--seconds", str(a.seconds), "-o", os.path.join(a.output, name + ".csv")]
        for s in sets + extra:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True)
    print("planetwear --set: " + " ".join(sets), flush=True)
    h5 = os.path.join(a.output, "planetwear_modes.h5")
    cmd = [a.planetwear, "simulate", "-q", "-c", toml, "--speed-rpm", str(rpm), "--power-w", str(power), "-o", h5]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    import h5py
    with h5py.File(h5) as f:
        grp = f["scalars/natural_frequency"]
        pw_modes = sorted(float(grp[k][()]) for k in grp)
    print("natural frequencies below 1 kHz [Hz]: indepsim4 " +
          ", ".join(f"{fr:.1f} (zeta {z:.3f})" for fr, z in indepsim4_natural_frequencies(st) if fr < 1000) +
          "; planetwear (torsional, undamped) " + ", ".join(f"{fr:.1f}" for fr in pw_modes if fr < 1000))
    f_fam = family_frequency(gs, a.body, rpm)
    amp = {}
    for name in ("indepsim4_fault", "planetwear_fault"):
        t, ch = read_csv(os.path.join(a.output, name + ".csv"))
        amp[name] = {q: [line_amplitude(ch[q], t, m * f_fam) for m in range(1, a.orders + 1)] for q in CHANNELS if q in ch}
    print(f"\nlines of the fault recordings at m x {f_fam:.4g} Hz ({a.body} family); speeds [rad/s], accelerations [m/s^2]")
    for q in CHANNELS:
        s4, pw = np.array(amp["indepsim4_fault"][q]), np.array(amp["planetwear_fault"][q])
        print(f"\n{q}\n    m  f [Hz]       indepsim4      planetwear   ratio")
        for m in range(1, a.orders + 1):
            i = m - 1
            ratio = f"{pw[i] / s4[i]:7.3g}" if s4[i] >= RELATIVE_FLOOR * s4.max() else "      -"
            print(f"  {m:3d} {m * f_fam:7.1f}  {s4[i]:14.4g}  {pw[i]:14.4g}  {ratio}")


if __name__ == "__main__":
    main()
