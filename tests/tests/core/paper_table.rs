//! The built-in table is the paper's Table 4, evaluated as the paper defines it.
//!
//! Expected forces were computed independently with `numpy.polyval` in float64
//! from the coefficients printed in the paper (x in mm, F in N); at x = 1 mm a
//! quartic is just the sum of its coefficients, which is checked by hand too.
use mre_algorithm::installation::DEFAULT_INSTALLATION;
use mre_algorithm::model::Branch;
use mre_algorithm::table::{
    content_crc, CurrentEntry, ModelTerms, Quartic, Table, TableError, TableImage, FORMAT_VERSION, FORMAT_VERSION_1,
    FORMAT_VERSION_2, FORMAT_VERSION_3, PAPER_TABLE4_ENTRIES,
};
use mre_tests::crc32_reference;

const CURRENTS_A: [f32; 5] = [0.0, 0.5, 1.0, 1.5, 2.0];
const XS_MM: [f32; 3] = [0.25, 0.5, 0.8];

/// numpy.polyval(Table 4 row, x) for x in XS_MM, per current (rows) — compression.
const COMPRESSION_N: [[f64; 3]; 5] = [
    [1549.7470, 2680.2275, 3557.5074],
    [1079.6784, 2532.6050, 4779.0080],
    [2725.5341, 4826.2200, 6480.3600],
    [2130.3091, 4350.4588, 6758.8777],
    [3430.2372, 5454.9950, 7145.7058],
];
/// Same for extension.
const EXTENSION_N: [[f64; 3]; 5] = [
    [135.8026, 567.2488, 1802.2287],
    [79.2006, 613.6850, 2692.1895],
    [1439.5706, 2674.5300, 4553.4194],
    [1075.8451, 2485.1338, 5131.1907],
    [2091.7827, 4649.2475, 6788.6708],
];

/// f32 Horner on coefficients of ~1e4 is good to ~1e-6 relative.
const TOL_N: f64 = 0.05;

fn paper() -> Table {
    Table::paper().expect("built-in table is valid")
}

#[test]
fn golden_values_at_tabulated_currents() {
    let t = paper();
    for (i, &current_a) in CURRENTS_A.iter().enumerate() {
        for (j, &x) in XS_MM.iter().enumerate() {
            let c = t.force_on_branch(x, Branch::Compression, current_a).force_n as f64;
            let e = t.force_on_branch(x, Branch::Extension, current_a).force_n as f64;
            assert!(
                (c - COMPRESSION_N[i][j]).abs() < TOL_N,
                "{current_a} A, x={x}: compression {c} vs {}",
                COMPRESSION_N[i][j]
            );
            assert!(
                (e - EXTENSION_N[i][j]).abs() < TOL_N,
                "{current_a} A, x={x}: extension {e} vs {}",
                EXTENSION_N[i][j]
            );
        }
    }
}

#[test]
fn at_one_millimetre_a_quartic_is_the_sum_of_its_coefficients() {
    // Hand check on the 0 A compression row: −1201.40 + 4792.40 − 8317.70 + 8945.10 − 236.86.
    let expected = -1201.40 + 4792.40 - 8317.70 + 8945.10 - 236.86;
    assert!((expected - 3981.54f64).abs() < 1e-9);
    let f = paper().force_on_branch(1.0, Branch::Compression, 0.0).force_n as f64;
    assert!((f - expected).abs() < TOL_N, "{f}");
}

#[test]
fn branch_follows_velocity_sign() {
    let t = paper();
    let up = t.force(0.5, 0.3, 1.0).force_n as f64;
    let down = t.force(0.5, -0.3, 1.0).force_n as f64;
    let zero = t.force(0.5, 0.0, 1.0).force_n as f64;
    assert!((up - COMPRESSION_N[2][1]).abs() < TOL_N);
    assert!((down - EXTENSION_N[2][1]).abs() < TOL_N);
    assert!(
        (zero - EXTENSION_N[2][1]).abs() < TOL_N,
        "v = 0 is extension in the paper's rule"
    );
}

