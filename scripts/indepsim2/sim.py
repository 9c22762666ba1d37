#!/usr/bin/env python3
"""indepsim2: a second, independent simulator of a planetary stage on a test rig.

Planar lateral-torsional lumped model (after Lin & Parker 1999, J. Vib. Acoust. 121:316)
in a reference frame rotating at the constant nominal carrier speed; Coriolis and
centripetal terms are neglected in the equations of motion (Omega_c << modal frequencies).
Time-varying mesh stiffness from the Kuang & Yang (1992) single-tooth stiffness law,
summed over the tooth pairs on the path of contact (tip circles), planet phasing as in
Parker & Lin 2004 (derived here from tooth positions), backlash dead zone per pair,
Coulomb friction smoothed by arctan of the sliding velocity, Rayleigh damping.
Rig: speed-controlled motor (PI) -> flexible input shaft -> sun; carrier -> flexible
output shaft -> torque-controlled brake.  Integrator: scipy solve_ivp DOP853 (adaptive).
Sensors: two optical encoders (quantised angle, differenced, low-passed) and one housing
accelerometer (ring translation along its radial direction, mount resonance, anti-alias).

See README.md in this directory for the equations, parameter values and sources.
No code of planetwear or of scripts/indepsim is used or imported.
"""
import json
import math
import os
import tomllib

import numpy as np
from scipy import linalg, signal
from scipy.integrate import solve_ivp

G0 = 9.80665
TWO_PI = 2.0 * math.pi


# ----------------------------------------------------------------------------------------
# gear set (only what a rig's documentation gives)
# ----------------------------------------------------------------------------------------
def read_gearset(path):
    with open(path, "rb") as f:
        d = tomllib.load(f)
    return gearset_from_dict(d)


def gearset_from_dict(d):
    st = d["stage"]
    gs = {"N": int(st["planet_count"])}
    for body in ("sun", "planet", "ring"):
        g = st[body]
        alpha = math.radians(g["pressure_angle_deg"]) if "pressure_angle_deg" in g else g["pressure_angle_rad"]
        gs[body] = dict(Z=int(g["teeth"]), m=float(g["module_m"]), alpha=alpha, b=float(g["face_width_m"]),
                        ha=float(g.get("addendum_coef", 1.0)), hf=float(g.get("dedendum_coef", 1.25)),
                        E=float(g.get("youngs_modulus_Pa", 206e9)), rho=float(g.get("density_kg_m3", 7850.0)))
    c = d.get("contact", {})
    gs["mu"] = float(c.get("friction_coefficient", 0.05))
    gs["backlash_sp"] = float(c.get("backlash_sun_planet_m", 0.0))
    gs["backlash_rp"] = float(c.get("backlash_planet_ring_m", 0.0))
    return gs


def gearset_toml(name, Zs, Zp, Zr, N, module, width, mu=0.06, backlash=1e-5, alpha_deg=20.0):
    """TOML text with only documented geometry, material, friction and design backlash."""
    out = [f"# Gear set '{name}' of the indepsim2 test rig: what its documentation gives.",
           "# Geometry, tooth counts, module, face width, material, friction, design backlash.",
           "# Rig internals (shafts, motor, brake, bearings, sensors) are not given.", "",
           "[stage]", f"planet_count = {N}", ""]
    for body, Z in (("sun", Zs), ("planet", Zp), ("ring", Zr)):
        out += [f"[stage.{body}]", f"teeth = {Z}", f"module_m = {module}", f"pressure_angle_deg = {alpha_deg:g}",
                f"face_width_m = {width}", "addendum_coef = 1.0", "dedendum_coef = 1.25",
                "youngs_modulus_Pa = 206000000000.0", "poisson_ratio = 0.3", "density_kg_m3 = 7850.0", ""]
    out += ["[contact]", f"friction_coefficient = {mu}", f"backlash_sun_planet_m = {backlash}",
            f"backlash_planet_ring_m = {backlash}", ""]
    return "\n".join(out)


# ----------------------------------------------------------------------------------------
# Kuang & Yang (1992) single-tooth stiffness [N/(mm um) = 1e9 N/m per m of face width]
#   K(r) = (A0 + A1 X) + (A2 + A3 X) (r - R) / ((1 + X) m)
#   A0 = 3.867 + 1.612 Z - 0.02916 Z^2 + 0.0001553 Z^3
#   A1 = 17.060 + 0.7289 Z - 0.01728 Z^2 + 0.0000999 Z^3
#   A2 = 2.637 - 1.222 Z + 0.02217 Z^2 - 0.0001179 Z^3
#   A3 = -6.330 - 1.033 Z + 0.02068 Z^2 - 0.0001130 Z^3
# (r - R): radius of the contact point minus the pitch radius (toward the tip positive);
# X profile shift (0 here).  Internal ring teeth: same law with the height measured toward
# the ring's tip (inward), Z clamped to [12, 100] (an approximation, README).
# ----------------------------------------------------------------------------------------
def ky_coefficients(Z):
    Z = float(min(max(Z, 12.0), 100.0))
    A0 = 3.867 + 1.612 * Z - 0.02916 * Z ** 2 + 0.0001553 * Z ** 3
    A1 = 17.060 + 0.7289 * Z - 0.01728 * Z ** 2 + 0.0000999 * Z ** 3
    A2 = 2.637 - 1.222 * Z + 0.02217 * Z ** 2 - 0.0001179 * Z ** 3
    A3 = -6.330 - 1.033 * Z + 0.02068 * Z ** 2 - 0.0001130 * Z ** 3
    return A0, A1, A2, A3


def ky_tooth_stiffness(Z, h_over_m, X=0.0):
    """Single-tooth stiffness per unit face width [N/m per m] at height h (from the pitch
    circle toward the tip) in modules."""
    A0, A1, A2, A3 = ky_coefficients(Z)
    K = (A0 + A1 * X) + (A2 + A3 * X) * np.asarray(h_over_m) / (1.0 + X)
    return 1e9 * np.maximum(K, 0.5)


