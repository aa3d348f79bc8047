#!/usr/bin/env python3
"""Peers for `mre bench-compare`: niapy's GSA and SciPy's differential_evolution
on the same Bouc-Wen objective, at the same number of evaluations.

Usage: compare_gsa.py DIR   (DIR holds objective.csv and bench.json from
`mre bench-compare --out DIR`)

The objective is `mre compare`'s, re-implemented here line for line:
recordings decimated as exported; z stepped exactly along x,
dz/dx = (1 - z^2 (beta*sgn(dx z) + gamma))/x_y with beta = (1+r)/2,
gamma = (1-r)/2 (tan/tanh after a reversal, tanh after); the linear parameters
(c0, k0, alpha, f0) by weighted least squares on the columns [v, x, z, 1];
J = sqrt(sum of weighted squared residuals), weight 1/(max|F| sqrt(n R)).
Search: (log10 x_y, r) inside the exported box. niapy evaluates one candidate at a
time (its API); differential_evolution runs `vectorized=True`, its fastest
mode, integrating the whole population at once with numpy.
"""
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
from niapy.algorithms.basic import GravitationalSearchAlgorithm
from niapy.problems import Problem
from niapy.task import Task
from scipy.optimize import differential_evolution


def load(d: Path):
    raw = np.loadtxt(d / "objective.csv", delimiter=",", skiprows=1)
    tracks = []
    for k in np.unique(raw[:, 0]).astype(int):
        r = raw[raw[:, 0] == k]
        tracks.append({"x": r[:, 2], "v": r[:, 3], "f": r[:, 4], "scale": r[0, 5]})
    return tracks, json.loads((d / "bench.json").read_text())


def towards_zero(w, u, r):
    """From w < 0 along dw/du = 1 + r w^2 for at most u: (w reached, u used)."""
    if r > 1e-12:
        q = math.sqrt(r)
        a = math.atan(q * w)
        need = -a / q
        return (0.0, need) if u >= need else (math.tan(a + q * u) / q, u)
    if r < -1e-12:
        q = math.sqrt(-r)
        qw = max(q * w, -1.0)
        a = -math.inf if qw <= -1.0 else math.atanh(qw)
        need = -a / q
        return (0.0, need) if u >= need else (math.tanh(a + q * u) / q, u)
    return (0.0, -w) if u >= -w else (w + u, u)


def step(z, dx, x_y, r):
    """Exact Bouc-Wen (n = 2, beta + gamma = 1) step, as mre's bouc_wen::step."""
    if dx == 0.0:
        return z
    s = 1.0 if dx > 0 else -1.0
    w, u = s * z, abs(dx) / x_y
    if w < 0.0:
        end, used = towards_zero(w, u, r)
        if used >= u:
            return s * end
        w, u = 0.0, u - used
    return s * math.tanh((math.inf if w >= 1.0 else math.atanh(w)) + u)


def z_path(x, x_y, r):
    """Scalar loop: one candidate."""
    z, out, x_prev = 0.0, np.empty(len(x)), x[0]
    for i, xi in enumerate(x):
        z = step(z, xi - x_prev, x_y, r)
        x_prev = xi
        out[i] = z
    return out


def z_paths(x, x_y, r):
    """Vectorised over candidates: x_y, r are arrays (one per candidate)."""
    z = np.zeros(len(x_y))
    out = np.empty((len(x), len(x_y)))
    x_prev = x[0]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for i, xi in enumerate(x):
            dx = xi - x_prev
            x_prev = xi
            if dx != 0.0:
                s = 1.0 if dx > 0 else -1.0
                w, u = s * z, abs(dx) / x_y
                q = np.sqrt(np.abs(r))
                pos, neg = r > 1e-12, r < -1e-12
                a = np.where(pos, np.arctan(q * w), np.where(neg, np.arctanh(np.maximum(q * w, -1.0)), w))
                qs = np.where(pos | neg, q, 1.0)
                need = np.where(pos | neg, -a / qs, -w)
                moving = np.where(pos, np.tan(a + q * u) / qs,
                                  np.where(neg, np.tanh(a + q * u) / qs, w + u))
                back = w < 0.0
                done = back & (u < need)
                rest = np.where(back, u - need, u)
                w0 = np.where(back, 0.0, w)
                loaded = np.tanh(np.where(w0 >= 1.0, np.inf, np.arctanh(np.minimum(w0, 1.0))) + rest)
                z = s * np.where(done, moving, loaded)
            out[i] = z
    return out


