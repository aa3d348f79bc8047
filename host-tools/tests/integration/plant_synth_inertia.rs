//! `inertia` in drop campaigns (`docs/effects.md`): the load cell sits
//! above a striker of mass m_s and reads `F + m_s·a`. In a drop the mass
//! obeys `M·a = M·g − F`, so the recorded force is
//!
//!     F_meas = F·(1 − m_s/M) + m_s·g
//!
//! a scale on the force that depends on the drop mass only. These tests check
//! that closed form on the recordings (loading branches, where the base law
//! is exactly a cubic in x times a constant), that the accelerometer records
//! `a = g − F/M`, and that a single-mass campaign's key says inertia cannot
//! be identified there.
use mre_host::dataset::Recording;
use mre_host::plant::effects::{Effect, INSTRUMENTED_EFFECTS};
use mre_host::plant::synth::{
    key_identifiable, resolve_effect_name_for, synthesize, synthesize_with_plan, SynthOutput, SynthPlan,
};
use std::collections::BTreeSet;

const SEED: u64 = 7;
const G_M_S2: f64 = 9.81;
const HEAVY_KG: f64 = 5.5;
const LIGHT_KG: f64 = 2.75;

/// Least-squares `F = c0 + c1·x + c3·x³` over the loading branch (v > 0.3
/// m/s, away from the turn-around where the loss factor switches sign). The
/// base law's loading force is `G·(1 + η)·(k1·x + k3·x³)`, so with inertia the
/// recorded force is exactly this cubic: c0 = m_s·g, c1 and c3 scaled by
/// `1 − m_s/M`.
fn loading_cubic(r: &Recording) -> [f64; 3] {
    let s = &r.samples;
    let rows: Vec<(f64, f64)> = (0..s.len())
        .filter(|&k| s.v_m_s[k] > 0.3)
        .map(|k| (s.x_mm[k], s.force_n[k]))
        .collect();
    assert!(rows.len() >= 10, "{}: {} loading samples", r.file, rows.len());
    let a = nalgebra::DMatrix::from_fn(rows.len(), 3, |i, j| rows[i].0.powi([0, 1, 3][j]));
    let y = nalgebra::DVector::from_iterator(rows.len(), rows.iter().map(|r| r.1));
    let c = a.svd(true, true).solve(&y, 1e-12).expect("least squares");
    [c[0], c[1], c[2]]
}

/// The cubic's force without its constant, at `x_mm`.
fn elastic_n(c: [f64; 3], x_mm: f64) -> f64 {
    c[1] * x_mm + c[2] * x_mm.powi(3)
}

fn m_s_kg(out: &SynthOutput) -> f64 {
    out.key["parameters"]["m_s_kg"].as_f64().expect("m_s_kg in the key")
}

fn constant_current(out: &SynthOutput) -> impl Iterator<Item = &Recording> {
    out.dataset
        .recordings
        .iter()
        .filter(|r| !r.tags.contains_key("step_at_ms"))
}

/// Peak displacement of the loading branch (v > 0.3 m/s).
fn loading_stroke_mm(r: &Recording) -> f64 {
    r.samples
        .x_mm
        .iter()
        .zip(&r.samples.v_m_s)
        .filter(|(_, v)| **v > 0.3)
        .map(|(x, _)| *x)
        .fold(0.0, f64::max)
}

/// Ratio of the elastic force of each 5.5 kg drop to its 2.75 kg twin (same
/// current, the same rank of drop height), at 80 % of the shorter loading stroke.
fn heavy_over_light(out: &SynthOutput) -> Vec<(String, f64)> {
    let recs: Vec<&Recording> = constant_current(out).collect();
    let mut ratios = Vec::new();
    let mut currents: Vec<f64> = recs.iter().map(|r| r.current_a).collect();
    currents.sort_by(f64::total_cmp);
    currents.dedup();
    for current_a in currents {
        let of_mass = |m: f64| {
            let mut v: Vec<&Recording> = recs
                .iter()
                .copied()
                .filter(|r| r.current_a == current_a && r.mass_kg == Some(m))
                .collect();
            v.sort_by(|a, b| {
                a.impact_velocity_m_s
                    .unwrap()
                    .total_cmp(&b.impact_velocity_m_s.unwrap())
            });
            v
        };
        let (heavy, light) = (of_mass(HEAVY_KG), of_mass(LIGHT_KG));
        assert_eq!(heavy.len(), light.len(), "{current_a} A: one twin per drop height");
        for (h, l) in heavy.iter().zip(&light) {
            let x_mm = 0.8 * loading_stroke_mm(h).min(loading_stroke_mm(l));
            let (ch, cl) = (loading_cubic(h), loading_cubic(l));
            ratios.push((
                format!("{} / {}", h.file, l.file),
                elastic_n(ch, x_mm) / elastic_n(cl, x_mm),
            ));
        }
    }
    ratios
}

