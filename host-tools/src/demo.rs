//! `mre demo`: the README's main command. Runs the whole workflow on the
//! bundled data and says where each result is.
//!
//! 1. The paper's workflow on the real MR damper data (`data/mr-damper-mts`):
//!    fit (GSA and the exact least-squares optimum) with 0.5 A held out,
//!    validate (0.5 A predicted by interpolation), plots, GSA sweep, table.
//! 2. The same on the bundled drop-impact set without hidden physics
//!    (`data/drop-none`), with its intermediate currents predicted by
//!    interpolation, and its flash table generated.
//! 3. A blind diagnosis of the bundled drop tests with a concealed effect,
//!    and a diagnosis of the real MR damper data (whole amplitude–frequency
//!    pairs held out, 0.5 A predicted).
//! 4. The closed-loop drop test: passive 0 A, passive 2 A, controlled by the
//!    core, in the installation of step 2's model file (`drop-none/model.toml`:
//!    the data set's mass, the defaults for the rest).
//!    Then the chain from recordings to flash on `data/drop-coil_lag`
//!    (`control_bench::demo_step`), and its model as `damper.fmu` and
//!    `controller.fmu` (`mre fmu`).
//! 5. The same with the firmware in QEMU closing the loop (`mre pil`), when
//!    `qemu-system-arm` is installed; otherwise it says how to install it.
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// Where the demo reads and writes.
#[derive(Clone, Debug)]
pub struct DemoOptions {
    /// Folder holding the bundled data sets (`data/` in the repository).
    pub data_dir: PathBuf,
    /// Output folder; each step writes a subfolder.
    pub out_dir: PathBuf,
    pub seed: u64,
}

/// One finished step, for the closing summary.
#[derive(Clone, Debug)]
pub struct DemoStep {
    pub title: String,
    pub headline: String,
    pub report: PathBuf,
    /// Files a reader takes away (the FMUs), linked from `index.html` too.
    pub downloads: Vec<PathBuf>,
}

/// Fit (GSA and lsq), validate, plot, sweep and flash table for one data set.
/// Recordings at `hold_out_a` are predicted by interpolation, never fitted.
fn fit_validate_plot(dataset: &Path, out: &Path, seed: u64, hold_out_a: &[f64], title: &str) -> Result<DemoStep> {
    let _progress = crate::progress::spinner(title);
    let options = crate::fit::FitOptions {
        gsa: crate::fit::gsa::GsaParams {
            seed,
            ..Default::default()
        },
        ..Default::default()
    };
    let model_path = out.join("model.toml");
    let run = crate::fit::run_fit(dataset, &options, hold_out_a, &model_path)
        .with_context(|| format!("fitting {}", dataset.display()))?;
    let model = model_path.display().to_string();
    let report = crate::validate::run_validate(dataset, &model, hold_out_a, &out.join("validate"))?;
    crate::plot::run_plot(
        dataset,
        &model_path,
        hold_out_a,
        &crate::plot::PlotOptions { interpolated_a: vec![] },
        &out.join("plots"),
    )?;
    crate::fit::sweep::run_sweep(dataset, &options, hold_out_a, &out.join("sweep"))?;
    crate::tables::run_tables(&model_path, &out.join("generated_table.rs"))?;
    let page = out.join("index.html");
    crate::html::Page::new(title)
        .folder(&out.join("validate"))
        .folder(&out.join("plots"))
        .folder(&out.join("sweep"))
        .file(&model_path)
        .file(&out.join("generated_table.rs"))
        .write(&page)?;
    let gaps: Vec<f64> = run.fits.iter().filter_map(|f| f.gap_ratio()).collect();
    let worst_gap = gaps.iter().cloned().fold(f64::NAN, f64::max);
    let nrmse: Vec<f64> = report.recordings.iter().map(|r| r.nrmse).collect();
    let mean_nrmse = nrmse.iter().sum::<f64>() / nrmse.len().max(1) as f64;
    Ok(DemoStep {
        title: title.to_string(),
        headline: format!(
            "{} branches fitted in {:.3} s; GSA/lsq RMSE ratio up to {:.2}; mean NRMSE {:.1} % over {} recordings",
            run.fits.len(),
            run.fit_seconds,
            worst_gap,
            100.0 * mean_nrmse,
            nrmse.len()
        ),
        report: page,
        downloads: Vec::new(),
    })
}

