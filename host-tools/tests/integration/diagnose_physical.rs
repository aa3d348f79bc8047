//! A physical final model (issue 26, point 5): beyond the covariate span
//! the fit has seen, predictions continue along the fit's tangent (never as
//! x⁴), sign constraints that hold a wrong-signed
//! coefficient at its bound, and searched-parameter intervals that are not
//! pinned to the search grid.
use crate::diagnose_support;

use diagnose_support::{dataset, law_n, Added, Campaign, SAMPLE_PERIOD_S};
use mre_host::dataset::Dataset;
use mre_host::diagnose::design::{Designs, Terms, Viscous};
use mre_host::diagnose::prepared::{prepare, FoldPlan};
use mre_host::diagnose::{diagnose, DiagnoseOptions};

const DT_S: f64 = 1e-3;
const NOISE_N: f64 = 2.0;

/// Two cycles of `x = A·sin(2πft)` with its exact velocity.
fn sinusoid(amp_mm: f64, freq_hz: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let w = 2.0 * std::f64::consts::PI * freq_hz;
    let n = (2.0 / freq_hz / DT_S) as usize;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * DT_S).collect();
    let x = t.iter().map(|t| amp_mm * (w * t).sin()).collect();
    let v = t.iter().map(|t| 1e-3 * amp_mm * w * (w * t).cos()).collect();
    (t, x, v)
}

/// A campaign of sinusoids at 0 and 1 A whose force is `force(x, v, I)` plus
/// Gaussian noise; `(amplitude mm, frequency Hz)` per test.
fn campaign(tests: &[(f64, f64)], force: impl Fn(f64, f64, f64) -> f64, seed: u64) -> Dataset {
    let per_sample = |x_mm: &[f64], v_m_s: &[f64], current_a: f64| -> Vec<f64> {
        x_mm.iter().zip(v_m_s).map(|(&x, &v)| force(x, v, current_a)).collect()
    };
    Campaign {
        name: "physical",
        currents_a: &[0.0, 1.0],
        tests,
        noise_n: NOISE_N,
        v_noise_m_s: 0.0,
        seed,
    }
    .build(sinusoid, per_sample)
}

/// A friction damper's force: a backbone that saturates at `F_s(I)` beyond a
/// few millimetres plus a yield force `f_y(I)` against the motion, so
/// |F| < F_s(I) + f_y(I) at every stroke.
fn saturating_n(x_mm: f64, v_m_s: f64, current_a: f64) -> f64 {
    let (f_s, f_y) = saturating_limits_n(current_a);
    f_s * (x_mm / 1.5).tanh() + f_y * (v_m_s / 0.005).tanh()
}

fn saturating_limits_n(current_a: f64) -> (f64, f64) {
    (800.0 * (1.0 + current_a), 150.0 * (1.0 + 2.0 * current_a))
}

