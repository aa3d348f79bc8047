//! `sensor_delay` on shaker/MTS campaigns from rate-independent base laws:
//! no delay where there is none, the true one where there is, on campaigns
//! none of the rules was tuned on.
use mre_host::diagnose::design::memory_feature_on_branches;
use mre_host::diagnose::{diagnose, options_from_cli, Diagnosis};
use mre_host::plant::base_laws::Hysteresis;
use mre_host::plant::synth_mts::{draw_law, synthesize_mts_with, MtsEffect};

fn names(d: &Diagnosis) -> Vec<&'static str> {
    d.findings.iter().map(|f| f.effect.name()).collect()
}

/// Seeds no rule was tuned or debugged on: `mre bench-diagnose` draws its
/// MTS cases from 1 000 000 + k, and the calibration set from its own
/// streams; these campaigns were first run when this test was written.
const FRESH_SEEDS: [u64; 2] = [7_300_011, 7_300_012];

/// An MTS campaign (as `mre bench-diagnose --mts-cases`: whole frequencies
/// held out, 0.5 A validate) on the base law of `seed` forced to `kind`,
/// with `effect` concealed.
fn diagnose_mts(kind: Hysteresis, effect: MtsEffect, seed: u64) -> Diagnosis {
    let mut law = draw_law(seed);
    law.hysteresis = kind;
    let out = synthesize_mts_with(&law, &effect, seed).unwrap();
    let opts = options_from_cli(None, Some("frequency_hz".into()), 5, vec![0.5], 1).unwrap();
    diagnose(&out.dataset, &opts).unwrap()
}

/// A slow turn-around at x = 10 mm (t = 0.5 s) whose measured v flips sign
/// inside the noise band for a few samples before and after the extreme.
fn slow_turn_with_flips() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (dt, w, amp) = (5e-3, std::f64::consts::PI, 10.0);
    let t: Vec<f64> = (0..200).map(|k| k as f64 * dt).collect();
    let x: Vec<f64> = t.iter().map(|t| amp * (w * t).sin()).collect();
    let mut v: Vec<f64> = t.iter().map(|t| 1e-3 * amp * w * (w * t).cos()).collect();
    // Samples 96 … 104 straddle the extreme (sample 100): ±0.4 mm/s noise,
    // alternating in sign, inside a 0.6 mm/s band.
    for (k, vk) in v.iter_mut().enumerate().take(105).skip(96) {
        *vk = if k % 2 == 0 { 0.4e-3 } else { -0.4e-3 };
    }
    (t, x, v)
}

#[test]
fn sign_flips_inside_the_noise_band_are_not_turn_arounds() {
    let (t, x, v) = slow_turn_with_flips();
    // One reversal, after the last flip: every sample from there on is
    // anchored at the same point, within the travel of the samples inside
    // the band around the extreme: 10·cos(π·0.02) = 9.980 mm ≤ x_r ≤ 10 mm.
    let (feature, compressing) = memory_feature_on_branches(&t, &x, &v, 0.6e-3);
    let anchors: Vec<f64> = feature[105..].iter().map(|a| a.unwrap().x_r_mm).collect();
    assert!(
        anchors.iter().all(|x_r| *x_r == anchors[0]),
        "re-anchored after the turn"
    );
    assert!(anchors[0] >= 9.98 && anchors[0] <= 10.0, "x_r {}", anchors[0]);
    // Compressing (v > 0) up to the extreme; the flips inside the band keep
    // it, and the first sample beyond −0.6 mm/s switches it.
    assert!(compressing[95] && compressing[103] && !compressing[105]);
    // Until then the test is still on its first stroke (it started at
    // speed, so there is no anchor before the first turn-around).
    assert!(feature[104].is_none());
    // Switching on every sign change (no band) re-anchors at each flip: the
    // sample after the last one sits on an anchor 0.01 mm from it, as if the
    // material had just turned around.
    let (feature, _) = memory_feature_on_branches(&t, &x, &v, 0.0);
    assert!(feature[104].unwrap().distance_mm < 0.01);
    assert!(feature[97].unwrap().x_r_mm != feature[99].unwrap().x_r_mm);
}

