//! Where a candidate acts, and whether it helps there.
//!
//! A candidate's signature often lives in a small part of the data (the
//! stroke extremes for an end stop, the fast tests for a delay, the
//! intermediate currents for saturation), so its held-out RMSE ratio over the
//! whole data set is diluted by every sample it does not touch. Its *support*
//! is the samples where its held-out prediction differs from the current
//! model's by more than the force noise and more than the RMS of that change:
//! both predictions come from fits without the sample's recording (a fit
//! recording's fold, or the full fit for a validate recording), so no
//! held-out sample chooses where it is scored.
//!
//! On the support: the held-out RMSE ratio, the recordings (units) whose
//! support improves, and a paired test of the squared-error differences
//! whose sample count is corrected for autocorrelation (AR(1): n·(1 − ρ)/(1 + ρ)
//! per recording).
use super::select::Scored;

/// A recording counts as a unit of the support with at least this many support samples.
pub const MIN_UNIT_SAMPLES: usize = 10;
/// The support needs the change to exceed this multiple of the force noise.
pub const NOISE_SIGMAS: f64 = 2.0;

/// One recording's share of the support comparison.
#[derive(Clone, Copy, Debug, Default)]
pub struct LocalRec {
    /// Held-out SSE before and after over the recording's support samples.
    pub sse_before: f64,
    pub sse_after: f64,
    pub n: usize,
    /// Sum of the paired squared-error differences (before − after), and
    /// their variance times the sample count, inflated by (1 + ρ)/(1 − ρ).
    pub sum_d: f64,
    pub var_sum: f64,
}

/// Per recording of the decision pool, the support comparison (`None`
/// outside the pool), with the change that defines the support.
#[derive(Clone, Debug, Default)]
pub struct LocalStats {
    pub recs: Vec<Option<LocalRec>>,
    /// The change (N) above which a sample is on the support.
    pub threshold_n: f64,
    /// Samples both models score in the pool.
    pub n_common: usize,
}

/// A candidate judged on its support.
#[derive(Clone, Copy, Debug, Default)]
pub struct Local {
    /// Held-out RMSE ratio before/after on the support.
    pub ratio: f64,
    /// Support samples over the samples both models score in the pool.
    pub share: f64,
    /// Recordings with support (≥ [`MIN_UNIT_SAMPLES`]) whose support SSE
    /// fell, of `n_units`.
    pub units_improved: usize,
    pub n_units: usize,
    /// Paired z of the squared-error differences, autocorrelation-corrected.
    pub z: f64,
}

impl LocalStats {
    /// The comparison over the pool without the recordings `excluded`.
    pub fn summary(&self, excluded: &[usize]) -> Local {
        let (mut sb, mut sa, mut n) = (0.0, 0.0, 0usize);
        let (mut sum_d, mut var_sum) = (0.0, 0.0);
        let (mut units_improved, mut n_units) = (0, 0);
        for (i, r) in self.recs.iter().enumerate() {
            let Some(r) = r.filter(|_| !excluded.contains(&i)) else { continue };
            sb += r.sse_before;
            sa += r.sse_after;
            n += r.n;
            sum_d += r.sum_d;
            var_sum += r.var_sum;
            if r.n >= MIN_UNIT_SAMPLES {
                n_units += 1;
                units_improved += usize::from(r.sse_after < r.sse_before);
            }
        }
        Local {
            ratio: if n == 0 { 1.0 } else { (sb / sa.max(1e-300)).sqrt() },
            share: n as f64 / self.n_common.max(1) as f64,
            units_improved,
            n_units,
            z: if var_sum > 0.0 { sum_d / var_sum.sqrt() } else { 0.0 },
        }
    }
}

/// [`LocalStats`] for `after` against `before` over the recordings `pool`.
/// The support reads only the two models' held-out predictions, never the
/// recorded force.
pub fn local(before: &Scored, after: &Scored, pool: &[usize], noise_n: f64) -> LocalStats {
    // The samples both models score.
    let common = |i: usize| {
        before.mask[i]
            .iter()
            .zip(&after.mask[i])
            .map(|(a, b)| *a && *b)
            .collect::<Vec<bool>>()
    };
    let masks: Vec<(usize, Vec<bool>)> = pool.iter().map(|&i| (i, common(i))).collect();
    let change = |i: usize, t: usize| after.heldout_pred[i][t] - before.heldout_pred[i][t];
    let (mut s2, mut n_common) = (0.0, 0usize);
    for (i, m) in &masks {
        for t in (0..m.len()).filter(|&t| m[t]) {
            s2 += change(*i, t).powi(2);
            n_common += 1;
        }
    }
    let threshold_n = (NOISE_SIGMAS * noise_n).max((s2 / n_common.max(1) as f64).sqrt());
    let mut recs = vec![None; before.mask.len()];
    for (i, m) in &masks {
        let on: Vec<usize> = (0..m.len())
            .filter(|&t| m[t] && change(*i, t).abs() > threshold_n)
            .collect();
        let d: Vec<f64> = on
            .iter()
            .map(|&t| before.heldout_se[*i][t] - after.heldout_se[*i][t])
            .collect();
        let mut r = LocalRec {
            sse_before: on.iter().map(|&t| before.heldout_se[*i][t]).sum(),
            sse_after: on.iter().map(|&t| after.heldout_se[*i][t]).sum(),
            n: d.len(),
            sum_d: 0.0,
            var_sum: 0.0,
        };
        if d.len() >= 2 {
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (d.len() - 1) as f64;
            let rho = lag1(&d, mean).clamp(0.0, 0.999);
            r.sum_d = d.iter().sum::<f64>();
            r.var_sum = d.len() as f64 * var * (1.0 + rho) / (1.0 - rho);
        }
        recs[*i] = Some(r);
    }
    LocalStats {
        recs,
        threshold_n,
        n_common,
    }
}

/// Lag-1 autocorrelation of `d` about `mean` (consecutive support samples).
fn lag1(d: &[f64], mean: f64) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for k in 0..d.len() {
        let e = d[k] - mean;
        den += e * e;
        if k > 0 {
            num += e * (d[k - 1] - mean);
        }
    }
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}
