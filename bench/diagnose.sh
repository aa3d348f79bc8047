#!/usr/bin/env bash
# Times `mre diagnose` on every bundled 54-recording drop-impact set, with a
# peer measured in the same run: `mre fit --method lsq` (the host's baseline
# least-squares fit) on the same set. Prints per-set median wall times over
# RUNS runs and the ratio diagnose / fit.
#
#   bash bench/diagnose.sh            # builds the release binary first
#   RUNS=9 MRE=target/release/mre bash bench/diagnose.sh
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${RUNS:-5}
if [[ -z "${MRE:-}" ]]; then
  cargo build --quiet --release -p host-tools --bin mre
  MRE=target/release/mre
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

now() { date +%s.%N; }
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }

printf '| data set | recordings | samples | diagnose median (s) | fit --method lsq median (s) | diagnose / fit | found |\n'
printf '|---|---|---|---|---|---|---|\n'
for set in data/drop-*/; do
  set=${set%/}
  name=$(basename "$set")
  d_times=() f_times=()
  for _ in $(seq "$RUNS"); do
    t0=$(now)
    "$MRE" diagnose "$set" --report "$out/rep" --json "$out/r.json" --predictions "$out/pred" >"$out/stdout"
    t1=$(now)
    "$MRE" fit "$set" --method lsq --out "$out/model.toml" >/dev/null
    t2=$(now)
    d_times+=("$(echo "$t1 - $t0" | bc -l)")
    f_times+=("$(echo "$t2 - $t1" | bc -l)")
  done
  d=$(printf '%s\n' "${d_times[@]}" | median)
  f=$(printf '%s\n' "${f_times[@]}" | median)
  recs=$(grep -c '^\[\[recording\]\]' "$set/dataset.toml")
  samples=$(cat "$set"/*.csv | wc -l)
  found=$(python3 -c "import json,sys; print(', '.join(e['name'] for e in json.load(open(sys.argv[1]))['effects']) or 'none')" "$out/r.json")
  printf '| %s | %s | %s | %.2f | %.2f | %.1f | %s |\n' "$name" "$recs" "$samples" "$d" "$f" "$(echo "$d / $f" | bc -l)" "$found"
done