#[test]
fn instrumented_inertia_scales_each_drop_mass_by_one_minus_m_s_over_m() {
    let out = synthesize_with_plan("inertia", SEED, &SynthPlan::instrumented()).unwrap();
    let m_s = m_s_kg(&out);
    assert!((0.3..0.8).contains(&m_s), "m_s = {m_s} kg");
    assert!(key_identifiable(&out.key));
    // The closed form: (1 − m_s/5.5) / (1 − m_s/2.75), 1.08–1.29 over the drawn range.
    let expected = (1.0 - m_s / HEAVY_KG) / (1.0 - m_s / LIGHT_KG);
    let ratios = heavy_over_light(&out);
    assert_eq!(ratios.len(), 5 * 3 + 4 * 3, "one twin per current and drop height");
    // Force noise ≤ 15 N against ≥ 500 N at 80 % stroke, over ≥ 10 samples:
    // each ratio to well within 1 %.
    for (file, r) in &ratios {
        assert!(
            (r - expected).abs() < 0.01 * expected,
            "{file}: {r:.4}, expected {expected:.4}"
        );
    }
    // The constant is the striker's weight (the cell is tared with it hanging).
    let c0: Vec<f64> = constant_current(&out).map(|r| loading_cubic(r)[0]).collect();
    let mean_c0 = c0.iter().sum::<f64>() / c0.len() as f64;
    assert!(
        (mean_c0 - m_s * G_M_S2).abs() < 3.0,
        "mean constant {mean_c0:.2} N, m_s·g = {:.2} N",
        m_s * G_M_S2
    );
}

#[test]
fn without_inertia_both_drop_masses_follow_one_force_law() {
    // The control for the test above: the same comparison finds ratio 1.
    let out = synthesize_with_plan("none", SEED, &SynthPlan::instrumented()).unwrap();
    for (file, r) in heavy_over_light(&out) {
        assert!((r - 1.0).abs() < 0.01, "{file}: {r:.4}");
    }
}

#[test]
fn the_accelerometer_records_g_minus_force_over_mass() {
    let out = synthesize_with_plan("none", SEED, &SynthPlan::instrumented()).unwrap();
    let noise = |k: &str| out.key["measurement"][k].as_f64().unwrap();
    let sigma_a = out.key["accelerometer"]["noise_m_s2"].as_f64().unwrap();
    assert_eq!(out.dataset.recordings.len(), 60);
    for r in &out.dataset.recordings {
        let s = &r.samples;
        let a = s
            .accel_m_s2
            .as_ref()
            .unwrap_or_else(|| panic!("{}: no acceleration", r.file));
        let m = r.mass_kg.unwrap();
        // Newton on the drop mass: M·(g − a) = F, to the two channels' noise.
        let sigma = (noise("force_noise_n").powi(2) + (m * sigma_a).powi(2)).sqrt();
        let rms = (a
            .iter()
            .zip(&s.force_n)
            .map(|(a, f)| (m * (G_M_S2 - a) - f).powi(2))
            .sum::<f64>()
            / a.len() as f64)
            .sqrt();
        assert!(rms < 1.5 * sigma, "{}: {rms:.1} N against σ {sigma:.1} N", r.file);
        // The acceleration integrates to the velocity channel's change. The
        // trapezoid rule is off by up to half a step times the jump where the
        // force switches branch at the turn-around (a few µs against a 50 µs
        // sample), plus the channels' noise (≤ 0.01 m/s).
        let dt = s.time_s[1] - s.time_s[0];
        let jump = (1..a.len()).map(|k| (a[k] - a[k - 1]).abs()).fold(0.0, f64::max);
        let dv: f64 = (1..a.len())
            .map(|k| 0.5 * (a[k] + a[k - 1]) * (s.time_s[k] - s.time_s[k - 1]))
            .sum();
        let measured = s.v_m_s[s.len() - 1] - s.v_m_s[0];
        assert!(
            (dv - measured).abs() < 0.01 + 0.5 * jump * dt,
            "{}: ∫a dt = {dv:.4} m/s, Δv = {measured:.4} m/s",
            r.file
        );
    }
    // Constant-current tests alternate the two masses; the light one drops
    // from twice the height (the same impact energy: v × √2), so both reach
    // about the same stroke.
    let masses: BTreeSet<u64> = constant_current(&out).map(|r| r.mass_kg.unwrap().to_bits()).collect();
    assert_eq!(masses.len(), 2);
    let fastest = |m: f64| {
        constant_current(&out)
            .filter(|r| r.mass_kg == Some(m) && r.current_a == 0.0)
            .map(|r| r.impact_velocity_m_s.unwrap())
            .fold(0.0, f64::max)
    };
    let ratio = fastest(LIGHT_KG) / fastest(HEAVY_KG);
    assert!(
        (ratio - 2f64.sqrt()).abs() < 0.02,
        "light / heavy impact velocity {ratio:.3}"
    );
}

