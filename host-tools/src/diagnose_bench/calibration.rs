//! `mre bench-diagnose --calibration N`: the frozen rules on campaigns whose
//! base law and effects are not the candidates' formulas
//! ([`crate::plant::calibration`]), none of them used to set a rule. Reports
//! the false-positive rate (a `none` campaign with any effect named: a
//! family-wise rate over every candidate and route) and the top-1 rate (the
//! first effect named after `hysteresis_memory` is the concealed one), each
//! with a 95 % Wilson score interval.
use crate::diagnose::prepared::FoldPlan;
use crate::diagnose::{diagnose, DiagnoseOptions};
use crate::plant::calibration::{case, VALIDATE_CURRENT_A};
use crate::vocabulary::Effect;
use anyhow::Result;
use serde::Serialize;

/// One case's outcome.
#[derive(Clone, Debug, Serialize)]
pub struct CalibrationOutcome {
    pub seed: u64,
    pub truth: &'static str,
    /// The effect's RMS change to the force over the RMS force (fit recordings).
    pub strength: f64,
    /// What was named, in order (`hysteresis_memory` included).
    pub found: Vec<&'static str>,
    /// Each accepted vocabulary effect: the route that accepted it, its
    /// held-out ratio over the decision pool and the units that improved
    /// (what a false positive passed on).
    pub accepted_by: Vec<String>,
    /// A `none` case with any effect other than `hysteresis_memory` named.
    pub false_positive: bool,
    /// An effect case whose first non-memory finding is the concealed one.
    pub top1: bool,
    /// An effect case with an effect named that is not the concealed one.
    pub wrong_name: bool,
    pub seconds: f64,
}

/// A proportion with its 95 % Wilson score interval.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Rate {
    pub k: usize,
    pub n: usize,
    pub lower95: f64,
    pub upper95: f64,
}

/// Wilson's score interval at z = 1.96 (two-sided 95 %):
/// `(p̂ + z²/2n ± z·√(p̂(1−p̂)/n + z²/4n²)) / (1 + z²/n)`.
pub fn wilson(k: usize, n: usize) -> Rate {
    if n == 0 {
        return Rate {
            k,
            n,
            lower95: 0.0,
            upper95: 1.0,
        };
    }
    let z = 1.959_963_984_540_054;
    let (nf, p) = (n as f64, k as f64 / n as f64);
    let centre = p + z * z / (2.0 * nf);
    let half = z * (p * (1.0 - p) / nf + z * z / (4.0 * nf * nf)).sqrt();
    let d = 1.0 + z * z / nf;
    Rate {
        k,
        n,
        lower95: ((centre - half) / d).max(0.0),
        upper95: ((centre + half) / d).min(1.0),
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct CalibrationSummary {
    pub first_seed: u64,
    pub cases: Vec<CalibrationOutcome>,
    pub false_positive: Rate,
    pub top1: Rate,
    pub wrong_name: Rate,
}

/// The options every case runs under: the frozen rules, one fold per
/// frequency, the middle current as validate.
pub fn options(rules: &DiagnoseOptions) -> DiagnoseOptions {
    DiagnoseOptions {
        folds: FoldPlan::ByTag("frequency_hz".into()),
        validate_currents_a: vec![VALIDATE_CURRENT_A],
        ..rules.clone()
    }
}

pub fn run(
    n_cases: usize,
    first_seed: u64,
    rules: &DiagnoseOptions,
    mut progress: impl FnMut(&CalibrationOutcome),
) -> Result<CalibrationSummary> {
    let opts = options(rules);
    let mut cases = Vec::with_capacity(n_cases);
    for k in 0..n_cases as u64 {
        let seed = first_seed + k;
        let c = case(seed)?;
        let start = std::time::Instant::now();
        let d = diagnose(&c.dataset, &opts)?;
        let found: Vec<&'static str> = d.findings.iter().map(|f| f.effect.name()).collect();
        let named: Vec<&'static str> = found
            .iter()
            .copied()
            .filter(|n| *n != Effect::HysteresisMemory.name())
            .collect();
        let accepted_by = d
            .selection
            .candidates
            .iter()
            .filter(|c| c.named)
            .map(|c| {
                format!(
                    "{} (inclusion {:.2}, nested {:.3}×)",
                    c.effect.name(),
                    c.inclusion,
                    c.gain.ratio
                )
            })
            .collect();
        let truth = c.effect.kind().name();
        let is_none = c.effect.kind() == Effect::None;
        let out = CalibrationOutcome {
            seed,
            truth,
            strength: c.strength,
            false_positive: is_none && !named.is_empty(),
            top1: !is_none && named.first() == Some(&truth),
            wrong_name: !is_none && named.iter().any(|n| *n != truth),
            found,
            accepted_by,
            seconds: start.elapsed().as_secs_f64(),
        };
        progress(&out);
        cases.push(out);
    }
    let none: Vec<&CalibrationOutcome> = cases.iter().filter(|c| c.truth == Effect::None.name()).collect();
    let effect: Vec<&CalibrationOutcome> = cases.iter().filter(|c| c.truth != Effect::None.name()).collect();
    Ok(CalibrationSummary {
        first_seed,
        false_positive: wilson(none.iter().filter(|c| c.false_positive).count(), none.len()),
        top1: wilson(effect.iter().filter(|c| c.top1).count(), effect.len()),
        wrong_name: wilson(effect.iter().filter(|c| c.wrong_name).count(), effect.len()),
        cases,
    })
}

pub fn format_summary(s: &CalibrationSummary) -> String {
    let line = |what: &str, r: &Rate| {
        format!(
            "{what}: {}/{} = {:.0} % (95 % Wilson {:.0}–{:.0} %)\n",
            r.k,
            r.n,
            100.0 * r.k as f64 / r.n.max(1) as f64,
            100.0 * r.lower95,
            100.0 * r.upper95
        )
    };
    let mut out = format!(
        "calibration set, seeds {}–{} (off-model effects, frozen rules)\n",
        s.first_seed,
        s.first_seed + s.cases.len() as u64 - 1
    );
    out += &line(
        "false positives (none cases with any effect named, family-wise over all candidates and routes)",
        &s.false_positive,
    );
    out += &line("top-1 (effect cases, first named effect is the concealed one)", &s.top1);
    out += &line("effect cases naming a wrong effect", &s.wrong_name);
    for e in ["viscous_damping", "sensor_delay", "end_stop", "inertia"] {
        let of: Vec<&CalibrationOutcome> = s.cases.iter().filter(|c| c.truth == e).collect();
        out += &format!("  {e}: top-1 {}/{}\n", of.iter().filter(|c| c.top1).count(), of.len());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_matches_a_textbook_value() {
        // k = 0, n = 20: upper = z²/n / (1 + z²/n) = 3.8415/23.8415 = 0.1611.
        let r = wilson(0, 20);
        assert!((r.upper95 - 0.1611).abs() < 1e-3 && r.lower95 == 0.0, "{r:?}");
        // k = 10, n = 20: 0.5 ± 1.96·√(0.0125 + 0.0024)/1.192 → 0.299–0.701.
        let r = wilson(10, 20);
        assert!(
            (r.lower95 - 0.299).abs() < 1e-3 && (r.upper95 - 0.701).abs() < 1e-3,
            "{r:?}"
        );
    }
}
