#!/usr/bin/python3
"""indepsim3: a third independent simulator of a planetary gear stage on a test rig.

Torsional lumped model in the carrier frame (Lin & Parker 1999, torsional subset), ISO 6336-1
method-B mesh stiffness levels distributed along the path of contact with a parabola peaking at
the pitch point, backlash dead zone, Coulomb friction with an arctan-smoothed sign, a DC motor
with a linear torque-speed line behind a flexible input shaft, an eddy-current brake (T = c w^2)
behind a flexible output shaft, generalized-alpha time integration (Chung & Hulbert 1993) and a
DAQ chain (incremental encoders, housing structural mode, IEPE high-pass, 8th-order anti-alias
Butterworth, decimation, noise). Every equation and its source: README.md next to this file.

SI units throughout (angles in rad, angular speeds in rad/s) except where a name says otherwise
(rpm, deg, ISO 6336 stiffness in N/(mm um) inside the ISO functions only).

Written without reading planetwear's sources or the other two independent simulators.
"""
import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import math  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402

import numpy as np  # noqa: E402
import scipy.signal  # noqa: E402

# ----------------------------------------------------------------------------------------------
# Constants and coefficients with their sources
# ----------------------------------------------------------------------------------------------

# ISO 6336-1:2006, 9.3.2 (method B), equation for the minimum value of the flexibility of a tooth
# pair q' [mm um / N] = C1 + C2/zn1 + C3/zn2 + C4 x1 + C5 x1/zn1 + C6 x2 + C7 x2/zn2 + C8 x1^2 + C9 x2^2,
# coefficients of its Table 8 (dimensionless coefficients of q' in mm um/N).
ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
ISO_C_M = 0.8        # ISO 6336-1 method B: correction factor C_M between theoretical and measured (solid discs)
ISO_C_R = 1.0        # ISO 6336-1 method B: gear blank factor C_R = 1 for solid disc gears
ISO_LINE_LOAD_REF = 100.0  # ISO 6336-1 method B: c' is reduced by (F_t K_A / b / 100 N/mm)^0.25 below 100 N/mm
N_PER_MM_UM = 1e9    # 1 N/(mm um) = 1e9 N/m^2 (stiffness per unit face width)

STEEL_E = 206e9      # Young's modulus of steel [Pa] (e.g. Shigley's Mechanical Engineering Design, Table A-5)
STEEL_NU = 0.3       # Poisson's ratio of steel [-] (same source)
STEEL_RHO = 7850.0   # density of steel [kg/m^3] (same source)

# Generalized-alpha (Chung & Hulbert 1993, J. Appl. Mech. 60:371-375), eq. (25)-(26) for a
# prescribed high-frequency spectral radius rho_inf: second order accurate, unconditionally stable.
RHO_INF = 0.9

FRICTION_V_EPS = 0.02   # [m/s] velocity scale of the arctan-smoothed sign of the sliding velocity (own choice)
MESH_ZETA = 0.05        # viscous mesh damping ratio (brief; cf. Kahraman & Singh 1991: 0.03-0.17 measured)
CONTACT_DAMPING_RAMP_M = 0.1e-6   # [m] compression over which a touching flank's damping ramps in (own choice)
COUNTER_CLOCK_HZ = 80e6  # encoder edge-time counter timebase [Hz] (a typical DAQ counter timebase, e.g. NI X series 80 MHz)


def _inv(a):
    """Involute function inv(a) = tan a - a [rad] (ISO 21771)."""
    return math.tan(a) - a


# ----------------------------------------------------------------------------------------------
# Inputs
# ----------------------------------------------------------------------------------------------

@dataclass
class GearSet:
    """What the stage's drawing gives (what gearset.toml states)."""
    name: str
    Zs: int
    Zp: int
    Zr: int
    N: int
    module_m: float
    face_width_m: float
    pressure_angle_deg: float = 20.0
    friction: float = 0.06             # documented Coulomb friction coefficient [-]
    backlash_sp_m: float = 20e-6       # design backlash along the line of action, sun-planet [m]
    backlash_pr_m: float = 20e-6       # same, planet-ring [m]
    youngs_modulus_Pa: float = STEEL_E
    poisson_ratio: float = STEEL_NU
    density_kg_m3: float = STEEL_RHO
    addendum_coef: float = 1.0         # h_a* (ISO 53 basic rack)
    dedendum_coef: float = 1.25        # h_f* (ISO 53 basic rack)
    shift_s: float = 0.0
    shift_p: float = 0.0
    shift_r: float = 0.0


@dataclass
class Rig:
    """The test rig around the stage (not in gearset.toml)."""
    J_motor: float = 0.08          # motor rotor + coupling half [kg m^2]
    J_brake: float = 0.3           # eddy-current brake rotor [kg m^2]
    f_input_shaft_Hz: float = 50.0   # target of the input-shaft torsional mode [Hz]
    f_output_shaft_Hz: float = 150.0  # target of the output-shaft torsional mode [Hz]
    shaft_zeta: float = 0.04       # modal damping ratio given to each shaft (c = 2 zeta k / omega_target)
    motor_sag: float = 0.04        # speed sag of the motor from no load to the operating torque [-]
    bearing_c_sun: float = 2e-4    # viscous bearing drag of the sun [N m s/rad]
    bearing_c_carrier: float = 5e-4  # viscous bearing drag of the carrier [N m s/rad]
    bearing_c_planet: float = 5e-5   # viscous drag of each planet bearing (relative to the carrier) [N m s/rad]
    housing_f_Hz: float = 2600.0   # housing structural mode [Hz]
    housing_zeta: float = 0.03     # its damping ratio
    housing_mass_kg: float = 20.0  # its modal mass [kg]
    window_power: float = 4.0      # influence ((1 + cos d)/2)^p of a planet at angular distance d from the sensor
    iepe_highpass_Hz: float = 2.0  # IEPE AC coupling, first order [Hz]
    lines_sun: int = 1024          # encoder lines per revolution, sun (input) shaft
    lines_carrier: int = 2048      # encoder lines per revolution, carrier (output) shaft


@dataclass
class Faults:
    """Effects. Defaults = healthy stage."""
    tooth_body: str = ""           # "", "sun", "planet", "ring"
    tooth_planet: int = 0
    tooth_index: int = 0
    tooth_stiffness_factor: float = 1.0
    pin_error_m: tuple = ()        # N tangential pin errors, + = advanced in the carrier's rotation
    carrier_ecc_m: float = 0.0
    carrier_ecc_phase_rad: float = 0.0   # direction of the runout in the carrier frame, from planet 0
    sun_ecc_m: float = 0.0
    sun_ecc_phase_rad: float = 0.0       # direction of the sun runout at t = 0 in the carrier frame
    ripple_fraction: float = 0.0
    ripple_order: float = 1.0
    ripple_phase_rad: float = 0.0
    worn_depth_m: float = 0.0            # worn-profile depth at the start of the path of contact
    friction_factor: float = 1.0
    stiffness_scale: float = 1.0
    damping_scale: float = 1.0
    backlash_factor: float = 1.0
    sensor_gain_factor: float = 1.0


@dataclass
class Case:
    rpm: float
    power_W: float
    duration_s: float
    fs_daq: float = 10000.0
    sensor_angle_rad: float = 0.0   # wanted sensor angle from planet 0 at the file's t = 0
    faults: Faults = field(default_factory=Faults)


# ----------------------------------------------------------------------------------------------
# ISO 6336-1 mesh stiffness
# ----------------------------------------------------------------------------------------------

