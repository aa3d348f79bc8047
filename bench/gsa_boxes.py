#!/usr/bin/env python3
"""GSA on two search boxes, and the speed-up split in two (bench/fitting.sh runs it).

Usage: gsa_boxes.py DATASET DATA_BOX_MODEL PAPER_BOX_MODEL MRE_DATA_S MRE_PAPER_S [PER_SAMPLE_BRANCHES]

The two model files are `mre fit --method both` with `--bounds data` and
`--bounds paper` (the paper's Table 3). For each box and each (current,
branch) of the fit recordings: the least-squares optimum inside the box
(bounded least squares, scipy's BVLS: the honest reference, since the
unconstrained optimum may lie outside), mre's GSA result (from the model
file), and niapy's GSA with the same N, N*T evaluations and box on the
moment-form objective (the same 5x5 quadratic form mre evaluates). Speed:
mre's GSA against niapy's on the same moment-form objective (what the search
costs), and niapy's per-sample numpy objective against its moment form on
the first PER_SAMPLE_BRANCHES branches (default 2; what the objective buys).
BRANCHES=K in the environment keeps only the first K branches.
"""
import os
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
from niapy.algorithms.basic import GravitationalSearchAlgorithm
from niapy.problems import Problem
from niapy.task import Task
from scipy.optimize import lsq_linear

sys.path.insert(0, str(Path(__file__).parent))
from gsa_peer import Rmse, branches  # noqa: E402  (per-sample objective, branch split as mre's)


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
    """Least squares restricted to the box (columns scaled for conditioning)."""
    phi = np.vander(x, 5)
    scale = np.linalg.norm(phi, axis=0)
    res = lsq_linear(phi / scale, f, bounds=(lower * scale, upper * scale), method="bvls")
    c = res.x / scale
    return c, float(np.sqrt(np.mean((f - phi @ c) ** 2)))


def niapy_gsa(problem, n, t, seed):
    task = Task(problem, max_evals=n * t)
    start = time.perf_counter()
    _, best = GravitationalSearchAlgorithm(population_size=n, seed=seed).run(task)
    return best, time.perf_counter() - start


def main():
    dataset = Path(sys.argv[1])
    models = {"data": Path(sys.argv[2]), "paper (Table 3)": Path(sys.argv[3])}
    mre_s = {"data": float(sys.argv[4]), "paper (Table 3)": float(sys.argv[5])}
    per_sample_branches = int(sys.argv[6]) if len(sys.argv) > 6 else 2
    data = list(branches(dataset))[: int(os.environ.get("BRANCHES", "1000"))]
    print(f"data set {dataset}: {len(data)} branches, {sum(len(d[2]) for d in data)} samples")
    print("| box | branches with the lsq optimum inside | lsq optimum (N, summed) | box optimum (N) "
          "| mre GSA (N) | mre / box optimum | niapy GSA (N) | niapy / box optimum | mre GSA time (s) "
          "| niapy GSA time, moment form (s) | niapy / mre time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    speed = None
    for box, path in models.items():
        model = tomllib.loads(path.read_text())
        n, t, seed = model["model"]["agents"], model["model"]["iters"], model["model"]["seed"]
        fits = {(c["current_a"], b): c["fit"][b] for c in model["current"] for b in ("compression", "extension")}
        table = {(c["current_a"], b): c[b] for c in model["current"] for b in ("compression", "extension")}
        assert model["model"]["table_coefficients"] == "lsq", f"{path}: fit with --method both"
        inside = lsq = opt = ours = peer = peer_s = 0.0
        for i, (c, b, x, f) in enumerate(data):
            meta = fits[(c, b)]
            lo, hi = np.array(meta["gsa_lower"]), np.array(meta["gsa_upper"])
            _, box_rmse = box_optimum(x, f, lo, hi)
            best, secs = niapy_gsa(MomentRmse(x, f, lo, hi), n, t, seed + i)
            coeffs = np.array(table[(c, b)])
            inside += float(np.all((coeffs >= lo) & (coeffs <= hi)))
            lsq += meta["lsq_rmse_n"]
            opt += box_rmse
            ours += meta["gsa_rmse_n"]
            peer += best
            peer_s += secs
        print(f"| {box} | {inside:.0f} / {len(data)} | {lsq:.1f} | {opt:.1f} | {ours:.1f} | {ours / opt:.3f} "
              f"| {peer:.1f} | {peer / opt:.3f} | {mre_s[box]:.3f} | {peer_s:.1f} | {peer_s / mre_s[box]:.0f} |")
        if speed is None:
            speed = (box, fits, n, t, seed)
    # What the objective buys: niapy's GSA, same seeds, per-sample against moment form.
    box, fits, n, t, seed = speed
    per_sample_s = moment_s = 0.0
    for i, (c, b, x, f) in enumerate(data[:per_sample_branches]):
        lo, hi = np.array(fits[(c, b)]["gsa_lower"]), np.array(fits[(c, b)]["gsa_upper"])
        _, s1 = niapy_gsa(Rmse(x, f, lo, hi), n, t, seed + i)
        _, s2 = niapy_gsa(MomentRmse(x, f, lo, hi), n, t, seed + i)
        per_sample_s += s1
        moment_s += s2
    k = min(per_sample_branches, len(data))
    print(f"niapy GSA on {k} branches ({box} box): per-sample objective {per_sample_s:.1f} s, "
          f"moment form {moment_s:.1f} s: the objective buys {per_sample_s / moment_s:.1f}x")


if __name__ == "__main__":
    main()
