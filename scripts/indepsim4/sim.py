#!/usr/bin/python3
"""indepsim4: a planetary stage on a test rig, the lumped-parameter literature's k(t) model.

* Lin & Parker (1999, J. Vib. Acoust. 121:316) translational-torsional model: sun, ring, carrier
  (x, y, u = r theta) and planets (zeta, eta, u) in the frame rotating with the carrier at the
  nominal speed; gyroscopic and centripetal terms NEGLECTED (Omega_c << the natural frequencies).
* Mesh stiffness as a function of TIME at the nominal mesh frequency (Kahraman 1994; Lin & Parker
  2002): a rectangular wave between k_min = c' b and k_max = 1.75 c' b (mean c_gamma_alpha b,
  ISO 6336-1 method B), edges tanh-smoothed over 2 % of a mesh cycle; mesh phasing of Parker & Lin
  (2004, J. Mech. Des. 126:365).
* Backlash dead zone (Kahraman), mesh damping in contact, errors e(t) entering as delta - e(t).
* Coulomb friction mu F sgn(v), sign reversing at the pitch point at a fixed fraction of the mesh
  cycle (tanh-smoothed), moment arms varying linearly through the cycle (Vaishya & Singh style).
* Rig: PI speed-controlled motor -> torsional coupling -> sun; carrier -> output shaft -> load
  inertia with a constant torque.
* Fixed-step RK4, batched over recordings (B x n numpy arrays).
README.md next to this file for the equations and sources.
"""
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np
from scipy import signal

ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
C_M, C_R, C_B = 0.8, 1.0, 0.975
MESH_ZETA = 0.05
EDGE_SMOOTH = 0.02      # tanh edge width of the stiffness wave and of the friction sign [mesh cycles]
K_MAX_OVER_SINGLE = 1.75  # k_max = 1.75 c'b, k_min = c'b -> mean c'b (0.25 + 0.75 eps) = c_gamma_alpha b


@dataclass
class GearSet:
    name: str
    Zs: int
    Zp: int
    Zr: int
    N: int
    module_m: float
    face_width_m: float
    friction: float
    backlash_sp_m: float
    backlash_pr_m: float
    pressure_angle_deg: float = 20.0
    shift_s: float = 0.0
    shift_p: float = 0.0
    shift_r: float = 0.0
    addendum_coef: float = 1.0
    dedendum_coef: float = 1.25
    youngs_modulus_Pa: float = 206e9
    poisson_ratio: float = 0.3
    density_kg_m3: float = 7850.0


@dataclass
class Rig:
    J_motor: float = 0.05            # motor rotor [kg m^2]
    J_load: float = 0.3              # load machine (dyno) [kg m^2]
    f_input_shaft_Hz: float = 45.0   # target of the coupling stiffness (motor vs the train)
    f_output_shaft_Hz: float = 220.0  # target of the output shaft stiffness (load vs the carrier)
    shaft_zeta: float = 0.03
    speed_loop_bw_Hz: float = 10.0
    tacho_bw_Hz: float = 1500.0      # first-order low pass of the speed sensors
    k_bearing: float = 1e8           # k_s = k_r = k_c = k_p [N/m]
    k_ring_u: float = 1e9            # ring torsional support, in u units [N/m]
    bearing_zeta_1kHz: float = 0.02  # stiffness-proportional bearing damping, zeta at 1 kHz


@dataclass
class Faults:
    tooth_body: str = ""             # "sun", "planet", "ring" or ""
    tooth_planet: int = 0
    tooth_index: int = 0
    tooth_stiffness_factor: float = 1.0
    pin_error_m: tuple = ()
    sun_ecc_m: float = 0.0
    sun_ecc_phase_rad: float = 0.0
    carrier_ecc_m: float = 0.0
    carrier_ecc_phase_rad: float = 0.0
    ripple_fraction: float = 0.0
    ripple_order: float = 1.0
    ripple_phase_rad: float = 0.0
    worn_depth_m: float = 0.0
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
    sensor_angle_rad: float = 0.0    # wanted angle, relative to planet 0 at the recording's t = 0
    faults: Faults = field(default_factory=Faults)


# ------------------------------------------------------------------------------------------
# ISO 6336-1 and involute geometry
# ------------------------------------------------------------------------------------------

def iso_single_stiffness(z1, z2, x1=0.0, x2=0.0):
    """c' [N/(mm um)] by ISO 6336-1 method B; z2 = inf for an internal gear (ring)."""
    C = ISO_C
    inv2 = 0.0 if math.isinf(z2) else 1.0 / z2
    q = (C[0] + C[1] / z1 + C[2] * inv2 + C[3] * x1 + C[4] * x1 / z1 + C[5] * x2 + C[6] * x2 * inv2
         + C[7] * x1 ** 2 + C[8] * x2 ** 2)
    return 1.0 / q * C_M * C_R * C_B


def contact_ratio_external(r1, r2, m, alpha):
    rb1, rb2 = r1 * math.cos(alpha), r2 * math.cos(alpha)
    ra1, ra2 = r1 + m, r2 + m
    pb = math.pi * m * math.cos(alpha)
    return (math.sqrt(ra1 ** 2 - rb1 ** 2) + math.sqrt(ra2 ** 2 - rb2 ** 2) - (r1 + r2) * math.sin(alpha)) / pb


def contact_ratio_internal(rp, rr, m, alpha):
    rbp, rbr = rp * math.cos(alpha), rr * math.cos(alpha)
    rap, rar = rp + m, rr - m
    pb = math.pi * m * math.cos(alpha)
    return (math.sqrt(rap ** 2 - rbp ** 2) - math.sqrt(rar ** 2 - rbr ** 2) + (rr - rp) * math.sin(alpha)) / pb


