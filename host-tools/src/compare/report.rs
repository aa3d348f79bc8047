//! report.json, report.md and predictions/<stem>.csv of `mre compare`.
use super::tracks::{information_criteria, mean_nrmse, nrmse, rmse_n};
use super::Comparison;
use crate::atomic_write::{write_atomic, write_atomic_with};
use crate::dataset::Role;
use anyhow::Result;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

#[derive(Clone, Debug, Serialize)]
pub struct RecordingJson {
    pub file: String,
    pub current_a: f64,
    pub role: Role,
    pub rmse_n: f64,
    pub nrmse: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct CostJson {
    pub flops: u32,
    pub divides: u32,
    pub transcendentals: u32,
    pub substeps: u32,
    pub state_floats: u32,
    pub cortex_m4f_cycles_per_step: u32,
}

#[derive(Clone, Debug, Serialize)]
pub struct FamilyJson {
    pub name: String,
    pub kind: String,
    pub equations: String,
    pub note: String,
    pub parameters: serde_json::Value,
    pub n_parameters: usize,
    /// Mean NRMSE over the fit recordings.
    pub fit_nrmse: f64,
    /// Mean NRMSE over the validate recordings (null if none).
    pub heldout_nrmse: Option<f64>,
    pub aic: f64,
    pub bic: f64,
    pub fit_time_s: f64,
    pub evaluations: Option<usize>,
    pub cortex_m4f: Option<CostJson>,
    pub recordings: Vec<RecordingJson>,
}

#[derive(Clone, Debug, Serialize)]
pub struct ReportJson {
    pub dataset: String,
    pub hold_out_currents_a: Vec<f64>,
    pub nrmse_definition: String,
    pub gsa_agents: usize,
    pub gsa_iters: usize,
    pub gsa_samples_per_recording: usize,
    pub lm_samples_per_recording: usize,
    pub seed: u64,
    /// True when the nonlinear search ran with less than the default budget (as in `mre demo`).
    pub reduced_budget: bool,
    pub total_time_s: f64,
    /// The family with the lowest held-out NRMSE.
    pub best_heldout: Option<String>,
    pub families: Vec<FamilyJson>,
    /// Families the data set is too small for, with what it lacks.
    pub left_out: Vec<super::LeftOut>,
    /// What the readers assumed reading each file (only files with notes).
    pub reading_notes: Vec<RecordingNotes>,
}

/// One recording's reading notes (`dataset::summary::recording_notes`).
pub use crate::dataset::summary::RecordingNotes;

/// The numbers of a comparison.
pub fn summarise(c: &Comparison) -> ReportJson {
    let families: Vec<FamilyJson> = c
        .outcomes
        .iter()
        .map(|o| {
            let (aic, bic) = information_criteria(&c.tracks, &o.predictions, o.n_parameters);
            let held = mean_nrmse(&c.tracks, &o.predictions, Role::Validate);
            FamilyJson {
                name: o.name.clone(),
                kind: o.kind.into(),
                equations: o.equations.clone(),
                note: o.note.clone(),
                parameters: o.parameters.clone(),
                n_parameters: o.n_parameters,
                fit_nrmse: mean_nrmse(&c.tracks, &o.predictions, Role::Fit),
                heldout_nrmse: held.is_finite().then_some(held),
                aic,
                bic,
                fit_time_s: o.fit_time_s,
                evaluations: o.evaluations,
                cortex_m4f: o.step_cost.map(|s| CostJson {
                    flops: s.flops,
                    divides: s.divides,
                    transcendentals: s.transcendentals,
                    substeps: s.substeps,
                    state_floats: s.state_floats,
                    cortex_m4f_cycles_per_step: s.cortex_m4f_cycles(),
                }),
                recordings: c
                    .tracks
                    .iter()
                    .zip(&o.predictions)
                    .map(|(t, p)| RecordingJson {
                        file: t.file.clone(),
                        current_a: t.current_a,
                        role: t.role,
                        rmse_n: rmse_n(&t.force_n, p),
                        nrmse: nrmse(t, p),
                    })
                    .collect(),
            }
        })
        .collect();
    let best_heldout = families
        .iter()
        .filter_map(|f| f.heldout_nrmse.map(|h| (h, f.name.clone())))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|b| b.1);
    let b = &c.options.budget;
    ReportJson {
        dataset: c.dataset.clone(),
        hold_out_currents_a: c.options.hold_out_a.clone(),
        nrmse_definition: format!(
            "{} per recording, averaged over recordings",
            crate::error_measure::DEFINITION
        ),
        gsa_agents: b.gsa.agents,
        gsa_iters: b.gsa.iters,
        gsa_samples_per_recording: b.gsa_samples_per_track,
        lm_samples_per_recording: b.lm_samples_per_track,
        seed: c.options.seed,
        reduced_budget: b.gsa.agents * b.gsa.iters < {
            let d = super::fit::Budget::default();
            d.gsa.agents * d.gsa.iters
        },
        total_time_s: c.total_time_s,
        best_heldout,
        families,
        left_out: c.left_out.clone(),
        reading_notes: c.reading_notes.clone(),
    }
}

