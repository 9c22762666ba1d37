#!/usr/bin/env python3
"""Independent torsional simulator of a planetary gear stage on a test rig.

Written from the literature only (no planetwear code, tables or config
reader); see scripts/indepsim/README.md for every equation with its source.
Run as `/usr/bin/python3 scripts/indepsim/sim.py --help` (numpy + scipy).

Model (Lin & Parker 1999, J. Vib. Acoust. 121:316, purely torsional subset)
--------------------------------------------------------------------------
Degrees of freedom (absolute angles, perturbations about the nominal rotation
Omega*t): motor m, sun s, carrier c, planets p_0..p_{N-1}, dynamometer d, plus
the integral state z of the dynamometer's speed controller. Ring fixed.

  mesh deflections (compression, line of action, [m]):
    delta_sp,i = r_bs th_s + r_bp th_pi - (r_bs + r_bp) th_c          (L&P 1999 eq. 4 torsional)
    delta_rp,i = -r_bp th_pi - (r_br - r_bp) th_c
  contact force with a dead zone b (backlash) and a static error e:
    F = k(t) g(delta - e) + c(t) d(delta)/dt [g != 0],  g(x) = x - clip(x, -b, 0)
  mesh stiffness: ISO 6336-1:2019 method B single-pair stiffness c' and mesh
    stiffness c_gamma_alpha = c'(0.75 eps_alpha + 0.25) (mean); time variation by a
    parabolic single-pair law 0.55 + 1.8 xi(1-xi) over the pair's contact
    (the form of Cai & Hayashi 1994, J. Mech. Des. 116:558 / Cai 1995, J. Mech.
    Des. 117:460), with 5 % tip-relief ramps (smoothstep) at both ends; the peak
    is scaled so that the time mean equals ISO's c_gamma_alpha b. Below a line
    load of 100 N/mm c' is reduced by (w/100)^0.25 (ISO 6336-1 method B).
  mesh phasing: Parker & Lin 2004 (J. Mech. Des. 126:365): sun meshes lag by
    Zs psi_i / 2pi mesh cycles, ring meshes lead by Zr psi_i / 2pi; the ring
    mesh of a planet follows its sun mesh by (Zp - 1)/2 cycles (opposite flanks
    of the same planet tooth; derived in README.md).
  damping: stiffness-proportional (Rayleigh beta) c(t) = beta k(t),
    beta = eta / (2 pi f_ref), loss factor eta = 0.10 at f_ref = 3 kHz.
  friction: Coulomb, mu |F| along the tooth tangent, sign reversing at the
    pitch point, smoothed tanh(s / s_eps), s_eps = 2 % of the base pitch;
    torques on sun, planet, carrier from the moment arms rho = r_b tan(alpha) +- s
    (e.g. He, Kahraman & Singh 2007 / Vaishya & Singh 2001 for the arms).
Rig: motor (torque controlled, constant torque P/Omega_s, optional ripple) ->
input shaft (k_in, c_in) -> sun; carrier -> output shaft (k_out, c_out) ->
dynamometer, speed controlled by a PI loop with torque feed-forward.
Sensors: encoders on sun and carrier (2nd-order Butterworth low-pass,
f_enc = 1 kHz), relative line-of-action accelerations of planet 0's meshes,
a housing accelerometer seeing each planet's ring-mesh force (mean removed)
through a von Mises window exp(kappa (cos d - 1)), kappa = 4 (half-power
half-width 0.6 rad), gain 2e-3 m/s^2/N; anti-alias Kaiser-window FIR
(cutoff 0.4 fs) and decimation; 5 % Gaussian noise of each channel's RMS
fluctuation; DC offsets on accelerometers.
Integrator: classical RK4 (explicit, fixed step), vectorised over a batch
of recordings; mesh stiffness, friction arms and errors are tabulated per mesh
cycle and interpolated.
"""
import dataclasses
import json
import math
import os
import sys
import time

try:
    import tomllib
except ImportError:  # pragma: no cover
    tomllib = None
import numpy as np
from scipy import signal

# ----------------------------------------------------------------------------
# Gear set description (our own dataclasses; TOML keys are the documented interface)
# ----------------------------------------------------------------------------


@dataclasses.dataclass
class Gear:
    teeth: int
    module_m: float = 0.003
    pressure_angle_rad: float = math.radians(20.0)
    face_width_m: float = 0.05
    addendum_coef: float = 1.0
    dedendum_coef: float = 1.25
    youngs_modulus_Pa: float = 206e9
    poisson_ratio: float = 0.3
    density_kg_m3: float = 7850.0


@dataclasses.dataclass
class GearSet:
    name: str
    planet_count: int
    sun: Gear
    planet: Gear
    ring: Gear
    friction_coefficient: float = 0.06
    backlash_sun_planet_m: float = 20e-6
    backlash_planet_ring_m: float = 20e-6


