//! `mre sim` outputs: per-run CSV, a summary (JSON and Markdown) and plots.
use super::closed_loop::{Comparison, RunResult};
use super::plots::{force_displacement_png, force_time_png};
use crate::atomic_write::{write_atomic, write_atomic_with};
use anyhow::Result;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const G_M_S2: f64 = 9.81;

fn rebound(r: &RunResult) -> String {
    r.summary
        .rebound_velocity_m_s
        .map_or_else(|| "did not leave".to_owned(), |v| format!("{v:.2}"))
}

/// The comparison as a Markdown table (also printed by the CLI).
pub fn summary_table(cmp: &Comparison) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| run | peak force (N) | peak deceleration (m/s², g) | stroke used / available (mm) | rebound velocity (m/s) |"
    );
    let _ = writeln!(out, "|---|---:|---:|---:|---:|");
    for r in &cmp.runs {
        let s = &r.summary;
        let _ = writeln!(
            out,
            "| {} | {:.0} | {:.0} ({:.1} g) | {:.2} / {:.1}{} | {} |",
            r.label,
            s.peak_force_n,
            s.peak_deceleration_m_s2,
            s.peak_deceleration_m_s2 / G_M_S2,
            s.max_stroke_mm,
            r.usable_stroke_mm,
            if r.within_stroke { "" } else { " (exceeds)" },
            rebound(r)
        );
    }
    match &cmp.controlled_vs_passive {
        Some((reference, pct)) => {
            let _ = writeln!(
                out,
                "\nControlled peak force is {pct:.1} % below {reference}, the lowest-peak passive run within the stroke."
            );
        }
        None if cmp.runs.iter().any(|r| r.label == "controlled") => {
            let _ = writeln!(
                out,
                "\nNo passive run stayed within the stroke, so there is no passive reference."
            );
        }
        None => {}
    }
    out
}

fn run_csv(r: &RunResult, buf: &mut Vec<u8>) -> Result<()> {
    let mut w = csv::Writer::from_writer(buf);
    w.write_record([
        "time_s",
        "displacement_mm",
        "velocity_m_s",
        "force_n",
        "command_a",
        "current_a",
    ])?;
    for s in &r.trajectory.samples {
        w.write_record(&[
            format!("{:.6}", s.time_s),
            format!("{:.4}", s.x_mm),
            format!("{:.4}", s.v_m_s),
            format!("{:.1}", s.force_n),
            format!("{:.4}", s.command_a),
            format!("{:.4}", s.current_a),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// Writes everything into `dir`; returns the files written.
pub fn write_sim_report(cmp: &Comparison, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for r in &cmp.runs {
        let path = dir.join(format!("{}.csv", r.spec.slug()));
        write_atomic_with(&path, |buf| run_csv(r, buf))?;
        written.push(path);
    }
    let json = dir.join("summary.json");
    let mut text = serde_json::to_string_pretty(cmp)?;
    text.push('\n');
    write_atomic(&json, text.as_bytes())?;
    written.push(json);
    let ft = dir.join("force_time.png");
    force_time_png(cmp, &ft)?;
    let fd = dir.join("force_displacement.png");
    force_displacement_png(cmp, &fd)?;
    let md = dir.join("summary.md");
    let body = format!(
        "# Drop impact: passive against controlled\n\n{}\n![force against time](force_time.png)\n\n![force against displacement](force_displacement.png)\n",
        summary_table(cmp)
    );
    write_atomic(&md, body.as_bytes())?;
    written.extend([ft, fd, md]);
    Ok(written)
}
