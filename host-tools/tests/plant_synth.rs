//! `mre synth`: each concealed effect changes the recordings the way
//! `shared/spec/effects.md` documents, `none` changes nothing, and a seed
//! always gives the same bytes.
//!
//! Every comparison pairs a data set with effect E and the `none` data set of
//! the same seed: both share the base plant, run order and noise seeds, so
//! any difference is the effect alone.
use mre_host::dataset::{Recording, Role};
use mre_host::plant::synth::{draw_base_plant, resolve_effect_name, synthesize, write_synth};
use mre_host::plant::{Effect, EFFECT_NAMES};
use std::collections::BTreeSet;

const SEED: u64 = 7;

fn pair(effect: &str) -> (mre_host::plant::synth::SynthOutput, mre_host::plant::synth::SynthOutput) {
    let with = synthesize(effect, SEED).expect("synth with effect");
    let without = synthesize("none", SEED).expect("synth none");
    assert_eq!(with.plant.law, without.plant.law, "same base plant for a seed");
    assert_eq!(with.plant.effect.name(), effect);
    (with, without)
}

fn peak(r: &Recording) -> f64 {
    r.samples.force_n.iter().copied().fold(f64::MIN, f64::max)
}

fn stroke(r: &Recording) -> f64 {
    r.samples.x_mm.iter().copied().fold(f64::MIN, f64::max)
}

#[test]
fn plan_has_fit_and_validate_currents_velocities_and_a_shuffled_order() {
    let out = synthesize("none", SEED).unwrap();
    let recs = &out.dataset.recordings;
    assert_eq!(recs.len(), 54);
    let currents = |role| {
        recs.iter()
            .filter(|r| r.role == role)
            .map(|r| (r.current_a * 10.0).round() as i64)
            .collect::<BTreeSet<_>>()
    };
    assert_eq!(currents(Role::Fit), BTreeSet::from([0, 5, 10, 15, 20]));
    assert_eq!(currents(Role::Validate), BTreeSet::from([3, 7, 13, 17]));
    let sequences: BTreeSet<u32> = recs.iter().map(|r| r.sequence.unwrap()).collect();
    assert_eq!(sequences, (1..=54).collect());
    let in_listing_order: Vec<u32> = recs.iter().map(|r| r.sequence.unwrap()).collect();
    assert!(
        in_listing_order.windows(2).any(|w| w[1] < w[0]),
        "run order is shuffled"
    );
    let speeds: BTreeSet<i64> = recs
        .iter()
        .map(|r| (r.impact_velocity_m_s.unwrap() * 10.0).round() as i64)
        .collect();
    assert!(speeds.len() >= 3, "several impact velocities: {speeds:?}");
    assert!(recs.iter().all(|r| r.mass_kg == Some(5.5) && r.temperature_c.is_some()));
    // Small: a few hundred samples per recording.
    let n: usize = recs.iter().map(|r| r.samples.len()).sum();
    assert!(
        n / recs.len() > 100 && n / recs.len() < 1000,
        "{} samples per recording",
        n / recs.len()
    );
}

#[test]
fn none_follows_the_paper_structure() {
    // Without an effect, the force at fixed state is linear in current
    // between tabulated currents (the paper's interpolation holds exactly)
    // and does not depend on velocity or on the test's place in the order.
    let plant = draw_base_plant(SEED);
    let x = 3.0;
    let f = |v: f64, i: f64, seq: u32| plant.force_n(x, v, i, seq);
    let interpolated = 0.4 * f(1.0, 0.0, 1) + 0.6 * f(1.0, 0.5, 1);
    assert!((f(1.0, 0.3, 1) - interpolated).abs() < 1e-9);
    assert_eq!(f(0.5, 1.0, 1), f(2.0, 1.0, 1));
    assert_eq!(f(1.0, 1.0, 1), f(1.0, 1.0, 50));
    let out = synthesize("none", SEED).unwrap();
    assert_eq!(out.key["effect"], "none");
    assert_eq!(out.key["parameters"], serde_json::json!({}));
}

#[test]
fn viscous_damping_adds_c_times_v() {
    let (with, without) = pair("viscous_damping");
    let Effect::ViscousDamping {
        c0_n_s_per_m,
        increase_per_a,
    } = with.plant.effect
    else {
        panic!("wrong effect")
    };
    for (a, b) in with.dataset.recordings.iter().zip(&without.dataset.recordings) {
        // Just after contact the trajectories have not yet parted, so the
        // force difference is the viscous term c(I)·v at the impact speed.
        let expected = c0_n_s_per_m * (1.0 + increase_per_a * a.current_a) * a.impact_velocity_m_s.unwrap();
        let got =
            (a.samples.force_n[1] + a.samples.force_n[2]) / 2.0 - (b.samples.force_n[1] + b.samples.force_n[2]) / 2.0;
        assert!(
            (got - expected).abs() < 0.15 * expected,
            "{}: {got} N vs c·v = {expected} N",
            a.file
        );
    }
}

