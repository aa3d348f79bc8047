//! What a loaded data set holds and what its readers assumed, for people:
//! `mre dataset check` prints it, and the fit and validation reports carry
//! the reading notes (tied time stamps spread, rows skipped, a units row
//! read, a vendor block picked, motion integrated and its uncertainty), so
//! an assumption is never silent.
use super::{Dataset, Recording, Role};
use std::fmt::Write;

/// Everything a reader assumed for one recording, one sentence each: its
/// notes, then how its motion was had when not measured.
pub fn recording_notes(rec: &Recording) -> Vec<String> {
    let mut out = rec.notes.clone();
    if let Some(m) = &rec.motion_from {
        out.push(m.describe());
    }
    if rec.velocity_estimated {
        out.push(VELOCITY_ESTIMATED_NOTE.to_string());
    }
    out
}

/// The note of a recording whose velocity was estimated (its file had none).
pub const VELOCITY_ESTIMATED_NOTE: &str =
    "velocity estimated from displacement (7-point local quadratic, Savitzky–Golay)";

/// One recording's reading notes ([`recording_notes`]), as the comparison's
/// and the diagnosis's `report.json` carry them.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RecordingNotes {
    pub file: String,
    pub notes: Vec<String>,
}

/// [`recording_notes`] of every recording that has any, in the manifest's order.
pub fn notes_by_file(ds: &Dataset) -> Vec<RecordingNotes> {
    ds.recordings
        .iter()
        .map(|r| RecordingNotes {
            file: r.file.clone(),
            notes: recording_notes(r),
        })
        .filter(|r| !r.notes.is_empty())
        .collect()
}

/// A "Reading notes" section in Markdown: per recording, what its reader
/// assumed; empty when no reader assumed anything.
pub fn reading_notes_markdown(ds: &Dataset) -> String {
    let mut s = String::new();
    for rec in notes_by_file(ds) {
        let _ = writeln!(s, "- `{}`:", rec.file);
        for n in rec.notes {
            let _ = writeln!(s, "  - {n}");
        }
    }
    if s.is_empty() {
        return s;
    }
    format!("## Reading notes\n\nWhat the readers assumed reading each file (docs/dataset-format.md):\n\n{s}\n")
}

/// The one-paragraph form of the reading notes the validation, comparison
/// and diagnosis reports carry: a line per file that has notes, its notes
/// joined by "; "; empty when no file has any.
pub fn reading_notes_paragraph<'a>(files: impl IntoIterator<Item = (&'a str, &'a [String])>) -> String {
    let mut s = String::new();
    for (file, notes) in files.into_iter().filter(|(_, n)| !n.is_empty()) {
        let _ = writeln!(s, "- `{file}`: {}", notes.join("; "));
    }
    if s.is_empty() {
        return s;
    }
    format!("Reading notes: what the readers assumed reading each file (docs/dataset-format.md):\n\n{s}\n")
}

fn range(v: &[f64]) -> Option<(f64, f64)> {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo <= hi).then_some((lo, hi))
}

/// `mre dataset check`: one row per recording (current, role, samples,
/// time span, force and stroke ranges as loaded, in internal units), then
/// the reading notes.
pub fn check_markdown(ds: &Dataset) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Data set: {}\n", ds.name);
    let _ = writeln!(s, "{} recording(s), all loaded.\n", ds.recordings.len());
    let _ = writeln!(
        s,
        "| recording | current (A) | role | samples | time (s) | force (N) | displacement (mm) | motion |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    let span = |v: &[f64]| range(v).map_or("–".to_string(), |(lo, hi)| format!("{lo:.6} … {hi:.6}"));
    for rec in &ds.recordings {
        let x = &rec.samples;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            rec.file,
            rec.current_a,
            match rec.role {
                Role::Fit => "fit",
                Role::Validate => "validate",
            },
            x.len(),
            span(&x.time_s),
            span(&x.force_n),
            span(&x.x_mm),
            if rec.motion_from.is_some() {
                "derived"
            } else {
                "measured"
            },
        );
    }
    let _ = writeln!(s);
    let notes = reading_notes_markdown(ds);
    if notes.is_empty() {
        let _ = writeln!(s, "No reader assumed anything: every file was read as written.");
    } else {
        s.push_str(&notes);
    }
    s
}
