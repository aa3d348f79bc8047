//! Signal primitives shared by `fit` and `diagnose`: one white-noise
//! estimate and one differentiator, so both commands read a channel alike.

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