/// The drop the closed-loop steps fly: step 2's model file's installation.
fn drop_request(out: &Path, seed: u64) -> Result<crate::plant::closed_loop::SimRequest> {
    let model = out.join("drop-none").join("model.toml");
    let stated = crate::installation::StatedInstallation::from_model_file(&model)?;
    Ok(crate::plant::closed_loop::SimRequest {
        seed,
        installation: stated.installation,
        ..Default::default()
    })
}

fn closed_loop(out: &Path, seed: u64) -> Result<DemoStep> {
    let _progress = crate::progress::spinner("closed-loop drop test (host)");
    let request = drop_request(out, seed)?;
    let dir = out.join("sim");
    let cmp = crate::plant::closed_loop::run_sim(&request, &dir)?;
    let headline = match &cmp.controlled_vs_passive {
        Some((reference, pct)) => format!("controlled peak force {pct:.1} % below {reference}"),
        None => "no passive run stayed within the stroke to compare with".to_string(),
    };
    Ok(DemoStep {
        title: "closed-loop drop test (host)".into(),
        headline,
        report: dir.join("summary.md"),
        downloads: Vec::new(),
    })
}

/// Blind diagnosis of a bundled drop-test set with a concealed effect; the
/// answer key (kept outside the set) is read only afterwards, to compare.
fn diagnosis(data: &Path, out: &Path, seed: u64) -> Result<DemoStep> {
    const SET: &str = "drop-viscous_damping";
    let _progress = crate::progress::spinner("blind diagnosis of a drop-test set");
    let dir = out.join("diagnose");
    let opts = crate::diagnose::options_from_cli(None, None, 5, vec![], seed)?;
    let found = crate::diagnose::run_to_files(
        &data.join(SET),
        &opts,
        &dir,
        &dir.join("report.json"),
        &dir.join("predictions"),
    )?;
    let key_path = data.join("keys").join(format!("{SET}.json"));
    let truth = std::fs::read_to_string(&key_path)
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .and_then(|key| key.get("effect").and_then(|e| e.as_str()).map(str::to_owned))
        .unwrap_or_else(|| "unknown (no key file)".into());
    Ok(DemoStep {
        title: format!("diagnosis of data/{SET} (blind)"),
        headline: format!("{}; answer key: {truth}", crate::diagnose::summary_line(&found)),
        report: dir.join("report.md"),
        downloads: Vec::new(),
    })
}

/// What the paper's model leaves out on the real MR damper: whole
/// amplitude–frequency pairs held out in turn, 0.5 A predicted.
fn real_data_diagnosis(data: &Path, out: &Path, seed: u64) -> Result<DemoStep> {
    let _progress = crate::progress::spinner("diagnosis of the real MR damper data");
    let dir = out.join("diagnose-mr-damper-mts");
    let opts = crate::diagnose::options_from_cli(None, Some("frequency_hz".into()), 5, vec![0.5], seed)?;
    let found = crate::diagnose::run_to_files(
        &data.join("mr-damper-mts"),
        &opts,
        &dir,
        &dir.join("report.json"),
        &dir.join("predictions"),
    )?;
    Ok(DemoStep {
        title: "diagnosis of the real MR damper data (whole frequencies held out, 0.5 A predicted)".into(),
        headline: crate::diagnose::summary_line(&found),
        report: dir.join("report.md"),
        downloads: Vec::new(),
    })
}

/// Model families side by side on the real MR damper data (Fig. 15), with
/// the reduced search budget (report.md states it).
fn model_families(data: &Path, out: &Path, seed: u64) -> Result<DemoStep> {
    let dir = out.join("compare-mr-damper-mts");
    let options = crate::compare::CompareOptions {
        seed,
        ..crate::compare::CompareOptions::reduced()
    };
    let r = crate::compare::run_compare(&data.join("mr-damper-mts"), &options, &dir)?;
    Ok(DemoStep {
        title: "model families side by side on the real MR damper data (0.5 A held out)".into(),
        headline: crate::compare::report::summary_line(&r),
        report: dir.join("report.md"),
        downloads: Vec::new(),
    })
}

