#!/usr/bin/env bash
# Fails when the firmware exceeds its budgets (issue 11):
#   model step ≤ 150 and control step ≤ 400 executed instructions, each the
#   most any measured window took (firmware/bench/icount.sh: a model grid over
#   x 0–12 mm and a whole drop, QEMU), with the flown table, with every
#   format 2 term, and with coil lag + sensor delay (what `mre pil` flies);
#   flash ≤ 64 KiB and RAM ≤ 16 KiB (static: .data + .bss + .uninit) for the
#   `cargo fw` image. Where a budget is not met yet, the row
#   says so and is held to an interim ceiling instead (see below), so that
#   it cannot grow unnoticed; the flown control step is held to its budget.
# Usage: bash firmware/bench/budgets.sh   (from the repository root; builds
# the images it measures)
set -euo pipefail
cd "$(dirname "$0")/../.."
MODEL_MAX=150 CONTROL_MAX=400 FLASH_MAX=$((64 * 1024)) RAM_MAX=$((16 * 1024))
# Interim ceilings until the budgets are met: the worst measured over the
# whole drop and the model grid (2026-11-23; BENCHMARKS.md, "Instructions per
# step") plus room for inlining noise. The flown model step: 152, a target
# below every entry's force (all 5 quartics scanned) at x ≥ 1 mm. Every
# format 2 term: model step 160, control step 458 (700 before the look-ahead
# from the plan's trend; 875 two rounds before).
FLOWN_MODEL_CEILING=155
TERMS_MODEL_CEILING=165
TERMS_CONTROL_CEILING=480
# Coil lag and sensor delay only (what `mre pil` flies for controller (c)):
# model step 152, control step 426 (2026-11-23).
LAG_MODEL_CEILING=155
LAG_CONTROL_CEILING=440

COUNTS=$(bash firmware/bench/icount.sh)
echo "$COUNTS"
cargo build --release -q -p mre-firmware --bin mre-firmware --target thumbv7em-none-eabihf
ELF=target/thumbv7em-none-eabihf/release/mre-firmware
SIZES=$(llvm-size -A "$ELF")

echo "$COUNTS" | awk -F' [|] ' -v m="$MODEL_MAX" -v c="$CONTROL_MAX" \
  -v fmc="$FLOWN_MODEL_CEILING" -v tmc="$TERMS_MODEL_CEILING" -v tcc="$TERMS_CONTROL_CEILING" \
  -v lmc="$LAG_MODEL_CEILING" -v lcc="$LAG_CONTROL_CEILING" '
  # Each row: table | step | max N | mean … | at window …
  $3 ~ /^max / { n = $3; sub(/^max +/, "", n); n += 0 }
  $1 ~ /^flown table/ && $2 ~ /^model/   { if (n > mm) mm = n }
  $1 ~ /^flown table/ && $2 ~ /^control/ { if (n > cm) cm = n }
  $1 ~ /all v2 terms/ && $2 ~ /^model/   { if (n > tm) tm = n }
  $1 ~ /all v2 terms/ && $2 ~ /^control/ { if (n > tc) tc = n }
  $1 ~ /lag, delay/ && $2 ~ /^model/     { if (n > lm) lm = n }
  $1 ~ /lag, delay/ && $2 ~ /^control/   { if (n > lc) lc = n }
  function row(name, n, budget, ceiling) {
    if (n <= budget) { printf "%s: worst %d / %d instructions: met\n", name, n, budget; return 0 }
    printf "%s: worst %d / %d instructions: budget NOT MET (interim ceiling %d)\n", name, n, budget, ceiling
    return n > ceiling
  }
  END {
    if (mm == 0 || cm == 0 || tm == 0 || tc == 0 || lm == 0 || lc == 0) { print "no instruction counts" > "/dev/stderr"; exit 1 }
    bad = row("flown table, model step", mm, m, fmc)
    bad += row("flown table, control step", cm, c, c)
    bad += row("every format 2 term, model step", tm, m, tmc)
    bad += row("every format 2 term, control step", tc, c, tcc)
    bad += row("coil lag + sensor delay, model step", lm, m, lmc)
    bad += row("coil lag + sensor delay, control step", lc, c, lcc)
    if (bad) { print "BUDGET EXCEEDED: instructions per step" > "/dev/stderr"; exit 1 }
  }'
echo "$SIZES" | awk -v f="$FLASH_MAX" -v r="$RAM_MAX" '
  $1 ~ /^\.(vector_table|text|rodata|data)$/ { flash += $2 }
  $1 ~ /^\.(data|bss|uninit)$/ { ram += $2 }
  END {
    printf "flash %d / %d bytes, static RAM %d / %d bytes\n", flash, f, ram, r
    if (flash == 0) { print "no sections measured" > "/dev/stderr"; exit 1 }
    if (flash > f || ram > r) { print "BUDGET EXCEEDED: memory" > "/dev/stderr"; exit 1 }
  }'
