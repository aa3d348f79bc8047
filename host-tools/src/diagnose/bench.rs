//! `mre bench-diagnose`: blind cases from `mre synth --effect random` (base
//! law, noise and effect parameters all drawn from each case's seed), each
//! diagnosed without its key, then scored against the key.
use super::{diagnose, DiagnoseOptions};
use crate::plant::effects::EFFECT_NAMES;
use crate::plant::synth::synthesize;
use anyhow::Result;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

/// One blind case.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchCase {
    pub seed: u64,
    pub truth: String,
    /// Accepted effects, most important first.
    pub found: Vec<String>,
    /// `none` when nothing was accepted.
    pub top1: String,
    /// Held-out RMSE ratio of the true effect's term (1 when not found; absent for `none`).
    pub heldout_improvement: Option<f64>,
    /// First-round held-out ratio of every candidate tested.
    pub first_round: Vec<(String, f64)>,
    pub seconds: f64,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchSummary {
    pub cases: Vec<BenchCase>,
    /// truth → predicted top-1 → count.
    pub confusion: BTreeMap<String, BTreeMap<String, usize>>,
    pub top1_accuracy: f64,
    /// Share of `none` cases where any effect was reported.
    pub false_positive_rate_none: f64,
    /// Median held-out improvement of the true effect's term, per effect.
    pub median_improvement: BTreeMap<String, f64>,
    pub median_seconds: f64,
    /// Shaker/MTS cases from a rate-independent base law (Dahl or Bouc–Wen;
    /// `mre synth --campaign mts`), scored apart: `hysteresis_memory` is the
    /// base law's own structure there, and `viscous_damping` may be named
    /// only when it was concealed.
    pub mts_cases: Vec<BenchCase>,
    /// MTS cases without concealed viscosity in which `viscous_damping` was named.
    pub mts_viscous_invented: usize,
    /// MTS cases whose concealed effect was found (`none`: nothing but `hysteresis_memory`).
    pub mts_found: usize,
}

/// The seed of case `k` of a run.
pub fn case_seed(seed: u64, k: usize) -> u64 {
    seed.wrapping_mul(1_000_003).wrapping_add(k as u64)
}