/// How much better than `base` a held-out score is, as a ratio base/best.
fn ratio(r: &ReportJson, best: f64, base: &str) -> Option<f64> {
    r.families
        .iter()
        .find(|f| f.name == base)
        .and_then(|f| f.heldout_nrmse)
        .map(|h| h / best)
}

/// A held-out NRMSE this many times lower than the polynomial-plus-diagnosis
/// counts as a wide margin (the report then says what the firmware would need).
pub const WIDE_MARGIN: f64 = 1.25;

/// An NRMSE (a fraction in the JSON) as pages print it: percent, 3 significant
/// digits at most; "–" where it is undefined.
fn percent(nrmse: f64) -> String {
    if nrmse.is_finite() {
        format!("{:.2} %", 100.0 * nrmse)
    } else {
        "–".into()
    }
}

pub fn markdown(r: &ReportJson) -> String {
    let mut s = format!(
        "# Model families side by side — {}\n\n\
         Fitted on the `fit` recordings only; recordings at {:?} A (and any `validate` recording) are only predicted. \
         {}. AIC/BIC = n·ln(SSE/n) + 2k / + k·ln n over the fit samples (samples are correlated: use them to rank). \
         Nonlinear families: GSA (N = {}, T = {}, recordings decimated to ≈ {} samples) then Levenberg–Marquardt \
         (≈ {} samples per recording); seed {}. Whole comparison: {:.1} s.\n\n",
        r.dataset,
        r.hold_out_currents_a,
        r.nrmse_definition,
        r.gsa_agents,
        r.gsa_iters,
        r.gsa_samples_per_recording,
        r.lm_samples_per_recording,
        r.seed,
        r.total_time_s
    );
    if r.reduced_budget {
        s.push_str(
            "**Reduced search budget** (as `mre demo` runs it): the nonlinear families may fit better with \
             `mre compare` at its defaults.\n\n",
        );
    }
    s.push_str(&crate::dataset::summary::reading_notes_paragraph(
        r.reading_notes.iter().map(|x| (x.file.as_str(), x.notes.as_slice())),
    ));
    s.push_str("| family | kind | parameters | fit NRMSE | held-out NRMSE | AIC | BIC | fit time (s) |\n|---|---|---|---|---|---|---|---|\n");
    for f in &r.families {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.0} | {:.0} | {:.2} |\n",
            f.name,
            f.kind,
            f.n_parameters,
            percent(f.fit_nrmse),
            f.heldout_nrmse.map_or("–".into(), percent),
            f.aic,
            f.bic,
            f.fit_time_s
        ));
    }
    for l in &r.left_out {
        s.push_str(&format!("\n**{} is left out**: {}.\n", l.family, l.missing));
    }
    s.push_str("\n## What wins on the held-out recordings\n\n");
    let best = r
        .best_heldout
        .as_ref()
        .and_then(|n| r.families.iter().find(|f| &f.name == n));
    match best {
        None => s.push_str("No recording was held out, so nothing is scored out of sample.\n"),
        Some(b) => {
            let h = b.heldout_nrmse.unwrap_or(f64::NAN);
            s.push_str(&format!(
                "**{}** predicts the held-out recordings best (mean NRMSE {}).",
                b.name,
                percent(h)
            ));
            for base in ["polynomial-lsq", "polynomial+diagnose"] {
                if let Some(q) = ratio(r, h, base).filter(|_| b.name != base) {
                    s.push_str(&format!(" It is {q:.2}× lower than {base}'s."));
                }
            }
            s.push('\n');
            let diag = r.families.iter().find(|f| f.name == "polynomial+diagnose");
            let wide = match diag.and_then(|d| d.heldout_nrmse) {
                Some(d) => b.kind == "nonlinear" && d / h >= WIDE_MARGIN,
                None => false,
            };
            if wide {
                s.push_str(&firmware_needs(b));
            } else if b.kind == "nonlinear" {
                s.push_str(&format!(
                    "\nIts margin over the polynomial with diagnosis is below {WIDE_MARGIN}×, not enough to change the firmware's model.\n"
                ));
            } else {
                s.push_str("\nNo nonlinear family beats it out of sample: the firmware's quartic tables stay.\n");
            }
        }
    }
    s.push_str("\n## Held-out recordings, NRMSE per family\n\n| recording | current (A) |");
    for f in &r.families {
        s.push_str(&format!(" {} |", f.name));
    }
    s.push_str("\n|---|---|");
    s.push_str(&"---|".repeat(r.families.len()));
    s.push('\n');
    if let Some(first) = r.families.first() {
        for (i, rec) in first
            .recordings
            .iter()
            .enumerate()
            .filter(|(_, x)| x.role == Role::Validate)
        {
            s.push_str(&format!("| {} | {} |", rec.file, rec.current_a));
            for f in &r.families {
                s.push_str(&format!(" {} |", percent(f.recordings[i].nrmse)));
            }
            s.push('\n');
        }
    }
    s.push_str("\n## Families\n\n");
    for f in &r.families {
        s.push_str(&format!("- **{}**: {} ({}).", f.name, f.equations, f.note));
        if let Some(c) = &f.cortex_m4f {
            s.push_str(&format!(
                " Board cost ≈ {} cycles/step, {} f32 of state.",
                c.cortex_m4f_cycles_per_step, c.state_floats
            ));
        }
        s.push('\n');
    }
    s.push_str(
        "\nPlots: `plots/<current>_<recording>.png|svg`, measured samples against every family. \
         Predictions: `predictions/<recording>.csv`, the measured force and one column per family.\n",
    );
    s
}

