//! `cargo bench -p host-tools --bench gsa_weights`: does the random-weight
//! form change what GSA finds? Fits every branch of DATASET (default
//! data/drop-none) on both search boxes (data, the paper's Table 3), with the
//! paper's per-agent weights and the reference code's per-dimension weights,
//! for SEEDS seeds (default 10), N = T = 100, and writes one CSV row per fit
//! (`box,weights,seed,current_a,branch,rmse_n`) to CSV (default
//! out/bench/gsa_weights.csv). `bench/gsa_boxes.py` turns it into gaps to the
//! least-squares optimum inside each box (BENCHMARKS.md, Fitting).
use anyhow::{Context, Result};
use mre_algorithm::model::Branch;
use mre_host::dataset::Dataset;
use mre_host::fit::bounds::BoundsChoice;
use mre_host::fit::gsa::{GsaParams, RandomWeights};
use mre_host::fit::problems::branch_problems;
use mre_host::fit::{fit_branches, FitOptions, Method};
use std::fmt::Write as _;
use std::path::PathBuf;

fn main() -> Result<()> {
    // `cargo bench` passes `--bench`; no other arguments are taken.
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let dataset = std::env::var("DATASET").map_or_else(|_| root.join("data/drop-none"), PathBuf::from);
    let seeds: u64 = std::env::var("SEEDS")
        .map_or(Ok(10), |s| s.parse())
        .context("SEEDS is not a number")?;
    let csv = std::env::var("CSV").map_or_else(|_| root.join("out/bench/gsa_weights.csv"), PathBuf::from);
    let problems = branch_problems(&Dataset::load(&dataset)?)?;
    let mut out = String::from("box,weights,seed,current_a,branch,rmse_n\n");
    for bounds in [BoundsChoice::Data, BoundsChoice::Paper] {
        for (weights, label) in [
            (RandomWeights::PerAgent, "per-agent"),
            (RandomWeights::PerDimension, "per-dimension"),
        ] {
            let mut summed_rmse_n = Vec::new();
            for seed in 1..=seeds {
                let options = FitOptions {
                    method: Method::Gsa,
                    gsa: GsaParams {
                        seed,
                        weights,
                        ..GsaParams::default()
                    },
                    bounds: bounds.clone(),
                    progress: false,
                };
                let fits = fit_branches(&problems, &options)?;
                let mut sum = 0.0;
                for fit in &fits {
                    let branch = match fit.branch {
                        Branch::Compression => "compression",
                        Branch::Extension => "extension",
                    };
                    writeln!(
                        out,
                        "{},{label},{seed},{},{branch},{}",
                        bounds.label(),
                        fit.current_a,
                        fit.chosen.rmse_n
                    )?;
                    sum += fit.chosen.rmse_n;
                }
                summed_rmse_n.push(sum);
            }
            summed_rmse_n.sort_by(f64::total_cmp);
            println!(
                "{} box, {label}: summed RMSE over {} branches, {seeds} seeds: median {:.1} N (min {:.1}, max {:.1})",
                bounds.label(),
                problems.len(),
                summed_rmse_n[summed_rmse_n.len() / 2],
                summed_rmse_n[0],
                summed_rmse_n[summed_rmse_n.len() - 1]
            );
        }
    }
    if let Some(dir) = csv.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(&csv, out).with_context(|| format!("cannot write {}", csv.display()))?;
    println!("wrote {}", csv.display());
    Ok(())
}
