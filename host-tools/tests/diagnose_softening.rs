//! Stress softening's held-out prediction stays inside the run-order span
//! its training recordings cover.
mod diagnose_support;
use diagnose_support::{dataset, Added};
use mre_host::diagnose::design::{Designs, SofteningLaw, Terms};
use mre_host::diagnose::prepared::{prepare, FoldPlan};

/// The law's covariate, by hand: g = 1 − exp(−(n − 1)/n0).
fn g(n: f64, n0: f64) -> f64 {
    1.0 - (-(n - 1.0) / n0).exp()
}

#[test]
fn a_held_out_test_before_every_training_test_is_predicted_at_the_earliest_trained_level() {
    let n0 = 3.0;
    let prep = prepare(
        &dataset(Added::Softening { delta: 0.2, n0 }, 1),
        &FoldPlan::Stratified { k: 3 },
        &[],
    )
    .expect("prepared");
    let first = prep
        .recs
        .iter()
        .position(|r| r.sequence == Some(1.0))
        .expect("run-order test 1");
    let fold = prep.recs[first].fold.expect("a fit recording");
    let train = prep.training_for(fold);
    let d = Designs::build(
        &prep,
        &Terms {
            softening: Some(SofteningLaw::Sequence { n0 }),
            ..Terms::default()
        },
    );
    let sol = d.solve(&prep, &train).expect("solved");
    // The earliest training test, from the run orders themselves.
    let n_min = train
        .iter()
        .map(|&i| prep.recs[i].sequence.expect("run order"))
        .fold(f64::INFINITY, f64::min);
    assert!(n_min >= 2.0, "test 1 is held out");
    let g_min = g(n_min, n0);
    // The unsoftened quartics' force, scaled at g_min, not at test 1's g = 0.
    let expected: Vec<f64> = d.recs[first]
        .predict(&sol.beta)
        .iter()
        .map(|q| q * (1.0 - sol.delta * g_min))
        .collect();
    let got = d.predict(&prep, first, &sol);
    let peak = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (e, p) in expected.iter().zip(&got) {
        assert!((e - p).abs() <= 1e-9 * peak, "{e} vs {p}");
    }
    // The clamp is what the check sees: the depth found is far from zero,
    // so extrapolating to g = 0 would differ by Δ·g_min of the force.
    assert!(sol.delta.abs() * g_min > 0.02, "Δ {} g_min {g_min}", sol.delta);
    // Inside the span nothing is clamped: a training test's level is its own.
    let inside = train[0];
    let n = prep.recs[inside].sequence.expect("run order");
    let own: Vec<f64> = d.recs[inside]
        .predict(&sol.beta)
        .iter()
        .map(|q| q * (1.0 - sol.delta * g(n, n0)))
        .collect();
    for (e, p) in own.iter().zip(&d.predict(&prep, inside, &sol)) {
        assert!((e - p).abs() <= 1e-9 * peak.max(1.0), "{e} vs {p}");
    }
}
