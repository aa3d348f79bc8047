//! `mre bench-diagnose --real`: the injections realise the strength they
//! claim, in time units whatever the sampling rate, at either end of a
//! two-sided stroke, with the physics' laws (Hunt–Crossley contact, Mullins
//! damage), not the estimator's shapes. Expected values from closed forms of
//! sinusoids and the published laws, by hand.
use crate::diagnose_support;

use mre_host::dataset::{Dataset, Samples};
use mre_host::diagnose::DiagnoseOptions;
use mre_host::diagnose_bench::real::{acceleration_from_x, added_force_n, force_rms_n, inject};
use mre_host::vocabulary::Effect;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

const AMP_MM: f64 = 10.0;
const F_HZ: f64 = 1.0;

/// Sinusoidal strokes about the middle: x = A·sin ωt, F = 100 N/mm · x, at
/// 1 ms and 5 ms sampling, two currents.
fn sinusoid_set() -> Dataset {
    let w = 2.0 * PI * F_HZ;
    let mut recordings = Vec::new();
    for (k, (dt, current_a)) in [(1e-3, 0.0), (5e-3, 0.0), (1e-3, 1.0), (5e-3, 1.0)]
        .into_iter()
        .enumerate()
    {
        let n = (10.0 / F_HZ / dt) as usize;
        let time_s: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
        let x_mm: Vec<f64> = time_s.iter().map(|t| AMP_MM * (w * t).sin()).collect();
        recordings.push(diagnose_support::fit_recording(
            format!("r{k}.csv"),
            current_a,
            Samples {
                v_m_s: time_s.iter().map(|t| 1e-3 * AMP_MM * w * (w * t).cos()).collect(),
                force_n: x_mm.iter().map(|x| 100.0 * x).collect(),
                x_mm,
                time_s,
                ..Samples::default()
            },
        ));
    }
    Dataset {
        name: "sinusoids".into(),
        root: Default::default(),
        recordings,
    }
}

#[test]
fn a_delay_is_injected_in_seconds_whatever_the_sampling_rate() {
    let ds = sinusoid_set();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let (out, inj) = inject(&ds, Effect::SensorDelay, 0.08, &mut rng, &DiagnoseOptions::default()).unwrap();
    // F(t − τ) − F(t) for F = F0·sin ωt has RMS F0·√2·sin(ωτ/2) against the
    // force RMS F0/√2: strength 2·sin(ωτ/2), so τ = 2·asin(s/2)/ω.
    let expected_s = 2.0 * (0.08f64 / 2.0).asin() / (2.0 * PI * F_HZ);
    let tau = inj.parameters["delay_s"];
    assert!(
        (tau - expected_s).abs() < 0.02 * expected_s,
        "τ = {tau}, expected {expected_s}"
    );
    // The same delay in seconds at 1 ms and at 5 ms: each recording's force
    // at t equals the original at t − τ (checked away from the start).
    for (r, o) in ds.recordings.iter().zip(&out.recordings) {
        let s = &r.samples;
        let w = 2.0 * PI * F_HZ;
        for i in (s.len() / 2..s.len()).step_by(37) {
            let want = 100.0 * AMP_MM * (w * (s.time_s[i] - tau)).sin();
            // Linear interpolation error ≤ F0·(ω·dt)²/8.
            assert!(
                (o.samples.force_n[i] - want).abs() < 1.0,
                "{}: {} vs {want}",
                r.file,
                o.samples.force_n[i]
            );
        }
    }
    assert!((inj.achieved_strength - 0.08).abs() < 1e-3);
}

#[test]
fn acceleration_from_displacement_follows_the_sinusoid() {
    let ds = sinusoid_set();
    let w = 2.0 * PI * F_HZ;
    for r in &ds.recordings {
        let a = acceleration_from_x(&r.samples.time_s, &r.samples.x_mm, 5e-3);
        for i in (10..r.samples.len() - 10).step_by(53) {
            let want = -1e-3 * AMP_MM * w * w * (w * r.samples.time_s[i]).sin();
            // A ±5 ms second difference of a 1 Hz sinusoid: error ≈ (ωh)²/12 ≈ 0.01 %.
            assert!(
                (a[i] - want).abs() < 1e-3 * 0.4 + 1e-6,
                "{}: {} vs {want}",
                r.file,
                a[i]
            );
        }
    }
}