def read_gearset_toml(path, name=None):
    """Reads the documented gear-set keys ([stage], [stage.sun|planet|ring], [contact])."""
    with open(path, "rb") as f:
        d = tomllib.load(f)
    st = d.get("stage", {})
    gears = {}
    for g, zdef in (("sun", 21), ("planet", 30), ("ring", 81)):
        s = st.get(g, {})
        pa = s.get("pressure_angle_rad")
        if pa is None:
            pa = math.radians(s.get("pressure_angle_deg", 20.0))
        gears[g] = Gear(teeth=int(s.get("teeth", zdef)), module_m=float(s.get("module_m", 0.003)),
                        pressure_angle_rad=float(pa), face_width_m=float(s.get("face_width_m", 0.05)),
                        addendum_coef=float(s.get("addendum_coef", 1.0)),
                        dedendum_coef=float(s.get("dedendum_coef", 1.25)),
                        youngs_modulus_Pa=float(s.get("youngs_modulus_Pa", 206e9)),
                        poisson_ratio=float(s.get("poisson_ratio", 0.3)),
                        density_kg_m3=float(s.get("density_kg_m3", 7850.0)))
    c = d.get("contact", {})
    return GearSet(name=name or os.path.splitext(os.path.basename(path))[0],
                   planet_count=int(st.get("planet_count", 3)), sun=gears["sun"], planet=gears["planet"],
                   ring=gears["ring"], friction_coefficient=float(c.get("friction_coefficient", 0.1)),
                   backlash_sun_planet_m=float(c.get("backlash_sun_planet_m", 0.0)),
                   backlash_planet_ring_m=float(c.get("backlash_planet_ring_m", 0.0)))


def gearset_toml_text(gs, comment=""):
    """The rig documentation: geometry and contact keys only (planetwear key names)."""
    lines = ["# Gear set of the independent test rig (scripts/indepsim): what its documentation gives.",
             "# Geometry, tooth counts, module, face width, material, friction, design backlash.",
             "# Rig internals (shafts, motor, dynamometer, sensors) are deliberately not given."]
    if comment:
        lines += ["# " + comment]
    lines += ["", "[stage]", f"planet_count = {gs.planet_count}", ""]
    for g in ("sun", "planet", "ring"):
        gg = getattr(gs, g)
        lines += [f"[stage.{g}]", f"teeth = {gg.teeth}", f"module_m = {gg.module_m!r}",
                  f"pressure_angle_deg = {math.degrees(gg.pressure_angle_rad):.6g}",
                  f"face_width_m = {gg.face_width_m!r}", f"addendum_coef = {gg.addendum_coef!r}",
                  f"dedendum_coef = {gg.dedendum_coef!r}", f"youngs_modulus_Pa = {gg.youngs_modulus_Pa!r}",
                  f"poisson_ratio = {gg.poisson_ratio!r}", f"density_kg_m3 = {gg.density_kg_m3!r}", ""]
    lines += ["[contact]", f"friction_coefficient = {gs.friction_coefficient!r}",
              f"backlash_sun_planet_m = {gs.backlash_sun_planet_m!r}",
              f"backlash_planet_ring_m = {gs.backlash_planet_ring_m!r}", ""]
    return "\n".join(lines)


# ----------------------------------------------------------------------------
# Rig, faults, cases
# ----------------------------------------------------------------------------


@dataclasses.dataclass
class Rig:
    """Rig internals (our assumptions, README.md "Parameter values")."""
    motor_inertia_kgm2: float = 0.12
    input_shaft_N_m_rad: float = 2.0e5
    input_shaft_damping_Nms: float = 15.0
    dyno_inertia_kgm2: float = 0.8
    output_shaft_N_m_rad: float = 1.0e6
    output_shaft_damping_Nms: float = 60.0
    speed_loop_bandwidth_Hz: float = 4.0
    loss_factor: float = 0.10
    loss_factor_ref_Hz: float = 3000.0
    friction_smoothing_pitch: float = 0.02
    tip_relief_fraction: float = 0.05
    encoder_bandwidth_Hz: float = 1000.0
    housing_gain_m_s2_per_N: float = 2.0e-3
    housing_kappa: float = 4.0
    iso_cm: float = 0.8
    iso_cr: float = 1.0
    stiffness_variation: bool = True       # False: constant mean mesh stiffness, no friction arms (tests)


@dataclasses.dataclass
class Faults:
    stiffness_scale: float = 1.0
    damping_scale: float = 1.0
    friction_coefficient: float = None     # None = the gear set's
    backlash_m: float = None               # None = the gear set's (both meshes)
    tooth_body: str = ""                   # "sun", "planet", "ring"
    tooth_planet: int = 0
    tooth_index: int = 0
    tooth_stiffness_factor: float = 1.0
    pin_error_m: tuple = ()                # per planet, + = advanced in the carrier's rotation
    sun_ecc_m: float = 0.0
    sun_ecc_phase_rad: float = 0.0
    carrier_ecc_m: float = 0.0
    carrier_ecc_phase_rad: float = 0.0
    ripple_fraction: float = 0.0
    ripple_order: float = 1.0
    ripple_phase_rad: float = 0.0
    worn_depth_m: float = 0.0
    housing_gain_scale: float = 1.0
    housing_kappa_scale: float = 1.0


