//! The inverse's shortcuts where the forces are proven ordered (`order.rs`)
//! give exactly the full scan's answer: every result is compared bit for bit
//! with the same table stripped of its order facts. The proven regions are
//! checked against crossings found independently (f64 bisection).
use mre_algorithm::table::{CurrentEntry, ModelTerms, Quartic, MAX_CURRENTS};
use mre_algorithm::{Branch, Table};
use proptest::prelude::*;

fn same_answer(t: &Table, x_mm: f32, v_m_s: f32, branch: Branch, target_n: f32) -> Result<(), TestCaseError> {
    let fast = t.current_for_branch_v(x_mm, v_m_s, branch, target_n);
    let scan = t
        .without_order_facts()
        .current_for_branch_v(x_mm, v_m_s, branch, target_n);
    prop_assert_eq!(
        fast.current_a.to_bits(),
        scan.current_a.to_bits(),
        "x {} v {} F {} {:?}: {:?} vs {:?}",
        x_mm,
        v_m_s,
        target_n,
        branch,
        fast,
        scan
    );
    prop_assert_eq!(fast.flags, scan.flags);
    Ok(())
}

fn generated(terms: ModelTerms) -> Table {
    Table::with_terms(&mre_algorithm::generated_table::GENERATED_ENTRIES, terms).unwrap()
}

fn branch(compression: bool) -> Branch {
    if compression {
        Branch::Compression
    } else {
        Branch::Extension
    }
}

/// Entries whose forces rise with current except near x = 0, where each
/// has its own small offset (as fitted tables do):
/// `F_k = base + k·slope·x + offset_k`, plus small higher-order
/// differences; half of them with a viscous term (arbitrary, or rising
/// with current).
fn nearly_ordered_table() -> impl Strategy<Value = Table> {
    (
        2usize..=MAX_CURRENTS,
        0.0f32..2000.0,
        1.0f32..800.0,
        proptest::array::uniform8(-20.0f32..20.0),
        proptest::array::uniform8(-0.05f32..0.05),
        prop::array::uniform8(-100.0f32..100.0),
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(n, base, slope, offsets, cubic, mut viscous, with_viscous, rising)| {
            if rising {
                // Non-decreasing with current: the facts' usual case.
                viscous.sort_by(f32::total_cmp);
            }
            let entries: Vec<CurrentEntry> = (0..n)
                .map(|k| {
                    let q = Quartic::new([0.0, cubic[k], 0.5, base + k as f32 * slope, offsets[k]]);
                    CurrentEntry {
                        current_a: 0.5 * k as f32,
                        compression: q,
                        extension: Quartic::new([0.0, -cubic[k], 0.1, 0.3 * (base + k as f32 * slope), offsets[k]]),
                        x_min_mm: -0.01,
                        x_max_mm: 15.0,
                    }
                })
                .collect();
            let mut terms = ModelTerms::NONE;
            if with_viscous {
                terms.viscous_n_s_per_m = viscous;
            }
            Table::with_terms(&entries, terms).unwrap()
        })
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(2000))]

    #[test]
    fn shortcuts_give_the_full_scans_answer(
        t in nearly_ordered_table(),
        x_mm in -0.5f32..16.0,
        v_m_s in prop_oneof![-3.0f32..3.0, Just(0.0f32), -200.0f32..200.0],
        target_n in prop_oneof![-100.0f32..500.0, 0.0f32..40_000.0],
        compression in any::<bool>(),
    ) {
        same_answer(&t, x_mm, v_m_s, branch(compression), target_n)?;
    }

    #[test]
    fn shortcuts_on_the_flown_entries_with_any_terms(
        every in any::<bool>(),
        x_mm in -0.1f32..15.5,
        v_m_s in -3.0f32..3.0,
        target_n in prop_oneof![-50.0f32..800.0, 0.0f32..40_000.0],
        compression in any::<bool>(),
    ) {
        let t = generated(if every { ModelTerms::EVERY_TERM } else { ModelTerms::NONE });
        same_answer(&t, x_mm, v_m_s, branch(compression), target_n)?;
    }
}