# ------------------------------------------------------------------------------------------
# Lin & Parker (1999) rows: every spring as a row g with deflection g.q
# ------------------------------------------------------------------------------------------

def lp_layout(N, rig=False):
    """DOF indices: carrier (x,y,u) 0..2, ring 3..5, sun 6..8, planet n: 9+3n .. 11+3n (zeta, eta, u);
    with rig: motor angle, load angle at the end."""
    n = 9 + 3 * N + (2 if rig else 0)
    idx = dict(xc=0, yc=1, uc=2, xr=3, yr=4, ur=5, xs=6, ys=7, us=8, n=n)
    if rig:
        idx["phim"], idx["phil"] = 9 + 3 * N, 10 + 3 * N
    return idx


def lp_rows(N, alpha_s, alpha_r, psi, n):
    """Mesh rows (sun-planet n, ring-planet n) and bearing rows exactly as Lin & Parker (1999) Eq. (2)-(3):
    delta_sn = -x_s sin psi_sn + y_s cos psi_sn - zeta_n sin a_s - eta_n cos a_s + u_s + u_n, psi_sn = psi_n - a_s
    delta_rn = -x_r sin psi_rn + y_r cos psi_rn + zeta_n sin a_r - eta_n cos a_r + u_r - u_n, psi_rn = psi_n + a_r
    planet bearing: radial x_c cos psi_n + y_c sin psi_n - zeta_n, tangential -x_c sin psi_n + y_c cos psi_n + u_c - eta_n."""
    Gs = np.zeros((N, n))
    Gr = np.zeros((N, n))
    Bp = []
    for i in range(N):
        z, e, u = 9 + 3 * i, 10 + 3 * i, 11 + 3 * i
        ps = psi[i] - alpha_s
        Gs[i, 6], Gs[i, 7] = -math.sin(ps), math.cos(ps)
        Gs[i, z], Gs[i, e] = -math.sin(alpha_s), -math.cos(alpha_s)
        Gs[i, 8], Gs[i, u] = 1.0, 1.0
        pr = psi[i] + alpha_r
        Gr[i, 3], Gr[i, 4] = -math.sin(pr), math.cos(pr)
        Gr[i, z], Gr[i, e] = math.sin(alpha_r), -math.cos(alpha_r)
        Gr[i, 5], Gr[i, u] = 1.0, -1.0
        b1 = np.zeros(n)
        b1[0], b1[1], b1[z] = math.cos(psi[i]), math.sin(psi[i]), -1.0
        b2 = np.zeros(n)
        b2[0], b2[1], b2[2], b2[e] = -math.sin(psi[i]), math.cos(psi[i]), 1.0, -1.0
        Bp += [b1, b2]
    return Gs, Gr, np.array(Bp)


def lp_stiffness(N, k_sp, k_rp, k_bearing, k_ru, alpha_s, alpha_r, psi=None, k_su=0.0, k_cu=0.0,
                 k_s=None, k_r=None, k_c=None, n=None):
    """The linear (constant mesh stiffness) stiffness matrix of the gear set [N/m]."""
    psi = [2 * math.pi * i / N for i in range(N)] if psi is None else psi
    n = 9 + 3 * N if n is None else n
    Gs, Gr, Bp = lp_rows(N, alpha_s, alpha_r, psi, n)
    K = k_sp * Gs.T @ Gs + k_rp * Gr.T @ Gr + k_bearing * Bp.T @ Bp
    k_s = k_bearing if k_s is None else k_s
    k_r = k_bearing if k_r is None else k_r
    k_c = k_bearing if k_c is None else k_c
    for j, k in ((0, k_c), (1, k_c), (3, k_r), (4, k_r), (6, k_s), (7, k_s)):
        K[j, j] += k
    K[5, 5] += k_ru
    K[8, 8] += k_su
    K[2, 2] += k_cu
    return K


def lp_mass(N, m_c, m_r, m_s, m_p, J_c, J_r, J_s, J_p, n=None):
    """Diagonal mass vector; J_* = I/r^2 [kg]."""
    n = 9 + 3 * N if n is None else n
    M = np.zeros(n)
    M[0:3] = (m_c, m_c, J_c)
    M[3:6] = (m_r, m_r, J_r)
    M[6:9] = (m_s, m_s, J_s)
    for i in range(N):
        M[9 + 3 * i: 12 + 3 * i] = (m_p, m_p, J_p)
    return M


def natural_frequencies(K, M):
    from scipy.linalg import eigh
    w2 = eigh(K, np.diag(M), eigvals_only=True)
    return np.sqrt(np.clip(w2, 0, None)) / (2 * math.pi)


# ------------------------------------------------------------------------------------------
# The stage on its rig
# ------------------------------------------------------------------------------------------

def _disc(rho, r_out, r_in, b):
    m = rho * math.pi * (r_out ** 2 - r_in ** 2) * b
    return m, 0.5 * m * (r_out ** 2 + r_in ** 2)