@dataclasses.dataclass
class Case:
    speed_rpm: float
    power_W: float
    duration_s: float
    faults: Faults = dataclasses.field(default_factory=Faults)
    sensor_angle_deg: float = 30.0
    seed: int = 1
    noise_fraction: float = 0.05
    dc_offset_fraction: float = 0.3


# ----------------------------------------------------------------------------
# Geometry and mesh tables
# ----------------------------------------------------------------------------


def _smoothstep(u):
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def pair_shape(xi, ramp):
    """Single-pair stiffness shape over the contact, xi in [0, 1] (0 outside)."""
    xi = np.asarray(xi, float)
    s = (0.55 + 1.8 * xi * (1.0 - xi)) * _smoothstep(xi / ramp) * _smoothstep((1.0 - xi) / ramp)
    return np.where((xi >= 0.0) & (xi <= 1.0), s, 0.0)


def iso_single_pair_stiffness(z1, z2, internal, rig, alpha_deg=20.0, hfp=1.25):
    """ISO 6336-1 method B c' [N/(mm um)] for spur gears, x1 = x2 = 0 (z2 = inf for internal)."""
    inv2 = 0.0 if internal else 1.0 / z2
    q = 0.04723 + 0.15551 / z1 + 0.25791 * inv2
    cth = 1.0 / q
    cb = (1.0 + 0.5 * (1.2 - hfp)) * (1.0 - 0.02 * (20.0 - alpha_deg))
    return cth * rig.iso_cm * rig.iso_cr * cb


