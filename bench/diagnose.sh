#!/usr/bin/env bash
# Times `mre diagnose` on every bundled 60-recording drop-impact set (54
# constant-current drops + 6 controlled impacts), with a
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

# Wall time (ns clock: the peer takes a few ms, below /usr/bin/time's 10 ms
# resolution) and CPU time (user + sys) of one command, in seconds.
timed() {
  local t0 t1
  t0=$(date +%s%N)
  /usr/bin/time -f '%U %S' -o "$out/time" "$@" >/dev/null
  t1=$(date +%s%N)
  awk -v w="$(( t1 - t0 ))" '{printf "%.4f %s\n", w / 1e9, $1 + $2}' "$out/time"
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }

printf '| data set | recordings | samples | diagnose wall median (s) | diagnose CPU median (s) | fit --method lsq wall median (s) | diagnose / fit (wall) | found |\n'
printf '|---|---|---|---|---|---|---|---|\n'
for set in data/drop-*/; do
  set=${set%/}
  name=$(basename "$set")
  d_wall=() d_cpu=() f_wall=()
  for _ in $(seq "$RUNS"); do
    read -r w c < <(timed "$MRE" diagnose "$set" --report "$out/rep" --json "$out/r.json" --predictions "$out/pred")
    d_wall+=("$w") d_cpu+=("$c")
    read -r w _ < <(timed "$MRE" fit "$set" --method lsq --out "$out/model.toml")
    f_wall+=("$w")
  done
  d=$(printf '%s\n' "${d_wall[@]}" | median)
  dc=$(printf '%s\n' "${d_cpu[@]}" | median)
  f=$(printf '%s\n' "${f_wall[@]}" | median)
  recs=$(grep -c '^\[\[recording\]\]' "$set/dataset.toml")
  samples=$(cat "$set"/*.csv | wc -l)
  found=$(python3 -c "import json,sys; print(', '.join(e['name'] for e in json.load(open(sys.argv[1]))['effects']) or 'none')" "$out/r.json")
  printf '| %s | %s | %s | %.2f | %.2f | %.3f | %.0f | %s |\n' "$name" "$recs" "$samples" "$d" "$dc" "$f" "$(echo "$d / $f" | bc -l)" "$found"
done
