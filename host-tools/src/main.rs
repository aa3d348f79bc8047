//! `mre`: command-line front end. Argument parsing only; the work is in the
//! `mre_host` library.
use anyhow::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "mre",
    version,
    about = "Model, fit, validate and diagnose MRE impact dampers"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// No progress bars (they are shown only on a terminal anyway).
    #[arg(long, short, global = true)]
    quiet: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Run the whole workflow on the bundled data (the README's main command).
    Demo {
        /// Folder with the bundled data sets.
        #[arg(long, default_value = "data")]
        data: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Write the model's compression and extension curves at one current (CSV).
    Model {
        /// `paper` (built-in Table 4) or a table TOML file.
        #[arg(long, default_value = "paper")]
        table: String,
        /// Coil current in A; between tabulated currents it is interpolated.
        #[arg(long)]
        current: f32,
        /// Samples along the fitted stroke.
        #[arg(long, default_value_t = 101)]
        points: usize,
        #[arg(long)]
        out: PathBuf,
    },
    /// Fit the per-current branch quartics to a data set (GSA, least squares, or both).
    Fit {
        /// Data set folder (holding dataset.toml).
        dataset: PathBuf,
        /// gsa, lsq, or both (table gets the lsq optimum; GSA's gap is reported).
        #[arg(long, default_value = "both")]
        method: mre_host::fit::Method,
        #[command(flatten)]
        gsa: GsaArgs,
        /// Treat recordings at these currents as `validate` (held out of the fit).
        #[arg(long, value_delimiter = ',')]
        hold_out_current: Vec<f64>,
        /// Model file to write (TOML; also a table file for --table).
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        installation: InstallationOptions,
    },
    /// Compare a model with every recording of a data set; write report.md and report.json.
    Validate {
        dataset: PathBuf,
        /// `paper` or a model/table file.
        #[arg(long)]
        model: String,
        /// Folder for report.md and report.json.
        #[arg(long, alias = "report")]
        out: PathBuf,
        /// Treat recordings at these currents as `validate` (as given to `fit`).
        #[arg(long, value_delimiter = ',')]
        hold_out_current: Vec<f64>,
    },
    /// Draw the paper's figures (PNG + SVG): loops per current, all currents, interpolated, bracket, convergence.
    Plot {
        dataset: PathBuf,
        /// Model file from `mre fit` (or any table file; then no convergence plot).
        #[arg(long)]
        model: PathBuf,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        /// Currents to draw interpolated loops at (default: midpoints and validate currents).
        #[arg(long, value_delimiter = ',')]
        interpolate: Vec<f64>,
        /// Treat recordings at these currents as `validate` (as given to `fit`).
        #[arg(long, value_delimiter = ',')]
        hold_out_current: Vec<f64>,
    },
    /// GSA performance index against iterations and agents (the paper's Figs. 13/14).
    Sweep {
        dataset: PathBuf,
        /// `--agents` is held for the iteration sweep, `--iters` for the agent sweep.
        #[command(flatten)]
        gsa: GsaArgs,
        #[arg(long, value_delimiter = ',')]
        hold_out_current: Vec<f64>,
        /// Output folder (sweep.csv and the figures).
        #[arg(long)]
        out: PathBuf,
    },
    /// Generate the firmware's flash table (Rust source with CRC) from a model file.
    Tables {
        /// Model file from `mre fit` (or any table file).
        model: PathBuf,
        /// Rust source to write; default: the firmware's own, `firmware/src/generated_table.rs`,
        /// when run from the root of a checkout (it never creates that folder elsewhere).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Write a synthetic drop-impact data set with a concealed effect (key file beside it).
    Synth {
        /// none, viscous_damping, sensor_delay, stress_softening, end_stop, magnetic_saturation, or random.
        #[arg(long, default_value = "random")]
        effect: String,
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Data set folder to create.
        #[arg(long)]
        out: PathBuf,
        /// Key file (effect + parameters, JSON); default `<out>.key.json` beside the folder.
        #[arg(long)]
        key: Option<PathBuf>,
        /// Replace an existing non-empty folder.
        #[arg(long)]
        force: bool,
        /// Choose a drop height per current so every current's fastest test
        /// reaches this stroke (mm), instead of the paper's velocities at all.
        #[arg(long)]
        full_stroke_mm: Option<f64>,
        /// `drop` (drop impacts, the paper's law), `instrumented` (the same drops with a striker
        /// accelerometer and every second repeat at 2.75 kg: reveals `inertia`) or `mts` (sinusoidal
        /// shaker/MTS tests, a Dahl or Bouc–Wen base law; effects none, viscous_damping,
        /// sensor_delay, end_stop, inertia).
        #[arg(long, default_value = "drop")]
        campaign: String,
    },
    /// Locate model-vs-recording mismatch, name the missing physics, model it, show the fit improve.
    Diagnose {
        /// Data set folder (dataset.toml + recordings).
        dataset: PathBuf,
        /// Baseline table TOML (default: fit the paper's model by least squares).
        #[arg(long)]
        model: Option<String>,
        /// Folder for report.md and its plots.
        #[arg(long, alias = "report")]
        out: PathBuf,
        /// report.json path (default: report.json in the --out folder).
        #[arg(long)]
        json: Option<PathBuf>,
        /// Folder for one predictions CSV per recording (default: predictions/ in the --out folder).
        #[arg(long)]
        predictions: Option<PathBuf>,
        /// Hold out whole groups: one cross-validation fold per value of this tag (e.g. frequency_hz).
        #[arg(long)]
        folds_by: Option<String>,
        /// Number of stratified cross-validation folds (when --folds-by is not given).
        #[arg(long, default_value_t = 5)]
        folds: usize,
        /// Treat recordings at these currents as `validate` (held out of every fit).
        #[arg(long, alias = "validate-current", value_delimiter = ',')]
        hold_out_current: Vec<f64>,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Also write the final model (a table file with its [installation]) for `mre tables`.
        #[arg(long)]
        model_out: Option<PathBuf>,
        #[command(flatten)]
        installation: InstallationOptions,
        /// Change a decision rule, NAME=VALUE (repeatable; the rules and their frozen
        /// defaults: host-tools/DIAGNOSE.md, "Rules").
        #[arg(long = "set")]
        rules: Vec<String>,
    },
    /// Controllers (a) paper table, (b) `mre fit`, (c) `mre diagnose` against the physical limit.
    BenchControl {
        /// Folder for report.md and report.json.
        #[arg(long, default_value = "out/bench-control")]
        out: PathBuf,
        /// Only the real coils (τ 10–20 ms: arming, impact range, driver sizing).
        #[arg(long)]
        real_coils: bool,
        #[command(flatten)]
        installation: SimInstallationArgs,
    },
    /// Blind benchmark of `diagnose` on `mre synth --effect random` cases.
    BenchDiagnose {
        #[arg(long, default_value_t = 60)]
        cases: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Also write every case and the summary as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Also run this many shaker/MTS cases from a rate-independent base law (Dahl / Bouc–Wen).
        #[arg(long, default_value_t = 10)]
        mts_cases: usize,
        /// Also run this many instrumented drop cases (two drop masses, striker accelerometer),
        /// effects in turn, `inertia` included.
        #[arg(long, default_value_t = 16)]
        instrumented_cases: usize,
        /// Inject effects into these real recordings instead (data set folder).
        #[arg(long)]
        real: Option<PathBuf>,
        /// With --real: one cross-validation fold per value of this tag.
        #[arg(long)]
        folds_by: Option<String>,
        /// With --real: treat recordings at these currents as `validate` (held out of every fit).
        #[arg(long, alias = "validate-current", value_delimiter = ',')]
        hold_out_current: Vec<f64>,
        /// With --real or --outside: run only the cases of these effects (`none` included by name);
        /// each case keeps its seed, so the cases run are the same as in the full benchmark.
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// Run this many calibration cases instead (effects not in the candidates' forms;
        /// seeds from --seed); reports false-positive and top-1 rates with 95 % bounds.
        #[arg(long)]
        calibration: Option<usize>,
        /// Run this many outside-class cases per vocabulary word instead (`plant::outside`:
        /// physics outside the model class, seeds from --seed); reports per-effect verdicts.
        #[arg(long)]
        outside: Option<usize>,
        /// Change a decision rule, NAME=VALUE (repeatable), as for `mre diagnose`.
        #[arg(long = "set")]
        rules: Vec<String>,
    },
    /// Fit the paper's polynomial, the polynomial with diagnose's terms and five
    /// nonlinear families (GSA + Levenberg–Marquardt) side by side (Fig. 15).
    Compare {
        /// Data set folder (holding dataset.toml).
        dataset: PathBuf,
        /// Folder for report.json, report.md, predictions/ and plots/.
        #[arg(long, alias = "report")]
        out: PathBuf,
        /// Recordings at these currents are only predicted (held out).
        #[arg(long, value_delimiter = ',', default_value = "0.5")]
        hold_out_current: Vec<f64>,
        /// GSA agents N for the nonlinear families.
        #[arg(long, default_value_t = 40)]
        agents: usize,
        /// GSA iterations T for the nonlinear families.
        #[arg(long, default_value_t = 150)]
        iters: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The demo's reduced budget (N = 30, T = 60, coarser refinement).
        #[arg(long)]
        reduced: bool,
    },
    /// Time the Bouc–Wen GSA of `compare` and export its objective for bench/compare_gsa.py.
    BenchCompare {
        #[arg(default_value = "data/mr-damper-mts")]
        dataset: PathBuf,
        /// Fit current whose recordings make the objective.
        #[arg(long, default_value_t = 1.0)]
        current: f64,
        #[arg(long, default_value_t = 40)]
        agents: usize,
        #[arg(long, default_value_t = 150)]
        iters: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Samples per recording after decimation.
        #[arg(long, default_value_t = 600)]
        samples: usize,
        #[arg(long, default_value_t = 5)]
        repeats: usize,
        /// Folder for objective.csv and bench.json.
        #[arg(long)]
        out: PathBuf,
    },
    /// Simulate the drop test: passive 0 A, passive 2 A and the core's impact law in the loop.
    Sim {
        #[command(flatten)]
        drop: DropArgs,
        /// Include the controlled run (the core's ImpactLaw in the loop).
        #[arg(long)]
        controlled: bool,
        /// Coil time constant L/R (ms); default: the current follows the command at once.
        #[arg(long)]
        coil_lag_ms: Option<f64>,
        /// Coil time constant while the current falls (ms), when switching off is slower (eddy currents); needs --coil-lag-ms.
        #[arg(long)]
        coil_lag_off_ms: Option<f64>,
        /// Folder for CSV, summary and plots.
        #[arg(long, alias = "report")]
        out: PathBuf,
    },
    /// Data set helpers: `mre dataset init DIR` writes dataset.toml for a folder of recordings;
    /// `mre dataset check DIR` loads it and prints what it holds and what the readers assumed.
    Dataset {
        #[command(subcommand)]
        action: DatasetAction,
    },
    /// Print a shell completion script (e.g. `mre completions bash > /etc/bash_completion.d/mre`).
    Completions { shell: clap_complete::Shell },
    /// Processor-in-the-loop: the drop comparison with the controlled run
    /// closed through the firmware in QEMU (`cargo fw-pil` image).
    Pil {
        #[command(flatten)]
        drop: DropArgs,
        /// The PIL firmware image; default: build it with `cargo fw-pil`.
        #[arg(long)]
        elf: Option<PathBuf>,
        /// Folder for CSV, summary, plots and pil.json.
        #[arg(long, alias = "report")]
        out: PathBuf,
        /// Inject faults instead (e.g. `all:1e-2`, `corrupt:1e-3,drop:1e-2,duplicate:1e-2,sensors,upload,sense-stuck,sense-stale`);
        /// writes faults.md and faults.json.
        #[arg(long)]
        faults: Option<String>,
        /// Hardware in the loop: the `pil` image already running on this serial port (a board's VCP) instead of QEMU.
        #[arg(long, conflicts_with_all = ["elf", "faults"])]
        serial: Option<PathBuf>,
    },
    /// Send a table to a running board over its serial port (no reflashing): it is stored in flash and flown after the next reset.
    Upload {
        /// The board's serial port (the ST-LINK virtual COM port, e.g. /dev/ttyACM0).
        #[arg(long)]
        port: PathBuf,
        /// Model or table file (as `mre tables` reads).
        model: PathBuf,
        /// The control rate of the configuration sent with it (the image keeps only the table if it runs another rate).
        #[arg(long)]
        rate_hz: Option<u32>,
    },
    /// Write the model as an FMI 3.0 (or 2.0) FMU (damper: displacement, velocity, current in; force out), evaluated by the board's core.
    Fmu {
        /// Model or table file (as `mre tables` reads).
        model: PathBuf,
        #[arg(long, default_value = "damper.fmu")]
        out: PathBuf,
        /// Also write controller.fmu beside it: the impact controller as the board runs it.
        #[arg(long)]
        controller: bool,
        /// FMI version of the FMUs: 3 (FMI 3.0) or 2 (FMI 2.0, for importers without 3.0); the same libraries and model.
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(2..=3))]
        fmi_version: u8,
    },
}

