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
    }
    Ok(())
}