# ----------------------------------------------------------------------------------------
# geometry of the two mesh types along their lines of action
# ----------------------------------------------------------------------------------------
def mesh_geometry(gs, ramp_fraction=0.03, ntab=1201):
    s, p, r = gs["sun"], gs["planet"], gs["ring"]
    m, al = s["m"], s["alpha"]
    b = min(s["b"], p["b"], r["b"])
    rs, rp, rr = m * s["Z"] / 2, m * p["Z"] / 2, m * r["Z"] / 2
    rbs, rbp, rbr = rs * math.cos(al), rp * math.cos(al), rr * math.cos(al)
    ras, rap, rar = rs + s["ha"] * m, rp + p["ha"] * m, rr - r["ha"] * m
    pb = math.pi * m * math.cos(al)
    sa = math.sin(al)
    geo = dict(m=m, alpha=al, b=b, rs=rs, rp=rp, rr=rr, rc=rs + rp, rbs=rbs, rbp=rbp, rbr=rbr,
               ras=ras, rap=rap, rar=rar, pb=pb, Zs=s["Z"], Zp=p["Z"], Zr=r["Z"])
    meshes = {}
    # sun-planet: gear 1 = sun (driver), gear 2 = planet; x from the pitch point along n
    xA = max(-math.sqrt(rap ** 2 - rbp ** 2) + rp * sa, -rs * sa)
    xE = min(math.sqrt(ras ** 2 - rbs ** 2) - rs * sa, rp * sa)
    meshes["sp"] = dict(xA=xA, xE=xE, xi1P=rs * sa, xi2P=-rp * sa, rb1=rbs, rb2=rbp, R1=rs, R2=rp,
                        Z1=s["Z"], Z2=p["Z"], internal2=False)
    # planet-ring (carrier frame: planet drives ring): gear 1 = planet, gear 2 = ring
    xA = max(math.sqrt(rar ** 2 - rbr ** 2) - rr * sa, -rp * sa)
    xE = math.sqrt(rap ** 2 - rbp ** 2) - rp * sa
    meshes["rp"] = dict(xA=xA, xE=xE, xi1P=rp * sa, xi2P=rr * sa, rb1=rbp, rb2=rbr, R1=rp, R2=rr,
                        Z1=p["Z"], Z2=r["Z"], internal2=True)
    for key, me in meshes.items():
        me["eps"] = (me["xE"] - me["xA"]) / pb
        me["xmax"] = max(-me["xA"], me["xE"])
        x = np.linspace(me["xA"], me["xE"], ntab)
        me["xtab"] = x
        me["ktab"] = pair_stiffness(me, x, b, pb, ramp_fraction)
        # mean combined stiffness over one base pitch
        nn = np.linspace(0, 1, 4001)[:-1]
        me["kmean"] = float(np.mean(combined_stiffness(me, nn, pb)))
    geo["meshes"] = meshes
    return geo


def pair_stiffness(me, x, b, pb, ramp_fraction=0.03):
    """Stiffness [N/m] of one tooth pair at position x (from the pitch point) on the path
    of contact: Kuang-Yang tooth stiffnesses of both teeth in series times face width,
    with a short smooth (cubic smoothstep) ramp of ramp_fraction * pb at both ends of
    the path of contact (tip rounding)."""
    x = np.asarray(x, dtype=float)
    xi1 = me["xi1P"] + x
    xi2 = me["xi2P"] + x
    r1 = np.sqrt(me["rb1"] ** 2 + xi1 ** 2)
    r2 = np.sqrt(me["rb2"] ** 2 + xi2 ** 2)
    m = pb / (math.pi * math.cos(math.acos(me["rb1"] / me["R1"])))
    h1 = (r1 - me["R1"]) / m
    h2 = ((me["R2"] - r2) if me["internal2"] else (r2 - me["R2"])) / m
    K1 = ky_tooth_stiffness(me["Z1"], h1)
    K2 = ky_tooth_stiffness(me["Z2"], h2)
    k = b * K1 * K2 / (K1 + K2)
    L = ramp_fraction * pb
    u = np.clip(np.minimum(x - me["xA"], me["xE"] - x) / L, 0.0, 1.0)
    w = u * u * (3.0 - 2.0 * u)
    return k * w * ((x >= me["xA"]) & (x <= me["xE"]))


def pair_k(me, x):
    return np.interp(x, me["xtab"], me["ktab"], left=0.0, right=0.0)


def combined_stiffness(me, n, pb):
    """Mesh stiffness [N/m] at mesh phase n (pair m at the pitch point when n = m)."""
    n = np.asarray(n, dtype=float)
    m0 = np.ceil(n - me["xE"] / pb)
    k = 0.0
    for j in range(4):
        k = k + pair_k(me, (n - (m0 + j)) * pb)
    return k


def iso6336_mesh_stiffness_per_width(Z1, Z2, eps, internal=False):
    """ISO 6336-1 method B c_gamma_alpha [N/m per m] for unshifted standard gears
    (C_M = 0.8, C_R = 1, C_B = 1 for h_fP = 1.25 m, alpha = 20 deg); internal: z_n2 -> inf."""
    z2 = math.inf if internal else Z2
    q = 0.04723 + 0.15551 / Z1 + (0.0 if internal else 0.25791 / z2)
    cp = 0.8 / q * (1 + 0.5 * (1.2 - 1.25)) * 1.0
    return 1e9 * cp * (0.75 * eps + 0.25)


# ----------------------------------------------------------------------------------------
# lumped parameters (rig internals: assumptions, README)
# ----------------------------------------------------------------------------------------
RIG_DEFAULTS = dict(
    bore_ratio=0.3, sun_hub_factor=3.0, ring_rim_modules=3.0, housing_mass_kg=5.0,
    carrier_plate_thickness_m=0.010,
    k_sun_bearing=2e8, k_carrier_bearing=5e8, k_planet_radial=4e8, k_planet_tangential=3e8,
    k_ring_mount=1e9, k_ring_torsion_per_rb2=1e9,
    motor_inertia=0.12, input_shaft_k=2.0e4, input_shaft_c=4.0,
    brake_inertia=0.6, output_shaft_k=2.5e5, output_shaft_c=40.0,
    speed_loop_bw_Hz=3.0, zeta_rayleigh=0.03, rayleigh_f2_over_f1=None,
    friction_v_eps=0.01, ramp_fraction=0.03,
    encoder_lines=2048, encoder_interp=4096, encoder_lp_Hz=1000.0,
    acc_resonance_Hz=3500.0, acc_resonance_zeta=0.05, acc_antialias_Hz=4000.0,
    housing_gain=1.0, sensor_angle_housing_deg=75.0,
)


