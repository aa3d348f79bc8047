//! From recordings to flash: `mre diagnose --model-out`, the physical limit
//! of `mre bench-control`, and one bench case end to end.
use mre_algorithm::installation::DEFAULT_INSTALLATION;
use mre_host::control_bench::limit::physical_limit;
use mre_host::control_bench::{controllers_for, drop_setup, record_campaign, run_case, Case};
use mre_host::plant::closed_loop::run_controlled;
use mre_host::plant::synth::SynthPlan;
use mre_host::plant::{ImpactConfig, LawParams, Plant};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// Whether the diagnosed coil τ lies close enough to the true one. The
/// estimator refines τ on a grid of 2^(1/16) steps (diagnose/terms/coil_lag.rs),
/// so the nearest grid point is within 2^(1/32) − 1 = 2.2 %; the held-out
/// error is flat within a step under the recordings' noise, so the
/// neighbouring point is as likely: one more step, 2^(3/32) − 1 = 6.7 %.
/// (The old 25 % would have passed the √2 grid's 2.26 ms for a 2 ms coil.)
fn tau_within_tolerance(tau_s: f64, true_tau_s: f64) -> bool {
    (tau_s / true_tau_s).ln().abs() < (3.0 / 32.0) * 2f64.ln()
}

#[test]
fn model_out_carries_the_coil_lag_the_answer_key_holds() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("final.toml");
    let (_, table, stated) = mre_host::diagnose::model_out::run_to_files_with_model(
        &root().join("data/drop-coil_lag"),
        // The lag shows only in the controlled impacts (validate recordings):
        // diagnose judges it there only when asked to.
        &mre_host::diagnose::DiagnoseOptions::with_validate_evidence(),
        &dir.path().join("report"),
        &dir.path().join("report.json"),
        &dir.path().join("predictions"),
        &model,
        &[],
    )
    .unwrap();
    let key: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root().join("data/keys/drop-coil_lag.json")).unwrap()).unwrap();
    let true_tau_s = key["parameters"]["time_constant_s"].as_f64().unwrap();
    let tau_s = f64::from(table.terms().coil_tau_s);
    println!(
        "coil τ in the model file: {:.4} ms, key {:.4} ms",
        tau_s * 1e3,
        true_tau_s * 1e3
    );
    assert!(tau_within_tolerance(tau_s, true_tau_s), "{tau_s} vs {true_tau_s}");
    // The model file carries the installation (format 3): the campaign's
    // 5.5 kg drop mass, from its metadata; the rest the defaults.
    assert_eq!(table.version(), 3);
    assert_eq!(*table.installation(), mre_algorithm::installation::DEFAULT_INSTALLATION);
    assert!(
        stated.describe().contains("mass_kg = 5.5 from the data set's metadata"),
        "{}",
        stated.describe()
    );
    // The file is what `mre tables` flashes: it reads back as the same table,
    // and the generated source carries τ and the data set's hash.
    let read = mre_host::table_file::read_table_file(&model).unwrap();
    assert_eq!(read, table);
    let source = dir.path().join("generated_table.rs");
    mre_host::tables::run_tables(&model, &source).unwrap();
    let text = std::fs::read_to_string(&source).unwrap();
    // The flash table is format 3 too: the installation under its CRC (issue 31).
    assert!(text.contains("coil_tau_s: ") && text.contains("version: 3,"));
    let sha = mre_host::table_file::read_dataset_sha256(&model).unwrap().unwrap();
    assert!(text.contains(&sha));
}

