#!/usr/bin/env bash
# Times `mre diagnose` on a 30-recording set of real recordings (issue 12:
# "each 30-recording real set is diagnosed in ≤ 10 s on 2 cores"), against
# a peer measured in the same loop: the same command on the bundled
# 15-recording set the 30 recordings are cut from.
#
#   bash bench/diagnose_real.sh              # builds the release binary first
#   RUNS=5 MRE=target/release/mre bash bench/diagnose_real.sh
#   KEEP=/tmp/mts30 bash bench/diagnose_real.sh   # also keep the 30-recording set
#
# The 30 recordings: every bundled MTS recording (data/mr-damper-mts, 15
# real recordings at 0/0.5/1 A, 5 amplitude-frequency pairs) cut at its
# middle sample into two contiguous halves, each its own recording with the
# same current and tags plus `segment = 1|2`. Every sample is a real
# measurement, used once, unresampled and in its original time order;
# nothing is copied, mirrored or synthesised. Both halves of a test share
# its frequency, so `--folds-by frequency_hz` keeps them in one fold (no
# half is held out against its own other half).
#
# Per run: wall and CPU (user, sys) from /usr/bin/time, and the 1-minute
# load average before the run (other work on the machine inflates wall
# time, not CPU time).
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${RUNS:-3}
SRC=data/mr-damper-mts
if [[ -z "${MRE:-}" ]]; then
  cargo build --quiet --release -p host-tools --bin mre
  MRE=target/release/mre
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
set30=${KEEP:-$out/mts30}
mkdir -p "$set30"

# dataset.toml of the split set: the source's [defaults], then two entries
# per source recording (file, current, tags read from the source manifest).
{
  printf 'name = "MR damper, MTS sinusoidal tests (real), each recording cut into two halves: 30 recordings"\n\n'
  printf '[defaults]\ndelimiter = "whitespace"\ncolumns = ["time_s", "displacement_mm", "velocity_mm_s", "force_n"]\n'
} >"$set30/dataset.toml"
n_src=0
while IFS=$'\t' read -r file current tags; do
  stem=${file%.txt}
  lines=$(wc -l <"$SRC/$file")
  half=$(( lines / 2 ))
  head -n "$half" "$SRC/$file" >"$set30/${stem}_1.txt"
  tail -n "+$(( half + 1 ))" "$SRC/$file" >"$set30/${stem}_2.txt"
  for seg in 1 2; do
    printf '\n[[recording]]\nfile = "%s_%s.txt"\ncurrent_a = %s\ntags = { %s, segment = %s }\n' \
      "$stem" "$seg" "$current" "$tags" "$seg" >>"$set30/dataset.toml"
  done
  n_src=$(( n_src + 1 ))
done < <(awk '
  /^file = /      { gsub(/"/, "", $3); f = $3 }
  /^current_a = / { c = $3 }
  /^tags = /      { t = $0; sub(/^tags = \{ */, "", t); sub(/ *\}$/, "", t); print f "\t" c "\t" t }
' "$SRC/dataset.toml")
n30=$(grep -c '^\[\[recording\]\]' "$set30/dataset.toml")
# Every source sample is in exactly one half.
src_samples=$(cat "$SRC"/*.txt | wc -l)
cut_samples=$(cat "$set30"/*.txt | wc -l)
[[ $n_src -eq 15 && $n30 -eq 30 && $src_samples -eq $cut_samples ]] || {
  echo "split set is wrong: $n_src sources, $n30 recordings, $cut_samples of $src_samples samples" >&2
  exit 1
}

run() { # set label
  local set=$1 label=$2 load
  load=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f '%e %U %S' -o "$out/time" "$MRE" diagnose "$set" --folds-by frequency_hz \
    --validate-current 0.5 --report "$out/rep-$label" --json "$out/$label.json" \
    --predictions "$out/pred-$label" --quiet >/dev/null
  read -r wall user sys <"$out/time"
  local found
  found=$(python3 -c "import json,sys; print(', '.join(e['name'] for e in json.load(open(sys.argv[1]))['effects']) or 'none')" "$out/$label.json")
  printf '| %s | %s | %s | %s | %s | %.2f | %s |\n' "$label" "$load" "$wall" "$user" "$sys" \
    "$(echo "$user + $sys" | bc -l)" "$found"
  echo "$label $wall $(echo "$user + $sys" | bc -l)" >>"$out/all"
}

echo "30-recording set: $n30 recordings, $cut_samples samples (from $n_src recordings of $SRC)"
printf '| set | load avg (1 min) before | wall (s) | user (s) | sys (s) | CPU (s) | found |\n'
printf '|---|---|---|---|---|---|---|\n'
for _ in $(seq "$RUNS"); do
  run "$set30" split-30
  run "$SRC" bundled-15
done
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
for label in split-30 bundled-15; do
  w=$(awk -v l="$label" '$1 == l {print $2}' "$out/all" | median)
  c=$(awk -v l="$label" '$1 == l {print $3}' "$out/all" | median)
  echo "$label: median wall $w s, median CPU $c s"
  eval "w_${label%%-*}=$w c_${label%%-*}=$c"
done
printf 'ratio 30 / 15: wall %.2f, CPU %.2f\n' "$(echo "$w_split / $w_bundled" | bc -l)" "$(echo "$c_split / $c_bundled" | bc -l)"
