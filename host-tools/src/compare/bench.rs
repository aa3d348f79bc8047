//! `mre bench-compare`: the Bouc–Wen GSA stage of `mre compare` timed on its
//! own, and the exact objective exported for the Python peers
//! (`bench/compare_gsa.py`: niapy's GSA and SciPy's differential evolution
//! at the same number of evaluations).
//!
//! The objective is the one `mre compare` searches: the fit recordings at one
//! current, each decimated to about `samples_per_track` samples, Bouc–Wen's
//! nonlinear parameters (x_y, r) with the linear ones solved by least squares.
use super::families::{bouc_wen::BoucWen, Family, Scales};
use super::fit::{refine, search};
use super::tracks::{tracks, Track};
use crate::atomic_write::{write_atomic, write_atomic_with};
use crate::dataset::{Dataset, Role};
use crate::fit::gsa::GsaParams;
use anyhow::{bail, Result};
use serde::Serialize;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// LM patience of the benchmark's refinement (as `mre compare`'s default budget).
const LM_PATIENCE: usize = 30;

#[derive(Clone, Debug, Serialize)]
pub struct BenchOutcome {
    pub current_a: f64,
    pub recordings: usize,
    pub samples: usize,
    pub agents: usize,
    pub iters: usize,
    pub evaluations: usize,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    pub seed: u64,
    pub threads: usize,
    /// Wall time of each repeat (s) and their median: GSA alone.
    pub seconds: Vec<f64>,
    pub median_s: f64,
    pub best_objective: f64,
    pub best_q: Vec<f64>,
    /// GSA then Levenberg–Marquardt from its best (the fit `mre compare` runs):
    /// evaluations charged (n + 1 per LM iteration, an upper bound), median
    /// time, final objective and point.
    pub refined_evaluations: usize,
    pub refined_median_s: f64,
    pub refined_objective: f64,
    pub refined_q: Vec<f64>,
}

/// The decimated fit tracks at `current_a` (held-out currents excluded).
pub fn objective_tracks(ds: &Dataset, hold_out_a: &[f64], current_a: f64, samples_per_track: usize) -> Vec<Track> {
    tracks(ds, hold_out_a)
        .into_iter()
        .filter(|t| t.role == Role::Fit && (t.current_a - current_a).abs() < 1e-9)
        .map(|t| t.at_most(samples_per_track))
        .collect()
}

/// Times `repeats` GSA runs and writes `objective.csv` + `bench.json` into `out`.
pub fn run_bench(
    dataset_dir: &Path,
    current_a: f64,
    gsa: GsaParams,
    samples_per_track: usize,
    repeats: usize,
    out: &Path,
) -> Result<BenchOutcome> {
    let ds = Dataset::load(dataset_dir)?;
    let data = objective_tracks(&ds, &[0.5], current_a, samples_per_track);
    if data.is_empty() {
        bail!("no fit recordings at {current_a} A");
    }
    let family = BoucWen;
    let (lower, upper) = family.bounds(&Scales::of(&data));
    let (mut seconds, mut refined_s) = (Vec::new(), Vec::new());
    let mut best = (f64::INFINITY, Vec::new(), 0);
    let mut refined = (f64::INFINITY, Vec::new(), 0);
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let r = search(&family, &data, &lower, &upper, &gsa, gsa.seed, 0);
        seconds.push(start.elapsed().as_secs_f64());
        let (q, value, lm_evals) = refine(&family, &r.best, &lower, &upper, &data, LM_PATIENCE);
        refined_s.push(start.elapsed().as_secs_f64());
        refined = (value, q, r.evaluations + lm_evals);
        best = (r.best_value, r.best, r.evaluations);
    }
    let median = |v: &[f64]| {
        let mut sorted = v.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted[sorted.len() / 2]
    };
    let outcome = BenchOutcome {
        current_a,
        recordings: data.len(),
        samples: data.iter().map(Track::len).sum(),
        agents: gsa.agents,
        iters: gsa.iters,
        evaluations: best.2,
        lower,
        upper,
        seed: gsa.seed,
        threads: rayon::current_num_threads(),
        median_s: median(&seconds),
        seconds,
        best_objective: best.0,
        best_q: best.1,
        refined_evaluations: refined.2,
        refined_median_s: median(&refined_s),
        refined_objective: refined.0,
        refined_q: refined.1,
    };
    write_atomic_with(&out.join("objective.csv"), |w| {
        writeln!(w, "track,time_s,x_mm,v_m_s,force_n,force_scale_n")?;
        for (k, t) in data.iter().enumerate() {
            for i in 0..t.len() {
                writeln!(
                    w,
                    "{k},{},{},{},{},{}",
                    t.time_s[i], t.x_mm[i], t.v_m_s[i], t.force_n[i], t.force_scale_n
                )?;
            }
        }
        Ok(())
    })?;
    write_atomic(
        &out.join("bench.json"),
        serde_json::to_string_pretty(&outcome)?.as_bytes(),
    )?;
    Ok(outcome)
}