def iso_q_prime(zn1, zn2, x1=0.0, x2=0.0):
    """ISO 6336-1:2006 method B: q' [mm um/N]. zn2 = inf for an internal gear (the C3 and C7 terms vanish)."""
    C1, C2, C3, C4, C5, C6, C7, C8, C9 = ISO_C
    i2 = 0.0 if math.isinf(zn2) else 1.0 / zn2
    return C1 + C2 / zn1 + C3 * i2 + C4 * x1 + C5 * x1 / zn1 + C6 * x2 + C7 * x2 * i2 + C8 * x1 ** 2 + C9 * x2 ** 2


def iso_basic_rack_factor(hfp_over_m=1.25, alpha_deg=20.0):
    """ISO 6336-1 method B: C_B = [1 + 0.5 (1.2 - h_fP/m_n)] [1 - 0.02 (20 deg - alpha_Pn)]."""
    return (1.0 + 0.5 * (1.2 - hfp_over_m)) * (1.0 - 0.02 * (20.0 - alpha_deg))


def iso_single_stiffness(zn1, zn2, x1=0.0, x2=0.0, hfp_over_m=1.25, alpha_deg=20.0, line_load_N_mm=None):
    """ISO 6336-1 method B single stiffness c' [N/(mm um)] of a spur pair (beta = 0, cos beta = 1):
    c' = c'_th C_M C_R C_B, c'_th = 1/q'; times (w/100)^0.25 for a line load w = F_t K_A / b < 100 N/mm."""
    c = (1.0 / iso_q_prime(zn1, zn2, x1, x2)) * ISO_C_M * ISO_C_R * iso_basic_rack_factor(hfp_over_m, alpha_deg)
    if line_load_N_mm is not None and line_load_N_mm < ISO_LINE_LOAD_REF:
        c *= (max(line_load_N_mm, 1e-6) / ISO_LINE_LOAD_REF) ** 0.25
    return c


def iso_mesh_stiffness(c_prime, eps_alpha):
    """ISO 6336-1 method B mean mesh stiffness of a spur pair: c_gamma_alpha = c' (0.75 eps_alpha + 0.25)."""
    return c_prime * (0.75 * eps_alpha + 0.25)


# ----------------------------------------------------------------------------------------------
# The stage
# ----------------------------------------------------------------------------------------------

