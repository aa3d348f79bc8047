//! Effect parameters with units and 95 % bootstrap intervals over recordings.
use super::candidates::Effect;
use super::design::{Designs, Layout, Solution, Span, Terms};
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
    /// Held at its physical bound (0) by the term's sign constraint
    /// ([`super::terms::Term::nonnegative`]): its least-squares value had the
    /// wrong sign.
    pub at_bound: bool,
}

/// `(name, value, unit)` of an effect's parameters in a fitted model.
pub fn extract(prep: &Prepared, effect: Effect, terms: &Terms, sol: &Solution) -> Vec<Value> {
    let layout = Layout::new(prep.currents_a.len(), terms);
    super::terms::of(effect).map_or_else(Vec::new, |t| t.parameters(prep, &layout, terms, sol))
}

/// A variant's parameter names and its searched and design values (the
/// linear ones read as 0): each variant has its own layout, so the final
/// model's solution cannot be read through it.
fn values_of_variant(prep: &Prepared, effect: Effect, terms: &Terms) -> Vec<Value> {
    let layout = Layout::new(prep.currents_a.len(), terms);
    let zero = Solution {
        beta: vec![0.0; layout.n_cols],
        delta: 0.0,
        sse: 0.0,
        span: Span::unbounded(prep.currents_a.len()),
        at_bound: Vec::new(),
    };
    super::terms::of(effect).map_or_else(Vec::new, |t| t.parameters(prep, &layout, terms, &zero))
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
    let resamples_linear = if terms.solved_scalars() > 0 {
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
    // Searched parameter: which variant wins on resampled recordings, then
    // refined between its neighbours (below), so an interval is not pinned
    // to the grid.
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    // The recordings the searched value was chosen on: the fit recordings,
    // or the validate ones for a term judged on them (never both).
    let term = super::terms::of(effect);
    let pool = if let Some(t) = term.filter(|t| t.validate_only()) {
        super::validate_terms::deciding(prep, t)
    } else {
        fit.clone()
    };
    let m = pool.len().max(1);
    // Each resample's SSE of every variant.
    let resampled_sse: Vec<Vec<f64>> = if variant_sse.len() > 1 && !pool.is_empty() {
        (0..resamples.max(200))
            .map(|_| {
                let idx: Vec<usize> = (0..m).map(|_| pool[rng.random_range(0..m)]).collect();
                variant_sse
                    .iter()
                    .map(|(_, v)| idx.iter().map(|&i| v[i]).sum::<f64>())
                    .collect()
            })
            .collect()
    } else {
        Vec::new()
    };
    let variant_values: Vec<Vec<Value>> = variant_sse
        .iter()
        .map(|(t, _)| values_of_variant(prep, effect, t))
        .collect();
    let keyed: Vec<&'static str> = term.map_or(Vec::new(), |t| {
        t.searched().iter().chain(t.set_by_design()).copied().collect()
    });
    let held: Vec<usize> = {
        let layout = Layout::new(prep.currents_a.len(), terms);
        // A block's columns run to the next block's first.
        let ends: Vec<usize> = layout
            .blocks
            .iter()
            .skip(1)
            .map(|p| p.at)
            .chain([layout.n_cols])
            .collect();
        layout
            .blocks
            .iter()
            .zip(ends)
            .filter(|(p, _)| p.term.effect() == effect)
            .flat_map(|(p, end)| sol.at_bound.iter().copied().filter(move |&c| c >= p.at && c < end))
            .collect()
    };
    let mut out = BTreeMap::new();
    for (k, (name, value, unit)) in point.iter().enumerate() {
        let from_linear: Vec<f64> = boot.iter().filter_map(|p| p.get(k).map(|q| q.1)).collect();
        let from_search: Vec<f64> = resampled_sse
            .iter()
            .filter_map(|sse| refined_optimum(name, &keyed, &variant_values, sse))
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
                .filter_map(|(t, _)| values_of_variant(prep, effect, t).into_iter().find(|q| &q.0 == name))
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
                at_bound: *value == 0.0 && !is_searched && !fixed && !held.is_empty(),
            },
        );
    }
    Ok(out)
}

