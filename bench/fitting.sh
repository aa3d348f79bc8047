#!/usr/bin/env bash
# Host fitting benchmark: mre's GSA against niapy's GSA (same objective, N, T,
# evaluation count and search box), in one run. Installs niapy if missing.
# Usage: bench/fitting.sh [DATASET]   (default: data/mr-damper-mts)
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${1:-data/mr-damper-mts}"
python3 -c "import niapy" 2>/dev/null || pip install --quiet niapy
cargo build --release -q -p host-tools
MRE=target/release/mre
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# mre: median fit time (excludes loading) of 7 GSA runs at N = T = 100.
times=()
for _ in 1 2 3 4 5 6 7; do
    ms="$("$MRE" fit "$DATA" --method gsa --out "$tmp/gsa.toml" | sed -n 's/^fitted .* in \([0-9.]*\) ms.*/\1/p')"
    times+=("$ms")
done
median_ms="$(printf '%s\n' "${times[@]}" | sort -g | sed -n 4p)"
echo "mre fit --method gsa: fit times (ms) ${times[*]}; median ${median_ms} ms"
time "$MRE" fit "$DATA" --method lsq --out "$tmp/lsq.toml" | tail -1
"$MRE" fit "$DATA" --method both --out "$tmp/both.toml" > /dev/null
python3 bench/gsa_peer.py "$DATA" "$tmp/both.toml" "$(python3 -c "print($median_ms / 1000)")"
