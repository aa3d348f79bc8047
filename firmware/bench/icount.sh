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
    split("model x=0.1mm,F=600N|model x=0.2mm,F=1726N|model x=0.5mm,F=3000N|model x=0.9mm,F=9000N (saturated)|law x=0.2mm,v=3m/s|law x=0.5mm,v=2m/s|control x=0.2mm,v=3m/s (sensor)|control x=0.5mm,v=2m/s (sensor)|control x=0.8mm (estimator)|control x=0.3mm,v=-1m/s (rebound)", names, "|")
    for (i = 0; i < k; i++) printf "%-42s %6d instructions\n", names[i + 1], counts[i]
    if (k != 10) { print "expected 10 measurements, got " k > "/dev/stderr"; exit 1 }
  }' "$TRACE"
