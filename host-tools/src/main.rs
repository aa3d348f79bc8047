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
}

#[derive(Subcommand)]
enum Command {
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
    },
    /// Locate model-vs-recording mismatch, name the missing physics, model it, show the fit improve.
    Diagnose {
        /// Data set folder (dataset.toml + recordings).
        dataset: PathBuf,
        /// Baseline table TOML (default: fit the paper's model by least squares).
        #[arg(long)]
        model: Option<String>,
        /// Folder for report.md and its plots.
        #[arg(long)]
        report: PathBuf,
        /// report.json path.
        #[arg(long)]
        json: PathBuf,
        /// Folder for one predictions CSV per recording.
        #[arg(long)]
        predictions: PathBuf,
        /// Hold out whole groups: one cross-validation fold per value of this tag (e.g. frequency_hz).
        #[arg(long)]
        folds_by: Option<String>,
        /// Number of stratified cross-validation folds (when --folds-by is not given).
        #[arg(long, default_value_t = 5)]
        folds: usize,
        /// Treat recordings at this current (A) as `validate`; repeatable.
        #[arg(long)]
        validate_current: Vec<f64>,
        #[arg(long, default_value_t = 1)]
        seed: u64,
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
    },
    /// Simulate the drop test: passive 0 A, passive 2 A and the core's impact law in the loop.
    Sim {
        /// passive:<A> or controlled (repeatable); default: passive:0, passive:2 and controlled.
        #[arg(long = "current")]
        current: Vec<String>,
        /// Include the controlled run (the core's ImpactLaw in the loop).
        #[arg(long)]
        controlled: bool,
        /// Concealed effect on the plant: none, a vocabulary name, or random.
        #[arg(long, default_value = "none")]
        effect: String,
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Impact velocity (m/s).
        #[arg(long, default_value_t = 2.24)]
        velocity: f64,
        /// Drop mass (kg).
        #[arg(long, default_value_t = 5.5)]
        mass: f64,
        /// Coil time constant L/R (ms); default: the current follows the command at once.
        #[arg(long)]
        coil_lag_ms: Option<f64>,
        /// Folder for CSV, summary and plots.
        #[arg(long)]
        report: PathBuf,
    },
}

fn main() {
    if let Err(e) = run(Cli::parse()) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
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
        Command::Synth {
            effect,
            seed,
            out,
            key,
            force,
        } => {
            let output = mre_host::plant::synth::write_synth(&effect, seed, &out, key.as_deref(), force)?;
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
            report,
            json,
            predictions,
            folds_by,
            folds,
            validate_current,
            seed,
        } => {
            let opts = mre_host::diagnose::options_from_cli(model.as_deref(), folds_by, folds, validate_current, seed)?;
            let out = mre_host::diagnose::run_to_files(&dataset, &opts, &report, &json, &predictions)?;
            println!("{}", mre_host::diagnose::summary_line(&out));
            println!("report: {}", report.join("report.md").display());
        }
        Command::BenchDiagnose { cases, seed, json } => {
            let opts = mre_host::diagnose::DiagnoseOptions::default();
            let summary = mre_host::diagnose::bench::run_bench(cases, seed, &opts, |k, c| {
                eprintln!(
                    "case {:>3} seed {}: truth {:<20} diagnosed {:?} ({:.2} s); first round {:?}",
                    k + 1,
                    c.seed,
                    c.truth,
                    c.found,
                    c.seconds,
                    c.first_round
                        .iter()
                        .map(|(n, r)| format!("{n} {r:.3}"))
                        .collect::<Vec<_>>()
                )
            })?;
            print!("{}", mre_host::diagnose::bench::format_summary(&summary));
            if let Some(path) = json {
                mre_host::atomic_write::write_atomic(&path, serde_json::to_string_pretty(&summary)?.as_bytes())?;
            }
        }
        Command::Sim {
            current,
            controlled,
            effect,
            seed,
            velocity,
            mass,
            coil_lag_ms,
            report,
        } => {
            use mre_host::plant::closed_loop::{run_sim, RunSpec, SimRequest, DEFAULT_RUNS};
            let mut runs = current.iter().map(|c| RunSpec::parse(c)).collect::<Result<Vec<_>>>()?;
            if controlled && !runs.is_empty() && !runs.contains(&RunSpec::Controlled) {
                runs.push(RunSpec::Controlled);
            }
            if runs.is_empty() {
                runs = DEFAULT_RUNS.to_vec();
            }
            let request = SimRequest {
                runs,
                effect,
                seed,
                impact_velocity_m_s: velocity,
                mass_kg: mass,
                coil_lag_s: coil_lag_ms.map(|ms| ms * 1e-3),
            };
            let cmp = run_sim(&request, &report)?;
            print!("{}", mre_host::plant::sim_report::summary_table(&cmp));
            println!("report: {}", report.join("summary.md").display());
        }
    }
    Ok(())
}
