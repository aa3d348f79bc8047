//! `mre bench-diagnose --outside N`: the frozen rules on N campaigns per
//! vocabulary word from [`crate::plant::outside`] (physics written outside the
//! model class, never calling the estimator). Per effect: named (the concealed
//! effect among the findings), `inconclusive`, `none`, and a wrong effect
//! named; for `none` campaigns, the family-wise false-positive rate (any
//! effect other than `hysteresis_memory` named) with its Wilson interval.
use super::calibration::{wilson, Rate};
use crate::diagnose::prepared::FoldPlan;
use crate::diagnose::verdict::Verdict;
use crate::diagnose::{diagnose, DiagnoseOptions};
use crate::plant::outside::{case, VALIDATE_CURRENT_A};
use crate::vocabulary::Effect;
use anyhow::Result;
use serde::Serialize;

#[derive(Clone, Debug, Serialize)]
pub struct OutsideOutcome {
    pub seed: u64,
    pub truth: &'static str,
    pub found: Vec<&'static str>,
    pub verdict: &'static str,
    pub seconds: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct OutsideSummary {
    pub first_seed: u64,
    pub cases: Vec<OutsideOutcome>,
    pub false_positive: Rate,
}

/// Stratified folds (the random and drop tests carry no frequency tag) and
/// the middle current as validate.
pub fn options(rules: &DiagnoseOptions) -> DiagnoseOptions {
    DiagnoseOptions {
        folds: FoldPlan::Stratified { k: 5 },
        validate_currents_a: vec![VALIDATE_CURRENT_A],
        ..rules.clone()
    }
}

/// `per_effect` cases of every vocabulary word (or only of the words in
/// `only`, when it is not empty), seeds `first_seed…`. A case keeps its seed
/// whatever `only` holds, so a filtered run repeats cases of the full one.
pub fn run(
    per_effect: usize,
    first_seed: u64,
    only: &[String],
    rules: &DiagnoseOptions,
    mut progress: impl FnMut(&OutsideOutcome),
) -> Result<OutsideSummary> {
    for name in only {
        if !Effect::VOCABULARY.iter().any(|e| e.name() == name) {
            anyhow::bail!(
                "--only {name}: not a vocabulary word ({:?})",
                Effect::VOCABULARY.iter().map(|e| e.name()).collect::<Vec<_>>()
            );
        }
    }
    let opts = options(rules);
    let mut cases = Vec::new();
    for k in 0..per_effect as u64 {
        for effect in Effect::VOCABULARY {
            if !only.is_empty() && !only.iter().any(|n| n == effect.name()) {
                continue;
            }
            let seed = first_seed + k;
            let c = case(effect, seed)?;
            let start = std::time::Instant::now();
            let d = diagnose(&c.dataset, &opts)?;
            let out = OutsideOutcome {
                seed,
                truth: effect.name(),
                found: d.findings.iter().map(|f| f.effect.name()).collect(),
                verdict: d.verdict.verdict.name(),
                seconds: start.elapsed().as_secs_f64(),
            };
            progress(&out);
            cases.push(out);
        }
    }
    let none: Vec<&OutsideOutcome> = cases.iter().filter(|c| c.truth == Effect::None.name()).collect();
    let memory = Effect::HysteresisMemory.name();
    Ok(OutsideSummary {
        first_seed,
        false_positive: wilson(
            none.iter().filter(|c| c.found.iter().any(|n| *n != memory)).count(),
            none.len(),
        ),
        cases,
    })
}

/// One row per effect: named / inconclusive / none / wrong effect named.
pub fn format_summary(s: &OutsideSummary) -> String {
    let mut out = format!(
        "outside-class set, seeds {}… (plant::outside, frozen rules)\n\n| effect | cases | named | inconclusive | none | wrong effect named |\n|---|---|---|---|---|---|\n",
        s.first_seed
    );
    let memory = Effect::HysteresisMemory.name();
    for effect in Effect::VOCABULARY {
        let of: Vec<&OutsideOutcome> = s.cases.iter().filter(|c| c.truth == effect.name()).collect();
        let count = |f: &dyn Fn(&OutsideOutcome) -> bool| of.iter().filter(|c| f(c)).count();
        let named = count(&|c| c.found.contains(&effect.name()));
        let wrong = count(&|c| c.found.iter().any(|n| *n != effect.name() && *n != memory));
        let inconclusive = count(&|c| c.verdict == Verdict::Inconclusive.name());
        let none = count(&|c| c.verdict == Verdict::None.name());
        out += &format!(
            "| {} | {} | {} | {inconclusive} | {none} | {wrong} |\n",
            effect.name(),
            of.len(),
            if effect == Effect::None {
                "—".to_string()
            } else {
                named.to_string()
            }
        );
    }
    let r = &s.false_positive;
    out += &format!(
        "\nfalse positives (none cases with any effect but hysteresis_memory named, family-wise over all candidates): {}/{} (95 % Wilson upper {:.0} %)\n",
        r.k,
        r.n,
        100.0 * r.upper95
    );
    out
}
