//! The core's model and inverse over arbitrary valid tables, not only the
//! paper's: 1–8 currents, coefficients up to ±2·10⁴, any stroke. Expected
//! values come from the definitions (quartic in f64, linear interpolation),
//! not from the core.
use mre_algorithm::model::Branch;
use mre_algorithm::table::{CurrentEntry, Quartic, TableImage, MAX_CURRENTS};
use mre_algorithm::{Flags, Table};
use proptest::prelude::*;

// Coefficients up to 2e3 keep |F| below validation's 1e9 N bound over any
// stroke this generator draws (x ≤ 21 mm: 2e3·(21⁴ + 21³ + …) ≈ 4e8 N).
fn quartic() -> impl Strategy<Value = Quartic> {
    proptest::array::uniform5(-2.0e3f32..2.0e3).prop_map(Quartic::new)
}

/// 1–8 entries with strictly ascending currents and a positive stroke.
fn table() -> impl Strategy<Value = Table> {
    proptest::collection::vec(
        (0.01f32..1.0, quartic(), quartic(), -1.0f32..1.0, 0.05f32..20.0),
        1..=MAX_CURRENTS,
    )
    .prop_map(|rows| {
        let mut current_a = -0.5;
        let entries: Vec<CurrentEntry> = rows
            .into_iter()
            .map(|(step_a, compression, extension, x_min_mm, width_mm)| {
                current_a += step_a;
                CurrentEntry {
                    current_a,
                    compression,
                    extension,
                    x_min_mm,
                    x_max_mm: x_min_mm + width_mm,
                }
            })
            .collect();
        Table::new(&entries).expect("ascending currents and positive strokes are valid")
    })
}

/// The quartic in f64 from its definition.
fn quartic_f64(q: &Quartic, x: f64) -> f64 {
    q.coeffs
        .iter()
        .rev()
        .enumerate()
        .map(|(p, &c)| c as f64 * x.powi(p as i32))
        .sum()
}

/// A bound on f32 rounding of a Horner evaluation at `x`: a few ulps of the
/// largest term.
fn horner_tol(q: &Quartic, x: f64) -> f64 {
    let largest = q
        .coeffs
        .iter()
        .rev()
        .enumerate()
        .map(|(p, &c)| (c as f64 * x.powi(p as i32)).abs())
        .fold(1.0, f64::max);
    largest * 8.0 * f32::EPSILON as f64
}