/// The paper's interpolation (its Eq. X, typo corrected):
/// f_I = f_lo + (I − I_lo)/(I_hi − I_lo) · (f_hi − f_lo).
#[test]
fn interpolated_currents_follow_the_papers_formula() {
    let t = paper();
    for (current_a, lo, hi) in [(0.3f32, 0usize, 1usize), (0.7, 1, 2), (1.3, 2, 3), (1.7, 3, 4)] {
        let w = (current_a as f64 - CURRENTS_A[lo] as f64) / 0.5;
        for (j, &x) in XS_MM.iter().enumerate() {
            for (branch, table) in [(Branch::Compression, &COMPRESSION_N), (Branch::Extension, &EXTENSION_N)] {
                let expected = table[lo][j] + w * (table[hi][j] - table[lo][j]);
                let got = t.force_on_branch(x, branch, current_a).force_n as f64;
                assert!(
                    (got - expected).abs() < 0.1,
                    "{current_a} A x={x} {branch:?}: {got} vs {expected}"
                );
            }
        }
    }
}

#[test]
fn currents_outside_the_table_are_clamped_and_flagged() {
    let t = paper();
    let above = t.force_on_branch(0.5, Branch::Compression, 3.0);
    assert!((above.force_n as f64 - COMPRESSION_N[4][1]).abs() < TOL_N);
    assert!(above.flags.contains(mre_algorithm::Flags::CURRENT_CLAMPED));
    let below = t.force_on_branch(0.5, Branch::Compression, -1.0);
    assert!((below.force_n as f64 - COMPRESSION_N[0][1]).abs() < TOL_N);
    assert!(below.flags.contains(mre_algorithm::Flags::CURRENT_CLAMPED));
}

#[test]
fn displacement_outside_the_fitted_stroke_is_clamped_and_flagged() {
    let t = paper();
    let entry = t.entries()[0];
    let beyond = t.force_on_branch(entry.x_max_mm + 5.0, Branch::Compression, 0.0);
    let at_end = t.force_on_branch(entry.x_max_mm, Branch::Compression, 0.0);
    assert_eq!(beyond.force_n, at_end.force_n);
    assert!(beyond.flags.contains(mre_algorithm::Flags::X_CLAMPED));
    assert!(!at_end.flags.contains(mre_algorithm::Flags::X_CLAMPED));
    let before = t.force_on_branch(-1.0, Branch::Compression, 0.0);
    // x clamps to 0, where the quartic is its constant term a5 = −236.86.
    assert!((before.force_n as f64 + 236.86).abs() < 1e-3);
}

#[test]
fn fitted_stroke_ends_where_the_loop_closes() {
    // The paper's loops close where compression meets extension (README note);
    // the built-in x_max_mm values are those crossings, to 1e-4 mm.
    for e in paper().entries() {
        let gap = e.compression.eval(e.x_max_mm) - e.extension.eval(e.x_max_mm);
        let slope = (e.compression.eval(e.x_max_mm + 1e-3) - e.extension.eval(e.x_max_mm + 1e-3)) - gap;
        // |gap| below what a 1e-4 mm position error can explain.
        assert!(
            gap.abs() <= slope.abs() * 0.1 + 0.5,
            "{} A: branches differ by {gap} N at x_max",
            e.current_a
        );
    }
}

#[test]
fn horner_matches_the_power_form() {
    let q = Quartic::new([2.0, -3.0, 0.5, 7.0, -1.0]);
    let x = 1.5f32;
    let power = 2.0 * x.powi(4) - 3.0 * x.powi(3) + 0.5 * x * x + 7.0 * x - 1.0;
    assert!((q.eval(x) - power).abs() < 1e-4);
}

