#!/usr/bin/env python3
"""A plain numpy peer for docs/benchmark.md: fixed-step RK4 of the same kind of
torsional planetary model (sun, carrier, N planets; ring fixed), the way a
script would do it.

    /usr/bin/python3 bench/peer_rk4.py [--seconds 0.2] [--dt 1e-5] [--rpm 200]

Model (torsional, lumped, Lin & Parker 1999 with the planet pins rigid on the
carrier): q = (theta_s, theta_c, theta_p1..N); mesh deflections d = g . q
along the lines of action, g_sp = (r_bs, -r_c, r_bp), g_pr = (r_c, -r_bp);
mesh stiffness a rectangular wave between one and two pairs in contact at the
mesh frequency (contact ratio 1.6), phased by planet; viscous mesh damping
(2 % of critical); constant input and load torques; seed gear data (Zs 21,
Zp 30, Zr 81, m 3 mm, 1 kW). Not a reference solution: only its cost per
simulated second is compared (the physics is of the same size: 5 DOFs, 6
meshes, a stiffness lookup per mesh per evaluation).

Prints the wall time per simulated second.
"""
import argparse
import time

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=0.2, help="simulated time [s] (default 0.2)")
    ap.add_argument("--dt", type=float, default=1e-5, help="RK4 step [s] (default 1e-5)")
    ap.add_argument("--rpm", type=float, default=200.0, help="input speed [rpm]")
    a = ap.parse_args()

    zs, zp, zr, m, alpha, N = 21, 30, 81, 3e-3, np.radians(20), 3
    rbs, rbp, rbr = (z * m / 2 * np.cos(alpha) for z in (zs, zp, zr))
    rc = (zs + zp) * m / 2 * np.cos(alpha)  # carrier arm projected on the line of action
    Js, Jp, Jc = 2.9e-4, 1.4e-3, 2.4e-2  # [kg m^2], of the seed stage's size
    P, ws = 1000.0, a.rpm * 2 * np.pi / 60
    wc = ws * zs / (zs + zr)
    fm = zs * (ws - wc) / (2 * np.pi)
    Ts = P / ws
    TL = P / wc
    k1, eps = 9e8, 1.6  # single-pair stiffness [N/m], contact ratio
    # Mesh deflection vectors d = g . q
    n = 2 + N
    g_sp = np.zeros((N, n))
    g_pr = np.zeros((N, n))
    for i in range(N):
        g_sp[i, 0], g_sp[i, 1], g_sp[i, 2 + i] = rbs, -rc, rbp
        g_pr[i, 1], g_pr[i, 2 + i] = rc, -rbp
    G = np.vstack([g_sp, g_pr])
    Minv = 1 / np.array([Js, Jc] + [Jp] * N)
    meq = 1 / np.einsum("ij,j,ij->i", G, Minv, G)
    c = 2 * 0.02 * np.sqrt(k1 * 1.5 * meq)
    phase = np.concatenate([np.arange(N) * zs / N, np.arange(N) * zr / N + 0.3]) % 1.0
    f_ext = np.zeros(n)
    f_ext[0], f_ext[1] = Ts, -TL

    def stiffness(t):
        frac = (fm * t + phase) % 1.0
        return np.where(frac < eps - 1, 2 * k1, k1)

    def rhs(t, y):
        q, v = y[:n], y[n:]
        d = G @ q
        dv = G @ v
        F = stiffness(t) * np.maximum(d, 0.0) + c * dv
        acc = Minv * (f_ext - G.T @ F)
        return np.concatenate([v, acc])

    y = np.zeros(2 * n)
    steps = int(round(a.seconds / a.dt))
    h = a.dt
    t = 0.0
    t0 = time.perf_counter()
    for _ in range(steps):
        k1_ = rhs(t, y)
        k2_ = rhs(t + h / 2, y + h / 2 * k1_)
        k3_ = rhs(t + h / 2, y + h / 2 * k2_)
        k4_ = rhs(t + h, y + h * k3_)
        y = y + h / 6 * (k1_ + 2 * k2_ + 2 * k3_ + k4_)
        t += h
    wall = time.perf_counter() - t0
    print(f"numpy RK4 peer: {steps} steps of {a.dt:g} s = {a.seconds:g} s simulated in {wall:.2f} s wall: "
          f"{wall / a.seconds:.1f} s per simulated second, {wall / steps * 1e6:.1f} us per step")


if __name__ == "__main__":
    main()
