//! `mre fit`: the paper's per-current, per-branch quartics, fitted by GSA
//! (as published), by exact least squares, or both (to show GSA's gap).
pub mod bounds;
pub mod gsa;
pub mod lsq;
pub mod model_file;
pub mod objective;
pub mod poly;
pub mod problems;
pub mod sweep;

use anyhow::{Context, Result};
use bounds::{BoundsChoice, SearchBox};
use gsa::GsaParams;
use mre_algorithm::model::Branch;
use objective::BranchMoments;
use problems::BranchProblem;
use rand::SeedableRng;
use rayon::prelude::*;

/// How the coefficients are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Gsa,
    Lsq,
    /// Both; the table gets the least-squares optimum, GSA's gap is reported.
    Both,
}

impl Method {
    pub fn label(self) -> &'static str {
        match self {
            Method::Gsa => "gsa",
            Method::Lsq => "lsq",
            Method::Both => "both",
        }
    }
}

impl std::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "gsa" => Ok(Method::Gsa),
            "lsq" => Ok(Method::Lsq),
            "both" => Ok(Method::Both),
            other => Err(format!("unknown method `{other}`: use gsa, lsq or both")),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    pub method: Method,
    pub gsa: GsaParams,
    pub bounds: BoundsChoice,
    /// Show a progress bar (the CLI sets it only on a terminal outside CI).
    pub progress: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            method: Method::Both,
            gsa: GsaParams::default(),
            bounds: BoundsChoice::Data,
            progress: false,
        }
    }
}

/// One solution and its performance index (RMSE, N).
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    pub coeffs: [f64; 5],
    pub rmse_n: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct GsaOutcome {
    pub solution: Solution,
    pub convergence_rmse_n: Vec<f64>,
    pub evaluations: usize,
    pub search_box: SearchBox,
}

/// One fitted branch.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchFit {
    pub current_a: f64,
    pub branch: Branch,
    pub samples: usize,
    pub x_min_mm: f64,
    pub x_max_mm: f64,
    /// What goes into the table: the lsq optimum when computed, else GSA's best.
    pub chosen: Solution,
    pub lsq: Option<Solution>,
    pub gsa: Option<GsaOutcome>,
}

impl BranchFit {
    /// GSA's RMSE over the least-squares RMSE (≥ 1; 1 = optimal), for `both`.
    pub fn gap_ratio(&self) -> Option<f64> {
        match (&self.lsq, &self.gsa) {
            (Some(l), Some(g)) if l.rmse_n > 0.0 => Some(g.solution.rmse_n / l.rmse_n),
            _ => None,
        }
    }
}

/// One ChaCha stream per branch, so results depend neither on rayon's
/// scheduling nor on which other branches are fitted (e.g. `--hold-out-current`).
pub fn branch_rng(seed: u64, stream: u64) -> rand_chacha::ChaCha8Rng {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// The stream of a (current, branch) pair: the current's bits, low bit = branch.
pub fn branch_stream(current_a: f64, branch: Branch) -> u64 {
    (current_a.to_bits() & !1)
        | match branch {
            Branch::Compression => 0,
            Branch::Extension => 1,
        }
}

/// Fits every branch in parallel (rayon).
pub fn fit_branches(problems: &[BranchProblem], options: &FitOptions) -> Result<Vec<BranchFit>> {
    let bar = if options.progress && options.method != Method::Lsq {
        let bar = indicatif::ProgressBar::new((problems.len() * options.gsa.iters) as u64);
        if let Ok(style) = indicatif::ProgressStyle::with_template("GSA {bar:40} {pos}/{len} iterations {elapsed}") {
            bar.set_style(style);
        }
        Some(bar)
    } else {
        None
    };
    let fits = problems
        .par_iter()
        .map(|p| fit_one(p, options, bar.as_ref()))
        .collect::<Result<Vec<_>>>();
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    fits
}

fn fit_one(p: &BranchProblem, options: &FitOptions, bar: Option<&indicatif::ProgressBar>) -> Result<BranchFit> {
    let what = || format!("{} A, {} branch", p.current_a, branch_name(p.branch));
    let x = &p.samples.x_mm;
    let f = &p.samples.force_n;
    let (x_min_mm, x_max_mm) = poly::min_max(x);
    let lsq = match options.method {
        Method::Lsq | Method::Both => {
            let q = lsq::fit_quartic(x, f).with_context(what)?;
            Some(Solution {
                coeffs: q.coeffs,
                rmse_n: q.rmse_n,
            })
        }
        Method::Gsa => None,
    };
    let gsa = match options.method {
        Method::Gsa | Method::Both => {
            let search_box = options.bounds.search_box(p.branch, x, f).with_context(what)?;
            let moments = BranchMoments::new(x, f);
            let mut rng = branch_rng(options.gsa.seed, branch_stream(p.current_a, p.branch));
            let r = gsa::minimize(
                |c| moments.rmse(c),
                &search_box,
                &options.gsa,
                &mut rng,
                || {
                    if let Some(b) = bar {
                        b.inc(1)
                    }
                },
            );
            Some(GsaOutcome {
                solution: Solution {
                    coeffs: r.best,
                    rmse_n: objective::rmse_by_samples(x, f, &r.best),
                },
                convergence_rmse_n: r.convergence,
                evaluations: r.evaluations,
                search_box,
            })
        }
        Method::Lsq => None,
    };
    let chosen = match (&lsq, &gsa) {
        (Some(l), _) => l.clone(),
        (None, Some(g)) => g.solution.clone(),
        (None, None) => anyhow::bail!("no method ran for {}", what()),
    };
    Ok(BranchFit {
        chosen,
        current_a: p.current_a,
        branch: p.branch,
        samples: p.samples.len(),
        x_min_mm,
        x_max_mm,
        lsq,
        gsa,
    })
}

pub fn branch_name(b: Branch) -> &'static str {
    match b {
        Branch::Compression => "compression",
        Branch::Extension => "extension",
    }
}