#[test]
fn a_prediction_beyond_the_fitted_stroke_stays_within_the_trained_force_range() {
    // Trained on |x| ≤ 5 mm; one 10 mm test (the same frequency, so twice the
    // speed) held out of the fit.
    let ds = campaign(&[(2.0, 1.0), (3.5, 1.0), (5.0, 1.0), (10.0, 1.0)], saturating_n, 11);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 2 }, &[]).expect("prepared");
    let long = |i: usize| prep.recs[i].file.starts_with("a10");
    let train: Vec<usize> = (0..prep.recs.len()).filter(|&i| !long(i)).collect();
    for terms in [
        Terms::default(),
        Terms {
            viscous: Some(Viscous::Linear),
            ..Terms::default()
        },
    ] {
        let designs = Designs::build(&prep, &terms);
        let sol = designs.solve(&prep, &train).expect("solved");
        for i in (0..prep.recs.len()).filter(|&i| long(i)) {
            let rec = &prep.recs[i];
            // The bound, from the training data and the physics: a damper's
            // force at a stroke or speed it was not tested at lies no
            // further out than the force it reached in the tests (the law
            // saturates, as a real damper's force does: here |F| < F_s + f_y
            // everywhere, and the 5 mm tests reach within 5 % of it), with a
            // quarter of that as the margin for the fitted model's own misfit
            // beyond the span (the tangent the fit has at 5 mm and at the
            // fastest speed tested, continued to a state no test combined).
            let trained_max_n = train
                .iter()
                .filter(|&&j| prep.recs[j].current_a == rec.current_a)
                .flat_map(|&j| prep.recs[j].force_n.iter())
                .fold(0.0f64, |m, f| m.max(f.abs()));
            let (f_s, f_y) = saturating_limits_n(rec.current_a);
            assert!(trained_max_n < 1.05 * (f_s + f_y) && trained_max_n > 0.95 * (f_s + f_y));
            let bound_n = 1.25 * trained_max_n;
            let pred = designs.predict(&prep, i, &sol);
            let worst = pred.iter().fold(0.0f64, |m, p| m.max(p.abs()));
            assert!(
                worst <= bound_n,
                "{} ({terms:?}): |F| up to {worst:.0} N predicted, bound {bound_n:.0} N",
                rec.file
            );
            // Without the bound (the stored design, covariates as recorded)
            // the same fit extrapolates its quartic far outside.
            let unbounded = designs.recs[i].predict(&sol.beta);
            let unbounded_worst = unbounded.iter().fold(0.0f64, |m, p| m.max(p.abs()));
            assert!(
                unbounded_worst > 2.0 * bound_n,
                "{}: unbounded only {unbounded_worst:.0} N",
                rec.file
            );
            // Not bounded by predicting nothing: the 10 mm test's force
            // (≈ F_s + f_y at its ends) is reached.
            assert!(worst > 0.8 * trained_max_n, "{}: at most {worst:.0} N", rec.file);
        }
    }
}

#[test]
fn beyond_the_fitted_stroke_a_linear_spring_continues_as_a_spring() {
    // F = k(I)·x: its tangent at the span's edge is the law itself, so the
    // 10 mm test held out of a fit on |x| ≤ 5 mm is predicted as well as the
    // noise allows. Holding x at the span's edge instead would miss by
    // k·(10 − 5) mm = 500–1000 N at the 10 mm test's ends.
    let spring = |x: f64, _v: f64, current_a: f64| 100.0 * (1.0 + current_a) * x;
    let ds = campaign(&[(2.0, 1.0), (3.5, 1.0), (5.0, 1.0), (10.0, 1.0)], spring, 12);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 2 }, &[]).expect("prepared");
    let long = |i: usize| prep.recs[i].file.starts_with("a10");
    let train: Vec<usize> = (0..prep.recs.len()).filter(|&i| !long(i)).collect();
    let designs = Designs::build(&prep, &Terms::default());
    let sol = designs.solve(&prep, &train).expect("solved");
    for i in (0..prep.recs.len()).filter(|&i| long(i)) {
        let rec = &prep.recs[i];
        let pred = designs.predict(&prep, i, &sol);
        let truth: Vec<f64> = rec.x_mm.iter().map(|&x| spring(x, 0.0, rec.current_a)).collect();
        let rms = |e: &mut dyn Iterator<Item = f64>| {
            let (sum, n) = e.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
            (sum / n as f64).sqrt()
        };
        let error_n = rms(&mut pred.iter().zip(&truth).map(|(p, t)| p - t));
        let force_rms_n = rms(&mut truth.iter().copied());
        // The slope at 5 mm is fitted from noisy data (σ = 2 N on ~10³ N):
        // within 2 % of the force's RMS (≈ 700–1400 N) over the 10 mm test.
        assert!(
            error_n < 0.02 * force_rms_n,
            "{}: RMS error {error_n:.1} N against force RMS {force_rms_n:.0} N",
            rec.file
        );
    }
}

