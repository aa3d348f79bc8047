//! Table magnitude validation: an extreme (e.g. uploaded) table must be
//! refused, because Horner overflows to ±inf and the inverse then yields NaN
//! (which once clamped to the softest current).
use mre_algorithm::law::{ImpactLaw, LawConfig};
use mre_algorithm::table::{MAX_TABLE_FORCE_N, MAX_VISCOUS_N_S_PER_M};
use mre_algorithm::{CurrentEntry, Flags, Quartic, Table, TableError};

fn entry(current_a: f32, compression: [f32; 5], x_max_mm: f32) -> CurrentEntry {
    CurrentEntry {
        current_a,
        compression: Quartic::new(compression),
        extension: Quartic::new([0.0, 0.0, 0.0, 10.0, 0.0]),
        x_min_mm: 0.0,
        x_max_mm,
    }
}

#[test]
fn finite_but_overflowing_coefficients_are_refused() {
    // 1e37 · x⁴ at x = 15 mm is 5e41: beyond f32 (3.4e38), yet finite as stored.
    let huge = [
        entry(0.0, [1.0e37, 0.0, 0.0, 0.0, 0.0], 15.0),
        entry(2.0, [0.0, 0.0, 0.0, 100.0, 0.0], 15.0),
    ];
    assert_eq!(Table::new(&huge), Err(TableError::TooLarge { index: 0 }));
}

#[test]
fn the_bound_is_the_largest_force_over_the_fitted_stroke() {
    // x⁴ reaches 1e9 N at x = 1e9^(1/4) = 177.8 mm.
    assert!(Table::new(&[entry(0.0, [1.0, 0.0, 0.0, 0.0, 0.0], 177.0)]).is_ok());
    assert_eq!(
        Table::new(&[entry(0.0, [1.0, 0.0, 0.0, 0.0, 0.0], 178.5)]),
        Err(TableError::TooLarge { index: 0 })
    );
    // Signs do not cancel in the bound: x⁴ − 9.8e8 is small at 177 mm
    // (177⁴ = 9.815e8), but its terms are not (9.8e8 + 9.815e8 > 1e9), and
    // Horner's partials are bounded only by the sum of the magnitudes.
    assert_eq!(
        Table::new(&[entry(0.0, [1.0, 0.0, 0.0, 0.0, -9.8e8], 177.0)]),
        Err(TableError::TooLarge { index: 0 })
    );
    // A constant at the bound passes, just above it fails.
    assert!(Table::new(&[entry(0.0, [0.0, 0.0, 0.0, 0.0, MAX_TABLE_FORCE_N], 10.0)]).is_ok());
    assert!(Table::new(&[entry(0.0, [0.0, 0.0, 0.0, 0.0, 1.1 * MAX_TABLE_FORCE_N], 10.0)]).is_err());
}

#[test]
fn extreme_stroke_current_and_viscous_terms_are_refused() {
    let line = [0.0, 0.0, 0.0, 1.0, 0.0];
    assert_eq!(
        Table::new(&[entry(0.0, line, 2000.0)]),
        Err(TableError::TooLarge { index: 0 })
    );
    assert_eq!(
        Table::new(&[entry(1.0e3, line, 10.0)]),
        Err(TableError::TooLarge { index: 0 })
    );
    let mut terms = mre_algorithm::table::ModelTerms::NONE;
    terms.viscous_n_s_per_m[0] = 2.0 * MAX_VISCOUS_N_S_PER_M;
    assert!(matches!(
        Table::with_terms(&[entry(0.0, line, 10.0)], terms),
        Err(TableError::BadTerm { .. })
    ));
}

#[test]
fn the_flown_tables_are_within_the_bounds() {
    assert!(Table::paper().is_ok());
    assert!(Table::from_image(&mre_algorithm::generated_table::GENERATED_TABLE).is_ok());
}

#[test]
fn a_bounded_table_gives_the_law_finite_commands_everywhere() {
    // The largest table the bounds allow, stepped over the whole valid
    // sensor range: never a NaN, never a silent softest current.
    let table = Table::new(&[
        entry(0.0, [0.0, 0.0, 0.0, 0.0, -MAX_TABLE_FORCE_N], 25.0),
        entry(2.0, [0.0, 0.0, 0.0, 0.0, MAX_TABLE_FORCE_N], 25.0),
    ])
    .unwrap();
    let mut law = ImpactLaw::new(LawConfig::default()).unwrap();
    for k in 0..=260 {
        let x_mm = -1.0 + 0.1 * k as f32;
        for v_m_s in [-19.0, -1.0, 0.0, 0.01, 1.0, 2.24, 19.0] {
            let cmd = law.step(&table, x_mm, v_m_s);
            assert!(cmd.current_a.is_finite(), "x {x_mm} v {v_m_s}");
            assert!(
                !cmd.flags.contains(Flags::TABLE_FAULT),
                "x {x_mm} v {v_m_s}: {:?}",
                cmd.flags
            );
        }
    }
}
