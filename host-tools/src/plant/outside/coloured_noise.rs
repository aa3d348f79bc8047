//! Coloured measurement noise: a first-order autoregressive process
//! `n_k = φ·n_{k−1} + σ·√(1 − φ²)·e_k`, stationary SD σ and lag-1
//! autocorrelation φ, seeded. The estimator's noise gates assume white noise.
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ColouredNoise {
    pub sd: f64,
    /// Lag-1 autocorrelation φ in [0, 1).
    pub phi: f64,
}

impl ColouredNoise {
    pub fn draw(&self, n: usize, rng: &mut impl Rng) -> Vec<f64> {
        let innovation = self.sd * (1.0 - self.phi * self.phi).sqrt();
        let mut prev: f64 = StandardNormal.sample(rng);
        prev *= self.sd;
        (0..n)
            .map(|_| {
                let e: f64 = StandardNormal.sample(rng);
                prev = self.phi * prev + innovation * e;
                prev
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn sd_and_lag1_correlation_are_as_specified() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let n = ColouredNoise { sd: 2.0, phi: 0.8 }.draw(400_000, &mut rng);
        let var = n.iter().map(|v| v * v).sum::<f64>() / n.len() as f64;
        let lag1 = n.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / (n.len() - 1) as f64 / var;
        // Standard errors at this length: SD ≈ 2·√((1+φ²)/(1−φ²)/(2N)) ≈ 0.0049,
        // lag-1 ≈ √((1−φ²)/N) ≈ 0.001; the bounds are ~4 of them.
        assert!((var.sqrt() - 2.0).abs() < 0.02, "sd {}", var.sqrt());
        assert!((lag1 - 0.8).abs() < 0.005, "lag1 {lag1}");
    }
}