def lumped_parameters(gs, rig=None):
    rig = dict(RIG_DEFAULTS, **(rig or {}))
    geo = mesh_geometry(gs, rig["ramp_fraction"])
    s, p, r = gs["sun"], gs["planet"], gs["ring"]
    m = geo["m"]
    rho = s["rho"]

    def disc(rad_out, rad_in, b, rho_):
        mass = rho_ * b * math.pi * (rad_out ** 2 - rad_in ** 2)
        return mass, 0.5 * mass * (rad_out ** 2 + rad_in ** 2)

    rs_root = geo["rs"] - s["hf"] * m
    rp_root = geo["rp"] - p["hf"] * m
    ms, Is = disc(rs_root, rig["bore_ratio"] * rs_root, s["b"], rho)
    ms *= rig["sun_hub_factor"]
    Is *= rig["sun_hub_factor"]
    mp, Ip = disc(rp_root, rig["bore_ratio"] * rp_root, p["b"], rho)
    rr_out = geo["rr"] + r["hf"] * m + rig["ring_rim_modules"] * m
    mr, Ir = disc(rr_out, geo["rar"], r["b"], rho)
    mr += rig["housing_mass_kg"]
    Ir += rig["housing_mass_kg"] * rr_out ** 2
    Rcp = geo["rc"] + 0.6 * geo["rp"]
    mc, Ic = disc(Rcp, 0.0, 2 * rig["carrier_plate_thickness_m"], rho)
    par = dict(N=gs["N"], alpha=geo["alpha"], rbs=geo["rbs"], rbp=geo["rbp"], rbr=geo["rbr"], rc=geo["rc"],
               ms=ms, Is=Is, mr=mr, Ir=Ir, mc=mc, Ic=Ic, mp=mp, Ip=Ip,
               ksp=geo["meshes"]["sp"]["kmean"], krp=geo["meshes"]["rp"]["kmean"],
               ks=rig["k_sun_bearing"], kc=rig["k_carrier_bearing"], kr=rig["k_ring_mount"],
               kpr=rig["k_planet_radial"], kpt=rig["k_planet_tangential"],
               kst=0.0, kct=0.0, krt=rig["k_ring_torsion_per_rb2"] * geo["rbr"] ** 2,
               Jm=rig["motor_inertia"], kin=rig["input_shaft_k"], cin=rig["input_shaft_c"],
               Jb=rig["brake_inertia"], kout=rig["output_shaft_k"], cout=rig["output_shaft_c"], rig=True)
    return par, geo, rig


# ----------------------------------------------------------------------------------------
# linear structure: DOFs, mass, bearing stiffness, mesh projection vectors
#   DOFs (rotating frame): sun x,y,theta | ring x,y,theta | carrier x,y,theta |
#   planet i x,y,theta (i = 0..N-1) | motor theta | brake theta   (angles in rad)
# ----------------------------------------------------------------------------------------
def J(v):
    return np.array([-v[1], v[0]])


def build_linear(par):
    N = par["N"]
    al = par["alpha"]
    rig = par.get("rig", False)
    nd = 9 + 3 * N + (2 if rig else 0)
    IS, IR, IC = 0, 3, 6
    IP = [9 + 3 * i for i in range(N)]
    IM, IB = (9 + 3 * N, 10 + 3 * N) if rig else (None, None)
    psi = np.array(par.get("psi", [TWO_PI * i / N for i in range(N)]))
    M = np.zeros(nd)
    M[IS:IS + 3] = [par["ms"], par["ms"], par["Is"]]
    M[IR:IR + 3] = [par["mr"], par["mr"], par["Ir"]]
    M[IC:IC + 3] = [par["mc"], par["mc"], par["Ic"]]
    for i in range(N):
        M[IP[i]:IP[i] + 3] = [par["mp"], par["mp"], par["Ip"]]
    if rig:
        M[IM], M[IB] = par["Jm"], par["Jb"]
    stage = np.zeros(nd, bool)
    stage[:9 + 3 * N] = True

    springs = []   # (g, k, kind, tag)

    def unit(i):
        g = np.zeros(nd)
        g[i] = 1.0
        return g

    for (i0, k) in ((IS, par["ks"]), (IR, par["kr"]), (IC, par["kc"])):
        springs += [(unit(i0), k, "ground", None), (unit(i0 + 1), k, "ground", None)]
    for (i0, k) in ((IS, par["kst"]), (IR, par["krt"]), (IC, par["kct"])):
        if k > 0:
            springs.append((unit(i0 + 2), k, "ground", None))
    er = np.stack([np.cos(psi), np.sin(psi)], 1)
    et = np.stack([-np.sin(psi), np.cos(psi)], 1)
    for i in range(N):
        Ci = par["rc"] * er[i]
        for (e, k, tag) in ((er[i], par["kpr"], "r"), (et[i], par["kpt"], "t")):
            g = np.zeros(nd)
            g[IP[i]:IP[i] + 2] = e
            g[IC:IC + 2] = -e
            g[IC + 2] = -e @ J(Ci)
            springs.append((g, k, "pin", (i, tag)))
    shafts = []
    if rig:
        g = np.zeros(nd); g[IM] = 1.0; g[IS + 2] = -1.0
        shafts.append((g, par["kin"], par["cin"]))
        g = np.zeros(nd); g[IC + 2] = 1.0; g[IB] = -1.0
        shafts.append((g, par["kout"], par["cout"]))

    # meshes: columns 0..N-1 sun-planet, N..2N-1 planet-ring
    G = np.zeros((nd, 2 * N))      # delta = G^T q
    Tt = np.zeros((nd, 2 * N))     # friction translation directions (force on gear1 = -phi t)
    R1 = np.zeros((nd, 2 * N))
    R2 = np.zeros((nd, 2 * N))
    nvec = np.zeros((2 * N, 2))
    rs_pitch = par["rbs"] / math.cos(al)
    rp_pitch = par["rbp"] / math.cos(al)
    rr_pitch = par["rbr"] / math.cos(al)
    for i in range(N):
        Ci = par["rc"] * er[i]
        for j, n, r1v, b1, r2v, b2 in (
                # sun-planet: gear 1 sun, gear 2 planet; force on the planet along n = sin(a) e_r + cos(a) e_t;
                # r1v = P - c_sun, r2v = P - c_planet at the pitch point P
                (i, math.sin(al) * er[i] + math.cos(al) * et[i], rs_pitch * er[i], IS, -rp_pitch * er[i], IP[i]),
                # planet-ring: gear 1 planet, gear 2 ring; force on the ring along n = sin(a) e_r - cos(a) e_t
                (N + i, math.sin(al) * er[i] - math.cos(al) * et[i], rp_pitch * er[i], IP[i], rr_pitch * er[i], IR)):
            # delta = n . (u_1(P) - u_2(P)),  u_k(P) = (x_k, y_k) + theta_k J(P - c_k)
            G[b1:b1 + 2, j] = n
            G[b1 + 2, j] = n @ J(r1v)
            G[b2:b2 + 2, j] = -n
            G[b2 + 2, j] = -(n @ J(r2v))
            t = J(n)
            Tt[b1:b1 + 2, j] = -t
            Tt[b2:b2 + 2, j] = t
            R1[b1 + 2, j] = 1.0
            R2[b2 + 2, j] = 1.0
            nvec[j] = n
    Kb = np.zeros((nd, nd))
    for g, k, kind, tag in springs:
        Kb += k * np.outer(g, g)
    Kshaft = np.zeros((nd, nd))
    Cshaft = np.zeros((nd, nd))
    for g, k, c in shafts:
        Kshaft += k * np.outer(g, g)
        Cshaft += c * np.outer(g, g)
    kbar = np.r_[np.full(N, par["ksp"]), np.full(N, par["krp"])]
    Kmesh = (G * kbar) @ G.T
    return dict(nd=nd, N=N, IS=IS, IR=IR, IC=IC, IP=IP, IM=IM, IB=IB, psi=psi, er=er, et=et, M=M, stage=stage,
                springs=springs, Kb=Kb, Kshaft=Kshaft, Cshaft=Cshaft, G=G, Tt=Tt, R1=R1, R2=R2, nvec=nvec,
                kbar=kbar, Kmesh=Kmesh, Klin=Kb + Kshaft + Kmesh)