#[test]
fn without_a_floor_and_with_a_stiff_coil_the_limit_is_the_constant_stopping_force() {
    // A coil so strong that 2 A reaches any force within a micrometre: the
    // ceiling-only limit is the constant force that stops m at v in s with
    // gravity still pushing, m·v²/(2s) + m·g = 5.5·2.24²/0.024 + 53.955
    // = 1203.99 N.
    let mut plant = Plant::nominal();
    plant.law = LawParams {
        gain_knots: [1.0, 2.0e4, 4.0e4, 6.0e4, 8.0e4],
        ..LawParams::nominal()
    };
    let impact = ImpactConfig::default();
    let limit = physical_limit(&plant, &impact, (0.0, 2.0), 12.0).unwrap();
    assert!((limit.ceiling_only_n - 1203.99).abs() < 2.0, "{:?}", limit);
    // The 0 A floor only adds force late in the stroke: the full limit is
    // at least the ceiling-only one, and at most the floor's force at the
    // end of the stroke (66·12 + 0.08·12³ = 930.2 N, ×1.5 while loading).
    assert!(limit.envelope_n >= limit.ceiling_only_n - 1.0);
    assert!(limit.envelope_n <= 1.5 * 930.24 + 1.0, "{:?}", limit);
}

#[test]
fn controller_c_meets_its_target_on_a_2_ms_coil_and_beats_the_paper_table() {
    let out = run_case(&Case::CoilTau { tau_ms: 2.0, seed: 203 }, &DEFAULT_INSTALLATION).unwrap();
    let (a, b, c) = (&out.runs[0], &out.runs[1], &out.runs[2]);
    // diagnose finds the lag from the campaign's controlled impacts.
    assert_eq!(out.diagnosed, vec!["coil_lag".to_owned()]);
    let tau_s = f64::from(out.identified_coil_tau_s);
    assert!(tau_within_tolerance(tau_s, 2.0e-3), "τ = {tau_s} s");
    assert!(!c.bottomed_out && c.over_limit <= 1.25, "{c:?}");
    assert!(c.peak_force_n < a.peak_force_n && c.peak_force_n < b.peak_force_n);
    assert!(out.target_met);
}

#[test]
fn controller_c_meets_the_nominal_target() {
    // Issue 11: on a plant without a concealed effect, (c) peaks at most
    // 1.10× the limit, within the stroke, and no higher than (a).
    let out = run_case(
        &Case::Effect {
            name: mre_host::vocabulary::Effect::None,
            seed: 101,
        },
        &DEFAULT_INSTALLATION,
    )
    .unwrap();
    let (a, c) = (&out.runs[0], &out.runs[2]);
    assert!(out.diagnosed.is_empty(), "{:?}", out.diagnosed);
    assert!(!c.bottomed_out && c.over_limit <= 1.10, "{c:?}");
    assert!(c.peak_force_n < a.peak_force_n);
    assert!(out.target_met);
}

#[test]
fn controller_c_holds_its_target_when_the_coil_time_constant_is_20_percent_off() {
    // Diagnosis reports τ within 6.7 % (the 2 ms coil of seed 203
    // comes out at 1.987 ms), but a real coil's τ drifts with temperature
    // (copper's resistance, +0.39 %/K, sets τ = L/R). With the
    // diagnosed quartics but τ set 20 % below and above the plant's, (c)
    // must still meet the τ ≤ 2 ms target: within the stroke and at
    // most 1.25× the limit.
    let case = Case::CoilTau { tau_ms: 2.0, seed: 203 };
    let plant = case.plant(&SynthPlan::default()).unwrap();
    let (_dir, campaign) = record_campaign(&plant, case.seed()).unwrap();
    let diagnosed = controllers_for(&campaign).unwrap().diagnosed;
    let setup = drop_setup(&plant, campaign.recordings.len(), case.seed(), &DEFAULT_INSTALLATION);
    let limit = physical_limit(&plant, &setup.impact, (0.0, 2.0), setup.usable_stroke_mm()).unwrap();
    for tau_s in [1.6e-3f32, 2.4e-3] {
        let terms = mre_algorithm::table::ModelTerms {
            coil_tau_s: tau_s,
            ..*diagnosed.terms()
        };
        let table = mre_algorithm::Table::with_terms(diagnosed.entries(), terms).unwrap();
        let s = run_controlled(&setup, &table).unwrap().summary;
        let ratio = s.peak_force_n / limit.envelope_n;
        assert!(
            s.max_stroke_mm <= setup.usable_stroke_mm() && ratio <= 1.25,
            "τ {tau_s}: {ratio:.3}× the limit, stroke {:.2} mm",
            s.max_stroke_mm
        );
    }
}