class Stage:
    """Geometry, stiffness law, inertias and the rig of one gear set. DOFs (perturbations from the
    nominal rotation, rad): 0 motor, 1 sun, 2 carrier, 3..3+N-1 planets (absolute rotation), 3+N brake."""

    def __init__(self, gs: GearSet, rig: Rig):
        self.gs, self.rig = gs, rig
        Zs, Zp, Zr, N = gs.Zs, gs.Zp, gs.Zr, gs.N
        if Zr != Zs + 2 * Zp:
            raise ValueError(f"{gs.name}: Zr = {Zr} must equal Zs + 2 Zp = {Zs + 2 * Zp} (coaxial, no profile shift)")
        if (Zs + Zr) % N:
            raise ValueError(f"{gs.name}: (Zs + Zr)/N = {(Zs + Zr) / N} is not an integer: equally spaced planets cannot be assembled")
        if not 3 <= N <= 6:
            raise ValueError(f"{gs.name}: N = {N} planets; 3..6 supported")
        if gs.shift_s or gs.shift_p or gs.shift_r:
            raise ValueError(f"{gs.name}: profile shifts other than 0 are not supported by this simulator")
        m, b = gs.module_m, gs.face_width_m
        al = math.radians(gs.pressure_angle_deg)
        self.alpha = al
        ha = gs.addendum_coef
        # reference, base and tip radii (ISO 21771); ring (internal) tip circle r_a = r - m h_a* (x = 0)
        self.r_s, self.r_p, self.r_r = m * Zs / 2, m * Zp / 2, m * Zr / 2
        self.rb_s, self.rb_p, self.rb_r = (r * math.cos(al) for r in (self.r_s, self.r_p, self.r_r))
        self.ra_s, self.ra_p = self.r_s + m * ha, self.r_p + m * ha
        self.ra_r = self.r_r - m * ha
        self.r_c = self.r_s + self.r_p           # carrier radius = centre distance (x = 0: alpha_w = alpha)
        self.rc_b = self.r_c * math.cos(al)      # = rb_s + rb_p = rb_r - rb_p
        self.pb = math.pi * m * math.cos(al)     # base pitch
        if self.ra_r <= self.rb_r:
            raise ValueError(f"{gs.name}: ring tip circle inside its base circle")
        if 2 * self.r_c * math.sin(math.pi / N) <= 2 * self.ra_p + 0.5 * m:
            raise ValueError(f"{gs.name}: {N} planets of {Zp} teeth do not fit side by side")
        ta = math.tan(al)
        # sun-planet mesh: the sun drives (carrier frame), contact from the planet's tip to the sun's tip.
        # AP = distance from the start of the path of contact to the pitch point, PE = pitch point to end.
        self.AP_s = math.sqrt(self.ra_p ** 2 - self.rb_p ** 2) - self.rb_p * ta
        self.PE_s = math.sqrt(self.ra_s ** 2 - self.rb_s ** 2) - self.rb_s * ta
        # planet-ring mesh: the planet drives the ring (carrier frame), contact from the ring's tip to the planet's tip
        self.AP_r = self.rb_r * ta - math.sqrt(self.ra_r ** 2 - self.rb_r ** 2)
        self.PE_r = math.sqrt(self.ra_p ** 2 - self.rb_p ** 2) - self.rb_p * ta
        # involute interference: the path must start outside the driver's base tangent point
        if self.rb_s * ta - self.AP_s <= 0 or self.rb_p * ta - self.AP_r <= 0:
            raise ValueError(f"{gs.name}: involute interference (path of contact starts inside a base circle)")
        self.g_s, self.g_r = self.AP_s + self.PE_s, self.AP_r + self.PE_r
        self.eps_s, self.eps_r = self.g_s / self.pb, self.g_r / self.pb
        if min(self.eps_s, self.eps_r) < 1.1:
            raise ValueError(f"{gs.name}: contact ratio {min(self.eps_s, self.eps_r):.3f} < 1.1")
        # ISO 6336-1 single stiffness without the load correction (pinion = fewer teeth; internal: zn2 = inf)
        self.cprime0_s = iso_single_stiffness(min(Zs, Zp), max(Zs, Zp), hfp_over_m=gs.dedendum_coef,
                                              alpha_deg=gs.pressure_angle_deg)
        self.cprime0_r = iso_single_stiffness(Zp, math.inf, hfp_over_m=gs.dedendum_coef,
                                              alpha_deg=gs.pressure_angle_deg)
        # single-pair stiffness shape: parabola with vertex c' at the pitch point, curvature such that the
        # mean mesh stiffness is ISO's c_gamma_alpha: <f> = 0.75 + 0.25/eps  (README section 2)
        self.xiP_s, self.xiP_r = self.AP_s / self.g_s, self.AP_r / self.g_r
        self.kap_s = self._kappa(self.eps_s, self.xiP_s)
        self.kap_r = self._kappa(self.eps_r, self.xiP_r)
        # ---- inertias (steel discs, README section 1.3)
        rho = gs.density_kg_m3
        self.J_s = 0.5 * rho * math.pi * b * (self.r_s ** 4 - (0.35 * self.r_s) ** 4)
        r_bore = 0.45 * self.r_p
        self.m_p = rho * math.pi * b * (self.r_p ** 2 - r_bore ** 2)
        self.J_p = 0.5 * self.m_p * (self.r_p ** 2 + r_bore ** 2)
        t_pl, R_pl, r_hole = 0.4 * b, self.r_c + 0.7 * self.r_p, 0.3 * self.r_c
        J_plates = 2 * 0.5 * rho * math.pi * t_pl * (R_pl ** 4 - r_hole ** 4)
        r_pin = 0.4 * self.r_p
        m_pin = rho * math.pi * r_pin ** 2 * (b + 2 * t_pl)
        self.J_c = J_plates + N * (self.m_p + m_pin) * self.r_c ** 2
        self.psi = 2 * math.pi * np.arange(N) / N
        # ---- DOFs
        self.n = N + 4
        self.im, self.is_, self.ic, self.ib = 0, 1, 2, 3 + N
        self.ip = np.arange(3, 3 + N)
        self.M = np.zeros(self.n)
        self.M[[0, 1, 2, 3 + N]] = [rig.J_motor, self.J_s, self.J_c, rig.J_brake]
        self.M[self.ip] = self.J_p
        self._matrices()
        self._tune_shafts()

    @staticmethod
    def _kappa(eps, xiP):
        return 0.25 * (1.0 - 1.0 / eps) / (1.0 / 3.0 - xiP + xiP ** 2)

    # kinematics ---------------------------------------------------------------------------------
    def speeds(self, rpm):
        """Nominal absolute speeds of the DOFs [rad/s] at a sun speed in rpm."""
        gs = self.gs
        Ws = rpm * 2 * math.pi / 60
        Wc = Ws * gs.Zs / (gs.Zs + gs.Zr)
        Wp = -Wc * (gs.Zr - gs.Zp) / gs.Zp
        W = np.empty(self.n)
        W[[0, 1, 2, 3 + gs.N]] = [Ws, Ws, Wc, Wc]
        W[self.ip] = Wp
        return W

    def mesh_frequency(self, rpm):
        gs = self.gs
        return gs.Zs * gs.Zr / (gs.Zs + gs.Zr) * rpm / 60.0

    # matrices ------------------------------------------------------------------------------------
    def _matrices(self):
        gs, N, n = self.gs, self.gs.N, self.n
        Mm = 2 * N
        ta = math.tan(self.alpha)
        G = np.zeros((Mm, n))        # mesh deflection along the line of action = G q (+ errors)
        Uc = np.zeros((Mm, n))       # roll coordinate along the line of action = Uc theta_total + u0
        u0 = np.zeros(Mm)
        Af = np.zeros((Mm, n))       # sliding velocity v = Af omega + w Bf omega (w: distance from the pitch point)
        Bf = np.zeros((Mm, n))
        # relative phase of a planet's ring mesh behind its sun mesh, in mesh cycles (README section 1.4)
        self.ring_lag = ((gs.Zp - 1) / 2.0) % 1.0
        for i in range(N):
            p = 3 + i
            # sun-planet i: delta = rb_s x_s - rc_b x_c + rb_p x_p
            G[i, 1], G[i, 2], G[i, p] = self.rb_s, -self.rc_b, self.rb_p
            Uc[i, 1], Uc[i, 2] = self.rb_s, -self.rb_s
            u0[i] = -self.rb_s * self.psi[i]
            Af[i, 1] += self.rb_s * ta
            Af[i, p] += self.rb_p * ta
            Af[i, 2] -= (self.rb_s + self.rb_p) * ta
            Bf[i, 1], Bf[i, p] = 1.0, -1.0
            # planet i-ring: delta = -rc_b x_c - rb_p x_p
            j = N + i
            G[j, 2], G[j, p] = -self.rc_b, -self.rb_p
            Uc[j, 2] = self.rb_r
            u0[j] = self.rb_r * self.psi[i] - self.ring_lag * self.pb
            Af[j, p] += self.rb_p * ta
            Af[j, 2] += (self.rb_r - self.rb_p) * ta
            Bf[j, p] = 1.0
        self.G, self.Uc, self.u0, self.Af, self.Bf = G, Uc, u0, Af, Bf
        self.Mm = Mm
        # per-mesh constants (first N sun meshes, then N ring meshes)
        S, R = slice(0, N), slice(N, Mm)
        self.AP = np.empty(Mm); self.AP[S], self.AP[R] = self.AP_s, self.AP_r
        self.PE = np.empty(Mm); self.PE[S], self.PE[R] = self.PE_s, self.PE_r
        self.gpath = self.AP + self.PE
        self.xiP = np.empty(Mm); self.xiP[S], self.xiP[R] = self.xiP_s, self.xiP_r
        self.kap = np.empty(Mm); self.kap[S], self.kap[R] = self.kap_s, self.kap_r
        self.eps = np.empty(Mm); self.eps[S], self.eps[R] = self.eps_s, self.eps_r
        self.P = int(math.floor(max(self.eps_s, self.eps_r))) + 1   # pair slots per mesh
        # equivalent masses of the pairs along the line of action
        me_s = 1.0 / (self.rb_s ** 2 / self.J_s + self.rb_p ** 2 / self.J_p)
        me_r = self.J_p / self.rb_p ** 2
        self.m_e = np.empty(Mm); self.m_e[S], self.m_e[R] = me_s, me_r

    def cprime(self, rpm, power_W):
        """ISO c' [N/(mm um)] of the sun-planet and planet-ring meshes at an operating point (load-corrected)."""
        gs = self.gs
        Ts = power_W / (rpm * 2 * math.pi / 60)
        Ft = Ts / (gs.N * self.r_s)                      # nominal tangential load per mesh at the reference circle
        w = Ft / (gs.face_width_m * 1e3)                 # N/mm, K_A = 1
        cs = iso_single_stiffness(min(gs.Zs, gs.Zp), max(gs.Zs, gs.Zp), hfp_over_m=gs.dedendum_coef,
                                  alpha_deg=gs.pressure_angle_deg, line_load_N_mm=w)
        cr = iso_single_stiffness(gs.Zp, math.inf, hfp_over_m=gs.dedendum_coef, alpha_deg=gs.pressure_angle_deg,
                                  line_load_N_mm=w)
        return cs, cr, w

    def mesh_levels(self, rpm, power_W, stiffness_scale=1.0):
        """Per mesh: peak single-pair stiffness k' = c' b and mean mesh stiffness c_gamma_alpha b [N/m]."""
        cs, cr, _ = self.cprime(rpm, power_W)
        N = self.gs.N
        c = np.empty(self.Mm); c[:N], c[N:] = cs, cr
        kpk = c * N_PER_MM_UM * self.gs.face_width_m * stiffness_scale
        kmean = iso_mesh_stiffness(kpk, self.eps)
        return kpk, kmean

    def pair_shape(self, m, w):
        """Normalized single-pair stiffness at distance w from the pitch point (0 outside the path)."""
        xi = (w + self.AP[m]) / self.gpath[m]
        f = 1.0 - self.kap[m] * (xi - self.xiP[m]) ** 2
        return np.where((w >= -self.AP[m]) & (w <= self.PE[m]), np.maximum(f, 0.3), 0.0)

    def mesh_stiffness_cycle(self, m, kpk, npts=2000):
        """Mesh stiffness of mesh m over one mesh cycle (roll u in [0, p_b)) [N/m]."""
        u = np.arange(npts) * self.pb / npts
        K = np.zeros(npts)
        for q in range(-4, 5):
            K += kpk * self.pair_shape(m, u - q * self.pb)
        return u, K

    def linear_K(self, kmean, k_in=None, k_out=None):
        k_in = self.k_in if k_in is None else k_in
        k_out = self.k_out if k_out is None else k_out
        K = self.G.T @ (kmean[:, None] * self.G)
        K[0, 0] += k_in; K[1, 1] += k_in; K[0, 1] -= k_in; K[1, 0] -= k_in
        c, bb = self.ic, self.ib
        K[c, c] += k_out; K[bb, bb] += k_out; K[c, bb] -= k_out; K[bb, c] -= k_out
        return K

    def _shaft_matrix(self, k_in, k_out):
        K = np.zeros((self.n, self.n))
        K[0, 0] += k_in; K[1, 1] += k_in; K[0, 1] -= k_in; K[1, 0] -= k_in
        c, bb = self.ic, self.ib
        K[c, c] += k_out; K[bb, bb] += k_out; K[c, bb] -= k_out; K[bb, c] -= k_out
        return K

    def _bearing_matrix(self):
        r = self.rig
        C = np.zeros((self.n, self.n))
        C[1, 1] += r.bearing_c_sun
        C[2, 2] += r.bearing_c_carrier
        for p in self.ip:      # planet bearing: drag on (omega_p - omega_c)
            C[p, p] += r.bearing_c_planet; C[2, 2] += r.bearing_c_planet
            C[p, 2] -= r.bearing_c_planet; C[2, p] -= r.bearing_c_planet
        return C

    def modes(self, K):
        """Undamped natural frequencies [Hz] and mode shapes of M q'' + K q = 0 (rigid mode first)."""
        Ms = 1.0 / np.sqrt(self.M)
        A = Ms[:, None] * K * Ms[None, :]
        lam, V = np.linalg.eigh(A)
        f = np.sqrt(np.maximum(lam, 0.0)) / (2 * math.pi)
        return f, Ms[:, None] * V

    def _tune_shafts(self):
        """Shaft stiffnesses that put the input- and output-shaft modes at the rig's targets (ISO levels
        at 100 N/mm, i.e. without load correction; the shaft modes hardly depend on the mesh level)."""
        r = self.rig
        N = self.gs.N
        c = np.empty(self.Mm); c[:N], c[N:] = self.cprime0_s, self.cprime0_r
        kmean = iso_mesh_stiffness(c * N_PER_MM_UM * self.gs.face_width_m, self.eps)
        # first guesses: motor against the sun side, brake against the carrier side
        Wr = self.speeds(60 / (2 * math.pi))      # ratios of the rigid mode
        Jsun_side = sum(self.M[k] * (Wr[k] / Wr[1]) ** 2 for k in range(1, self.n - 1))
        Jcar_side = sum(self.M[k] * (Wr[k] / Wr[2]) ** 2 for k in range(0, self.n - 1))
        k_in = (2 * math.pi * r.f_input_shaft_Hz) ** 2 / (1 / r.J_motor + 1 / Jsun_side)
        k_out = (2 * math.pi * r.f_output_shaft_Hz) ** 2 / (1 / r.J_brake + 1 / Jcar_side)
        # the two lowest elastic modes are the shaft modes: solve f_1, f_2 = the sorted targets
        tgt = np.sort([r.f_input_shaft_Hz, r.f_output_shaft_Hz])

        def resid(lk):
            f = self.modes(self.linear_K(kmean, math.exp(lk[0]), math.exp(lk[1])))[0]
            return np.log(f[1:3] / tgt)

        import scipy.optimize
        sol = scipy.optimize.fsolve(resid, [math.log(k_in), math.log(k_out)], xtol=1e-12)
        if np.max(np.abs(resid(sol))) > 1e-6:
            raise ValueError(f"{self.gs.name}: cannot place the shaft modes at {tgt} Hz")
        k_in, k_out = math.exp(sol[0]), math.exp(sol[1])
        self.k_in, self.k_out = k_in, k_out
        self.c_in = 2 * r.shaft_zeta * k_in / (2 * math.pi * r.f_input_shaft_Hz)
        self.c_out = 2 * r.shaft_zeta * k_out / (2 * math.pi * r.f_output_shaft_Hz)
        f, _ = self.modes(self.linear_K(kmean))
        self.f_modes_ref = f

    # quasi-static efficiency: sets the brake so that the nominal stage runs at its operating point
    def quasi_static_loss(self, rpm, power_W, mu):
        """Mean friction + bearing loss [W] of the healthy stage at an operating point: every mesh loaded
        by its nominal force, shared between the pairs in proportion to their stiffness (equal
        deflection), sliding velocity w (omega_1 -+ omega_2) from the nominal speeds."""
        W = self.speeds(rpm)
        Ts = power_W / W[1]
        F = Ts / (self.gs.N * self.rb_s)   # normal force per mesh
        kpk, _ = self.mesh_levels(rpm, power_W)
        loss = 0.0
        for m in (0, self.gs.N):
            u = (np.arange(4000) + 0.5) * self.pb / 4000
            ws = u[:, None] - np.arange(-4, 5)[None, :] * self.pb
            ks = self.pair_shape(m, ws)
            share = ks / ks.sum(1, keepdims=True)
            v = (self.Af[m] @ W) + ws * (self.Bf[m] @ W)
            s = (2 / math.pi) * np.arctan(v / FRICTION_V_EPS)
            loss += self.gs.N * mu * F * np.mean(np.sum(share * s * v, axis=1))
        Cb = self._bearing_matrix()
        loss += W @ Cb @ W
        return loss