class Stage:
    def __init__(self, gs: GearSet, rig: Rig):
        self.gs, self.rig = gs, rig
        N = gs.N
        m, b = gs.module_m, gs.face_width_m
        a = math.radians(gs.pressure_angle_deg)
        self.alpha = a
        self.rs, self.rp, self.rr = gs.Zs * m / 2, gs.Zp * m / 2, gs.Zr * m / 2
        self.rsb, self.rpb, self.rrb = (r * math.cos(a) for r in (self.rs, self.rp, self.rr))
        self.rc = self.rs + self.rp
        self.pb = math.pi * m * math.cos(a)
        self.psi = [2 * math.pi * i / N for i in range(N)]
        # ISO 6336-1 method B stiffness, pinion = the gear with fewer teeth
        z1, z2 = min(gs.Zs, gs.Zp), max(gs.Zs, gs.Zp)
        self.cp_sp = iso_single_stiffness(z1, z2)
        self.cp_rp = iso_single_stiffness(gs.Zp, math.inf)
        self.eps_sp = contact_ratio_external(self.rs, self.rp, m, a)
        self.eps_rp = contact_ratio_internal(self.rp, self.rr, m, a)
        bmm = b * 1e3
        self.k_single_sp = self.cp_sp * bmm * 1e6
        self.k_single_rp = self.cp_rp * bmm * 1e6
        self.k_mean_sp = self.cp_sp * (0.75 * self.eps_sp + 0.25) * bmm * 1e6
        self.k_mean_rp = self.cp_rp * (0.75 * self.eps_rp + 0.25) * bmm * 1e6
        # masses: steel discs (sun and planet: bore 0.3 of the root radius; the sun with an integral
        # shaft stub of its own mass), ring: rim 3 modules beyond the root circle, carrier: two plates
        rho = gs.density_kg_m3
        rf = lambda r: r - gs.dedendum_coef * m  # noqa: E731
        ms, Is = _disc(rho, self.rs, 0.3 * rf(self.rs), b)
        ms, Is = 2 * ms, 2 * Is
        mp, Ip = _disc(rho, self.rp, 0.3 * rf(self.rp), b)
        rrf = self.rr + gs.dedendum_coef * m
        mr, Ir = _disc(rho, rrf + 3 * m, self.rr, b)
        mcp, Icp = _disc(rho, self.rc + 0.6 * self.rp, 0.3 * self.rs, 0.012)
        mc, Ic = 2 * mcp, 2 * Icp
        self.masses = dict(m_s=ms, m_p=mp, m_r=mr, m_c=mc, I_s=Is, I_p=Ip, I_r=Ir, I_c=Ic)
        ix = lp_layout(N, rig=True)
        self.ix = ix
        n = ix["n"]
        self.n = n
        M = lp_mass(N, mc, mr, ms, mp, Ic / self.rc ** 2, Ir / self.rrb ** 2, Is / self.rsb ** 2,
                    Ip / self.rpb ** 2, n=n)
        M[ix["phim"]] = rig.J_motor
        M[ix["phil"]] = rig.J_load
        self.M = M
        Gs, Gr, Bp = lp_rows(N, a, a, self.psi, n)
        self.G = np.vstack([Gs, Gr])  # meshes 0..N-1 sun-planet, N..2N-1 ring-planet
        # bearings (linear part)
        K = rig.k_bearing * Bp.T @ Bp
        for j in (0, 1, 3, 4, 6, 7):
            K[j, j] += rig.k_bearing
        K[ix["ur"], ix["ur"]] += rig.k_ring_u
        beta = 2 * rig.bearing_zeta_1kHz / (2 * math.pi * 1000.0)
        C = beta * K.copy()
        # rig: coupling motor-sun (torque k_in (phi_m - u_s/r_sb)), output shaft carrier-load
        g_in = np.zeros(n)
        g_in[ix["phim"]], g_in[ix["us"]] = 1.0, -1.0 / self.rsb
        g_out = np.zeros(n)
        g_out[ix["uc"]], g_out[ix["phil"]] = 1.0 / self.rc, -1.0
        ratio = gs.Zs / (gs.Zs + gs.Zr)  # Omega_c / Omega_s
        # inertia of the train referred to the sun (rigid gears): sun + (carrier + planets orbit + spin) ratio^2
        w_p_rel = (1 - ratio) * gs.Zs / gs.Zp  # planet spin relative to carrier per unit sun speed
        J_train_c = Ic + N * mp * self.rc ** 2
        J_ref_sun = Is + J_train_c * ratio ** 2 + N * Ip * (ratio - w_p_rel) ** 2
        w_in = 2 * math.pi * rig.f_input_shaft_Hz
        J_rest = J_ref_sun + rig.J_load * ratio ** 2
        self.k_in = w_in ** 2 * rig.J_motor * J_rest / (rig.J_motor + J_rest)
        w_out = 2 * math.pi * rig.f_output_shaft_Hz
        J_c_side = J_ref_sun / ratio ** 2  # the train referred to the carrier (the soft coupling decouples the motor)
        self.k_out = w_out ** 2 * rig.J_load * J_c_side / (rig.J_load + J_c_side)
        K += self.k_in * np.outer(g_in, g_in) + self.k_out * np.outer(g_out, g_out)
        c_in = 2 * rig.shaft_zeta * math.sqrt(self.k_in * rig.J_motor * J_rest / (rig.J_motor + J_rest))
        c_out = 2 * rig.shaft_zeta * math.sqrt(self.k_out * rig.J_load * J_c_side / (rig.J_load + J_c_side))
        C += c_in * np.outer(g_in, g_in) + c_out * np.outer(g_out, g_out)
        # PI speed loop: T_m = T0 - Kp dphi_m - Ki phi_m (its integrator is the angle deviation)
        wb = 2 * math.pi * rig.speed_loop_bw_Hz
        self.J_in_total = rig.J_motor + J_rest
        self.Kp = self.J_in_total * wb
        self.Ki = self.Kp * wb / 4.0
        K[ix["phim"], ix["phim"]] += self.Ki
        C[ix["phim"], ix["phim"]] += self.Kp
        self.K_lin, self.C_lin = K, C
        self.ratio = ratio
        self.g_in, self.g_out = g_in, g_out
        # effective masses of the meshes (torsional), for the mesh damping
        Js, Jp = Is / self.rsb ** 2, Ip / self.rpb ** 2
        self.me_sp = Js * Jp / (Js + Jp)
        self.me_rp = Jp
        self._mesh_geometry()

    # --- mesh geometry: contact path, friction rows, phasing -----------------------------------
    def _mesh_geometry(self):
        gs, N, a, m = self.gs, self.gs.N, self.alpha, self.gs.module_m
        n = self.n
        # carrier-frame nominal velocities (for the sliding direction): per unit sun speed relative to carrier
        ws_rel = 1.0
        wp_rel = -gs.Zs / gs.Zp
        wr_rel = -gs.Zs / gs.Zr
        vnom = np.zeros(n)
        vnom[self.ix["us"]] = self.rsb * ws_rel
        vnom[self.ix["ur"]] = self.rrb * wr_rel
        for i in range(N):
            vnom[11 + 3 * i] = self.rpb * wp_rel
        assert np.allclose(self.G @ vnom, 0, atol=1e-12), "nominal kinematics leave the meshes deflected"
        self.vnom_rel_per_ws = vnom
        H0 = np.zeros((2 * N, n))
        H1 = np.zeros((2 * N, n))
        self.dir = np.zeros(2 * N)
        self.gf = np.zeros(2 * N)
        self.ga = np.zeros(2 * N)
        for k in range(2 * N):
            i = k % N
            psi = self.psi[i]
            er = np.array([math.cos(psi), math.sin(psi)])
            et = np.array([-math.sin(psi), math.cos(psi)])
            Op = self.rc * er
            if k < N:
                d = np.array([-math.sin(psi - a), math.cos(psi - a)])
                Oa, rab, iu_a, ixa, iya = np.zeros(2), self.rsb, 8, 6, 7
                P = self.rs * er
                r1a, r2a = self.rs + m, self.rp + m
            else:
                d = np.array([-math.sin(psi + a), math.cos(psi + a)])
                Oa, rab, iu_a, ixa, iya = np.zeros(2), self.rrb, 5, 3, 4
                P = self.rr * er
                r1a, r2a = self.rr - m, self.rp + m
            p = np.array([-d[1], d[0]])  # k x d
            cr = lambda r, v: r[0] * v[1] - r[1] * v[0]  # noqa: E731
            # Lin & Parker's coefficients of u_a, u_p must follow from the geometry at the pitch point
            sa = cr(P - Oa, d) / rab
            sp = -cr(P - Op, d) / self.rpb
            assert abs(sa - self.G[k, iu_a]) < 1e-9 and abs(sp - self.G[k, 11 + 3 * i]) < 1e-9, (k, sa, sp)
            # contact path along d: inside the planet tip disc and the sun tip disc (external) or outside
            # the ring's tip circle (internal)
            lam = np.linspace(-3 * self.pb, 3 * self.pb, 600001)
            pts = P[None, :] + lam[:, None] * d[None, :]
            inside_p = np.hypot(*(pts - Op).T) <= r2a
            ra = np.hypot(*(pts - Oa).T)
            ok = inside_p & ((ra <= r1a) if k < N else (ra >= r1a))
            # keep the connected part through the pitch point
            j0 = np.argmin(np.abs(lam))
            lo = j0
            while lo > 0 and ok[lo - 1]:
                lo -= 1
            hi = j0
            while hi < len(lam) - 1 and ok[hi + 1]:
                hi += 1
            eps_num = (lam[hi] - lam[lo]) / self.pb
            eps_ref = self.eps_sp if k < N else self.eps_rp
            assert abs(eps_num - eps_ref) < 1e-3, (k, eps_num, eps_ref)
            # contact travel: the direction the driver's surface moves along d (sun for sun meshes, planet
            # for ring meshes, in the carrier frame)
            if k < N:
                v_drv = ws_rel * cr(P - Oa, d)
            else:
                v_drv = wp_rel * cr(P - Op, d)
            dirk = 1.0 if v_drv > 0 else -1.0
            self.dir[k] = dirk
            start, end = (lam[lo], lam[hi]) if dirk > 0 else (lam[hi], lam[lo])
            self.gf[k] = abs(start)   # approach length (start of contact to the pitch point)
            self.ga[k] = abs(end)     # recess length
            # friction row: relative displacement (gear a minus planet) along p at the contact point
            # C = P + lam d: translations . p, rotations theta (C - O) . d (moment arm along the line)
            h0 = np.zeros(n)
            h0[ixa], h0[iya] = p
            h0[9 + 3 * i], h0[10 + 3 * i] = -(p @ er), -(p @ et)
            h0[iu_a] = ((P - Oa) @ d) / rab          # theta_a = u_a / r_ab (checked above)
            h0[11 + 3 * i] = -((P - Op) @ d) / self.rpb
            h1 = np.zeros(n)
            h1[iu_a] = 1.0 / rab
            h1[11 + 3 * i] = -1.0 / self.rpb
            H0[k], H1[k] = h0, h1
        self.H0, self.H1 = H0, H1
        # sliding speed per unit lambda (per unit relative sun speed): v = lam (H1 . vnom) since H0 . vnom = 0
        self.slide0 = H0 @ vnom
        self.slide1 = H1 @ vnom
        assert np.allclose(self.slide0, 0, atol=1e-9), self.slide0
        # a rigid rotation of the whole stage must not slide
        rig = np.zeros(n)
        for j, r in ((2, self.rc), (5, self.rrb), (8, self.rsb)):
            rig[j] = r
        for i in range(N):
            rig[10 + 3 * i], rig[11 + 3 * i] = self.rc, self.rpb
        assert np.allclose(H0 @ rig, 0, atol=1e-9) and np.allclose(H1 @ rig, 0, atol=1e-9)
        assert np.allclose(self.G @ rig, 0, atol=1e-9)
        # Parker & Lin (2004) phasing [mesh cycles]: gamma_sp,n = Zs psi_n/2pi, gamma_rp,n = -Zr psi_n/2pi,
        # ring vs sun of one planet: frac(Zp/2) (both pitch points on the line of centres, the same flank
        # family engaged; a tooth faces a tooth for even Zp and a space for odd Zp)
        self.gamma_rs = (gs.Zp / 2.0) % 1.0
        self.gamma = np.array([gs.Zs * p_ / (2 * math.pi) for p_ in self.psi]
                              + [-gs.Zr * p_ / (2 * math.pi) + self.gamma_rs for p_ in self.psi])

    def mesh_freq(self, rpm):
        fs = rpm / 60.0
        return self.gs.Zs * self.gs.Zr / (self.gs.Zs + self.gs.Zr) * fs

    def linear_K(self, scale=1.0):
        """K with the mean mesh stiffnesses (all meshes in contact)."""
        N = self.gs.N
        km = np.r_[np.full(N, self.k_mean_sp), np.full(N, self.k_mean_rp)] * scale
        return self.K_lin + (self.G.T * km) @ self.G

    def freqs_kmax(self):
        N = self.gs.N
        km = np.r_[np.full(N, self.k_single_sp), np.full(N, self.k_single_rp)] * K_MAX_OVER_SINGLE
        return natural_frequencies(self.K_lin + (self.G.T * km) @ self.G, self.M)


