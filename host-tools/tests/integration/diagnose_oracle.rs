//! The real-data benchmark's oracle (`diagnose_bench::oracle`): the reference
//! model given the true injected force as a column with a free amplitude.
//! On a set whose only misfit is that column plus a pattern no column can
//! follow, the held-out ratio is known by hand; on `none` it is 1.
use crate::diagnose_support;

use mre_host::dataset::{Dataset, Role, Samples};
use mre_host::diagnose::acceptance::Thresholds;
use mre_host::diagnose::design::Terms;
use mre_host::diagnose::prepared::{prepare, FoldPlan};
use mre_host::diagnose_bench::oracle::{oracle, Amplitude};
use mre_host::vocabulary::Effect;
use std::f64::consts::PI;

const SIGMA_N: f64 = 5.0;
/// Amplitude of the injected column (unit RMS): k = √3·σ, so the reference's
/// held-out error is √(σ² + k²) = 2σ and the oracle's σ: a ratio of 2.
const K_N: f64 = 8.660_254_037_844_386;
const SAMPLES: usize = 2000;

/// The injected column: (−1)^t, unit RMS. The unfittable rest: σ·(+1, +1,
/// −1, −1, …), orthogonal to it over every four samples. Both alternate far
/// faster than x, so the branch quartics (smooth in x over half cycles)
/// absorb next to nothing of either.
fn column(t: usize) -> f64 {
    if t.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    }
}

fn rest(t: usize) -> f64 {
    if t % 4 < 2 {
        SIGMA_N
    } else {
        -SIGMA_N
    }
}

/// Sinusoids x = A·sin ωt, F = 100 N/mm·x (inside the model class) at 0 A
/// and 1 A, three amplitudes each (fit), and two 0.5 A validate recordings.
/// `added(role, t)` is added to each force and returned per recording.
fn set(added: &dyn Fn(Role, usize) -> f64) -> (Dataset, Vec<Vec<f64>>) {
    let dt = 1e-3;
    let w = 2.0 * PI * 2.0;
    let mut recordings = Vec::new();
    let mut injected = Vec::new();
    let runs = [
        (0.0, 5.0),
        (0.0, 10.0),
        (0.0, 15.0),
        (1.0, 5.0),
        (1.0, 10.0),
        (1.0, 15.0),
        (0.5, 8.0),
        (0.5, 12.0),
    ];
    for (k, (current_a, amp_mm)) in runs.into_iter().enumerate() {
        let role = if current_a == 0.5 { Role::Validate } else { Role::Fit };
        let time_s: Vec<f64> = (0..SAMPLES).map(|i| i as f64 * dt).collect();
        let x_mm: Vec<f64> = time_s.iter().map(|t| amp_mm * (w * t).sin()).collect();
        let add: Vec<f64> = (0..SAMPLES).map(|t| added(role, t)).collect();
        let mut r = diagnose_support::fit_recording(
            format!("r{k}.csv"),
            current_a,
            Samples {
                v_m_s: time_s.iter().map(|t| 1e-3 * amp_mm * w * (w * t).cos()).collect(),
                force_n: x_mm
                    .iter()
                    .enumerate()
                    .map(|(t, x)| 100.0 * x + rest(t) + add[t])
                    .collect(),
                x_mm,
                time_s,
                ..Samples::default()
            },
        );
        r.role = role;
        recordings.push(r);
        injected.push(add);
    }
    (
        Dataset {
            name: "oracle".into(),
            root: Default::default(),
            recordings,
        },
        injected,
    )
}

fn run(added: &dyn Fn(Role, usize) -> f64, _effect: Effect) -> mre_host::diagnose_bench::oracle::Oracle {
    let (ds, injected) = set(added);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 3 }, &[]).unwrap();
    oracle(
        &prep,
        &Terms::default(),
        &injected,
        &Thresholds::default(),
        Amplitude::Shared,
    )
    .unwrap()
}

#[test]
fn the_oracle_recovers_a_column_that_is_exactly_the_misfit() {
    let o = run(&|_, t| K_N * column(t), Effect::SensorDelay);
    // √(σ² + k²)/σ = √(1 + 3) = 2, up to the little the quartics take of
    // the alternating patterns.
    assert!((o.held_out_ratio - 2.0).abs() < 0.02, "{o:?}");
    assert!((o.held_out_ratio_all - 2.0).abs() < 0.02, "{o:?}");
    // The amplitude is the injected RMS (the column has unit RMS).
    assert!((o.amplitude_rms_n - K_N).abs() < 0.01 * K_N, "{o:?}");
    assert!(o.passes_gain, "{o:?}");
}

#[test]
fn a_column_only_on_validate_recordings_is_judged_on_them() {
    // Added to the two 0.5 A validate recordings only: the amplitude is
    // chosen leave-one-validate-recording-out, the same k on both.
    let o = run(
        &|role, t| if role == Role::Validate { K_N * column(t) } else { 0.0 },
        Effect::MagneticSaturation,
    );
    assert!((o.held_out_ratio - 2.0).abs() < 0.02, "{o:?}");
    // The injected RMS over every sample: k on two recordings of eight, k/2.
    assert!((o.amplitude_rms_n - K_N / 2.0).abs() < 0.01 * K_N, "{o:?}");
    // Over every recording the fit ones (residual σ either way) dilute it:
    // √((6σ² + 2·4σ²)/(8σ²)) = √(14/8).
    assert!((o.held_out_ratio_all - (14.0f64 / 8.0).sqrt()).abs() < 0.02, "{o:?}");
}

#[test]
fn on_none_the_oracle_gains_nothing() {
    let o = run(&|_, _| 0.0, Effect::None);
    assert_eq!(o.held_out_ratio, 1.0, "{o:?}");
    assert_eq!(o.held_out_ratio_all, 1.0, "{o:?}");
    assert!(!o.passes_gain, "{o:?}");
}