#[test]
fn sensor_delay_shifts_force_but_not_displacement() {
    let (with, without) = pair("sensor_delay");
    let Effect::SensorDelay { delay_s } = with.plant.effect else {
        panic!("wrong effect")
    };
    let dt = with.plant.measurement.sample_period_s;
    let sigma = with.plant.measurement.force_noise_n;
    for (a, b) in with.dataset.recordings.iter().zip(&without.dataset.recordings) {
        assert_eq!(a.samples.x_mm, b.samples.x_mm, "displacement channel untouched");
        // F_meas(t) = F(t − τ): the delayed record matches the undelayed one
        // shifted by τ (interpolated), up to the two records' noise.
        let mut worst = 0.0f64;
        let mut unshifted = 0.0f64;
        // Skip the turn-around: the force changes branch within a sample
        // there, which no interpolation between samples resolves.
        let turn = (0..b.samples.len())
            .max_by(|&i, &j| b.samples.x_mm[i].total_cmp(&b.samples.x_mm[j]))
            .unwrap();
        for k in (10..a.samples.len() - 1).filter(|k| k.abs_diff(turn) > 8) {
            let t = k as f64 - delay_s / dt;
            let (i, frac) = (t.floor() as usize, t - t.floor());
            let shifted = b.samples.force_n[i] + frac * (b.samples.force_n[i + 1] - b.samples.force_n[i]);
            worst = worst.max((a.samples.force_n[k] - shifted).abs());
            unshifted = unshifted.max((a.samples.force_n[k] - b.samples.force_n[k]).abs());
        }
        let peak_n = peak(b);
        assert!(
            worst < 8.0 * sigma + 0.03 * peak_n,
            "{}: shifted mismatch {worst} N",
            a.file
        );
        // The error scales with stiffness·velocity: clear at the stiff currents.
        if a.current_a >= 1.0 {
            assert!(
                unshifted > 0.05 * peak_n,
                "{}: delay leaves a clear mismatch ({unshifted} N)",
                a.file
            );
        } else {
            assert!(
                unshifted > 2.0 * sigma,
                "{}: delay above the noise ({unshifted} N)",
                a.file
            );
        }
    }
}

#[test]
fn stress_softening_grows_with_sequence() {
    let (with, without) = pair("stress_softening");
    let Effect::StressSoftening { depth, tests_n0 } = with.plant.effect else {
        panic!("wrong effect")
    };
    for (a, b) in with.dataset.recordings.iter().zip(&without.dataset.recordings) {
        let n = f64::from(a.sequence.unwrap());
        let factor = 1.0 - depth * (1.0 - (-(n - 1.0) / tests_n0).exp());
        if n == 1.0 {
            assert_eq!(a.samples, b.samples, "the first test is unsoftened");
            continue;
        }
        // A softer spring at the same energy: lower peak, longer stroke; for
        // F ∝ s·x (near-linear backbone) the peak scales by about √s.
        assert!(peak(a) < peak(b) && stroke(a) > stroke(b), "{}", a.file);
        let ratio = peak(a) / peak(b);
        assert!(
            (ratio - factor.sqrt()).abs() < 0.04,
            "{} (seq {n}): peak ratio {ratio} vs √factor {}",
            a.file,
            factor.sqrt()
        );
    }
}

#[test]
fn end_stop_acts_only_beyond_its_stroke() {
    let (with, without) = pair("end_stop");
    let Effect::EndStop { x_e_mm, .. } = with.plant.effect else {
        panic!("wrong effect")
    };
    let mut reached = 0;
    let longest = without.dataset.recordings.iter().map(stroke).fold(0.0, f64::max);
    for (a, b) in with.dataset.recordings.iter().zip(&without.dataset.recordings) {
        // Noise-free margin: a test whose true stroke stays below x_e is
        // unchanged; one that passes it stops sooner and harder.
        if stroke(b) < x_e_mm - 0.1 {
            assert_eq!(a.samples, b.samples, "{}", a.file);
        } else if stroke(b) > x_e_mm + 1.0 {
            reached += 1;
            assert!(stroke(a) < stroke(b), "{}", a.file);
            assert!(peak(a) > peak(b), "{}: {} vs {}", a.file, peak(a), peak(b));
            if stroke(b) > longest - 0.5 {
                assert!(
                    peak(a) > 1.2 * peak(b),
                    "{}: deepest test {} vs {}",
                    a.file,
                    peak(a),
                    peak(b)
                );
            }
        }
    }
    assert!(reached >= 2, "the longest-stroke tests reach the stop");
}

