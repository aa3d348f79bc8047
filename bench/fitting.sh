#!/usr/bin/env bash
# Fitting benchmarks (BENCHMARKS.md, "Fitting"), in one run:
#  1. mre's GSA against niapy's GSA on DATASET (default data/mr-damper-mts):
#     same objective values, N, T, evaluation count and search box (data box);
#  2. the two-box benchmark on BOX_DATASET (default data/drop-none, the
#     paper's scale), every branch: GSA on the data box and on the paper's
#     Table 3 box, each against the least-squares optimum inside the box and
#     against niapy's GSA on the same moment-form objective; the speed-up split
#     in two (the objective: niapy per-sample vs moment form; the search: mre
#     on one thread vs niapy on the moment form); mre's per-agent against
#     per-dimension random weights over 10 seeds (`cargo bench --bench gsa_weights`).
# About 40 min on an idle 2-core machine (niapy: ~1 min per branch and run).
# Installs niapy and scipy if missing. MRE=path uses that binary (no build).
# NIAPY_CACHE=FILE reuses niapy results (bench/gsa_boxes.py).
# Usage: bench/fitting.sh [DATASET [BOX_DATASET]]
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${1:-data/mr-damper-mts}"
BOX_DATA="${2:-data/drop-none}"
python3 -c "import niapy, scipy" 2>/dev/null || pip install --quiet niapy scipy
if [[ -z "${MRE:-}" ]]; then
    cargo build --release -q -p host-tools
    MRE=target/release/mre
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Median fit time (ms, excludes loading) of RUNS GSA fits at N = T = 100.
gsa_ms() {
    local times=() ms
    for _ in $(seq "${RUNS:-7}"); do
        ms="$("$MRE" fit "$@" --method gsa --out "$tmp/gsa.toml" | sed -n 's/^fitted .* in \([0-9.]*\) ms.*/\1/p')"
        times+=("$ms")
    done
    printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'
}

echo "== 1. mre GSA vs niapy GSA on $DATA (data box)"
median_ms="$(gsa_ms "$DATA")"
echo "mre fit --method gsa: median ${median_ms} ms"
"$MRE" fit "$DATA" --method lsq --out "$tmp/lsq.toml" | tail -1
"$MRE" fit "$DATA" --method both --out "$tmp/both.toml" > /dev/null
python3 bench/gsa_peer.py "$DATA" "$tmp/both.toml" "$(python3 -c "print($median_ms / 1000)")"

echo "== 2. two boxes on $BOX_DATA"
data_ms="$(RAYON_NUM_THREADS=1 gsa_ms "$BOX_DATA" --bounds data)"
paper_ms="$(RAYON_NUM_THREADS=1 gsa_ms "$BOX_DATA" --bounds paper)"
echo "mre GSA on one thread, all branches: data box ${data_ms} ms, paper box ${paper_ms} ms (median of ${RUNS:-7})"
DATASET="$PWD/$BOX_DATA" CSV="$tmp/weights.csv" cargo bench -q -p host-tools --bench gsa_weights
"$MRE" fit "$BOX_DATA" --method both --bounds data --out "$tmp/box-data.toml" > /dev/null
"$MRE" fit "$BOX_DATA" --method both --bounds paper --out "$tmp/box-paper.toml" > /dev/null
python3 bench/gsa_boxes.py "$BOX_DATA" "$tmp/box-data.toml" "$tmp/box-paper.toml" \
    "$(python3 -c "print($data_ms / 1000)")" "$(python3 -c "print($paper_ms / 1000)")" "$tmp/weights.csv"