#[derive(Subcommand)]
enum DatasetAction {
    /// Write DIR/dataset.toml from the recordings in DIR (never overwrites one).
    Init {
        dir: PathBuf,
        /// Metadata in file names, `x` for the decimal point, e.g. '{amplitude_mm}mm{frequency_hz}Hz{current_a}A'.
        #[arg(long)]
        pattern: Option<String>,
        /// The data set's name (default: the folder's name).
        #[arg(long)]
        name: Option<String>,
    },
    /// Load DIR/dataset.toml as every command does and print what it holds and what the readers assumed.
    Check { dir: PathBuf },
}

/// GSA settings shared by `fit` and `sweep`.
#[derive(clap::Args)]
struct GsaArgs {
    /// GSA agents N.
    #[arg(long, default_value_t = 100)]
    agents: usize,
    /// GSA iterations T.
    #[arg(long, default_value_t = 100)]
    iters: usize,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// GSA search box: `data` (around a cheap estimate) or `paper` (Table 3).
    #[arg(long, default_value = "data")]
    bounds: mre_host::fit::bounds::BoundsChoice,
}

impl GsaArgs {
    fn options(&self, method: mre_host::fit::Method, progress: bool) -> mre_host::fit::FitOptions {
        mre_host::fit::FitOptions {
            method,
            gsa: mre_host::fit::gsa::GsaParams {
                agents: self.agents,
                iters: self.iters,
                seed: self.seed,
                ..Default::default()
            },
            bounds: self.bounds.clone(),
            progress,
        }
    }
}