#[test]
fn magnetic_saturation_changes_only_intermediate_currents_with_one_sign() {
    let (with, without) = pair("magnetic_saturation");
    for (a, b) in with.dataset.recordings.iter().zip(&without.dataset.recordings) {
        match a.role {
            Role::Fit => assert_eq!(a.samples, b.samples, "{}: tabulated currents unchanged", a.file),
            // Largest where the gain still rises steeply (below 1 A).
            Role::Validate => assert!(
                peak(a) > if a.current_a < 1.0 { 1.02 } else { 1.0 } * peak(b),
                "{}: saturating gain is above linear interpolation ({} vs {})",
                a.file,
                peak(a),
                peak(b)
            ),
        }
    }
}

#[test]
fn same_seed_same_bytes_and_seeds_vary_the_plant() {
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one");
    let two = dir.path().join("two");
    write_synth("random", 11, &one, None, false).unwrap();
    write_synth("random", 11, &two, None, false).unwrap();
    let files = |d: &std::path::Path| {
        let mut names: Vec<_> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name()).collect();
        names.sort();
        names
    };
    assert_eq!(files(&one), files(&two));
    for name in files(&one) {
        assert_eq!(
            std::fs::read(one.join(&name)).unwrap(),
            std::fs::read(two.join(&name)).unwrap()
        );
    }
    assert_eq!(
        std::fs::read(dir.path().join("one.key.json")).unwrap(),
        std::fs::read(dir.path().join("two.key.json")).unwrap()
    );
    assert!(!one.join("one.key.json").exists(), "key never inside the folder");
    // A key path inside the folder is refused.
    assert!(write_synth(
        "none",
        1,
        &dir.path().join("three"),
        Some(&dir.path().join("three/key.json")),
        false
    )
    .is_err());
    // Refuses to overwrite without --force, replaces with it.
    assert!(write_synth("none", 12, &one, None, false).is_err());
    write_synth("none", 12, &one, None, true).unwrap();
    assert_ne!(draw_base_plant(1).law, draw_base_plant(2).law);
    assert_ne!(draw_base_plant(1).measurement, draw_base_plant(2).measurement);
}

#[test]
fn random_effect_covers_the_vocabulary_including_none() {
    let picked: BTreeSet<&str> = (0..200).map(|s| resolve_effect_name("random", s).unwrap()).collect();
    assert_eq!(picked, EFFECT_NAMES.iter().copied().collect());
    assert!(resolve_effect_name("inertia_typo", 0).is_err());
}

#[test]
fn effect_terms_match_the_spec_formulas() {
    // Hand-evaluated spec terms on the nominal plant at x = 5 mm, v = 1 m/s.
    use mre_host::plant::Plant;
    let base = Plant::nominal();
    let (x, v) = (5.0, 1.0);
    let elastic = 66.0 * x + 0.080 * x * x * x;
    let loading = |gain: f64| gain * elastic * (1.0 + 0.5 * (v / 0.003f64).tanh());
    assert!((base.force_n(x, v, 0.0, 1) - loading(1.0)).abs() < 1e-9);

    let sat = base.clone().with_effect(Effect::MagneticSaturation { i_s_a: 0.4 });
    let u = |i: f64| (i / 0.4f64).tanh();
    let gain = 1.0 + (u(0.3) - u(0.0)) / (u(0.5) - u(0.0)) * (10.15 - 1.0);
    assert!((sat.force_n(x, v, 0.3, 1) - loading(gain)).abs() < 1e-6);
    assert_eq!(sat.force_n(x, v, 0.5, 1), base.force_n(x, v, 0.5, 1));

    let stop = base.clone().with_effect(Effect::EndStop {
        x_e_mm: 4.0,
        k_e_n_per_mm2: 100.0,
    });
    assert!((stop.force_n(x, v, 0.0, 1) - (loading(1.0) + 100.0)).abs() < 1e-9);

    let soft = base.clone().with_effect(Effect::StressSoftening {
        depth: 0.2,
        tests_n0: 5.0,
    });
    let factor = 1.0 - 0.2 * (1.0 - (-10.0f64 / 5.0).exp());
    assert!((soft.force_n(x, v, 0.0, 11) - factor * loading(1.0)).abs() < 1e-9);

    let visc = base.with_effect(Effect::ViscousDamping {
        c0_n_s_per_m: 300.0,
        increase_per_a: 0.5,
    });
    assert!((visc.force_n(x, v, 1.0, 1) - (loading(15.13) + 300.0 * 1.5 * v)).abs() < 1e-9);
}
