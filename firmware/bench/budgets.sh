#!/usr/bin/env bash
# Fails when the firmware exceeds its budgets (issue 11):
#   model step ≤ 150 executed instructions with the flown table and with
#   every format 2 term, control step ≤ 400 with the flown table (the
#   every-term control step: an interim ceiling, see below), all measured by
#   firmware/bench/icount.sh (QEMU); flash ≤ 64 KiB and RAM ≤ 16 KiB
#   (static: .data + .bss + .uninit) for the `cargo fw` image.
# Usage: bash firmware/bench/budgets.sh   (from the repository root; builds
# the images it measures)
set -euo pipefail
cd "$(dirname "$0")/../.."
MODEL_MAX=150 CONTROL_MAX=400 FLASH_MAX=$((64 * 1024)) RAM_MAX=$((16 * 1024))
# The every-term control step's ceiling until it meets CONTROL_MAX: the
# measured worst (653, 2026-11-23; 875 before) plus room for inlining noise.
TERMS_CONTROL_CEILING=680

COUNTS=$(bash firmware/bench/icount.sh)
echo "$COUNTS"
cargo build --release -q -p mre-firmware --bin mre-firmware --target thumbv7em-none-eabihf
ELF=target/thumbv7em-none-eabihf/release/mre-firmware
SIZES=$(llvm-size -A "$ELF")

echo "$COUNTS" | awk -v m="$MODEL_MAX" -v c="$CONTROL_MAX" -v ct="$TERMS_CONTROL_CEILING" '
  { n = $(NF - 1) }
  # Enforced on both row sets: the model step (≤ 150), and the control step
  # (≤ 400) of the table `cargo fw` flies. The control step with every
  # format 2 term (a diagnosed model with coil lag, delay, viscous and
  # saturation terms) is still over 400 (BENCHMARKS.md, "Instructions per
  # step"): it is held to an interim ceiling so it cannot grow unnoticed.
  /^flown table / && /model x=/   { if (n > mm) mm = n }
  /^flown table / && /control x=/ { if (n > cm) cm = n }
  /all v2 terms/ && /model x=/    { if (n > tm) tm = n }
  /all v2 terms/ && /control x=/  { if (n > tc) tc = n }
  END {
    printf "flown table: model step worst %d / %d instructions, control step worst %d / %d\n", mm, m, cm, c
    printf "every format 2 term: model step worst %d / %d, control step worst %d / %d (interim ceiling %d)\n", tm, m, tc, c, ct
    if (mm == 0 || cm == 0 || tm == 0 || tc == 0) { print "no instruction counts" > "/dev/stderr"; exit 1 }
    if (tc > c) print "every format 2 term: control step budget NOT MET (" tc " > " c ")"
    if (mm > m || cm > c || tm > m || tc > ct) { print "BUDGET EXCEEDED: instructions per step" > "/dev/stderr"; exit 1 }
  }'
echo "$SIZES" | awk -v f="$FLASH_MAX" -v r="$RAM_MAX" '
  $1 ~ /^\.(vector_table|text|rodata|data)$/ { flash += $2 }
  $1 ~ /^\.(data|bss|uninit)$/ { ram += $2 }
  END {
    printf "flash %d / %d bytes, static RAM %d / %d bytes\n", flash, f, ram, r
    if (flash == 0) { print "no sections measured" > "/dev/stderr"; exit 1 }
    if (flash > f || ram > r) { print "BUDGET EXCEEDED: memory" > "/dev/stderr"; exit 1 }
  }'