#[test]
fn no_delay_is_named_on_fresh_campaigns_of_either_law() {
    for kind in [Hysteresis::Dahl, Hysteresis::BoucWen] {
        for seed in FRESH_SEEDS {
            let d = diagnose_mts(kind, MtsEffect::None, seed);
            assert!(
                !names(&d).contains(&"sensor_delay"),
                "{kind:?} seed {seed}: {:?}",
                names(&d)
            );
        }
    }
}

#[test]
fn a_true_lag_is_found_as_a_lag_of_its_size_on_a_fresh_bouc_wen_campaign() {
    a_true_lag_is_found_as_a_lag_of_its_size(&[(Hysteresis::BoucWen, FRESH_SEEDS[1], 6.7e-3)]);
}

/// Found by the greedy method, missed by the joint fit at `fee4611` (the
/// turn-around memory basis took the lag); found again at `afde157`, with
/// the memory columns of either form, so it runs in every `cargo test`.
#[test]
fn a_true_lag_is_found_as_a_lag_of_its_size_on_a_fresh_dahl_campaign() {
    a_true_lag_is_found_as_a_lag_of_its_size(&[(Hysteresis::Dahl, FRESH_SEEDS[0], 4.3e-3)]);
}

fn a_true_lag_is_found_as_a_lag_of_its_size(cases: &[(Hysteresis, u64, f64)]) {
    // Off the search grid (whole samples, then quarter samples) and inside
    // the synthesiser's 3–8 ms range; a lag, so a sign error in the design's
    // time shift (x(t + τ) for x(t − τ)) reports a lead and fails.
    for &(kind, seed, delay_s) in cases {
        let d = diagnose_mts(kind, MtsEffect::SensorDelay { delay_s }, seed);
        let f = d
            .findings
            .iter()
            .find(|f| f.effect.name() == "sensor_delay")
            .unwrap_or_else(|| panic!("{kind:?} seed {seed}: no delay in {:?}", names(&d)));
        let tau_s = f.parameters["tau_s"].value;
        // Within a factor 2: on a Bouc–Wen law the memory basis only
        // approximates the loop's turn-around and the delay takes up part of
        // that misfit (DIAGNOSE.md, "Known limits").
        assert!(
            tau_s > 0.5 * delay_s && tau_s < 2.0 * delay_s,
            "{kind:?} seed {seed}: τ {tau_s} vs {delay_s}"
        );
    }
}

/// Evidence: a physics-written outside-class plant (`plant::outside`: a
/// 200 Hz Butterworth anti-aliasing filter and a transport delay on the force
/// channel, fractional generalized-Maxwell base law), tuning seed 7282 of the
/// delay helper. The lag is found, at the size of the filter's DC group delay
/// plus the delay (√2/ω_c + τ, by hand 1.13 + 6.35 ms). Before the library
/// dropped a net-negative sign-constrained group, viscous damping fitted with
/// c < 0 (a lagged spring is −τ·k·v) stood in for the lag: nested 1.02×,
/// `inconclusive`.
#[test]
fn an_anti_aliasing_filter_and_transport_delay_outside_the_model_class_is_named() {
    use mre_host::diagnose::DiagnoseOptions;
    use mre_host::diagnose_bench::outside::options;
    use mre_host::plant::outside::{case, Concealed};
    use mre_host::vocabulary::Effect;
    let c = case(Effect::SensorDelay, 7282).expect("campaign");
    let Concealed::Delay(channel) = c.concealed else {
        panic!("not a delay plant: {:?}", c.concealed)
    };
    let lag_s = channel.dc_lag_s();
    let d = diagnose(&c.dataset, &options(&DiagnoseOptions::default())).expect("diagnosis");
    let f = d
        .findings
        .iter()
        .find(|f| f.effect.name() == "sensor_delay")
        .unwrap_or_else(|| panic!("no delay in {:?} ({})", names(&d), d.verdict.verdict.name()));
    let tau_s = f.parameters["tau_s"].value;
    assert!(tau_s > 0.5 * lag_s && tau_s < 2.0 * lag_s, "τ {tau_s} vs {lag_s}");
}