// ---- real coils (#29): the simulator's coil and approach ----

use mre_host::plant::{simulate, ConcealedEffect, CurrentSource};

/// The coil current at each sample of a drop whose command is `command_a`
/// until `switch_s`, then 0 A, on the default 12 V / 4 Ω half bridge.
fn coil_currents(cfg: &ImpactConfig, command_a: f64, switch_s: f64) -> Vec<(f64, f64)> {
    let t = simulate(
        &Plant::nominal(),
        cfg,
        CurrentSource::Function(Box::new(move |t| if t < switch_s { command_a } else { 0.0 })),
    )
    .unwrap();
    t.samples.iter().map(|s| (s.time_s, s.current_a)).collect()
}

#[test]
fn a_coil_switches_off_with_its_own_slower_time_constant() {
    // From 1 A held, the command drops to 0 A at t = 0: the current decays as
    // e^{−t/τ}. After 3 ms (within the impact) it is e^{−0.15} = 0.8607 A
    // with τ_off = 20 ms, and e^{−0.3} = 0.7408 A with τ_off = τ_on = 10 ms.
    let base = ImpactConfig {
        coil_lag_s: Some(0.010),
        initial_current_a: 1.0,
        ..ImpactConfig::default()
    };
    let at_3_ms = |cfg: &ImpactConfig| {
        coil_currents(cfg, 0.0, 0.0)
            .into_iter()
            .find(|(t, _)| *t >= 0.003 - 1e-9)
            .unwrap()
            .1
    };
    let slow_off = ImpactConfig {
        coil_lag_off_s: Some(0.020),
        ..base.clone()
    };
    assert!((at_3_ms(&slow_off) - 0.8607).abs() < 1e-3, "{}", at_3_ms(&slow_off));
    assert!((at_3_ms(&base) - 0.7408).abs() < 1e-3, "{}", at_3_ms(&base));
    // Switching on still follows τ_on: from 0 A towards 1 A, 1 − e^{−0.3} = 0.2592 A after 3 ms.
    let on = ImpactConfig {
        initial_current_a: 0.0,
        ..slow_off
    };
    let (_, i) = coil_currents(&on, 1.0, 1.0)
        .into_iter()
        .find(|(t, _)| *t >= 0.003 - 1e-9)
        .unwrap();
    assert!((i - 0.2592).abs() < 1e-3, "{i}");
}

#[test]
fn the_approach_falls_freely_and_reaches_contact_at_the_impact_velocity() {
    // 30 mm before a 2.24 m/s contact the mass falls at √(2.24² − 2·9.81·0.03)
    // = 2.1051 m/s; at contact (x crossing 0) it moves at 2.24 m/s.
    let cfg = ImpactConfig {
        approach_mm: 30.0,
        ..ImpactConfig::default()
    };
    let t = simulate(&Plant::nominal(), &cfg, CurrentSource::Constant(2.0)).unwrap();
    let first = t.samples[0];
    assert!(
        (first.x_mm + 30.0).abs() < 0.01 && (first.v_m_s - 2.1051).abs() < 0.002,
        "{first:?}"
    );
    let contact = t.samples.iter().find(|s| s.x_mm >= 0.0).unwrap();
    assert!((contact.v_m_s - 2.24).abs() < 0.005, "{contact:?}");
    // The impact itself is the one that starts at contact.
    let at_contact = simulate(
        &Plant::nominal(),
        &ImpactConfig::default(),
        CurrentSource::Constant(2.0),
    )
    .unwrap();
    let rel = (t.summary.max_stroke_mm / at_contact.summary.max_stroke_mm - 1.0).abs();
    assert!(
        rel < 1e-3,
        "{} vs {}",
        t.summary.max_stroke_mm,
        at_contact.summary.max_stroke_mm
    );
}

