#!/usr/bin/env python3
"""What the softening scale route can reach on real recordings (issue 12).

Reads `mre bench-diagnose --real … --json FILE` outputs, whose candidate
tables print each recording's gain for `stress_softening`
(`gains index:run_order:level:gain,…`), and reports:

1. Per injected softening case, the oracle: with the true onset n0 and the
   recorded run order (the law's shape known, its depth Δ and the levels
   free), how far the law's gain predictions stand above the untouched
   gains' scatter, z = sqrt(SSE_level − SSE_law) / σ, σ the RMS of the
   `none` cases' gains about their levels in the same round (every `none`
   case carries the same untouched gains, in another random order).
   z < 3.09 (one-sided p 0.001 with everything but Δ known) is counted as
   not identifiable at the route's strictness.
2. On the untouched gains, the realised false-positive rate of the F test
   over random run orders: the share of 5000 random orders whose F passes
   the critical value of the Student-t (4 dof) null at p ≤ 0.005, and of a
   Gaussian null for comparison.

    python3 bench/softening_oracle.py soft_3.json soft_4.json …

The F statistic and the law (a level per current, Δ ∈ [0, 0.6] on a grid,
n0 on host-tools/src/diagnose/scale.rs's grid) follow scale.rs.
"""
import json
import re
import sys

import numpy as np

N0_GRID = np.array([1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0])
DEPTHS = np.linspace(0.0, 0.6, 241)


def law(n, n0):
    return 1.0 - np.exp(-(n - 1.0) / n0)


def sse_level(k, lev):
    return sum(((k[lev == c] - k[lev == c].mean()) ** 2).sum() for c in np.unique(lev))


def explained(k, lev, s):
    """Σ over levels of (Σk·s)²/Σs², for gain sets k (M×N) and scales s (D×N)."""
    out = 0.0
    for c in np.unique(lev):
        m = lev == c
        out = out + (k[:, m] @ s[:, m].T) ** 2 / (s[:, m] ** 2).sum(1)
    return out


def f_stat(k, seq, lev):
    """The F statistic of scale.rs for each row of k (M×N)."""
    best = np.full(k.shape[0], -np.inf)
    for n0 in N0_GRID:
        s = 1.0 - DEPTHS[:, None] * law(seq, n0)[None, :]
        best = np.maximum(best, explained(k, lev, s).max(1))
    sk2 = (k**2).sum(1)
    s0 = sk2 - sum(k[:, lev == c].sum(1) ** 2 / (lev == c).sum() for c in np.unique(lev))
    s1 = np.maximum(sk2 - best, 1e-300)
    df = k.shape[1] - len(np.unique(lev)) - 2
    return ((s0 - s1) / 2.0) / (s1 / df)


def oracle_z(k, seq, lev, n0, sigma):
    s = 1.0 - DEPTHS[:, None] * law(seq, n0)[None, :]
    gain = explained(k[None, :], lev, s).max() - sum(
        k[lev == c].sum() ** 2 / (lev == c).sum() for c in np.unique(lev)
    )
    return np.sqrt(max(gain, 0.0)) / sigma


def rows(path):
    for c in json.load(open(path))["cases"]:
        inj = c["injection"]
        for rnd, tested in enumerate(c["tested"]):
            for t in tested:
                if t.startswith("stress_softening") and "; gains " in t:
                    g = np.array(
                        [[float(v) for v in x.split(":")] for x in t.split("; gains ")[1].split(";")[0].split(",")]
                    )
                    yield c, inj, rnd, g


def main(paths):
    rng = np.random.default_rng(1)
    for path in paths:
        data = list(rows(path))
        sigma = {}
        untouched = {}
        for c, inj, rnd, g in data:
            if inj["effect"] == "none" and rnd not in sigma:
                lev = g[:, 2].astype(int)
                sigma[rnd] = np.sqrt(sse_level(g[:, 3], lev) / (len(g) - len(np.unique(lev))))
                untouched[rnd] = g
        print(f"{path}: untouched gains' scatter per round {({r: round(s, 4) for r, s in sigma.items()})}")
        best = {}
        for c, inj, rnd, g in data:
            if inj["effect"] != "stress_softening" or rnd not in sigma:
                continue
            lev = g[:, 2].astype(int)
            z = oracle_z(g[:, 3], g[:, 1], lev, inj["parameters"]["tests_n0"], sigma[rnd])
            key = c["case"]
            if key not in best or z > best[key][0]:
                best[key] = (z, inj["achieved_strength"], "stress_softening" in c["found"])
        for case, (z, strength, found) in sorted(best.items()):
            verdict = "identifiable" if z >= 3.09 else "not identifiable"
            print(f"  case {case:2d}: strength {100 * strength:4.1f} %, oracle z {z:4.1f} ({verdict}), found {found}")
        for rnd, g in sorted(untouched.items()):
            k, lev = g[:, 3], g[:, 2].astype(int)
            levels = np.unique(lev)
            mu = np.array([k[lev == c].mean() for c in levels])[np.searchsorted(levels, lev)]
            f_orders = np.array([f_stat(k[None, :], rng.permutation(len(k)) + 1.0, lev)[0] for _ in range(5000)])
            for name, draw in (
                ("t(4)", lambda n: rng.standard_t(4.0, n) * np.sqrt(0.5)),
                ("Gaussian", lambda n: rng.standard_normal(n)),
            ):
                crit = np.mean(
                    [
                        np.quantile(f_stat(mu + sigma[rnd] * draw((20000, len(k))), rng.permutation(len(k)) + 1.0, lev), 0.995)
                        for _ in range(4)
                    ]
                )
                print(
                    f"  untouched gains, round {rnd}: {name} null, critical F {crit:.2f} at p 0.005; "
                    f"random orders passing {100 * (f_orders >= crit).mean():.2f} %"
                )


if __name__ == "__main__":
    main(sys.argv[1:])