#[test]
fn end_stops_act_at_either_end_with_the_requested_strength() {
    let ds = sinusoid_set();
    let rms = force_rms_n(&ds);
    let mut sides = Vec::new();
    for seed in 0..12 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (out, inj) = inject(&ds, Effect::EndStop, 0.05, &mut rng, &DiagnoseOptions::default()).unwrap();
        let x_e = inj.parameters["x_e_mm"];
        let lower = inj.parameters["lower_end"] == 1.0;
        sides.push(lower);
        assert_eq!(lower, x_e < 0.0);
        // 60–85 % of the stroke at that end.
        assert!(
            (0.6 * AMP_MM * 0.99..=0.85 * AMP_MM).contains(&x_e.abs()),
            "x_e = {x_e}"
        );
        // Hunt & Crossley (1975): F = k·δⁿ·(1 + α·δ̇), δ the penetration.
        let (k, expo, alpha) = (
            inj.parameters["k_n_per_mm_n"],
            inj.parameters["exponent"],
            inj.parameters["alpha_s_per_mm"],
        );
        assert!(
            (1.3..1.7).contains(&expo) && (0.002..0.01).contains(&alpha),
            "{:?}",
            inj.parameters
        );
        let side = if lower { -1.0 } else { 1.0 };
        let add = added_force_n(&ds, &out);
        let (mut s2, mut n) = (0.0, 0);
        for (r, a) in ds.recordings.iter().zip(&add) {
            for ((x, v), d) in r.samples.x_mm.iter().zip(&r.samples.v_m_s).zip(a) {
                let beyond = if lower { *x < x_e } else { *x > x_e };
                if beyond {
                    // The stop pushes back towards the middle.
                    assert!(if lower { *d < 0.0 } else { *d > 0.0 });
                    let (delta_mm, rate_mm_s) = ((x - x_e).abs(), side * 1e3 * v);
                    let expected = side * k * delta_mm.powf(expo) * (1.0 + alpha * rate_mm_s);
                    assert!(
                        (d - expected).abs() < 1e-9 * expected.abs().max(1.0),
                        "{d} vs {expected}"
                    );
                } else {
                    assert!(d.abs() < 1e-9);
                }
                s2 += d * d;
                n += 1;
            }
        }
        assert!(((s2 / n as f64).sqrt() / rms - 0.05).abs() < 1e-6);
    }
    assert!(sides.contains(&true) && sides.contains(&false), "{sides:?}");
}

#[test]
fn every_case_records_a_random_run_order_and_none_changes_no_force() {
    let ds = sinusoid_set();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (out, inj) = inject(&ds, Effect::None, 0.1, &mut rng, &DiagnoseOptions::default()).unwrap();
    assert_eq!(inj.achieved_strength, 0.0);
    assert!(added_force_n(&ds, &out).iter().flatten().all(|d| *d == 0.0));
    let mut order: Vec<u32> = out.recordings.iter().map(|r| r.sequence.unwrap()).collect();
    order.sort_unstable();
    assert_eq!(order, vec![1, 2, 3, 4]);
}

/// Softening is Mullins damage carried through the recorded run order, not
/// the estimator's law. Expected values from Ogden & Roxburgh (1999) and a
/// saturating cumulative damage, by hand: while the first test in run order
/// first loads to its largest stroke nothing is softened (no larger strain
/// yet, no cycle completed); at the last test's first peak (the largest
/// strain again, so no pseudo-elastic softening) only the cumulative damage
/// of the 3 × 10 cycles before it acts, `1 − depth·d_∞·(1 − e^{−30/N₀})`.
#[test]
fn softening_is_mullins_damage_in_run_order() {
    let ds = sinusoid_set();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (out, inj) = inject(
        &ds,
        Effect::StressSoftening,
        0.05,
        &mut rng,
        &DiagnoseOptions::default(),
    )
    .unwrap();
    let mut order: Vec<u32> = out.recordings.iter().map(|r| r.sequence.unwrap()).collect();
    order.sort_unstable();
    assert_eq!(order, vec![1, 2, 3, 4], "a permutation of the run");
    let p = &inj.parameters;
    let (depth, d_inf, n0) = (p["depth"], p["damage_d_inf"], p["damage_n0_cycles"]);
    assert!(
        depth > 0.0 && (0.05..0.2).contains(&d_inf) && (10.0..30.0).contains(&n0),
        "{p:?}"
    );
    let added = added_force_n(&ds, &out);
    let (s2, n) = added
        .iter()
        .flatten()
        .fold((0.0, 0usize), |(s, n), d| (s + d * d, n + 1));
    assert!(((s2 / n as f64).sqrt() / force_rms_n(&ds) - 0.05).abs() < 1e-9);
    for (r, a) in ds.recordings.iter().zip(&added) {
        for (f, d) in r.samples.force_n.iter().zip(a) {
            assert!(f * d <= 1e-12, "softening never stiffens: F {f}, added {d}");
        }
    }
    let by_order = |k: u32| out.recordings.iter().position(|r| r.sequence == Some(k)).unwrap();
    let first = by_order(1);
    let quarter = ds.recordings[first]
        .samples
        .time_s
        .iter()
        .take_while(|t| **t < 0.25 / F_HZ)
        .count();
    assert!(
        added[first][..quarter].iter().all(|d| *d == 0.0),
        "{:?}",
        &added[first][..quarter]
    );
    let last = by_order(4);
    let s = &ds.recordings[last].samples;
    let peak = s.time_s.iter().position(|t| (t - 0.25 / F_HZ).abs() < 1e-9).unwrap();
    let expected = -depth * d_inf * (1.0 - (-30.0 / n0).exp());
    let got = added[last][peak] / s.force_n[peak];
    assert!(
        (got - expected).abs() < 1e-6,
        "added/F at the last test's first peak {got}, expected {expected}"
    );
    assert!(got < -1e-3, "the cumulative damage shows");
}