#[test]
fn real_coil_time_constants_run_and_out_of_range_ones_get_a_sentence() {
    let plant = Plant::nominal().with_effect(ConcealedEffect::CoilLag { time_constant_s: 0.020 });
    let cfg = ImpactConfig {
        coil_lag_s: Some(0.020),
        ..ImpactConfig::default()
    };
    assert!(simulate(&plant, &cfg, CurrentSource::Constant(1.0)).is_ok());
    let too_slow = Plant::nominal().with_effect(ConcealedEffect::CoilLag { time_constant_s: 0.2 });
    let e = format!(
        "{:#}",
        simulate(&too_slow, &cfg, CurrentSource::Constant(1.0)).unwrap_err()
    );
    assert!(e.contains("at most 100 ms") && !e.contains('{'), "{e}");
    let e = format!(
        "{:#}",
        simulate(
            &Plant::nominal(),
            &ImpactConfig {
                coil_lag_s: Some(0.2),
                ..ImpactConfig::default()
            },
            CurrentSource::Constant(1.0)
        )
        .unwrap_err()
    );
    assert!(e.contains("at most 100 ms") && !e.contains('{'), "{e}");
}

#[test]
fn a_20_ms_coil_armed_before_contact_stops_softer_than_any_fixed_current() {
    use mre_host::control_bench::real_coil::{run_armed, Prediction};
    use mre_host::plant::closed_loop::{run_passive, SimSetup};
    // The bundled fit of the nominal plant (what `cargo fw` flies), with the
    // coil's L/R of 20 ms, on the nominal plant with that coil.
    let tau_s = 0.020;
    let table = mre_algorithm::Table::with_terms(
        &mre_algorithm::generated_table::GENERATED_ENTRIES,
        mre_algorithm::table::ModelTerms {
            coil_tau_s: tau_s as f32,
            ..mre_algorithm::table::ModelTerms::NONE
        },
    )
    .unwrap();
    let setup = SimSetup {
        plant: Plant::nominal().with_effect(ConcealedEffect::CoilLag { time_constant_s: tau_s }),
        impact: ImpactConfig {
            coil_lag_s: Some(tau_s),
            ..ImpactConfig::default()
        },
        installation: DEFAULT_INSTALLATION,
    };
    // The peer: the passive drop with the lowest peak within the stroke.
    let best_fixed_n = (0..=100)
        .map(|k| run_passive(&setup, f64::from(k) * 0.02).unwrap().summary)
        .filter(|s| s.max_stroke_mm <= 12.0)
        .map(|s| s.peak_force_n)
        .fold(f64::INFINITY, f64::min);
    // And within #29's target for a 20 ms coil: 1.5× the physical limit.
    // (Idling at the old fixed 0.5 A instead of the robust current, the run
    // without a prediction peaked at 1.75× here.)
    let limit_n = physical_limit(&setup.plant, &setup.impact, (0.0, 2.0), 12.0)
        .unwrap()
        .envelope_n;
    for prediction in [Prediction::FromApproach { velocity_scale: 1.0 }, Prediction::None] {
        let s = run_armed(&setup, &table, prediction, None).unwrap().summary;
        println!(
            "{prediction:?}: {:.0} N, {:.2} mm; best fixed {best_fixed_n:.0} N, limit {limit_n:.0} N",
            s.peak_force_n, s.max_stroke_mm
        );
        assert!(s.max_stroke_mm <= 12.0, "{prediction:?}: {} mm", s.max_stroke_mm);
        assert!(s.peak_force_n < best_fixed_n, "{prediction:?}: {} N", s.peak_force_n);
        assert!(s.peak_force_n <= 1.5 * limit_n, "{prediction:?}: {} N", s.peak_force_n);
    }
}
