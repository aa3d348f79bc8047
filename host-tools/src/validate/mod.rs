//! `mre validate`: how well a table reproduces each recording.
//!
//! The model force is the core's (`Table::force`, the board's f32 arithmetic):
//! branch by the sign of v, linear interpolation in current between entries.
//! Per recording:
//! - RMSE (N) over all samples;
//! - NRMSE = RMSE / (max F − min F) of the *measured* force (its range);
//! - peak force: largest |F| measured and largest |F| modelled;
//! - the point of largest error (the paper's Tables 5/6): the sample where
//!   |F_meas − F_model| is largest, with both forces there and the error in %
//!   of the measured force, `|F_meas − F_model| / |F_meas| · 100`.
//!
//! Recordings whose current is not a table entry are predicted by
//! interpolation (never fitted: `fit` only uses `role = "fit"`). For those,
//! the Fig. 12 bracket check: which fraction of the measured samples lies
//! between the neighbours' loops? (The interpolated model itself always does:
//! linear interpolation, so that is not reported.)
pub mod report;

use crate::dataset::{Dataset, Recording, Role};
use mre_algorithm::table::Table;
use mre_algorithm::Flags;
use serde::Serialize;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LargestError {
    pub sample: usize,
    pub time_s: f64,
    pub x_mm: f64,
    pub measured_n: f64,
    pub model_n: f64,
    /// |measured − model| / |measured| · 100.
    pub error_pct: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bracket {
    pub lower_current_a: f64,
    pub upper_current_a: f64,
    /// Fraction of measured samples lying between the neighbours' models.
    pub measured_between: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RecordingReport {
    pub file: String,
    pub current_a: f64,
    pub role: Role,
    /// True when the current is not a table entry (predicted by interpolation).
    pub interpolated: bool,
    pub samples: usize,
    pub rmse_n: f64,
    /// RMSE / measured force range.
    pub nrmse: f64,
    pub peak_measured_n: f64,
    pub peak_model_n: f64,
    pub largest_error: LargestError,
    /// Fraction of samples outside the table's fitted stroke (x clamped).
    pub x_clamped_fraction: f64,
    pub velocity_estimated: bool,
    /// Set when velocity and displacement were integrated from force or
    /// acceleration: what from (docs/dataset-format.md).
    pub motion_derived_from: Option<String>,
    /// What the file's reader assumed (`Recording::notes`): rows skipped,
    /// a units row read, tied time stamps spread, a vendor block picked.
    pub reading_notes: Vec<String>,
    pub bracket: Option<Bracket>,
}

/// The point of largest error is sought only where the measured force is
/// at least this share of its peak: near zero force a percentage error
/// means nothing (a 50 N miss at 0.3 N measured is 16 000 %).
pub const PERCENT_ERROR_MIN_SHARE: f64 = 0.10;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ValidationReport {
    pub dataset: String,
    pub model: String,
    pub nrmse_normaliser: String,
    /// [`PERCENT_ERROR_MIN_SHARE`], as used.
    pub percent_error_min_share_of_peak: f64,
    pub recordings: Vec<RecordingReport>,
}

/// The model's force for every sample of a recording (N), and whether x was
/// clamped. The current is the recording's per-sample `current_a` column when
/// it has one (a controlled impact), else the current it held.
pub fn model_forces(table: &Table, rec: &Recording) -> (Vec<f64>, Vec<bool>) {
    let s = &rec.samples;
    let current_at = |t: usize| {
        s.current_a
            .as_ref()
            .and_then(|c| c.get(t).copied())
            .unwrap_or(rec.current_a)
    };
    s.x_mm
        .iter()
        .zip(&s.v_m_s)
        .enumerate()
        .map(|(t, (&x, &v))| {
            let r = table.force(x as f32, v as f32, current_at(t) as f32);
            (r.force_n as f64, r.flags.contains(Flags::X_CLAMPED))
        })
        .unzip()
}

/// Validates every recording of `ds` against `table`.
pub fn validate(ds: &Dataset, table: &Table, model_label: &str) -> ValidationReport {
    ValidationReport {
        dataset: ds.name.clone(),
        model: model_label.to_string(),
        nrmse_normaliser: crate::error_measure::DEFINITION.to_string(),
        percent_error_min_share_of_peak: PERCENT_ERROR_MIN_SHARE,
        recordings: ds.recordings.iter().map(|r| validate_recording(table, r)).collect(),
    }
}

pub fn validate_recording(table: &Table, rec: &Recording) -> RecordingReport {
    let (model, clamped) = model_forces(table, rec);
    let measured = &rec.samples.force_n;
    let n = measured.len().max(1) as f64;
    let sse: f64 = measured.iter().zip(&model).map(|(m, p)| (m - p).powi(2)).sum();
    let rmse_n = (sse / n).sqrt();
    let (lo, hi) = crate::fit::poly::min_max(measured);
    let range = hi - lo;
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let floor_n = PERCENT_ERROR_MIN_SHARE * peak(measured);
    let worst = measured
        .iter()
        .zip(&model)
        .enumerate()
        .filter(|(_, (m, _))| m.abs() >= floor_n)
        .max_by(|a, b| (a.1 .0 - a.1 .1).abs().total_cmp(&(b.1 .0 - b.1 .1).abs()))
        .map_or(0, |(i, _)| i);
    let measured_n = measured.get(worst).copied().unwrap_or(0.0);
    let model_n = model.get(worst).copied().unwrap_or(0.0);
    let interpolated = !table.entries().iter().any(|e| e.current_a == rec.current_a as f32);
    RecordingReport {
        file: rec.file.clone(),
        current_a: rec.current_a,
        role: rec.role,
        interpolated,
        samples: measured.len(),
        rmse_n,
        nrmse: crate::error_measure::nrmse(rmse_n, range),
        peak_measured_n: peak(measured),
        peak_model_n: peak(&model),
        largest_error: LargestError {
            sample: worst,
            time_s: rec.samples.time_s.get(worst).copied().unwrap_or(0.0),
            x_mm: rec.samples.x_mm.get(worst).copied().unwrap_or(0.0),
            measured_n,
            model_n,
            error_pct: if measured_n != 0.0 {
                (measured_n - model_n).abs() / measured_n.abs() * 100.0
            } else {
                f64::NAN
            },
        },
        x_clamped_fraction: clamped.iter().filter(|&&c| c).count() as f64 / n,
        velocity_estimated: rec.velocity_estimated,
        motion_derived_from: rec.motion_from.map(|m| m.describe()),
        reading_notes: rec.notes.clone(),
        bracket: if interpolated { bracket(table, rec) } else { None },
    }
}

/// The tabulated currents just below and above `current_a`, if it lies strictly inside.
pub fn neighbours(table: &Table, current_a: f64) -> Option<(f32, f32)> {
    let c = current_a as f32;
    let e = table.entries();
    e.windows(2)
        .find(|w| w[0].current_a < c && c < w[1].current_a)
        .map(|w| (w[0].current_a, w[1].current_a))
}

fn between(f: f64, a: f64, b: f64) -> bool {
    f >= a.min(b) && f <= a.max(b)
}

/// The Fig. 12 check for one interpolated recording.
pub fn bracket(table: &Table, rec: &Recording) -> Option<Bracket> {
    let (lo, hi) = neighbours(table, rec.current_a)?;
    let s = &rec.samples;
    let measured_inside = s
        .x_mm
        .iter()
        .zip(&s.v_m_s)
        .zip(&s.force_n)
        .filter(|((&x, &v), &f)| {
            let fl = table.force(x as f32, v as f32, lo).force_n as f64;
            let fh = table.force(x as f32, v as f32, hi).force_n as f64;
            between(f, fl, fh)
        })
        .count();
    Some(Bracket {
        lower_current_a: as_written(lo),
        upper_current_a: as_written(hi),
        measured_between: measured_inside as f64 / s.len().max(1) as f64,
    })
}

/// A table's f32 current as the number that was written (0.45, not the
/// 0.44999998807907104 that `as f64` gives): f32's shortest decimal form.
pub fn as_written(current_a: f32) -> f64 {
    current_a.to_string().parse().unwrap_or(current_a as f64)
}

/// `mre validate DATASET --model MODEL --report DIR`.
pub fn run_validate(
    dataset_dir: &std::path::Path,
    model: &str,
    hold_out_a: &[f64],
    report_dir: &std::path::Path,
) -> anyhow::Result<ValidationReport> {
    let mut ds = Dataset::load(dataset_dir)?;
    crate::fit::problems::hold_out(&mut ds, hold_out_a);
    let table = crate::table_file::load_table(model)?;
    let report = validate(&ds, &table, model);
    report::write(report_dir, &report)?;
    crate::html::Page::new(format!("Validation of {}", report.dataset))
        .folder(report_dir)
        .write(&report_dir.join("index.html"))?;
    Ok(report)
}
