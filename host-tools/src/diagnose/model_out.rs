//! `mre diagnose … --model-out final.toml`: the diagnosis's final model as a
//! model file, which `mre tables` turns into flash. It carries the
//! installation (format 3): the data set's metadata and `--installation`
//! options over the defaults (`crate::installation`).
//!
//! What the v2 table holds, from the final model's terms:
//! - the per-current branch quartics (fitted with every accepted term);
//! - `viscous_n_s_per_m`: `c(I)·v`; a saturating `c·v0·tanh(v/v0)` is
//!   written as its secant slope at the fastest recorded speed;
//! - `saturation_current_a`: the `tanh(I/I_s)` interpolation variable;
//! - `coil_tau_s`: the coil lag, which the law inverts.
//!
//! Folded in rather than carried: stress softening scales the quartics and
//! viscous terms by the softening factor of the latest recording (the damper
//! as it is now); an end stop `k_e(I)·max(0, x − x_e)²` (or its mirror at the
//! extension end) is added to each
//! quartic by a least-squares refit over its stroke.
//!
//! Not carried: a delay between the recorded force and displacement channels
//! is compensated in the quartics (fitted at `x(t − τ)`) and written as
//! metadata only, because the controller does not read the force channel
//! (`sensor_delay_s` stays 0: it means the controller's own x/v samples lag);
//! load-cell inertia (a scale in a free drop) and turn-around memory (the
//! core has one quartic per branch) are left out.
use super::design::{end_stop_shape, Layout, Viscous, QUARTIC_TERMS};
use super::report::{write_all, ReportJson};
use super::{diagnose, DiagnoseOptions, Diagnosis};
use crate::dataset::Dataset;
use crate::installation::StatedInstallation;
use crate::linalg::solve;
use anyhow::{anyhow, Result};
use mre_core::table::{CurrentEntry, ModelTerms, Quartic, Table, MAX_CURRENTS};
use nalgebra::{DMatrix, DVector};
use std::path::Path;

/// The final model as a version 2 table (without its installation).
pub fn final_table(d: &Diagnosis) -> Result<Table> {
    let prep = &d.prep;
    let model = &d.selection.final_model;
    let terms = &model.terms;
    let sol = &model.solution;
    let layout = Layout::new(prep.currents_a.len(), terms);
    if prep.currents_a.len() > MAX_CURRENTS {
        return Err(anyhow!(
            "{} currents in the final model, a table holds {MAX_CURRENTS}",
            prep.currents_a.len()
        ));
    }
    // The damper as the latest recording found it.
    let softening = match terms.softening {
        Some(law) => {
            let g = prep
                .recs
                .iter()
                .map(|r| law.covariate(r))
                .fold(f64::NEG_INFINITY, f64::max);
            let g = if g.is_finite() { g } else { 0.0 };
            1.0 - sol.delta * g
        }
        None => 1.0,
    };
    let fastest_m_s = prep
        .recs
        .iter()
        .flat_map(|r| r.v_m_s.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let mut entries = Vec::new();
    let mut mt = ModelTerms {
        saturation_current_a: terms.saturation_i_a.unwrap_or(0.0) as f32,
        coil_tau_s: terms.coil_lag_s.unwrap_or(0.0) as f32,
        ..ModelTerms::NONE
    };
    for (k, &current_a) in prep.currents_a.iter().enumerate() {
        let xs = prep
            .fit_indices()
            .into_iter()
            .filter(|&i| prep.recs[i].current_a == current_a)
            .flat_map(|i| prep.recs[i].x_mm.iter().copied());
        let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
        if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
            return Err(anyhow!("{current_a} A: no fitted stroke"));
        }
        // x⁰..x⁴ as fitted, scaled by the softening factor.
        let powers = |comp: bool| -> [f64; QUARTIC_TERMS] {
            std::array::from_fn(|p| softening * sol.beta[layout.quartic_col(k, comp, p)])
        };
        let with_end_stop = |p: [f64; QUARTIC_TERMS]| -> Result<Quartic> {
            let p = match (terms.end_stop_x_mm, layout.end_stop_at) {
                (Some(x_e), Some(at)) => {
                    add_end_stop(p, softening * sol.beta[at + k], x_e, terms.end_stop_lower, lo, hi)?
                }
                _ => p,
            };
            // The core stores the highest power first.
            Ok(Quartic::new(std::array::from_fn(|i| p[QUARTIC_TERMS - 1 - i] as f32)))
        };
        entries.push(CurrentEntry {
            current_a: current_a as f32,
            compression: with_end_stop(powers(true))?,
            extension: with_end_stop(powers(false))?,
            x_min_mm: lo as f32,
            x_max_mm: hi as f32,
        });
        if let (Some(visc), Some(at)) = (terms.viscous, layout.viscous_at) {
            let c = softening * sol.beta[at + k];
            let slope = match visc {
                Viscous::Linear => c,
                Viscous::Saturating { v0_m_s } if fastest_m_s > 0.0 => {
                    c * v0_m_s * (fastest_m_s / v0_m_s).tanh() / fastest_m_s
                }
                Viscous::Saturating { .. } => c,
            };
            mt.viscous_n_s_per_m[k] = slope as f32;
        }
    }
    Table::with_terms(&entries, mt).map_err(|e| anyhow!("final model: {e}"))
}

