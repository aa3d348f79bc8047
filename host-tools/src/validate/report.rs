//! The validation report: `report.md` (tables for people) and `report.json`
//! (the same numbers, full precision). Both are rendered before either is
//! written, and each is written atomically.
use super::ValidationReport;
use anyhow::{Context, Result};
use std::fmt::Write;
use std::path::Path;

fn pct(v: f64) -> String {
    format!("{:.2}", v * 100.0)
}

pub fn markdown(r: &ValidationReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Validation: {}\n", r.dataset);
    let _ = writeln!(s, "Model: `{}`. NRMSE normaliser: {}.\n", r.model, r.nrmse_normaliser);
    let _ = writeln!(
        s,
        "Model force: the control core's `Table::force` (f32), branch by the sign of v, linear interpolation \
         between tabulated currents. Recordings at currents that are not table entries are **predicted** \
         (never fitted).\n"
    );
    if r.recordings.iter().any(|x| x.velocity_estimated) {
        let _ = writeln!(
            s,
            "Velocity was **estimated** from displacement (7-point local quadratic, Savitzky–Golay) for the \
             recordings marked *.\n"
        );
    }
    let derived: Vec<String> = r
        .recordings
        .iter()
        .filter_map(|x| x.motion_derived_from.as_ref().map(|m| format!("`{}`: {m}", x.file)))
        .collect();
    if !derived.is_empty() {
        let _ = writeln!(
            s,
            "Motion was **derived**: these recordings have no displacement column, so their velocity and \
             displacement were integrated (docs/dataset-format.md, force–time drop records):\n"
        );
        for line in derived {
            let _ = writeln!(s, "- {line}");
        }
        let _ = writeln!(s);
    }
    s.push_str(&crate::dataset::summary::reading_notes_paragraph(
        r.recordings
            .iter()
            .map(|x| (x.file.as_str(), x.reading_notes.as_slice())),
    ));
    let _ = writeln!(s, "## Error per recording\n");
    let _ = writeln!(
        s,
        "| recording | current (A) | role | predicted by | samples | RMSE (N) | NRMSE (%) | peak measured (N) | \
         peak model (N) | x clamped (%) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for x in &r.recordings {
        let _ = writeln!(
            s,
            "| {}{} | {} | {} | {} | {} | {:.2} | {} | {:.2} | {:.2} | {} |",
            x.file,
            if x.velocity_estimated { " *" } else { "" },
            x.current_a,
            match x.role {
                crate::dataset::Role::Fit => "fit",
                crate::dataset::Role::Validate => "validate",
            },
            if x.interpolated { "interpolation" } else { "table entry" },
            x.samples,
            x.rmse_n,
            pct(x.nrmse),
            x.peak_measured_n,
            x.peak_model_n,
            pct(x.x_clamped_fraction)
        );
    }
    let _ = writeln!(
        s,
        "\n## Force at the point of largest error (as the paper's Tables 5 and 6)\n"
    );
    let _ = writeln!(
        s,
        "| recording | current (A) | t (s) | x (mm) | experiment (N) | simulation (N) | error there (% of the measured force there) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    let note = format!(
        "The paper's Tables 5 and 6 compare the two forces at one sample: the error there is in % of the measured \
         force at that sample, so it is not the NRMSE above (which averages over every sample and divides by the \
         whole force range, docs/error-measure.md) and can be several times larger. The sample is the largest \
         error among those where the measured force is at least {} % of the recording's peak: near zero force a \
         percentage means nothing.",
        r.percent_error_min_share_of_peak * 100.0
    );
    for x in &r.recordings {
        let e = &x.largest_error;
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {:.3} | {:.2} | {:.2} | {:.2} |",
            x.file, x.current_a, e.time_s, e.x_mm, e.measured_n, e.model_n, e.error_pct
        );
    }
    let _ = writeln!(s, "\n{note}");
    let brackets: Vec<_> = r
        .recordings
        .iter()
        .filter_map(|x| x.bracket.as_ref().map(|b| (x, b)))
        .collect();
    let _ = writeln!(s, "\n## Interpolated loops between their neighbours (Fig. 12)\n");
    if brackets.is_empty() {
        let _ = writeln!(s, "No recording is at a current between two table entries.");
    } else {
        let _ = writeln!(
            s,
            "| recording | current (A) | neighbours (A) | measured samples between neighbour models (%) |"
        );
        let _ = writeln!(s, "|---|---|---|---|");
        for (x, b) in brackets {
            let _ = writeln!(
                s,
                "| {} | {} | {} – {} | {} |",
                x.file,
                x.current_a,
                b.lower_current_a,
                b.upper_current_a,
                pct(b.measured_between)
            );
        }
    }
    s
}

/// Writes `report.md` and `report.json` into `dir`.
pub fn write(dir: &Path, r: &ValidationReport) -> Result<()> {
    let md = markdown(r);
    let json = serde_json::to_string_pretty(r).context("cannot render report.json")?;
    crate::atomic_write::write_atomic(&dir.join("report.md"), md.as_bytes())?;
    crate::atomic_write::write_atomic(&dir.join("report.json"), json.as_bytes())?;
    Ok(())
}