fn entry(current_a: f32) -> CurrentEntry {
    CurrentEntry {
        current_a,
        compression: Quartic::new([0.0, 0.0, 0.0, 1000.0, 0.0]),
        extension: Quartic::new([0.0, 0.0, 0.0, 500.0, 0.0]),
        x_min_mm: 0.0,
        x_max_mm: 5.0,
    }
}

#[test]
fn corrupt_or_inconsistent_tables_are_rejected() {
    assert_eq!(Table::new(&[]), Err(TableError::Empty));
    assert_eq!(
        Table::new(&[entry(1.0), entry(0.5)]),
        Err(TableError::UnsortedCurrents { index: 1 })
    );
    assert_eq!(
        Table::new(&[entry(1.0), entry(1.0)]),
        Err(TableError::UnsortedCurrents { index: 1 })
    );
    assert_eq!(
        Table::new(&[entry(f32::NAN)]),
        Err(TableError::UnsortedCurrents { index: 0 })
    );
    let mut nan = entry(0.0);
    nan.extension.coeffs[2] = f32::NAN;
    assert_eq!(Table::new(&[nan]), Err(TableError::NonFiniteValue { index: 0 }));
    let mut inf = entry(0.0);
    inf.compression.coeffs[0] = f32::INFINITY;
    assert_eq!(
        Table::new(&[entry(-1.0), inf]),
        Err(TableError::NonFiniteValue { index: 1 })
    );
    let mut backwards = entry(0.0);
    backwards.x_min_mm = 6.0;
    assert_eq!(Table::new(&[backwards]), Err(TableError::BadStroke { index: 0 }));
    let nine: Vec<CurrentEntry> = (0..9).map(|i| entry(i as f32)).collect();
    assert_eq!(Table::new(&nine), Err(TableError::TooManyEntries { count: 9 }));
}

#[test]
fn a_flipped_bit_in_a_stored_table_fails_its_crc() {
    let good = TableImage {
        version: FORMAT_VERSION_1,
        entries: &PAPER_TABLE4_ENTRIES,
        terms: ModelTerms::NONE,
        installation: DEFAULT_INSTALLATION,
        crc32: content_crc(
            FORMAT_VERSION_1,
            &PAPER_TABLE4_ENTRIES,
            &ModelTerms::NONE,
            &DEFAULT_INSTALLATION,
        ),
    };
    assert!(Table::from_image(&good).is_ok());
    let mut corrupt = PAPER_TABLE4_ENTRIES;
    corrupt[3].extension.coeffs[1] = f32::from_bits(corrupt[3].extension.coeffs[1].to_bits() ^ 1);
    let image = TableImage {
        entries: &corrupt,
        ..good
    };
    assert!(matches!(Table::from_image(&image), Err(TableError::CrcMismatch { .. })));
    let wrong_version = TableImage {
        version: FORMAT_VERSION + 1,
        ..good
    };
    assert_eq!(
        Table::from_image(&wrong_version).err(),
        Some(TableError::UnsupportedVersion {
            version: FORMAT_VERSION + 1
        })
    );
}

