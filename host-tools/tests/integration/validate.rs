//! `mre validate` on a synthetic data set made from the paper's Table 4:
//! exact recordings give zero error; a scaled force gives a known error; an
//! intermediate-current recording is predicted by interpolation and bracketed.
use mre_algorithm::table::Table;
use mre_host::dataset::{Dataset, Recording, Role, Samples};
use mre_host::validate::{validate, validate_recording};
use std::collections::BTreeMap;

/// One loop at `current_a`: x = 0 → x_max → 0, forces from the paper table × `gain`.
fn recording(table: &Table, current_a: f64, gain: f64, role: Role) -> Recording {
    let n = 200;
    let x_max = 0.88f64;
    let mut s = Samples::default();
    for i in 0..n {
        let phase = i as f64 / n as f64;
        let (x, v) = if phase < 0.5 {
            (x_max * phase * 2.0, 0.5)
        } else {
            (x_max * (1.0 - phase) * 2.0, -0.5)
        };
        let f = table.force(x as f32, v as f32, current_a as f32).force_n as f64;
        s.time_s.push(i as f64 * 1e-3);
        s.x_mm.push(x);
        s.v_m_s.push(v);
        s.force_n.push(gain * f);
    }
    Recording {
        file: format!("{current_a}.csv"),
        current_a,
        role,
        mass_kg: None,
        impact_velocity_m_s: None,
        sequence: None,
        temperature_c: None,
        tags: BTreeMap::new(),
        samples: s,
        velocity_estimated: false,
        motion_from: None,
        notes: Vec::new(),
    }
}

#[test]
fn exact_recording_has_zero_error() {
    let table = Table::paper().unwrap();
    let r = validate_recording(&table, &recording(&table, 1.0, 1.0, Role::Fit));
    assert_eq!(r.rmse_n, 0.0);
    assert!(!r.interpolated);
    assert!(r.bracket.is_none());
}

#[test]
fn scaled_force_gives_the_known_percentage_and_rmse() {
    // Measured = 1.25 × model, so at every sample error = 0.25·|model| =
    // 0.2·|measured|: 20 % at the point of largest error, and RMSE = 0.25 ×
    // RMS(model) = 0.2 × RMS(measured).
    let table = Table::paper().unwrap();
    let rec = recording(&table, 0.5, 1.25, Role::Fit);
    let r = validate_recording(&table, &rec);
    assert!(
        (r.largest_error.error_pct - 20.0).abs() < 1e-3,
        "{}",
        r.largest_error.error_pct
    );
    let rms = (rec.samples.force_n.iter().map(|f| f * f).sum::<f64>() / rec.samples.len() as f64).sqrt();
    assert!((r.rmse_n - 0.2 * rms).abs() < 1e-3 * rms);
    assert!((r.peak_measured_n - 1.25 * r.peak_model_n).abs() < 1e-2);
}

#[test]
fn paper_table5_percentage_is_relative_to_experiment() {
    // Table 5, 0 A: experiment 2079.22 N, simulation 1821.72 N, 12.38 %.
    let table = Table::paper().unwrap();
    let mut rec = recording(&table, 0.0, 1.0, Role::Fit);
    let model_at_0 = rec.samples.force_n[50];
    // Put one "measured" sample 2079.22/1821.72 above the model there.
    rec.samples.force_n[50] = model_at_0 * 2079.22 / 1821.72;
    let r = validate_recording(&table, &rec);
    assert_eq!(r.largest_error.sample, 50);
    assert!(
        (r.largest_error.error_pct - 12.384).abs() < 0.01,
        "{}",
        r.largest_error.error_pct
    );
}

#[test]
fn intermediate_current_is_interpolated_and_bracketed() {
    let table = Table::paper().unwrap();
    let ds = Dataset {
        name: "synthetic".into(),
        root: ".".into(),
        recordings: vec![recording(&table, 0.7, 1.0, Role::Validate)],
    };
    let report = validate(&ds, &table, "paper");
    let r = &report.recordings[0];
    assert!(r.interpolated);
    assert_eq!(r.rmse_n, 0.0);
    let b = r.bracket.as_ref().unwrap();
    assert_eq!((b.lower_current_a, b.upper_current_a), (0.5, 1.0));
    // The recording is the interpolated model itself: every sample lies between.
    assert_eq!(b.measured_between, 1.0);

    // Every other sample 100 kN above both neighbours: exactly half lie between.
    let mut shifted = recording(&table, 0.7, 1.0, Role::Validate);
    for f in shifted.samples.force_n.iter_mut().step_by(2) {
        *f += 1e5;
    }
    let b = validate_recording(&table, &shifted).bracket.unwrap();
    assert_eq!(b.measured_between, 0.5);
}

#[test]
fn report_files_hold_the_same_numbers() {
    let table = Table::paper().unwrap();
    let ds = Dataset {
        name: "synthetic".into(),
        root: ".".into(),
        recordings: vec![recording(&table, 0.5, 1.1, Role::Fit)],
    };
    let report = validate(&ds, &table, "paper");
    let dir = tempfile::tempdir().unwrap();
    mre_host::validate::report::write(dir.path(), &report).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("report.json")).unwrap()).unwrap();
    let rmse = json["recordings"][0]["rmse_n"].as_f64().unwrap();
    assert!((rmse - report.recordings[0].rmse_n).abs() < 1e-12 * rmse);
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(md.contains(&format!("| {:.2} |", rmse)));
}

#[test]
fn a_recorded_current_column_is_followed_sample_by_sample() {
    // A controlled loop: the force was made at 0.5 A for the first half and
    // 1.5 A for the second, and the per-sample `current_a` column says so.
    // Predicted at the header's 0.5 A throughout, the second half would be wrong.
    let table = Table::paper().unwrap();
    let low = recording(&table, 0.5, 1.0, Role::Validate);
    let high = recording(&table, 1.5, 1.0, Role::Validate);
    let mut rec = low.clone();
    let half = rec.samples.force_n.len() / 2;
    rec.samples.force_n[half..].copy_from_slice(&high.samples.force_n[half..]);
    let n = rec.samples.force_n.len();
    rec.samples.current_a = Some((0..n).map(|i| if i < half { 0.5 } else { 1.5 }).collect());
    let r = validate_recording(&table, &rec);
    assert!(r.rmse_n < 1e-3, "rmse {}", r.rmse_n);
    // The same recording without the column is predicted at 0.5 A: the
    // second half's error is the 0.5 A vs 1.5 A force difference, not zero.
    rec.samples.current_a = None;
    assert!(validate_recording(&table, &rec).rmse_n > 1.0);
}

/// Output hygiene (#27): a bracket's neighbour currents print as written.
#[test]
fn f32_currents_print_as_written() {
    assert_eq!(mre_host::validate::as_written(0.45f32).to_string(), "0.45");
    assert_eq!(mre_host::validate::as_written(0.73f32).to_string(), "0.73");
    assert_ne!((0.45f32 as f64).to_string(), "0.45", "the cast this replaces");
}
