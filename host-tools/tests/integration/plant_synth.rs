//! `mre synth`: each concealed effect changes the recordings the way
//! `docs/effects.md` documents, `none` changes nothing, and a seed
//! always gives the same bytes.
//!
//! Every comparison pairs a data set with effect E and the `none` data set of
//! the same seed: both share the base plant, run order and noise seeds, so
//! any difference is the effect alone.
use mre_host::dataset::write::dataset_toml;
use mre_host::dataset::{Recording, Role, TagValue};
use mre_host::plant::synth::{
    draw_base_plant, draw_plant, resolve_effect_name, step_command, synthesize, write_synth, SynthPlan,
};
use mre_host::plant::{simulate, ConcealedEffect, CurrentSource, ImpactConfig, LawParams, Plant, DROP_EFFECTS};
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

/// A controlled impact (the command steps during the test).
fn is_controlled(r: &Recording) -> bool {
    r.tags.contains_key("step_at_ms")
}

/// (from, to, nominal velocity) read back from a controlled impact's file
/// name, `step_i<from>-<to>_v<velocity>.csv`.
fn step_from_name(file: &str) -> (f64, f64, f64) {
    let rest = file
        .strip_prefix("step_i")
        .and_then(|r| r.strip_suffix(".csv"))
        .unwrap();
    let (currents, v) = rest.split_once("_v").unwrap();
    let (from, to) = currents.split_once('-').unwrap();
    (from.parse().unwrap(), to.parse().unwrap(), v.parse().unwrap())
}

/// The step time the plan documents (0.8 ms after contact).
const STEP_AT_S: f64 = 0.8e-3;