/// The value of parameter `name` that minimises one resample's SSE: the best
/// variant's, refined by the vertex of the parabola through it and its two
/// neighbours along `name` (the variants whose other searched and design
/// values, `keyed`, are the same). `None` when the best variant has no such
/// parameter. At an end of the searched range, or where the three points do
/// not bend upwards, the best variant's own value. Variants whose SSEs tie
/// to rounding are one fit: the first listed wins, as in every choice of
/// the search (`cv::first_best`), so an interval does not hang on rounding.
pub fn refined_optimum(name: &str, keyed: &[&str], values: &[Vec<Value>], sse: &[f64]) -> Option<f64> {
    let all: Vec<usize> = (0..sse.len()).collect();
    let best = super::cv::first_best(&all, |v| sse[v])?;
    let get = |v: usize, n: &str| values[v].iter().find(|q| q.0 == n).map(|q| q.1);
    let p_b = get(best, name)?;
    let same_line = |v: usize| {
        keyed
            .iter()
            .filter(|k| **k != name)
            .all(|k| get(v, k).map(f64::to_bits) == get(best, k).map(f64::to_bits))
    };
    let mut lower: Option<(f64, f64)> = None;
    let mut upper: Option<(f64, f64)> = None;
    for v in (0..sse.len()).filter(|&v| v != best && same_line(v)) {
        let Some(p) = get(v, name) else { continue };
        if p < p_b && lower.is_none_or(|l| p > l.0) {
            lower = Some((p, sse[v]));
        } else if p > p_b && upper.is_none_or(|u| p < u.0) {
            upper = Some((p, sse[v]));
        }
    }
    let (Some((p_l, s_l)), Some((p_u, s_u))) = (lower, upper) else {
        return Some(p_b);
    };
    Some(parabola_vertex((p_l, s_l), (p_b, sse[best]), (p_u, s_u)).unwrap_or(p_b))
}

/// The abscissa of the minimum of the parabola through three points with
/// `l.0 < b.0 < u.0`, when it bends upwards; clamped to `[l.0, u.0]`.
pub fn parabola_vertex(l: (f64, f64), b: (f64, f64), u: (f64, f64)) -> Option<f64> {
    let (dl, du) = (b.0 - l.0, b.0 - u.0);
    let (fl, fu) = (b.1 - u.1, b.1 - l.1);
    let num = dl * dl * fl - du * du * fu;
    let den = dl * fl - du * fu;
    // Upward curvature: the slope rises from [l, b] to [b, u].
    let curvature = (u.1 - b.1) / (u.0 - b.0) - (b.1 - l.1) / (b.0 - l.0);
    if curvature.is_nan() || curvature <= 0.0 || den == 0.0 || !num.is_finite() {
        return None;
    }
    Some((b.0 - 0.5 * num / den).clamp(l.0, u.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vertex_of_a_sampled_parabola_is_found_between_unequal_steps() {
        // f(p) = 3·(p − 0.37)² + 5 at 0, 0.5, 2 (exact for a parabola).
        let f = |p: f64| 3.0 * (p - 0.37) * (p - 0.37) + 5.0;
        let v = parabola_vertex((0.0, f(0.0)), (0.5, f(0.5)), (2.0, f(2.0))).unwrap();
        assert!((v - 0.37).abs() < 1e-12, "{v}");
        // A concave triple has no minimum between its points.
        assert!(parabola_vertex((0.0, 1.0), (1.0, 2.0), (2.0, 1.0)).is_none());
    }

    #[test]
    fn a_resample_optimum_moves_only_along_its_own_parameter() {
        let vals = |tau: f64, side: f64| {
            vec![
                ("tau_s".to_string(), tau, "s".to_string()),
                ("side".to_string(), side, "1".to_string()),
            ]
        };
        // Two lines (side 0 and 1); the best is on side 0 at 2, its
        // neighbours 1 and 3 on the same side; side 1's value at 2.5 must
        // not be taken as a neighbour.
        let values = vec![vals(1.0, 0.0), vals(2.0, 0.0), vals(3.0, 0.0), vals(2.5, 1.0)];
        let f = |p: f64| (p - 2.2) * (p - 2.2);
        let sse = vec![f(1.0), f(2.0), f(3.0), 10.0];
        let p = refined_optimum("tau_s", &["tau_s", "side"], &values, &sse).unwrap();
        assert!((p - 2.2).abs() < 1e-12, "{p}");
        // At the end of the searched range the best value stands.
        let sse = vec![0.0, 1.0, 4.0, 10.0];
        assert_eq!(refined_optimum("tau_s", &["tau_s", "side"], &values, &sse), Some(1.0));
    }

    /// Hand-written: two variants (a linear and a saturating form that the
    /// sign constraint made one model) whose SSEs differ by rounding only,
    /// 1e-15 relative, the later listed the smaller. They are one fit, so
    /// the first listed stands, as in the search; a plain argmin takes the
    /// later one's value.
    #[test]
    fn a_tie_to_rounding_keeps_the_first_listed_variant() {
        let values = vec![
            vec![("v0_m_s".to_string(), 0.05, "m/s".to_string())],
            vec![("v0_m_s".to_string(), 0.4, "m/s".to_string())],
        ];
        let sse = vec![100.0, 100.0 * (1.0 - 1e-15)];
        assert_eq!(refined_optimum("v0_m_s", &["v0_m_s"], &values, &sse), Some(0.05));
        // A real difference still decides.
        let sse = vec![100.0, 99.0];
        assert_eq!(refined_optimum("v0_m_s", &["v0_m_s"], &values, &sse), Some(0.4));
    }
}
