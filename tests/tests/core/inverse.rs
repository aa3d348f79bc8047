//! The inverse model: lowest current that gives a force, exact on its segment.
use mre_algorithm::model::Branch;
use mre_algorithm::{Flags, Table};
use proptest::prelude::*;

fn paper() -> Table {
    Table::paper().expect("built-in table is valid")
}

// At x = 0.25 mm the paper's compression forces are not monotone in current
// (numpy.polyval of Table 4): 0 A 1549.7470, 0.5 A 1079.6784, 1 A 2725.5341,
// 1.5 A 2130.3091, 2 A 3430.2372 N.
const X_MM: f32 = 0.25;

#[test]
fn lowest_crossing_is_found_when_force_is_not_monotone() {
    let t = paper();
    // 2400 N is crossed three times (0.5–1, 1–1.5, 1.5–2 A); the lowest is on
    // 0.5–1 A at 0.5 + 0.5·(2400 − 1079.6784)/(2725.5341 − 1079.6784).
    let expected = 0.5 + 0.5 * (2400.0 - 1079.6784) / (2725.5341 - 1079.6784);
    let r = t.current_for_branch(X_MM, Branch::Compression, 2400.0);
    assert!(
        (r.current_a as f64 - expected).abs() < 1e-4,
        "{} vs {expected}",
        r.current_a
    );
    assert_eq!(r.flags, Flags::NONE);

    // 1300 N: 0 A already gives more; the force first falls to 1300 N on 0–0.5 A.
    let expected = 0.5 * (1549.7470 - 1300.0) / (1549.7470 - 1079.6784);
    let r = t.current_for_branch(X_MM, Branch::Compression, 1300.0);
    assert!(
        (r.current_a as f64 - expected).abs() < 1e-4,
        "{} vs {expected}",
        r.current_a
    );
}

#[test]
fn unreachable_targets_saturate_at_the_nearest_force() {
    let t = paper();
    let high = t.current_for_branch(X_MM, Branch::Compression, 10_000.0);
    assert_eq!(high.current_a, 2.0, "2 A gives the largest force, 3430 N");
    assert!(high.flags.contains(Flags::SATURATED_HIGH));
    let low = t.current_for_branch(X_MM, Branch::Compression, 500.0);
    assert_eq!(low.current_a, 0.5, "0.5 A gives the smallest force, 1080 N");
    assert!(low.flags.contains(Flags::SATURATED_LOW));
}

#[test]
fn a_tabulated_force_maps_back_to_its_current() {
    let t = paper();
    let f = t.force_on_branch(0.5, Branch::Extension, 1.5).force_n;
    let r = t.current_for_branch(0.5, Branch::Extension, f);
    let back = t.force_on_branch(0.5, Branch::Extension, r.current_a).force_n;
    assert!((back - f).abs() < 0.01);
    assert!(r.current_a <= 1.5 + 1e-6);
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(256))]
    /// Wherever a force is reachable (it was produced by some current), the
    /// inverse returns a current, no higher than that one, that reproduces it.
    #[test]
    fn inverse_of_forward_returns_the_requested_force(
        x_frac in 0.0f32..=1.0,
        current_a in 0.0f32..=2.0,
        compression in any::<bool>(),
    ) {
        let t = paper();
        let x_max = t.entries().iter().map(|e| e.x_max_mm).fold(f32::INFINITY, f32::min);
        let x_mm = x_frac * x_max;
        let branch = if compression { Branch::Compression } else { Branch::Extension };
        let target = t.force_on_branch(x_mm, branch, current_a).force_n;
        let r = t.current_for_branch(x_mm, branch, target);
        prop_assert!(!r.flags.intersects(Flags::SATURATED_HIGH | Flags::SATURATED_LOW));
        prop_assert!(r.current_a <= current_a + 1e-4, "{} > {}", r.current_a, current_a);
        let back = t.force_on_branch(x_mm, branch, r.current_a).force_n;
        // f32 rounding in the forces (≈1e-6 relative of ~1e4 N coefficients).
        prop_assert!((back - target).abs() <= 0.05 + 1e-5 * target.abs(), "{back} vs {target}");
    }
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(256))]
    /// Outside the stroke every entry shares, entries clamp x one by one; the
    /// inverse must still invert the forward model there, and say it clamped.
    #[test]
    fn inverse_of_forward_holds_where_entries_clamp(
        x_mm in 0.9f32..=1.6,
        current_a in 0.0f32..=2.0,
        compression in any::<bool>(),
    ) {
        let t = paper();
        let branch = if compression { Branch::Compression } else { Branch::Extension };
        let target = t.force_on_branch(x_mm, branch, current_a).force_n;
        let r = t.current_for_branch(x_mm, branch, target);
        prop_assert!(r.flags.contains(Flags::X_CLAMPED), "2 A's stroke ends at 0.8819 mm");
        prop_assert!(!r.flags.intersects(Flags::SATURATED_HIGH | Flags::SATURATED_LOW));
        let back = t.force_on_branch(x_mm, branch, r.current_a).force_n;
        prop_assert!((back - target).abs() <= 0.05 + 1e-5 * target.abs(), "{back} vs {target}");
    }
}