/// The support's law plus `c(I)·v` with the given damping per current.
fn with_damping(c_0a: f64, c_1a: f64) -> impl Fn(f64, f64, f64) -> f64 {
    move |x, v, current_a| law_n(x, v > 0.0, current_a) + if current_a == 0.0 { c_0a } else { c_1a } * v
}

#[test]
fn a_wrong_signed_damping_coefficient_is_held_at_zero_and_said() {
    // Three speeds per current, so c(I)·v is separable from the quartics.
    let tests = [(2.0, 1.0), (2.0, 4.0), (3.0, 2.0)];
    // c(0 A) = +3000 N·s/m, c(1 A) = −2000 N·s/m: the unconstrained least
    // squares recovers the −2000 (the law is inside the model class).
    let ds = campaign(&tests, with_damping(3000.0, -2000.0), 5);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 2 }, &[]).expect("prepared");
    let terms = Terms {
        viscous: Some(Viscous::Linear),
        ..Terms::default()
    };
    let designs = Designs::build(&prep, &terms);
    let sol = designs.solve(&prep, &prep.fit_indices()).expect("solved");
    let at = designs
        .layout
        .at(mre_host::vocabulary::Effect::ViscousDamping, 0)
        .expect("viscous columns");
    // Currents in table order: 0 A, 1 A.
    assert_eq!(sol.beta[at + 1], 0.0, "c(1 A) held at its bound");
    assert_eq!(sol.at_bound, vec![at + 1]);
    // The 0 A tests share no column with the 1 A ones, so c(0 A) is the
    // unconstrained estimate: the true 3000 within 3 %.
    assert!((sol.beta[at] - 3000.0).abs() < 90.0, "c(0 A) = {}", sol.beta[at]);
    // The parameter says it is held at its bound.
    let params = mre_host::diagnose::parameters::with_intervals(
        &prep,
        mre_host::vocabulary::Effect::ViscousDamping,
        &terms,
        &sol,
        &[(terms, vec![0.0; prep.recs.len()])],
        200,
        1,
    )
    .expect("intervals");
    assert!(params["c_at_1a_n_s_per_m"].at_bound);
    assert!(!params["c_at_0a_n_s_per_m"].at_bound);
    // Every resample is fitted under the same constraint.
    assert!(params["c_at_1a_n_s_per_m"].ci95[0] >= 0.0);

    // Both negative: the term is no term, and the dissipation rule drops it.
    let ds = campaign(&tests, with_damping(-1500.0, -2000.0), 6);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 2 }, &[]).expect("prepared");
    let designs = Designs::build(&prep, &terms);
    let sol = designs.solve(&prep, &prep.fit_indices()).expect("solved");
    assert_eq!((sol.beta[at], sol.beta[at + 1]), (0.0, 0.0));
    let viscous = mre_host::diagnose::terms::of(mre_host::vocabulary::Effect::ViscousDamping).unwrap();
    assert!(!viscous.physical(&designs.layout, &terms, &sol));
}

#[test]
fn a_delay_off_the_grid_gets_an_interval_around_it_not_pinned_to_grid_points() {
    // 3.37 samples: between the refined grid's quarter samples 3.25 and 3.5.
    let tau_s = 3.37 * SAMPLE_PERIOD_S;
    let d = diagnose(&dataset(Added::Delay { tau_s }, 3), &DiagnoseOptions::default()).expect("diagnosis");
    let f = d
        .findings
        .iter()
        .find(|f| f.effect.name() == "sensor_delay")
        .expect("the delay is found");
    let p = &f.parameters["tau_s"];
    assert!(p.ci95[0] <= tau_s && tau_s <= p.ci95[1], "interval {:?}", p.ci95);
    let quarter = 0.25 * SAMPLE_PERIOD_S;
    for end in p.ci95 {
        let steps = end / quarter;
        assert!(
            (steps - steps.round()).abs() > 1e-3,
            "end {end} is a grid point ({steps} quarter samples)"
        );
    }
    // Narrower than one grid step: the data pin the delay that well.
    assert!(p.ci95[1] - p.ci95[0] < quarter, "interval {:?}", p.ci95);
}
