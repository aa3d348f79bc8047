#!/usr/bin/env bash
# Regenerates the bundled drop-impact data sets, byte for byte.
#
#   bash data/generate.sh
#
# Each set is `mre synth` output: 60 drop tests of a 5.5 kg mass in a shuffled
# run order: 54 at constant current (fit currents 0/0.5/1/1.5/2 A, validate
# currents 0.3/0.7/1.3/1.7 A, impact velocities 1.4/1.8/2.24 m/s, 2 repeats)
# and 6 controlled impacts (validate), whose coil command steps 0.8 ms after
# contact (step_i<from>-<to>_v<velocity>.csv, command in the current_a column).
# Every set has the same plan. drop-none has no concealed effect; each other
# set has the one effect its name says. The answers (effect
# parameters, base law, instrument) are in data/keys/, outside the sets, so a
# diagnosis run on a set stays blind. `tests/plant_bundled_data.rs` checks the
# committed files still match this script.
#
# drop-full-stroke (no concealed effect) has the same plan except the drop
# heights: one per current, so that every current's fastest test reaches
# 15 mm (0 A about 2 m/s, 2 A about 8.5 m/s). At the paper's 2.24 m/s the
# stiff currents stop the mass within 4–5 mm, and a model fitted on those
# drops would be clamped over the rest of the stroke; the model `cargo fw`
# flies (models/drop-full-stroke.toml) is fitted on this set.
set -euo pipefail
cd "$(dirname "$0")/.."
MRE=${MRE:-"cargo run --quiet -p host-tools --bin mre --"}

gen() {
  local effect=$1 seed=$2
  $MRE synth --effect "$effect" --seed "$seed" --out "data/drop-$effect" --key "data/keys/drop-$effect.json" --force
}

gen none 101
gen viscous_damping 102
gen sensor_delay 103
gen stress_softening 104
gen end_stop 105
gen magnetic_saturation 106
gen coil_lag 107
$MRE synth --effect none --seed 108 --full-stroke-mm 15 --out data/drop-full-stroke --key data/keys/drop-full-stroke.json --force
