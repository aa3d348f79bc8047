//! `mre fit` and `mre diagnose` split samples into branches by one rule
//! (`signal::clear_branch` with the recording's own `branch_band_m_s`), so on
//! the same data they fit the same samples and report the same baseline.
use crate::diagnose_support;

use mre_host::dataset::{split_branches, Dataset, Samples};
use mre_host::diagnose::baseline::{fit_table, predict_all};
use mre_host::diagnose::prepared::{prepare, FoldPlan};
use mre_host::fit::problems::branch_problems;
use mre_host::fit::{fit_branches, FitOptions, Method};
use std::path::PathBuf;

/// A ramp v_n = −0.05 + 0.001·n m/s (n = 0..100) plus ε·(−1)ⁿ, ε = 1 mm/s.
/// Its second difference is 4ε·(−1)ⁿ everywhere, so the white-noise estimate
/// is 1.4826·4ε/√6 = 2.421 mm/s and the band 2σ = 4.842 mm/s. By hand:
/// even n give v = (n − 49) mm/s, odd n give v = (n − 51) mm/s; |v| < 4.842
/// for n ∈ {46, 48, 50, 52} and {47, 49, 51, 53, 55}: 9 samples left out.
/// Compression (v ≥ 5 mm/s): even 54..=100 (24) and odd 57..=99 (22) = 46.
/// Extension (v ≤ −5 mm/s): even 0..=44 (23) and odd 1..=45 (23) = 46.
fn ramp_samples() -> Samples {
    let n = 101;
    let v_m_s: Vec<f64> = (0..n)
        .map(|i| -0.05 + 0.001 * i as f64 + if i % 2 == 0 { 0.001 } else { -0.001 })
        .collect();
    Samples {
        time_s: (0..n).map(|i| i as f64 * 1e-3).collect(),
        x_mm: (0..n).map(|i| i as f64 * 0.1).collect(),
        force_n: (0..n).map(|i| 10.0 * i as f64).collect(),
        v_m_s,
        ..Samples::default()
    }
}

#[test]
fn samples_inside_the_band_are_exactly_those_left_out() {
    let s = ramp_samples();
    let (compression, extension) = split_branches(&s);
    assert_eq!((compression.len(), extension.len()), (46, 46));
    // The kept samples are those with |v| ≥ 5 mm/s, each on its sign's branch.
    let kept: Vec<f64> = compression.x_mm.iter().chain(&extension.x_mm).copied().collect();
    for (i, &v) in s.v_m_s.iter().enumerate() {
        let x = s.x_mm[i];
        let in_band = v.abs() < 0.0045;
        assert_eq!(kept.contains(&x), !in_band, "sample {i}, v = {v}");
        if !in_band {
            let on_compression = compression.x_mm.contains(&x);
            assert_eq!(on_compression, v > 0.0, "sample {i}, v = {v}");
        }
    }
    // `diagnose` leaves out the same nine.
    let ds = Dataset {
        name: "ramp".into(),
        root: PathBuf::new(),
        recordings: vec![diagnose_support::fit_recording("ramp.csv".into(), 0.0, s)],
    };
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 1 }, &[]).unwrap();
    let scored = prep.recs[0].scored_mask(None);
    assert_eq!(scored.iter().filter(|&&m| !m).count(), 9);
}

/// Two currents, three sinusoidal recordings each, hysteresis of ±F0 about a
/// stiffness line, and white noise on the measured velocity: near every
/// turn-around the measured sign of v is chance and a sample there can sit
/// 2·F0 off its branch.
fn noisy_velocity_set(seed: u64) -> Dataset {
    const DT_S: f64 = 1e-3;
    const F0_N: f64 = 300.0;
    let sinusoid = |amp_mm: f64, freq_hz: f64| {
        let w = 2.0 * std::f64::consts::PI * freq_hz;
        let n = (2.0 / freq_hz / DT_S) as usize;
        let time_s: Vec<f64> = (0..n).map(|i| i as f64 * DT_S).collect();
        let x_mm = time_s.iter().map(|t| amp_mm * (w * t).sin()).collect();
        let v_m_s = time_s.iter().map(|t| 1e-3 * amp_mm * w * (w * t).cos()).collect();
        (time_s, x_mm, v_m_s)
    };
    let hysteretic = |x_mm: &[f64], v_m_s: &[f64], current_a: f64| -> Vec<f64> {
        let k = 40.0 + 30.0 * current_a;
        x_mm.iter()
            .zip(v_m_s)
            .map(|(x, v)| k * x + 0.2 * x * x + F0_N * (1.0 + current_a) * v.signum())
            .collect()
    };
    diagnose_support::Campaign {
        name: "noisy velocity",
        currents_a: &[0.0, 1.0],
        tests: &[(4.0, 1.0), (8.0, 0.5), (12.0, 0.5)],
        noise_n: 2.0,
        v_noise_m_s: 0.003,
        seed,
    }
    .build(sinusoid, hysteretic)
}

#[test]
fn fit_and_diagnose_report_the_same_baseline_on_noisy_velocity() {
    let ds = noisy_velocity_set(7);

    // `mre fit`: one lsq quartic per (current, branch); the pooled RMSE.
    let options = FitOptions {
        method: Method::Lsq,
        ..Default::default()
    };
    let fits = fit_branches(&branch_problems(&ds).unwrap(), &options).unwrap();
    let fit_n: usize = fits.iter().map(|b| b.samples).sum();
    let fit_se: f64 = fits.iter().map(|b| b.samples as f64 * b.chosen.rmse_n.powi(2)).sum();
    let fit_rmse_n = (fit_se / fit_n as f64).sqrt();

    // `mre diagnose`: the baseline table over its scored samples (as
    // report.json's `baseline.rmse_n`, all recordings being fit recordings).
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 5 }, &[]).unwrap();
    let table = fit_table(&prep).unwrap();
    let pred = predict_all(&prep, &table);
    let (mut se, mut n) = (0.0, 0usize);
    for (r, p) in prep.recs.iter().zip(&pred) {
        for ((f, q), m) in r.force_n.iter().zip(p).zip(r.scored_mask(None)) {
            if m {
                se += (f - q).powi(2);
                n += 1;
            }
        }
    }
    let diagnose_rmse_n = (se / n as f64).sqrt();

    let total: usize = ds.recordings.iter().map(|r| r.samples.len()).sum();
    assert!(n < total, "the set must have samples inside the band");
    assert_eq!(fit_n, n, "fit and diagnose must score the same samples");
    // Same samples, same least-squares problem: the RMSEs differ only by the
    // f32 table diagnose predicts through.
    assert!(
        (fit_rmse_n - diagnose_rmse_n).abs() <= 1e-3 * diagnose_rmse_n,
        "fit {fit_rmse_n} N, diagnose {diagnose_rmse_n} N"
    );
}
