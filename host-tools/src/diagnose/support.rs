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
use super::cv::Scored;
use super::prepared::scored_by_both;

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
            let Some(r) = r.filter(|_| !excluded.contains(&i)) else {
                continue;
            };
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
    fn side(s: &Scored) -> Side<'_> {
        Side {
            pred: &s.heldout_pred,
            se: &s.heldout_se,
            mask: &s.mask,
        }
    }
    local_from(side(before), side(after), pool, noise_n)
}

/// One model's held-out predictions, squared errors and scored samples, per recording.
#[derive(Clone, Copy)]
pub struct Side<'a> {
    pub pred: &'a [Vec<f64>],
    pub se: &'a [Vec<f64>],
    pub mask: &'a [Vec<bool>],
}

/// [`local`] on plain per-recording channels.
pub fn local_from(before: Side, after: Side, pool: &[usize], noise_n: f64) -> LocalStats {
    // The samples both models score.
    let common = |i: usize| scored_by_both(&before.mask[i], &after.mask[i]);
    let masks: Vec<(usize, Vec<bool>)> = pool.iter().map(|&i| (i, common(i))).collect();
    let change = |i: usize, t: usize| after.pred[i][t] - before.pred[i][t];
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
        let d: Vec<f64> = on.iter().map(|&t| before.se[*i][t] - after.se[*i][t]).collect();
        let mut r = LocalRec {
            sse_before: on.iter().map(|&t| before.se[*i][t]).sum(),
            sse_after: on.iter().map(|&t| after.se[*i][t]).sum(),
            n: d.len(),
            sum_d: 0.0,
            var_sum: 0.0,
        };
        if d.len() >= 2 {
            let sum_d: f64 = d.iter().sum();
            let mean = sum_d / d.len() as f64;
            let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (d.len() - 1) as f64;
            let rho = lag1(&d, mean).clamp(0.0, 0.999);
            r.sum_d = sum_d;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_support_is_where_the_prediction_changes_and_only_there_is_scored() {
        // One recording, six samples; the candidate changes the prediction
        // by 10 N on samples 2 and 3 only (RMS change √(200/6) = 5.77 N,
        // above 2 × 1 N noise, so the threshold is 5.77 N).
        let f = [0.0, 0.0, 10.0, 10.0, 0.0, 0.0];
        let pred_b = vec![vec![1.0, -1.0, 0.0, 0.0, 1.0, -1.0]];
        let pred_a = vec![vec![1.0, -1.0, 10.0, 10.0, 1.0, -1.0]];
        let se = |p: &[f64]| -> Vec<f64> { p.iter().zip(&f).map(|(p, f)| (p - f) * (p - f)).collect() };
        let (se_b, se_a) = (vec![se(&pred_b[0])], vec![se(&pred_a[0])]);
        let mask = vec![vec![true; 6]];
        let b = Side {
            pred: &pred_b,
            se: &se_b,
            mask: &mask,
        };
        let a = Side {
            pred: &pred_a,
            se: &se_a,
            mask: &mask,
        };
        let st = local_from(b, a, &[0], 1.0);
        assert!((st.threshold_n - (200.0f64 / 6.0).sqrt()).abs() < 1e-12);
        let r = st.recs[0].expect("in the pool");
        // Support = samples 2, 3: SSE before 100 + 100, after 0.
        assert_eq!(r.n, 2);
        assert_eq!((r.sse_before, r.sse_after), (200.0, 0.0));
        let l = st.summary(&[]);
        assert!(l.ratio > 1e100, "every support error removed");
        assert!((l.share - 2.0 / 6.0).abs() < 1e-12);
        // Two support samples are fewer than a unit needs.
        assert_eq!((l.units_improved, l.n_units), (0, 0));
        // Whole-recording ratio would be √(204/4) = 7.1: the ±1 N errors
        // elsewhere are untouched and do not dilute the support's.
        assert!(st.summary(&[0]).n_units == 0 && st.summary(&[0]).ratio == 1.0);
    }

    #[test]
    fn lag1_autocorrelation_by_hand() {
        // Values 2 and 0 about their mean 1 (deviations ±1), n = 40.
        // Blocks of ten: 36 neighbour pairs agree, 3 disagree → ρ = 33/40.
        // Alternating: all 39 pairs disagree → ρ = −39/40.
        let blocks: Vec<f64> = (0..40).map(|k| if (k / 10) % 2 == 0 { 2.0 } else { 0.0 }).collect();
        let alternating: Vec<f64> = (0..40).map(|k| if k % 2 == 0 { 2.0 } else { 0.0 }).collect();
        assert!((lag1(&blocks, 1.0) - 33.0 / 40.0).abs() < 1e-12);
        assert!((lag1(&alternating, 1.0) + 39.0 / 40.0).abs() < 1e-12);
    }
}
