//! `mre diagnose … --model-out final.toml`: the diagnosis's final model as a
//! model file, which `mre tables` turns into flash. It carries the
//! installation (format 3): the data set's metadata and `--installation`
//! options over the defaults (`crate::installation`).
//!
//! The table holds the per-current branch quartics (fitted with every named
//! term) scaled by each term's [`Term::table_scale`]; then each term of the
//! final model writes itself in ([`Term::write_table`]): a coefficient of
//! the core's model terms, a change to the quartics, or `[diagnose]`
//! metadata. What each term writes, and what no table can carry, is listed
//! in `docs/effects.md`.
use super::design::{Layout, QUARTIC_TERMS};
use super::report::{write_all, ReportJson};
use super::terms::{TableParts, Term, REGISTRY};
use super::{diagnose, DiagnoseOptions, Diagnosis};
use crate::dataset::Dataset;
use crate::installation::StatedInstallation;
use anyhow::{anyhow, Result};
use mre_algorithm::table::{CurrentEntry, ModelTerms, Quartic, Table, MAX_CURRENTS};
use std::path::Path;

/// The final model as a version 2 table (without its installation).
pub fn final_table(d: &Diagnosis) -> Result<Table> {
    table_and_metadata(d).map(|(t, _)| t)
}

/// The table and the `[diagnose]` metadata the final model's terms write.
fn table_and_metadata(d: &Diagnosis) -> Result<(Table, Vec<(String, f64)>)> {
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
    let present: Vec<&'static dyn Term> = REGISTRY.iter().copied().filter(|t| t.present_in(terms)).collect();
    let scale: f64 = present.iter().map(|t| t.table_scale(prep, terms, sol)).product();
    let mut parts = TableParts {
        quartics: Vec::new(),
        stroke_mm: Vec::new(),
        scale,
        fastest_m_s: prep
            .recs
            .iter()
            .flat_map(|r| r.v_m_s.iter())
            .fold(0.0f64, |m, v| m.max(v.abs())),
        terms: ModelTerms::NONE,
        metadata: Vec::new(),
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
        parts.stroke_mm.push((lo, hi));
        // x⁰..x⁴ as fitted, at the table's scale.
        let powers = |comp: bool| -> [f64; QUARTIC_TERMS] {
            std::array::from_fn(|p| scale * sol.beta[layout.quartic_col(k, comp, p)])
        };
        parts.quartics.push([powers(true), powers(false)]);
    }
    for t in &present {
        t.write_table(&layout, terms, sol, &mut parts)?;
    }
    // The core stores the highest power first.
    let quartic = |p: &[f64; QUARTIC_TERMS]| Quartic::new(std::array::from_fn(|i| p[QUARTIC_TERMS - 1 - i] as f32));
    let entries: Vec<CurrentEntry> = prep
        .currents_a
        .iter()
        .zip(parts.quartics.iter().zip(&parts.stroke_mm))
        .map(|(&current_a, (q, &(lo, hi)))| CurrentEntry {
            current_a: current_a as f32,
            compression: quartic(&q[0]),
            extension: quartic(&q[1]),
            x_min_mm: lo as f32,
            x_max_mm: hi as f32,
        })
        .collect();
    let table = Table::with_terms(&entries, parts.terms).map_err(|e| anyhow!("final model: {e}"))?;
    Ok((table, parts.metadata))
}

/// The model file: `[model]` provenance, the identified values as metadata
/// (`[diagnose]`), then the table (`[terms]`, `[[current]]`).
pub fn model_file_text(d: &Diagnosis, table: &Table, dataset_name: &str, input_sha256: &str) -> String {
    let found: Vec<String> = d.findings.iter().map(|f| format!("{:?}", f.effect.name())).collect();
    let mut s = String::new();
    s.push_str("# Written by `mre diagnose --model-out`: the diagnosis's final model as a table file.\n");
    s.push_str("# `mre tables` turns it into flash; [model] and [diagnose] are metadata.\n");
    s.push_str(&format!(
        "\n[model]\ndataset = {dataset_name:?}\ninput_sha256 = {input_sha256:?}\nmethod = \"diagnose\"\n"
    ));
    s.push_str(&format!("\n[diagnose]\neffects = [{}]\n", found.join(", ")));
    for (key, value) in table_and_metadata(d).map(|(_, m)| m).unwrap_or_default() {
        s.push_str(&format!("{key} = {value:?}\n"));
    }
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
    let report = write_all(&d, &ds, report_dir, json_path, predictions_dir)?;
    crate::atomic_write::write_atomic(model_out, text.as_bytes())?;
    Ok((report, table, installation))
}