def project(tracks, zs):
    rows, ys = [], []
    for t, z in zip(tracks, zs):
        w = 1.0 / (t["scale"] * math.sqrt(len(t["x"]) * len(tracks)))
        rows.append(w * np.column_stack([t["v"], t["x"], z, np.ones(len(z))]))
        ys.append(w * t["f"])
    a, y = np.vstack(rows), np.concatenate(ys)
    theta, *_ = np.linalg.lstsq(a, y, rcond=None)
    return float(np.sqrt(np.sum((a @ theta - y) ** 2)))


def objective(tracks, q):
    x_y, r = 10.0 ** q[0], q[1]
    if not (x_y > 0 and -1 <= r <= 3):
        return float("inf")
    return project(tracks, [z_path(t["x"], x_y, r) for t in tracks])


DE_EVALS = [0]


def objective_population(tracks, qs):
    """qs: shape (2, S) as differential_evolution passes it when vectorized."""
    DE_EVALS[0] += qs.shape[1]
    paths = [z_paths(t["x"], 10.0 ** qs[0], qs[1]) for t in tracks]
    return np.array([project(tracks, [p[:, j] for p in paths]) for j in range(qs.shape[1])])


class BoucWen(Problem):
    def __init__(self, tracks, lower, upper):
        super().__init__(2, np.array(lower), np.array(upper))
        self.tracks = tracks

    def _evaluate(self, q):
        return objective(self.tracks, q)


def main():
    d = Path(sys.argv[1])
    tracks, bench = load(d)
    n, t, seed = bench["agents"], bench["iters"], bench["seed"]
    # The peers get as many evaluations as mre's whole fit (GSA + LM, LM charged n + 1 per iteration).
    evals = max(bench["evaluations"], bench["refined_evaluations"])
    lower, upper = bench["lower"], bench["upper"]
    check = objective(tracks, bench["best_q"])
    print(f"objective: {bench['recordings']} recordings, {bench['samples']} samples; "
          f"Python J at mre's best point {check:.6f} vs mre {bench['best_objective']:.6f}")

    task = Task(BoucWen(tracks, lower, upper), max_evals=evals)
    start = time.perf_counter()
    niapy_q, niapy_best = GravitationalSearchAlgorithm(population_size=n, seed=seed).run(task)
    niapy_s = time.perf_counter() - start

    # popsize is a multiplier of the dimension (2); maxiter generations after the first.
    pop = n // 2
    gens = evals // (pop * 2) - 1
    start = time.perf_counter()
    de = differential_evolution(lambda qs: objective_population(tracks, qs), list(zip(lower, upper)),
                                popsize=pop, maxiter=gens, tol=0, polish=False, seed=seed,
                                vectorized=True, updating="deferred")
    de_s = time.perf_counter() - start

    rows = [("mre GSA + LM", bench["refined_median_s"], bench["refined_evaluations"], bench["refined_objective"],
             bench["refined_q"]),
            ("niapy GSA", niapy_s, task.evals, float(niapy_best), list(niapy_q)),
            ("scipy differential_evolution", de_s, DE_EVALS[0], float(de.fun), list(de.x))]
    print(f"(mre GSA alone: {bench['evaluations']} evaluations, {bench['median_s']:.3f} s, J {bench['best_objective']:.6f}; "
          f"{bench['threads']} threads)")
    print(f"{'optimiser':<30} {'time (s)':>10} {'evaluations':>12} {'final J':>12}  final (log10 x_y, r)")
    for name, s, e, j, q in rows:
        print(f"{name:<30} {s:>10.3f} {e:>12} {j:>12.8f}  ({q[0]:.4f}, {q[1]:.4f})")
    fastest = min(rows[1:], key=lambda r: r[1])
    print(f"mre (GSA + LM) is {fastest[1] / rows[0][1]:.0f}x faster than the fastest peer ({fastest[0]}); "
          f"final J {rows[0][3]:.6f} vs {fastest[3]:.6f}; best peer J {min(r[3] for r in rows[1:]):.6f}")


if __name__ == "__main__":
    main()
