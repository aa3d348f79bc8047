//! `mre diagnose`: locate the model-vs-recording mismatch, name the missing
//! physics from the vocabulary (`docs/effects.md`), model it, and show
//! the out-of-sample fit improve.
//!
//! Stages, each using only those before it: [`prepared`] (channels, folds,
//! branches; on the primitives of [`signals`]) → [`baseline`] (the paper's
//! model) → [`locate`] (where the residual sits) → [`library`] (one joint
//! design: the quartics and every identifiable term of [`terms`], its value
//! chosen by [`cv`], its columns built by [`design`]) → [`select`] (group
//! STLSQ of [`sparse`], ensemble inclusion and nested held-out gain, gated
//! by the two numbers of [`acceptance`]) → [`verdict`] → [`parameters`]
//! (values and intervals) → [`report`] (with what stays [`unexplained`]).
pub mod acceptance;
pub mod baseline;
pub mod candidates;
pub mod cv;
pub mod design;
pub mod heldout;
pub mod library;
pub mod locate;
pub mod model_out;
pub mod parameters;
pub mod plots;
pub mod prepared;
pub mod report;
pub mod select;
pub mod signals;
pub mod sparse;
pub mod terms;
pub mod unexplained;
pub mod validate_terms;
pub mod verdict;

use crate::dataset::Dataset;
use acceptance::Thresholds;
use anyhow::Result;
use candidates::Effect;
use cv::Scored;
use design::Designs;
use mre_algorithm::table::Table;
use prepared::{FoldPlan, Prepared};
use select::Selection;

#[derive(Clone, Debug)]
pub struct DiagnoseOptions {
    /// Use this table as the baseline instead of fitting one.
    pub model: Option<Table>,
    pub folds: FoldPlan,
    /// Treat recordings at these currents as `validate` (held out).
    pub validate_currents_a: Vec<f64>,
    pub thresholds: Thresholds,
    /// Bootstrap resamples for parameter intervals.
    pub parameter_resamples: usize,
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            model: None,
            folds: FoldPlan::Stratified { k: 5 },
            validate_currents_a: Vec::new(),
            thresholds: Thresholds::default(),
            parameter_resamples: 200,
        }
    }
}

impl DiagnoseOptions {
    /// The defaults, with the validate recordings as the evidence for the
    /// terms that change only their predictions (`coil_lag`,
    /// `magnetic_saturation`): for a campaign whose controlled impacts are
    /// there to pin the coil, not to check the model.
    pub fn with_validate_evidence() -> Self {
        let mut o = DiagnoseOptions::default();
        o.thresholds.validate_evidence = true;
        o
    }
}

/// A named effect with its evidence.
#[derive(Clone, Debug)]
pub struct Finding {
    pub effect: Effect,
    pub parameters: std::collections::BTreeMap<String, parameters::Param>,
    pub evidence: String,
    /// Held-out RMSE over the library's recordings without → with the term
    /// (nested: the rest of the model chosen without each fold).
    pub rmse_n_before: f64,
    pub rmse_n_after: f64,
    /// The same ratio with the rest of the model chosen on all data.
    pub heldout_improvement: f64,
    /// The headline: the nested ratio ([`select::Candidate::gain`]).
    pub heldout_improvement_nested: f64,
    /// 95 % bootstrap interval of `heldout_improvement_nested`, over the
    /// same recordings.
    pub ratio_ci95: [f64; 2],
    /// Share of the ensemble's fits that kept it.
    pub inclusion_probability: f64,
    /// The per-recording held-out SSEs the nested ratio comes from.
    pub nested: heldout::HeldOutRatio,
}

/// Everything the diagnosis found, for the report writers.
#[derive(Clone, Debug)]
pub struct Diagnosis {
    pub prep: Prepared,
    pub baseline_table: Table,
    /// Whether the baseline table was given (`--model`) rather than fitted.
    pub baseline_given: bool,
    pub locate: locate::Locate,
    pub selection: Selection,
    pub findings: Vec<Finding>,
    pub baseline_pred: Vec<Vec<f64>>,
    pub final_pred: Vec<Vec<f64>>,
    /// Samples the baseline and final metrics are computed on: those both
    /// models score.
    pub scored_mask: Vec<Vec<bool>>,
    /// Where the final residual is still concentrated, beyond the noise.
    pub unexplained: Vec<unexplained::Unexplained>,
    /// Found, none or inconclusive, with the reasons and deciding experiments.
    pub verdict: verdict::VerdictReport,
    pub thresholds: Thresholds,
    /// Bootstrap resamples behind the parameter intervals.
    pub parameter_resamples: usize,
}

/// In-sample predictions of a scored model for every recording.
pub fn predictions(prep: &Prepared, scored: &Scored) -> Vec<Vec<f64>> {
    let d = Designs::build(prep, &scored.terms);
    (0..prep.recs.len())
        .map(|i| d.predict(prep, i, &scored.solution))
        .collect()
}