/// A Markdown table of every branch's fit; with `both`, GSA's gap to the optimum.
pub fn summary_markdown(fits: &[BranchFit]) -> String {
    let mut s = String::from(
        "| current (A) | branch | samples | lsq RMSE (N) | GSA RMSE (N) | GSA − lsq (N) | GSA / lsq |\n|---|---|---|---|---|---|---|\n",
    );
    let cell = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.3}"));
    for b in fits {
        let l = b.lsq.as_ref().map(|s| s.rmse_n);
        let g = b.gsa.as_ref().map(|g| g.solution.rmse_n);
        let diff = match (l, g) {
            (Some(l), Some(g)) => Some(g - l),
            _ => None,
        };
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} |\n",
            b.current_a,
            branch_name(b.branch),
            b.samples,
            cell(l),
            cell(g),
            cell(diff),
            b.gap_ratio().map_or("–".to_string(), |r| format!("{r:.4}"))
        ));
    }
    s
}

/// The outcome of `mre fit`.
#[derive(Clone, Debug, PartialEq)]
pub struct FitRun {
    pub fits: Vec<BranchFit>,
    pub model: model_file::ModelFile,
    /// Wall time of the fitting alone (not loading), seconds.
    pub fit_seconds: f64,
    /// What the readers assumed reading the recordings, in Markdown
    /// (`crate::dataset::summary`); empty when nothing.
    pub reading_notes: String,
}

/// Fits a loaded data set and assembles the model file (nothing written).
pub fn fit_dataset(ds: &crate::dataset::Dataset, options: &FitOptions) -> Result<FitRun> {
    let problems = problems::branch_problems(ds)?;
    let start = std::time::Instant::now();
    let fits = fit_branches(&problems, options)?;
    let fit_seconds = start.elapsed().as_secs_f64();
    let hash = crate::dataset::hash::input_sha256(ds)?;
    let velocity_estimated = ds.recordings.iter().any(|r| r.velocity_estimated);
    let model = model_file::build(&ds.name, &hash, velocity_estimated, &fits, options)?
        .with_installation(crate::installation::StatedInstallation::from_dataset(ds));
    Ok(FitRun {
        fits,
        model,
        fit_seconds,
        reading_notes: crate::dataset::summary::reading_notes_markdown(ds),
    })
}

/// `mre fit DATASET --out MODEL`: load, fit, write the model file atomically.
/// Recordings at a current in `hold_out_a` are made `validate` (not fitted).
pub fn run_fit(
    dataset_dir: &std::path::Path,
    options: &FitOptions,
    hold_out_a: &[f64],
    out: &std::path::Path,
) -> Result<FitRun> {
    run_fit_with_installation(dataset_dir, options, hold_out_a, &[], out)
}

/// [`run_fit`] with `--installation KEY=VALUE` options over what the data
/// set's metadata says (`crate::installation`); the model file's
/// `[installation]` is the result.
pub fn run_fit_with_installation(
    dataset_dir: &std::path::Path,
    options: &FitOptions,
    hold_out_a: &[f64],
    installation_options: &[String],
    out: &std::path::Path,
) -> Result<FitRun> {
    let mut ds = crate::dataset::Dataset::load(dataset_dir)?;
    problems::hold_out(&mut ds, hold_out_a);
    let stated = crate::installation::StatedInstallation::from_dataset(&ds).with_options(installation_options)?;
    let mut run = fit_dataset(&ds, options)?;
    run.model = run.model.with_installation(stated);
    run.model.model.held_out_current_a = crate::dataset::distinct_currents_a(hold_out_a.iter().copied());
    model_file::write(out, &run.model)?;
    Ok(run)
}
