//! `mre compare`: model families side by side on one data set (the paper's
//! Fig. 15 compares its polynomial with an exponential-type model).
//!
//! Every family is fitted on the `fit` recordings only and predicts every
//! recording; `validate` recordings (and held-out currents) are only
//! predicted. Families: the paper's quartics by least squares and by GSA,
//! the quartics with the terms `mre diagnose` selects, and the nonlinear
//! families of [`families`] (GSA, then Levenberg–Marquardt: [`fit`]).
//! [`report`] writes report.json, report.md and the predictions; [`plots`]
//! the overlays.
pub mod bench;
pub mod families;
pub mod fastmath;
pub mod fit;
pub mod plots;
pub mod polynomial;
pub mod report;
pub mod tracks;

use crate::dataset::{Dataset, Role};
use crate::fit::gsa::GsaParams;
use crate::fit::Method;
use anyhow::{bail, Result};
use families::{CurrentLaw, Family, StepCost};
use fit::Budget;
use serde_json::json;
use std::time::Instant;
use tracks::Track;

#[derive(Clone, Debug, PartialEq)]
pub struct CompareOptions {
    /// Recordings at these currents are only predicted.
    pub hold_out_a: Vec<f64>,
    /// Nonlinear families' search budget.
    pub budget: Budget,
    /// GSA of the paper's polynomial (the paper's N = T = 100 by default).
    pub poly_gsa: GsaParams,
    pub seed: u64,
    /// Leave out the polynomial-plus-diagnosis family (it runs the whole diagnosis).
    pub skip_diagnosis: bool,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            hold_out_a: vec![0.5],
            budget: Budget::default(),
            poly_gsa: GsaParams::default(),
            seed: 1,
            skip_diagnosis: false,
        }
    }
}

impl CompareOptions {
    /// The budget `mre demo` uses: a quarter of the GSA iterations and
    /// coarser recordings for the nonlinear families.
    pub fn reduced() -> CompareOptions {
        let mut o = CompareOptions::default();
        o.budget.gsa.iters = 60;
        o.budget.gsa.agents = 30;
        o.budget.lm_samples_per_track = 1500;
        o.budget.lm_patience = 15;
        o
    }
}

/// One family's outcome.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub name: String,
    /// "polynomial" or "nonlinear".
    pub kind: &'static str,
    pub equations: String,
    pub note: String,
    pub parameters: serde_json::Value,
    pub n_parameters: usize,
    /// One per track, in track order.
    pub predictions: Vec<Vec<f64>>,
    pub fit_time_s: f64,
    /// Objective evaluations spent (nonlinear families).
    pub evaluations: Option<usize>,
    pub step_cost: Option<StepCost>,
}

/// Everything a comparison produced.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub dataset: String,
    pub options: CompareOptions,
    pub tracks: Vec<Track>,
    pub outcomes: Vec<Outcome>,
    /// Families this data set is too small for, each with what is missing.
    pub left_out: Vec<LeftOut>,
    /// What the readers assumed reading each recording (`summary::recording_notes`),
    /// for the recordings where they assumed anything.
    pub reading_notes: Vec<report::RecordingNotes>,
    pub total_time_s: f64,
}

/// A family not fitted, and what the data set lacks for it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LeftOut {
    pub family: String,
    pub missing: String,
}

/// What the data set lacks for a comparison at all: fit recordings, and fit
/// currents on both sides of every held-out one (its loops are interpolated).
fn what_is_missing(tracks: &[tracks::Track], hold_out_a: &[f64]) -> Option<String> {
    let fit_a = crate::dataset::distinct_currents_a(tracks.iter().filter(|t| t.role == Role::Fit).map(|t| t.current_a));
    let (Some(&lo), Some(&hi)) = (fit_a.first(), fit_a.last()) else {
        return Some("no recording is left to fit once the held-out currents are set aside".into());
    };
    let outside: Vec<String> = hold_out_a
        .iter()
        .filter(|&&c| c <= lo || c >= hi)
        .map(|c| format!("{c} A"))
        .collect();
    (!outside.is_empty()).then(|| {
        format!(
            "held-out {} not between two fitted currents (fitted: {:?} A): a held-out current is predicted by \
             interpolating its neighbours, so record currents on both sides of it or hold out another",
            outside.join(", "),
            fit_a
        )
    })
}

/// Why `polynomial+diagnose` cannot be scored, if it cannot: the diagnosis
/// cross-validates over folds of fit recordings, so it needs one per fold.
fn diagnosis_needs(tracks: &[tracks::Track]) -> Option<String> {
    let folds = match crate::diagnose::DiagnoseOptions::default().folds {
        crate::diagnose::prepared::FoldPlan::Stratified { k } => k,
        crate::diagnose::prepared::FoldPlan::ByTag(_) => return None,
    };
    let fit = tracks.iter().filter(|t| t.role == Role::Fit).count();
    (fit < folds).then(|| {
        format!(
            "too few fit recordings: `mre diagnose` cross-validates over {folds} folds of recordings and this \
             data set has {fit}; add recordings (at least {folds} fit recordings) to score it"
        )
    })
}