/// Runs the whole diagnosis on a loaded data set.
pub fn diagnose(ds: &Dataset, opts: &DiagnoseOptions) -> Result<Diagnosis> {
    let mut prep = prepared::prepare(ds, &opts.folds, &opts.validate_currents_a)?;
    prep.validate_evidence = opts.thresholds.validate_evidence;
    let (baseline_table, baseline_given) = match &opts.model {
        Some(t) => (*t, true),
        None => (baseline::fit_table(&prep)?, false),
    };
    let baseline_pred = baseline::predict_all(&prep, &baseline_table);
    let loc = locate::locate(&prep, &baseline_pred);
    let selection = select::select(&prep, &opts.thresholds)?;
    let final_pred = if selection.candidates.iter().any(|c| c.named) {
        predictions(&prep, &selection.final_model)
    } else {
        baseline_pred.clone()
    };
    let mut findings = Vec::new();
    // The strongest first: ranked by nested held-out gain.
    let mut named: Vec<&select::Candidate> = selection.candidates.iter().filter(|c| c.named).collect();
    named.sort_by(|a, b| b.gain.ratio.total_cmp(&a.gain.ratio));
    for c in named {
        // The final model without this term: what the evidence compares.
        let without = terms::of(c.effect).map_or(selection.final_model.terms, |t| {
            t.removed_from(&selection.final_model.terms)
        });
        let pred_before = predictions(&prep, &cv::score(&prep, &[without])?);
        // The term's variants on the rest of the final model: its searched
        // parameters' intervals re-choose among them.
        let around = match terms::of(c.effect) {
            Some(t) if !t.searched().is_empty() => {
                cv::score_refined(&prep, t.variants(&prep, &without), &|best| t.refinements(&prep, best))?.variant_sse
            }
            _ => selection.final_model.variant_sse.clone(),
        };
        // The recordings its held-out ratio is over.
        let pool = if c.decided_by.is_empty() {
            prep.fit_indices()
        } else {
            c.decided_by.clone()
        };
        let n_samples: usize = pool.iter().map(|&i| selection.final_model.n[i]).sum::<usize>().max(1);
        findings.push(Finding {
            effect: c.effect,
            parameters: parameters::with_intervals(
                &prep,
                c.effect,
                &selection.final_model.terms,
                &selection.final_model.solution,
                &around,
                opts.parameter_resamples,
                opts.thresholds.seed,
            )?,
            evidence: evidence_for(&prep, c, &pred_before, &final_pred),
            rmse_n_before: (c.gain.sse_before.iter().sum::<f64>() / n_samples as f64).sqrt(),
            rmse_n_after: (c.gain.sse_after.iter().sum::<f64>() / n_samples as f64).sqrt(),
            heldout_improvement: c.gain_plain,
            heldout_improvement_nested: c.gain.ratio,
            ratio_ci95: c.gain.ci95,
            inclusion_probability: c.inclusion,
            nested: c.gain.clone(),
        });
    }
    let scored_mask: Vec<Vec<bool>> = prep
        .recs
        .iter()
        .zip(&selection.final_model.mask)
        .map(|(r, m)| prepared::scored_by_both(&r.in_domain, m))
        .collect();
    let unexplained = unexplained::locate_unexplained(&prep, &final_pred, &scored_mask);
    let verdict = verdict::decide(&prep, &selection, findings.len(), &opts.thresholds);
    Ok(Diagnosis {
        prep,
        baseline_table,
        baseline_given,
        locate: loc,
        selection,
        findings,
        baseline_pred,
        final_pred,
        scored_mask,
        unexplained,
        verdict,
        thresholds: opts.thresholds,
        parameter_resamples: opts.parameter_resamples,
    })
}

