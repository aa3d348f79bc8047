//! The `mre demo` step "from recordings to flash": the bundled campaign with
//! a concealed coil lag (`data/drop-coil_lag`), `mre diagnose --model-out`,
//! `mre tables`, and the controlled drop on the plant that recorded it, with
//! the paper's table (a) and the diagnosed model (c) against the passive
//! damper and the physical limit.
use super::limit::physical_limit;
use super::{drop_setup, RunOutcome};
use crate::demo::DemoStep;
use crate::plant::closed_loop::{run_controlled, run_passive, Comparison, RunResult, RunSpec};
use crate::plant::synth::{draw_plant, SynthPlan};
use anyhow::{anyhow, Result};
use mre_algorithm::Table;
use std::path::Path;

/// The set and the seed `data/generate.sh` made it with (its plant).
const SET: &str = "drop-coil_lag";
const SEED: u64 = 107;

pub fn recordings_to_flash(data: &Path, out: &Path) -> Result<DemoStep> {
    let dir = out.join("recordings-to-flash");
    let diag_dir = dir.join("diagnose");
    let model = dir.join("final.toml");
    let opts = crate::diagnose::DiagnoseOptions::with_validate_evidence();
    let (found, _, _) = crate::diagnose::model_out::run_to_files_with_model(
        &data.join(SET),
        &opts,
        &diag_dir,
        &diag_dir.join("report.json"),
        &diag_dir.join("predictions"),
        &model,
        &[],
    )?;
    // What the board would fly: the table read back from the model file.
    let flashed = crate::tables::run_tables(&model, &dir.join("generated_table.rs"))?;

    let plant = draw_plant("coil_lag", SEED, &SynthPlan::default())?;
    // The drop in the model file's installation (what the table carries).
    let setup = drop_setup(&plant, 60, SEED, flashed.installation());
    let limit = physical_limit(&plant, &setup.impact, (0.0, 2.0), setup.usable_stroke_mm())?;
    let paper = Table::paper().map_err(|e| anyhow!("{e}"))?;
    let runs = [("(a) paper Table 4", &paper), ("(c) diagnose --model-out", &flashed)]
        .into_iter()
        .map(|(label, table)| {
            let t = run_controlled(&setup, table)?;
            Ok(RunResult::new(RunSpec::Controlled, label.to_owned(), &setup, t))
        })
        .collect::<Result<Vec<_>>>()?;
    let outcomes: Vec<RunOutcome> = runs
        .iter()
        .map(|r| RunOutcome::new(&r.label, &r.summary, &limit, setup.usable_stroke_mm()))
        .collect();
    // The figure also shows the passive damper at both ends of the coil's
    // range: what the controller is there to beat.
    let mut drawn = runs;
    for current_a in [0.0, 2.0] {
        let spec = RunSpec::Passive(current_a);
        let t = run_passive(&setup, current_a)?;
        drawn.push(RunResult::new(spec, spec.label(), &setup, t));
    }
    let cmp = Comparison::from_runs(drawn);
    let png = dir.join("force-displacement.png");
    crate::plant::plots::force_displacement_with_limit_png(&cmp, Some(limit.envelope_n), &png)?;

    let tau_ms = f64::from(flashed.terms().coil_tau_s) * 1e3;
    let true_tau_ms = plant.effect.coil_lag_s().unwrap_or(0.0) * 1e3;
    let mut md = format!(
        "# From recordings to flash: {SET}\n\n{}\n\nIdentified coil τ {tau_ms:.3} ms (the plant's: {true_tau_ms:.3} ms), \
         written to `final.toml` (format {}) and `generated_table.rs` (CRC {:#010x}).\n\n\
         Drop: {} kg at {} m/s, usable stroke {} mm, physical limit {:.0} N.\n\n\
         | controller | peak (N) | × limit | stroke (mm) | peak decel (g) | rebound (m/s) |\n|---|---|---|---|---|---|\n",
        crate::diagnose::summary_line(&found),
        flashed.version(),
        flashed.crc32(),
        setup.impact.mass_kg,
        setup.impact.impact_velocity_m_s,
        setup.usable_stroke_mm(),
        limit.envelope_n
    );
    for o in &outcomes {
        md.push_str(&format!(
            "| {} | {:.0} | {:.2} | {:.2} | {:.1} | {} |\n",
            o.controller,
            o.peak_force_n,
            o.over_limit,
            o.max_stroke_mm,
            o.peak_deceleration_m_s2 / 9.81,
            o.rebound_velocity_m_s.map_or("–".to_owned(), |v| format!("{v:.2}"))
        ));
    }
    md.push_str("\n![force against displacement](force-displacement.png)\n");
    crate::atomic_write::write_atomic(&dir.join("summary.md"), md.as_bytes())?;
    crate::html::Page::new("From recordings to flash")
        .folder(&dir)
        .write(&dir.join("index.html"))?;
    let [a, c] = &outcomes[..] else {
        return Err(anyhow!("internal: two runs expected"));
    };
    Ok(DemoStep {
        title: format!("from recordings to flash: data/{SET} → diagnose --model-out → tables → controlled drop"),
        headline: format!(
            "τ {tau_ms:.2} ms identified; peak force {:.0} N ({:.2}× the limit) with the diagnosed model vs {:.0} N ({:.2}×) with Table 4",
            c.peak_force_n, c.over_limit, a.peak_force_n, a.over_limit
        ),
        report: dir.join("summary.md"),
        downloads: Vec::new(),
    })
}
