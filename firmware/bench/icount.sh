#!/usr/bin/env bash
# Executed-instruction counts of the model step and the control step, without
# a board: the `pil,bench` image runs in QEMU with one instruction per
# translation block and an exec trace; every traced block is then exactly one
# executed Thumb instruction. The firmware brackets each measured call with
# `mre_mark_begin()` / `mre_mark_end()` (firmware/src/board/pil.rs, mod
# icount); this script counts the instructions from the entry of
# mre_mark_begin to the entry of mre_mark_end and subtracts the markers' own 3
# (begin's `nop; bx lr`, the `bl mre_mark_end`). Argument moves into
# registers before the call are not counted. QEMU counts instructions, not
# cycles: FPU divides, flash wait states and pipeline stalls are not in it.
#
# The windows (firmware/src/board/pil.rs, mod icount) come per table, first
# the flown one (firmware/src/generated_table.rs), then the same entries with
# every format 2 term (coil τ, sensor delay, viscous, saturation: the worst
# path), then with coil lag and sensor delay only (what `mre pil` flies for
# controller (c)), then with what diagnosis finds on real data (a viscous
# term rising with current, saturation, coil τ, sensor delay): the model step on a grid (x 0–12 mm × 5 forces, from below the 0 A
# force to above the 2 A force) and on a grid near contact, where the fitted
# entries cross (x 0–0.87 mm in 0.0725 mm steps × 5 forces), then the
# control step over one whole drop
# (5.5 kg at 2.24 m/s stopped at constant deceleration within 12 mm, sampled
# every 0.1 ms from contact to the stop plus 10 rebound periods) on a fresh
# controller with the velocity sensor, then again without it (estimator).
# Printed per table and step: the most instructions, and where (the window
# index for profile.sh, and the state); `--all` prints every window too.
#
# Usage: bash firmware/bench/icount.sh [--all]   (from the repository root)
set -euo pipefail
cd "$(dirname "$0")/../.."
ALL=0
[ "${1:-}" = --all ] && ALL=1
. firmware/bench/image.sh
ELF=$(firmware_image pil-bench build --profile firmware -p mre-firmware --bin mre-firmware \
  --target thumbv7em-none-eabihf --no-default-features --features pil,bench)
. firmware/bench/trace.sh
# A "Stopped execution of TB chain before" line means the traced block did
# not run (an interrupt came first); it is traced again when it does.
awk -v b="$BEGIN_PC" -v e="$END_PC" -v all="$ALL" '
  /^Trace/   { split($4, f, "/"); pc = f[2]
               if (pc == b) { on = 1; n = 0 }
               if (on && pc == e) { counts[k++] = n - 3; on = 0 }
               else if (on) n++ ; next }
  /^Stopped/ { if (on) n-- }
  END {
    # The same constants as firmware/src/board/pil.rs (mod icount) and the
    # 10 kHz rate of the PIL image: they only label the windows.
    v0 = 2.24; s_mm = 12.0; period_s = 1.0e-4; grid = 13; grid_step_mm = 1.0
    near = 13; near_step_mm = 0.0725
    split("50 400 1200 2500 90000", forces, " "); nf = 5
    split("-10 100 300 600 90000", near_forces, " ")
    whole = grid * nf; model = whole + near * nf
    split("flown table|flown + all v2 terms|flown + lag, delay|flown + diagnosed", names, "|"); tables = 4
    per_table = k / tables; per_pass = (per_table - model) / 2
    if (k % tables != 0 || per_pass < 1 || per_pass != int(per_pass)) {
      print "unexpected number of measurements: " k > "/dev/stderr"; exit 1 }
    a = v0 * v0 / (2 * s_mm * 1.0e-3)
    for (i = 0; i < k; i++) {
      j = i % per_table
      table = names[int(i / per_table) + 1]
      if (j < model) {
        kind = "model step"
        if (j < whole) where = sprintf("x=%.0f mm, F=%s N", int(j / nf) * grid_step_mm, forces[j % nf + 1])
        else where = sprintf("x=%.4f mm, F=%s N", int((j - whole) / nf) * near_step_mm, near_forces[(j - whole) % nf + 1])
      } else {
        c = j - model; pass = (c < per_pass) ? "sensor" : "estimator"; c = c % per_pass
        kind = "control step (" pass ")"; t = c * period_s
        where = sprintf("period %d: x=%.2f mm, v=%.2f m/s", c, (v0 * t - 0.5 * a * t * t) * 1.0e3, v0 - a * t)
      }
      if (all) printf "%-20s | %-26s | %4d | window %d, %s\n", table, kind, counts[i], i, where
      key = sprintf("%-20s | %-26s", table, kind)
      if (!(key in max) || counts[i] > max[key]) { max[key] = counts[i]; at[key] = "window " i ", " where }
      windows[key]++; sum[key] += counts[i]
      if (!(key in seen)) { seen[key] = 1; order[m++] = key }
    }
    for (q = 0; q < m; q++) {
      key = order[q]
      printf "%s | max %4d | mean %4.0f over %3d | at %s\n", key, max[key], sum[key] / windows[key], windows[key], at[key]
    }
  }' "$TRACE"