/// The diagnosed model of "from recordings to flash" as `damper.fmu` and
/// `controller.fmu` (`mre fmu --controller`). When the FMU libraries cannot be
/// built or the FMUs written, the step says why and the demo goes on.
fn fmus(out: &Path) -> Result<DemoStep> {
    let _progress = crate::progress::spinner("building the FMUs of the diagnosed model");
    let title =
        "the diagnosed model as FMUs for vehicle models (FMI 3.0: OpenModelica, Simulink, Dymola, FMPy)".to_string();
    let model = out.join("recordings-to-flash").join("final.toml");
    let dir = out.join("fmu");
    let libraries = match crate::fmu::library_dir() {
        Ok(dir) => dir,
        Err(e) => {
            return Ok(DemoStep {
                title,
                headline: format!("skipped: {e:#}"),
                report: model,
                downloads: Vec::new(),
            })
        }
    };
    let request = crate::fmu::FmuRequest {
        model: model.clone(),
        out: dir.join("damper.fmu"),
        controller: true,
        fmi: crate::fmu::FmiVersion::V3,
    };
    let written = match crate::fmu::run_fmu_with(&request, &libraries) {
        Ok(written) => written,
        Err(e) => {
            return Ok(DemoStep {
                title,
                headline: format!("skipped: writing the FMUs failed: {e:#}"),
                report: model,
                downloads: Vec::new(),
            })
        }
    };
    // Linked from the page so a reader downloads them (the browser check
    // fails on a link to a file that is not there).
    let links: Vec<String> = written
        .iter()
        .filter_map(|p| p.file_name())
        .map(|n| format!("[`{0}`]({0})", n.to_string_lossy()))
        .collect();
    let summary = format!(
        "# The diagnosed model as FMUs\n\n\
         {} are `mre fmu ../recordings-to-flash/final.toml --controller`: FMI 3.0 \
         (damper: Co-Simulation and Model Exchange; controller: Co-Simulation) for {}, evaluated by the \
         board's control core.\n\n\
         - damper: `displacement_m` (m), `velocity_m_s` (m/s), `current_a` (A) in; `force_n` (N) out.\n\
         - controller: measured `displacement_m`, `velocity_m_s` in; `coil_current_a` (A, the commanded coil \
         current: wire it to the damper's `current_a`), `drive_voltage_v` (V) and `coil_command_a` (the law's \
         drive over the coil resistance) out, one control tick per `control_period_s` (the board's 10 kHz).\n\n\
         docs/fmu.md in the repository shows how to use them in OpenModelica, Simulink and FMPy.\n",
        links.join(" and "),
        crate::fmu::PLATFORM
    );
    crate::atomic_write::write_atomic(&dir.join("summary.md"), summary.as_bytes())?;
    crate::html::Page::new("The diagnosed model as FMUs")
        .folder(&dir)
        .write(&dir.join("index.html"))?;
    Ok(DemoStep {
        title,
        headline: format!("wrote {} FMUs of the diagnosed model", written.len()),
        report: dir.join("summary.md"),
        downloads: written,
    })
}

fn processor_in_the_loop(out: &Path, seed: u64) -> Result<DemoStep> {
    use crate::pil::qemu::{firmware_target_missing, usable_qemu, workspace_root};
    let title = "closed-loop drop test, firmware in QEMU (PIL)".to_string();
    let skipped = |why: String| DemoStep {
        title: title.clone(),
        headline: format!("skipped: {why}"),
        report: workspace_root().join("firmware/README.md"),
        downloads: Vec::new(),
    };
    if let Err(why) = usable_qemu() {
        return Ok(skipped(why));
    }
    if let Some(why) = firmware_target_missing() {
        return Ok(skipped(why));
    }
    let _progress = crate::progress::spinner("building the PIL firmware and running it in QEMU");
    let dir = out.join("pil");
    let request = crate::pil::sim::PilRequest {
        sim: drop_request(out, seed)?,
        elf: None,
    };
    // A failing image build or QEMU run skips this step alone: the rest of
    // the demo's pages are still written.
    let run = match crate::pil::sim::run_pil(&request, &dir) {
        Ok(run) => run,
        Err(e) => return Ok(skipped(format!("the firmware-in-QEMU run failed: {e:#}"))),
    };
    let a = run.agreement;
    let gain = match &run.comparison.controlled_vs_passive {
        Some((reference, pct)) => format!("; controlled peak force {pct:.1} % below {reference}"),
        None => String::new(),
    };
    Ok(DemoStep {
        title,
        headline: format!(
            "{} of {} commands bit-identical to the host run over {} frames{gain}",
            a.bit_identical_commands, a.samples, a.frames
        ),
        report: dir.join("summary.md"),
        downloads: Vec::new(),
    })
}

