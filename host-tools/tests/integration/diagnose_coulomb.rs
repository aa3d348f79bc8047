//! A term added as one file and one registry line (`coulomb_friction`) is
//! named from data whose friction is written from the physics, not from the
//! term's columns, and not named where there is none.
use crate::diagnose_support::Campaign;
use mre_host::diagnose::{diagnose, DiagnoseOptions};
use std::f64::consts::PI;

/// Sinusoids at 1 kHz over two cycles: x = A·sin(2πft) (mm), v = dx/dt (m/s).
fn motion(amp_mm: f64, freq_hz: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = (2.0 * 1000.0 / freq_hz) as usize;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
    let w = 2.0 * PI * freq_hz;
    let x = t.iter().map(|t| amp_mm * (w * t).sin()).collect();
    let v = t.iter().map(|t| amp_mm * w * (w * t).cos() * 1e-3).collect();
    (t, x, v)
}

/// A spring stiffening with current plus, with `friction`, dry friction at
/// the seal: `f_c(I)` once sliding, reached over a creep speed `v_s` as
/// `(2/π)·atan(v/v_s)` (an arctangent, not the term's tanh).
fn campaign(friction: bool, seed: u64) -> mre_host::dataset::Dataset {
    let tests = [(2.0, 0.5), (2.0, 2.0), (4.0, 1.0), (4.0, 4.0), (6.0, 0.5), (6.0, 2.0)];
    Campaign {
        name: "coulomb",
        currents_a: &[0.0, 0.5, 1.0],
        tests: &tests,
        noise_n: 1.0,
        v_noise_m_s: 0.0,
        seed,
    }
    .build(motion, |x, v, i| {
        let k_n_per_mm = 50.0 * (1.0 + i);
        let f_c_n = 30.0 + 60.0 * i;
        let v_s_m_s = 0.002;
        x.iter()
            .zip(v)
            .map(|(x, v)| {
                let dry = if friction {
                    f_c_n * (2.0 / PI) * (v / v_s_m_s).atan()
                } else {
                    0.0
                };
                k_n_per_mm * x + dry
            })
            .collect()
    })
}

fn named(d: &mre_host::diagnose::Diagnosis) -> Vec<&'static str> {
    d.findings.iter().map(|f| f.effect.name()).collect()
}

#[test]
fn coulomb_friction_is_named_where_the_seal_has_it() {
    let d = diagnose(&campaign(true, 1), &DiagnoseOptions::default()).expect("diagnosis");
    let found = named(&d);
    assert!(found.contains(&"coulomb_friction"), "{found:?}");
    let f = d
        .findings
        .iter()
        .find(|f| f.effect.name() == "coulomb_friction")
        .expect("named");
    assert!(f.heldout_improvement_nested >= d.thresholds.min_nested_gain, "{f:?}");
    assert!(f.inclusion_probability >= d.thresholds.min_inclusion, "{f:?}");
    // Not asserted: f_c itself. Far from rest f_c·tanh(v/v_c) is a constant
    // per branch, which the quartics hold too, so only the transition pins
    // the split between them (a 90 N friction at 1 A came out as 26 N of
    // term plus the rest in the branch offsets).
}

#[test]
fn coulomb_friction_is_not_named_without_friction() {
    let d = diagnose(&campaign(false, 2), &DiagnoseOptions::default()).expect("diagnosis");
    assert!(!named(&d).contains(&"coulomb_friction"), "{:?}", named(&d));
}