fn branch(compression: bool) -> Branch {
    if compression {
        Branch::Compression
    } else {
        Branch::Extension
    }
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(1000))]

    #[test]
    fn any_input_gives_a_finite_force(t in table(), x in proptest::num::f32::ANY, v in proptest::num::f32::ANY, i in proptest::num::f32::ANY) {
        let r = t.force(x, v, i);
        prop_assert!(r.force_n.is_finite());
    }

    #[test]
    fn at_a_tabulated_current_the_force_is_that_entrys_quartic(t in table(), k in 0usize..MAX_CURRENTS, frac in 0.0f64..=1.0, compression in any::<bool>()) {
        let e = t.entries()[k % t.entries().len()];
        let x = e.x_min_mm as f64 + frac * (e.x_max_mm - e.x_min_mm) as f64;
        let x32 = x as f32;
        let q = if compression { e.compression } else { e.extension };
        let got = t.force_on_branch(x32, branch(compression), e.current_a).force_n as f64;
        let want = quartic_f64(&q, x32 as f64);
        prop_assert!((got - want).abs() <= horner_tol(&q, x32 as f64), "{got} vs {want}");
    }

    #[test]
    fn between_currents_the_force_is_the_linear_interpolation(t in table(), k in 0usize..MAX_CURRENTS, s in 0.0f32..=1.0, x in -1.0f32..21.0, compression in any::<bool>()) {
        let e = t.entries();
        prop_assume!(e.len() >= 2);
        let k = k % (e.len() - 1);
        let (lo, hi) = (e[k].current_a, e[k + 1].current_a);
        let c = lo + s * (hi - lo);
        prop_assume!(c >= lo && c <= hi);
        let b = branch(compression);
        let f_lo = t.force_on_branch(x, b, lo).force_n as f64;
        let f_hi = t.force_on_branch(x, b, hi).force_n as f64;
        let w = ((c - lo) / (hi - lo)) as f64;
        let want = f_lo + w * (f_hi - f_lo);
        let got = t.force_on_branch(x, b, c).force_n as f64;
        let tol = 16.0 * f32::EPSILON as f64 * f_lo.abs().max(f_hi.abs()).max(1.0);
        prop_assert!((got - want).abs() <= tol, "{got} vs {want} (lo {f_lo}, hi {f_hi})");
    }

    #[test]
    fn outside_the_current_range_the_current_is_clamped_and_flagged(t in table(), x in 0.0f32..1.0, above in any::<bool>()) {
        let (lo, hi) = t.current_range_a();
        let (edge, outside) = if above { (hi, hi + 1.0) } else { (lo, lo - 1.0) };
        let r = t.force_on_branch(x, Branch::Compression, outside);
        prop_assert!(r.flags.contains(Flags::CURRENT_CLAMPED));
        prop_assert_eq!(r.force_n, t.force_on_branch(x, Branch::Compression, edge).force_n);
    }

    /// Where a force was produced by some current, the inverse finds a
    /// current no higher that reproduces it (to f32 rounding of the forces).
    #[test]
    fn inverse_of_forward_returns_the_requested_force(t in table(), frac in 0.0f32..=1.0, s in 0.0f32..=1.0, compression in any::<bool>()) {
        let (lo, hi) = t.current_range_a();
        let current_a = lo + s * (hi - lo);
        let x_mm = t.entries()[0].x_min_mm + frac * (t.entries()[0].x_max_mm - t.entries()[0].x_min_mm);
        let b = branch(compression);
        let target = t.force_on_branch(x_mm, b, current_a).force_n;
        let r = t.current_for_branch(x_mm, b, target);
        prop_assert!(r.current_a.is_finite() && r.current_a >= lo && r.current_a <= hi);
        prop_assert!(!r.flags.intersects(Flags::SATURATED_HIGH | Flags::SATURATED_LOW), "{:?}", r.flags);
        let scale = t.entries().iter().map(|e| {
            let q = if compression { e.compression } else { e.extension };
            horner_tol(&q, x_mm as f64)
        }).fold(0.0, f64::max);
        let force_tol_n = 64.0 * scale + 1e-3;
        // Currents whose forces differ by less than the force rounding cannot
        // be told apart: where F(I) is nearly flat the "no higher" bound
        // widens by force_tol / |dF/dI| (the slope of the segment around
        // `current_a`, one-sided at the range's ends).
        let h = 1e-3 * (hi - lo).max(1e-3);
        let (i0, i1) = ((current_a - h).max(lo), (current_a + h).min(hi));
        let slope = if i1 > i0 {
            ((t.force_on_branch(x_mm, b, i1).force_n - t.force_on_branch(x_mm, b, i0).force_n) as f64 / (i1 - i0) as f64).abs()
        } else {
            0.0
        };
        let current_tol_a = 1e-4 * (hi - lo).max(1.0) as f64 + force_tol_n / slope.max(1e-12);
        prop_assert!((r.current_a as f64) <= current_a as f64 + current_tol_a, "{} > {} (slope {slope} N/A)", r.current_a, current_a);
        let back = t.force_on_branch(x_mm, b, r.current_a).force_n;
        prop_assert!(((back - target) as f64).abs() <= force_tol_n, "{back} vs {target}");
    }

    /// The inverse's answer from its definition: the knot forces in f64,
    /// the first segment from the lowest current whose ends bracket the
    /// target, and for a target beyond every knot the knot with the nearest
    /// force. Targets and knots closer than f32 rounding are skipped (their
    /// order is the rounding's). Covers the scans with and without the
    /// proven order facts, on tables where the forces cross in any order.
    #[test]
    fn the_inverse_is_the_first_bracketing_segment_or_the_nearest_knot(
        t in table(), frac in 0.0f64..=1.0, pick in -0.3f64..1.3, compression in any::<bool>(),
    ) {
        let entries = t.entries();
        let lo_mm = entries.iter().map(|e| e.x_min_mm).fold(f32::NEG_INFINITY, f32::max);
        let hi_mm = entries.iter().map(|e| e.x_max_mm).fold(f32::INFINITY, f32::min);
        prop_assume!(lo_mm < hi_mm);
        let x_mm = (lo_mm as f64 + frac * (hi_mm - lo_mm) as f64) as f32;
        prop_assume!(x_mm >= lo_mm && x_mm <= hi_mm);
        let b = branch(compression);
        let quartic = |e: &CurrentEntry| if compression { e.compression } else { e.extension };
        let knots: Vec<f64> = entries.iter().map(|e| quartic_f64(&quartic(e), x_mm as f64)).collect();
        let tol = entries.iter().map(|e| horner_tol(&quartic(e), x_mm as f64)).fold(0.0, f64::max) + 1e-3;
        let (f_min, f_max) = knots.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &f| (a.min(f), b.max(f)));
        let target = f_min + pick * (f_max - f_min) + (pick - 0.5).signum() * 2.0 * tol;
        prop_assume!(knots.iter().all(|f| (f - target).abs() > 4.0 * tol));
        let currents: Vec<f32> = entries.iter().map(|e| e.current_a).collect();
        for table in [t, t.without_order_facts()] {
            let r = table.current_for_branch(x_mm, b, target as f32);
            if target < f_min || target > f_max {
                let high = target > f_max;
                let want = if high { f_max } else { f_min };
                // The nearest knot must be clear of the others.
                prop_assume!(knots.iter().filter(|&&f| (f - want).abs() <= 4.0 * tol).count() == 1);
                let k = knots.iter().position(|&f| f == want).unwrap_or(0);
                prop_assert_eq!(r.current_a, currents[k], "{:?} {} {:?}", knots, target, r);
                let side = if high { Flags::SATURATED_HIGH } else { Flags::SATURATED_LOW };
                prop_assert!(r.flags.contains(side), "{:?}", r.flags);
            } else {
                let j = knots.windows(2).position(|w| (w[0] < target) != (w[1] < target));
                prop_assert!(j.is_some(), "a target within the knots' range is bracketed");
                let j = j.unwrap_or(0);
                let slack = 1e-4 * (currents[j + 1] - currents[j]).max(1e-3);
                prop_assert!(
                    r.current_a >= currents[j] - slack && r.current_a <= currents[j + 1] + slack,
                    "{} outside segment {} ({}..{} A) of {:?} at {}", r.current_a, j, currents[j], currents[j + 1], knots, target
                );
                prop_assert!(!r.flags.intersects(Flags::SATURATED_HIGH | Flags::SATURATED_LOW), "{:?}", r.flags);
            }
        }
    }

    /// A table survives its flash image: same entries, and any flipped bit in
    /// the stored CRC is caught.
    #[test]
    fn the_image_round_trips_and_a_wrong_crc_is_refused(t in table(), bit in 0u32..32) {
        let image = t.image();
        let back = Table::from_image(&image).expect("its own image");
        prop_assert_eq!(back.entries(), t.entries());
        let bad = TableImage { crc32: t.crc32() ^ (1 << bit), ..image };
        prop_assert!(Table::from_image(&bad).is_err());
    }
}
