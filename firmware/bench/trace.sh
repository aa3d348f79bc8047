# Sourced by icount.sh and profile.sh (not run on its own): the QEMU exec
# trace of the `pil,bench` image with one instruction per translation block.
# Expects ELF; sets NM, BEGIN_PC, END_PC (the markers' entry addresses, as
# the trace prints them) and TRACE (a temporary file, removed on exit along
# with any file listed in TRACE_CLEANUP).
NM=$(command -v llvm-nm || command -v arm-none-eabi-nm || command -v rust-nm)
addr() { printf '%016x' "0x$("$NM" "$ELF" | awk -v s="$1" '$3==s {print $1}')"; }
BEGIN_PC=$(addr mre_mark_begin)
END_PC=$(addr mre_mark_end)
TRACE=$(mktemp)
trap 'rm -f "$TRACE" ${TRACE_CLEANUP:-}' EXIT
timeout 120 qemu-system-arm -M b-l475e-iot01a -nographic -monitor none -serial null \
  -semihosting-config enable=on,target=native -kernel "$ELF" \
  -accel tcg,one-insn-per-tb=on -d exec,nochain -D "$TRACE" >/dev/null