/// Installation values a model file is written with (`fit`, `diagnose --model-out`).
#[derive(clap::Args)]
struct InstallationOptions {
    /// Installation value KEY=VALUE over the data set's metadata and the defaults (repeatable;
    /// keys as a model file's [installation], e.g. mass_kg=3, usable_stroke_mm=9).
    #[arg(long = "installation", value_name = "KEY=VALUE")]
    values: Vec<String>,
}

/// The installation a simulation runs in (`sim`, `pil`, `bench-control`).
#[derive(clap::Args)]
struct SimInstallationArgs {
    /// Model file whose [installation] (mass, usable stroke, coil, sensors) the drop and the
    /// controller use; default: DEFAULT_INSTALLATION. The output says where each value came from.
    #[arg(long)]
    model: Option<PathBuf>,
    /// Installation value KEY=VALUE over the model file's (repeatable, e.g. usable_stroke_mm=9).
    #[arg(long = "installation", value_name = "KEY=VALUE")]
    values: Vec<String>,
}

impl SimInstallationArgs {
    /// The installation, stated (printed: which values came from where).
    fn resolve(&self, mass_kg: Option<f64>) -> Result<mre_host::installation::StatedInstallation> {
        use mre_host::installation::StatedInstallation;
        let from_file = match &self.model {
            Some(path) => StatedInstallation::from_model_file(path)?,
            None => StatedInstallation::default(),
        };
        let mut values = self.values.clone();
        if let Some(kg) = mass_kg {
            values.push(format!("mass_kg={kg}"));
        }
        let stated = from_file.with_options(&values)?;
        println!("{}", stated.describe());
        Ok(stated)
    }
}