def natural_frequencies(lin, kscale=1.0, exclude_rig=False):
    K = lin["Kb"] + lin["Kshaft"] + kscale * lin["Kmesh"]
    M = np.diag(lin["M"])
    if exclude_rig and lin["IM"] is not None:
        keep = lin["stage"]
        K, M = K[np.ix_(keep, keep)], M[np.ix_(keep, keep)]
    w2, V = linalg.eigh(K, M)
    return np.sqrt(np.maximum(w2, 0.0)) / TWO_PI, V


def rayleigh_coefficients(lin, zeta=0.03, f2_over_f1=None):
    """alpha, beta of C = alpha M + beta K (stage) with zeta(f) = alpha/(2 w) + beta w/2 equal to
    zeta at f1, the lowest mode whose strain energy is mostly (> 50 %) in the stage (bearings and
    meshes, not the rig's shafts), and at f2, the lowest mode with >= 25 % of its strain energy in
    the meshes (or f2_over_f1 * f1 if given). Between them zeta is a little lower, above f2 higher."""
    f, V = natural_frequencies(lin)
    K = lin["Klin"]
    Kst = lin["Kb"] + lin["Kmesh"]
    f1 = f2 = None
    for k in range(len(f)):
        if f[k] < 1.0:
            continue
        v = V[:, k]
        e_tot = v @ K @ v
        if f1 is None and (v @ Kst @ v) / e_tot > 0.5:
            f1 = f[k]
        if f2 is None and (v @ lin["Kmesh"] @ v) / e_tot >= 0.25:
            f2 = f[k]
    if f2_over_f1 is not None or f2 is None or f2 <= f1:
        f2 = f1 * (f2_over_f1 or 3.0)
    w1, w2 = TWO_PI * f1, TWO_PI * f2
    beta = 2 * zeta / (w1 + w2)
    alpha = beta * w1 * w2
    return alpha, beta, (f1, f2)


