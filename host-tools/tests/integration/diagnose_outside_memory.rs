//! `hysteresis_memory` on physics-written outside-class plants
//! (`plant::outside`: Prandtl–Ishlinskii plays on a fractional generalized-
//! Maxwell base law, AR(1) noise, velocity from quantised displacement,
//! sinusoids, a multisine and drops). Evidence: physics-written plants,
//! tuning seeds of the memory fix (7240–7259), never a reporting seed.
use mre_host::diagnose::{diagnose, DiagnoseOptions};
use mre_host::diagnose_bench::outside::options;
use mre_host::plant::outside::case;
use mre_host::vocabulary::Effect;

/// Plays recover after a reversal only what the stroke before it displaced;
/// with a basis that predicted every minor reversal of the multisine with a
/// full turn-around, memory lost held out there (0.61×) and was never named
/// on these plants (both seeds `inconclusive`).
#[test]
fn memory_is_named_on_prandtl_ishlinskii_plays_outside_the_model_class() {
    let opts = options(&DiagnoseOptions::default());
    for seed in [7240, 7244] {
        let c = case(Effect::HysteresisMemory, seed).expect("campaign");
        let d = diagnose(&c.dataset, &opts).expect("diagnosis");
        let found: Vec<&str> = d.findings.iter().map(|f| f.effect.name()).collect();
        assert!(
            found.contains(&"hysteresis_memory"),
            "seed {seed}: {} {found:?} {:?}",
            d.verdict.verdict.name(),
            d.verdict.reasons
        );
    }
}
