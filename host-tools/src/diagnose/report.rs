//! Outputs: `report.json` (a contract scripts read), one predictions CSV per
//! recording, and a readable `report.md` with plots.
use super::parameters::Param;
use super::prepared::scored;
use super::{plots, Diagnosis};
use crate::atomic_write::{write_atomic, write_atomic_with};
use anyhow::Result;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Metrics {
    pub rmse_n: f64,
    /// RMSE over the range of measured force.
    pub nrmse: f64,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct EffectEntry {
    pub name: String,
    pub parameters: BTreeMap<String, Param>,
    pub evidence: String,
    pub rmse_n_before: f64,
    pub rmse_n_after: f64,
    /// The round winner's held-out ratio (carries its selection bias).
    pub heldout_improvement: f64,
    /// The headline: `heldout_improvement` with the choice between effects
    /// nested, each held-out unit scored by the effect chosen without it
    /// (≤ the plain figure when another candidate would have been chosen, or
    /// none).
    pub heldout_improvement_nested: f64,
    /// 95 % bootstrap interval of `heldout_improvement_nested`, resampling the
    /// recordings that ratio is computed over.
    pub heldout_improvement_nested_ci95: [f64; 2],
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NotIdentifiable {
    pub name: String,
    pub needs: String,
}

/// `report.json`, exactly the contract of issue 5.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ReportJson {
    /// Found, none or inconclusive, with its reasons.
    pub verdict: super::verdict::VerdictReport,
    pub baseline: Metrics,
    pub effects: Vec<EffectEntry>,
    pub not_identifiable: Vec<NotIdentifiable>,
    #[serde(rename = "final")]
    pub final_: Metrics,
    /// Where the final residual is still concentrated and no vocabulary term
    /// explains it (every term was tested on top of the final model).
    pub unexplained: Vec<super::unexplained::Unexplained>,
    /// What the readers assumed reading each file (only files with notes;
    /// the key is absent when every file was read as written). Filled by
    /// [`write_all`], which has the data set.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reading_notes: Vec<crate::dataset::summary::RecordingNotes>,
}

/// RMSE over every scored sample of every recording (validate recordings
/// only within the fitted stroke), and RMSE / force range.
pub fn metrics(d: &Diagnosis, pred: &[Vec<f64>]) -> Metrics {
    let (mut se, mut n) = (0.0, 0usize);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for ((r, p), mask) in d.prep.recs.iter().zip(pred).zip(&d.scored_mask) {
        for (f, q) in scored(r.force_n.iter().zip(p), mask) {
            se += (f - q) * (f - q);
            lo = lo.min(*f);
            hi = hi.max(*f);
            n += 1;
        }
    }
    let rmse_n = (se / n.max(1) as f64).sqrt();
    Metrics {
        rmse_n,
        nrmse: crate::error_measure::nrmse(rmse_n, if hi > lo { hi - lo } else { 0.0 }),
    }
}

pub fn report_json(d: &Diagnosis) -> ReportJson {
    ReportJson {
        verdict: d.verdict.clone(),
        baseline: metrics(d, &d.baseline_pred),
        effects: d
            .findings
            .iter()
            .map(|f| EffectEntry {
                name: f.effect.name().to_string(),
                parameters: f.parameters.clone(),
                evidence: f.evidence.clone(),
                rmse_n_before: f.rmse_n_before,
                rmse_n_after: f.rmse_n_after,
                heldout_improvement: f.heldout_improvement,
                heldout_improvement_nested: f.heldout_improvement_nested,
                heldout_improvement_nested_ci95: f.ratio_ci95,
            })
            .collect(),
        not_identifiable: d
            .selection
            .not_identifiable
            .iter()
            .map(|(e, needs)| NotIdentifiable {
                name: e.name().to_string(),
                needs: needs.clone(),
            })
            .collect(),
        final_: metrics(d, &d.final_pred),
        unexplained: d.unexplained.clone(),
        reading_notes: Vec::new(),
    }
}

/// The verdict when nothing was found: none, or inconclusive with its reasons.
fn verdict_markdown(s: &mut String, v: &super::verdict::VerdictReport) {
    use super::verdict::Verdict;
    match v.verdict {
        Verdict::Found => {}
        Verdict::None => {
            let _ = writeln!(
                s,
                "**Verdict: none.** No candidate improved the held-out fit significantly, and these data could \
                 have shown one (final held-out residual {:.1}× the force noise).\n",
                v.residual_over_noise
            );
        }
        Verdict::Inconclusive => {
            let _ = writeln!(
                s,
                "**Verdict: inconclusive.** No candidate passed, but the final held-out residual is {:.0}× the \
                 force noise and these data cannot rule the vocabulary out:\n",
                v.residual_over_noise
            );
            for r in &v.reasons {
                let _ = writeln!(s, "- `{}`: {}. Would decide: {}.", r.code, r.detail, r.experiment);
            }
            let _ = writeln!(s);
        }
    }
}

/// The `unexplained` section: where the final residual still sits.
fn unexplained_markdown(s: &mut String, json: &ReportJson) {
    use super::unexplained::{MIN_CONCENTRATION, MIN_ENERGY_SHARE, NOISE_FACTOR};
    let _ = writeln!(s, "\n## Unexplained: what the final model leaves\n");
    let Some(first) = json.unexplained.first() else {
        let _ = writeln!(
            s,
            "Nothing located: the final residual is within {NOISE_FACTOR}× the force noise, or no branch, \
             stretch of stroke or time, frequency or current holds ≥ {:.0} % of its energy at ≥ \
             {MIN_CONCENTRATION}× its share of the samples.\n",
            100.0 * MIN_ENERGY_SHARE
        );
        return;
    };
    let _ = writeln!(
        s,
        "Final residual {:.3} N RMS against {:.3} N force noise. Every vocabulary term was tested on top of \
         the final model and none passed, so this structure is not explained by any of them:\n",
        first.overall_rmse_n, first.noise_rmse_n
    );
    let _ = writeln!(
        s,
        "| where | cell | share of residual energy | share of samples | RMS (N) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    for u in &json.unexplained {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.2} | {:.3} |",
            u.dimension, u.cell, u.energy_share, u.sample_share, u.rmse_n
        );
    }
}

