//! The saturated inverse's map from a segment fraction back to current
//! (firmware/algorithm/src/saturation.rs): where a segment is fitted, the f32
//! polynomial lies within its stated bound of the exact map
//! `i0 + I_s·(atanh(w0 + t·Δw) − atanh(w0))`, computed here in f64 with
//! std's atanh (independent of the core's math), on a fine grid of t.
use mre_algorithm::model::interpolation_variable;
use mre_algorithm::saturation::{SegmentMap, TOLERANCE_PER_A};
use mre_algorithm::table::ModelTerms;
use mre_algorithm::Table;
use proptest::prelude::*;

/// The most |polynomial − exact| over t = k/4096 (k = 1 … 4095) and the
/// ends' neighbours, for the segment from current `i0` to `i1`.
fn worst_error(map: &SegmentMap, w0: f32, w1: f32, i_s: f32, i0: f32) -> f64 {
    let dw = f64::from(w1 - w0);
    let exact =
        |t: f32| f64::from(i0) + f64::from(i_s) * ((f64::from(w0) + f64::from(t) * dw).atanh() - f64::from(w0).atanh());
    let mut ts: Vec<f32> = (1..4096).map(|k| k as f32 / 4096.0).collect();
    ts.extend([f32::MIN_POSITIVE, 1.0e-6, 1.0 - f32::EPSILON / 2.0, 1.0]);
    ts.iter()
        .map(|&t| (f64::from(map.eval(i0, t)) - exact(t)).abs())
        .fold(0.0, f64::max)
}

fn knots(currents: &[f32], i_s: f32) -> Vec<f32> {
    currents.iter().map(|c| interpolation_variable(*c, i_s)).collect()
}

#[test]
fn the_flown_currents_at_one_and_a_half_amperes_are_fitted_within_their_bound() {
    // The generated table's currents with ModelTerms::EVERY_TERM's I_s.
    let currents = [0.0f32, 0.5, 1.0, 1.5, 2.0];
    let i_s = 1.5;
    let w = knots(&currents, i_s);
    for k in 0..4 {
        let fit = SegmentMap::fit(w[k], w[k + 1], i_s, currents[k], currents[k + 1])
            .unwrap_or_else(|| panic!("segment {k} not fitted"));
        let err = worst_error(&fit.map, w[k], w[k + 1], i_s, currents[k]);
        assert!(
            err <= f64::from(fit.bound_a),
            "segment {k}: error {err:e} > bound {:e}",
            fit.bound_a
        );
        // A few f32 ulps of 2 A (2.4e-7 each).
        assert!(err <= 3.0e-7, "segment {k}: error {err:e}");
        assert!(
            fit.bound_a <= TOLERANCE_PER_A * 2.0,
            "segment {k}: bound {:e}",
            fit.bound_a
        );
        assert!(
            fit.map.eval(currents[k], 1.0) >= currents[k + 1],
            "segment {k} short of its upper current"
        );
    }
    // The table builds the same maps.
    let table = Table::with_terms(
        &mre_algorithm::generated_table::GENERATED_ENTRIES,
        ModelTerms::EVERY_TERM,
    )
    .unwrap();
    for k in 0..4 {
        let fit = SegmentMap::fit(w[k], w[k + 1], i_s, currents[k], currents[k + 1]).unwrap();
        assert_eq!(*table.segment_map(k), fit.map);
    }
}

#[test]
fn a_segment_too_wide_for_the_fit_keeps_the_exact_map() {
    // 0 → 1 A at I_s = 0.5 A: w from 0 to tanh 2 = 0.964, ρ = 0.93.
    let w1 = interpolation_variable(1.0, 0.5);
    assert!(SegmentMap::fit(0.0, w1, 0.5, 0.0, 1.0).is_none());
    // A linear table has no maps at all.
    let t = Table::new(&mre_algorithm::generated_table::GENERATED_ENTRIES).unwrap();
    assert!(!t.segment_map(0).fitted);
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(400))]
    /// Any segment the fit accepts is within its bound, the bound within
    /// the tolerance, and the polynomial never below i0.
    #[test]
    fn every_fitted_segment_is_within_its_bound(
        i_s in 0.2f32..20.0,
        lo in -5.0f32..5.0,
        width in 0.01f32..3.0,
    ) {
        let (i0, i1) = (lo, lo + width);
        let (w0, w1) = (interpolation_variable(i0, i_s), interpolation_variable(i1, i_s));
        prop_assume!(w0 < w1 && w0.abs() < 1.0 && w1.abs() < 1.0);
        if let Some(fit) = SegmentMap::fit(w0, w1, i_s, i0, i1) {
            let err = worst_error(&fit.map, w0, w1, i_s, i0);
            prop_assert!(err <= f64::from(fit.bound_a), "error {err:e} > bound {:e}", fit.bound_a);
            prop_assert!(fit.bound_a <= TOLERANCE_PER_A * i1.abs().max(1.0));
            for k in 1..=64 {
                let t = k as f32 / 64.0;
                prop_assert!(fit.map.eval(i0, t) >= i0, "below i0 at t = {t}");
            }
            // The inverse clamps to i1: a tabulated force's t = 1 gives i1.
            prop_assert!(fit.map.eval(i0, 1.0) >= i1);
        }
    }
}
