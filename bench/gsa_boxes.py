#!/usr/bin/env python3
"""GSA on two search boxes, every branch, against niapy and the optimum (bench/fitting.sh runs it).

Usage: gsa_boxes.py DATASET DATA_BOX_MODEL PAPER_BOX_MODEL MRE_DATA_S MRE_PAPER_S [WEIGHTS_CSV]

The two model files are `mre fit --method both` with `--bounds data` and
`--bounds paper` (the paper's Table 3); MRE_*_S are mre's GSA fit times for
all branches on one thread. For each box and each (current, branch) of the
fit recordings: the least-squares optimum inside the box (bounded least
squares, scipy's BVLS: the reference, since the unconstrained optimum may lie
outside), mre's GSA result (from the model file) and niapy's GSA with the
same N, N*T evaluations and box on the moment-form objective (the same 5x5
quadratic form mre evaluates); each one's gap = its RMSE / the box optimum.
Speed-up in two parts, data box: niapy per-sample numpy objective against
niapy moment form, back to back per branch (what the objective buys), niapy
moment form against mre on one thread (what the search costs). WEIGHTS_CSV (from
`cargo bench --bench gsa_weights`) adds mre's per-agent against per-dimension
random weights, several seeds, as gaps to the same box optima.

Environment: BRANCHES=K keeps the first K branches; PER_SAMPLE=0 skips the
speed-up runs, PER_SAMPLE_BRANCHES=K times them on the first K branches
(default all; never cached); NIAPY_CACHE=FILE stores each niapy result (value,
seconds, UTC time, load) and reuses those whose inputs match, so the tables
can be rebuilt without the ~1 min per niapy run (the cached times are from
when they were measured: printed).
"""
import csv
import hashlib
import json
import os
import statistics
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
from niapy.algorithms.basic import GravitationalSearchAlgorithm
from niapy.problems import Problem
from niapy.task import Task
from scipy.optimize import lsq_linear
from scipy.stats import binomtest

sys.path.insert(0, str(Path(__file__).parent))
from gsa_peer import Rmse, branches  # noqa: E402  (per-sample objective, branch split as mre's)

BOXES = ("data", "paper")


class MomentRmse(Problem):
    """RMSE from the branch's moments: sqrt(c'Ac - 2b'c + f2), O(25) per evaluation."""

    def __init__(self, x, f, lower, upper):
        super().__init__(5, lower, upper)
        phi = np.vander(x, 5)  # x^4 ... 1, the coefficient order of the model file
        self.a = phi.T @ phi / len(x)
        self.b = phi.T @ f / len(x)
        self.f2 = float(f @ f) / len(x)

    def _evaluate(self, c):
        return float(np.sqrt(max(c @ self.a @ c - 2.0 * self.b @ c + self.f2, 0.0)))


def box_optimum(x, f, lower, upper):
    """RMSE of least squares restricted to the box (columns scaled for conditioning)."""
    phi = np.vander(x, 5)
    scale = np.linalg.norm(phi, axis=0)
    res = lsq_linear(phi / scale, f, bounds=(lower * scale, upper * scale), method="bvls", tol=1e-12)
    c = np.clip(res.x / scale, lower, upper)
    return float(np.sqrt(np.mean((f - phi @ c) ** 2)))


