//! The building blocks: current interpolation weights and reversal detection.
use mre_host::diagnose::design::{current_weights, memory_feature};

#[test]
fn hat_weights_interpolate_linearly_between_tabulated_currents() {
    let c = [0.0, 0.5, 1.0];
    let w = current_weights(&c, 0.75, None);
    assert_eq!((w[0].0, w[1].0), (1, 2));
    assert!((w[0].1 - 0.5).abs() < 1e-12 && (w[1].1 - 0.5).abs() < 1e-12);
    // Clamped outside the table, like the core.
    assert_eq!(current_weights(&c, 2.0, None)[0], (2, 1.0));
}

#[test]
fn saturating_weights_follow_tanh() {
    // u = tanh(I/0.5): between 0 and 1 A, 0.5 A sits at tanh(1)/tanh(2) of the way.
    let w = current_weights(&[0.0, 1.0], 0.5, Some(0.5));
    let t = 1f64.tanh() / 2f64.tanh();
    assert!((w[1].1 - t).abs() < 1e-12, "{w:?}");
}

#[test]
fn reversals_are_found_on_displacement_not_noisy_velocity() {
    // Up to 5 mm and back, with a ±0.01 mm wiggle at the top.
    let mut x: Vec<f64> = (0..=50).map(|i| i as f64 * 0.1).collect();
    x.extend([4.99, 5.0, 4.99]);
    x.extend((0..=50).rev().map(|i| i as f64 * 0.1));
    let (feature, compressing) = memory_feature(&x, 0.5);
    // No reversal while loading; the one reversal is at the 5 mm peak.
    assert!(feature[..50].iter().all(|f| f.is_none()));
    let last = feature.last().expect("samples").expect("after the reversal");
    assert!((last.0 - 5.0).abs() < 1e-12, "distance from the reversal {}", last.0);
    assert!(!compressing[x.len() - 1] && compressing[10]);
}