/// A file name for a recording's predictions (its path, flattened).
pub fn predictions_file_name(recording_file: &str) -> String {
    let stem: String = recording_file
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let stem = stem
        .strip_suffix(".csv")
        .or_else(|| stem.strip_suffix(".txt"))
        .unwrap_or(&stem);
    format!("{stem}.predictions.csv")
}

/// Writes `time_s,force_measured_n,force_baseline_n,force_final_n` per recording.
pub fn write_predictions(d: &Diagnosis, dir: &Path) -> Result<()> {
    for (i, r) in d.prep.recs.iter().enumerate() {
        let path = dir.join(predictions_file_name(&r.file));
        write_atomic_with(&path, |buf| {
            let mut w = csv::Writer::from_writer(buf);
            w.write_record(["time_s", "force_measured_n", "force_baseline_n", "force_final_n"])?;
            for t in 0..r.len() {
                w.write_record([
                    r.time_s[t].to_string(),
                    r.force_n[t].to_string(),
                    // Model forces to 1 mN (as `mre compare` writes them): the
                    // f64 digits beyond add size, not information.
                    format!("{:.3}", d.baseline_pred[i][t]),
                    format!("{:.3}", d.final_pred[i][t]),
                ])?;
            }
            w.flush()?;
            Ok(())
        })?;
    }
    Ok(())
}

/// RMSE over the samples where the model is defined (`mask`).
fn rec_rmse(f: &[f64], p: &[f64], mask: &[bool]) -> f64 {
    let (sse, n) = scored(f.iter().zip(p), mask).fold((0.0, 0usize), |(s, n), (a, b)| (s + (a - b) * (a - b), n + 1));
    (sse / n.max(1) as f64).sqrt()
}

fn peak_error(f: &[f64], p: &[f64]) -> f64 {
    let fmax = f.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let pmax = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    pmax - fmax
}

