//! A held-out RMSE ratio with its bootstrap interval over the same
//! recordings ([`HeldOutRatio`]), the figure reported for a named effect.
use super::acceptance::Thresholds;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A held-out RMSE ratio and its 95 % bootstrap interval, both computed over
/// the same recordings (every recording, each scored held out), so the
/// interval printed beside the ratio is the doubt about that ratio.
#[derive(Clone, Debug)]
pub struct HeldOutRatio {
    /// `sqrt(Σ sse_before / Σ sse_after)` over every recording.
    pub ratio: f64,
    /// Percentile bootstrap interval of the same ratio, resampling the same
    /// recordings ([`bootstrap_ratio_ci95`]).
    pub ci95: [f64; 2],
    /// Per recording: held-out SSE before and after.
    pub sse_before: Vec<f64>,
    pub sse_after: Vec<f64>,
}

impl HeldOutRatio {
    pub fn over_every_recording(sse_before: Vec<f64>, sse_after: Vec<f64>, th: &Thresholds) -> Self {
        let all: Vec<usize> = (0..sse_before.len()).collect();
        HeldOutRatio {
            ratio: (sse_before.iter().sum::<f64>() / sse_after.iter().sum::<f64>().max(1e-300)).sqrt(),
            ci95: bootstrap_ratio_ci95(&sse_before, &sse_after, &all, th),
            sse_before,
            sse_after,
        }
    }
}

/// 95 % percentile bootstrap interval of `sqrt(Σ sse_before / Σ sse_after)`
/// over the recordings `idx`, resampled with replacement.
pub fn bootstrap_ratio_ci95(sse_before: &[f64], sse_after: &[f64], idx: &[usize], th: &Thresholds) -> [f64; 2] {
    if idx.is_empty() || th.bootstrap_resamples == 0 {
        return [f64::NAN, f64::NAN];
    }
    let mut rng = ChaCha8Rng::seed_from_u64(th.seed);
    let mut ratios: Vec<f64> = (0..th.bootstrap_resamples)
        .map(|_| {
            let (mut b, mut a) = (0.0, 0.0);
            for _ in 0..idx.len() {
                let i = idx[rng.random_range(0..idx.len())];
                b += sse_before[i];
                a += sse_after[i];
            }
            (b / a.max(1e-300)).sqrt()
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    let pct = |p: f64| ratios[((p * (ratios.len() - 1) as f64).round() as usize).min(ratios.len() - 1)];
    [pct(0.025), pct(0.975)]
}
