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
    }
    Ok(())
}
