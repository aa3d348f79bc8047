#!/usr/bin/env bash
# Regenerates the tables of BENCHMARKS.md, one section per argument
# (default: all of them). Each section prints its rows; paste them into
# BENCHMARKS.md with the commit (`git rev-parse --short HEAD`), the date and
# the machine (`nproc`, the load average printed before each section).
#
#   bash bench/all.sh                    # everything (about 1 h on 2 cores)
#   bash bench/all.sh fitting control    # some sections
#   DIAG_SEEDS="3 4 5 6 7" bash bench/all.sh diagnosis   # real-data seeds (5 min each)
set -euo pipefail
cd "$(dirname "$0")/.."
sections=("$@")
[[ ${#sections[@]} -eq 0 ]] && sections=(fitting firmware control diagnosis families reliability)
out=out/bench
mkdir -p "$out"
cargo build --release -q -p host-tools
MRE=target/release/mre

for s in "${sections[@]}"; do
    echo "== $s: $(git rev-parse --short HEAD), $(date -u '+%F %H:%M UTC'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
    case "$s" in
    fitting)
        bash bench/fitting.sh
        cargo bench -q -p host-tools --bench fit -- --noplot
        cargo test -q -p host-tools --test integration dataset_motion::drift -- --nocapture
        cargo test -q -p host-tools --test integration dataset_motion::fit_from -- --nocapture
        ;;
    firmware)
        bash firmware/bench/budgets.sh
        bash firmware/bench/reset_icount.sh
        "$MRE" pil --report "$out/pil" | tail -3
        cargo test -q -p host-tools pil_drop_with_a_full_blocking_rtt_buffer -- --nocapture
        ;;
    control)
        "$MRE" bench-control --out "$out/control" >/dev/null
        cat "$out/control/report.md"
        "$MRE" bench-control --real-coils --out "$out/real-coils" >/dev/null
        cat "$out/real-coils/report.md"
        "$MRE" fmu models/drop-full-stroke.toml --out "$out/damper.fmu"
        CARGO_TARGET_DIR=target/fmu cargo run -q --release \
            -p mre-fmu --example step_cost -- "$out/damper.fmu"
        cargo test -q -p host-tools --test integration fmu_fmpy:: -- --nocapture
        ;;
    diagnosis)
        "$MRE" bench-diagnose --cases 60 --seed 1 --mts-cases 10 --json "$out/sim1.json"
        "$MRE" bench-diagnose --cases 0 --mts-cases 0 --instrumented-cases 40 --seed 2 --json "$out/instr2.json"
        "$MRE" bench-diagnose --cases 0 --mts-cases 30 --instrumented-cases 0 --seed 1 --json "$out/mts30.json"
        # The reporting seeds (BENCHMARKS.md): 3000-3099; 1000-1099 and
        # 2000-2099 are tuning cases now.
        "$MRE" bench-diagnose --calibration 100 --seed "${CALIBRATION_SEED:-3000}" --json "$out/calibration.json"
        "$MRE" diagnose data/mr-damper-mts --report "$out/diagnose-mts-default" \
            --json "$out/diagnose-mts-default.json" --predictions "$out/diagnose-mts-default-pred" | tail -3
        python3 bench/near_rest.py "$out/diagnose-mts-default-pred"
        for seed in ${DIAG_SEEDS:-3}; do
            "$MRE" bench-diagnose --real data/mr-damper-mts --cases 30 --seed "$seed" \
                --folds-by frequency_hz --validate-current 0.5 --json "$out/real_$seed.json"
        done
        "$MRE" diagnose data/mr-damper-mts --folds-by frequency_hz --validate-current 0.5 \
            --report "$out/diagnose-mts" | tail -5
        RUNS=3 MRE="$MRE" bash bench/diagnose_real.sh
        RUNS=3 MRE="$MRE" bash bench/diagnose.sh
        ;;
    families)
        bash bench/compare.sh
        ;;
    reliability)
        for seed in $(seq 1 20); do
            for rate in 1e-3 1e-2; do
                "$MRE" pil --faults "corrupt:$rate,drop:$rate,duplicate:$rate" --seed "$seed" \
                    --report "$out/faults-$rate-$seed" | tail -1 | sed "s/^/rate $rate seed $seed: /"
            done
        done
        "$MRE" pil --faults all:1e-2 --report "$out/faults-all" | tail -3
        (cd fuzz && for t in dataset_reader table_loader frame_decoder upload; do
            mkdir -p "corpus/$t"
            cargo +nightly fuzz run "$t" -O "corpus/$t" "seeds/$t" -- -max_total_time=150 -seed=7 2>&1 | tail -2
        done)
        ;;
    *)
        echo "unknown section: $s (fitting, firmware, control, diagnosis, families, reliability)" >&2
        exit 2
        ;;
    esac
done