/// The human-readable report.
pub fn report_markdown(d: &Diagnosis, json: &ReportJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Diagnosis report\n");
    let p = &d.prep;
    let n_total: usize = p.recs.iter().map(|r| r.len()).sum();
    let count = |m: &[bool]| m.iter().filter(|b| **b).count();
    let n_scored: usize = d.scored_mask.iter().map(|m| count(m)).sum();
    let n_in_range: usize = p.recs.iter().map(|r| count(&r.in_range)).sum();
    let n_ambiguous = n_in_range - n_scored;
    let mut noise: Vec<f64> = p.recs.iter().map(|r| r.velocity_noise_m_s).collect();
    noise.sort_by(f64::total_cmp);
    let median_noise_m_s = noise.get(noise.len() / 2).copied().unwrap_or(0.0);
    let _ = writeln!(
        s,
        "{} recordings ({} fit, {} validate), tabulated currents {:?} A, {} cross-validation folds.\n",
        p.recs.len(),
        p.fit_indices().len(),
        p.validate_indices().len(),
        p.currents_a,
        p.n_folds
    );
    let _ = writeln!(
        s,
        "Baseline: {} (predicted through the core's `force_on_branch`). Baseline RMSE {:.3} N \
         (NRMSE {:.4}); final RMSE {:.3} N (NRMSE {:.4}). These two are over all recordings: \
         in-sample for fit recordings, predicted for validate ones. Every improvement below is \
         held out.\n\n\
         Scored samples: {} of {}. Left out: {} whose branch is ambiguous (|v| < {}σ of the \
         velocity noise, median σ = {:.2} mm/s, at the velocity the baseline or the final model \
         reads: the paper's model picks a branch by the sign of v, and at a turn-around that sign \
         is chance), and {} of validate recordings outside the \
         stroke or turn-around range the bracketing currents were fitted on.\n",
        if d.baseline_given {
            "the given model"
        } else {
            "the paper's model, least squares on the fit recordings"
        },
        json.baseline.rmse_n,
        json.baseline.nrmse,
        json.final_.rmse_n,
        json.final_.nrmse,
        n_scored,
        n_total,
        n_ambiguous,
        crate::diagnose::prepared::BRANCH_AMBIGUITY_SIGMAS,
        1e3 * median_noise_m_s,
        n_total - n_scored - n_ambiguous,
    );
    let _ = writeln!(s, "{}\n", velocity_sentence(p));
    let _ = writeln!(s, "{}\n", independent_check_sentence(d));
    // The velocity sentence above already says how motion was had; the
    // per-file paragraph keeps what else the readers assumed.
    let stated = motion_notes(p);
    let unstated: Vec<(&str, Vec<String>)> = json
        .reading_notes
        .iter()
        .map(|x| {
            let rest = x.notes.iter().filter(|n| !stated.contains(n)).cloned().collect();
            (x.file.as_str(), rest)
        })
        .collect();
    s.push_str(&crate::dataset::summary::reading_notes_paragraph(
        unstated.iter().map(|(file, notes)| (*file, notes.as_slice())),
    ));
    let _ = writeln!(s, "## Result\n");
    verdict_markdown(&mut s, &json.verdict);
    for (k, (e, f)) in json.effects.iter().zip(&d.findings).enumerate() {
        let _ = writeln!(
            s,
            "{}. **{}**: {:.2}× held out, nested: the rest of the model chosen without each held-out fold (95 % CI {:.2}–{:.2}×, \
             resampling the same recordings); held-out RMSE {:.3} → {:.3} N ({:.2}× with the rest of the \
             model chosen on all data); inclusion probability {:.2}",
            k + 1,
            e.name,
            e.heldout_improvement_nested,
            f.ratio_ci95[0],
            f.ratio_ci95[1],
            e.rmse_n_before,
            e.rmse_n_after,
            e.heldout_improvement,
            f.inclusion_probability
        );
        let term = super::terms::of(f.effect);
        for (n, p) in &e.parameters {
            // A wrong sign is said next to the value, not hidden.
            let warning = term
                .and_then(|t| t.wrong_sign(n, p.value))
                .map(|why| format!(" — **not physical**: {why}"))
                .or_else(|| {
                    p.at_bound
                        .then(|| " — held at its physical bound 0 (its fit had the wrong sign)".into())
                })
                .unwrap_or_default();
            let _ = writeln!(
                s,
                "   - `{n}` = {:.6} {} (95 % bootstrap {:.6} … {:.6}){warning}",
                p.value, p.unit, p.ci95[0], p.ci95[1]
            );
        }
        let _ = writeln!(s, "   - evidence: {}", e.evidence);
    }
    if !d.findings.is_empty() {
        let _ = writeln!(s, "\n{}", interval_sentence(d.parameter_resamples));
    }
    unexplained_markdown(&mut s, json);
    let _ = writeln!(s, "\n## Where the baseline misses\n");
    let l = &d.locate;
    let _ = writeln!(s, "{}.\n", super::locate::describe(l));
    let _ = writeln!(
        s,
        "| where | shares of residual energy |\n|---|---|\n| branch (compression, extension) | {:.2}, {:.2} |",
        l.branch_share[0], l.branch_share[1]
    );
    let fmt5 = |a: &[f64; 5]| a.iter().map(|v| format!("{v:.2}")).collect::<Vec<_>>().join(", ");
    let _ = writeln!(s, "| stroke fifths (0→max) | {} |", fmt5(&l.stroke_share));
    let _ = writeln!(s, "| time fifths (start→end) | {} |\n", fmt5(&l.time_share));
    let _ = writeln!(s, "| covariate | correlation with residual |\n|---|---|");
    for (n, r) in &l.sample_correlations {
        let _ = writeln!(s, "| {n} (per sample) | {r:+.3} |");
    }
    for (n, r) in &l.recording_correlations {
        let _ = writeln!(s, "| {n} (per recording, residual scale) | {r:+.3} |");
    }
    let _ = writeln!(
        s,
        "\n![residual map](residual_map.png)\n\n![residual vs covariates](residual_covariates.png)\n"
    );
    let th = &d.thresholds;
    let sel = &d.selection;
    let _ = writeln!(s, "## Candidates: one joint sparse fit\n");
    let _ = writeln!(
        s,
        "Every identifiable term sits in one library with the per-current branch quartics ({} columns over {} \
         recordings); each term's searched value was chosen first, on its own, by grouped cross-validation. \
         Group STLSQ keeps a term whose contribution is ≥ {:.0} % of what the quartics alone leave. A term is \
         named when it is kept by ≥ {:.0} % of {} fits on complementary half-samples of the recordings \
         (inclusion probability) **and** its nested held-out RMSE ratio without → with it is ≥ {:.2}× (the rest \
         of the model chosen without the held-out fold). Stability bound on wrongly included terms at that \
         inclusion: {:.2} expected (q²/((2π − 1)·p)).\n",
        sel.n_columns,
        sel.n_recordings,
        100.0 * th.sparsity,
        100.0 * th.min_inclusion,
        sel.ensemble_fits,
        th.min_nested_gain,
        sel.false_inclusion_bound
    );
    let _ = writeln!(
        s,
        "| candidate | chosen form | inclusion probability | nested held-out gain (95 % CI) | gain, rest chosen on all data | share outside the quartics' span | named |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for c in &sel.candidates {
        let form = super::terms::of(c.effect)
            .and_then(|t| t.describe(&c.own))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "| {} | {}{} | {:.2} | {:.3} ({:.3}–{:.3}) | {:.3} | {:.2} | {} |",
            c.effect.name(),
            form,
            if c.linearised {
                " (linearised)"
            } else if !c.decided_by.is_empty() {
                " (validate stage)"
            } else {
                ""
            },
            c.inclusion,
            c.gain.ratio,
            c.gain.ci95[0],
            c.gain.ci95[1],
            c.gain_plain,
            c.outside_baseline,
            if c.named { "**yes**" } else { "no" }
        );
    }
    if sel.candidates.iter().any(|c| !c.decided_by.is_empty()) {
        let _ = writeln!(
            s,
            "\nA term marked *validate stage* changes only the validate recordings' predictions and is not in \
             the library: it was judged on the deciding half of its validate recordings, each predicted with \
             its value chosen on the others; its inclusion is the share of those recordings on which it gains \
             the gain gate alone, its gains are over them, and the recordings it kept as the check were read \
             by no decision (its evidence, below, names both)."
        );
    }
    let _ = writeln!(s, "\n## Not identifiable from this data set\n");
    for n in &json.not_identifiable {
        let _ = writeln!(s, "- `{}`: needs {}", n.name, n.needs);
    }
    let _ = writeln!(s, "\n## Before / after per recording\n");
    let _ = writeln!(s, "| recording | role | current (A) | RMSE before (N) | RMSE after (N) | peak error before (N) | peak error after (N) |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for (i, r) in p.recs.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {:?} | {} | {:.3} | {:.3} | {:+.3} | {:+.3} |",
            r.file,
            r.role,
            r.current_label(),
            rec_rmse(&r.force_n, &d.baseline_pred[i], &d.scored_mask[i]),
            rec_rmse(&r.force_n, &d.final_pred[i], &d.scored_mask[i]),
            peak_error(&r.force_n, &d.baseline_pred[i]),
            peak_error(&r.force_n, &d.final_pred[i])
        );
    }
    let _ = writeln!(
        s,
        "\n## Loops of the worst recordings, before and after\n\nScored samples only (the lines break where \
         a sample is left out).\n\n![loops](loops_worst.png)"
    );
    s
}

