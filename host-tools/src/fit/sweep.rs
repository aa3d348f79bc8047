//! `mre sweep`: the paper's Figs. 13 and 14, the performance index against
//! GSA iterations (agents fixed) and against agents (iterations fixed).
//!
//! Performance index per run: the mean over branches of GSA's RMSE divided by
//! the least-squares RMSE of that branch (1 = the optimum), plus the summed
//! GSA RMSE in N. Every run uses the same seed, so the curves differ only by N or T.
use super::gsa::GsaParams;
use super::problems::BranchProblem;
use super::{fit_branches, FitOptions, Method};
use anyhow::Result;
use serde::Serialize;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepPoint {
    pub agents: usize,
    pub iters: usize,
    /// Mean over branches of GSA RMSE / lsq RMSE.
    pub mean_gsa_over_lsq: f64,
    /// Σ over branches of GSA RMSE (N).
    pub total_gsa_rmse_n: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sweep {
    pub vs_iters: Vec<SweepPoint>,
    pub vs_agents: Vec<SweepPoint>,
}

/// Default grids (the paper's study spans up to 100 of each; we go past it).
pub const ITERS: [usize; 9] = [5, 10, 20, 40, 60, 80, 100, 150, 200];
pub const AGENTS: [usize; 9] = [5, 10, 20, 40, 60, 80, 100, 150, 200];

fn point(problems: &[BranchProblem], base: &FitOptions, agents: usize, iters: usize) -> Result<SweepPoint> {
    let options = FitOptions {
        method: Method::Both,
        gsa: GsaParams {
            agents,
            iters,
            ..base.gsa
        },
        bounds: base.bounds.clone(),
        progress: false,
    };
    let fits = fit_branches(problems, &options)?;
    let ratios: Vec<f64> = fits.iter().filter_map(|f| f.gap_ratio()).collect();
    Ok(SweepPoint {
        agents,
        iters,
        mean_gsa_over_lsq: ratios.iter().sum::<f64>() / ratios.len().max(1) as f64,
        total_gsa_rmse_n: fits
            .iter()
            .filter_map(|f| f.gsa.as_ref())
            .map(|g| g.solution.rmse_n)
            .sum(),
    })
}

/// Runs both sweeps around `base.gsa` (its N for the iteration sweep, its T for the agent sweep).
pub fn sweep(problems: &[BranchProblem], base: &FitOptions, iters: &[usize], agents: &[usize]) -> Result<Sweep> {
    Ok(Sweep {
        vs_iters: iters
            .iter()
            .map(|&t| point(problems, base, base.gsa.agents, t))
            .collect::<Result<_>>()?,
        vs_agents: agents
            .iter()
            .map(|&n| point(problems, base, n, base.gsa.iters))
            .collect::<Result<_>>()?,
    })
}

/// CSV: `study,agents,iters,mean_gsa_over_lsq,total_gsa_rmse_n`.
pub fn to_csv(s: &Sweep) -> String {
    let mut out = String::from("study,agents,iters,mean_gsa_over_lsq,total_gsa_rmse_n\n");
    for (study, pts) in [("iterations", &s.vs_iters), ("agents", &s.vs_agents)] {
        for p in pts {
            out.push_str(&format!(
                "{study},{},{},{},{}\n",
                p.agents, p.iters, p.mean_gsa_over_lsq, p.total_gsa_rmse_n
            ));
        }
    }
    out
}

/// `mre sweep DATASET --out DIR`: sweep.csv plus the two figures.
pub fn run_sweep(
    dataset_dir: &std::path::Path,
    base: &FitOptions,
    hold_out_a: &[f64],
    dir: &std::path::Path,
) -> Result<Sweep> {
    let mut ds = crate::dataset::Dataset::load(dataset_dir)?;
    super::problems::hold_out(&mut ds, hold_out_a);
    let problems = super::problems::branch_problems(&ds)?;
    let s = sweep(&problems, base, &ITERS, &AGENTS)?;
    let csv = to_csv(&s);
    crate::plot::sweep::render_sweep(&s, base, dir)?;
    crate::atomic_write::write_atomic(&dir.join("sweep.csv"), csv.as_bytes())?;
    Ok(s)
}