pub fn run_case(seed: u64, opts: &DiagnoseOptions) -> Result<BenchCase> {
    let synth = synthesize("random", seed)?;
    let truth = synth.key["effect"].as_str().unwrap_or("none").to_string();
    let start = Instant::now();
    let d = diagnose(&synth.dataset, opts)?;
    let seconds = start.elapsed().as_secs_f64();
    let found: Vec<String> = d.findings.iter().map(|f| f.effect.name().to_string()).collect();
    let heldout_improvement = (truth != "none").then(|| {
        d.findings
            .iter()
            .find(|f| f.effect.name() == truth)
            .map_or(1.0, |f| f.heldout_improvement)
    });
    let first_round = d
        .selection
        .rounds
        .first()
        .map(|r| {
            r.tested
                .iter()
                .filter_map(|c| c.effect.map(|e| (e.name().to_string(), c.ratio)))
                .collect()
        })
        .unwrap_or_default();
    Ok(BenchCase {
        first_round,
        seed,
        truth,
        top1: found.first().cloned().unwrap_or_else(|| "none".into()),
        found,
        heldout_improvement,
        seconds,
    })
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Summarises cases into the confusion matrix and rates.
pub fn summarize(cases: Vec<BenchCase>) -> BenchSummary {
    let mut confusion: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    for c in &cases {
        *confusion
            .entry(c.truth.clone())
            .or_default()
            .entry(c.top1.clone())
            .or_default() += 1;
    }
    let correct = cases.iter().filter(|c| c.top1 == c.truth).count();
    let none: Vec<&BenchCase> = cases.iter().filter(|c| c.truth == "none").collect();
    let fp = none.iter().filter(|c| !c.found.is_empty()).count();
    let mut median_improvement = BTreeMap::new();
    for name in EFFECT_NAMES.iter().filter(|n| **n != "none") {
        let mut v: Vec<f64> = cases
            .iter()
            .filter(|c| c.truth == *name)
            .filter_map(|c| c.heldout_improvement)
            .collect();
        if !v.is_empty() {
            median_improvement.insert(name.to_string(), median(&mut v));
        }
    }
    let mut secs: Vec<f64> = cases.iter().map(|c| c.seconds).collect();
    BenchSummary {
        top1_accuracy: correct as f64 / cases.len().max(1) as f64,
        false_positive_rate_none: if none.is_empty() {
            0.0
        } else {
            fp as f64 / none.len() as f64
        },
        median_improvement,
        median_seconds: median(&mut secs),
        confusion,
        cases,
        mts_cases: Vec::new(),
        mts_viscous_invented: 0,
        mts_found: 0,
    }
}

/// One MTS case from a rate-independent base law: whole frequencies held
/// out, 0.5 A as the validate current.
pub fn run_mts_case(seed: u64) -> Result<BenchCase> {
    let synth = crate::plant::synth_mts::synthesize_mts("random", seed)?;
    let truth = synth.effect.name().to_string();
    let opts = super::options_from_cli(None, Some("frequency_hz".into()), 5, vec![0.5], 1)?;
    let start = Instant::now();
    let d = diagnose(&synth.dataset, &opts)?;
    let seconds = start.elapsed().as_secs_f64();
    let found: Vec<String> = d.findings.iter().map(|f| f.effect.name().to_string()).collect();
    let beyond_base: Vec<&String> = found.iter().filter(|n| *n != "hysteresis_memory").collect();
    Ok(BenchCase {
        seed,
        top1: beyond_base
            .first()
            .map_or_else(|| "none".to_string(), |n| n.to_string()),
        heldout_improvement: (truth != "none").then(|| {
            d.findings
                .iter()
                .find(|f| f.effect.name() == truth)
                .map_or(1.0, |f| f.heldout_improvement)
        }),
        first_round: Vec::new(),
        truth,
        found,
        seconds,
    })
}

/// Runs `n_cases` blind drop cases and `n_mts` MTS cases; `progress` is told
/// about each as it finishes.
pub fn run_bench(
    n_cases: usize,
    n_mts: usize,
    seed: u64,
    opts: &DiagnoseOptions,
    mut progress: impl FnMut(usize, &BenchCase),
) -> Result<BenchSummary> {
    let mut cases = Vec::with_capacity(n_cases);
    for k in 0..n_cases {
        let c = run_case(case_seed(seed, k), opts)?;
        progress(k, &c);
        cases.push(c);
    }
    let mut mts = Vec::with_capacity(n_mts);
    for k in 0..n_mts {
        let c = run_mts_case(case_seed(seed, n_cases + k))?;
        progress(n_cases + k, &c);
        mts.push(c);
    }
    let mut s = summarize(cases);
    s.mts_viscous_invented = mts
        .iter()
        .filter(|c| c.truth != "viscous_damping" && c.found.iter().any(|n| n == "viscous_damping"))
        .count();
    s.mts_found = mts.iter().filter(|c| c.top1 == c.truth).count();
    s.mts_cases = mts;
    Ok(s)
}

/// The printed summary: confusion matrix, accuracy, false positives, improvements.
pub fn format_summary(s: &BenchSummary) -> String {
    let mut out = String::new();
    let mut labels: Vec<String> = EFFECT_NAMES.iter().map(|n| n.to_string()).collect();
    for c in &s.cases {
        for l in c.found.iter().chain([&c.top1]) {
            if !labels.contains(l) {
                labels.push(l.clone());
            }
        }
    }
    let _ = writeln!(out, "confusion matrix (rows: true effect, columns: top-1 diagnosis)");
    let _ = write!(out, "{:>20}", "");
    for l in &labels {
        let _ = write!(out, " {:>8.8}", l);
    }
    let _ = writeln!(out);
    for t in &labels {
        let Some(row) = s.confusion.get(t) else { continue };
        let _ = write!(out, "{t:>20}");
        for l in &labels {
            let _ = write!(out, " {:>8}", row.get(l).copied().unwrap_or(0));
        }
        let _ = writeln!(out);
    }
    let correct = s.cases.iter().filter(|c| c.top1 == c.truth).count();
    let _ = writeln!(
        out,
        "top-1 accuracy: {:.1} % ({correct}/{})",
        100.0 * s.top1_accuracy,
        s.cases.len()
    );
    let n_none = s.cases.iter().filter(|c| c.truth == "none").count();
    let _ = writeln!(
        out,
        "false-positive rate on none: {:.1} % (of {n_none} cases)",
        100.0 * s.false_positive_rate_none
    );
    let _ = writeln!(out, "median held-out RMSE improvement of the true effect's term:");
    for (e, m) in &s.median_improvement {
        let n = s.cases.iter().filter(|c| &c.truth == e).count();
        let _ = writeln!(out, "  {e:<20} {m:.2}× (n = {n})");
    }
    let _ = writeln!(out, "median diagnosis time per case: {:.2} s", s.median_seconds);
    if !s.mts_cases.is_empty() {
        let n = s.mts_cases.len();
        let _ = writeln!(
            out,
            "MTS campaigns, rate-independent base law (Dahl / Bouc–Wen): top-1 beyond hysteresis_memory \
             {}/{n}; viscous_damping named without concealed viscosity in {} of {} cases",
            s.mts_found,
            s.mts_viscous_invented,
            s.mts_cases.iter().filter(|c| c.truth != "viscous_damping").count()
        );
        for c in &s.mts_cases {
            let _ = writeln!(out, "  seed {}: truth {:<16} found {:?}", c.seed, c.truth, c.found);
        }
    }
    out
}
