//! The turn-around memory also covers a test that starts from rest: the
//! material leaves standstill as it leaves a turn-around, from a relaxed
//! state. A Dahl law (`plant::base_laws`, z = 0 at the first sample) makes
//! that exact: from rest the force lies `G·f_y·e^{−d/x_y}` off its steady
//! branch after a travel d, after a reversal twice that, so a memory basis at
//! δ = x_y with its own coefficient for the start (relaxing over 2.5 % of the
//! 20 mm stroke span, also x_y) fits the first quarter cycle to the noise; without it that stretch is predicted on the steady
//! branch, G·f_y (150–900 N here) off at the start.
use crate::diagnose_support;

use mre_host::dataset::Dataset;
use mre_host::diagnose::design::{memory_feature_on_branches, Designs, Terms, START_FROM_REST};
use mre_host::diagnose::prepared::{prepare, FoldPlan};
use mre_host::plant::base_laws::{Hysteresis, HystereticLaw};

const DT_S: f64 = 0.002;
const NOISE_N: f64 = 1.0;

/// `x = −A·cos(ω(t + t0))`: starts at the −A end, moving at 5 % of the peak
/// speed (sin 0.05), three cycles.
fn from_rest(amp_mm: f64, freq_hz: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let w = 2.0 * std::f64::consts::PI * freq_hz;
    let t0 = 0.05 / w;
    let n = (3.0 / freq_hz / DT_S) as usize;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * DT_S).collect();
    let x = t.iter().map(|t| -amp_mm * (w * (t + t0)).cos()).collect();
    let v = t.iter().map(|t| 1e-3 * amp_mm * w * (w * (t + t0)).sin()).collect();
    (t, x, v)
}

fn dahl_from_rest(seed: u64) -> (Dataset, HystereticLaw) {
    let law = HystereticLaw::example(Hysteresis::Dahl, 0.0);
    let tests = [(2.0, 2.0), (5.0, 1.0), (10.0, 0.5)];
    let forces = |x_mm: &[f64], v_m_s: &[f64], current_a: f64| law.forces_n(x_mm, v_m_s, current_a);
    let ds = diagnose_support::Campaign {
        name: "dahl from rest",
        currents_a: &[0.0, 1.0],
        tests: &tests,
        noise_n: NOISE_N,
        v_noise_m_s: 0.0,
        seed,
    }
    .build(from_rest, forces);
    (ds, law)
}

#[test]
fn a_start_from_rest_is_anchored_and_a_running_start_is_not() {
    let (t, x, v) = from_rest(2.0, 2.0);
    assert!(v[0] <= START_FROM_REST * 2.0 * std::f64::consts::PI * 2.0 * 2.0e-3);
    let (feature, compressing) = memory_feature_on_branches(&t, &x, &v, 0.0);
    // Before the first reversal (at +A, half a cycle later) the
    // anchor is the first sample, flagged as the start from rest.
    let a = feature[10].expect("anchored from the first sample");
    assert!(a.from_rest && compressing[10]);
    assert!((a.x_r_mm - x[0]).abs() < 1e-12 && (a.distance_mm - (x[10] - x[0])).abs() < 1e-12);
    // After the reversal at the +A end: an ordinary turn-around near +2 mm.
    let half = (0.25 / DT_S) as usize + 20;
    let a = feature[half].expect("after the reversal");
    assert!(!a.from_rest && (a.x_r_mm - 2.0).abs() < 0.01, "x_r {}", a.x_r_mm);

    // A sinusoid already running (x = A·sin ωt starts at its peak speed).
    let w = 2.0 * std::f64::consts::PI * 2.0;
    let xs: Vec<f64> = t.iter().map(|t| 2.0 * (w * t).sin()).collect();
    let vs: Vec<f64> = t.iter().map(|t| 2e-3 * w * (w * t).cos()).collect();
    let (feature, _) = memory_feature_on_branches(&t, &xs, &vs, 0.0);
    assert!(feature[10].is_none(), "no anchor before the first reversal");
}

#[test]
fn the_first_quarter_cycle_of_a_dahl_law_from_rest_is_fitted_to_the_noise() {
    let (ds, law) = dahl_from_rest(7);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 3 }, &[]).expect("prepared");
    let terms = Terms {
        memory_mm: Some(law.x_y_mm),
        ..Terms::default()
    };
    let designs = Designs::build(&prep, &terms);
    let fit = prep.fit_indices();
    let sol = designs.solve(&prep, &fit).expect("solved");
    for &i in &fit {
        let rec = &prep.recs[i];
        let pred = designs.predict(&prep, i, &sol);
        let mask = &designs.recs[i].mask;
        // Samples before the first sign change of v: the travel from rest.
        let first = (1..rec.len()).find(|&t| (rec.v_m_s[t] > 0.0) != (rec.v_m_s[t - 1] > 0.0));
        let first = first.expect("the test reverses");
        let scored: Vec<f64> = (0..first)
            .filter(|&t| mask[t])
            .map(|t| rec.force_n[t] - pred[t])
            .collect();
        assert!(scored.len() > first / 2, "{}: start mostly scored", rec.file);
        let rms = (scored.iter().map(|r| r * r).sum::<f64>() / scored.len() as f64).sqrt();
        // The steady-branch error at the start is G·f_y = 150 N at 0 A; the
        // quartic's own misfit of the cubic backbone stays a few newtons.
        assert!(rms < 4.0 * NOISE_N, "{}: start residual {rms:.2} N", rec.file);
    }
}
