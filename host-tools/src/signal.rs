//! Signal primitives shared by `fit` and `diagnose`: one white-noise
//! estimate and one differentiator, so both commands read a channel alike;
//! and the one branch rule both fit and score by (`fit` through
//! `dataset::split_branches`).
use mre_algorithm::model::Branch;

/// A sample's branch counts as ambiguous when its speed is within this many
/// standard deviations of the velocity noise (two-sided ≈ 95 %).
pub const BRANCH_AMBIGUITY_SIGMAS: f64 = 2.0;

/// |v| below this (m/s) leaves a recording's branch to chance: the paper's
/// model switches branch on the sign of v, and the two branches differ by the
/// whole hysteresis band, so the sample nearest v = 0 at a turn-around can
/// carry an error of thousands of newtons that says nothing about the model.
pub fn branch_band_m_s(v_m_s: &[f64]) -> f64 {
    BRANCH_AMBIGUITY_SIGMAS * white_noise_sd(v_m_s)
}

/// The branch of a sample at speed `v_m_s` (v > 0 compression, else
/// extension, as `Branch::from_velocity`), or `None` when |v| is below the
/// recording's `band_m_s` ([`branch_band_m_s`]) and the branch is chance.
pub fn clear_branch(v_m_s: f64, band_m_s: f64) -> Option<Branch> {
    match (v_m_s.abs() >= band_m_s, v_m_s > 0.0) {
        (false, _) => None,
        (true, true) => Some(Branch::Compression),
        (true, false) => Some(Branch::Extension),
    }
}

/// White-noise standard deviation of a channel sampled fast enough that its
/// signal is smooth: the second difference of white noise has σ·√6, that of a
/// smooth signal is small, and the median absolute value (scaled by 1.4826
/// for a Gaussian) ignores the few samples where the signal bends sharply.
pub fn white_noise_sd(y: &[f64]) -> f64 {
    let mut d2: Vec<f64> = y.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).abs()).collect();
    if d2.is_empty() {
        return 0.0;
    }
    let mid = d2.len() / 2;
    let (_, median, _) = d2.select_nth_unstable_by(mid, f64::total_cmp);
    1.4826 * *median / 6f64.sqrt()
}

/// Central difference of `y` over `t` (one-sided at the ends; 0 where time
/// does not advance).
pub fn differentiate(t: &[f64], y: &[f64]) -> Vec<f64> {
    let n = t.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            let dt = t[b] - t[a];
            if dt > 0.0 {
                (y[b] - y[a]) / dt
            } else {
                0.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_noise_on_a_line_is_its_sigma() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let n = Normal::new(0.0, 0.5).unwrap();
        let y: Vec<f64> = (0..20_000).map(|i| 0.01 * i as f64 + n.sample(&mut rng)).collect();
        let s = white_noise_sd(&y);
        assert!((s - 0.5).abs() < 0.03, "σ = {s}");
    }

    #[test]
    fn the_derivative_of_a_parabola_is_exact_inside() {
        let t: Vec<f64> = (0..10).map(|i| 0.1 * i as f64).collect();
        let y: Vec<f64> = t.iter().map(|t| t * t).collect();
        let d = differentiate(&t, &y);
        assert!((d[5] - 1.0).abs() < 1e-12);
    }
}
