#!/usr/bin/env bash
# The paper's whole offline workflow on the bundled real MR damper data:
# fit (GSA and least squares, 0.5 A held out) → validate (0.5 A predicted by
# interpolation) → plots → GSA sweep → flash table source.
# Usage: scripts/pipeline.sh [OUT_DIR]   (default: out/pipeline)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-out/pipeline}"
DATA=data/mr-damper-mts
cargo build --release -q -p host-tools
MRE=target/release/mre
"$MRE" fit "$DATA" --method both --hold-out-current 0.5 --out "$OUT/model.toml"
"$MRE" validate "$DATA" --model "$OUT/model.toml" --hold-out-current 0.5 --report "$OUT/report" > /dev/null
echo "wrote $OUT/report/report.md and report.json"
"$MRE" plot "$DATA" --model "$OUT/model.toml" --hold-out-current 0.5 --out "$OUT/plots"
"$MRE" sweep "$DATA" --hold-out-current 0.5 --out "$OUT/sweep" | tail -1
# The flash table from the committed full model (all three currents):
"$MRE" tables models/mr-damper-mts.toml --out "$OUT/generated_table.rs"
# Diagnosis on a bundled drop-impact set with a concealed effect (answer in data/keys/):
"$MRE" diagnose data/drop-end_stop --report "$OUT/diagnose" --json "$OUT/diagnose/report.json" --predictions "$OUT/diagnose/predictions"
echo "diagnosis report: $OUT/diagnose/report.md"
