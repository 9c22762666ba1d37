#!/usr/bin/env python3
"""First-order and total Sobol' indices from Saltelli sample matrices, with
bootstrap confidence intervals.

Estimators (Saltelli et al. 2010, Comput. Phys. Commun. 181:259, Table 2,
(b) and (f); (f) is Jansen 1999), for N rows j and d factors i::

    V    = Var([f(A); f(B)])                        (both matrices, 2N values)
    S_i  = mean_j( f(B)_j (f(AB_i)_j - f(A)_j) ) / V
    ST_i = mean_j( (f(A)_j - f(AB_i)_j)^2 ) / (2 V)

AB_i is A with column i taken from B. The outputs are first centred (the
mean of [f(A); f(B)] subtracted, as SALib does): this leaves the estimators'
expectations unchanged and makes S_i far less noisy for outputs whose mean
is large compared with their spread. Confidence intervals: the rows j are
resampled with replacement (the same rows for A, B and every AB_i, so the
correlation between the matrices is kept), the indices recomputed, and the
percentile interval of `n_bootstrap` resamples reported; `seed` makes it
reproducible. The bootstrap assumes independent rows; for a (scrambled)
Sobol' sequence the true error is usually smaller, so the interval is
conservative.

As a module: ``sobol_indices(fA, fB, fAB, n_bootstrap=1000, seed=0)`` ->
DataFrame. As a script, on a campaign archive of a saltelli design::

    /usr/bin/python3 scripts/sobol_indices.py results.h5 -y sun_planet/0/acceleration_rms -y max_wear/sun
"""

import os
import sys

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

if __name__ == "__main__":
    try:
        import h5py  # noqa: F401
        import numpy  # noqa: F401
        import pandas  # noqa: F401
    except ImportError:
        if os.path.exists("/usr/bin/python3") and not os.environ.get("PWPLOT_REEXEC") \
                and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
            os.environ["PWPLOT_REEXEC"] = "1"
            os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
        raise

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402


def _indices(fA, fB, fAB):
    """Point estimates for stacked resamples: fA, fB [..., N], fAB [..., N, d]."""
    var = np.var(np.concatenate([fA, fB], axis=-1), axis=-1)[..., None]
    s1 = np.mean(fB[..., None] * (fAB - fA[..., None]), axis=-2) / var
    st = 0.5 * np.mean((fA[..., None] - fAB) ** 2, axis=-2) / var
    return s1, st