/// The simulated drop test, shared by `sim` and `pil`.
#[derive(clap::Args)]
struct DropArgs {
    /// passive:<A> or controlled (repeatable); default: passive:0, passive:2 and controlled.
    #[arg(long = "current")]
    current: Vec<String>,
    /// Concealed effect on the plant: none, a vocabulary name, or random.
    #[arg(long, default_value = "none")]
    effect: String,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Impact velocity (m/s).
    #[arg(long, default_value_t = 2.24)]
    velocity: f64,
    /// Drop mass (kg), over the installation's (same as --installation mass_kg=KG).
    #[arg(long)]
    mass: Option<f64>,
    #[command(flatten)]
    installation: SimInstallationArgs,
}

impl DropArgs {
    fn request(self, coil_lag_s: Option<f64>) -> Result<mre_host::plant::closed_loop::SimRequest> {
        use mre_host::plant::closed_loop::RunSpec;
        Ok(mre_host::plant::closed_loop::SimRequest {
            runs: self
                .current
                .iter()
                .map(|c| RunSpec::parse(c))
                .collect::<Result<Vec<_>>>()?,
            effect: self.effect,
            seed: self.seed,
            impact_velocity_m_s: self.velocity,
            installation: self.installation.resolve(self.mass)?.installation,
            coil_lag_s,
            coil_lag_off_s: None,
        })
    }
}