#[test]
fn plan_has_fit_and_validate_currents_velocities_and_a_shuffled_order() {
    let out = synthesize("none", SEED).unwrap();
    let recs = &out.dataset.recordings;
    assert_eq!(recs.len(), 60, "54 constant-current tests + 6 controlled impacts");
    let currents = |role| {
        recs.iter()
            .filter(|r| r.role == role && !is_controlled(r))
            .map(|r| (r.current_a * 10.0).round() as i64)
            .collect::<BTreeSet<_>>()
    };
    assert_eq!(currents(Role::Fit), BTreeSet::from([0, 5, 10, 15, 20]));
    assert_eq!(currents(Role::Validate), BTreeSet::from([3, 7, 13, 17]));
    let sequences: BTreeSet<u32> = recs.iter().map(|r| r.sequence.unwrap()).collect();
    assert_eq!(sequences, (1..=60).collect());
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
    let ConcealedEffect::ViscousDamping {
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
    let ConcealedEffect::SensorDelay { delay_s } = with.plant.effect else {
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
        // Likewise the command step of a controlled impact.
        let step = is_controlled(a).then(|| (STEP_AT_S / dt).round() as usize);
        let away = |k: usize, at: Option<usize>| at.is_none_or(|at| k.abs_diff(at) > 8);
        for k in (10..a.samples.len() - 1).filter(|&k| away(k, Some(turn)) && away(k, step)) {
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
        // The error scales with stiffness·velocity: clear at the stiff currents
        // (a controlled impact counts by its lower current).
        let lowest_a = a
            .samples
            .current_a
            .as_ref()
            .map_or(a.current_a, |c| c.iter().copied().fold(f64::MAX, f64::min));
        if lowest_a >= 1.0 {
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
    let ConcealedEffect::StressSoftening { depth, tests_n0 } = with.plant.effect else {
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
        // F ∝ s·x (near-linear backbone) the peak scales by about √s (not
        // with a step in the command: there the peak can be at the step).
        assert!(peak(a) < peak(b) && stroke(a) > stroke(b), "{}", a.file);
        if is_controlled(a) {
            continue;
        }
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
    let ConcealedEffect::EndStop { x_e_mm, .. } = with.plant.effect else {
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
            // A 2 A → 0 A step has its peak at the step, before the stop.
            if is_controlled(a) {
                continue;
            }
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
        // Controlled impacts step between tabulated currents: unchanged too.
        if is_controlled(a) {
            assert_eq!(a.samples, b.samples, "{}: tabulated currents unchanged", a.file);
            continue;
        }
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
    let files = |d: &std::path::Path| {
        let mut names: Vec<_> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name()).collect();
        names.sort();
        names
    };
    for (effect, seed, stem) in [("coil_lag", 13, "lag"), ("random", 11, "")] {
        let one = dir.path().join(format!("{stem}one"));
        let two = dir.path().join(format!("{stem}two"));
        write_synth(effect, seed, &one, None, false).unwrap();
        write_synth(effect, seed, &two, None, false).unwrap();
        assert_eq!(files(&one), files(&two));
        for name in files(&one) {
            assert_eq!(
                std::fs::read(one.join(&name)).unwrap(),
                std::fs::read(two.join(&name)).unwrap(),
                "{effect}: {name:?}"
            );
        }
        assert_eq!(
            std::fs::read(dir.path().join(format!("{stem}one.key.json"))).unwrap(),
            std::fs::read(dir.path().join(format!("{stem}two.key.json"))).unwrap()
        );
    }
    let one = dir.path().join("one");
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
    let picked: BTreeSet<&str> = (0..200)
        .map(|s| resolve_effect_name("random", s).unwrap().name())
        .collect();
    // The spec's words a plain drop campaign can reveal (not `inertia`, not
    // `hysteresis_memory`), and `none`.
    let expected = [
        "none",
        "viscous_damping",
        "sensor_delay",
        "stress_softening",
        "end_stop",
        "magnetic_saturation",
        "coil_lag",
    ];
    assert_eq!(picked, expected.into_iter().collect());
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

    let sat = base
        .clone()
        .with_effect(ConcealedEffect::MagneticSaturation { i_s_a: 0.4 });
    let u = |i: f64| (i / 0.4f64).tanh();
    let gain = 1.0 + (u(0.3) - u(0.0)) / (u(0.5) - u(0.0)) * (10.15 - 1.0);
    assert!((sat.force_n(x, v, 0.3, 1) - loading(gain)).abs() < 1e-6);
    assert_eq!(sat.force_n(x, v, 0.5, 1), base.force_n(x, v, 0.5, 1));

    let stop = base.clone().with_effect(ConcealedEffect::EndStop {
        x_e_mm: 4.0,
        k_e_n_per_mm2: 100.0,
    });
    assert!((stop.force_n(x, v, 0.0, 1) - (loading(1.0) + 100.0)).abs() < 1e-9);

    let soft = base.clone().with_effect(ConcealedEffect::StressSoftening {
        depth: 0.2,
        tests_n0: 5.0,
    });
    let factor = 1.0 - 0.2 * (1.0 - (-10.0f64 / 5.0).exp());
    assert!((soft.force_n(x, v, 0.0, 11) - factor * loading(1.0)).abs() < 1e-9);

    // The coil lag acts on the current, not on the force law at a given current.
    let lag = base
        .clone()
        .with_effect(ConcealedEffect::CoilLag { time_constant_s: 5e-4 });
    assert_eq!(lag.force_n(x, v, 1.0, 1), base.force_n(x, v, 1.0, 1));
    assert_eq!(lag.effect.coil_lag_s(), Some(5e-4));

    let visc = base.with_effect(ConcealedEffect::ViscousDamping {
        c0_n_s_per_m: 300.0,
        increase_per_a: 0.5,
    });
    assert!((visc.force_n(x, v, 1.0, 1) - (loading(15.13) + 300.0 * 1.5 * v)).abs() < 1e-9);
}

#[test]
fn every_campaign_has_the_same_plan_with_six_controlled_impacts() {
    // The plan (files, roles, currents, run order, covariates) is the same
    // whatever the effect, so it never gives the effect away.
    let expected_files: BTreeSet<&str> = [
        "step_i0.0-2.0_v2.24.csv",
        "step_i2.0-0.0_v2.24.csv",
        "step_i0.5-1.5_v1.80.csv",
        "step_i1.5-0.5_v1.80.csv",
        "step_i0.0-1.0_v1.40.csv",
        "step_i2.0-1.0_v1.40.csv",
    ]
    .into();
    let mut plans = Vec::new();
    for effect in DROP_EFFECTS {
        let out = synthesize(effect.name(), SEED).unwrap();
        let recs = &out.dataset.recordings;
        assert_eq!(recs.len(), 60, "{effect}");
        let controlled: Vec<&Recording> = recs.iter().filter(|r| is_controlled(r)).collect();
        let files: BTreeSet<&str> = controlled.iter().map(|r| r.file.as_str()).collect();
        assert_eq!(files, expected_files, "{effect}");
        for r in &controlled {
            let (from, to, v) = step_from_name(&r.file);
            assert_ne!(from, to);
            assert_eq!(r.role, Role::Validate, "{effect}/{}", r.file);
            assert_eq!(r.current_a, from, "{effect}/{}: header = initial command", r.file);
            assert_eq!(r.tags["step_at_ms"], TagValue::Number(0.8), "{effect}/{}", r.file);
            assert!((r.impact_velocity_m_s.unwrap() / v - 1.0).abs() < 0.03, "{}", r.file);
        }
        // They take part in the shuffled run order, not appended at its end.
        assert!(
            controlled.iter().any(|r| r.sequence.unwrap() <= 54),
            "{effect}: controlled impacts are shuffled in"
        );
        plans.push(dataset_toml(&out.dataset).unwrap());
    }
    assert!(plans.windows(2).all(|w| w[0] == w[1]), "one plan for every effect");
}

#[test]
fn controlled_current_column_is_the_commanded_step() {
    let out = synthesize("none", SEED).unwrap();
    for r in &out.dataset.recordings {
        let Some(column) = &r.samples.current_a else {
            assert!(!is_controlled(r), "{}: controlled impacts carry the command", r.file);
            continue;
        };
        assert!(is_controlled(r), "{}: constant-current tests have no column", r.file);
        let (from, to, _) = step_from_name(&r.file);
        assert_eq!(column.len(), r.samples.len());
        // Each sample carries the command held over the sample period that
        // ended at it: the initial one up to the step, then the new one.
        for (t, i) in r.samples.time_s.iter().zip(column) {
            let expected = if *t <= STEP_AT_S + 1e-9 { from } else { to };
            assert_eq!(*i, expected, "{} at {t} s", r.file);
        }
        assert!(r.samples.time_s.last().unwrap() > &(2.0 * STEP_AT_S), "{}", r.file);
    }
}

#[test]
fn none_controlled_impacts_follow_the_law_at_the_commanded_current() {
    // Without the lag, the force just after the step is the law at the new
    // current (checked on the true plant of the seed at the measured state,
    // so up to the x noise times the stiffness, and the force noise).
    let out = synthesize("none", SEED).unwrap();
    let plant = draw_base_plant(SEED);
    let m = &plant.measurement;
    for r in out.dataset.recordings.iter().filter(|r| is_controlled(r)) {
        let (from, to, _) = step_from_name(&r.file);
        let k = r.samples.time_s.iter().position(|t| *t > STEP_AT_S + 1e-9).unwrap();
        let (mut off_new, mut off_old) = (0.0, 0.0);
        for j in k..k + 4 {
            let (x, v) = (r.samples.x_mm[j], r.samples.v_m_s[j]);
            let at = |i: f64| plant.force_n(x, v, i, r.sequence.unwrap());
            // Local stiffness at the new current, for the displacement noise.
            let stiffness = (plant.force_n(x + 0.01, v, to, 1) - plant.force_n(x - 0.01, v, to, 1)) / 0.02;
            let tolerance = 5.0 * (m.force_noise_n + stiffness * m.x_noise_mm) + 1.0;
            let got = r.samples.force_n[j];
            assert!(
                (got - at(to)).abs() < tolerance,
                "{} at sample {j}: {got} N vs law at {to} A {} N (±{tolerance})",
                r.file,
                at(to)
            );
            off_new += (got - at(to)).abs();
            off_old += (got - at(from)).abs();
        }
        assert!(off_old > 3.0 * off_new, "{}: {off_old} vs {off_new} N", r.file);
    }
}

#[test]
fn coil_lag_changes_only_the_controlled_impacts() {
    let (with, without) = pair("coil_lag");
    let ConcealedEffect::CoilLag { time_constant_s: tau } = with.plant.effect else {
        panic!("wrong effect")
    };
    assert!((0.2e-3..=0.8e-3).contains(&tau), "τ = {tau} s");
    assert_eq!(with.key["parameters"]["time_constant_s"], tau);
    let sigma = with.plant.measurement.force_noise_n;
    for (a, b) in with.dataset.recordings.iter().zip(&without.dataset.recordings) {
        if !is_controlled(a) {
            // The coil is energised before contact: nothing to lag behind.
            assert_eq!(a.samples, b.samples, "{}", a.file);
            continue;
        }
        let (from, to, _) = step_from_name(&a.file);
        let k = a.samples.time_s.iter().position(|t| *t > STEP_AT_S + 1e-9).unwrap();
        assert_eq!(
            a.samples.force_n[..k],
            b.samples.force_n[..k],
            "{}: same up to the step",
            a.file
        );
        let column = a.samples.current_a.as_ref().unwrap();
        for (t, i) in a.samples.time_s.iter().zip(column) {
            let command = if *t <= STEP_AT_S + 1e-9 { from } else { to };
            assert_eq!(
                *i, command,
                "{}: the column is the command, not the lagging current",
                a.file
            );
        }
        // Just after the step the coil carries to + (from − to)·e^{−(t − t_s)/τ}:
        // the force stays near the old command's, less on an up-step and
        // more on a down-step, by the law's force at that current.
        let plant = &without.plant;
        for j in k..k + 2 {
            let (x, v, t) = (b.samples.x_mm[j], b.samples.v_m_s[j], b.samples.time_s[j]);
            let lagging_a = to + (from - to) * (-(t - STEP_AT_S) / tau).exp();
            let n = a.sequence.unwrap();
            let expected = plant.force_n(x, v, lagging_a, n) - plant.force_n(x, v, to, n);
            let got = a.samples.force_n[j] - b.samples.force_n[j];
            assert!(
                -(to - from).signum() * expected > 5.0 * sigma,
                "{} at sample {j}: {expected} N",
                a.file
            );
            assert!(
                (got - expected).abs() < 0.1 * expected.abs() + 5.0 * sigma,
                "{} at sample {j}: {got} N vs {expected} N",
                a.file
            );
        }
    }
}

#[test]
fn coil_lag_key_and_drawn_time_constant_in_range() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lag");
    write_synth("coil_lag", 3, &out, None, false).unwrap();
    let key: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("lag.key.json")).unwrap()).unwrap();
    assert_eq!(key["effect"], "coil_lag");
    let tau = key["parameters"]["time_constant_s"].as_f64().unwrap();
    assert!((0.2e-3..=0.8e-3).contains(&tau), "τ = {tau} s");
    assert_eq!(key["parameters"].as_object().unwrap().len(), 1);
    let plan = SynthPlan::default();
    let drawn: Vec<f64> = (0..40)
        .map(|seed| draw_plant("coil_lag", seed, &plan).unwrap().effect.clone())
        .map(|e| match e {
            ConcealedEffect::CoilLag { time_constant_s } => time_constant_s,
            other => panic!("{other:?}"),
        })
        .collect();
    assert!(drawn.iter().all(|t| (0.2e-3..=0.8e-3).contains(t)));
    let (lo, hi) = (
        drawn.iter().copied().fold(f64::MAX, f64::min),
        drawn.iter().copied().fold(0.0, f64::max),
    );
    assert!(lo < 0.35e-3 && hi > 0.65e-3, "spread over the range: {lo}..{hi}");
}

#[test]
fn controlled_step_lands_early_in_compression_for_every_plant_synth_draws() {
    // The softest and stiffest corners of the ranges `draw_base_plant` draws
    // from (README): the step must find the mass still compressing, and
    // leave at least 1.5 ms (≈ 2τ at the largest τ) of compression after it.
    let nominal = LawParams::nominal();
    let corner = |k1: f64, k3: f64, eta: f64, vt: f64, g: f64| {
        let mut gain_knots = nominal.gain_knots;
        for k in gain_knots.iter_mut().skip(1) {
            *k *= g;
        }
        Plant {
            law: LawParams {
                k1_n_per_mm: nominal.k1_n_per_mm * k1,
                k3_n_per_mm3: nominal.k3_n_per_mm3 * k3,
                loss_eta: eta,
                turn_velocity_m_s: vt,
                gain_knots,
            },
            ..Plant::nominal()
        }
    };
    let plan = SynthPlan::default();
    assert_eq!(plan.step_at_s, STEP_AT_S);
    for plant in [
        corner(1.08, 1.15, 0.58, 0.002, 1.05),
        corner(0.92, 0.85, 0.42, 0.005, 0.95),
        Plant::nominal(),
    ] {
        for c in &plan.controlled {
            for v in [c.velocity_m_s * 0.98, c.velocity_m_s * 1.02] {
                let cfg = ImpactConfig {
                    impact_velocity_m_s: v,
                    initial_current_a: c.from_a,
                    ..ImpactConfig::default()
                };
                let source = CurrentSource::Function(Box::new(step_command(c.from_a, c.to_a, STEP_AT_S, cfg.step_s)));
                let t = simulate(&plant, &cfg, source).unwrap();
                let deepest = t.samples.iter().max_by(|a, b| a.x_mm.total_cmp(&b.x_mm)).unwrap();
                let at_step = t.samples.iter().find(|s| s.time_s > STEP_AT_S - 1e-9).unwrap();
                assert!(at_step.v_m_s > 0.8 * v, "{c:?}: still compressing fast at the step");
                assert!(
                    deepest.time_s > STEP_AT_S + 1.5e-3,
                    "{c:?} at {v} m/s: compression ends {} ms after contact",
                    deepest.time_s * 1e3
                );
            }
        }
    }
}

/// `mre synth --campaign mts`: the base law is rate-independent, so the two
/// 25 mm tests (0.1 and 0.25 Hz, 2.5× apart in speed) trace the same loop;
/// with concealed viscosity they differ by c·Δv.
#[test]
fn mts_campaign_loops_do_not_depend_on_speed_without_viscosity() {
    use mre_host::plant::base_laws::{Hysteresis, HystereticLaw};
    use mre_host::plant::synth_mts::{synthesize_mts_with, MtsEffect};
    for hysteresis in [Hysteresis::Dahl, Hysteresis::BoucWen] {
        let law = HystereticLaw::example(hysteresis, 0.0);
        for (effect, c) in [
            (MtsEffect::None, 0.0),
            (MtsEffect::ViscousDamping { c0_n_s_per_m: 1000.0 }, 1000.0),
        ] {
            let out = synthesize_mts_with(&law, &effect, 7).unwrap();
            let rec = |name: &str| out.dataset.recordings.iter().find(|r| r.file == name).unwrap();
            let (slow, fast) = (rec("25mm0.1Hz0A.csv"), rec("25mm0.25Hz0A.csv"));
            // Force at mid-stroke (|x| < 1 mm, far past any switching) on the
            // loading branch, averaged: x = A·sin ωt, v = A·ω at x = 0.
            let mean_at_zero = |r: &mre_host::dataset::Recording| {
                let s = &r.samples;
                let f: Vec<f64> = (0..s.len())
                    .filter(|&i| s.x_mm[i].abs() < 1.0 && s.v_m_s[i] > 0.0)
                    .map(|i| s.force_n[i] - 2.0 * s.x_mm[i] - 0.001 * s.x_mm[i].powi(3))
                    .collect();
                f.iter().sum::<f64>() / f.len() as f64
            };
            let v = |f_hz: f64| 25e-3 * 2.0 * std::f64::consts::PI * f_hz;
            // Expected difference: c·(v_fast − v_slow) at x = 0 (gain 1 at 0 A),
            // the yield force f_y·z (z = 1 on loading after 24 mm of travel) cancels.
            let want = c * (v(0.25) - v(0.1));
            let got = mean_at_zero(fast) - mean_at_zero(slow);
            assert!((got - want).abs() < 3.0, "{hysteresis:?} c = {c}: {got} vs {want}");
        }
    }
}
