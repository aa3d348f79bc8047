#!/usr/bin/env bash
# `mre compare` benchmarks, in one run:
#  1. the Bouc–Wen GSA stage against niapy's GSA and SciPy's differential_evolution
#     (same objective, same evaluation count; installs niapy and scipy if missing);
#  2. the whole comparison on the bundled MTS data (wall time).
# Usage: bench/compare.sh [DATASET]   (default: data/mr-damper-mts)
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${1:-data/mr-damper-mts}"
python3 -c "import niapy, scipy" 2>/dev/null || pip install --quiet niapy scipy
cargo build --release -q -p host-tools
MRE=target/release/mre
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$MRE" bench-compare "$DATA" --out "$tmp/bench"
RAYON_NUM_THREADS=1 "$MRE" bench-compare "$DATA" --out "$tmp/bench1" | sed 's/^/single thread: /'
python3 bench/compare_gsa.py "$tmp/bench"
/usr/bin/time -f "mre compare: %e s wall, %U s user" "$MRE" compare "$DATA" --report "$tmp/report" | tail -2