fn main() {
    let cli = Cli::parse();
    mre_host::progress::set_enabled(!cli.quiet && show_progress());
    if let Err(e) = mre_host::atomic_write::interrupt::install() {
        eprintln!("warning: {e:#}; an interrupted run may leave .mre-stage-* files behind");
    }
    // Every command's outputs are published together or not at all; the demo
    // stages its whole output folder itself (its steps read earlier outputs).
    let result = match cli.command {
        Command::Demo { .. } => run(cli),
        _ => mre_host::atomic_write::command(|| run(cli)),
    };
    mre_host::atomic_write::interrupt::defer_to_handler_if_interrupted();
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

/// Progress bars only on an interactive terminal, never in CI.
fn show_progress() -> bool {
    use std::io::IsTerminal;
    std::io::stderr().is_terminal() && std::env::var_os("CI").is_none()
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Demo { data, out, seed } => {
            let steps = mre_host::demo::run_demo(&mre_host::demo::DemoOptions {
                data_dir: data,
                out_dir: out.clone(),
                seed,
            })?;
            println!();
            for step in steps {
                println!("{}\n  {}", step.title, step.headline);
            }
            // One place to look: the page links every step's report.
            println!("\n{}", out.join("index.html").display());
        }
        Command::Model {
            table,
            current,
            points,
            out,
        } => {
            let table = mre_host::table_file::load_table(&table)?;
            let curve = mre_host::loops::model_loop(&table, current, points)?;
            mre_host::atomic_write::write_atomic_with(&out, |buf| mre_host::loops::write_loop_csv(buf, &curve))?;
            println!("wrote {} points at {current} A to {}", curve.len(), out.display());
        }
        Command::Fit {
            dataset,
            method,
            gsa,
            hold_out_current,
            out,
            installation,
        } => {
            let options = gsa.options(method, mre_host::progress::enabled());
            let run = mre_host::fit::run_fit_with_installation(
                &dataset,
                &options,
                &hold_out_current,
                &installation.values,
                &out,
            )?;
            if let Some(stated) = &run.model.installation {
                println!("{}", stated.describe());
            }
            print!("{}", run.reading_notes);
            print!("{}", mre_host::fit::summary_markdown(&run.fits));
            println!(
                "fitted {} branches in {:.3} ms; wrote {}",
                run.fits.len(),
                run.fit_seconds * 1e3,
                out.display()
            );
        }
        Command::Validate {
            dataset,
            model,
            out: report,
            hold_out_current,
        } => {
            let _progress = mre_host::progress::spinner("validating");
            let r = mre_host::validate::run_validate(&dataset, &model, &hold_out_current, &report)?;
            print!("{}", mre_host::validate::report::markdown(&r));
            println!("\nwrote {0}/report.md, report.json and index.html", report.display());
        }
        Command::Plot {
            dataset,
            model,
            out,
            interpolate,
            hold_out_current,
        } => {
            let options = mre_host::plot::PlotOptions {
                interpolated_a: interpolate,
            };
            let _progress = mre_host::progress::spinner("drawing the figures");
            let files = mre_host::plot::run_plot(&dataset, &model, &hold_out_current, &options, &out)?;
            for f in files {
                println!("wrote {}.png and .svg", f.display());
            }
        }
        Command::Sweep {
            dataset,
            gsa,
            hold_out_current,
            out,
        } => {
            let base = gsa.options(mre_host::fit::FitOptions::default().method, false);
            let _progress = mre_host::progress::spinner("sweeping GSA iterations and agents");
            let s = mre_host::fit::sweep::run_sweep(&dataset, &base, &hold_out_current, &out)?;
            print!("{}", mre_host::fit::sweep::to_csv(&s));
            println!("wrote {}/sweep.csv and the Fig. 13/14 plots", out.display());
        }
        Command::Tables { model, out } => {
            let out = mre_host::tables::resolve_out(out)?;
            let (table, installation) = mre_host::tables::run_tables_stated(&model, &out)?;
            println!(
                "wrote {} entries (CRC-32 {:#010x}) to {}",
                table.entries().len(),
                table.crc32(),
                out.display()
            );
            println!(
                "installation (format {}) from {}: {}",
                table.version(),
                installation.describe(),
                mre_host::table_file::installation_summary(table.installation())
            );
        }
        Command::Synth {
            effect,
            seed,
            out,
            key,
            force,
            campaign,
            ..
        } if campaign == "mts" => {
            let output = mre_host::plant::synth_mts::write_synth_mts(&effect, seed, &out, key.as_deref(), force)?;
            println!(
                "wrote {} recordings to {} ({:?} base law)",
                output.dataset.recordings.len(),
                out.display(),
                output.law.hysteresis
            );
        }
        Command::Synth {
            effect,
            seed,
            out,
            key,
            force,
            campaign,
            full_stroke_mm,
        } => {
            let base = match campaign.as_str() {
                "drop" => mre_host::plant::synth::SynthPlan::default(),
                "instrumented" => mre_host::plant::synth::SynthPlan::instrumented(),
                _ => anyhow::bail!("unknown campaign `{campaign}`; expected drop, instrumented or mts"),
            };
            let plan = match full_stroke_mm {
                Some(mm) => mre_host::plant::synth::SynthPlan {
                    full_stroke_mm: Some(mm),
                    ..base
                },
                None => base,
            };
            let output =
                mre_host::plant::synth::write_synth_with_plan(&effect, seed, &plan, &out, key.as_deref(), force)?;
            let key_path = key.unwrap_or_else(|| mre_host::plant::synth::default_key_path(&out));
            println!(
                "wrote {} recordings to {} (key: {})",
                output.dataset.recordings.len(),
                out.display(),
                key_path.display()
            );
        }
        Command::Diagnose {
            dataset,
            model,
            out: report,
            json,
            predictions,
            folds_by,
            folds,
            hold_out_current,
            seed,
            model_out,
            rules,
            installation,
        } => {
            let json = json.unwrap_or_else(|| report.join("report.json"));
            let predictions = predictions.unwrap_or_else(|| report.join("predictions"));
            let mut opts =
                mre_host::diagnose::options_from_cli(model.as_deref(), folds_by, folds, hold_out_current, seed)?;
            opts.thresholds = opts.thresholds.with_overrides(&rules)?;
            let progress = mre_host::progress::spinner("diagnosing");
            let out = match &model_out {
                Some(path) => {
                    use mre_host::diagnose::model_out::run_to_files_with_model;
                    let (out, _, stated) = run_to_files_with_model(
                        &dataset,
                        &opts,
                        &report,
                        &json,
                        &predictions,
                        path,
                        &installation.values,
                    )?;
                    println!("final model: {}", path.display());
                    println!("{}", stated.describe());
                    out
                }
                None => mre_host::diagnose::run_to_files(&dataset, &opts, &report, &json, &predictions)?,
            };
            std::mem::drop(progress);
            println!("{}", mre_host::diagnose::summary_line(&out));
            println!("report: {}", report.join("report.md").display());
            println!("page: {}", report.join("index.html").display());
        }
        Command::BenchControl {
            out,
            real_coils,
            installation,
        } => {
            let installation = installation.resolve(None)?.installation;
            let mut cases = mre_host::control_bench::default_cases();
            if real_coils {
                cases.retain(mre_host::control_bench::Case::is_real_coil);
            }
            let outcomes = mre_host::control_bench::run_to_files(&cases, &installation, &out)?;
            print!("{}", mre_host::control_bench::markdown(&outcomes));
            println!("\nreport: {}", out.join("report.md").display());
            println!("page: {}", out.join("index.html").display());
        }
        Command::BenchDiagnose {
            seed,
            json,
            outside: Some(n),
            only,
            rules,
            ..
        } => {
            let mut opts = mre_host::diagnose::DiagnoseOptions::default();
            opts.thresholds = opts.thresholds.with_overrides(&rules)?;
            let summary = mre_host::diagnose_bench::outside::run(n, seed, &only, &opts, |c| {
                eprintln!(
                    "seed {}: truth {:<20} verdict {:<12} found {:?} ({:.1} s)",
                    c.seed, c.truth, c.verdict, c.found, c.seconds
                )
            })?;
            print_summary(
                &mre_host::diagnose_bench::outside::format_summary(&summary),
                &summary,
                json,
            )?;
        }
        Command::BenchDiagnose {
            seed,
            json,
            calibration: Some(n),
            rules,
            ..
        } => {
            let mut opts = mre_host::diagnose::DiagnoseOptions::default();
            opts.thresholds = opts.thresholds.with_overrides(&rules)?;
            let summary = mre_host::diagnose_bench::calibration::run(n, seed, &opts, |c| {
                eprintln!(
                    "seed {}: truth {:<16} ({:.1} %) found {:?} [{}] ({:.1} s)",
                    c.seed,
                    c.truth,
                    100.0 * c.strength,
                    c.found,
                    c.accepted_by.join("; "),
                    c.seconds
                )
            })?;
            print_summary(
                &mre_host::diagnose_bench::calibration::format_summary(&summary),
                &summary,
                json,
            )?;
        }
        Command::BenchDiagnose {
            cases,
            seed,
            json,
            real: Some(real),
            folds_by,
            hold_out_current,
            only,
            rules,
            ..
        } => {
            let mut opts = mre_host::diagnose::options_from_cli(None, folds_by, 5, hold_out_current, seed)?;
            opts.thresholds = opts.thresholds.with_overrides(&rules)?;
            let ds = mre_host::dataset::Dataset::load(&real)?;
            let summary = mre_host::diagnose_bench::real::run_real_bench(&ds, cases, seed, &only, &opts, |c| {
                eprintln!(
                    "case {:>3}: {} at {:.1} % {:?}: found {:?} ({:.2} s); oracle {:?}; tested {:?}",
                    c.case + 1,
                    c.injection.effect,
                    100.0 * c.injection.achieved_strength,
                    c.injection.parameters,
                    mre_host::vocabulary::names(&c.found),
                    c.seconds,
                    c.oracle,
                    c.tested
                )
            })?;
            print_summary(
                &mre_host::diagnose_bench::real::format_real_summary(&summary),
                &summary,
                json,
            )?;
        }
        Command::BenchDiagnose {
            cases,
            mts_cases,
            instrumented_cases: inst,
            seed,
            json,
            ..
        } => {
            let opts = mre_host::diagnose::DiagnoseOptions::default();
            let progress = mre_host::progress::bar((cases + mts_cases + inst) as u64, "cases");
            let summary =
                mre_host::diagnose_bench::simulated::run_bench(cases, mts_cases, inst, seed, &opts, |k, c| {
                    progress.inc();
                    progress.println(&format!(
                        "case {:>3} seed {}: truth {:<20} diagnosed {:?} ({:.2} s); first round {:?}",
                        k + 1,
                        c.seed,
                        c.truth,
                        mre_host::vocabulary::names(&c.found),
                        c.seconds,
                        c.first_round
                            .iter()
                            .map(|(n, r)| format!("{n} {r:.3}"))
                            .collect::<Vec<_>>()
                    ))
                })?;
            std::mem::drop(progress);
            print_summary(
                &mre_host::diagnose_bench::simulated::format_summary(&summary),
                &summary,
                json,
            )?;
        }
        Command::Compare {
            dataset,
            out: report,
            hold_out_current,
            agents,
            iters,
            seed,
            reduced,
        } => {
            let mut opts = if reduced {
                mre_host::compare::CompareOptions::reduced()
            } else {
                let mut o = mre_host::compare::CompareOptions::default();
                o.budget.gsa.agents = agents;
                o.budget.gsa.iters = iters;
                o
            };
            opts.hold_out_a = hold_out_current;
            opts.seed = seed;
            let r = mre_host::compare::run_compare(&dataset, &opts, &report)?;
            for l in &r.left_out {
                eprintln!("note: {} left out: {}", l.family, l.missing);
            }
            println!("{}", mre_host::compare::report::summary_line(&r));
            println!("report: {}", report.join("report.md").display());
            println!("page: {}", report.join("index.html").display());
        }
        Command::BenchCompare {
            dataset,
            current,
            agents,
            iters,
            seed,
            samples,
            repeats,
            out,
        } => {
            let gsa = mre_host::fit::gsa::GsaParams {
                agents,
                iters,
                seed,
                ..Default::default()
            };
            let b = mre_host::compare::bench::run_bench(&dataset, current, gsa, samples, repeats, &out)?;
            println!(
                "bouc-wen GSA: {} evaluations on {} samples, median {:.4} s ({} threads), best objective {:.6}; \
                 + LM: {} evaluations, {:.4} s, objective {:.6}",
                b.evaluations,
                b.samples,
                b.median_s,
                b.threads,
                b.best_objective,
                b.refined_evaluations,
                b.refined_median_s,
                b.refined_objective
            );
        }
        Command::Sim {
            drop,
            controlled,
            coil_lag_ms,
            coil_lag_off_ms,
            out: report,
        } => {
            use mre_host::plant::closed_loop::{run_sim, RunSpec, DEFAULT_RUNS};
            let mut request = drop.request(coil_lag_ms.map(|ms| ms * 1e-3))?;
            request.coil_lag_off_s = coil_lag_off_ms.map(|ms| ms * 1e-3);
            if controlled && !request.runs.is_empty() && !request.runs.contains(&RunSpec::Controlled) {
                request.runs.push(RunSpec::Controlled);
            }
            if request.runs.is_empty() {
                request.runs = DEFAULT_RUNS.to_vec();
            }
            let progress = mre_host::progress::spinner("simulating the drop test");
            let cmp = run_sim(&request, &report)?;
            std::mem::drop(progress);
            print!("{}", mre_host::plant::sim_report::summary_table(&cmp));
            println!("report: {}", report.join("summary.md").display());
            println!("page: {}", report.join("index.html").display());
        }
        Command::Dataset {
            action: DatasetAction::Init { dir, pattern, name },
        } => {
            let path = mre_host::dataset::init::run_init(&dir, pattern.as_deref(), name.as_deref())?;
            println!("wrote {} (check the units it assumed, in its comments)", path.display());
        }
        Command::Dataset {
            action: DatasetAction::Check { dir },
        } => {
            let ds = mre_host::dataset::Dataset::load(&dir)?;
            print!("{}", mre_host::dataset::summary::check_markdown(&ds));
        }
        Command::Completions { shell } => {
            use clap::CommandFactory;
            clap_complete::generate(shell, &mut Cli::command(), "mre", &mut std::io::stdout());
        }
        Command::Pil {
            drop,
            elf,
            out: report,
            faults: Some(spec),
            serial: _,
        } => {
            let plan = mre_host::pil::faults::FaultPlan::parse(&spec, drop.seed)?;
            let request = mre_host::pil::sim::PilRequest {
                sim: drop.request(None)?,
                elf,
            };
            let r = mre_host::pil::faults::run_to_report(&request, &plan, &report)?;
            print!("{}", r.markdown());
            println!("report: {}", report.join("faults.md").display());
            if !r.all_detected_and_survived() {
                anyhow::bail!("not every injected fault was detected and survived (see faults.md)");
            }
        }
        Command::Pil {
            drop,
            elf,
            out: report,
            faults: None,
            serial,
        } => {
            let sim = drop.request(None)?;
            let progress = mre_host::progress::spinner(if serial.is_some() {
                "running the drop with the firmware on the serial port"
            } else {
                "building the PIL firmware and running it in QEMU"
            });
            let firmware_on = if serial.is_some() { "serial port" } else { "QEMU" };
            let out = match serial {
                Some(port) => {
                    let link = mre_host::pil::sim::FirmwareLink::Serial { port: &port };
                    mre_host::pil::sim::run_pil_on(&sim, link, &report)?
                }
                None => mre_host::pil::sim::run_pil(&mre_host::pil::sim::PilRequest { sim, elf }, &report)?,
            };
            std::mem::drop(progress);
            print!("{}", mre_host::plant::sim_report::summary_table(&out.comparison));
            let a = out.agreement;
            println!(
                "firmware ({firmware_on}) vs in-process control: {} of {} commands bit-identical, max diff {:.3e} A, {} frames",
                a.bit_identical_commands, a.samples, a.max_command_diff_a, a.frames
            );
            if let Some(c) = out.counters {
                println!(
                    "firmware log: {} defmt frames dropped, {} events dropped",
                    c.log_frames_dropped, c.log_events_dropped
                );
            }
            println!("report: {}", report.join("summary.md").display());
            println!("page: {}", report.join("index.html").display());
            if !a.agrees() {
                anyhow::bail!("the firmware run does not match the in-process run (see pil.json)");
            }
        }
        Command::Fmu {
            model,
            out,
            controller,
            fmi_version,
        } => {
            let progress = mre_host::progress::spinner("building the FMU libraries and packing the FMUs");
            let fmi = if fmi_version == 2 {
                mre_host::fmu::FmiVersion::V2
            } else {
                mre_host::fmu::FmiVersion::V3
            };
            let written = mre_host::fmu::run_fmu(&mre_host::fmu::FmuRequest {
                model,
                out,
                controller,
                fmi,
            })?;
            std::mem::drop(progress);
            for path in written {
                println!("wrote {}", path.display());
            }
        }
        Command::Upload { port, model, rate_hz } => {
            let u = mre_host::upload::run_upload(&port, &model, rate_hz)?;
            println!(
                "uploaded {} currents (table CRC-32 {:#010x}, {} Hz, {} kg, {} mm stroke, {} words) to {}: stored, flown after the board's next reset",
                u.currents,
                u.table_crc32,
                u.rate_hz,
                u.mass_kg,
                u.stroke_mm,
                u.words,
                port.display()
            );
        }
    }
    Ok(())
}

/// Prints a benchmark's text summary and, with `--json PATH`, writes the
/// summary itself there (atomically).
fn print_summary<T: serde::Serialize>(text: &str, summary: &T, json: Option<PathBuf>) -> Result<()> {
    print!("{text}");
    if let Some(path) = json {
        mre_host::atomic_write::write_atomic(&path, serde_json::to_string_pretty(summary)?.as_bytes())?;
    }
    Ok(())
}