/// Around the crossings the proofs stop at: a dense grid on the flown
/// table, the paper's, and each with a viscous term.
#[test]
fn shortcuts_agree_on_a_dense_grid_near_contact() {
    let paper = Table::paper().unwrap();
    let mut viscous = ModelTerms::NONE;
    viscous.viscous_n_s_per_m = [0.0, 30.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let paper_viscous = Table::with_terms(paper.entries(), viscous).unwrap();
    // Viscous coefficients that rise with current: the quartics' facts at
    // every velocity of the branch's sign up to ORDER_V_MAX_M_S.
    let mut rising = ModelTerms::EVERY_TERM;
    rising.viscous_n_s_per_m = [0.0, 10.0, 20.0, 30.0, 40.0, 0.0, 0.0, 0.0];
    for t in [
        generated(ModelTerms::NONE),
        generated(ModelTerms::EVERY_TERM),
        generated(rising),
        paper,
        paper_viscous,
    ] {
        for i in 0..=1200 {
            let x_mm = -0.02 + i as f32 * 0.001;
            for target_n in [-5.0, 0.0, 3.0, 20.0, 60.0, 150.0, 300.0, 500.0, 700.0, 1000.0, 5000.0] {
                // Inside the viscous facts' velocity range, at its ends and past them.
                for v_m_s in [0.0, 0.01, 0.5, 2.24, 5.0, 6.0, -1.0, -5.0, -6.0] {
                    for b in [Branch::Compression, Branch::Extension] {
                        same_answer(&t, x_mm, v_m_s, b, target_n).unwrap();
                    }
                }
            }
        }
    }
}

fn quartic_f64(q: &Quartic, x: f64) -> f64 {
    q.coeffs.iter().fold(0.0, |acc, &c| acc * x + c as f64)
}

/// The flown table's 1.5 A and 2 A compression quartics cross near contact
/// (found here by f64 bisection on their difference): the "forces rise with
/// current" region starts above it, within 0.01 mm; the "largest entry at
/// contact" region ends below the first crossing of that entry, likewise.
#[test]
fn the_proven_regions_end_at_the_flown_tables_crossing() {
    let e = &mre_algorithm::generated_table::GENERATED_ENTRIES;
    let d = |x: f64| quartic_f64(&e[4].compression, x) - quartic_f64(&e[3].compression, x);
    let (mut lo, mut hi) = (0.1, 1.0);
    assert!(d(lo) < 0.0 && d(hi) > 0.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if d(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let crossing_mm = lo as f32;
    let facts = *generated(ModelTerms::NONE).order_facts(Branch::Compression);
    assert!(
        facts.ascending_from_mm > crossing_mm && facts.ascending_from_mm < crossing_mm + 0.01,
        "{facts:?} vs {crossing_mm}"
    );
    // The largest entry at the bottom of the shared stroke (the highest
    // x_min of the entries), found in f64, and the first x above it where
    // another entry's quartic overtakes it (an f64 scan in 1 µm steps, then
    // bisection): the "largest entry" region ends below that crossing,
    // within 0.01 mm of it.
    let bottom_mm = e.iter().map(|c| c.x_min_mm as f64).fold(f64::NEG_INFINITY, f64::max);
    let at = |k: usize, x: f64| quartic_f64(&e[k].compression, x);
    let top = (0..e.len())
        .max_by(|&a, &b| at(a, bottom_mm).total_cmp(&at(b, bottom_mm)))
        .unwrap();
    assert_eq!(facts.top, top, "{facts:?}");
    let overtaken = |x: f64| (0..e.len()).any(|k| k != top && at(k, x) > at(top, x));
    let mut x = bottom_mm;
    while !overtaken(x + 1e-3) {
        x += 1e-3;
        assert!(x < 1.0, "entry {top} stays the largest past 1 mm");
    }
    let (mut lo, mut hi) = (x, x + 1e-3);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if overtaken(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let overtaken_mm = lo as f32;
    assert!(
        facts.top_to_mm <= overtaken_mm && facts.top_to_mm > overtaken_mm - 0.01,
        "{facts:?} vs {overtaken_mm}"
    );
}

/// A viscous term can reorder the entries at speed: a table with one gets
/// facts for its branch's velocities up to `ORDER_V_MAX_M_S` only, and they
/// must hold with the viscous forces at both ends of that range.
#[test]
fn a_viscous_term_limits_the_facts_to_a_velocity_range() {
    use mre_algorithm::order::ORDER_V_MAX_M_S;
    let t = generated(ModelTerms::EVERY_TERM);
    let c = t.order_facts(Branch::Compression);
    assert_eq!((c.v_min_m_s, c.v_max_m_s), (0.0, ORDER_V_MAX_M_S));
    let e = t.order_facts(Branch::Extension);
    assert_eq!((e.v_min_m_s, e.v_max_m_s), (-ORDER_V_MAX_M_S, 0.0));
    // Without it: every velocity.
    let plain = generated(ModelTerms::NONE);
    let p = plain.order_facts(Branch::Compression);
    assert_eq!((p.v_min_m_s, p.v_max_m_s), (f32::NEG_INFINITY, f32::INFINITY));
    // EVERY_TERM's 0.5 A entry has 30 N·s/m, the 1 A entry none: at 5 m/s
    // the 0.5 A force gains 150 N, so "forces rise with current" needs the
    // 1 A quartic 150 N above the 0.5 A one (x ≳ 0.34 mm by their linear
    // terms, 1375 − 932 N/mm), and the 1.5 A / 2 A crossing (0.435 mm)
    // still bounds it: the region starts at that crossing, as without the
    // viscous term.
    assert!(
        c.ascending_from_mm >= p.ascending_from_mm && c.ascending_from_mm < p.ascending_from_mm + 0.01,
        "{c:?} vs {p:?}"
    );
    // Near contact the 0.5 A entry is the largest at speed but not at rest,
    // which is why the "largest entry" fact is not proven with a viscous
    // term (the inverse would not use it).
    assert_eq!(c.top_to_mm, f32::NEG_INFINITY);
    assert_eq!(e.top_to_mm, f32::NEG_INFINITY);
    let e = &mre_algorithm::generated_table::GENERATED_ENTRIES;
    let f = |k: usize, v: f32| f64::from(e[k].compression.eval(0.1)) + f64::from(t.terms().viscous_n_s_per_m[k] * v);
    assert!(f(1, 5.0) > f(3, 5.0) && f(1, 0.0) < f(3, 0.0));
}

/// A viscous coefficient that falls with current by more than the quartics'
/// margin at `ORDER_V_MAX_M_S` leaves no ascending region; one that rises
/// with current keeps the quartics' own.
#[test]
fn falling_viscous_coefficients_can_only_shrink_the_facts() {
    let plain = *generated(ModelTerms::NONE).order_facts(Branch::Compression);
    let mut rising = ModelTerms::NONE;
    rising.viscous_n_s_per_m = [0.0, 10.0, 20.0, 30.0, 40.0, 0.0, 0.0, 0.0];
    let r = *generated(rising).order_facts(Branch::Compression);
    assert!(
        r.ascending_from_mm <= plain.ascending_from_mm + 1e-3,
        "{r:?} vs {plain:?}"
    );
    let mut falling = ModelTerms::NONE;
    // 2 A loses 10⁴ N·s/m against 1.5 A: 50 kN at 5 m/s, beyond any
    // difference of their quartics on the stroke.
    falling.viscous_n_s_per_m = [0.0, 0.0, 0.0, 1.0e4, 0.0, 0.0, 0.0, 0.0];
    let f = *generated(falling).order_facts(Branch::Compression);
    assert_eq!(f.ascending_from_mm, f32::INFINITY, "{f:?}");
}