def sobol_indices(fA, fB, fAB, n_bootstrap=1000, confidence=0.95, seed=0, center=True):
    """S1 and ST of each factor with bootstrap standard errors and percentile
    confidence intervals.

    fA, fB: [N] model outputs of the rows of A and B; fAB: [N, d], column i =
    outputs of AB_i. Rows with a NaN anywhere are dropped (a failed case
    invalidates its row). center: subtract the mean of [fA; fB] from every
    output first (as SALib does): the indices' expectations are unchanged
    (E[f(AB_i) - f(A)] = 0) but the S1 estimator's variance drops by a
    large factor when |mean| >> standard deviation. Returns a DataFrame indexed 0..d-1 with columns S1,
    S1_lo, S1_hi, S1_se, ST, ST_lo, ST_hi, ST_se; attrs: N (rows used),
    variance, confidence, n_bootstrap, seed."""
    fA = np.asarray(fA, dtype=float)
    fB = np.asarray(fB, dtype=float)
    fAB = np.asarray(fAB, dtype=float)
    if fAB.ndim == 1:
        fAB = fAB[:, None]
    if fA.ndim != 1 or fB.shape != fA.shape or fAB.shape[0] != fA.shape[0]:
        raise ValueError(f"shapes: fA {fA.shape}, fB {fB.shape}, fAB {fAB.shape}; expected [N], [N], [N, d]")
    ok = np.isfinite(fA) & np.isfinite(fB) & np.all(np.isfinite(fAB), axis=1)
    fA, fB, fAB = fA[ok], fB[ok], fAB[ok]
    n, d = fAB.shape
    if n < 2:
        raise ValueError(f"need at least 2 complete rows, have {n}")
    if center:
        m = np.mean(np.concatenate([fA, fB]))
        fA, fB, fAB = fA - m, fB - m, fAB - m
    s1, st = _indices(fA, fB, fAB)
    var = float(np.var(np.concatenate([fA, fB])))
    out = pd.DataFrame({"S1": s1, "ST": st})
    if n_bootstrap > 0 and var > 0:
        rng = np.random.default_rng(seed)
        bs1, bst = [], []
        chunk = max(1, min(n_bootstrap, int(2e7 // max(1, n * (d + 2)))))
        done = 0
        while done < n_bootstrap:
            m = min(chunk, n_bootstrap - done)
            idx = rng.integers(0, n, size=(m, n))
            a, b = _indices(fA[idx], fB[idx], fAB[idx])
            bs1.append(a)
            bst.append(b)
            done += m
        bs1, bst = np.concatenate(bs1), np.concatenate(bst)
        lo, hi = 50 * (1 - confidence), 50 * (1 + confidence)
        out["S1_lo"], out["S1_hi"] = np.nanpercentile(bs1, lo, axis=0), np.nanpercentile(bs1, hi, axis=0)
        out["S1_se"] = np.nanstd(bs1, axis=0, ddof=1)
        out["ST_lo"], out["ST_hi"] = np.nanpercentile(bst, lo, axis=0), np.nanpercentile(bst, hi, axis=0)
        out["ST_se"] = np.nanstd(bst, axis=0, ddof=1)
    else:
        for c in ("S1_lo", "S1_hi", "S1_se", "ST_lo", "ST_hi", "ST_se"):
            out[c] = np.nan
    out = out[["S1", "S1_lo", "S1_hi", "S1_se", "ST", "ST_lo", "ST_hi", "ST_se"]]
    out.attrs.update(N=n, variance=var, confidence=confidence, n_bootstrap=n_bootstrap, seed=seed, center=center)
    return out


def ishigami(x, a=7.0, b=0.1):
    """Ishigami function of x [n, 3] on [-pi, pi]^3 (a test function with known
    indices, see ishigami_indices)."""
    x = np.asarray(x, dtype=float)
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices(a=7.0, b=0.1):
    """Analytic (S1, ST) of the Ishigami function (Sobol' & Levitan 1999):
    V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V13 = b^2 pi^8 (1/18 - 1/50),
    V = V1 + V2 + V13."""
    pi4 = np.pi ** 4
    v1 = 0.5 * (1 + b * pi4 / 5) ** 2
    v2 = a ** 2 / 8
    v13 = b ** 2 * np.pi ** 8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    return np.array([v1, v2, 0.0]) / v, np.array([v1 + v13, v2, v13]) / v


def main(argv=None):
    import argparse
    import pwcampaign
    p = argparse.ArgumentParser(
        description="First-order (S1) and total (ST) Sobol' indices of scalar outputs of a saltelli campaign "
                    "(Saltelli 2010 / Jansen estimators) with bootstrap confidence intervals.")
    p.add_argument("archive", help="campaign archive of a design with type = \"saltelli\"")
    p.add_argument("-y", "--output", action="append", metavar="SCALAR",
                   help="scalar result (column of the design table), e.g. sun_planet/0/acceleration_rms, "
                        "max_wear/sun; repeatable (default: those two, where present)")
    p.add_argument("--bootstrap", type=int, default=1000, help="bootstrap resamples (default 1000; 0 = none)")
    p.add_argument("--confidence", type=float, default=0.95, help="confidence level of the intervals")
    p.add_argument("--seed", type=int, default=0, help="seed of the bootstrap resampling")
    p.add_argument("--csv", metavar="FILE", help="also write the table as CSV")
    a = p.parse_args(argv)
    try:
        c = pwcampaign.load(a.archive)
        outputs = a.output or [o for o in ("sun_planet/0/acceleration_rms", "max_wear/sun") if o in c.design]
        tables = []
        for o in outputs:
            r = c.sobol(o, n_bootstrap=a.bootstrap, confidence=a.confidence, seed=a.seed)
            print(f"{o} [{c.units.get(o, '')}]: {r.attrs['rows_used']} of {r.attrs['rows']} rows complete, "
                  f"variance {r.attrs.get('variance', float('nan')):.6g}, {100 * a.confidence:g} % intervals "
                  f"from {a.bootstrap} bootstrap resamples")
            with pd.option_context("display.float_format", "{:.4f}".format, "display.width", 160):
                print(r.to_string())
            r.insert(0, "output", o)
            tables.append(r.reset_index())
        if a.csv and tables:
            pd.concat(tables).to_csv(a.csv, index=False)
            print(f"wrote {a.csv}")
    except (pwcampaign.CampaignError, ValueError) as exc:
        sys.exit(f"error: {exc}")


if __name__ == "__main__":
    main()