# ----------------------------------------------------------------------------------------------
# Batch simulation
# ----------------------------------------------------------------------------------------------

def _gen_alpha(rho):
    am = (2 * rho - 1) / (rho + 1)
    af = rho / (rho + 1)
    gam = 0.5 - am + af
    beta = 0.25 * (1 - am + af) ** 2
    return am, af, gam, beta


class _Op:
    """Per-case constants of a batch."""

    def __init__(self, st: Stage, cases):
        B, Mm, N = len(cases), st.Mm, st.gs.N
        gs, rig = st.gs, st.rig
        self.B = B
        self.Om = np.array([st.speeds(c.rpm) for c in cases])
        self.kpk = np.empty((B, Mm)); self.kmean = np.empty((B, Mm))
        self.cm = np.empty((B, Mm)); self.bl = np.empty((B, Mm))
        self.mu = np.empty(B); self.hw_lo = np.empty(B); self.hw_hi = np.empty(B)
        self.eps0 = np.zeros((B, Mm)); self.es = np.zeros(B); self.es_ph = np.zeros(B)
        self.Tst = np.empty(B); self.w0 = np.empty(B); self.cb = np.empty(B)
        self.rip_r = np.zeros(B); self.rip_k = np.ones(B); self.rip_ph = np.zeros(B)
        self.Tin = np.empty(B); self.Tout = np.empty(B); self.loss_qs = np.empty(B)
        self.line_load = np.empty(B)
        Ltab = [int(np.lcm(gs.Zs, gs.Zp))] * N + [int(np.lcm(gs.Zr, gs.Zp))] * N
        self.Ltab = np.array(Ltab, dtype=np.int64)
        self.offtab = np.concatenate([[0], np.cumsum(self.Ltab)[:-1]]).astype(np.int64)
        self.table = np.ones((B, int(self.Ltab.sum())))
        self.any_damage = False
        al = st.alpha
        for k, c in enumerate(cases):
            f = c.faults
            kpk, kmean = st.mesh_levels(c.rpm, c.power_W, f.stiffness_scale)
            self.kpk[k], self.kmean[k] = kpk, kmean
            self.line_load[k] = st.cprime(c.rpm, c.power_W)[2]
            self.cm[k] = f.damping_scale * 2 * MESH_ZETA * np.sqrt(kmean * st.m_e)
            self.bl[k, :N] = gs.backlash_sp_m * f.backlash_factor
            self.bl[k, N:] = gs.backlash_pr_m * f.backlash_factor
            self.mu[k] = gs.friction * f.friction_factor
            self.hw_lo[k], self.hw_hi[k] = f.worn_depth_m, 0.6 * f.worn_depth_m
            # geometric mesh errors [m] added to the compression (README section 5)
            pins = np.zeros(N) if len(f.pin_error_m) == 0 else np.asarray(f.pin_error_m, float)
            if len(pins) != N:
                raise ValueError("pin_error_m needs N values")
            self.eps0[k, :N] -= pins * math.cos(al)
            self.eps0[k, N:] -= pins * math.cos(al)
            ec, phc = f.carrier_ecc_m, f.carrier_ecc_phase_rad
            self.eps0[k, :N] -= ec * np.sin(phc - st.psi + al)
            self.eps0[k, N:] -= ec * np.sin(phc - st.psi - al)
            self.es[k], self.es_ph[k] = f.sun_ecc_m, f.sun_ecc_phase_rad
            # motor and brake at the operating point (README section 3)
            W = self.Om[k]
            Tin = c.power_W / W[1]
            loss = st.quasi_static_loss(c.rpm, c.power_W, gs.friction)   # the rig is set up on the healthy stage
            self.loss_qs[k] = loss
            Tout = (c.power_W - loss) / W[2]
            self.Tin[k], self.Tout[k] = Tin, Tout
            self.w0[k] = W[0] * (1 + rig.motor_sag)
            self.Tst[k] = Tin * (1 + rig.motor_sag) / rig.motor_sag
            self.cb[k] = Tout / W[st.ib] ** 2
            self.rip_r[k], self.rip_k[k], self.rip_ph[k] = f.ripple_fraction, f.ripple_order, f.ripple_phase_rad
            # damaged tooth: lookup table over lcm(Z_gear, Zp) passes per mesh
            if f.tooth_body and f.tooth_stiffness_factor != 1.0:
                self.any_damage = True
                fs = np.ones(gs.Zs); fp = np.ones((N, gs.Zp)); fr = np.ones(gs.Zr)
                if f.tooth_body == "sun":
                    fs[f.tooth_index % gs.Zs] = f.tooth_stiffness_factor
                elif f.tooth_body == "planet":
                    fp[f.tooth_planet % N, f.tooth_index % gs.Zp] = f.tooth_stiffness_factor
                elif f.tooth_body == "ring":
                    fr[f.tooth_index % gs.Zr] = f.tooth_stiffness_factor
                else:
                    raise ValueError(f"unknown tooth body {f.tooth_body!r}")
                h = (gs.Zp - 1) // 2
                for i in range(N):
                    q = np.arange(self.Ltab[i])
                    self.table[k, self.offtab[i]:self.offtab[i] + self.Ltab[i]] = fs[q % gs.Zs] * fp[i, q % gs.Zp]
                    j = N + i
                    q = np.arange(self.Ltab[j])
                    ptooth = (q - h - (gs.Zs + gs.Zr) * i // N) % gs.Zp
                    self.table[k, self.offtab[j]:self.offtab[j] + self.Ltab[j]] = fr[q % gs.Zr] * fp[i, ptooth]
        self.any_sun_runout = bool(np.any(self.es != 0))


def static_start(st: Stage, op: _Op, k):
    """Static deflection at the mean mesh stiffness under the nominal torques and the constant mesh errors."""
    K = st.linear_K(op.kmean[k])
    f = np.zeros(st.n)
    f[0], f[st.ib] = op.Tin[k], -op.Tout[k]
    f -= st.G.T @ (op.kmean[k] * op.eps0[k])
    r = op.Om[k] / op.Om[k][1]
    f -= r * (r @ f) / (r @ r)           # the loads balance only up to the losses: drop the rigid-mode part
    x = np.linalg.lstsq(K, f, rcond=None)[0]
    return x - r * x[1]                    # gauge: sun perturbation 0 at t = 0


def linear_system(st: Stage, op: _Op, k):
    """Linearized M, C, K about the nominal operating point (mean mesh stiffness, motor and brake slopes)."""
    K = st.linear_K(op.kmean[k])
    C = st._shaft_matrix(st.c_in, st.c_out) + st._bearing_matrix() + st.G.T @ (op.cm[k][:, None] * st.G)
    C[0, 0] += op.Tst[k] / op.w0[k]
    C[st.ib, st.ib] += 2 * op.cb[k] * op.Om[k][st.ib]
    return np.diag(st.M), C, K


def warmup_time(st: Stage, op: _Op, decay=1e4):
    """ln(decay) / slowest modal decay rate of the linearized rig (README section 4)."""
    worst = 0.0
    for k in range(op.B):
        Mx, C, K = linear_system(st, op, k)
        n = st.n
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        Mi = 1.0 / np.diag(Mx)
        A[n:, :n] = -Mi[:, None] * K
        A[n:, n:] = -Mi[:, None] * C
        lam = np.linalg.eigvals(A)
        sig = -lam.real
        sig = sig[sig > 1e-9]
        worst = max(worst, math.log(decay) / sig.min())
    return worst


def natural_frequencies(st: Stage, op: _Op, k=0):
    return st.modes(st.linear_K(op.kmean[k]))[0]


def choose_rate(st: Stage, cases, op: _Op):
    """Internal rate: >= 10 steps per period of the 30th mesh harmonic at the fastest case and of the
    highest natural frequency at the stiffest case, rounded up to a multiple of every DAQ rate."""
    fm = max(st.mesh_frequency(c.rpm) for c in cases)
    fnat = max(natural_frequencies(st, op, k).max() for k in range(op.B))
    # the peak pair stiffness exceeds the mean one: use the highest frequency at the peak mesh stiffness
    kmax = np.array([[st.mesh_stiffness_cycle(m, op.kpk[k, m])[1].max() for m in range(st.Mm)]
                     for k in range(op.B)])
    fnat_pk = max(st.modes(st.linear_K(kmax[k]))[0].max() for k in range(op.B))
    need = max(10 * 30 * fm, 10 * fnat)      # fnat_pk is reported (>= 9 steps per period there)
    base = int(np.lcm.reduce([int(round(c.fs_daq)) for c in cases]))
    f_int = base * math.ceil(need / base)
    return f_int, dict(f_mesh_max_Hz=fm, f_nat_max_Hz=fnat, f_nat_peak_stiffness_Hz=fnat_pk, required_Hz=need)


def _sos_housing(rig: Rig, fs):
    """Housing mode a/F = s^2 / (m (s^2 + 2 zeta w s + w^2)), bilinear with prewarping at w."""
    w = 2 * math.pi * rig.housing_f_Hz
    wp = 2 * fs * math.tan(w / (2 * fs))
    b = [1.0 / rig.housing_mass_kg, 0.0, 0.0]
    a = [1.0, 2 * rig.housing_zeta * wp, wp ** 2]
    bz, az = scipy.signal.bilinear(b, a, fs)
    return scipy.signal.tf2sos(bz, az)


def _sos_highpass(fc, fs):
    return scipy.signal.butter(1, fc, btype="highpass", fs=fs, output="sos")


def _sos_antialias(fs_daq, fs):
    """8th-order Butterworth low-pass at 0.4 x the DAQ rate (the DAQ's anti-alias filter)."""
    return scipy.signal.butter(8, 0.4 * fs_daq, fs=fs, output="sos")


class Encoder:
    """Incremental encoder with `lines` lines/rev: the speed is (2 pi / lines) / (time between successive
    edges), the edge times quantized to the counter clock, held until the next edge."""

    def __init__(self, lines, theta0, t0, w0, clock=COUNTER_CLOCK_HZ):
        self.d = 2 * math.pi / lines
        self.clock = clock
        self.c_prev = math.floor(theta0 / self.d)
        self.th_prev, self.t_prev = theta0, t0
        self.t_edge = None
        self.speed = w0

    def run(self, t, th):
        """t, th: step times and angles of one chunk -> held speed [rad/s] at every step."""
        th_all = np.concatenate([[self.th_prev], th])
        t_all = np.concatenate([[self.t_prev], t])
        c = np.floor(th_all / self.d).astype(np.int64)
        c[0] = self.c_prev
        nE = np.diff(c)
        nE = np.maximum(nE, 0)           # the shafts never turn backwards at these loads; a reversal holds the count
        out = np.empty(len(t))
        tot = int(nE.sum())
        if tot == 0:
            out[:] = self.speed
        else:
            idx = np.repeat(np.arange(len(nE)), nE)
            first = np.repeat(np.cumsum(nE) - nE, nE)
            rank = np.arange(tot) - first
            ang = (np.repeat(c[:-1], nE) + 1 + rank) * self.d
            th0, th1 = th_all[idx], th_all[idx + 1]
            te = t_all[idx] + (ang - th0) / (th1 - th0) * (t_all[idx + 1] - t_all[idx])
            te = np.round(te * self.clock) / self.clock
            prev = np.concatenate([[self.t_edge if self.t_edge is not None else np.nan], te[:-1]])
            sp = self.d / (te - prev)
            if self.t_edge is None:
                sp[0] = self.speed
            pos = np.searchsorted(te, t, side="right") - 1
            out = np.where(pos >= 0, sp[np.maximum(pos, 0)], self.speed)
            self.speed = sp[-1]
            self.t_edge = te[-1]
        self.c_prev = max(int(c[-1]), self.c_prev)
        self.th_prev, self.t_prev = th[-1], t[-1]
        return out


def housing_influence(d, alpha, power):
    """Projection of a planet-ring force on the radial sensor axis, sin(d + alpha), times the
    transfer-path influence ((1 + cos d)/2)^power; d = angle of the mesh point from the sensor."""
    return np.sin(d + alpha) * ((1.0 + np.cos(d)) * 0.5) ** power


def simulate_batch(st: Stage, cases, n_iter=2, max_iter=6, iter_tol=5e-3, chunk=4000, f_int=None, warmup_s=None, energy=False,
                   progress=None, record_states=False):
    """Simulate a batch of cases of one stage together (numpy arrays over the cases).

    Returns (results, info): per case a dict with the DAQ-rate channels 'time' [s], 'sun_rpm',
    'carrier_rpm' [rpm], 'housing' [m/s^2], 'a_sp0', 'a_pr0' [m/s^2] (no noise yet), the file's sensor
    angle and diagnostics; info: rates, warm-up, step counts, wall time."""
    t_start = time.time()
    gs, rig = st.gs, st.rig
    B, n, Mm, N, P = len(cases), st.n, st.Mm, gs.N, st.P
    op = _Op(st, cases)
    rate_info = {}
    if f_int is None:
        f_int, rate_info = choose_rate(st, cases, op)
    h = 1.0 / f_int
    D = np.array([int(round(f_int / c.fs_daq)) for c in cases])
    if np.any(np.abs(D * np.array([c.fs_daq for c in cases]) - f_int) > 1e-6 * f_int):
        raise ValueError("internal rate must be a multiple of every DAQ rate")
    if warmup_s is None:
        warmup_s = max(0.4, warmup_time(st, op))
    i0 = np.array([int(math.ceil(warmup_s * f_int / d)) * d for d in D])
    nsamp = np.array([int(round(c.duration_s * c.fs_daq)) for c in cases])
    i_end = i0 + (nsamp - 1) * D
    nsteps = int(i_end.max())
    am, af, gam, beta = _gen_alpha(RHO_INF)
    h2 = h * h
    # ---- constant arrays
    Md = st.M[None, :]
    G, GT = st.G, st.G.T.copy()
    UcT = st.Uc.T.copy()
    u0 = st.u0[None, :]
    GAB = np.concatenate([st.G, st.Af, st.Bf], axis=0)      # (3M, n)
    GABpair = np.repeat(GAB, P, axis=0)                      # (3 M P, n): pair forces -> generalized forces
    AfT, BfT = st.Af.T.copy(), st.Bf.T.copy()
    pb = st.pb
    AP3, PE2 = st.AP[None, :, None], st.PE[None, :]
    ginv3 = (1.0 / st.gpath)[None, :, None]
    xiP3, kap3 = st.xiP[None, :, None], st.kap[None, :, None]
    APinv3, PEinv3 = (1.0 / st.AP)[None, :, None], (1.0 / st.PE)[None, :, None]
    ar = np.arange(P)[None, None, :]
    kpk3 = op.kpk[:, :, None]
    cm, bl3 = op.cm, op.bl[:, :, None]
    mu3 = (2.0 / math.pi) * op.mu[:, None, None]
    hwlo3, hwhi3 = op.hw_lo[:, None, None], op.hw_hi[:, None, None]
    any_wear = bool(np.any(op.hw_lo > 0))
    Om = op.Om
    Kshaft = st._shaft_matrix(st.k_in, st.k_out)
    Clin = st._shaft_matrix(st.c_in, st.c_out) + st._bearing_matrix()
    Cshaft = st._shaft_matrix(st.c_in, st.c_out)
    Cbrg = st._bearing_matrix()
    Q0 = -(Om @ Cbrg)                          # constant bearing drag at the nominal speeds (Cbrg symmetric)
    # one matrix for everything linear in (x, v): [d | d_dot | Af v | Bf v | Kshaft x + Clin v]
    W1 = np.zeros((2 * n, 4 * Mm + n))
    W1[:n, :Mm] = GT
    W1[n:, Mm:2 * Mm] = GT
    W1[n:, 2 * Mm:3 * Mm] = AfT
    W1[n:, 3 * Mm:4 * Mm] = BfT
    W1[:n, 4 * Mm:] = Kshaft.T
    W1[n:, 4 * Mm:] = Clin.T
    OmAf, OmBf = Om @ AfT, Om @ BfT
    ib = st.ib
    inv_veps = 1.0 / FRICTION_V_EPS
    inv_cramp = 1.0 / CONTACT_DAMPING_RAMP_M
    psi_sun = st.psi[None, :]
    al = st.alpha
    # iteration matrix J = (1-am) M + (1-af) (gam h C + beta h^2 K) at the mean mesh stiffness, inverted once
    Jinv = np.empty((B, n, n))
    Cref = np.empty((B, n, n))
    for k in range(B):
        Mx, C, K = linear_system(st, op, k)
        Cref[k] = C
        Jinv[k] = np.linalg.inv((1 - am) * Mx + (1 - af) * (gam * h * C + beta * h2 * K))
    Mdiag = (1 - am) * np.diag(st.M)[None, :, :]
    cx = (1 - af) * h2 * beta
    cv = (1 - af) * h * gam
    # ---- initial state: static deflection, nominal speeds
    x = np.array([static_start(st, op, k) for k in range(B)])
    v = np.zeros((B, n))
    t = 0.0

    def forces(xa, va, ta, geo):
        """Generalized forces Q(x, v, t) and the pair-level quantities (for the outputs)."""
        k, w, e_pair, ks_inv = geo
        Z = np.concatenate([xa, va], axis=1) @ W1
        c = Z[:, :Mm, None] - e_pair                # pair compression along the line of action
        cb_ = c + bl3
        # contact weight: 1 in contact, 0 in the dead zone, a linear ramp over the first C_RAMP of
        # compression so that the damping force does not jump when a flank touches (README section 1.5)
        kinc = k * (np.clip(c * inv_cramp, 0.0, 1.0) + np.clip(cb_ * -inv_cramp, 0.0, 1.0))
        # drive flank: c > 0; coast flank: c < -backlash; dead zone between (README section 1.5);
        # viscous mesh damping shared by the pairs in contact in proportion to their stiffness
        Fj = k * (np.maximum(c, 0.0) + np.minimum(cb_, 0.0)) + (cm * Z[:, Mm:2 * Mm] * ks_inv)[:, :, None] * kinc
        vs = (OmAf + Z[:, 2 * Mm:3 * Mm])[:, :, None] + w * (OmBf + Z[:, 3 * Mm:4 * Mm])[:, :, None]
        gj = mu3 * np.abs(Fj) * np.arctan(vs * inv_veps)     # mu |F| (2/pi) arctan(v / v_eps)
        Q = Q0 - Z[:, 4 * Mm:] - np.concatenate([Fj, gj, gj * w], axis=1).reshape(B, -1) @ GABpair
        wm = Om[:, 0] + va[:, 0]
        thm = Om[:, 0] * ta + xa[:, 0]
        Tm = op.Tst * (1.0 - wm / op.w0) * (1.0 + op.rip_r * np.cos(op.rip_k * thm + op.rip_ph))
        wb = Om[:, ib] + va[:, ib]
        Tb = op.cb * wb * np.abs(wb)
        Q[:, 0] += Tm
        Q[:, ib] -= Tb
        return Q, (Fj, gj, vs, Tm * wm, Tb * wb, kinc, c, Z)

    def geometry(xg, ta):
        th = Om * ta + xg
        u = th @ UcT + u0
        qlo = np.ceil((u - PE2) / pb)
        q = qlo[:, :, None] + ar
        w = u[:, :, None] - q * pb
        valid = w >= -AP3
        xi = (w + AP3) * ginv3
        shp = np.maximum(1.0 - kap3 * (xi - xiP3) ** 2, 0.3)
        k = kpk3 * shp * valid
        if op.any_damage:
            qi = q.astype(np.int64)
            idx = (op.offtab[None, :, None] + qi % op.Ltab[None, :, None]).reshape(B, -1)
            k = k * np.take_along_axis(op.table, idx, axis=1).reshape(B, Mm, P)
        eps_m = op.eps0
        if op.any_sun_runout:
            beta_s = (th[:, 1] - th[:, 2] + op.es_ph)[:, None]
            eps_m = eps_m.copy()
            eps_m[:, :N] += op.es[:, None] * np.sin(beta_s - psi_sun + al)
        if any_wear:
            ew = np.where(w < 0.0, hwlo3 * (w * APinv3) ** 2, hwhi3 * (w * PEinv3) ** 2)
            e_pair = ew - eps_m[:, :, None]
        else:
            e_pair = -eps_m[:, :, None]
        ks = k.sum(2)
        ks_inv = np.where(ks > 0, 1.0 / np.maximum(ks, 1e-30), 0.0)
        return k, w, e_pair, ks_inv

    Q, _ = forces(x, v, t, geometry(x, t))
    a = (Q / Md)
    a_prev = a
    # ---- sensors
    fs_list = sorted({c.fs_daq for c in cases})
    sos_aa = {fs: _sos_antialias(fs, f_int) for fs in fs_list}
    sos_h = np.concatenate([_sos_housing(rig, f_int), _sos_highpass(rig.iepe_highpass_Hz, f_int)])
    # wanted sensor angle phi (from planet 0 at the file's t = 0) -> housing angle with the nominal carrier angle
    phi_h = np.array([c.sensor_angle_rad + Om[k, 2] * i0[k] * h for k, c in enumerate(cases)])
    enc_s = [Encoder(rig.lines_sun, x[k, 1], 0.0, Om[k, 1]) for k in range(B)]
    enc_c = [Encoder(rig.lines_carrier, x[k, 2], 0.0, Om[k, 2]) for k in range(B)]
    zi_h = [None] * B
    zi_aa = [None] * B
    out = [dict(time=np.arange(nsamp[k]) / cases[k].fs_daq, sun_rpm=np.empty(nsamp[k]),
                carrier_rpm=np.empty(nsamp[k]), housing=np.empty(nsamp[k]), a_sp0=np.empty(nsamp[k]),
                a_pr0=np.empty(nsamp[k])) for k in range(B)]
    acc = dict(P_in=np.zeros(B), P_b=np.zeros(B), P_fric=np.zeros(B), n=np.zeros(B), sep=np.zeros(B),
               coast=np.zeros(B), speed_s=np.zeros(B), speed_c=np.zeros(B))
    en = None
    if energy:
        en = dict(P_in=0.0, P_b=0.0, P_fric=0.0, P_mdamp=0.0, P_lin=0.0, E0=None, E1=None, T=0.0)
    rpm = 60.0 / (2 * math.pi)
    theta_c_file0 = np.zeros(B)
    max_corr = 0.0
    n_iters_total = 0
    n_newton = 0
    states = [] if record_states else None

    def energy_state(xx, vv, tt):
        geo = geometry(xx, tt)
        _, extra = forces(xx, vv, tt, geo)
        kinc, c = extra[5], extra[6]
        c_eff = np.where(c > 0, c, np.where(c < -bl3, c + bl3, 0.0))
        om = Om + vv
        KE = 0.5 * (Md * om ** 2).sum(1)
        PEs = 0.5 * np.einsum("bi,ij,bj->b", xx, Kshaft, xx)
        PEm = 0.5 * (kinc * c_eff ** 2).sum((1, 2))
        return KE + PEs + PEm

    step = 0
    while step < nsteps:
        nc = min(chunk, nsteps - step)
        X = np.empty((nc, B, n)); A = np.empty((nc, B, n)); FR = np.empty((nc, B, N))
        PIN = np.empty((nc, B)); PBR = np.empty((nc, B)); PFR = np.empty((nc, B))
        SEP = np.empty((nc, B), bool); COAST = np.empty((nc, B), bool)
        for j in range(nc):
            t1 = t + h
            ta = t1 - af * h
            xb = x + (1 - af) * (h * v + h2 * (0.5 - beta) * a)
            vb = v + (1 - af) * h * (1 - gam) * a
            an = 2.0 * a - a_prev          # predictor: linear extrapolation of the acceleration
            geo = geometry(xb + cx * an, ta)
            for it in range(max_iter):
                xa = xb + cx * an
                va = vb + cv * an
                Q, extra = forces(xa, va, ta, geo)
                R = Md * ((1 - am) * an + am * a) - Q
                da = np.matmul(Jinv, R[:, :, None])[:, :, 0]
                an = an - da
                if it + 1 >= n_iter:
                    ratio = np.abs(da).max() / (np.abs(an).max() + 1e-30)
                    if ratio <= iter_tol:
                        break
            if ratio > iter_tol:
                # rare (a re-engaging mesh): Newton with the tangent of the present contact state
                for it2 in range(12):
                    Kt = np.einsum("mi,bm,mj->bij", G, extra[5].sum(2), G) + Kshaft
                    Jt = Mdiag + (1 - af) * (beta * h2 * Kt + gam * h * Cref)
                    da = np.linalg.solve(Jt, R[:, :, None])[:, :, 0]
                    an = an - da
                    xa = xb + cx * an
                    va = vb + cv * an
                    Q, extra = forces(xa, va, ta, geo)
                    R = Md * ((1 - am) * an + am * a) - Q
                    ratio = np.abs(da).max() / (np.abs(an).max() + 1e-30)
                    it += 1
                    if ratio <= iter_tol:
                        break
                n_newton += 1
            n_iters_total += it + 1
            max_corr = max(max_corr, ratio)
            x = x + h * v + h2 * ((0.5 - beta) * a + beta * an)
            v = v + h * ((1 - gam) * a + gam * an)
            a_prev = a
            a = an
            t = t1
            Fj, gj, vs, pin, pbr, kinc, c, Z = extra
            Fm = Fj.sum(2)
            X[j] = x; A[j] = a; FR[j] = Fm[:, N:]
            PIN[j] = pin; PBR[j] = pbr
            PFR[j] = (gj * vs).sum((1, 2))          # friction loss: sum of mu |F| sgn(v) v
            kc = kinc.sum(2)
            SEP[j] = (kc <= 0.0).any(1)
            COAST[j] = (c < -bl3).any((1, 2))
            if energy:
                gi = step + j + 1
                if gi == int(nsteps * 0.4):
                    en["E0"] = energy_state(x, v, t)
                elif en["E0"] is not None and en["E1"] is None:
                    om_a = Om + va
                    dd = Z[:, Mm:2 * Mm]
                    en["P_in"] += pin * h; en["P_b"] += pbr * h; en["P_fric"] += PFR[j] * h
                    en["P_mdamp"] += (cm * dd ** 2 * kc * geo[3]).sum(1) * h
                    en["P_lin"] += (np.einsum("bi,ij,bj->b", va, Cshaft, va)
                                    + np.einsum("bi,ij,bj->b", om_a, Cbrg, om_a)) * h
                    en["T"] += h
                    if gi == nsteps:
                        en["E1"] = energy_state(x, v, t)
            if record_states:
                states.append((t, x.copy(), v.copy()))
        # ---- sensor chain for this chunk
        gidx = step + 1 + np.arange(nc)           # global step index of each stored state
        tt = gidx * h
        th_s = Om[None, :, 1] * tt[:, None] + X[:, :, 1]
        th_c = Om[None, :, 2] * tt[:, None] + X[:, :, 2]
        asp0 = A @ G[0]
        apr0 = A @ G[N]
        for k in range(B):
            ws = enc_s[k].run(tt, th_s[:, k]) * rpm
            wc = enc_c[k].run(tt, th_c[:, k]) * rpm
            d = st.psi[None, :] + th_c[:, k, None] - phi_h[k]
            Fh = (housing_influence(d, al, rig.window_power) * FR[:, k, :]).sum(1)
            if zi_h[k] is None:
                zi_h[k] = scipy.signal.sosfilt_zi(sos_h) * Fh[0]
            ah, zi_h[k] = scipy.signal.sosfilt(sos_h, Fh, zi=zi_h[k])
            ah = ah * cases[k].faults.sensor_gain_factor
            ch = np.stack([ws, wc, ah, asp0[:, k], apr0[:, k]], axis=1)
            sos = sos_aa[cases[k].fs_daq]
            if zi_aa[k] is None:
                zi_aa[k] = scipy.signal.sosfilt_zi(sos)[:, :, None] * ch[0][None, None, :]
            y, zi_aa[k] = scipy.signal.sosfilt(sos, ch, axis=0, zi=zi_aa[k])
            sel = (gidx >= i0[k]) & (gidx <= i_end[k]) & ((gidx - i0[k]) % D[k] == 0)
            if sel.any():
                si = (gidx[sel] - i0[k]) // D[k]
                o = out[k]
                o["sun_rpm"][si] = y[sel, 0]; o["carrier_rpm"][si] = y[sel, 1]; o["housing"][si] = y[sel, 2]
                o["a_sp0"][si] = y[sel, 3]; o["a_pr0"][si] = y[sel, 4]
            rec = (gidx >= i0[k]) & (gidx <= i_end[k])
            if np.any(gidx == i0[k]):
                theta_c_file0[k] = th_c[gidx == i0[k], k][0]
            if rec.any():
                acc["P_in"][k] += PIN[rec, k].sum(); acc["P_b"][k] += PBR[rec, k].sum()
                acc["P_fric"][k] += PFR[rec, k].sum(); acc["n"][k] += rec.sum()
                acc["sep"][k] += SEP[rec, k].sum(); acc["coast"][k] += COAST[rec, k].sum()
        step += nc
        if progress:
            progress(step, nsteps, time.time() - t_start)
    results = []
    for k, c in enumerate(cases):
        o = out[k]
        nn = max(acc["n"][k], 1)
        ang = (phi_h[k] - theta_c_file0[k]) % (2 * math.pi)
        o.update(sensor_angle_rad=ang, sensor_angle_deg=math.degrees(ang),
                 mean_P_in_W=acc["P_in"][k] / nn, mean_P_brake_W=acc["P_b"][k] / nn,
                 mean_P_friction_W=acc["P_fric"][k] / nn, separated_fraction=acc["sep"][k] / nn,
                 coast_contact_fraction=acc["coast"][k] / nn,
                 mean_sun_rpm=float(np.mean(o["sun_rpm"])), mean_carrier_rpm=float(np.mean(o["carrier_rpm"])),
                 line_load_N_mm=float(op.line_load[k]), quasi_static_loss_W=float(op.loss_qs[k]),
                 T_stall_Nm=float(op.Tst[k]), w_noload_rad_s=float(op.w0[k]), brake_c_Nms2=float(op.cb[k]),
                 mesh_stiffness_mean_N_m=[float(op.kmean[k, 0]), float(op.kmean[k, N])])
        results.append(o)
    info = dict(f_int_Hz=f_int, dt_s=h, warmup_s=float(i0.max() * h), warmup_rule_s=warmup_s, steps=nsteps,
                n_iter=n_iter, mean_iterations=n_iters_total / max(nsteps, 1), newton_fallback_steps=n_newton, max_final_correction_ratio=max_corr, wall_s=time.time() - t_start,
                k_in=st.k_in, k_out=st.k_out, c_in=st.c_in, c_out=st.c_out, **rate_info)
    if energy:
        info["energy"] = en
    if record_states:
        info["states"] = states
    return results, info


def add_daq_noise(ch, rng, noise_fraction=0.05, dc_fraction=0.0):
    """White Gaussian noise of std noise_fraction x the channel's RMS about its mean, plus a DC offset of
    dc_fraction x that RMS (accelerometer channels)."""
    rms = float(np.std(ch))
    return ch + rng.normal(0.0, noise_fraction * rms, size=ch.shape) + dc_fraction * rms


def describe(st: Stage):
    """Numbers of a stage for the README / corpus log."""
    gs = st.gs
    return dict(Zs=gs.Zs, Zp=gs.Zp, Zr=gs.Zr, N=gs.N, module_m=gs.module_m, face_width_m=gs.face_width_m,
                eps_sun_planet=st.eps_s, eps_planet_ring=st.eps_r, AP_s=st.AP_s, PE_s=st.PE_s, AP_r=st.AP_r,
                PE_r=st.PE_r, cprime_sp_N_mm_um=st.cprime0_s, cprime_pr_N_mm_um=st.cprime0_r,
                J_sun=st.J_s, J_planet=st.J_p, m_planet=st.m_p, J_carrier=st.J_c, J_motor=st.rig.J_motor,
                J_brake=st.rig.J_brake, k_in=st.k_in, k_out=st.k_out, c_in=st.c_in, c_out=st.c_out,
                ring_lag_cycles=st.ring_lag, in_phase=(gs.Zs % gs.N == 0),
                modes_Hz_at_iso_100N_mm=[float(f) for f in st.f_modes_ref])
