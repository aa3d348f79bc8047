#!/usr/bin/env python3
"""Which rate law could carry `viscous_damping` to 2x on data/mr-damper-mts (issue 38).

A numpy re-statement of the library `mre diagnose` fits on the real MTS set, on
top of which a rate column is judged by held-out gain, as `select.rs` does:
per current and branch (sign of v, the switch only outside the branch band)
a quartic in x; the turn-around memory (exp(-d/(L*delta)) * x_r^p, L = 0.4, 1,
2.5, p = 0, 1, delta = 1.247 mm as diagnose chooses, plus the start from rest
over 2.5 % of the stroke span); the yield force f(I)*tanh(v/v0), v0 = 13.1 mm/s
as diagnose chooses. The five folds are diagnose's stratified folds on this set
(each holds one test type at all three currents, in order of peak speed).
Gain = sqrt(SSE without / SSE with) over the held-out folds, samples with
|v| <= 2 sigma_v left out. Plain least squares (no sign bounds, no sparse
choice): its gain for c(I)*v is 1.234x where diagnose reports 1.25x.

    python3 bench/rate_term_mts.py            # about 3 min
    python3 bench/rate_term_mts.py --cycles   # the half-widths only, seconds

`--cycles` prints each test's mid-stroke loop half-width per cycle (cycles
between upward zero crossings of v; |x| < 20 % of the stroke; half the
difference of the mean force on the two branches): the first and last cycles
are the test's amplitude tapers.

Each candidate is a physical rate law, one set of coefficients per current
unless said: Bingham's c(I)*v, per branch (valve asymmetry), v*|v| (orifice),
Herschel-Bulkley |v|^n*sgn(v), a saturating v0*tanh(v/v0), a Maxwell branch
(v through a first-order lag tau = c/k), damping acting only after the
pre-yield length, a pre-yield relaxation in time since the reversal, and a free
odd function of speed (hat functions every 10 mm/s): the most any memoryless
rate law per current can do.
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "data", "mr-damper-mts")
TESTS = ["25mm0x1Hz", "25mm0x25Hz", "2mm5Hz", "10mm1Hz", "5mm3Hz"]  # fold order
CURRENTS = ["0A", "0x5A", "1A"]
NC = len(CURRENTS)
DELTA_MM, YIELD_V0_M_S = 1.247, 0.013136
BAND_M_S = 2 * 0.02e-3  # 2 sigma of the velocity noise diagnose reports


def features(r):
    """Branch, travel since the anchor, anchor position and time, as design.rs."""
    t, x, v = r["t"], r["x"], r["v"]
    n = len(x)
    peak = np.abs(v).max()
    anchor = (x[0], True, t[0]) if abs(v[0]) <= 0.1 * peak else None
    direction, last = None, 0
    d, xr, rest, tsr = np.full(n, np.nan), np.zeros(n), np.zeros(n, bool), np.full(n, np.nan)
    comp = np.zeros(n, bool)
    for k in range(n):
        if k > 0 and (v[k] > 0) != (v[k - 1] > 0):
            last = k
        outside = abs(v[k]) > BAND_M_S
        if direction is None and outside:
            direction = v[k] > 0
        elif direction is not None and outside and direction != (v[k] > 0):
            direction = not direction
            kk = max(last, 1)
            v0, v1, dt = v[kk - 1], v[kk], t[kk] - t[kk - 1]
            phi = np.clip(v0 / (v0 - v1), 0, 1) if v0 != v1 else 1.0
            anchor = (x[kk - 1] + 1e3 * 0.5 * v0 * phi * dt, False, t[kk - 1] + phi * dt)
        comp[k] = direction if direction is not None else v[k] > 0
        if anchor is not None:
            d[k], xr[k], rest[k], tsr[k] = abs(x[k] - anchor[0]), anchor[0], anchor[1], t[k] - anchor[2]
    r.update(d=np.nan_to_num(d, nan=1e9), xr=xr, rest=rest, comp=comp, tsr=np.nan_to_num(tsr, nan=1e9),
             scored=np.abs(v) > BAND_M_S)


def load():
    recs = []
    for ci, c in enumerate(CURRENTS):
        for fi, name in enumerate(TESTS):
            t, x, v_mm_s, f = np.loadtxt(os.path.join(DATA, name + c + ".txt")).T
            recs.append(dict(t=t, x=x, v=v_mm_s / 1e3, F=f, ci=ci, fold=fi, name=name + c))
    for r in recs:
        features(r)
    span = max(r["x"].max() for r in recs) - min(r["x"].min() for r in recs)
    return recs, 0.025 * span


def baseline(r, start_mm):
    x, v, comp, ci, n = r["x"], r["v"], r["comp"], r["ci"], len(r["x"])
    q = np.zeros((n, NC * 10))
    for p in range(5):
        q[:, ci * 10 + p] = np.where(comp, (x / 25) ** p, 0)
        q[:, ci * 10 + 5 + p] = np.where(~comp, (x / 25) ** p, 0)
    m = np.zeros((n, NC * 14))
    for b, br in enumerate([comp, ~comp]):
        j = 0
        for length in [0.4, 1.0, 2.5]:
            e = np.exp(-r["d"] / (length * DELTA_MM)) * (~r["rest"])
            for p in range(2):
                m[:, ci * 14 + b * 7 + j] = np.where(br, e * (r["xr"] / 25) ** p, 0)
                j += 1
        m[:, ci * 14 + b * 7 + 6] = np.where(br, np.exp(-r["d"] / start_mm) * r["rest"], 0)
    y = np.zeros((n, NC))
    y[:, ci] = np.tanh(v / YIELD_V0_M_S)
    return np.hstack([q, m, y])


def held_out(recs, base, extra=None):
    des = [(np.hstack([a, extra(r)[r["scored"]]]) if extra else a, y) for (a, y), r in zip(base, recs)]
    sse = np.zeros(5)
    for f in range(5):
        a = np.vstack([des[i][0] for i, r in enumerate(recs) if r["fold"] != f])
        y = np.concatenate([des[i][1] for i, r in enumerate(recs) if r["fold"] != f])
        used = np.abs(a).sum(0) > 0
        beta = np.zeros(a.shape[1])
        beta[used] = np.linalg.lstsq(a[:, used], y, rcond=None)[0]
        sse[f] = sum(((des[i][0] @ beta - des[i][1]) ** 2).sum() for i, r in enumerate(recs) if r["fold"] == f)
    return sse


def per_current(fn):
    def cols(r):
        z = np.zeros((len(r["x"]), NC))
        z[:, r["ci"]] = fn(r)
        return z
    return cols


def per_branch(fn):
    def cols(r):
        z, f = np.zeros((len(r["x"]), 2 * NC)), fn(r)
        z[:, 2 * r["ci"]] = np.where(r["comp"], f, 0)
        z[:, 2 * r["ci"] + 1] = np.where(~r["comp"], f, 0)
        return z
    return cols


def lag(r, tau_s):
    """v through dF/dt = (v - F)/tau, exact for v linear over each step."""
    t, v = r["t"], r["v"]
    out, s = np.zeros_like(v), 0.0
    for k in range(1, len(v)):
        dt = t[k] - t[k - 1]
        a = np.exp(-dt / tau_s)
        s = a * s + (1 - a) * v[k - 1] + (v[k] - v[k - 1]) * (1 - (tau_s / dt) * (1 - a))
        out[k] = s
    return out


def odd_speed_hats(r):
    knots = np.arange(0.01, 0.1, 0.01)
    a, s = np.abs(r["v"]), np.sign(r["v"])
    z = np.zeros((len(a), NC * len(knots)))
    for j, k in enumerate(knots):
        h = np.clip(1 - np.abs(a - k) / 0.01, 0, 1)
        if j == len(knots) - 1:
            h = np.where(a >= k, 1 + (a - k) / 0.01, h)
        z[:, r["ci"] * len(knots) + j] = s * h
    return z


def time_memory(r):
    z = np.zeros((len(r["x"]), NC * 12))
    for b, br in enumerate([r["comp"], ~r["comp"]]):
        for j, tau in enumerate([0.005, 0.015, 0.04]):
            e = np.exp(-r["tsr"] / tau) * (~r["rest"])
            for p in range(2):
                z[:, ((r["ci"] * 2 + b) * 3 + j) * 2 + p] = np.where(br, e * (r["xr"] / 25) ** p, 0)
    return z


def cycles():
    for c in CURRENTS:
        for name in TESTS:
            t, x, v, f = np.loadtxt(os.path.join(DATA, name + c + ".txt")).T
            stroke = np.abs(x).max()
            up = np.where((np.sign(v[:-1]) <= 0) & (np.sign(v[1:]) > 0))[0]
            half = []
            for a, b in zip(up[:-1], up[1:]):
                mid = np.abs(x[a:b]) < 0.2 * stroke
                vv, ff = v[a:b][mid], f[a:b][mid]
                if (vv > 0).sum() > 2 and (vv < 0).sum() > 2:
                    half.append(0.5 * (ff[vv > 0].mean() - ff[vv < 0].mean()))
            print(f"{name + c:16s} peak {np.abs(v).max():5.1f} mm/s  half-width per cycle (N): "
                  + " ".join(f"{h:.0f}" for h in half))


def main():
    if "--cycles" in sys.argv:
        return cycles()
    recs, start_mm = load()
    base = [(baseline(r, start_mm)[r["scored"]], r["F"][r["scored"]]) for r in recs]
    without = held_out(recs, base)
    n = sum(r["scored"].sum() for r in recs)
    print(f"memory + yield, held out: RMS {np.sqrt(without.sum() / n):.1f} N; fold shares of its SSE "
          + ", ".join(f"{TESTS[f]} {s:.2f}" for f, s in enumerate(without / without.sum())))
    lin = per_current(lambda r: r["v"])
    for r in recs:
        r["lag5"], r["lag20"] = lag(r, 0.005), lag(r, 0.02)
    candidates = [
        ("c(I)*v (Bingham; diagnose's linear variant)", lin),
        ("c(I, branch)*v (valve asymmetry)", per_branch(lambda r: r["v"])),
        ("c(I)*v|v| (orifice)", per_current(lambda r: r["v"] * np.abs(r["v"]))),
        ("c(I)*|v|^0.5 sgn v (Herschel-Bulkley)", per_current(lambda r: np.sign(r["v"]) * np.abs(r["v"]) ** 0.5)),
        ("c(I)*|v|^0.3 sgn v (Herschel-Bulkley)", per_current(lambda r: np.sign(r["v"]) * np.abs(r["v"]) ** 0.3)),
        ("c(I)*v0 tanh(v/v0), v0 = 37.6 mm/s", per_current(lambda r: 0.0376 * np.tanh(r["v"] / 0.0376))),
        ("c(I)*v0 tanh(v/v0), v0 = 94 mm/s", per_current(lambda r: 0.094 * np.tanh(r["v"] / 0.094))),
        ("Maxwell branch, tau = 5 ms", per_current(lambda r: r["lag5"])),
        ("Maxwell branch, tau = 20 ms", per_current(lambda r: r["lag20"])),
        ("c(I)*v after the pre-yield length (1 - e^-d/delta)",
         per_current(lambda r: r["v"] * (1 - np.exp(-r["d"] / DELTA_MM)))),
        ("c(I)*v + c2(I)*v*x (position-dependent)",
         lambda r: np.hstack([lin(r), per_current(lambda q: q["v"] * q["x"] / 25)(r)])),
        ("pre-yield relaxation in time since reversal (5, 15, 40 ms)", time_memory),
        ("free odd function of speed per current", odd_speed_hats),
    ]
    print("\n| rate column | held-out gain | per fold (" + ", ".join(TESTS) + ") | without the 0.1 Hz fold |")
    print("|---|---|---|---|")
    for name, cols in candidates:
        with_ = held_out(recs, base, cols)
        folds = ", ".join(f"{g:.2f}" for g in np.sqrt(without / with_))
        print(f"| {name} | {np.sqrt(without.sum() / with_.sum()):.3f} | {folds} | "
              f"{np.sqrt(without[1:].sum() / with_[1:].sum()):.3f} |", flush=True)


if __name__ == "__main__":
    main()
