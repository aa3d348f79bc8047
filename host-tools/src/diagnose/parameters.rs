//! Effect parameters with units and 95 % bootstrap intervals over recordings.
use super::candidates::Effect;
use super::design::{Designs, Layout, Solution, Terms};
use super::prepared::Prepared;
use super::terms::Value;
use anyhow::bail;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::collections::BTreeMap;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Param {
    pub value: f64,
    pub unit: String,
    /// 95 % bootstrap interval (resampling recordings).
    pub ci95: [f64; 2],
    /// Set by the search design rather than estimated (`ci95` is then `[value, value]`).
    pub fixed: bool,
}

/// `(name, value, unit)` of an effect's parameters in a fitted model.
pub fn extract(prep: &Prepared, effect: Effect, terms: &Terms, sol: &Solution) -> Vec<Value> {
    let layout = Layout::new(prep.currents_a.len(), terms);
    super::terms::of(effect).map_or_else(Vec::new, |t| t.parameters(prep, &layout, terms, sol))
}

fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((p * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)]
}

/// Parameters of `effect` in the final model, with bootstrap intervals:
/// linear ones by refitting on resampled fit recordings; the searched one
/// (τ, x_e, v0, n0, I_s, coil τ) by re-choosing, on resampled recordings, among the
/// variants scored when the effect was accepted (`variant_sse`).
pub fn with_intervals(
    prep: &Prepared,
    effect: Effect,
    terms: &Terms,
    sol: &Solution,
    variant_sse: &[(Terms, Vec<f64>)],
    resamples: usize,
    seed: u64,
) -> anyhow::Result<BTreeMap<String, Param>> {
    let point = extract(prep, effect, terms, sol);
    let designs = Designs::build(prep, terms);
    let fit = prep.fit_indices();
    // Each softening fit is a 1-D search of solves: fewer resamples keep it quick.
    let resamples_linear = if terms.softening.is_some() {
        resamples.div_ceil(4)
    } else {
        resamples
    };
    let boot: Vec<Option<Vec<Value>>> = (0..resamples_linear)
        .into_par_iter()
        .map(|b| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(b as u64));
            // Resampled within each current, so every resample keeps every
            // tabulated current (a missing one would zero its coefficients).
            let train: Vec<usize> = prep
                .currents_a
                .iter()
                .flat_map(|&c| {
                    let group: Vec<usize> = fit.iter().copied().filter(|&i| prep.recs[i].current_a == c).collect();
                    (0..group.len())
                        .map(|_| group[rng.random_range(0..group.len())])
                        .collect::<Vec<_>>()
                })
                .collect();
            designs
                .solve(prep, &train)
                .ok()
                .map(|s| extract(prep, effect, terms, &s))
        })
        .collect();
    let failed = boot.iter().filter(|b| b.is_none()).count();
    // A few singular resamples (a resample that left out every recording of
    // one branch at some current) are expected; more and the interval would
    // describe a different population: fail loudly instead.
    if resamples_linear > 0 && failed * 10 > resamples_linear {
        bail!(
            "{}: {failed} of {resamples_linear} bootstrap resamples could not be fitted; no interval",
            effect.name()
        );
    }
    let boot: Vec<Vec<Value>> = boot.into_iter().flatten().collect();
    // Searched parameter: which variant wins on resampled recordings.
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    // The recordings the searched value was chosen on: the fit recordings,
    // or the validate ones for a term judged on them (never both).
    let term = super::terms::of(effect);
    let pool = if prep.validate_evidence && term.is_some_and(|t| t.validate_only()) {
        prep.validate_indices()
    } else {
        fit.clone()
    };
    let m = pool.len().max(1);
    let searched: Vec<Terms> = if variant_sse.len() > 1 && !pool.is_empty() {
        (0..resamples.max(200))
            .map(|_| {
                let idx: Vec<usize> = (0..m).map(|_| pool[rng.random_range(0..m)]).collect();
                let best = variant_sse
                    .iter()
                    .min_by(|a, b| {
                        let s = |v: &Vec<f64>| idx.iter().map(|&i| v[i]).sum::<f64>();
                        s(&a.1).total_cmp(&s(&b.1))
                    })
                    .expect("non-empty");
                best.0
            })
            .collect()
    } else {
        Vec::new()
    };
    let mut out = BTreeMap::new();
    for (k, (name, value, unit)) in point.iter().enumerate() {
        let from_linear: Vec<f64> = boot.iter().filter_map(|p| p.get(k).map(|q| q.1)).collect();
        let from_search: Vec<f64> = searched
            .iter()
            .filter_map(|t| {
                extract(prep, effect, t, sol)
                    .into_iter()
                    .find(|q| &q.0 == name)
                    .map(|q| q.1)
            })
            .collect();
        let is_searched = term.is_some_and(|t| t.searched().contains(&name.as_str()));
        let mut samples = if is_searched { from_search } else { from_linear };
        // Set by design, not estimated (the stop's side; a searched value
        // with a single alternative): no interval, said so.
        let fixed =
            term.is_some_and(|t| t.set_by_design().contains(&name.as_str())) || (is_searched && variant_sse.len() <= 1);
        let ci95 = if fixed {
            [*value, *value]
        } else if samples.is_empty() && is_searched {
            // No resample chose a form with this parameter: the data do not
            // pin it, so the interval is the whole searched range.
            let all: Vec<f64> = variant_sse
                .iter()
                .filter_map(|(t, _)| extract(prep, effect, t, sol).into_iter().find(|q| &q.0 == name))
                .map(|q| q.1)
                .collect();
            [
                all.iter().copied().fold(*value, f64::min),
                all.iter().copied().fold(*value, f64::max),
            ]
        } else if samples.is_empty() {
            bail!("{}: no bootstrap resample gave `{name}`; no interval", effect.name());
        } else {
            [percentile(&mut samples, 0.025), percentile(&mut samples, 0.975)]
        };
        out.insert(
            name.clone(),
            Param {
                value: *value,
                unit: unit.clone(),
                ci95,
                fixed,
            },
        );
    }
    Ok(out)
}