def describe(st: Stage):
    f = st.freqs_kmax()
    fm = natural_frequencies(st.linear_K(), st.M)
    return dict(r_sun_base_m=st.rsb, r_planet_base_m=st.rpb, r_ring_base_m=st.rrb, r_carrier_m=st.rc,
                base_pitch_m=st.pb, contact_ratio_sp=st.eps_sp, contact_ratio_rp=st.eps_rp,
                iso_c_prime_sp_N_mm_um=st.cp_sp, iso_c_prime_rp_N_mm_um=st.cp_rp,
                k_single_sp_N_m=st.k_single_sp, k_single_rp_N_m=st.k_single_rp,
                k_mean_sp_N_m=st.k_mean_sp, k_mean_rp_N_m=st.k_mean_rp,
                approach_m=st.gf.tolist(), recess_m=st.ga.tolist(), mesh_phase_cycles=st.gamma.tolist(),
                masses=st.masses, k_input_coupling_Nm_rad=st.k_in, k_output_shaft_Nm_rad=st.k_out,
                speed_loop_Kp=st.Kp, speed_loop_Ki=st.Ki,
                lowest_freqs_mean_k_Hz=[round(x, 2) for x in fm[:6]],
                highest_freq_kmax_Hz=float(f[-1]))


# ------------------------------------------------------------------------------------------
# Time functions (nominal time) of a batch
# ------------------------------------------------------------------------------------------

