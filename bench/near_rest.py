"""The final model near rest on data/mr-damper-mts (BENCHMARKS.md, Diagnosis).

Near rest: samples slower than 2 % of their recording's peak speed (the
turn-arounds). Prints the mean |F| measured, by the final model and by the
baseline quartics there, and each model's RMS error, from the predictions
`mre diagnose data/mr-damper-mts --predictions PRED` wrote.

    python3 bench/near_rest.py PRED [DATA_DIR]
"""
import glob
import os
import sys

import numpy as np

pred_dir = sys.argv[1]
data_dir = sys.argv[2] if len(sys.argv) > 2 else "data/mr-damper-mts"
measured, final, baseline = [], [], []
for path in sorted(glob.glob(os.path.join(data_dir, "*.txt"))):
    name = os.path.basename(path)[:-4]
    v_mm_s = np.loadtxt(path)[:, 2]  # columns: time_s, displacement_mm, velocity_mm_s, force_n
    p = np.genfromtxt(os.path.join(pred_dir, f"{name}.predictions.csv"), delimiter=",", names=True)
    n = len(p)
    rest = np.abs(v_mm_s[:n]) < 0.02 * np.abs(v_mm_s).max()
    measured.append(p["force_measured_n"][rest])
    final.append(p["force_final_n"][rest])
    baseline.append(p["force_baseline_n"][rest])
m, f, b = (np.concatenate(a) for a in (measured, final, baseline))
rms = lambda e: float(np.sqrt(np.mean(e**2)))
print(f"near rest: {len(m)} samples; mean |F| measured {np.abs(m).mean():.0f} N, "
      f"final model {np.abs(f).mean():.0f} N (RMS error {rms(f - m):.0f} N), "
      f"baseline {np.abs(b).mean():.0f} N (RMS error {rms(b - m):.0f} N)")