fn evidence_for(prep: &Prepared, c: &select::Candidate, pred_before: &[Vec<f64>], pred_after: &[Vec<f64>]) -> String {
    let effect = c.effect;
    let loc = locate::locate(prep, pred_before);
    let (mut res, mut term) = (Vec::new(), Vec::new());
    // Where the added term acts: recordings ranked by the RMS change it makes.
    let mut acts: Vec<(f64, &str, String)> = Vec::new();
    for (i, r) in prep.recs.iter().enumerate() {
        let mut e = 0.0;
        for t in 0..r.len() {
            res.push(r.force_n[t] - pred_before[i][t]);
            let d = pred_after[i][t] - pred_before[i][t];
            term.push(d);
            e += d * d;
        }
        acts.push(((e / r.len().max(1) as f64).sqrt(), r.file.as_str(), r.current_label()));
    }
    acts.sort_by(|a, b| b.0.total_cmp(&a.0));
    let acts_on: Vec<String> = acts
        .iter()
        .take(3)
        .map(|(rms, f, c)| format!("{f} ({c} A, {rms:.0} N RMS)"))
        .collect();
    // The covariates the effect's signature follows, as named by [`locate`].
    let sig = terms::of(effect).map_or(&[][..], |t| t.signature());
    let follows = loc
        .sample_correlations
        .iter()
        .chain(&loc.recording_correlations)
        .find(|(n, _)| sig.contains(&n.as_str()))
        .map(|(n, r)| format!("; residual correlates with {n} (r = {r:+.2})"))
        .unwrap_or_default();
    let files = |ix: &[usize]| {
        let f: Vec<&str> = ix.iter().map(|&i| prep.recs[i].file.as_str()).collect();
        if f.is_empty() {
            "none".to_string()
        } else {
            f.join(", ")
        }
    };
    let kept = if c.decided_by.is_empty() {
        format!("kept by {:.0} % of the ensemble's fits", 100.0 * c.inclusion)
    } else {
        format!(
            "decided on the validate recordings {} (each predicted with the value chosen on the others; it \
             lowered the error of {:.0} % of them), the rest of the model chosen on the fit recordings; kept \
             as the check, read by no decision: {}",
            files(&c.decided_by),
            100.0 * c.inclusion,
            files(&c.checked_by)
        )
    };
    format!(
        "{}; {:.2}× held out, nested (95 % bootstrap over the recordings \
         {:.2}–{:.2}×; {:.2}× with the rest of the model chosen on all data); \
         residual before: {}{}; the term acts most on {} and explains the residual with r = {:.2}",
        kept,
        c.gain.ratio,
        c.gain.ci95[0],
        c.gain.ci95[1],
        c.gain_plain,
        locate::describe(&loc),
        follows,
        acts_on.join(", "),
        locate::pearson(&res, &term)
    )
}

/// Options from the CLI's flags.
pub fn options_from_cli(
    model: Option<&str>,
    folds_by: Option<String>,
    folds: usize,
    validate_currents_a: Vec<f64>,
    seed: u64,
) -> Result<DiagnoseOptions> {
    if validate_currents_a.iter().any(|c| !c.is_finite()) {
        anyhow::bail!("--validate-current must be a finite current in A");
    }
    Ok(DiagnoseOptions {
        model: model.map(crate::table_file::load_table).transpose()?,
        folds: match folds_by {
            Some(tag) => FoldPlan::ByTag(tag),
            None => FoldPlan::Stratified { k: folds },
        },
        validate_currents_a,
        thresholds: Thresholds {
            seed,
            ..Thresholds::default()
        },
        ..DiagnoseOptions::default()
    })
}

/// `mre diagnose`: loads the data set, diagnoses it and writes every output.
/// Nothing is written unless the diagnosis succeeds.
pub fn run_to_files(
    dataset_dir: &std::path::Path,
    opts: &DiagnoseOptions,
    report_dir: &std::path::Path,
    json_path: &std::path::Path,
    predictions_dir: &std::path::Path,
) -> Result<report::ReportJson> {
    let json_path = &in_a_folder(json_path);
    let ds = Dataset::load(dataset_dir)?;
    let d = diagnose(&ds, opts)?;
    let json = report::write_all(&d, &ds, report_dir, json_path, predictions_dir)?;
    crate::html::Page::new(format!("Diagnosis of {}", dataset_dir.display()))
        .folder(report_dir)
        .file(json_path)
        .write(&report_dir.join("index.html"))?;
    Ok(json)
}

/// `path` with its folder spelt out: a bare file name (`--json diag.json`)
/// has an empty parent, which the HTML page cannot list; `./diag.json` has one.
pub fn in_a_folder(path: &std::path::Path) -> std::path::PathBuf {
    match path.parent() {
        Some(p) if p.as_os_str().is_empty() => std::path::Path::new(".").join(path),
        _ => path.to_path_buf(),
    }
}

/// One line for the terminal: what was found.
pub fn summary_line(r: &report::ReportJson) -> String {
    if r.effects.is_empty() {
        let head = match r.verdict.verdict {
            verdict::Verdict::Inconclusive => {
                let mut codes: Vec<&str> = r.verdict.reasons.iter().map(|x| x.code).collect();
                codes.dedup();
                format!("inconclusive: {}", codes.join(", "))
            }
            _ => "no missing physics found".to_string(),
        };
        return format!(
            "{head} (baseline RMSE {:.3} N, NRMSE {:.2} %; final held-out residual {:.0}× the force noise)",
            r.baseline.rmse_n,
            100.0 * r.baseline.nrmse,
            r.verdict.residual_over_noise
        );
    }
    let names: Vec<String> = r
        .effects
        .iter()
        // The nested figure: each held-out unit scored by a choice it played
        // no part in (the plain one carries the winner's selection bias).
        .map(|e| format!("{} ({:.2}× held out, nested)", e.name, e.heldout_improvement_nested))
        .collect();
    format!(
        "found: {}; RMSE {:.3} → {:.3} N",
        names.join(", "),
        r.baseline.rmse_n,
        r.final_.rmse_n
    )
}