# ----------------------------------------------------------------------------------------
# the model for a batch of recordings (columns) of one gear set
# ----------------------------------------------------------------------------------------
class Batch:
    """cases: list of dicts with keys rpm, power_W and optional effect parameters:
    tooth damage ('sun_tooth': {index: factor}, 'planet_tooth': {(planet, index): factor},
    'ring_tooth': {index: factor}), pin_error_m (list), sun_ecc_m, sun_ecc_phase_rad,
    carrier_ecc_m, carrier_ecc_phase_rad, stiffness_scale, damping_scale, mu,
    ripple_fraction, ripple_order, ripple_phase_rad, worn_depth_m, backlash_m,
    plus 'static' True for a non-rotating test case (no speed, no load)."""

    def __init__(self, gs, cases, rig=None, par_override=None):
        self.gs = gs
        self.par, self.geo, self.rig = lumped_parameters(gs, rig)
        if par_override:
            self.par.update(par_override)
        self.lin = build_linear(self.par)
        L = self.lin
        self.alpha0, self.beta0, self.f_rayleigh = rayleigh_coefficients(L, self.rig["zeta_rayleigh"],
                                                                         self.rig["rayleigh_f2_over_f1"])
        self.cases = cases
        B = self.B = len(cases)
        N = self.N = gs["N"]
        geo = self.geo
        Zs, Zp, Zr = geo["Zs"], geo["Zp"], geo["Zr"]
        self.c_r = ((Zp - 1) / 2.0) % 1.0     # ring phase offset (planet tooth phasing)
        # integer offsets J_i: planet tooth index at ring pair m is (m - J_i) mod Zp
        self.Joff = np.array([round((Zs + Zr) * i / N - self.c_r - (1 - Zp) / 2.0) for i in range(N)])
        col = lambda key, default: np.array([float(c.get(key, default)) for c in cases])
        rpm = col("rpm", 0.0)
        self.Om_s = rpm * TWO_PI / 60.0
        self.Om_c = self.Om_s * Zs / (Zs + Zr)
        P = col("power_W", 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            self.T0 = np.where(self.Om_s > 0, P / np.where(self.Om_s > 0, self.Om_s, 1), 0.0)
            self.TL = np.where(self.Om_c > 0, P / np.where(self.Om_c > 0, self.Om_c, 1), 0.0)
        self.T0 = col("motor_torque_Nm", 0.0) + self.T0 if any("motor_torque_Nm" in c for c in cases) else self.T0
        Jeq = self.par["Jm"] + self.par["Is"] + (self.par["Ic"] + self.par["Jb"] + N * self.par["mp"] * self.par["rc"] ** 2) \
            * (Zs / (Zs + Zr)) ** 2
        wbw = TWO_PI * self.rig["speed_loop_bw_Hz"]
        self.Kp = np.array([0.0 if c.get("static") else 2 * 0.8 * wbw * Jeq for c in cases])
        self.Ki = np.array([0.0 if c.get("static") else wbw ** 2 * Jeq for c in cases])
        self.kscale = col("stiffness_scale", 1.0)
        ds = col("damping_scale", 1.0)
        self.alpha = self.alpha0 * ds
        self.beta = self.beta0 * ds
        self.shaft_c_scale = np.array([0.0 if c.get("undamped") else 1.0 for c in cases])
        self.mu = np.array([float(c.get("mu", gs["mu"])) for c in cases])
        self.b_sp = np.array([float(c.get("backlash_m", gs["backlash_sp"])) for c in cases])
        self.b_rp = np.array([float(c.get("backlash_m", gs["backlash_rp"])) for c in cases])
        self.wear = col("worn_depth_m", 0.0)
        self.e_s = col("sun_ecc_m", 0.0)
        self.ph_s = col("sun_ecc_phase_rad", 0.0)
        self.rip = col("ripple_fraction", 0.0)
        self.rip_ord = col("ripple_order", 1.0)
        self.rip_ph = col("ripple_phase_rad", 0.0)
        # tooth factors
        self.fs = np.ones((Zs, B))
        self.fp = np.ones((N, Zp, B))
        self.fr = np.ones((Zr, B))
        for b, c in enumerate(cases):
            for k, f in c.get("sun_tooth", {}).items():
                self.fs[int(k) % Zs, b] = f
            for (i, k), f in c.get("planet_tooth", {}).items():
                self.fp[int(i), int(k) % Zp, b] = f
            for k, f in c.get("ring_tooth", {}).items():
                self.fr[int(k) % Zr, b] = f
        self.has_damage = bool((self.fs != 1).any() or (self.fp != 1).any() or (self.fr != 1).any())
        # constant generalised forces from pin errors and carrier eccentricity (bearing offsets)
        nd = L["nd"]
        self.f_off = np.zeros((nd, B))
        for b, c in enumerate(cases):
            pe = c.get("pin_error_m", [0.0] * N)
            ec = float(c.get("carrier_ecc_m", 0.0))
            Ec = ec * np.array([math.cos(c.get("carrier_ecc_phase_rad", 0.0)),
                                math.sin(c.get("carrier_ecc_phase_rad", 0.0))])
            for g, k, kind, tag in L["springs"]:
                if kind != "pin":
                    continue
                i, d = tag
                e = L["er"][i] if d == "r" else L["et"][i]
                off = e @ Ec + (pe[i] if d == "t" else 0.0)
                self.f_off[:, b] += k * off * g
        # matrices
        self.Minv = 1.0 / L["M"]
        self.Mst = L["M"] * L["stage"]
        Kst = L["Kb"].copy()
        self.Kbs = Kst                      # stage bearings (Rayleigh beta part)
        self.Kall = L["Kb"] + L["Kshaft"]
        self.Cshaft = L["Cshaft"]
        self.Gx = np.hstack([L["G"], L["Tt"], L["R1"], L["R2"]])
        self.GT = L["G"].T.copy()
        me_sp, me_rp = geo["meshes"]["sp"], geo["meshes"]["rp"]
        self.me = (me_sp, me_rp)
        self.pb = geo["pb"]
        self.xE = np.r_[np.full(N, me_sp["xE"]), np.full(N, me_rp["xE"])][:, None, None]
        self.xi1P = np.r_[np.full(N, me_sp["xi1P"]), np.full(N, me_rp["xi1P"])][:, None, None]
        self.xi2P = np.r_[np.full(N, me_sp["xi2P"]), np.full(N, me_rp["xi2P"])][:, None, None]
        self.xmax = np.r_[np.full(N, me_sp["xmax"]), np.full(N, me_rp["xmax"])][:, None, None]
        self.kbar = L["kbar"][:, None]
        self.angn = np.arctan2(L["nvec"][:N, 1], L["nvec"][:N, 0])[:, None]
        self.Zs, self.Zp, self.Zr = Zs, Zp, Zr
        self.Om_p = -(self.Om_s - self.Om_c) * Zs / Zp
        self.veps = self.rig["friction_v_eps"]
        self.nfev = 0

    # --- parameter tiling for evaluating the RHS at many samples at once
    def _cols(self, reps):
        names = ["Om_s", "Om_c", "Om_p", "T0", "TL", "Kp", "Ki", "kscale", "alpha", "beta", "shaft_c_scale", "mu",
                 "b_sp", "b_rp", "wear", "e_s", "ph_s", "rip", "rip_ord", "rip_ph"]
        d = {k: np.repeat(getattr(self, k), reps) for k in names}
        d["f_off"] = np.repeat(self.f_off, reps, axis=1)
        d["fs"] = np.repeat(self.fs, reps, axis=1)
        d["fp"] = np.repeat(self.fp, reps, axis=2)
        d["fr"] = np.repeat(self.fr, reps, axis=1)
        d["bl"] = np.repeat(self._bl(), reps, axis=2)
        return d

    def _bl(self):
        N = self.N
        return np.vstack([np.repeat(self.b_sp[None, :], N, 0), np.repeat(self.b_rp[None, :], N, 0)])[:, None, :]

    def _self_cols(self):
        names = ["Om_s", "Om_c", "Om_p", "T0", "TL", "Kp", "Ki", "kscale", "alpha", "beta", "shaft_c_scale", "mu",
                 "b_sp", "b_rp", "wear", "e_s", "ph_s", "rip", "rip_ord", "rip_ph", "f_off", "fs", "fp", "fr"]
        d = {k: getattr(self, k) for k in names}
        d["bl"] = self._bl()
        return d

    def mesh_state(self, t, q, v, C):
        """Per-pair quantities: returns dict with x, k, f (pair normal forces), delta."""
        L = self.lin
        N = self.N
        IS, IR, IC = L["IS"], L["IR"], L["IC"]
        th_s = (C["Om_s"] - C["Om_c"]) * t + q[IS + 2] - q[IC + 2]
        th_c = C["Om_c"] * t + q[IC + 2] - q[IR + 2]
        psi = L["psi"][:, None]
        n = np.vstack([self.Zs / TWO_PI * (th_s[None, :] - psi),
                       self.Zr / TWO_PI * (th_c[None, :] + psi) - self.c_r])
        m0 = np.ceil(n - self.xE[:, :, 0] / self.pb)
        m = m0[:, None, :] + np.arange(3)[None, :, None]
        x = (n[:, None, :] - m) * self.pb
        k = np.empty_like(x)
        k[:N] = pair_k(self.me[0], x[:N])
        k[N:] = pair_k(self.me[1], x[N:])
        if self.has_damage:
            mi = m.astype(np.int64)
            colix = np.arange(x.shape[2])[None, None, :]
            pl = np.arange(N)[:, None, None]
            fsun = C["fs"][(-mi[:N]) % self.Zs, colix]
            fpl_s = C["fp"][pl, mi[:N] % self.Zp, colix]
            fring = C["fr"][mi[N:] % self.Zr, colix]
            fpl_r = C["fp"][pl, (mi[N:] - self.Joff[:, None, None]) % self.Zp, colix]
            k[:N] *= fsun * fpl_s
            k[N:] *= fring * fpl_r
        k *= C["kscale"][None, None, :]
        delta = self.GT @ q
        # sun eccentricity (the sun's geometric centre rotates with the sun in the frame)
        if np.any(C["e_s"] != 0):
            ang = (C["Om_s"] - C["Om_c"]) * t + q[IS + 2] + C["ph_s"]
            delta[:N] += C["e_s"][None, :] * np.cos(ang[None, :] - self.angn)
        g = (2.0 * C["wear"])[None, None, :] * np.abs(x) / self.xmax
        bl = C["bl"]
        d3 = delta[:, None, :]
        f = k * (np.maximum(d3 - g, 0.0) - np.maximum(-d3 - bl - g, 0.0))
        return dict(n=n, x=x, k=k, f=f, delta=delta, g=g, bl=bl)

    def rhs_cols(self, t, Y, C):
        L = self.lin
        nd = L["nd"]
        N = self.N
        q = Y[:nd]
        v = Y[nd:]
        IS, IR, IC, IM, IB = L["IS"], L["IR"], L["IC"], L["IM"], L["IB"]
        ms = self.mesh_state(t, q, v, C)
        f, x = ms["f"], ms["x"]
        Fm = f.sum(axis=1)
        gate = np.any(f != 0.0, axis=1)
        dd = self.GT @ v
        Fd = gate * (C["beta"][None, :] * self.kbar) * C["kscale"][None, :] * dd
        # friction (arctan-smoothed Coulomb, pair-wise moment arms xi1, xi2)
        if np.any(C["mu"] != 0):
            w_s = C["Om_s"] - C["Om_c"] + v[IS + 2] - v[IC + 2]
            w_r = -C["Om_c"] + v[IR + 2] - v[IC + 2]
            IPth = np.array(L["IP"]) + 2
            w_p = C["Om_p"][None, :] + v[IPth] - v[IC + 2][None, :]
            w1 = np.vstack([np.repeat(w_s[None], N, 0), w_p])[:, None, :]
            w2 = np.vstack([w_p, np.repeat(w_r[None], N, 0)])[:, None, :]
            xi1 = self.xi1P + x
            xi2 = self.xi2P + x
            vrel = w1 * xi1 - w2 * xi2
            phi = C["mu"][None, None, :] * np.abs(f) * (2.0 / math.pi) * np.arctan(vrel / self.veps)
            Phi = phi.sum(axis=1)
            M1 = -(phi * xi1).sum(axis=1)
            M2 = (phi * xi2).sum(axis=1)
        else:
            Phi = M1 = M2 = np.zeros_like(Fm)
        F = -(self.Kall @ q) - C["shaft_c_scale"] * (self.Cshaft @ v) + C["f_off"]
        F -= C["alpha"] * (self.Mst[:, None] * v) + C["beta"] * (self.Kbs @ v)
        F += self.Gx @ np.vstack([-Fm - Fd, Phi, M1, M2])
        if IM is not None:
            th_m = C["Om_s"] * t + q[IM]
            F[IM] += C["T0"] * (1.0 + C["rip"] * np.cos(C["rip_ord"] * th_m + C["rip_ph"])) \
                - C["Kp"] * v[IM] - C["Ki"] * q[IM]
            F[IB] -= C["TL"]
        a = F * self.Minv[:, None]
        return np.vstack([v, a])

    # --- static solution at mean stiffness (no friction): initial state
    def static_state(self):
        L = self.lin
        nd = L["nd"]
        Y0 = np.zeros((2 * nd, self.B))
        for b in range(self.B):
            K = L["Kb"] + L["Kshaft"] + self.kscale[b] * L["Kmesh"]
            F = self.f_off[:, b].copy()
            if L["IM"] is not None:
                K = K.copy()
                K[L["IM"], L["IM"]] += max(self.Ki[b], 1.0)
                F[L["IM"]] += self.T0[b]
                F[L["IB"]] -= self.TL[b]
            Y0[:nd, b] = np.linalg.solve(K, F)
        return Y0

    def integrate(self, t_end, fs_out, y0=None, chunk_s=0.05, rtol=1e-7, atol_scale=1e-3, on_chunk=None,
                  method="DOP853"):
        """Integrate 0..t_end; samples every 1/fs_out. on_chunk(t, Y) gets each chunk's samples,
        Y shape (2 nd, B, S). Returns final state."""
        L = self.lin
        nd = L["nd"]
        B = self.B
        C = self._self_cols()
        Y = self.static_state() if y0 is None else y0.copy()
        # absolute tolerances: displacements ~ 1e-6 m scale, angles ~ 1e-5 rad
        sc = np.where(np.arange(nd) % 3 == 2, 1e-5, 1e-6)
        if L["IM"] is not None:
            sc[L["IM"]] = sc[L["IB"]] = 1e-5
        atol = np.r_[sc * atol_scale, sc * atol_scale * 1e4]
        atol = np.repeat(atol[:, None], B, axis=1).ravel()

        def fun(t, y):
            self.nfev += 1
            return self.rhs_cols(t, y.reshape(2 * nd, B), C).ravel()

        nsamp = int(round(t_end * fs_out))
        per = max(1, int(round(chunk_s * fs_out)))
        i0 = 0
        t0 = 0.0
        first = 2e-6          # a safe first step (the automatic guess may overshoot into NaN)
        if on_chunk is not None:
            on_chunk(np.array([0.0]), Y[:, :, None])
        while i0 < nsamp:
            i1 = min(nsamp, i0 + per)
            te = np.arange(i0 + 1, i1 + 1) / fs_out
            sol = solve_ivp(fun, (t0, te[-1]), Y.ravel(), method=method, t_eval=te, rtol=rtol, atol=atol,
                            first_step=first)
            if not sol.success:
                raise RuntimeError(sol.message)
            Ys = sol.y.reshape(2 * nd, B, -1)
            if on_chunk is not None:
                on_chunk(te, Ys)
            Y = Ys[:, :, -1]
            t0 = te[-1]
            i0 = i1
        return Y

    def accelerations(self, t, Ys):
        """RHS evaluated at samples: t (S,), Ys (2nd, B, S) -> accelerations (nd, B, S)."""
        nd = self.lin["nd"]
        B, S = Ys.shape[1], Ys.shape[2]
        C = self._cols(S)
        tt = np.tile(t, B)
        Yc = Ys.reshape(2 * nd, B * S)
        d = self.rhs_cols(tt, Yc, C)
        ms = self.mesh_state(tt, Yc[:nd], None, C)
        Frp = ms["f"][self.N:].sum(axis=1).reshape(self.N, B, S)
        return d[nd:].reshape(nd, B, S), Frp

    def energy(self, Y):
        """Mechanical energy of each column (for the free-vibration test): kinetic + bearings
        + shafts + mesh pair potentials. Y (2nd, B)."""
        L = self.lin
        nd = L["nd"]
        q, v = Y[:nd], Y[nd:]
        T = 0.5 * np.sum(L["M"][:, None] * v * v, axis=0)
        Vb = 0.5 * np.einsum("ib,ij,jb->b", q, self.Kall, q)
        C = self._self_cols()
        ms = self.mesh_state(0.0, q, v, C)
        k, d3, g, bl = ms["k"], ms["delta"][:, None, :], ms["g"], ms["bl"]
        Vm = 0.5 * k * (np.maximum(d3 - g, 0) ** 2 + np.maximum(-d3 - bl - g, 0) ** 2)
        return T + Vb + Vm.sum(axis=(0, 1))


# ----------------------------------------------------------------------------------------
# sensors
# ----------------------------------------------------------------------------------------
def encoder_speed(theta, fs, lines=2048, interp=4096, lp_Hz=1000.0, zi_value=None):
    """Optical encoder: angle quantised to 2 pi/(lines*interp), speed = backward difference
    over the sample interval, then a 2nd-order Butterworth low-pass (electronics), started in
    steady state. theta sampled at fs. Returns speed [rad/s] of len(theta) - 1 (aligned with
    theta[1:])."""
    dq = TWO_PI / (lines * interp)
    qa = np.floor(np.asarray(theta) / dq) * dq
    w = np.diff(qa) * fs
    bb, aa = signal.butter(2, lp_Hz, fs=fs)
    zi = signal.lfilter_zi(bb, aa) * (w[0] if zi_value is None else zi_value)
    return signal.lfilter(bb, aa, w, zi=zi)[0], dq * fs


def accelerometer_chain(a, fs_int, f_res=3500.0, zeta=0.05, f_aa=4000.0):
    """Mount resonance (base-excitation transmissibility (2 z w s + w^2)/(s^2 + 2 z w s + w^2),
    bilinear with prewarping) then a 4th-order Butterworth anti-alias low-pass, at fs_int."""
    w = TWO_PI * f_res
    num = [2 * zeta * w, w * w]
    den = [1.0, 2 * zeta * w, w * w]
    bd, ad = _bilinear_prewarp(num, den, fs_int, f_res)
    y = signal.lfilter(bd, ad, a - a[0]) + a[0]
    sos = signal.butter(4, f_aa, fs=fs_int, output="sos")
    zi = signal.sosfilt_zi(sos) * y[0]
    return signal.sosfilt(sos, y, zi=zi)[0]


def _bilinear_prewarp(num, den, fs, f0):
    # prewarped bilinear transform: s -> k (z-1)/(z+1), k = w0 / tan(w0 / (2 fs))
    w0 = TWO_PI * f0
    k = w0 / math.tan(w0 / (2 * fs))
    # second-order: num = [b1, b0] (b1 s + b0), den = [1, a1, a0]
    b1, b0 = num
    a2, a1, a0 = den
    B = np.array([b1 * k + b0, 2 * b0, b0 - b1 * k])
    A = np.array([a2 * k * k + a1 * k + a0, 2 * a0 - 2 * a2 * k * k, a2 * k * k - a1 * k + a0])
    return B / A[0], A / A[0]


def rim_parameters(bt):
    """Ring rim as an infinite Euler beam on a Winkler foundation (Hetenyi 1946): bending stiffness
    EI of the rim (face width x rim thickness), foundation modulus k_f = k_ring_mount / (pi r_rim),
    i.e. the distributed mount whose rigid translation stiffness is the ring's mount stiffness."""
    g = bt.gs["ring"]
    m = g["m"]
    h = (bt.rig["ring_rim_modules"] + g["hf"]) * m
    r_rim = m * g["Z"] / 2 + g["hf"] * m + 0.5 * bt.rig["ring_rim_modules"] * m
    EI = g["E"] * g["b"] * h ** 3 / 12.0
    kf = bt.rig["k_ring_mount"] / (math.pi * r_rim)
    beta = (kf / (4 * EI)) ** 0.25
    return dict(EI=EI, kf=kf, beta=beta, r_rim=r_rim)


def rim_influence(rim, s):
    """Radial deflection [m/N] at arc distance s from a radial point load (Hetenyi):
    w = beta/(2 k_f) exp(-beta|s|) (cos beta|s| + sin beta|s|)."""
    bs = rim["beta"] * np.abs(s)
    return rim["beta"] / (2 * rim["kf"]) * np.exp(-bs) * (np.cos(bs) + np.sin(bs))


def rim_deflection_at_sensor(rim, theta_c, psi, phi_s, Fr):
    """Sum over planets of the influence of each planet-ring mesh's radial force component Fr (N, S)
    at the sensor angle phi_s (housing frame); planet i's mesh at housing angle theta_c + psi_i."""
    w = np.zeros(Fr.shape[1])
    for i, ps in enumerate(psi):
        d = np.angle(np.exp(1j * (theta_c + ps - phi_s)))
        for k in (-1, 0, 1):
            w += rim_influence(rim, (d + TWO_PI * k) * rim["r_rim"]) * Fr[i]
    return w


# ----------------------------------------------------------------------------------------
# recording files (docs/recordings.md: CSV + JSON sidecar)
# ----------------------------------------------------------------------------------------
def write_recording(csv_path, t, w_sun_rpm, w_carrier, acc_g, rpm, power_W, sensor_angle_deg, description,
                    generator="scripts/indepsim2/sim.py (second independent simulator)"):
    os.makedirs(os.path.dirname(csv_path) or ".", exist_ok=True)
    data = np.column_stack([t, w_sun_rpm, w_carrier, acc_g])
    tmp = csv_path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# indepsim2 rig DAQ export\n")
        f.write("time,w_sun,w_carrier,acc_housing\n")
        np.savetxt(f, data, fmt=["%.8f", "%.6f", "%.7f", "%.8g"], delimiter=",")
    os.replace(tmp, csv_path)
    meta = {
        "description": description,
        "generator": generator,
        "operating": {"input_speed_rpm": rpm, "input_power_W": power_W},
        "time_column": "time",
        "time_unit": "s",
        "columns": {
            "w_sun": {"quantity": "sun_speed", "unit": "rpm"},
            "w_carrier": {"quantity": "carrier_speed", "unit": "rad/s"},
            "acc_housing": {"quantity": "housing_acceleration", "unit": "g",
                            "sensor_angle_deg": round(float(sensor_angle_deg), 4)},
        },
    }
    jp = os.path.splitext(csv_path)[0] + ".json"
    with open(jp + ".tmp", "w") as f:
        json.dump(meta, f, indent=2)
    os.replace(jp + ".tmp", jp)
    return jp


def mesh_frequency(gs, rpm):
    Zs, Zr = gs["sun"]["Z"], gs["ring"]["Z"]
    return Zs * Zr / (Zs + Zr) * rpm / 60.0


# ----------------------------------------------------------------------------------------
# run a batch of recordings
# ----------------------------------------------------------------------------------------
SENSOR_PRE_ROLL_S = 0.05   # filter pre-roll inside the warm-up [s]


def integrate_stage(bt, windows, fs, oversample, rtol, log=print):
    """Integrates the Batch bt to the end of the latest window and stores, from the earliest window's
    filter pre-roll on, what the sensors need: the sun and carrier angles, the ring's displacement,
    velocity and acceleration (rotating frame) and the planet-ring mesh forces. windows: dicts with
    start_s, duration_s. Returns (t, channels (B, S) by name, planet-ring forces (N, B, S))."""
    import time as _time
    L = bt.lin
    IS, IR, IC = L["IS"], L["IR"], L["IC"]
    fs_int = fs * oversample
    t_end = max(r["start_s"] + r["duration_s"] for r in windows) + 2.0 / fs
    store = {"t": [], "ths": [], "thc": [], "ax": [], "ay": [], "vx": [], "vy": [], "x": [], "y": [], "frp": []}
    t_first_store = min(r["start_s"] for r in windows) - SENSOR_PRE_ROLL_S - 1.0 / fs

    def on_chunk(te, Ys):
        keep = te >= t_first_store
        if not np.any(keep):
            return
        te = te[keep]
        Ys = Ys[:, :, keep]
        A, Frp = bt.accelerations(te, Ys)
        store["frp"].append(Frp)
        nd = L["nd"]
        store["t"].append(te)
        store["ths"].append(Ys[IS + 2])
        store["thc"].append(Ys[IC + 2])
        store["x"].append(Ys[IR]); store["y"].append(Ys[IR + 1])
        store["vx"].append(Ys[nd + IR]); store["vy"].append(Ys[nd + IR + 1])
        store["ax"].append(A[IR]); store["ay"].append(A[IR + 1])

    t0 = _time.time()
    bt.integrate(t_end, fs_int, on_chunk=on_chunk, rtol=rtol)
    log(f"  integrated {t_end:.2f} s for {bt.B} recordings: {bt.nfev} RHS calls, {_time.time() - t0:.0f} s")
    t = np.concatenate(store["t"])
    cat = {k: np.concatenate(v, axis=1) for k, v in store.items() if k not in ("t", "frp")}
    frp = np.concatenate(store["frp"], axis=2)          # (N, B, S) planet-ring mesh forces
    return t, cat, frp


def sensor_window(bt, t, cat, frp, rim, b, r, fs, oversample):
    """The noise-free sensor channels of column b of an integrated Batch over the window r (start_s,
    duration_s, optional housing_gain_scale, sensor_angle_housing_deg): encoder speeds w_s, w_c
    [rad/s] and the housing acceleration acc [m/s^2] at fs; also the absolute angles at the window's
    first sample, the sidecar's sensor angle and the encoders' angle samples (ths_s, thc_s from one
    sample before the window; w[j] of encoder_speed belongs to sample j + 1, so the window is
    w[k0:k0 + nout])."""
    rigp = bt.rig
    fs_int = fs * oversample
    pre = SENSOR_PRE_ROLL_S
    Om_s, Om_c = bt.Om_s[b], bt.Om_c[b]
    # absolute angles
    ths = Om_s * t + cat["ths"][b]
    thc = Om_c * t + cat["thc"][b]
    # ring acceleration in the housing frame: X = R(Om_c t) x
    ph = Om_c * t
    ax = cat["ax"][b] - 2 * Om_c * cat["vy"][b] - Om_c ** 2 * cat["x"][b]
    ay = cat["ay"][b] + 2 * Om_c * cat["vx"][b] - Om_c ** 2 * cat["y"][b]
    AX = np.cos(ph) * ax - np.sin(ph) * ay
    AY = np.sin(ph) * ax + np.cos(ph) * ay
    phs = math.radians(r.get("sensor_angle_housing_deg", rigp["sensor_angle_housing_deg"]))
    a_rigid = AX * math.cos(phs) + AY * math.sin(phs)
    # local radial rim deflection at the sensor (quasi-static beam on elastic foundation)
    w_loc = rim_deflection_at_sensor(rim, thc, bt.lin["psi"], phs, frp[:, b, :] * math.sin(bt.par["alpha"]))
    a_loc = np.zeros_like(w_loc)
    a_loc[1:-1] = (w_loc[2:] - 2 * w_loc[1:-1] + w_loc[:-2]) * fs_int ** 2
    a_loc[0], a_loc[-1] = a_loc[1], a_loc[-2]
    a_rad = a_rigid + a_loc
    # window: from start - pre (filter settling) to start + duration
    i_pre = int(np.searchsorted(t, r["start_s"] - pre - 0.5 / fs_int))
    i_0 = int(np.searchsorted(t, r["start_s"] - 0.5 / fs_int))
    nout = int(round(r["duration_s"] * fs))
    gain = rigp["housing_gain"] * r.get("housing_gain_scale", 1.0)
    acc = gain * accelerometer_chain(a_rad[i_pre:], fs_int, rigp["acc_resonance_Hz"],
                                     rigp["acc_resonance_zeta"], rigp["acc_antialias_Hz"])
    acc = acc[(i_0 - i_pre)::oversample][:nout]
    # encoders at fs: angle samples from one sample before the record's start
    ths_s = ths[i_pre:][::oversample]
    thc_s = thc[i_pre:][::oversample]
    w_s, _ = encoder_speed(ths_s, fs, rigp["encoder_lines"], rigp["encoder_interp"], rigp["encoder_lp_Hz"],
                           zi_value=Om_s)
    w_c, _ = encoder_speed(thc_s, fs, rigp["encoder_lines"], rigp["encoder_interp"], rigp["encoder_lp_Hz"],
                           zi_value=Om_c)
    k0 = (i_0 - i_pre) // oversample - 1      # w[j] belongs to sample j+1
    theta_c0 = thc[i_0]
    return dict(w_s=w_s[k0:k0 + nout], w_c=w_c[k0:k0 + nout], acc=acc, nout=nout, k0=k0, ths_s=ths_s,
                thc_s=thc_s, theta_c0=theta_c0, theta_s0=ths[i_0], phs=phs,
                sensor_angle_deg=(math.degrees(phs - theta_c0)) % 360.0, Om_s=Om_s, Om_c=Om_c)


def simulate_batch(gs, recs, fs=10000.0, oversample=4, rig=None, rtol=1e-7, log=print):
    """recs: list of dicts {case (for Batch), start_s, duration_s, noise_seed, housing_gain_scale,
    sensor_angle_housing_deg}. Returns list of dicts with t, w_sun_rpm, w_carrier, acc_g,
    sensor_angle_deg (sidecar, relative to planet 0 at the record's t = 0), theta_c0 and
    noise-free channels."""
    bt = Batch(gs, [r["case"] for r in recs], rig=rig)
    t, cat, frp = integrate_stage(bt, recs, fs, oversample, rtol, log)
    rim = rim_parameters(bt)
    out = []
    for b, r in enumerate(recs):
        sw = sensor_window(bt, t, cat, frp, rim, b, r, fs, oversample)
        w_s, w_c, acc, nout = sw["w_s"], sw["w_c"], sw["acc"], sw["nout"]
        tt = np.arange(nout) / fs
        clean = dict(w_s=w_s.copy(), w_c=w_c.copy(), acc=acc.copy())
        rng = np.random.default_rng(r["noise_seed"])
        noise = r.get("noise_fraction", 0.05)

        def noisy(xx):
            return xx + noise * np.std(xx) * rng.standard_normal(len(xx))
        w_s_n = noisy(w_s)
        w_c_n = noisy(w_c)
        acc_n = noisy(acc)
        dc = r.get("dc_offset_fraction", 0.0) * np.std(acc)
        acc_n = acc_n + dc
        out.append(dict(t=tt, w_sun_rpm=w_s_n * 60 / TWO_PI, w_carrier=w_c_n, acc_g=acc_n / G0,
                        clean=clean, sensor_angle_deg=sw["sensor_angle_deg"], theta_c0=sw["theta_c0"],
                        theta_s0=sw["theta_s0"], fs=fs, Om_s=sw["Om_s"], Om_c=sw["Om_c"]))
    return out, bt