/// Fits every family on `ds` (loaded) and predicts every recording.
pub fn compare(ds: &Dataset, options: &CompareOptions) -> Result<Comparison> {
    let start = Instant::now();
    let mut ds = ds.clone();
    crate::fit::problems::hold_out(&mut ds, &options.hold_out_a);
    let tracks = tracks::tracks(&ds, &[]);
    if let Some(missing) = what_is_missing(&tracks, &options.hold_out_a) {
        bail!("data set `{}` cannot be compared: {missing}", ds.name);
    }
    let mut outcomes = Vec::new();
    let mut left_out = Vec::new();
    for (name, method) in [("polynomial-lsq", Method::Lsq), ("polynomial-gsa", Method::Gsa)] {
        let t0 = Instant::now();
        let p = polynomial::quartics(
            &ds,
            method,
            GsaParams {
                seed: options.seed,
                ..options.poly_gsa
            },
        )?;
        outcomes.push(poly_outcome(
            name,
            "F = a1·x⁴ + … + a5 per current and branch (v > 0 / v ≤ 0), forces interpolated in I",
            p,
            t0,
        ));
    }
    let diagnosis_missing = diagnosis_needs(&tracks);
    if let (false, Some(missing)) = (options.skip_diagnosis, &diagnosis_missing) {
        left_out.push(LeftOut {
            family: "polynomial+diagnose".into(),
            missing: missing.clone(),
        });
    }
    if !options.skip_diagnosis && diagnosis_missing.is_none() {
        let t0 = Instant::now();
        let p = polynomial::with_diagnosis(&ds, &options.hold_out_a, &tracks)?;
        outcomes.push(poly_outcome(
            "polynomial+diagnose",
            "the quartics plus the terms `mre diagnose` accepts when run on the fit recordings alone (fitted jointly by its least squares)",
            p,
            t0,
        ));
    }
    for family in families::all() {
        outcomes.push(nonlinear(family.as_ref(), &tracks, options));
    }
    Ok(Comparison {
        dataset: ds.name.clone(),
        options: options.clone(),
        tracks,
        outcomes,
        left_out,
        // The same notes `mre dataset check` and the diagnosis give: the
        // readers', then how motion or velocity was had when not measured.
        reading_notes: crate::dataset::summary::notes_by_file(&ds),
        total_time_s: start.elapsed().as_secs_f64(),
    })
}

fn poly_outcome(name: &str, equations: &str, p: polynomial::PolyOutcome, t0: Instant) -> Outcome {
    Outcome {
        name: name.into(),
        kind: "polynomial",
        equations: equations.into(),
        note: p.note,
        parameters: p.parameters,
        n_parameters: p.n_parameters,
        predictions: p.predictions,
        fit_time_s: t0.elapsed().as_secs_f64(),
        evaluations: None,
        step_cost: None,
    }
}

/// Fits one nonlinear family and predicts every track.
pub fn nonlinear(family: &dyn Family, tracks: &[Track], options: &CompareOptions) -> Outcome {
    let t0 = Instant::now();
    let fitted = fit::fit_family(family, tracks, &options.budget, options.seed);
    let fit_time_s = t0.elapsed().as_secs_f64();
    let predictions = tracks.iter().map(|t| fit::predict(family, &fitted, t)).collect();
    let names = family.param_names();
    let sets: Vec<serde_json::Value> = fitted
        .sets
        .iter()
        .zip(fitted.gsa_objective.iter().zip(&fitted.lm_objective))
        .map(|((c, p), (g, l))| {
            let values: serde_json::Map<String, serde_json::Value> =
                names.iter().zip(p).map(|(n, v)| (n.to_string(), json!(v))).collect();
            json!({
                "current_a": if c.is_finite() { json!(c) } else { json!("all") },
                "values": values,
                "objective_after_gsa": g,
                "objective_after_lm": l,
            })
        })
        .collect();
    Outcome {
        name: family.name().into(),
        kind: "nonlinear",
        equations: family.equations().into(),
        note: match family.law() {
            CurrentLaw::PerCurrent => "per-current parameters, linear in I between fitted currents".into(),
            CurrentLaw::Joint => "one parameter set, laws linear in I".into(),
        },
        parameters: json!(sets),
        n_parameters: fitted.n_parameters(),
        predictions,
        fit_time_s,
        evaluations: Some(fitted.evaluations),
        step_cost: Some(family.step_cost()),
    }
}

/// `mre compare DATASET --report DIR`: compare, then write every output.
pub fn run_compare(
    dataset_dir: &std::path::Path,
    options: &CompareOptions,
    dir: &std::path::Path,
) -> Result<report::ReportJson> {
    let ds = Dataset::load(dataset_dir)?;
    let c = compare(&ds, options)?;
    let json = report::summarise(&c);
    report::write_all(&c, &json, dir)?;
    plots::overlays(&c, &dir.join("plots"))?;
    crate::html::Page::new("Model families side by side (the paper's Fig. 15)")
        .folder(dir)
        .folder(&dir.join("plots"))
        .write(&dir.join("index.html"))?;
    Ok(json)
}