def _box(s, lo, hi, w):
    return 0.5 * (np.tanh((s - lo) / w) - np.tanh((s - hi) / w))


class TimeFunctions:
    """Per recording and mesh: k(t), S0(t), S1(t) (friction), e(t), motor torque T_m0(t)."""

    def __init__(self, st: Stage, cases):
        self.st, self.cases = st, cases
        gs, N = st.gs, st.gs.N
        B = len(cases)
        M2 = 2 * N
        self.fm = np.array([st.mesh_freq(c.rpm) for c in cases])         # mesh frequency [Hz]
        self.ws = np.array([c.rpm / 60 * 2 * math.pi for c in cases])    # sun speed [rad/s]
        self.wc = self.ws * st.ratio
        self.T_in = np.array([c.power_W for c in cases]) / self.ws
        self.T_L = np.array([c.power_W for c in cases]) / self.wc
        f = [c.faults for c in cases]
        self.kscale = np.array([x.stiffness_scale for x in f])
        self.mu = np.array([gs.friction * x.friction_factor for x in f])
        ks = np.r_[np.full(N, st.k_single_sp), np.full(N, st.k_single_rp)]
        self.k_single = ks[None, :] * self.kscale[:, None]
        km = np.r_[np.full(N, st.k_mean_sp), np.full(N, st.k_mean_rp)]
        me = np.r_[np.full(N, st.me_sp), np.full(N, st.me_rp)]
        zeta = MESH_ZETA * np.array([x.damping_scale for x in f])
        self.c_mesh = 2 * zeta[:, None] * np.sqrt(km[None, :] * self.kscale[:, None] * me[None, :])
        bl = np.r_[np.full(N, gs.backlash_sp_m), np.full(N, gs.backlash_pr_m)]
        self.backlash = bl[None, :] * np.array([x.backlash_factor for x in f])[:, None]
        # constant mesh errors from pin errors and carrier runout: planet displaced by q_err -> delta += G q_err
        self.e_const = np.zeros((B, M2))
        for b, x in enumerate(f):
            qe = np.zeros(st.n)
            for i, pe in enumerate(x.pin_error_m):
                qe[10 + 3 * i] += pe
            if x.carrier_ecc_m:
                E = x.carrier_ecc_m * np.array([math.cos(x.carrier_ecc_phase_rad), math.sin(x.carrier_ecc_phase_rad)])
                for i in range(N):
                    psi = st.psi[i]
                    qe[9 + 3 * i] += E @ np.array([math.cos(psi), math.sin(psi)])
                    qe[10 + 3 * i] += E @ np.array([-math.sin(psi), math.cos(psi)])
            self.e_const[b] = -(st.G @ qe)
        self.sun_ecc = np.array([x.sun_ecc_m for x in f])
        self.sun_ecc_ph = np.array([x.sun_ecc_phase_rad for x in f])
        self.worn = np.array([x.worn_depth_m for x in f])
        self.ripple = np.array([x.ripple_fraction for x in f])
        self.ripple_k = np.array([x.ripple_order for x in f])
        self.ripple_ph = np.array([x.ripple_phase_rad for x in f])
        # damaged tooth masks
        self.tooth = [(x.tooth_body, x.tooth_planet, x.tooth_index, x.tooth_stiffness_factor) for x in f]
        self.fric_sign = np.sign(st.dir * st.slide1)  # sign of sliding for s > 0 (s along travel)

    def eval(self, t):
        """t: (T,) times -> k (T,B,M), S0, S1 (T,B,M), e (T,B,M), Tm0 (T,B)."""
        st = self.st
        N = st.gs.N
        pb = st.pb
        w = EDGE_SMOOTH
        th = t[:, None, None] * self.fm[None, :, None] - st.gamma[None, None, :]   # (T,B,M) cycles
        fl = np.floor(th)
        fr = th - fl
        gf = st.gf / pb
        ga = st.ga / pb
        T, B, M2 = th.shape
        W = np.zeros_like(th)
        Wphi = np.zeros_like(th)
        S0 = np.zeros_like(th)
        S1 = np.zeros_like(th)
        ewear = np.zeros_like(th)
        wmax = np.maximum(gf, ga)
        fac = np.ones_like(th)
        for kk in (-2, -1, 0, 1):
            s = fr + kk                                   # pair position along the travel [base pitches]
            wk = _box(s, -gf[None, None, :], ga[None, None, :], w)
            npair = fl - kk                               # this pair's pitch-point count
            phi = np.ones_like(th)
            for b, (body, pl, j, f_) in enumerate(self.tooth):
                if not body or f_ == 1.0:
                    continue
                if body == "sun":
                    Zs = st.gs.Zs
                    hit = np.mod(npair[:, b, :N] + j, Zs) == 0      # tooth j passes planet i at theta = -j
                    phi[:, b, :N] = np.where(hit, f_, 1.0)
                elif body == "ring":
                    Zr = st.gs.Zr
                    hit = np.mod(npair[:, b, N:] - j, Zr) == 0      # ring tooth j meets every planet
                    phi[:, b, N:] = np.where(hit, f_, 1.0)
                elif body == "planet":
                    Zp = st.gs.Zp
                    I_pl = int(round((st.gs.Zs + st.gs.Zr) * pl / N))
                    hit_s = np.mod(npair[:, b, pl] - j, Zp) == 0
                    # the same planet tooth meets the ring half a planet revolution later:
                    # theta_r = theta_s + (Zs + Zr) psi/2pi - frac(Zp/2)
                    hit_r = np.mod(npair[:, b, N + pl] - j - (Zp // 2) - I_pl, Zp) == 0
                    phi[:, b, pl] = np.where(hit_s, f_, 1.0)
                    phi[:, b, N + pl] = np.where(hit_r, f_, 1.0)
            W += wk
            Wphi += wk * phi
            sg = np.tanh(s / w) * self.fric_sign[None, None, :]
            S0 += wk * sg
            S1 += wk * sg * (st.dir[None, None, :] * s * pb)
            ewear += wk * phi * (s / wmax[None, None, :]) ** 2
        Wc = np.maximum(W, 1e-9)
        k = self.k_single[None] * (0.25 + 0.75 * W) * (Wphi / Wc)
        S0 /= Wc
        S1 /= Wc
        e = np.broadcast_to(self.e_const[None], th.shape).copy()
        e += self.worn[None, :, None] * ewear / np.maximum(Wphi, 1e-9)
        if np.any(self.sun_ecc):
            ang = self.sun_ecc_ph[None, :] + (self.ws - self.wc)[None, :] * t[:, None]   # (T,B) in the carrier frame
            ex = self.sun_ecc[None, :] * np.cos(ang)
            ey = self.sun_ecc[None, :] * np.sin(ang)
            gx, gy = st.G[:N, 6], st.G[:N, 7]
            e[:, :, :N] -= ex[:, :, None] * gx[None, None, :] + ey[:, :, None] * gy[None, None, :]
        Tm0 = self.T_in[None, :] * (1 + self.ripple[None, :] * np.cos(
            self.ripple_k[None, :] * self.ws[None, :] * t[:, None] + self.ripple_ph[None, :]))
        return k, S0, S1, e, Tm0


# ------------------------------------------------------------------------------------------
# Integration
# ------------------------------------------------------------------------------------------

def static_state(st: Stage, tf: TimeFunctions):
    """Static solution with the mean mesh stiffnesses (all meshes loaded), mean errors included."""
    B = len(tf.cases)
    q0 = np.zeros((B, st.n))
    for b in range(B):
        K = st.K_lin + (st.G.T * (np.r_[np.full(st.gs.N, st.k_mean_sp), np.full(st.gs.N, st.k_mean_rp)]
                                  * tf.kscale[b])) @ st.G
        F = np.zeros(st.n)
        F[st.ix["phim"]] = tf.T_in[b]
        F[st.ix["phil"]] = -tf.T_L[b]
        km = np.r_[np.full(st.gs.N, st.k_mean_sp), np.full(st.gs.N, st.k_mean_rp)] * tf.kscale[b]
        F += st.G.T @ (km * tf.e_const[b])
        q0[b] = np.linalg.solve(K, F)
    return q0


def choose_step(st: Stage, fs_list, min_steps_per_period=10.0):
    """h = 1/(10 kHz * D) with >= min_steps_per_period steps per period of the highest mode at k_max."""
    fmax = st.freqs_kmax()[-1]
    base = 10000.0
    D = int(math.ceil(min_steps_per_period * fmax / base))
    D = max(D, 1)
    return 1.0 / (base * D), D, fmax


def simulate_batch(st: Stage, cases, warmup_s=0.35, progress=None, h=None, chunk=2000, record=True):
    """Simulate every case together. Returns (list of result dicts, info)."""
    t_wall0 = _time.time()
    warmup_s = 0.35 if warmup_s is None else warmup_s
    B, n, N = len(cases), st.n, st.gs.N
    M2 = 2 * N
    tf = TimeFunctions(st, cases)
    if h is None:
        h, D10, fmax = choose_step(st, [c.fs_daq for c in cases])
    else:
        fmax = st.freqs_kmax()[-1]
        D10 = int(round(1.0 / (h * 10000.0)))
    T_rec = max(c.duration_s for c in cases)
    # padding for the decimation filters (P = 16 D at the lowest DAQ rate)
    Dmax = int(round(1.0 / (h * min(c.fs_daq for c in cases))))
    P = 16 * Dmax
    n_warm = int(round(warmup_s / h))
    n_rec = int(round(T_rec / h))
    n_total = n_warm + n_rec + P + 2
    store_from = n_warm - P
    q = static_state(st, tf)
    v = np.zeros((B, n))
    GT = st.G.T.copy()
    GH = np.vstack([st.G, st.H0, st.H1])            # (3M, n)
    KC = np.vstack([st.K_lin, st.C_lin])             # (2n, n)
    Minv = 1.0 / st.M
    im, il = st.ix["phim"], st.ix["phil"]
    c_mesh, bl, mu = tf.c_mesh, tf.backlash, tf.mu[:, None]
    T_L = tf.T_L
    ixr, iyr = st.ix["xr"], st.ix["yr"]
    n_store = n_total - store_from if record else 0
    store = np.zeros((n_store, B, 5), dtype=np.float64) if record else None
    lp_a = 1 - math.exp(-2 * math.pi * st.rig.tacho_bw_Hz * h)
    w_lp = np.zeros((B, 2))
    w_lp[:] = np.c_[tf.ws, tf.wc]
    # accumulators over the recorded window
    acc = dict(P_in=np.zeros(B), P_out=np.zeros(B), P_fric=np.zeros(B), P_damp=np.zeros(B),
               sep=np.zeros(B), coast=np.zeros(B), cnt=0, sun=np.zeros(B), car=np.zeros(B))
    sens_extra = {}

    def rhs(q, v, k, S0, S1, e, Tm0, diag=False):
        qv = np.concatenate([q, v], axis=0)              # (2B, n)
        dd = qv @ GT                                      # (2B, M)
        dl = dd[:B] - e
        dld = dd[B:]
        drive = dl > 0
        coast = dl < -bl
        fel = np.where(drive, dl, np.where(coast, dl + bl, 0.0))
        inc = drive | coast
        F = k * fel + c_mesh * dld * inc
        Fn = np.maximum(F, 0.0)
        muF = mu * Fn
        FF = np.concatenate([F, muF * S0, muF * S1], axis=1)   # (B, 3M)
        Q = -(FF @ GH) - np.concatenate([q, v], axis=1) @ KC
        Tm = Tm0 - st.Kp * v[:, im] - st.Ki * q[:, im]
        Q[:, im] += Tm0
        Q[:, il] -= T_L
        a = Q * Minv
        if diag:
            return a, dict(F=F, muF=muF, drive=drive, coast=coast, inc=inc, dld=dld, Tm=Tm)
        return a

    # rhs: note the PI terms -Kp dphi -Ki phi are inside K_lin/C_lin; Q[:, im] += Tm0 adds the command
    step = 0
    nchunks = int(math.ceil(n_total / chunk))
    for ci in range(nchunks):
        j0 = ci * chunk
        j1 = min(n_total, j0 + chunk)
        m = j1 - j0
        tt = (j0 + np.arange(2 * m + 1) * 0.5) * h
        K_, S0_, S1_, E_, T_ = tf.eval(tt)
        for j in range(m):
            i2 = 2 * j
            k1v, d = rhs(q, v, K_[i2], S0_[i2], S1_[i2], E_[i2], T_[i2], diag=True)
            # sensors at t = (j0+j) h
            gstep = j0 + j
            a = k1v
            t_now = gstep * h
            w_s = tf.ws + v[:, st.ix["us"]] / st.rsb
            w_c = tf.wc + v[:, st.ix["uc"]] / st.rc
            w_lp[:, 0] += lp_a * (w_s - w_lp[:, 0])
            w_lp[:, 1] += lp_a * (w_c - w_lp[:, 1])
            if record and gstep >= store_from:
                r = gstep - store_from
                store[r, :, 0] = w_lp[:, 0]
                store[r, :, 1] = w_lp[:, 1]
                ag = a @ GT
                store[r, :, 2] = ag[:, 0]
                store[r, :, 3] = ag[:, N]
                th_c = tf.wc * t_now + q[:, st.ix["uc"]] / st.rc
                # ring acceleration from the carrier frame to the fixed frame (Coriolis/centripetal neglected)
                store[r, :, 4] = a[:, ixr] * np.cos(th_c) - a[:, iyr] * np.sin(th_c)
                sens_extra.setdefault("ay", None)
                if r == 0:
                    store_ay = np.zeros((n_store, B))
                    sens_extra["ay"] = store_ay
                sens_extra["ay"][r] = a[:, ixr] * np.sin(th_c) + a[:, iyr] * np.cos(th_c)
            if n_warm <= gstep < n_warm + n_rec:
                acc["cnt"] += 1
                acc["P_in"] += d["Tm"] * (tf.ws + v[:, im])
                acc["P_out"] += T_L * (tf.wc + v[:, il])
                # friction power: mu F (S0 h0 + S1 h1) . (v_nom + v)
                vfull = v + (tf.ws - tf.wc)[:, None] * st.vnom_rel_per_ws[None, :]
                hv0 = vfull @ st.H0.T
                hv1 = vfull @ st.H1.T
                acc["P_fric"] += np.sum(d["muF"] * (S0_[i2] * hv0 + S1_[i2] * hv1), axis=1)
                acc["P_damp"] += np.sum(c_mesh * d["dld"] ** 2 * d["inc"], axis=1) + np.einsum(
                    "bi,ij,bj->b", v, st.C_lin, v) - st.Kp * v[:, im] ** 2
                acc["sep"] += np.any(~d["drive"], axis=1)
                acc["coast"] += np.any(d["coast"], axis=1)
                acc["sun"] += w_s
                acc["car"] += w_c
            # RK4
            k1q = v
            q2 = q + 0.5 * h * k1q
            v2 = v + 0.5 * h * k1v
            k2v = rhs(q2, v2, K_[i2 + 1], S0_[i2 + 1], S1_[i2 + 1], E_[i2 + 1], T_[i2 + 1])
            q3 = q + 0.5 * h * v2
            v3 = v + 0.5 * h * k2v
            k3v = rhs(q3, v3, K_[i2 + 1], S0_[i2 + 1], S1_[i2 + 1], E_[i2 + 1], T_[i2 + 1])
            q4 = q + h * v3
            v4 = v + h * k3v
            k4v = rhs(q4, v4, K_[i2 + 2], S0_[i2 + 2], S1_[i2 + 2], E_[i2 + 2], T_[i2 + 2])
            q = q + (h / 6.0) * (v + 2 * v2 + 2 * v3 + v4)
            v = v + (h / 6.0) * (k1v + 2 * k2v + 2 * k3v + k4v)
            step += 1
        if not np.all(np.isfinite(q)):
            raise FloatingPointError(f"indepsim4: the integration diverged at t = {j1 * h:.4f} s")
        if progress:
            progress(j1, n_total, _time.time() - t_wall0)
    cnt = max(acc["cnt"], 1)
    results = []
    for b, c in enumerate(cases):
        res = dict(mean_sun_rpm=float(acc["sun"][b] / cnt * 60 / (2 * math.pi)),
                   mean_carrier_rpm=float(acc["car"][b] / cnt * 60 / (2 * math.pi)),
                   mean_P_in_W=float(acc["P_in"][b] / cnt), mean_P_out_W=float(acc["P_out"][b] / cnt),
                   mean_P_friction_W=float(acc["P_fric"][b] / cnt), mean_P_damping_W=float(acc["P_damp"][b] / cnt),
                   backlash_fraction=float(acc["sep"][b] / cnt), coast_contact_fraction=float(acc["coast"][b] / cnt))
        if record:
            fs = c.fs_daq
            D = int(round(1.0 / (h * fs)))
            nout = int(round(c.duration_s * fs))
            Pd = 16 * D
            bfir = signal.firwin(2 * Pd + 1, 0.4 * fs, fs=1.0 / h, window="blackman")
            j0s = n_warm - store_from   # store index of the recording's t = 0 (= P)
            chans = {}
            # housing: ring acceleration in the fixed frame projected on the sensor's radial direction
            phi_abs = c.sensor_angle_rad + tf.wc[b] * n_warm * h   # planet 0 at the recording's t = 0
            ax = store[:, b, 4]
            ay = sens_extra["ay"][:, b]
            hous = (ax * math.cos(phi_abs) + ay * math.sin(phi_abs)) * c.faults.sensor_gain_factor
            for name, x in (("sun", store[:, b, 0]), ("car", store[:, b, 1]), ("sp", store[:, b, 2]),
                            ("pr", store[:, b, 3]), ("hous", hous)):
                seg = x[j0s - Pd: j0s + (nout - 1) * D + Pd + 1]
                y = signal.upfirdn(bfir, seg, 1, D)
                chans[name] = y[2 * Pd // D: 2 * Pd // D + nout]
            res.update(time=np.arange(nout) / fs, sun_rpm=chans["sun"] * 60 / (2 * math.pi),
                       carrier_rpm=chans["car"] * 60 / (2 * math.pi), a_sp0=chans["sp"], a_pr0=chans["pr"],
                       housing=chans["hous"],
                       sensor_angle_deg=float(math.degrees(c.sensor_angle_rad) % 360.0),
                       sensor_angle_abs_deg=float(math.degrees(phi_abs) % 360.0), warmup_s=n_warm * h)
        results.append(res)
    info = dict(h_s=h, internal_rate_Hz=1.0 / h, f_max_kmax_Hz=float(fmax),
                steps_per_highest_period=float(1.0 / (h * fmax)),
                steps_per_mesh_cycle_min=float(1.0 / (h * max(tf.fm))), warmup_s=n_warm * h, steps=n_total,
                wall_s=_time.time() - t_wall0, recordings=B)
    return results, info


def add_daq_noise(x, rng, frac, dc_fraction=0.0, floor=0.0):
    """White Gaussian noise at frac x the RMS of the signal's AC part and an absolute floor (added in quadrature),
    plus a DC offset of dc_fraction x that RMS. The floor is the sensor chain's own broadband noise: without it a
    channel whose signal cancels (the ring's translation of an in-phase stage with equal planets, ~1e-11 m/s^2)
    would carry noise of that size, which no accelerometer has."""
    ac = np.sqrt(np.mean((x - np.mean(x)) ** 2))
    return x + rng.normal(0.0, np.hypot(frac * ac, floor), size=x.shape) + dc_fraction * ac