class Stage:
    """Geometry, mesh tables and linear matrices of one gear set on the rig."""
    TABLE = 4096

    def __init__(self, gs: GearSet, rig: Rig = None):
        self.gs, self.rig = gs, (rig or Rig())
        rig = self.rig
        N = gs.planet_count
        self.N = N
        al = gs.sun.pressure_angle_rad
        self.alpha = al
        m = gs.sun.module_m
        Zs, Zp, Zr = gs.sun.teeth, gs.planet.teeth, gs.ring.teeth
        self.Z = (Zs, Zp, Zr)
        if Zr != Zs + 2 * Zp:
            raise ValueError("unshifted gears need Zr = Zs + 2 Zp")
        if (Zs + Zr) % N:
            raise ValueError("(Zs + Zr) / N must be an integer for equally spaced planets")
        rs, rp, rr = Zs * m / 2, Zp * m / 2, Zr * m / 2
        self.r = (rs, rp, rr)
        rbs, rbp, rbr = rs * math.cos(al), rp * math.cos(al), rr * math.cos(al)
        self.rb = (rbs, rbp, rbr)
        ras, rap = rs + gs.sun.addendum_coef * m, rp + gs.planet.addendum_coef * m
        rar = rr - gs.ring.addendum_coef * m
        self.pb = math.pi * m * math.cos(al)
        # approach / recess lengths along the line of action (sun mesh: sun drives;
        # ring mesh: the planet drives the ring in the carrier frame)
        ga_sp = math.sqrt(rap ** 2 - rbp ** 2) - rp * math.sin(al)
        gr_sp = math.sqrt(ras ** 2 - rbs ** 2) - rs * math.sin(al)
        ga_rp = rr * math.sin(al) - math.sqrt(rar ** 2 - rbr ** 2)
        gr_rp = math.sqrt(rap ** 2 - rbp ** 2) - rp * math.sin(al)
        self.g = {"sp": (ga_sp, gr_sp), "rp": (ga_rp, gr_rp)}
        self.eps = {k: (a + b) / self.pb for k, (a, b) in self.g.items()}
        self.rc = rs + rp
        self.psi = 2 * math.pi * np.arange(N) / N
        # ISO 6336-1 stiffness
        b = gs.sun.face_width_m
        self.face_width = b
        self.cprime = {"sp": iso_single_pair_stiffness(Zs, Zp, False, rig, math.degrees(al)),
                       "rp": iso_single_pair_stiffness(Zp, Zr, True, rig, math.degrees(al))}
        self.kmean_iso = {k: self.cprime[k] * (0.75 * self.eps[k] + 0.25) * b * 1e9 for k in self.cprime}
        # inertias (our own estimates, README.md)
        rho = gs.sun.density_kg_m3
        self.I_s = 0.5 * rho * math.pi * rs ** 4 * b * 1.3          # + 30 % for the sun shaft stub
        ri = 0.4 * rp
        mp = rho * math.pi * (rp ** 2 - ri ** 2) * b
        self.m_p = mp
        self.I_p = 0.5 * mp * (rp ** 2 + ri ** 2)
        Rcar, tcar = self.rc + 0.6 * rp, 0.3 * b
        Icar = 2 * 0.5 * rho * math.pi * tcar * Rcar ** 4
        self.I_c = Icar + N * mp * self.rc ** 2
        # DOF layout
        self.n = N + 4
        self.im, self.i_s, self.ic, self.ip, self.idy = 0, 1, 2, 3 + np.arange(N), N + 3
        self.M = np.zeros(self.n)
        self.M[[self.im, self.i_s, self.ic, self.idy]] = [rig.motor_inertia_kgm2, self.I_s, self.I_c,
                                                        rig.dyno_inertia_kgm2]
        self.M[self.ip] = self.I_p
        # A: mesh deflection = A @ theta  (rows: sp_0..sp_{N-1}, rp_0..rp_{N-1})
        A = np.zeros((2 * N, self.n))
        for i in range(N):
            A[i, self.i_s] = rbs
            A[i, self.ip[i]] = rbp
            A[i, self.ic] = -(rbs + rbp)
            A[N + i, self.ip[i]] = -rbp
            A[N + i, self.ic] = -(rbr - rbp)
        self.A = A
        # shafts
        Ks = np.zeros((self.n, self.n))
        Cs = np.zeros((self.n, self.n))
        for (a, c_, k, cc) in ((self.im, self.i_s, rig.input_shaft_N_m_rad, rig.input_shaft_damping_Nms),
                               (self.ic, self.idy, rig.output_shaft_N_m_rad, rig.output_shaft_damping_Nms)):
            Ks[a, a] += k; Ks[c_, c_] += k; Ks[a, c_] -= k; Ks[c_, a] -= k
            Cs[a, a] += cc; Cs[c_, c_] += cc; Cs[a, c_] -= cc; Cs[c_, a] -= cc
        self.Ks, self.Cs = Ks, Cs
        # phases: pair counters m_sp,i = f_m t + off_sp[i]; m_rp,i = f_m t + off_rp[i]
        self.off_sp = -Zs * self.psi / (2 * math.pi)
        self.off_rp = Zr * self.psi / (2 * math.pi) - (Zp - 1) / 2.0
        self._tables()

    # -- per-mesh-cycle tables -------------------------------------------------
    def _pairs(self, key, u):
        """Pairs in contact at mesh-cycle position u (array); yields (s, xi, active)."""
        ga, gr = self.g[key]
        pb = self.pb
        out = []
        for j in range(-3, 4):
            s = (u - j) * pb
            xi = (s + ga) / (ga + gr)
            out.append((s, xi))
        return out

    def _tables(self):
        L = self.TABLE
        u = np.arange(L + 1) / L
        rbs, rbp, rbr = self.rb
        ta = math.tan(self.alpha)
        ramp = self.rig.tip_relief_fraction
        self.shape_mean = {}
        self.tab = {}
        self.kpeak = {}
        for key in ("sp", "rp"):
            ga, gr = self.g[key]
            ssum = np.zeros_like(u)
            wsum = {a: np.zeros_like(u) for a in ("s", "p", "c", "te")}
            for s, xi in self._pairs(key, u):
                S = pair_shape(xi, ramp)
                ssum += S
                sig = np.tanh(s / (self.rig.friction_smoothing_pitch * self.pb))
                if key == "sp":
                    wsum["s"] += S * (-sig * (rbs * ta + s))
                    wsum["p"] += S * (-sig * (rbp * ta - s))
                    wsum["c"] += S * (sig * (rbs + rbp) * ta)
                else:
                    wsum["p"] += S * (sig * (rbp * ta + s))
                    wsum["c"] += S * (sig * (rbr - rbp) * ta)
                wsum["te"] += S * np.abs(s) / max(ga, gr)
            xi_f = np.linspace(0, 1, 20001)
            mean_shape = np.trapz(pair_shape(xi_f, ramp), xi_f) * self.eps[key]
            self.shape_mean[key] = mean_shape
            kpeak = self.kmean_iso[key] / mean_shape
            self.kpeak[key] = kpeak
            tab = np.stack([ssum * kpeak] + [wsum[a] / ssum for a in ("s", "p", "c", "te")], axis=1)
            if not self.rig.stiffness_variation:
                tab[:, 0] = self.kmean_iso[key]
                tab[:, 1:4] = 0.0
            self.tab[key] = tab
        # self-check of the mean
        for key in ("sp", "rp"):
            assert abs(self.tab[key][:-1, 0].mean() / self.kmean_iso[key] - 1) < 2e-3

    def mesh_frequency(self, speed_rpm):
        Zs, _, Zr = self.Z
        return Zs * Zr / (Zs + Zr) * speed_rpm / 60.0

    def nominal(self, case):
        Zs, _, Zr = self.Z
        Ws = case.speed_rpm * 2 * math.pi / 60
        Wc = Ws * Zs / (Zs + Zr)
        T0 = case.power_W / Ws
        return Ws, Wc, T0

    def load_factor(self, case):
        """ISO 6336-1: c' reduced by (F_t/b / 100 N/mm)^0.25 below 100 N/mm."""
        _, _, T0 = self.nominal(case)
        w = T0 / (self.N * self.r[0]) / (self.face_width * 1e3)
        return min(1.0, (max(w, 1e-3) / 100.0) ** 0.25)

    def static_state(self, T0, kvec, e=None):
        """Static deflection under input torque T0 (motor) balanced by the ideal output torque;
        dyno angle fixed at 0. Returns (x (n,), mesh forces k (A x - e) (2N,))."""
        n = self.n
        Zs, _, Zr = self.Z
        e = np.zeros(2 * self.N) if e is None else np.asarray(e, float)
        K = self.stiffness_matrix(kvec)
        f = np.zeros(n)
        f[self.im] = T0
        f[self.idy] = -T0 * (Zs + Zr) / Zs
        f += self.A.T @ (kvec * e)
        keep = [i for i in range(n) if i != self.idy]
        x = np.zeros(n)
        x[keep] = np.linalg.solve(K[np.ix_(keep, keep)], f[keep])
        return x, kvec * (self.A @ x - e)

    def stiffness_matrix(self, kvec):
        return self.A.T @ (kvec[:, None] * self.A) + self.Ks

    def natural_frequencies(self, scale=1.0, peak=False):
        """Undamped natural frequencies [Hz] of the linearised stage+rig (free rotation removed)."""
        N = self.N
        if peak:
            kk = np.r_[np.full(N, self.tab["sp"][:, 0].max()), np.full(N, self.tab["rp"][:, 0].max())]
        else:
            kk = np.r_[np.full(N, self.kmean_iso["sp"]), np.full(N, self.kmean_iso["rp"])]
        K = self.stiffness_matrix(kk * scale)
        Mi = 1 / np.sqrt(self.M)
        w2 = np.linalg.eigvalsh(Mi[:, None] * K * Mi[None, :])
        return np.sqrt(np.clip(w2, 0, None)) / (2 * math.pi)