/// What the firmware would need to run `f` instead of its quartic tables.
fn firmware_needs(f: &FamilyJson) -> String {
    let Some(c) = &f.cortex_m4f else { return String::new() };
    // The board runs its control loop at 10 kHz on an 80 MHz Cortex-M4F: 8000 cycles per period.
    let period_pct = c.cortex_m4f_cycles_per_step as f64 / 8000.0 * 100.0;
    format!(
        "\nTo fly {} the firmware would need: its state ({} f32) carried from one control period to the next, \
         reset at power-up; per step about {} flops, {} divides and {} exp/tanh ({} sub-steps), ≈ {} Cortex-M4F cycles \
         ({period_pct:.1} % of the 8000-cycle period at 10 kHz, 80 MHz), once per candidate current; {} parameters in flash; and an inverse \
         (lowest current for a force) solved by iteration, since the model is not linear in a per-current table.\n",
        f.name,
        c.state_floats,
        c.flops,
        c.divides,
        c.transcendentals,
        c.substeps,
        c.cortex_m4f_cycles_per_step,
        f.n_parameters
    )
}

/// Writes report.json, report.md and every prediction CSV under `dir`.
/// The predictions CSV's column for a family: `force_<name>_n`, the name's
/// `+` and `-` as `_` (`polynomial+diagnose` → `force_polynomial_diagnose_n`).
pub fn prediction_column(family: &str) -> String {
    format!("force_{}_n", family.replace(['+', '-'], "_"))
}

pub fn write_all(c: &Comparison, r: &ReportJson, dir: &Path) -> Result<()> {
    // One file per recording, every family a column: time and the measured
    // force are written once, not once per family.
    for (k, t) in c.tracks.iter().enumerate() {
        let path = dir.join("predictions").join(format!("{}.csv", t.stem));
        write_atomic_with(&path, |w| {
            write!(w, "time_s,force_measured_n")?;
            for o in &c.outcomes {
                write!(w, ",{}", prediction_column(&o.name))?;
            }
            writeln!(w)?;
            for (i, (time, f)) in t.time_s.iter().zip(&t.force_n).enumerate() {
                write!(w, "{time},{f}")?;
                // Model forces to 1 mN: far below any measured force's resolution.
                for o in &c.outcomes {
                    write!(w, ",{:.3}", o.predictions[k][i])?;
                }
                writeln!(w)?;
            }
            Ok(())
        })?;
    }
    write_atomic(&dir.join("report.md"), markdown(r).as_bytes())?;
    write_atomic(&dir.join("report.json"), serde_json::to_string_pretty(r)?.as_bytes())?;
    Ok(())
}

/// One line for the terminal: the best held-out family and the total time.
pub fn summary_line(r: &ReportJson) -> String {
    let best = r
        .best_heldout
        .as_ref()
        .and_then(|n| r.families.iter().find(|f| &f.name == n));
    match best {
        Some(b) => format!(
            "{} families in {:.1} s; best on held-out recordings: {} (mean NRMSE {})",
            r.families.len(),
            r.total_time_s,
            b.name,
            b.heldout_nrmse.map_or("–".into(), percent)
        ),
        None => format!(
            "{} families in {:.1} s; no held-out recordings",
            r.families.len(),
            r.total_time_s
        ),
    }
}
