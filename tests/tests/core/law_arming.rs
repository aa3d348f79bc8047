//! Arming a lagging coil before contact (#29): idle at the robust current,
//! and on the approach at the current for the predicted impact. Expected
//! currents by hand (energy balance), on a model of constant forces.
use mre_algorithm::law::{ImpactLaw, LawConfig};
use mre_algorithm::table::ModelTerms;
use mre_algorithm::Table;
use mre_tests::linear_entry;

/// 500 N at 0 A and 2500 N at 2 A, at any x in 0–20 mm, a coil of τ = 10 ms.
fn constant_forces() -> Table {
    let terms = ModelTerms {
        coil_tau_s: 0.01,
        ..ModelTerms::NONE
    };
    Table::with_terms(&[linear_entry(0.0, 0.0, 500.0), linear_entry(2.0, 0.0, 2500.0)], terms).unwrap()
}

/// The board's defaults (5.5 kg, 12 mm, impacts up to 2.5 m/s), with a
/// displacement sensor that sees 30 mm of approach.
fn seeing_the_approach() -> LawConfig {
    LawConfig {
        x_valid_min_mm: -31.0,
        ..LawConfig::default()
    }
}

// Stopping 5.5 kg in 12 mm at a constant force F: (F − m·g)·s = ½·m·v².
// At 2.5 m/s: F = 17.1875 J / 0.012 m + 53.955 N = 1486.247 N → I = 0.986247 A
// (F = 500 N + 1000 N/A · I); at 2.24 m/s: 1203.822 N → 0.703822 A.
const ROBUST_A: f32 = 0.986_247;
const AT_2_24_A: f32 = 0.703_822;

#[test]
fn idle_holds_the_current_that_stops_the_fastest_expected_impact() {
    let table = constant_forces();
    let mut law = ImpactLaw::new(LawConfig::default()).unwrap();
    assert!((law.idle_current_a(&table) - ROBUST_A).abs() < 1e-4);
    for _ in 0..100 {
        law.step(&table, 0.0, 0.0);
    }
    assert!(
        (law.coil_estimate_a() - ROBUST_A).abs() < 1e-4,
        "{}",
        law.coil_estimate_a()
    );
}

#[test]
fn the_approach_arms_for_the_impact_velocity_predicted_by_free_fall() {
    let table = constant_forces();
    let mut law = ImpactLaw::new(seeing_the_approach()).unwrap();
    law.step(&table, 0.0, 0.0);
    // Falling freely towards a 2.24 m/s impact, sampled every 0.1 ms from
    // 30 mm out: v(x) = √(2.24² − 2·g·|x|).
    let (g, period_s) = (9.81f32, 1.0e-4f32);
    let mut x_m = -0.030f32;
    let mut v = (2.24f32 * 2.24 - 2.0 * g * 0.030).sqrt();
    let mut coil_a = Vec::new();
    while x_m < -0.001 {
        law.step(&table, x_m * 1e3, v);
        coil_a.push(law.coil_estimate_a());
        x_m += v * period_s + 0.5 * g * period_s * period_s;
        v += g * period_s;
    }
    let last = *coil_a.last().unwrap();
    assert!((last - AT_2_24_A).abs() < 2e-3, "armed at {last} A");
    // It got there from the robust current, driving down at the supply's
    // limit: −3 A through τ = 10 ms takes τ·ln(3.986/3.704) = 0.73 ms = 8 periods.
    assert!(coil_a.len() > 60);
    assert!((coil_a[12] - AT_2_24_A).abs() < 2e-3, "{}", coil_a[12]);
}

#[test]
fn without_a_lagging_coil_the_approach_is_not_armed() {
    // τ = 0: the current follows at once, nothing to arm; the law plans as
    // it always did (here: the compression plan, a current above 0.7 A).
    let table = Table::with_terms(constant_forces().entries(), ModelTerms::NONE).unwrap();
    let mut law = ImpactLaw::new(seeing_the_approach()).unwrap();
    let cmd = law.step(&table, -10.0, 2.2);
    assert!((cmd.current_a - AT_2_24_A).abs() > 0.05, "{}", cmd.current_a);
}
