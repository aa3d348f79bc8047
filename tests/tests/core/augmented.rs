//! The version 2 (augmented) model: per-current viscous terms and the
//! saturating interpolation variable, forward and inverse, with no panic.
use mre_algorithm::model::Branch;
use mre_algorithm::table::ModelTerms;
use mre_algorithm::{CurrentEntry, Flags, Quartic, Table};
use proptest::prelude::*;

/// Two linear "quartics": 0 A gives 100·x N, 1 A gives 300·x N (both
/// branches), fitted on 0–10 mm.
fn linear_entries() -> [CurrentEntry; 2] {
    [linear_entry(0.0, 100.0), linear_entry(1.0, 300.0)]
}

/// An entry whose force is `k·x` N on both branches, fitted on 0–10 mm.
fn linear_entry(current_a: f32, k: f32) -> CurrentEntry {
    CurrentEntry {
        current_a,
        compression: Quartic::new([0.0, 0.0, 0.0, k, 0.0]),
        extension: Quartic::new([0.0, 0.0, 0.0, k, 0.0]),
        x_min_mm: 0.0,
        x_max_mm: 10.0,
    }
}

fn augmented() -> Table {
    let mut terms = ModelTerms {
        saturation_current_a: 0.5,
        ..ModelTerms::NONE
    };
    terms.viscous_n_s_per_m[0] = 10.0;
    terms.viscous_n_s_per_m[1] = 50.0;
    Table::with_terms(&linear_entries(), terms).unwrap()
}

#[test]
fn forward_interpolates_in_tanh_and_adds_the_viscous_term() {
    // By hand: at x = 2 mm, v = 1 m/s, I = 0.5 A: the entries give
    // 100·2 + 10·1 = 210 N and 300·2 + 50·1 = 650 N; the interpolation
    // fraction is tanh(0.5/0.5)/tanh(1/0.5) = 0.761594/0.964028 = 0.790008,
    // so F = 210 + 0.790008·440 = 557.603 N (linear in I it would be 430 N).
    let t = augmented();
    let f = t.force(2.0, 1.0, 0.5);
    assert_eq!(f.flags, Flags::NONE);
    assert!((f.force_n - 557.603).abs() < 0.5, "{}", f.force_n);
    // At rest the viscous term is gone: 200 + 0.790008·400 = 516.003 N.
    let at_rest = t.force_on_branch(2.0, Branch::Compression, 0.5).force_n;
    assert!((at_rest - 516.003).abs() < 0.5, "{at_rest}");
    // On a tabulated current the interpolation is exact.
    assert_eq!(t.force(2.0, 1.0, 1.0).force_n, 650.0);
    assert_eq!(t.force(2.0, -1.0, 0.0).force_n, 190.0);
}

#[test]
fn inverse_undoes_tanh_and_the_viscous_term() {
    let t = augmented();
    let r = t.current_for_branch_v(2.0, 1.0, Branch::Compression, 557.603);
    assert_eq!(r.flags, Flags::NONE);
    assert!((r.current_a - 0.5).abs() < 2e-3, "{}", r.current_a);
    // Tabulated forces map back to the tabulated currents exactly.
    assert_eq!(
        t.current_for_branch_v(2.0, 1.0, Branch::Compression, 650.0).current_a,
        1.0
    );
    assert_eq!(
        t.current_for_branch_v(2.0, 1.0, Branch::Compression, 210.0).current_a,
        0.0
    );
    // Beyond 1 A's force: saturated at 1 A.
    let high = t.current_for_branch_v(2.0, 1.0, Branch::Compression, 700.0);
    assert_eq!(high.current_a, 1.0);
    assert!(high.flags.contains(Flags::SATURATED_HIGH));
}

/// The linear entries with a saturation current `i_s` and no viscous term.
fn saturating(i_s: f32) -> Table {
    let terms = ModelTerms {
        saturation_current_a: i_s,
        ..ModelTerms::NONE
    };
    Table::with_terms(&linear_entries(), terms).unwrap()
}

#[test]
fn saturated_inverse_maps_back_through_atanh_on_narrow_and_wide_segments() {
    // At x = 2 mm the entries give 200 N (0 A) and 600 N (1 A); a target F
    // lies at t = (F − 200)/400 of the segment, w = t·tanh(1/I_s) and
    // I = I_s·atanh(w) (std, f64). I_s = 2.5 A keeps the addition-theorem
    // argument below 0.4 (the series); I_s = 0.5 A takes the logarithm.
    for i_s in [2.5f64, 0.5] {
        let t = saturating(i_s as f32);
        for target in [210.0f64, 300.0, 400.0, 500.0, 590.0] {
            let frac = (target - 200.0) / 400.0;
            let expected = i_s * (frac * (1.0 / i_s).tanh()).atanh();
            let r = t.current_for_branch(2.0, Branch::Compression, target as f32);
            assert_eq!(r.flags, Flags::NONE);
            assert!(
                (f64::from(r.current_a) - expected).abs() < 2e-6,
                "I_s {i_s}, {target} N: {} vs {expected}",
                r.current_a
            );
        }
    }
}

