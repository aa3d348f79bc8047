//! The building blocks: current interpolation weights, reversal detection,
//! the coil lag, and the velocity noise behind the branch-ambiguity mask.
use crate::diagnose_support;
use diagnose_support::{dataset_with_steps, lagged_step_a, Added, SAMPLE_PERIOD_S, STEPS_A, STEP_SAMPLE};
use mre_host::diagnose::design::effective_current_a;
use mre_host::diagnose::prepared::{prepare, velocity_noise_m_s, FoldPlan};
use mre_host::diagnose::signals::{current_weights, memory_feature};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

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

#[test]
fn the_effective_current_follows_a_step_through_the_coil_lag() {
    let ds = dataset_with_steps(Added::None, 1);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 3 }, &[]).expect("prepared");
    let rec = prep
        .recs
        .iter()
        .find(|r| r.file == "step0_i0-1.csv")
        .expect("step recording");
    let tau = 3.0 * SAMPLE_PERIOD_S;
    let lagged = effective_current_a(rec, Some(tau));
    // The recorded command switches at STEP_SAMPLE; the coil is taken to see it
    // half a sample earlier (mid-interval), then 1 − e^{−t/τ}.
    let t_step = (STEP_SAMPLE as f64 - 0.5) * SAMPLE_PERIOD_S;
    let (from, to) = STEPS_A[0];
    for k in [
        0,
        STEP_SAMPLE - 1,
        STEP_SAMPLE,
        STEP_SAMPLE + 1,
        STEP_SAMPLE + 3,
        STEP_SAMPLE + 10,
    ] {
        let t = k as f64 * SAMPLE_PERIOD_S;
        let want = lagged_step_a(from, to, t, t_step, tau);
        assert!((lagged[k] - want).abs() < 1e-9, "sample {k}: {} vs {want}", lagged[k]);
    }
    // By hand: one and a half samples after the switch, 1 − e^{−0.5} of the step.
    assert!((lagged[STEP_SAMPLE + 1] - (1.0 - (-0.5f64).exp())).abs() < 1e-9);
    // Without a lag the recorded current is used as it is.
    assert_eq!(effective_current_a(rec, None)[STEP_SAMPLE], to);
}

#[test]
fn velocity_noise_is_estimated_from_the_channel_itself() {
    // A 1 m/s, 100 Hz sinusoid sampled at 20 kHz plus 3 mm/s white noise.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let noise = Normal::new(0.0, 0.003).expect("valid");
    let v: Vec<f64> = (0..4000)
        .map(|i| (2.0 * std::f64::consts::PI * 100.0 * i as f64 / 20_000.0).sin() + noise.sample(&mut rng))
        .collect();
    let sigma = velocity_noise_m_s(&v);
    assert!((sigma - 0.003).abs() < 0.0003, "sigma {sigma}");
    // A clean signal has (almost) none.
    let clean: Vec<f64> = (0..4000).map(|i| (i as f64 * 1e-3).sin()).collect();
    assert!(velocity_noise_m_s(&clean) < 1e-6);
}

#[test]
fn samples_whose_branch_is_chance_are_neither_fitted_nor_scored() {
    let ds = dataset_with_steps(Added::None, 2);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 3 }, &[]).expect("prepared");
    for r in &prep.recs {
        let limit = 2.0 * r.velocity_noise_m_s;
        for t in 0..r.len() {
            if r.v_m_s[t].abs() < limit {
                assert!(!r.in_domain[t], "{} sample {t}", r.file);
            }
        }
    }
    // The support data have noise-free kinematics: nothing is ambiguous but an exact zero.
    assert!(prep.recs.iter().all(|r| r.n_branch_ambiguous() <= 1));
}

/// Softening is a crossed effect: a drift over the run order is told from a
/// difference between test conditions only where a condition is repeated at
/// another place in the run.
#[test]
fn softening_is_identifiable_only_where_a_test_condition_is_repeated_in_the_run() {
    use mre_host::diagnose::acceptance::Thresholds;
    use mre_host::diagnose::candidates::{conditions, identifiable, Effect};
    // 3 currents × 3 strokes × 2 repeats, the run order shuffled: 9
    // conditions, each run twice.
    let ds = diagnose_support::dataset(Added::None, 1);
    let prep = prepare(&ds, &FoldPlan::Stratified { k: 3 }, &[]).expect("prepared");
    let c = conditions(&prep);
    let mut distinct = c.clone();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), 9, "{c:?}");
    assert!(
        distinct.iter().all(|k| c.iter().filter(|x| *x == k).count() == 2),
        "{c:?}"
    );
    assert!(identifiable(&prep, Effect::StressSoftening, &Thresholds::default()).is_ok());
    // The outside-class campaign runs each test once per current (four
    // sinusoids of different stroke or speed, a multisine, a drop), in a
    // shuffled order: nothing is repeated, but each sinusoid runs 3 cycles,
    // enough for the decline within a test.
    let mut case = mre_host::plant::outside::case(Effect::StressSoftening, 1).expect("campaign");
    let plan = FoldPlan::Stratified { k: 5 };
    let validate = [mre_host::plant::outside::VALIDATE_CURRENT_A];
    let prep = prepare(&case.dataset, &plan, &validate).expect("prepared");
    assert!(identifiable(&prep, Effect::StressSoftening, &Thresholds::default()).is_ok());
    // Without the multisines, each sinusoid cut to its first 2.5 cycles (5/6
    // of its 3-cycle length), and the run order not recorded: too few
    // cycles, nothing repeated, and no strain history to compare runs by.
    case.dataset.recordings.retain(|r| !r.file.contains("multisine"));
    for r in &mut case.dataset.recordings {
        r.sequence = None;
        let keep = (r.samples.time_s.len() * 5) / 6;
        let s = &mut r.samples;
        for v in [&mut s.time_s, &mut s.x_mm, &mut s.v_m_s, &mut s.force_n] {
            v.truncate(keep);
        }
        for v in [&mut s.accel_m_s2, &mut s.current_a, &mut s.temperature_c]
            .into_iter()
            .flatten()
        {
            v.truncate(keep);
        }
    }
    let prep = prepare(&case.dataset, &plan, &validate).expect("prepared");
    let why = identifiable(&prep, Effect::StressSoftening, &Thresholds::default()).unwrap_err();
    assert!(
        why.contains("repeated") && why.contains("cycles") && why.contains("strain history"),
        "{why}"
    );
}
