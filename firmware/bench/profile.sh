#!/usr/bin/env bash
# Where the instructions of one measured window go: the QEMU exec trace of
# firmware/bench/icount.sh, cut to window N (0-based, in icount.sh's order),
# each executed instruction attributed to its source line and innermost
# (inlined) function through the ELF's debug info.
#
# Usage: bash firmware/bench/profile.sh N [lines]   (from the repository root;
# run icount.sh first: it builds the image this reads)
set -euo pipefail
cd "$(dirname "$0")/../.."
N=${1:?window index}
MODE=${2:-functions}
ELF=${CARGO_TARGET_DIR:-target}/images/pil-bench/mre-firmware
PCS=$(mktemp)
TRACE_CLEANUP=$PCS
. firmware/bench/trace.sh
awk -v b="$BEGIN_PC" -v e="$END_PC" -v want="$N" '
  /^Trace/   { split($4, f, "/"); pc = f[2]
               if (pc == b) { on = 1; last = "" ; next}
               if (on && pc == e) { on = 0; w++; next }
               if (on && w == want) { print pc; last = pc }
               next }
  /^Stopped/ { if (on && w == want && last != "") print "-" last }
' "$TRACE" > "$PCS"
# Interrupted-then-retraced blocks: drop one occurrence each.
grep -v '^-' "$PCS" | sort | uniq -c | sort -k2 > "$PCS.c"
echo "window $N: $(grep -vc '^-' "$PCS") instructions traced (markers included)"
awk '{ sub(/^0+/, "", $2); print "0x" $2 }' "$PCS.c" | llvm-addr2line -f -i -e "$ELF" -a > "$PCS.sym"
# Each address block: 0xADDR, then (function, file:line) pairs, innermost
# first. Modes: functions (innermost function), lines (source line), or
# depth D (the inline chain from the outermost frame, cut at D frames).
awk -v mode="$MODE" -v depth="${3:-3}" 'NR==FNR { a = $2; sub(/^0+/, "", a); cnt["0x" a] = $1; next }
  function flush() { if (a == "") return
      if (mode == "lines") key = loc1 " " substr(fn1, 1, 60)
      else if (mode == "functions") key = fn1
      else { key = ""; for (i = nf; i >= 1 && i > nf - depth; i--) key = key (key == "" ? "" : " > ") fns[i] }
      tot[key] += cnt[a] }
  /^0x/ { flush(); a = $1; sub(/^0x0*/, "0x", a); nf = 0; next }
  { fn = $0; getline loc; sub(/.*\/(src|library)\//, "", loc)
    # short name: the last path segments before the hash
    short = fn; sub(/17h[0-9a-f]+E$/, "", short); gsub(/_\$LT\$|\$GT\$|\$u20\$|\$u7b\$|\$u7d\$/, "", short)
    n = split(short, parts, /[0-9]+/); short = parts[n - 1] "::" parts[n]
    nf++; fns[nf] = short; if (nf == 1) { fn1 = fn; loc1 = loc } }
  END { flush(); for (k in tot) printf "%5d %s\n", tot[k], k }' "$PCS.c" "$PCS.sym" | sort -rn | head -60
rm -f "$PCS.c" "$PCS.sym"