# ----------------------------------------------------------------------------
# Batch simulation
# ----------------------------------------------------------------------------


def _interp_table(tab, u):
    """Linear interpolation of a per-cycle table (L+1, k) at u (any shape) in [0,1)."""
    L = tab.shape[0] - 1
    x = u * L
    i = np.minimum(x.astype(np.int64), L - 1)
    w = (x - i)[..., None]
    return tab[i] * (1 - w) + tab[i + 1] * w


class Decimator:
    """Streaming linear-phase FIR decimation (delay compensated): output k <-> fine index k*D."""

    def __init__(self, D, fs_fine, fs_out, nch):
        self.D = D
        half = 12 * D
        self.h = signal.firwin(2 * half + 1, 0.4 * fs_out, fs=fs_fine, window=("kaiser", 8.0))
        self.half = half
        self.buf = None
        self.buf_start = 0      # fine index of buf[..., 0]
        self.next_k = 0
        self.out = []

    def push(self, x, start_index):
        """x: (nch..., S) fine samples starting at fine index start_index (contiguous pushes)."""
        if self.buf is None:
            self.buf = x
            self.buf_start = start_index
        else:
            self.buf = np.concatenate([self.buf, x], axis=-1)
        end = self.buf_start + self.buf.shape[-1] - 1
        k0 = self.next_k
        # need centre - half >= buf_start (first outputs: centre >= half)
        while k0 * self.D - self.half < self.buf_start:
            k0 += 1
        k1 = (end - self.half) // self.D
        if k1 >= k0:
            i0 = k0 * self.D - self.half - self.buf_start
            K = k1 - k0 + 1
            acc = np.zeros(self.buf.shape[:-1] + (K,))
            stop = i0 + (K - 1) * self.D + 1
            for j, hj in enumerate(self.h):
                acc += hj * self.buf[..., i0 + j:stop + j:self.D]
            self.out.append(acc)
            self.next_k = k1 + 1
            keep_from = self.next_k * self.D - self.half - self.buf_start
            self.buf = self.buf[..., keep_from:].copy()
            self.buf_start += keep_from

    def result(self):
        first = self.next_k - sum(o.shape[-1] for o in self.out)
        return first, np.concatenate(self.out, axis=-1)


def choose_rates(stage, cases, dt_factor=1.0):
    """DAQ rate fs (>= 9 f_m, from a list of usual rates) and integration step dt = 1/(D fs)."""
    fm = max(stage.mesh_frequency(c.speed_rpm) for c in cases)
    fs = next(r for r in (5000.0, 10000.0, 12500.0, 20000.0, 25000.0, 50000.0, 100000.0) if r >= 9 * fm)
    smax = max(c.faults.stiffness_scale for c in cases)
    wmax = 2 * math.pi * stage.natural_frequencies(scale=smax, peak=True).max()
    dt_max = dt_factor / wmax
    D = max(1, int(math.ceil(1.0 / (dt_max * fs))))
    return fs, D


def encoder_sos(rig, fs_fine):
    """Encoder speed channel: 2nd-order Butterworth low-pass at rig.encoder_bandwidth_Hz."""
    return signal.butter(2, rig.encoder_bandwidth_Hz, fs=fs_fine, output="sos")