/// Writes every output; `report_dir` gets `report.md` and its PNGs. `ds`
/// is the data set `d` was made from: its reading notes go in the report.
pub fn write_all(
    d: &Diagnosis,
    ds: &crate::dataset::Dataset,
    report_dir: &Path,
    json_path: &Path,
    predictions_dir: &Path,
) -> Result<ReportJson> {
    let json = ReportJson {
        reading_notes: crate::dataset::summary::notes_by_file(ds),
        ..report_json(d)
    };
    plots::residual_map(d, &report_dir.join("residual_map.png"))?;
    plots::residual_covariates(d, &report_dir.join("residual_covariates.png"))?;
    plots::loops_worst(d, &report_dir.join("loops_worst.png"))?;
    write_predictions(d, predictions_dir)?;
    write_atomic(&report_dir.join("report.md"), report_markdown(d, &json).as_bytes())?;
    let text = serde_json::to_string_pretty(&json)?;
    write_atomic(json_path, text.as_bytes())?;
    Ok(json)
}

/// The reading notes [`velocity_sentence`] states for the whole data set.
fn motion_notes(p: &crate::diagnose::prepared::Prepared) -> Vec<String> {
    let mut out = vec![crate::dataset::summary::VELOCITY_ESTIMATED_NOTE.to_string()];
    out.extend(
        p.recs
            .iter()
            .filter_map(|r| r.motion_from.as_ref().map(|m| m.describe())),
    );
    out
}