/// Runs every step; stops at the first failure. The whole output folder is
/// built in a staging folder and renamed into place at the end, so a failed
/// run leaves the previous `out` exactly as it was (a previous `out` is
/// replaced only if mre wrote it).
pub fn run_demo(options: &DemoOptions) -> Result<Vec<DemoStep>> {
    let mut steps = Vec::new();
    crate::atomic_write::stage_folder(&options.out_dir, true, |staging| {
        steps = run_steps(&DemoOptions {
            out_dir: staging.to_path_buf(),
            ..options.clone()
        })?;
        write_index(staging, &steps)?;
        name_the_published_folder(staging, &options.out_dir)?;
        for step in &mut steps {
            if let Ok(inside) = step.report.strip_prefix(staging) {
                step.report = options.out_dir.join(inside);
            }
        }
        Ok(())
    })?;
    Ok(steps)
}

/// Steps record the paths they were given (a model file, a data set's
/// outputs), which during the run lie in the hidden staging folder that is
/// renamed to `out` at the end. Pages must name the folder the user asked
/// for, so every text output's staging path is rewritten to `out`.
fn name_the_published_folder(staging: &Path, out: &Path) -> Result<()> {
    const TEXT: [&str; 8] = ["md", "html", "json", "toml", "csv", "rs", "txt", "svg"];
    // The staging folder as steps may have spelled it (absolute, canonical, as
    // given), each with the published folder in the same form.
    let out_abs = std::path::absolute(out).unwrap_or_else(|_| out.to_path_buf());
    let mut spellings: Vec<(String, String)> = Vec::new();
    for (staged, published) in [
        (std::path::absolute(staging).ok(), &out_abs),
        (std::fs::canonicalize(staging).ok(), &out_abs),
        (Some(staging.to_path_buf()), &out.to_path_buf()),
    ] {
        let Some(staged) = staged else { continue };
        let pair = (staged.display().to_string(), published.display().to_string());
        if !spellings.contains(&pair) {
            spellings.push(pair);
        }
    }
    let mut folders = vec![staging.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).with_context(|| format!("cannot read {}", folder.display()))? {
            let path = entry?.path();
            if path.is_dir() {
                folders.push(path);
                continue;
            }
            let is_text = path.extension().is_some_and(|e| TEXT.iter().any(|t| e == *t));
            if !is_text {
                continue;
            }
            let Ok(text) = std::fs::read_to_string(&path) else {
                continue;
            };
            let mut renamed = text.clone();
            for (staged, published) in &spellings {
                renamed = renamed.replace(staged.as_str(), published);
            }
            if renamed != text {
                std::fs::write(&path, renamed).with_context(|| format!("cannot write {}", path.display()))?;
            }
        }
    }
    Ok(())
}

