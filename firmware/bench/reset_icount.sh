#!/usr/bin/env bash
# Executed instructions from the reset vector to the first coil command, in
# QEMU (one instruction per translation block, exec trace, as icount.sh).
# The first coil command on every reset path is the store that makes PB4 a
# low output in `__pre_init` (firmware/src/board/mod.rs, label
# `mre_coil_pin_safe`): it runs before RAM init and before RCC_CSR is read,
# so it is the same on every path (watchdog, software, brown-out/power-on,
# pin). Measured on the PIL image and on the B-L475E-IOT01A image (`cargo
# fw`; it runs in QEMU up to embassy_stm32::init, whose backup-domain unlock
# waits for a PWR model QEMU does not have: the fail-safe PWM duty after it
# cannot be reached here).
#
# Usage: bash firmware/bench/reset_icount.sh   (from the repository root)
set -euo pipefail
cd "$(dirname "$0")/../.."
. firmware/bench/image.sh
PIL=$(firmware_image fw-pil fw-pil)
FW=$(firmware_image fw fw)
NM=$(command -v llvm-nm || command -v arm-none-eabi-nm || command -v rust-nm)
TRACE=$(mktemp)
trap 'rm -f "$TRACE"' EXIT
for image in "pil:$PIL" "b-l475e-iot01a:$FW"; do
  name=${image%%:*}
  ELF=${image#*:}
  pc=$(printf '%016x' "0x$("$NM" "$ELF" | awk '$3=="mre_coil_pin_safe" {print $1}')")
  # Both images wait (for frames, or in a loop QEMU cannot leave): stop after 3 s.
  timeout 3 qemu-system-arm -M b-l475e-iot01a -nographic -monitor none -serial null \
    -semihosting-config enable=on,target=native -kernel "$ELF" \
    -accel tcg,one-insn-per-tb=on -d exec,nochain -D "$TRACE" >/dev/null 2>&1 || true
  awk -v e="$pc" -v name="$name" '
    /^Trace/   { split($4, f, "/"); n++; if (f[2] == e) { print name ": reset vector -> coil pin low (pre_init store): " n " instructions"; found = 1; exit } next }
    /^Stopped/ { n-- }
    END { if (!found) { print name ": mre_coil_pin_safe never ran" > "/dev/stderr"; exit 1 } }' "$TRACE"
done
