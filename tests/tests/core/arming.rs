//! The arming currents (`mre_algorithm::arming`): expected values by hand, from
//! energy balance, and one by an independent time integration.
use mre_algorithm::arming::{compression_work_j, lead_time_s, Arming};
use mre_algorithm::table::{ModelTerms, Table};
// `linear(I, a1, a0)`: an entry whose force is `a1·x + a0` (x in mm) over 0–20 mm.
use mre_tests::linear_entry as linear;

const M_KG: f32 = 5.5;
const G: f32 = 9.81;

#[test]
fn constant_forces_arm_at_the_force_that_stops_the_mass_at_the_stroke_end() {
    // 500 N at 0 A, 2500 N at 2 A (linear in I between them). Stopping
    // 5.5 kg from 2.24 m/s in 12 mm at a constant force F:
    // (F − m·g)·s = ½·m·v² → F = 13.7984 J / 0.012 m + 53.955 N = 1203.822 N,
    // so I = (1203.822 − 500) / 1000 = 0.703822 A.
    let table = Table::new(&[linear(0.0, 0.0, 500.0), linear(2.0, 0.0, 2500.0)]).unwrap();
    let arming = Arming::new(&table, M_KG, G, 12.0, 2.5);
    let i = arming.stop_current_a(2.24);
    assert!((i - 0.703_822).abs() < 1e-4, "{i}");
    // Robust: the 2.5 m/s impact, 17.1875 J / 0.012 + 53.955 = 1486.247 N → 0.986247 A.
    assert!((arming.robust_current_a() - 0.986_247).abs() < 1e-4);
    // A standing mass needs only its weight over the stroke: 0 A gives more.
    assert_eq!(arming.stop_current_a(0.0), 0.0);
    // Beyond what 2 A stops (2500 N: v = sqrt(2·(2500 − 53.955)·0.012/5.5) = 3.2675 m/s)
    // and for a non-finite velocity: the highest current.
    assert_eq!(arming.stop_current_a(3.3), 2.0);
    assert_eq!(arming.stop_current_a(f32::NAN), 2.0);
    assert!(arming.stop_current_a(3.26) < 2.0);
}

#[test]
fn a_spring_model_stops_the_mass_at_the_stroke_end_in_an_independent_integration() {
    // F = k(I)·x with k = 100 N/mm at 0 A and 300 N/mm at 1 A. The current
    // found for 2.24 m/s must, when the drop is integrated in time
    // (semi-implicit Euler, 0.1 µs), stop the mass at 12 mm.
    let table = Table::new(&[linear(0.0, 100.0, 0.0), linear(1.0, 300.0, 0.0)]).unwrap();
    let i = Arming::new(&table, M_KG, G, 12.0, 2.5).stop_current_a(2.24) as f64;
    // By hand: ½·k·s² = ½·m·v² + m·g·s → k = 2·14.44586 J / (0.012 m)² = 200 637 N/m
    // = 200.637 N/mm → I = 0.50319 A.
    assert!((i - 0.50319).abs() < 1e-3, "{i}");
    let k_n_per_m = (100.0 + 200.0 * i) * 1e3;
    let (mut x, mut v, h) = (0.0f64, 2.24f64, 1e-7);
    while v > 0.0 {
        v += (9.81 - k_n_per_m * x / 5.5) * h;
        x += v * h;
    }
    assert!((x * 1e3 - 12.0).abs() < 0.01, "{} mm", x * 1e3);
}

#[test]
fn under_saturation_the_current_comes_back_through_atanh() {
    // Constant forces 500 N and 2500 N at 0 and 2 A, interpolated in
    // w = tanh(I / 1 A): the 1203.822 N of the first test is at
    // w = 0.351911·tanh(2) = 0.339258 → I = atanh(0.339258) = 0.353203 A.
    let entries = [linear(0.0, 0.0, 500.0), linear(2.0, 0.0, 2500.0)];
    let terms = ModelTerms {
        saturation_current_a: 1.0,
        ..ModelTerms::NONE
    };
    let table = Table::with_terms(&entries, terms).unwrap();
    let i = Arming::new(&table, M_KG, G, 12.0, 2.5).stop_current_a(2.24);
    assert!((i - 0.353_203).abs() < 1e-3, "{i}");
}

#[test]
fn beyond_the_fitted_stroke_the_force_is_held() {
    // 0–5 mm fitted, F = 100·x: 1250 N·mm inside, then 500 N for 7 mm.
    let mut e = linear(0.0, 100.0, 0.0);
    e.x_max_mm = 5.0;
    let w = compression_work_j(&e, 12.0);
    assert!((w - (1.25 + 3.5)).abs() < 1e-5, "{w}");
    // Fitted from 2 mm: 200 N below it, over 2 mm: 0.4 J, then 2–12 mm
    // of 100·x: (144 − 4)/2·100 N·mm = 7 J.
    let mut e = linear(0.0, 100.0, 0.0);
    e.x_min_mm = 2.0;
    let w = compression_work_j(&e, 12.0);
    assert!((w - 7.4).abs() < 1e-4, "{w}");
}

#[test]
fn lead_time_is_the_first_order_rise_at_the_supply_limit() {
    // 20 ms coil from 0.5 A to 1.5 A at +3 A drive: 20 ms·ln(2.5/1.5) = 10.2165 ms.
    let t = lead_time_s(0.02, 0.5, 1.5, -3.0, 3.0);
    assert!((t - 0.010_216_5).abs() < 1e-5, "{t}");
    // Down from 1.5 A to 0.5 A at −3 A: 20 ms·ln(4.5/3.5) = 5.0262 ms.
    let t = lead_time_s(0.02, 1.5, 0.5, -3.0, 3.0);
    assert!((t - 0.005_026_2).abs() < 1e-5, "{t}");
    // Beyond the supply: never.
    assert_eq!(lead_time_s(0.02, 0.0, 3.5, -3.0, 3.0), f32::INFINITY);
    assert_eq!(lead_time_s(0.02, 1.0, 1.0, -3.0, 3.0), 0.0);
}
