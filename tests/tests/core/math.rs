//! The core's own exp/ln/tanh/atanh (firmware/algorithm/src/math.rs) against std's
//! f64 functions: the saturation term's forward and inverse rely on them
//! agreeing to ~1e-6 without a refinement step.
use mre_algorithm::math;
use proptest::prelude::*;

proptest! {
    #![proptest_config(mre_tests::proptest_config(256))]
    #[test]
    fn exp_is_within_a_few_ulps_of_std(x in -80.0f32..80.0) {
        let exact = f64::from(x).exp();
        let got = f64::from(math::exp(x));
        // Cephes' 2^f is good to ~2e-7; x·log2 e rounds to 2^-24 of |x|·1.44,
        // which moves e^x by that much relative.
        let tol = 4e-7 + f64::from(x.abs()) * 1.5 * 6e-8;
        prop_assert!((got / exact - 1.0).abs() <= tol, "exp({x}) = {got}, std {exact}");
    }

    #[test]
    fn ln_is_within_a_few_ulps_of_std(y in 1.0e-30f32..1.0e30) {
        let exact = f64::from(y).ln();
        let got = f64::from(math::ln(y));
        prop_assert!((got - exact).abs() <= 2e-7 * exact.abs().max(1.0), "ln({y}) = {got}, std {exact}");
    }

    #[test]
    fn atanh_undoes_tanh(u in -4.0f32..4.0) {
        // tanh flattens: at |u| = 4 one ulp of w near 1 is 6e-8 / (1 − w²) ≈ 1e-4 of u.
        let back = math::atanh(math::tanh(u));
        let w = f64::from(u).tanh();
        let tol = 2e-6 + 3.0 * 6e-8 / (1.0 - w * w);
        prop_assert!((f64::from(back) - f64::from(u)).abs() <= tol, "atanh(tanh({u})) = {back}");
    }
}

#[test]
fn exp_and_tanh_saturate_without_overflow() {
    assert!(math::exp(1.0e6).is_finite());
    assert_eq!(math::tanh(100.0), 1.0);
    assert_eq!(math::tanh(-100.0), -1.0);
    assert_eq!(math::tanh(0.0), 0.0);
    assert_eq!(math::exp(0.0), 1.0);
}