#[test]
fn a_version_1_table_is_the_paper_model_whatever_the_velocity() {
    let plain = Table::new(&linear_entries()).unwrap();
    assert_eq!(plain.terms(), &ModelTerms::NONE);
    // 100·2 + 0.5·(600 − 200) = 400 N at any velocity.
    assert_eq!(plain.force(2.0, 3.0, 0.5).force_n, 400.0);
    assert_eq!(
        plain
            .current_for_branch_v(2.0, 3.0, Branch::Compression, 400.0)
            .current_a,
        0.5
    );
}

fn terms_strategy() -> impl Strategy<Value = ModelTerms> {
    (
        prop::array::uniform8(-500.0f32..2000.0),
        prop_oneof![Just(0.0f32), 0.3f32..5.0],
        0.0f32..0.01,
        0.0f32..0.01,
    )
        .prop_map(|(viscous, i_s, delay, tau)| ModelTerms {
            viscous_n_s_per_m: viscous,
            saturation_current_a: i_s,
            sensor_delay_s: delay,
            coil_tau_s: tau,
        })
}

fn generated_with(terms: ModelTerms) -> Table {
    Table::with_terms(&mre_algorithm::generated_table::GENERATED_ENTRIES, terms).unwrap()
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(256))]
    /// A force produced by some current is given back by the inverse: the
    /// current it returns (no higher than the one that made it) reproduces
    /// it, with the viscous term and the saturating variable in play.
    #[test]
    fn augmented_inverse_of_forward_returns_the_force(
        terms in terms_strategy(),
        x_mm in 0.0f32..3.9,
        v_m_s in -3.0f32..3.0,
        current_a in 0.0f32..=2.0,
        compression in any::<bool>(),
    ) {
        let t = generated_with(terms);
        let branch = if compression { Branch::Compression } else { Branch::Extension };
        let target = t.force_on_branch_v(x_mm, v_m_s, branch, current_a).force_n;
        let r = t.current_for_branch_v(x_mm, v_m_s, branch, target);
        prop_assert!(!r.flags.intersects(Flags::SATURATED_HIGH | Flags::SATURATED_LOW), "{:?}", r);
        prop_assert!(r.current_a <= current_a + 2e-3, "{} > {}", r.current_a, current_a);
        let back = t.force_on_branch_v(x_mm, v_m_s, branch, r.current_a).force_n;
        // micromath's tanh/atanh agree to ~1e-4 relative, so the current is
        // off by that much of its segment and the force by that much of the
        // segment's force span; the 0–2 A span bounds every segment's. Allow
        // 1e-3 of it (or of the target, if larger) plus f32 rounding.
        let span_n = (t.force_on_branch_v(x_mm, v_m_s, branch, 2.0).force_n
            - t.force_on_branch_v(x_mm, v_m_s, branch, 0.0).force_n)
            .abs();
        let tol_n = 1.0 + 1e-3 * span_n.max(target.abs());
        prop_assert!((back - target).abs() <= tol_n, "{back} vs {target} (tolerance {tol_n})");
    }

    /// Any input, finite or not, gives a finite force and a current within
    /// the table's range: no panic, no NaN.
    #[test]
    fn augmented_model_is_total(
        terms in terms_strategy(),
        x_mm in prop::num::f32::ANY,
        v_m_s in prop::num::f32::ANY,
        current_a in prop::num::f32::ANY,
        target_n in prop::num::f32::ANY,
        compression in any::<bool>(),
    ) {
        let t = generated_with(terms);
        let branch = if compression { Branch::Compression } else { Branch::Extension };
        let f = t.force(x_mm, v_m_s, current_a);
        prop_assert!(f.force_n.is_finite(), "{f:?}");
        let r = t.current_for_branch_v(x_mm, v_m_s, branch, target_n);
        prop_assert!(r.current_a.is_finite() && (0.0..=2.0).contains(&r.current_a), "{r:?}");
    }
}

#[test]
fn a_version_2_table_uploads_to_the_pil_firmware_with_its_terms() {
    use mre_algorithm::control::ControlConfig;
    use mre_protocol::frame::{decode_config, encode_config, CONFIG_MAX_WORDS};
    let table = augmented();
    let cfg = ControlConfig::at_rate(10_000).unwrap();
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(&table, &cfg, &mut words);
    // The version 1 layout (2 + 13 per current + 13 law + 7 control) plus
    // I_s, delay, τ and one viscous term per current.
    assert_eq!(n, 2 + 13 * 2 + (3 + 2) + 13 + 7);
    let (back, _) = decode_config(&words[..n]).unwrap();
    assert_eq!(back, table);
    assert_eq!(back.terms().viscous_n_s_per_m[1], 50.0);
}