/// How the velocity every rate term and branch reads was obtained.
fn velocity_sentence(p: &crate::diagnose::prepared::Prepared) -> String {
    let n = p.recs.len();
    let mut from_motion: Vec<String> = p
        .recs
        .iter()
        .filter_map(|r| r.motion_from.as_ref().map(|m| m.describe()))
        .collect();
    from_motion.dedup();
    let integrated = p.recs.iter().filter(|r| r.motion_from.is_some()).count();
    let estimated = p
        .recs
        .iter()
        .filter(|r| r.velocity_estimated && r.motion_from.is_none())
        .count();
    let mut parts = Vec::new();
    if integrated > 0 {
        parts.push(format!("in {integrated} of {n} recordings {}", from_motion.join("; ")));
    }
    if estimated > 0 {
        parts.push(format!(
            "in {estimated} of {n} recordings estimated from displacement (a local quadratic \
             least-squares fit over ±{} samples, differentiated at each sample): its noise and lag \
             enter the branch choice and every rate term",
            crate::dataset::velocity::HALF_WINDOW
        ));
    }
    if parts.is_empty() {
        format!("Velocity: measured in all {n} recordings.")
    } else {
        format!("Velocity: {}.", parts.join("; "))
    }
}

/// How the parameter intervals were drawn, with their Monte Carlo error.
fn interval_sentence(resamples: usize) -> String {
    let b = resamples.max(1) as f64;
    // The 2.5 % bound is an order statistic: among B resamples the number
    // falling below the true 2.5 % point is binomial, B·0.025 ± √(B·0.025·0.975).
    let rank = (0.025 * b).round().max(1.0);
    let sd = (b * 0.025 * 0.975).sqrt();
    format!(
        "Parameter intervals: 95 % percentile bootstrap over the fit recordings (resampled within each \
         current), {resamples} resamples ({} for a model with a parameter solved by a 1-D search, such as a softening depth); searched \
         parameters re-choose among the scored variants in {} resamples. Each bound is about the {rank:.0}th \
         value from its end; Monte Carlo error of that rank ±{sd:.1} (binomial), so another seed moves a bound \
         by about {sd:.0} neighbouring resampled values.",
        resamples.div_ceil(4),
        resamples.max(200),
    )
}

/// The validate recordings no decision read, and the RMSE over them: the
/// independent check ([`super::validate_terms`]).
pub fn independent_check_sentence(d: &Diagnosis) -> String {
    let p = &d.prep;
    let read = &d.selection.validate_read;
    let free: Vec<usize> = p.validate_indices().into_iter().filter(|i| !read.contains(i)).collect();
    let names = |ix: &[usize]| {
        ix.iter()
            .map(|&i| p.recs[i].file.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if p.validate_indices().is_empty() {
        return "No validate recordings: no independent check beyond the held-out folds.".into();
    }
    let rmse = |pred: &[Vec<f64>]| {
        let (mut se, mut n) = (0.0, 0usize);
        for &i in &free {
            for (f, q) in scored(p.recs[i].force_n.iter().zip(&pred[i]), &d.scored_mask[i]) {
                se += (f - q) * (f - q);
                n += 1;
            }
        }
        (n > 0).then(|| (se / n as f64).sqrt())
    };
    let head = if read.is_empty() {
        "No decision read a validate recording".to_string()
    } else {
        format!("Validate recordings read by a decision: {}", names(read))
    };
    match (rmse(&d.baseline_pred), rmse(&d.final_pred)) {
        (Some(b), Some(f)) => format!(
            "{head}. Independent check, over the validate recordings no decision read ({}): RMSE {b:.3} N \
             (baseline) → {f:.3} N (final model).",
            names(&free)
        ),
        _ => format!("{head}. No validate recording is left unread: there is no independent validate check."),
    }
}
