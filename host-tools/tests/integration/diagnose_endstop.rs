//! The end-stop term `k_e(I)·max(0, x − x_e)²` (or its mirror at the
//! extension end): one stiffness per tabulated current, never negative.
//! Expected values by construction: the recordings are exactly a line in x
//! per current plus the stop, which the model class holds.
use crate::diagnose_support;

use mre_host::dataset::{Dataset, Samples};
use mre_host::diagnose::design::{Designs, Terms};
use mre_host::diagnose::prepared::{prepare, FoldPlan};
use std::f64::consts::PI;

const X_E_MM: f64 = 15.0;

/// Sinusoids of 5, 10 and 20 mm at 0 and 1 A, F = s(I)·x + extra(I, x).
fn set(extra: &dyn Fn(f64, f64) -> f64) -> Dataset {
    let (f_hz, dt) = (1.0, 2e-3);
    let w = 2.0 * PI * f_hz;
    let mut recordings = Vec::new();
    for current_a in [0.0, 1.0] {
        for amp_mm in [5.0, 10.0, 20.0] {
            let n = (3.0 / f_hz / dt) as usize;
            let time_s: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
            let x_mm: Vec<f64> = time_s.iter().map(|t| amp_mm * (w * t).sin()).collect();
            let slope = 20.0 + 80.0 * current_a;
            recordings.push(diagnose_support::fit_recording(
                format!("a{amp_mm}_i{current_a}.csv"),
                current_a,
                Samples {
                    v_m_s: time_s.iter().map(|t| 1e-3 * amp_mm * w * (w * t).cos()).collect(),
                    force_n: x_mm.iter().map(|&x| slope * x + extra(current_a, x)).collect(),
                    x_mm,
                    time_s,
                    ..Samples::default()
                },
            ));
        }
    }
    Dataset {
        name: "stops".into(),
        root: Default::default(),
        recordings,
    }
}

/// The fitted stop stiffness per current (N/mm²) for a stop at `x_e`.
fn fitted_k(ds: &Dataset, x_e: f64, lower: bool) -> Vec<f64> {
    let prep = prepare(ds, &FoldPlan::Stratified { k: 3 }, &[]).unwrap();
    let terms = Terms {
        end_stop_x_mm: Some(x_e),
        end_stop_lower: lower,
        ..Terms::default()
    };
    let d = Designs::build(&prep, &terms);
    let sol = d.solve(&prep, &prep.fit_indices()).unwrap();
    let at = d
        .layout
        .at(mre_host::vocabulary::Effect::EndStop, 0)
        .expect("a stop column per current");
    (0..prep.currents_a.len()).map(|k| sol.beta[at + k]).collect()
}

fn stop(x_mm: f64, x_e: f64) -> f64 {
    (x_mm - x_e).max(0.0).powi(2)
}

#[test]
fn each_current_gets_its_own_stop_stiffness() {
    // 3 N/mm² at 0 A, 7 N/mm² at 1 A: a shared k_e could not give both.
    let ds = set(&|i, x| if i == 0.0 { 3.0 } else { 7.0 } * stop(x, X_E_MM));
    let k = fitted_k(&ds, X_E_MM, false);
    assert!((k[0] - 3.0).abs() < 1e-6 && (k[1] - 7.0).abs() < 1e-6, "{k:?}");
}

#[test]
fn a_stop_never_pulls_a_current_that_softens_at_the_end_gets_none() {
    // At 1 A the force falls below the line beyond x_e (−2·(x − x_e)²): a
    // stop cannot pull, so that current's stiffness is 0, not −2, and the
    // 0 A stop (4 N/mm²) is still recovered exactly (the currents' columns
    // are separate blocks of the least-squares problem).
    let ds = set(&|i, x| if i == 0.0 { 4.0 } else { -2.0 } * stop(x, X_E_MM));
    let k = fitted_k(&ds, X_E_MM, false);
    assert!((k[0] - 4.0).abs() < 1e-6, "{k:?}");
    assert_eq!(k[1], 0.0, "{k:?}");
    // Unconstrained, 1 A would have taken a negative stiffness: with only
    // the 1 A softening in the data, no current gets a stop at all. The 0 A
    // data are exactly a line, so its stop's least-squares value is 0 up to
    // round-off, whose sign decides whether the bound holds it at exactly 0
    // (after e31e445's Qᵀ·y it comes out +3.6e-15): 0 within 1e-9 N/mm².
    let ds = set(&|i, x| if i == 0.0 { 0.0 } else { -2.0 } * stop(x, X_E_MM));
    let k = fitted_k(&ds, X_E_MM, false);
    assert_eq!(k[1], 0.0, "{k:?}");
    assert!(k[0].abs() < 1e-9, "{k:?}");
}

#[test]
fn a_stop_at_the_extension_end_pushes_towards_the_middle() {
    // −k·(x_e − x)² below x_e = −15 mm, 5 N/mm² at both currents.
    let ds = set(&|_, x| -5.0 * (-X_E_MM - x).max(0.0).powi(2));
    let k = fitted_k(&ds, -X_E_MM, true);
    assert!(k.iter().all(|k| (k - 5.0).abs() < 1e-6), "{k:?}");
}
