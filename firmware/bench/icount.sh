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
# The cases span the whole usable stroke (x 0–12 mm, including x ≥ 4 mm where
# the stiff currents' quartics clamp x), first with the flown table
# (firmware/src/generated_table.rs), then with the same entries and every
# format 2 term (coil τ, sensor delay, viscous, saturation): the worst path.
#
# Usage: bash firmware/bench/icount.sh   (from the repository root)
set -euo pipefail
cd "$(dirname "$0")/../.."
TARGET_DIR=target/pil-bench
cargo build --release -q -p mre-firmware --bin mre-firmware --target thumbv7em-none-eabihf \
  --no-default-features --features pil,bench --target-dir "$TARGET_DIR"
ELF=$TARGET_DIR/thumbv7em-none-eabihf/release/mre-firmware
NM=$(command -v llvm-nm || command -v arm-none-eabi-nm || command -v rust-nm)
addr() { printf '%016x' "0x$("$NM" "$ELF" | awk -v s="$1" '$3==s {print $1}')"; }
BEGIN_PC=$(addr mre_mark_begin)
END_PC=$(addr mre_mark_end)
TRACE=$(mktemp)
trap 'rm -f "$TRACE"' EXIT
timeout 120 qemu-system-arm -M b-l475e-iot01a -nographic -monitor none -serial null \
  -semihosting-config enable=on,target=native -kernel "$ELF" \
  -accel tcg,one-insn-per-tb=on -d exec,nochain -D "$TRACE" >/dev/null
# A "Stopped execution of TB chain before" line means the traced block did
# not run (an interrupt came first); it is traced again when it does.
awk -v b="$BEGIN_PC" -v e="$END_PC" '
  /^Trace/   { split($4, f, "/"); pc = f[2]
               if (pc == b) { on = 1; n = 0 }
               if (on && pc == e) { counts[k++] = n - 3; on = 0 }
               else if (on) n++ ; next }
  /^Stopped/ { if (on) n-- }
  END {
    split("model x=0.5mm,v=2.2,F=900N|model x=2mm,v=2.0,F=1300N|model x=3.5mm,v=1.9,F=1250N|model x=6mm,v=1.5,F=1250N (clamped)|model x=10mm,v=0.9,F=1300N (clamped)|model x=12mm,v=0.3,F=90kN (clamped, saturated)|control x=0.5mm,v=2.2 (sensor)|control x=3mm,v=1.9 (sensor)|control x=6mm,v=1.5 (sensor)|control x=10mm (estimator)|control x=11.95mm,v=0.2 (terminal)|control x=6mm,v=-1 (rebound)", names, "|")
    for (i = 0; i < k; i++) {
      table = (i < 12) ? "flown table" : "flown + all v2 terms"
      printf "%-22s %-46s %6d instructions\n", table, names[i % 12 + 1], counts[i]
    }
    if (k != 24) { print "expected 24 measurements, got " k > "/dev/stderr"; exit 1 }
  }' "$TRACE"