class Niapy:
    """niapy's GSA, optionally cached on disk by a hash of its inputs."""

    def __init__(self, path):
        self.path = Path(path) if path else None
        self.cache = json.loads(self.path.read_text()) if self.path and self.path.exists() else {}

    def run(self, kind, x, f, lo, hi, n, t, seed):
        key = hashlib.sha256(repr((kind, x.tobytes(), f.tobytes(), lo.tolist(), hi.tolist(), n, t, seed))
                             .encode()).hexdigest()
        if key not in self.cache:
            problem = (MomentRmse if kind == "moment" else Rmse)(x, f, lo, hi)
            task = Task(problem, max_evals=n * t)
            start = time.perf_counter()
            _, best = GravitationalSearchAlgorithm(population_size=n, seed=seed).run(task)
            secs = time.perf_counter() - start
            self.cache[key] = {"value": float(best), "seconds": secs,
                               "utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                               "load": os.getloadavg()[0]}
            if self.path:
                self.path.write_text(json.dumps(self.cache, indent=0))
        return self.cache[key]


def spread(gaps):
    return f"{statistics.median(gaps):.2f} ({min(gaps):.2f}–{max(gaps):.2f})"


def main():
    dataset = Path(sys.argv[1])
    models = {"data": Path(sys.argv[2]), "paper": Path(sys.argv[3])}
    mre_data_s = float(sys.argv[4])  # sys.argv[5], the paper box's time, is printed by fitting.sh
    weights_csv = Path(sys.argv[6]) if len(sys.argv) > 6 else None
    niapy = Niapy(os.environ.get("NIAPY_CACHE"))
    data = list(branches(dataset))[: int(os.environ.get("BRANCHES", "1000"))]
    print(f"data set {dataset}: {len(data)} branches, {sum(len(d[2]) for d in data)} samples")
    optimum, summary, runs = {}, [], []
    for box in BOXES:
        model = tomllib.loads(models[box].read_text())
        assert model["model"]["table_coefficients"] == "lsq", f"{models[box]}: fit with --method both"
        assert model["model"]["bounds"] == box, f"{models[box]}: fit with --bounds {box}"
        n, t, seed = model["model"]["agents"], model["model"]["iters"], model["model"]["seed"]
        print(f"\n### {box} box: gap = RMSE / least-squares optimum inside the box "
              f"(N = {n}, T = {t}, {n * t} evaluations per branch)\n")
        print("| current (A) | branch | samples | lsq optimum inside | box optimum (N) | mre GSA gap "
              "| niapy GSA gap | niapy time (s) |")
        print("|---:|---|---:|---|---:|---:|---:|---:|")
        inside, opt_sum, ours_sum, peer_sum, ours_gaps, peer_gaps, wins = 0, 0.0, 0.0, 0.0, [], [], 0
        for i, (c, b, x, f) in enumerate(data):
            cur = next(e for e in model["current"] if e["current_a"] == c)
            meta = cur["fit"][b]
            lo, hi = np.array(meta["gsa_lower"]), np.array(meta["gsa_upper"])
            opt = box_optimum(x, f, lo, hi)
            optimum[(box, c, b)] = opt
            peer = niapy.run("moment", x, f, lo, hi, n, t, seed + i)
            runs.append(peer)
            coeffs = np.array(cur[b])  # the lsq coefficients (table_coefficients = lsq)
            is_inside = bool(np.all((coeffs >= lo) & (coeffs <= hi)))
            inside += is_inside
            ours, theirs = meta["gsa_rmse_n"] / opt, peer["value"] / opt
            ours_gaps.append(ours)
            peer_gaps.append(theirs)
            wins += ours < theirs
            opt_sum += opt
            ours_sum += meta["gsa_rmse_n"]
            peer_sum += peer["value"]
            print(f"| {c:g} | {b} | {len(x)} | {'yes' if is_inside else 'no'} | {opt:.2f} | {ours:.3g} "
                  f"| {theirs:.3g} | {peer['seconds']:.1f} |")
        summary.append((box, inside, opt_sum, ours_sum, peer_sum, ours_gaps, peer_gaps, wins))
    print("\n### Summary (gap: summed RMSE / summed box optimum; per branch: median (min–max))\n")
    print("| box | lsq optimum inside | box optimum (N, summed) | mre GSA gap | per branch | niapy GSA gap "
          "| per branch | mre below niapy |")
    print("|---|---|---:|---:|---|---:|---|---|")
    for box, inside, opt_sum, ours_sum, peer_sum, ours_gaps, peer_gaps, wins in summary:
        print(f"| {box} | {inside} / {len(data)} | {opt_sum:.1f} | {ours_sum / opt_sum:.3g} | {spread(ours_gaps)} "
              f"| {peer_sum / opt_sum:.3g} | {spread(peer_gaps)} | {wins} / {len(data)} |")
    if os.environ.get("PER_SAMPLE", "1") != "0":
        speed_split(data, models["data"], mre_data_s, int(os.environ.get("PER_SAMPLE_BRANCHES", len(data))))
    when = sorted({r["utc"] for r in runs})
    loads = [r["load"] for r in runs]
    print(f"niapy runs: {when[0]} to {when[-1]} UTC, load {min(loads):.1f}–{max(loads):.1f}")
    if weights_csv:
        weights_table(weights_csv, optimum)


def speed_split(data, model_path, mre_s, k):
    """The speed-up in two parts, timed now (never from the cache), data box.

    Per branch, niapy's GSA on the moment form and on the per-sample objective
    back to back (alternating which goes first), so that a changing load hits
    both alike; and the cost of one evaluation of each objective alone.
    """
    model = tomllib.loads(model_path.read_text())
    n, t, seed = model["model"]["agents"], model["model"]["iters"], model["model"]["seed"]
    runs = {"moment": 0.0, "per-sample": 0.0}
    eval_us = {"moment": 0.0, "per-sample": 0.0}
    same = 0
    rng = np.random.default_rng(0)
    for i, (c, b, x, f) in enumerate(data[:k]):
        meta = next(e for e in model["current"] if e["current_a"] == c)["fit"][b]
        lo, hi = np.array(meta["gsa_lower"]), np.array(meta["gsa_upper"])
        values = {}
        for kind in (("moment", "per-sample") if i % 2 == 0 else ("per-sample", "moment")):
            r = Niapy(None).run(kind, x, f, lo, hi, n, t, seed + i)
            runs[kind] += r["seconds"]
            values[kind] = r["value"]
            problem = (MomentRmse if kind == "moment" else Rmse)(x, f, lo, hi)
            points = lo + (hi - lo) * rng.random((2000, 5))
            start = time.perf_counter()
            for p in points:
                problem._evaluate(p)
            eval_us[kind] += (time.perf_counter() - start) / len(points) * 1e6 / k
        same += abs(values["moment"] - values["per-sample"]) <= 1e-6 * values["moment"]
    per_branch_mre = mre_s / len(data)
    print(f"\nspeed-up, timed {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC, load "
          f"{os.getloadavg()[0]:.1f}, data box, niapy on {k} branches (same final RMSE on {same} / {k}):")
    print(f"- one evaluation: per-sample numpy {eval_us['per-sample']:.1f} µs, moment form "
          f"{eval_us['moment']:.1f} µs ({eval_us['per-sample'] / eval_us['moment']:.1f}x)")
    print(f"- part 1, what the objective buys niapy: per-sample {runs['per-sample']:.1f} s, moment form "
          f"{runs['moment']:.1f} s: {runs['per-sample'] / runs['moment']:.2f}x")
    print(f"- part 2, what the search costs (moment form, per branch): niapy {runs['moment'] / k:.2f} s, "
          f"mre on one thread {per_branch_mre * 1e3:.2f} ms: {runs['moment'] / k / per_branch_mre:.0f}x; "
          f"niapy per-sample against mre: {runs['per-sample'] / k / per_branch_mre:.0f}x")


def weights_table(path, optimum):
    """mre's per-agent against per-dimension random weights, gaps to the same box optima."""
    rows = list(csv.DictReader(path.open()))
    print(f"\n### mre GSA random weights ({path.name}: {len({r['seed'] for r in rows})} seeds per branch)\n")
    print("| box | per-agent gap, summed: median over seeds (min–max) | per-dimension | "
          "per-dimension lower on (seed, branch) | sign test p (two-sided) "
          "| median per-branch ratio per-dimension / per-agent |")
    print("|---|---|---|---|---:|---:|")
    for box in BOXES:
        by = {}
        for r in rows:
            if r["box"] == box and (box, float(r["current_a"]), r["branch"]) in optimum:
                by.setdefault(r["weights"], {})[(r["seed"], float(r["current_a"]), r["branch"])] = float(r["rmse_n"])
        if len(by) != 2:
            continue
        opt = {k: v for k, v in optimum.items() if k[0] == box}
        opt_sum = sum(opt.values())
        seeds = sorted({k[0] for k in by["per-agent"]})
        summed = {w: [sum(v for k, v in by[w].items() if k[0] == s) / opt_sum for s in seeds] for w in by}
        pairs = [(by["per-agent"][k], by["per-dimension"][k]) for k in by["per-agent"] if k in by["per-dimension"]]
        lower = sum(d < a for a, d in pairs)
        untied = sum(d != a for a, d in pairs)
        p_value = binomtest(lower, untied).pvalue if untied else 1.0
        ratio = statistics.median(d / a for a, d in pairs)
        print(f"| {box} | {spread(summed['per-agent'])} | {spread(summed['per-dimension'])} "
              f"| {lower} / {len(pairs)} | {p_value:.2g} | {ratio:.3f} |")


if __name__ == "__main__":
    main()