/// The four results a reader came for, shown first on `out/index.html`: each
/// a figure a step wrote, linked to that step's page.
fn results(out: &Path) -> Vec<crate::html::ResultFigure> {
    let figure = |png: &str, page: &str, caption: &str, missing: &str| crate::html::ResultFigure {
        image: out.join(png),
        page: out.join(page),
        caption: caption.to_string(),
        missing: missing.to_string(),
    };
    vec![
        figure(
            "mr-damper-mts/plots/fig12_bracket_0p5A.png",
            "mr-damper-mts/index.html",
            "The paper's model against real MR damper loops at 0.5 A, a current it was never fitted on \
             (interpolated between 0 A and 1 A).",
            "the fit step wrote no figure at 0.5 A",
        ),
        figure(
            "diagnose-mr-damper-mts/loops_worst.png",
            "diagnose-mr-damper-mts/index.html",
            "Diagnosis on the real MR damper data: measured loops, the paper's model, and the model with \
             the physics diagnosis found, on recordings held out of the fit.",
            "the diagnosis wrote no loop figure",
        ),
        figure(
            "recordings-to-flash/force-displacement.png",
            "recordings-to-flash/index.html",
            "The controlled drop (simulated plant): the diagnosed model and the paper's table flown by the \
             board's controller, against the passive damper and the physical limit.",
            "the closed-loop step wrote no figure",
        ),
        figure(
            &format!("pil/{}.png", crate::pil::sim::AGREEMENT_FIGURE),
            "pil/index.html",
            "Processor in the loop: the real firmware image in QEMU against the same core on the host, \
             coil command per control period.",
            "skipped: QEMU 10 was not found (see the PIL step below for the command that installs it)",
        ),
    ]
}

/// `index.html` in the demo's output folder: the four result figures, then
/// every step's headline, linked to the step's own page (the `index.html`
/// beside its report).
fn write_index(out: &Path, steps: &[DemoStep]) -> Result<()> {
    let pages: Vec<Option<PathBuf>> = steps
        .iter()
        .map(|s| {
            let page = s.report.with_file_name("index.html");
            (s.report.starts_with(out) && page.is_file()).then_some(page)
        })
        .collect();
    let entries: Vec<crate::html::IndexEntry> = steps
        .iter()
        .zip(&pages)
        .map(|(s, page)| crate::html::IndexEntry {
            title: &s.title,
            headline: &s.headline,
            link: page.as_deref(),
            downloads: &s.downloads,
        })
        .collect();
    crate::html::write_index(
        out,
        "mre demo: every step on the bundled data",
        "The paper's model fitted to real MR damper recordings and to simulated drop tests, validated by \
         predicting currents it never saw, diagnosed for missing physics, and run in closed loop on the host \
         and on the firmware. Each step's page has its tables, figures and data files.",
        &results(out),
        &entries,
    )
}

fn run_steps(options: &DemoOptions) -> Result<Vec<DemoStep>> {
    let data = &options.data_dir;
    let out = &options.out_dir;
    let steps = vec![
        fit_validate_plot(
            &data.join("mr-damper-mts"),
            &out.join("mr-damper-mts"),
            options.seed,
            &[0.5],
            "paper workflow on real MR damper data (0.5 A held out, predicted by interpolation)",
        )?,
        fit_validate_plot(
            &data.join("drop-none"),
            &out.join("drop-none"),
            options.seed,
            &[],
            "paper workflow on drop tests (intermediate currents predicted by interpolation)",
        )?,
        diagnosis(data, out, options.seed)?,
        real_data_diagnosis(data, out, options.seed)?,
        model_families(data, out, options.seed)?,
        closed_loop(out, options.seed)?,
        crate::control_bench::demo_step::recordings_to_flash(data, out)?,
        fmus(out)?,
        processor_in_the_loop(out, options.seed)?,
    ];
    Ok(steps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pages_name_the_published_folder_not_the_staging_one() {
        let dir = tempfile::tempdir().unwrap();
        let staging = dir.path().join(".mre-stage-abc123");
        std::fs::create_dir_all(staging.join("fit/validate")).unwrap();
        let model = staging.join("fit/model.toml");
        let report = staging.join("fit/validate/report.md");
        std::fs::write(&report, format!("Model: `{}`.\n", model.display())).unwrap();
        std::fs::write(staging.join("fig.png"), b"\x89PNG not text").unwrap();
        let out = dir.path().join("out");
        name_the_published_folder(&staging, &out).unwrap();
        let text = std::fs::read_to_string(&report).unwrap();
        assert_eq!(text, format!("Model: `{}`.\n", out.join("fit/model.toml").display()));
        assert_eq!(std::fs::read(staging.join("fig.png")).unwrap(), b"\x89PNG not text");
    }
}