#[test]
fn crc_is_the_standard_crc32_of_the_documented_byte_layout() {
    // The reference CRC-32 (zlib/ISO-HDLC, bitwise definition) over the
    // layout documented in `content_crc`.
    assert_eq!(
        crc32_reference(b"123456789"),
        0xCBF4_3926,
        "reference implementation self-check"
    );
    let entries = [entry(0.0), entry(1.0)];
    let layout = |version: u16| {
        let mut bytes = vec![];
        bytes.extend_from_slice(&version.to_le_bytes());
        bytes.push(2);
        for e in &entries {
            for v in [e.current_a, e.x_min_mm, e.x_max_mm] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
            for v in e.compression.coeffs.iter().chain(&e.extension.coeffs) {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        bytes
    };
    let none = ModelTerms::NONE;
    assert_eq!(
        content_crc(FORMAT_VERSION_1, &entries, &none, &DEFAULT_INSTALLATION),
        crc32_reference(&layout(FORMAT_VERSION_1))
    );
    // Version 2 appends I_s, sensor delay, coil τ and one viscous term per entry.
    let mut terms = ModelTerms {
        saturation_current_a: 0.75,
        sensor_delay_s: 2.0e-4,
        coil_tau_s: 3.0e-3,
        ..none
    };
    terms.viscous_n_s_per_m[0] = 120.0;
    terms.viscous_n_s_per_m[1] = 240.0;
    terms.viscous_n_s_per_m[5] = 99.0; // past the entries: not hashed
    let mut bytes = layout(FORMAT_VERSION_2);
    for v in [0.75f32, 2.0e-4, 3.0e-3, 120.0, 240.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    assert_eq!(
        content_crc(FORMAT_VERSION_2, &entries, &terms, &DEFAULT_INSTALLATION),
        crc32_reference(&bytes)
    );
    // Version 3 appends the installation: mass, usable stroke, coil rating,
    // coil resistance, supply, x sensor range, v sensor full scale, impact
    // v min, impact v max (the order documented in `content_crc`).
    let lab = mre_algorithm::installation::Installation {
        mass_kg: 3.0,
        usable_stroke_mm: 9.0,
        coil_rating_a: 1.5,
        coil_resistance_ohm: 4.0,
        supply_v: 12.0,
        x_sensor_range_mm: 25.0,
        v_sensor_full_scale_m_s: 5.0,
        impact_v_min_m_s: 1.0,
        impact_v_max_m_s: 3.0,
    };
    let mut bytes = layout(FORMAT_VERSION_3);
    for v in [
        0.75f32, 2.0e-4, 3.0e-3, 120.0, 240.0, 3.0, 9.0, 1.5, 4.0, 12.0, 25.0, 5.0, 1.0, 3.0,
    ] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    assert_eq!(
        content_crc(FORMAT_VERSION_3, &entries, &terms, &lab),
        crc32_reference(&bytes)
    );
}

#[test]
fn version_2_images_carry_their_terms_and_version_1_images_may_not() {
    let entries = [entry(0.0), entry(1.0)];
    let mut terms = ModelTerms {
        coil_tau_s: 2.0e-3,
        ..ModelTerms::NONE
    };
    terms.viscous_n_s_per_m[1] = 50.0;
    let v2 = Table::with_terms(&entries, terms).unwrap();
    assert_eq!(v2.version(), FORMAT_VERSION_2);
    let image = TableImage {
        version: FORMAT_VERSION_2,
        entries: &entries,
        terms,
        installation: DEFAULT_INSTALLATION,
        crc32: v2.crc32(),
    };
    assert_eq!(Table::from_image(&image), Ok(v2));
    // A changed term breaks the CRC.
    let changed = TableImage {
        terms: ModelTerms {
            coil_tau_s: 2.5e-3,
            ..terms
        },
        ..image
    };
    assert!(matches!(
        Table::from_image(&changed),
        Err(TableError::CrcMismatch { .. })
    ));
    // Terms in a version 1 image are refused, whatever its CRC.
    let v1_with_terms = TableImage {
        version: FORMAT_VERSION_1,
        crc32: content_crc(FORMAT_VERSION_1, &entries, &terms, &DEFAULT_INSTALLATION),
        ..image
    };
    assert!(matches!(
        Table::from_image(&v1_with_terms),
        Err(TableError::BadTerm { .. })
    ));
    // Out-of-range terms are refused.
    for bad in [
        ModelTerms {
            coil_tau_s: -1.0e-3,
            ..terms
        },
        ModelTerms {
            sensor_delay_s: f32::NAN,
            ..terms
        },
        ModelTerms {
            saturation_current_a: -0.5,
            ..terms
        },
        // tanh(2 A / 0.01 A) rounds to 1: the knots collapse.
        ModelTerms {
            saturation_current_a: 0.01,
            ..terms
        },
    ] {
        assert!(
            matches!(Table::with_terms(&entries, bad), Err(TableError::BadTerm { .. })),
            "{bad:?}"
        );
    }
}
