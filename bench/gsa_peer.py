#!/usr/bin/env python3
"""Peer benchmark: niapy's GravitationalSearchAlgorithm on the same objective.

Usage: gsa_peer.py DATASET_DIR MODEL_TOML RUST_GSA_SECONDS

For every (current, branch) of the data set's fit recordings (compression v > 0,
extension v <= 0, as `mre fit`), runs niapy's GSA with the same N (agents), the
same evaluation count N*T, inside the same search box `mre fit` used (read from
the model file's gsa_lower/gsa_upper), minimising the same performance index
(RMSE in N, summed sample by sample with numpy). Prints time and final
objective of both, and the ratios.
"""
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
from niapy.algorithms.basic import GravitationalSearchAlgorithm
from niapy.problems import Problem
from niapy.task import Task

SCALE = {"time_s": 1.0, "time_ms": 1e-3, "displacement_mm": 1.0, "displacement_m": 1e3,
         "velocity_m_s": 1.0, "velocity_mm_s": 1e-3, "force_n": 1.0, "force_kn": 1e3}


def branches(dataset_dir: Path):
    meta = tomllib.loads((dataset_dir / "dataset.toml").read_text())
    defaults = meta.get("defaults", {})
    by_current = {}
    for rec in meta["recording"]:
        if rec.get("role", defaults.get("role", "fit")) != "fit":
            continue
        cols = rec.get("columns", defaults.get("columns"))
        delim = rec.get("delimiter", defaults.get("delimiter", ","))
        path = dataset_dir / rec["file"]
        if cols is None:
            data = np.genfromtxt(path, delimiter=None if delim == "whitespace" else ",", names=True)
            get = lambda n: data[n]
            names = data.dtype.names
        else:
            data = np.loadtxt(path, delimiter=None if delim == "whitespace" else ",")
            get = lambda n: data[:, cols.index(n)]
            names = cols
        pick = lambda q: next(n for n in names if n.startswith(q))
        x = get(pick("displacement")) * SCALE[pick("displacement")]
        f = get(pick("force")) * SCALE[pick("force")]
        v = get(pick("velocity")) * SCALE[pick("velocity")]
        by_current.setdefault(rec["current_a"], []).append((x, v, f))
    for c in sorted(by_current):
        x = np.concatenate([r[0] for r in by_current[c]])
        v = np.concatenate([r[1] for r in by_current[c]])
        f = np.concatenate([r[2] for r in by_current[c]])
        yield c, "compression", x[v > 0], f[v > 0]
        yield c, "extension", x[v <= 0], f[v <= 0]


class Rmse(Problem):
    def __init__(self, x, f, lower, upper):
        super().__init__(5, lower, upper)
        self.x, self.f = x, f

    def _evaluate(self, a):
        return float(np.sqrt(np.mean((self.f - np.polyval(a, self.x)) ** 2)))


def main():
    dataset_dir, model_path, rust_s = Path(sys.argv[1]), Path(sys.argv[2]), float(sys.argv[3])
    model = tomllib.loads(model_path.read_text())
    n, t, seed = model["model"]["agents"], model["model"]["iters"], model["model"]["seed"]
    fits = {(c["current_a"], b): c["fit"][b] for c in model["current"] for b in ("compression", "extension")}
    total_peer_s, rows = 0.0, []
    for i, (c, b, x, f) in enumerate(branches(dataset_dir)):
        meta = fits[(c, b)]
        problem = Rmse(x, f, np.array(meta["gsa_lower"]), np.array(meta["gsa_upper"]))
        task = Task(problem, max_evals=n * t)
        algo = GravitationalSearchAlgorithm(population_size=n, seed=seed + i)
        start = time.perf_counter()
        _, best = algo.run(task)
        total_peer_s += time.perf_counter() - start
        rows.append((c, b, len(x), meta["lsq_rmse_n"], meta["gsa_rmse_n"], best, task.evals))
    print(f"N = {n}, T = {t}, evaluations per branch = {n * t}, branches = {len(rows)}")
    print("| current (A) | branch | samples | lsq RMSE (N) | mre GSA RMSE (N) | niapy GSA RMSE (N) | niapy / mre |")
    print("|---|---|---|---|---|---|---|")
    for c, b, s, lsq, ours, peer, evals in rows:
        print(f"| {c} | {b} | {s} | {lsq:.3f} | {ours:.3f} | {peer:.3f} | {peer / ours:.3f} |")
    ours_sum = sum(r[4] for r in rows)
    peer_sum = sum(r[5] for r in rows)
    lsq_sum = sum(r[3] for r in rows)
    print(f"summed RMSE: lsq {lsq_sum:.1f} N, mre GSA {ours_sum:.1f} N ({ours_sum / lsq_sum:.3f}x lsq), "
          f"niapy GSA {peer_sum:.1f} N ({peer_sum / lsq_sum:.3f}x lsq)")
    print(f"time: mre GSA (all branches, 2 threads) {rust_s * 1e3:.2f} ms, niapy GSA {total_peer_s:.2f} s; "
          f"speed ratio niapy/mre = {total_peer_s / rust_s:.0f}x")


if __name__ == "__main__":
    main()