#[test]
fn single_mass_inertia_is_a_pure_scale_and_its_key_says_it_cannot_be_identified() {
    let with = synthesize("inertia", SEED).unwrap();
    let without = synthesize("none", SEED).unwrap();
    assert_eq!(with.plant.law, without.plant.law);
    assert!(!key_identifiable(&with.key));
    let why = with.key["not_identifiable_because"].as_str().unwrap();
    assert!(why.contains("a = g − F/M"), "{why}");
    assert!(key_identifiable(&without.key), "only inertia is marked");
    assert!(
        without.key.get("identifiable").is_none(),
        "plain keys keep their fields"
    );
    let m_s = m_s_kg(&with);
    let expected = 1.0 - m_s / HEAVY_KG;
    for (a, b) in constant_current(&with).zip(constant_current(&without)) {
        assert_eq!(a.file, b.file);
        assert!(a.samples.accel_m_s2.is_none(), "no accelerometer on a plain drop");
        let x_mm = 0.8 * b.samples.x_mm.iter().copied().fold(0.0, f64::max);
        let r = elastic_n(loading_cubic(a), x_mm) / elastic_n(loading_cubic(b), x_mm);
        assert!(
            (r - expected).abs() < 0.01 * expected,
            "{}: {r:.4}, expected 1 − m_s/M = {expected:.4}",
            a.file
        );
    }
}

#[test]
fn random_on_the_instrumented_campaign_covers_inertia_and_the_plain_one_never_draws_it() {
    let instrumented = SynthPlan::instrumented();
    let picked: BTreeSet<&str> = (0..200)
        .map(|s| resolve_effect_name_for("random", s, &instrumented).unwrap().name())
        .collect();
    // Every word of the spec but `hysteresis_memory` (not a concealable
    // effect), and `none`.
    let vocabulary: BTreeSet<&str> = [
        "none",
        "viscous_damping",
        "sensor_delay",
        "stress_softening",
        "end_stop",
        "magnetic_saturation",
        "coil_lag",
        "inertia",
    ]
    .into_iter()
    .collect();
    assert_eq!(picked, vocabulary);
    assert_eq!(
        INSTRUMENTED_EFFECTS.iter().map(|e| e.name()).collect::<BTreeSet<_>>(),
        vocabulary
    );
    let plain = SynthPlan::default();
    assert!((0..200).all(|s| resolve_effect_name_for("random", s, &plain).unwrap() != Effect::Inertia));
    assert!(instrumented.reveals_inertia() && !plain.reveals_inertia());
    // An accelerometer alone does not reveal it: one mass keeps a ∝ g − F/M.
    let one_mass = SynthPlan {
        second_mass_kg: None,
        ..SynthPlan::instrumented()
    };
    assert!(!one_mass.reveals_inertia());
    // Two masses need two repeats: the second mass drops the even ones.
    let one_repeat = SynthPlan {
        repeats: 1,
        ..SynthPlan::instrumented()
    };
    assert!(!one_repeat.reveals_inertia());
    let bad_mass = SynthPlan {
        second_mass_kg: Some(-1.0),
        ..SynthPlan::instrumented()
    };
    assert!(synthesize_with_plan("none", SEED, &bad_mass).is_err());
}

/// The path users run: `mre synth --campaign instrumented` writes the
/// acceleration column and the per-recording masses, and the data set reads
/// back; the key beside it names the masses; an unknown campaign is an error
/// naming the choices, and writes nothing.
#[test]
fn synth_cli_writes_an_instrumented_campaign() {
    use std::process::Command;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("inst");
    let run = |campaign: &str, out: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_mre"))
            .args([
                "synth",
                "--effect",
                "inertia",
                "--seed",
                "3",
                "--campaign",
                campaign,
                "--out",
            ])
            .arg(out)
            .output()
            .unwrap()
    };
    let ok = run("instrumented", &out);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let ds = mre_host::dataset::Dataset::load(&out).unwrap();
    assert_eq!(ds.recordings.len(), 60);
    assert!(ds.recordings.iter().all(|r| r.samples.accel_m_s2.is_some()));
    assert_eq!(ds.recordings.iter().filter(|r| r.mass_kg == Some(LIGHT_KG)).count(), 27);
    let key: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("inst.key.json")).unwrap()).unwrap();
    assert_eq!(key["effect"], "inertia");
    assert_eq!(key["drop_masses_kg"], serde_json::json!([HEAVY_KG, LIGHT_KG]));
    assert!(key_identifiable(&key));

    let bad_out = dir.path().join("bad");
    let bad = run("shaker", &bad_out);
    assert!(!bad.status.success());
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("drop, instrumented or mts"), "{err}");
    assert!(!bad_out.exists());
}