def simulate_batch(stage, cases, warmup_s=0.6, chunk=1024, dt_factor=1.0, verbose=False,
                   fs=None, D=None, keep_fine=False, initial_offset=None):
    """Integrates every case of one gear set together (batch dimension B).

    Returns (fs, list of dicts with the DAQ channels in SI units before noise:
    time [s] from 0, sun_speed, carrier_speed [rad/s], acc_sp0, acc_pr0,
    housing [m/s^2]) and info (dt, steps, cpu seconds)."""
    gs, rig, N, n = stage.gs, stage.rig, stage.N, stage.n
    B = len(cases)
    if fs is None:
        fs, D = choose_rates(stage, cases, dt_factor)
    dt = 1.0 / (fs * D)
    T_end = warmup_s + max(c.duration_s for c in cases)
    n_out = int(round(T_end * fs)) + 1
    nsteps = n_out * D + 13 * D + chunk
    nsteps = int(math.ceil(nsteps / chunk) * chunk)
    Zs, Zp, Zr = stage.Z
    M2 = 2 * N
    # --- per-case parameters
    Ws = np.array([stage.nominal(c)[0] for c in cases])
    Wc = np.array([stage.nominal(c)[1] for c in cases])
    T0 = np.array([stage.nominal(c)[2] for c in cases])
    fm = Wc * Zr / (2 * math.pi)
    lf = np.array([stage.load_factor(c) for c in cases])
    kscale = lf * np.array([c.faults.stiffness_scale for c in cases])                    # (B,)
    beta = np.array([rig.loss_factor * c.faults.damping_scale for c in cases]) / (2 * math.pi * rig.loss_factor_ref_Hz)
    mu = np.array([gs.friction_coefficient if c.faults.friction_coefficient is None else c.faults.friction_coefficient
                   for c in cases])
    bl = np.zeros((B, M2))
    for b, c in enumerate(cases):
        bl[b, :N] = gs.backlash_sun_planet_m if c.faults.backlash_m is None else c.faults.backlash_m
        bl[b, N:] = gs.backlash_planet_ring_m if c.faults.backlash_m is None else c.faults.backlash_m
    # static errors (constant part): pin errors, carrier runout
    e_const = np.zeros((B, M2))
    al = stage.alpha
    for b, c in enumerate(cases):
        f = c.faults
        if len(f.pin_error_m):
            pe = np.asarray(f.pin_error_m, float)
            e_const[b, :N] += pe * math.cos(al)
            e_const[b, N:] += pe * math.cos(al)
        if f.carrier_ecc_m:
            e_const[b, :N] += f.carrier_ecc_m * np.sin(f.carrier_ecc_phase_rad - stage.psi + al)
            e_const[b, N:] -= f.carrier_ecc_m * np.sin(stage.psi + al - f.carrier_ecc_phase_rad)
    sun_ecc = np.array([c.faults.sun_ecc_m for c in cases])
    sun_ph = np.array([c.faults.sun_ecc_phase_rad for c in cases])
    worn = np.array([c.faults.worn_depth_m for c in cases])
    rip = np.array([c.faults.ripple_fraction for c in cases])
    rip_o = np.array([c.faults.ripple_order for c in cases])
    rip_ph = np.array([c.faults.ripple_phase_rad for c in cases])
    # tooth damage -> per mesh: (modulus Z, tooth, factor-1)
    dmg = []
    for b, c in enumerate(cases):
        f = c.faults
        if f.tooth_body and f.tooth_stiffness_factor != 1.0:
            if f.tooth_body == "sun":
                meshes, Z = list(range(N)), Zs
            elif f.tooth_body == "planet":
                meshes, Z = [f.tooth_planet, N + f.tooth_planet], Zp
            elif f.tooth_body == "ring":
                meshes, Z = list(range(N, 2 * N)), Zr
            else:
                raise ValueError(f.tooth_body)
            for mi in meshes:
                dmg.append((b, mi, Z, f.tooth_index % Z, f.tooth_stiffness_factor - 1.0))
    offs = np.r_[stage.off_sp, stage.off_rp]                       # (2N,)
    keys = ["sp"] * N + ["rp"] * N
    # --- linear part: Q_lin = Y @ L  (Y = [x (n), v (n), z])
    ratio = (Zs + Zr) / Zs
    J_eff = rig.dyno_inertia_kgm2 + stage.I_c + N * stage.I_p * (Zs / (2.0 * Zp)) ** 2 * 0 \
        + (stage.I_s + rig.motor_inertia_kgm2) * ratio ** 2
    Kp = J_eff * 2 * math.pi * rig.speed_loop_bandwidth_Hz
    Ki = Kp * 2 * math.pi * rig.speed_loop_bandwidth_Hz / 4
    # the PI integral of the dyno speed error is the dyno angle perturbation x_d itself
    Lm = np.zeros((2 * n, n))
    Lm[:n, :] = -stage.Ks.T
    Lm[n:2 * n, :] = -stage.Cs.T
    Lm[n + stage.idy, stage.idy] += -Kp
    Lm[stage.idy, stage.idy] += -Ki
    Q0 = np.zeros((B, n))
    Q0[:, stage.idy] = -T0 * (Zs + Zr) / Zs
    invM = 1.0 / stage.M
    Ablk = np.zeros((2 * n, 2 * M2))
    Ablk[:n, :M2] = stage.A.T
    Ablk[n:, M2:] = stage.A.T
    ipl = stage.ip
    # --- initial state: static solution with mean stiffness, x_d = 0
    Y = np.zeros((B, 2 * n))
    for b in range(B):
        kk = np.r_[np.full(N, stage.kmean_iso["sp"]), np.full(N, stage.kmean_iso["rp"])] * kscale[b]
        Y[b, :n] = stage.static_state(T0[b], kk, e_const[b])[0]
    if initial_offset is not None:
        Y += initial_offset
    # --- output channels on the fine grid: ws, wc, asp0, apr0, F_pr (N), wF (N), w (N)
    nch = 4 + 3 * N
    sos = encoder_sos(rig, fs * D)
    zi = np.zeros((B, 2, sos.shape[0], 2))
    for b in range(B):
        for j, w0 in enumerate((Ws[b], Wc[b])):
            zi[b, j] = signal.sosfilt_zi(sos) * w0
    dec = Decimator(D, fs * D, fs, nch)
    kappa = np.array([rig.housing_kappa * c.faults.housing_kappa_scale for c in cases])
    gain = np.array([rig.housing_gain_m_s2_per_N * c.faults.housing_gain_scale for c in cases])
    phis = np.radians([c.sensor_angle_deg for c in cases])     # physical sensor angle (planet 0 at t=0)
    A_sp0, A_rp0 = stage.A[0], stage.A[N]
    fine = [] if keep_fine else None
    cpu0 = time.process_time()
    wall0 = time.time()
    # mapping of [F, mu F arm_s, mu F arm_p, mu F arm_c] per mesh to generalised torques
    Map2 = np.zeros((M2, 4, n))
    for mi in range(M2):
        Map2[mi, 0] = -stage.A[mi]
        Map2[mi, 1, stage.i_s] = 1.0
        Map2[mi, 2, ipl[mi % N]] = 1.0
        Map2[mi, 3, stage.ic] = 1.0
    Map2 = Map2.reshape(M2 * 4, n)
    for c0 in range(0, nsteps, chunk):
        # precompute on the half-step grid: RK stage j of step i is at index 2 i + j
        tt = (c0 + np.arange(2 * chunk + 1) / 2.0) * dt                      # (2S+1,)
        mcyc = fm[None, :, None] * tt[:, None, None] + offs[None, None, :]    # (2S+1,B,2N)
        u = mcyc - np.floor(mcyc)
        KK = np.empty(mcyc.shape)
        EE = np.empty(mcyc.shape)
        AR = np.empty(mcyc.shape + (4,))
        AR[..., 0] = 1.0
        for key, sl in (("sp", slice(0, N)), ("rp", slice(N, M2))):
            T = _interp_table(stage.tab[key], u[..., sl])                     # (2S+1,B,N,5)
            KK[..., sl] = T[..., 0]
            EE[..., sl] = T[..., 4] * worn[None, :, None]
            AR[..., sl, 1:] = T[..., 1:4] * mu[None, :, None, None]
        for (b, mi, Z, tooth, df) in dmg:
            q = np.mod(mcyc[:, b, mi] - tooth, Z)
            ud = np.where(q > Z / 2, q - Z, q)
            ga, gr = stage.g[keys[mi]]
            xi = (ud * stage.pb + ga) / (ga + gr)
            KK[:, b, mi] += df * stage.kpeak[keys[mi]] * pair_shape(xi, rig.tip_relief_fraction)
        KK *= kscale[None, :, None]
        CC = KK * beta[None, :, None]
        # time-varying errors: sun runout; constant errors
        ths = Ws[None, :] * tt[:, None]
        thc = Wc[None, :] * tt[:, None]
        EE += e_const[None]
        if np.any(sun_ecc):
            arg = ths[..., None] + sun_ph[None, :, None] - stage.psi[None, None, :] - thc[..., None] + al
            EE[..., :N] -= sun_ecc[None, :, None] * np.sin(arg)
        Tm = T0[None, :] * (1 + rip[None, :] * np.sin(rip_o * ths + rip_ph))
        TX = np.broadcast_to(Q0, (2 * chunk + 1, B, n)).copy()
        TX[..., stage.im] += Tm
        ACC = np.empty((chunk, B, n))
        FF = np.empty((chunk, B, M2))
        XV = np.empty((chunk, B, 3))
        h = dt
        ivs, ivc = n + stage.i_s, n + stage.ic
        nbl = -bl
        mx, mn, sub_, mul_ = np.maximum, np.minimum, np.subtract, np.multiply
        for i in range(chunk):
            i2 = 2 * i

            def rhs(Yc, j):
                DD = Yc @ Ablk
                d = sub_(DD[:, :M2], EE[i2 + j])
                g = d - mn(mx(d, nbl), 0.0)
                F = KK[i2 + j] * g
                F += CC[i2 + j] * DD[:, M2:] * (g != 0)
                Q = (F[:, :, None] * AR[i2 + j]).reshape(B, 4 * M2) @ Map2
                Q += Yc @ Lm
                Q += TX[i2 + j]
                Q *= invM
                return np.concatenate([Yc[:, n:], Q], axis=1), F

            k1, F1 = rhs(Y, 0)
            ACC[i] = k1[:, n:2 * n]
            FF[i] = F1
            XV[i, :, 0] = Y[:, stage.ic]
            XV[i, :, 1] = Y[:, ivs]
            XV[i, :, 2] = Y[:, ivc]
            k2, _ = rhs(Y + 0.5 * h * k1, 1)
            k3, _ = rhs(Y + 0.5 * h * k2, 1)
            k4, _ = rhs(Y + h * k3, 2)
            Y = Y + (h / 6.0) * (k1 + 2 * (k2 + k3) + k4)
        if not np.all(np.isfinite(Y)):
            raise FloatingPointError(f"integration diverged near t = {c0 * dt:.4f} s")
        # channels on the fine grid
        t0 = tt[0:2 * chunk:2]
        ch = np.empty((B, nch, chunk))
        ch[:, 0, :] = (Ws[None, :] + XV[:, :, 1]).T
        ch[:, 1, :] = (Wc[None, :] + XV[:, :, 2]).T
        ch[:, 2, :] = (ACC @ A_sp0).T
        ch[:, 3, :] = (ACC @ A_rp0).T
        Fpr = FF[:, :, N:]                                                      # (S,B,N)
        thc_abs = Wc[None, :, None] * t0[:, None, None] + XV[:, :, 0][:, :, None] + stage.psi[None, None, :]
        w = np.exp(kappa[None, :, None] * (np.cos(thc_abs - phis[None, :, None]) - 1.0))
        ch[:, 4:4 + N, :] = Fpr.transpose(1, 2, 0)
        ch[:, 4 + N:4 + 2 * N, :] = (w * Fpr).transpose(1, 2, 0)
        ch[:, 4 + 2 * N:, :] = w.transpose(1, 2, 0)
        # encoders: 2nd-order Butterworth on the fine grid (state carried between chunks)
        for b in range(B):
            for j in range(2):
                ch[b, j], zi[b, j] = signal.sosfilt(sos, ch[b, j], zi=zi[b, j])
        if keep_fine:
            fine.append(ch.copy())
        dec.push(ch, c0)
        if verbose and (c0 // chunk) % 50 == 0:
            el = time.time() - wall0
            print(f"  t = {(c0 + chunk) * dt:.3f}/{nsteps * dt:.3f} s, {el:.0f} s wall", file=sys.stderr, flush=True)
    cpu = time.process_time() - cpu0
    first, out = dec.result()                                            # (B, nch, K), fine index k*D
    k_w = int(round(warmup_s * fs))
    if first > k_w:
        raise RuntimeError("decimator lost the start of the record")
    res = []
    for b, c in enumerate(cases):
        nb = int(round(c.duration_s * fs))
        sl = slice(k_w - first, k_w - first + nb)
        o = out[b, :, sl]
        Fpr = o[4:4 + N]
        wF = o[4 + N:4 + 2 * N]
        ww = o[4 + 2 * N:]
        Fm = Fpr.mean(axis=1, keepdims=True)
        housing = gain[b] * (wF - ww * Fm).sum(axis=0)
        res.append(dict(time=np.arange(nb) / fs, sun_speed=o[0], carrier_speed=o[1], acc_sp0=o[2], acc_pr0=o[3],
                        housing=housing, mean_planet_ring_force=Fm[:, 0], t_start=k_w / fs,
                        carrier_angle_start=Wc[b] * k_w / fs))
    info = dict(fs=fs, D=D, dt=dt, steps=nsteps, cpu_s=cpu, wall_s=time.time() - wall0, batch=B,
                simulated_s=nsteps * dt, fine=np.concatenate(fine, axis=-1) if keep_fine else None)
    return fs, res, info


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(description="Simulate one recording (SI channels to a .npz); "
                                 "the corpus is made by corpus.py")
    ap.add_argument("-c", "--gearset", required=True, help="gear-set TOML ([stage], [stage.sun], ...)")
    ap.add_argument("--speed-rpm", type=float, default=400.0)
    ap.add_argument("--power-w", type=float, default=1000.0)
    ap.add_argument("--seconds", type=float, default=1.0)
    ap.add_argument("-o", "--out", required=True)
    a = ap.parse_args(argv)
    st = Stage(read_gearset_toml(a.gearset))
    fs, res, info = simulate_batch(st, [Case(a.speed_rpm, a.power_w, a.seconds)], verbose=True)
    np.savez(a.out, fs=fs, **{k: v for k, v in res[0].items()})
    print(f"fs {fs} Hz, dt {info['dt']:.3g} s, cpu {info['cpu_s']:.1f} s for {info['simulated_s']:.2f} s simulated")


if __name__ == "__main__":
    main()