/// `p(x) + k_e·`[`end_stop_shape`] projected onto a quartic by least squares
/// on 200 points over `[lo, hi]` (powers x⁰..x⁴).
fn add_end_stop(
    p: [f64; QUARTIC_TERMS],
    k_e: f64,
    x_e: f64,
    lower: bool,
    lo: f64,
    hi: f64,
) -> Result<[f64; QUARTIC_TERMS]> {
    const N: usize = 200;
    let x = |r: usize| lo + (hi - lo) * r as f64 / (N - 1) as f64;
    let a = DMatrix::from_fn(N, QUARTIC_TERMS, |r, c| x(r).powi(c as i32));
    let y = DVector::from_fn(N, |r, _| {
        let xr = x(r);
        let q: f64 = p.iter().rev().fold(0.0, |acc, c| acc * xr + c);
        q + k_e * end_stop_shape(xr, x_e, lower)
    });
    let fit = solve(&a, &y)?;
    Ok(std::array::from_fn(|i| fit.coeffs[i]))
}

/// The model file: `[model]` provenance, the identified values as metadata
/// (`[diagnose]`), then the table (`[terms]`, `[[current]]`).
pub fn model_file_text(d: &Diagnosis, table: &Table, dataset_name: &str, input_sha256: &str) -> String {
    let terms = &d.selection.final_model.terms;
    let found: Vec<String> = d.findings.iter().map(|f| format!("{:?}", f.effect.name())).collect();
    let mut s = String::new();
    s.push_str("# Written by `mre diagnose --model-out`: the diagnosis's final model as a table file.\n");
    s.push_str("# `mre tables` turns it into flash; [model] and [diagnose] are metadata.\n");
    s.push_str(&format!(
        "\n[model]\ndataset = {dataset_name:?}\ninput_sha256 = {input_sha256:?}\nmethod = \"diagnose\"\n"
    ));
    s.push_str(&format!(
        "\n[diagnose]\neffects = [{}]\nforce_channel_delay_s = {:?}\n",
        found.join(", "),
        terms.delay_s.unwrap_or(0.0)
    ));
    let table_text = crate::table_file::table_to_toml(table);
    // `format_version` (the first line) must stay a top-level key, before any [table].
    let (version_line, tables) = table_text.split_at(table_text.find('\n').map_or(0, |i| i + 1));
    format!("{version_line}{s}{tables}")
}

/// The model file's text for a diagnosed data set, in the installation its
/// metadata gives, checked to read back as its table.
pub fn model_file(d: &Diagnosis, ds: &Dataset) -> Result<(Table, String)> {
    model_file_in(d, ds, &StatedInstallation::from_dataset(ds))
}

/// [`model_file`] carrying `installation`.
pub fn model_file_in(d: &Diagnosis, ds: &Dataset, installation: &StatedInstallation) -> Result<(Table, String)> {
    let table = final_table(d)?
        .carrying(installation.installation)
        .map_err(|e| anyhow!("the final model with its installation: {e:?}"))?;
    let sha = crate::dataset::hash::input_sha256(ds)?;
    let text = model_file_text(d, &table, &ds.name, &sha);
    if crate::table_file::parse_table_toml(&text)? != table {
        return Err(anyhow!("internal: the model file does not read back as its table"));
    }
    Ok((table, text))
}

/// `mre diagnose … --model-out PATH [--installation KEY=VALUE]…`:
/// [`super::run_to_files`]'s outputs plus the final model file, and the
/// installation it carries. The model is built before anything is written.
pub fn run_to_files_with_model(
    dataset_dir: &Path,
    opts: &DiagnoseOptions,
    report_dir: &Path,
    json_path: &Path,
    predictions_dir: &Path,
    model_out: &Path,
    installation_options: &[String],
) -> Result<(ReportJson, Table, StatedInstallation)> {
    let ds = Dataset::load(dataset_dir)?;
    let installation = StatedInstallation::from_dataset(&ds).with_options(installation_options)?;
    let d = diagnose(&ds, opts)?;
    let (table, text) = model_file_in(&d, &ds, &installation)?;
    let report = write_all(&d, report_dir, json_path, predictions_dir)?;
    crate::atomic_write::write_atomic(model_out, text.as_bytes())?;
    Ok((report, table, installation))
}
