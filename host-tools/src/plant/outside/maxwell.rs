//! The base law outside the Dahl/Bouc–Wen family: a stiffening elastic
//! backbone plus a generalized-Maxwell (Prony series) viscoelastic force whose
//! branches are log-spaced in relaxation time with moduli `∝ τ^{−α}`: the
//! Prony approximation of a fractional-derivative (Scott-Blair) element of
//! order α, a nearly constant loss over the tested decades. A fast branch
//! alone (τ ≪ the test periods) is a viscous damper: that is how
//! `viscous_damping` is generated, never as `c·v`.

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GeneralizedMaxwell {
    /// Backbone `k₁·x + k₃·x³` (N/mm, N/mm³), compression positive.
    pub k1_n_per_mm: f64,
    pub k3_n_per_mm3: f64,
    /// Prony branches: (modulus N/mm, relaxation time s).
    pub branches: Vec<(f64, f64)>,
}

impl GeneralizedMaxwell {
    /// `n` branches from `tau_min_s` to `tau_max_s` (log-spaced) with total
    /// modulus `k_total` shared `∝ τ^{−α}`.
    pub fn fractional(k1: f64, k3: f64, k_total: f64, alpha: f64, tau_min_s: f64, tau_max_s: f64, n: usize) -> Self {
        let taus: Vec<f64> = (0..n)
            .map(|i| tau_min_s * (tau_max_s / tau_min_s).powf(i as f64 / (n.max(2) - 1) as f64))
            .collect();
        let weights: Vec<f64> = taus.iter().map(|t| t.powf(-alpha)).collect();
        let sum: f64 = weights.iter().sum();
        GeneralizedMaxwell {
            k1_n_per_mm: k1,
            k3_n_per_mm3: k3,
            branches: taus
                .iter()
                .zip(&weights)
                .map(|(&t, &w)| (k_total * w / sum, t))
                .collect(),
        }
    }

    pub fn elastic_n(&self, x_mm: f64) -> f64 {
        self.k1_n_per_mm * x_mm + self.k3_n_per_mm3 * x_mm.powi(3)
    }

    /// Advances the branch forces `q` (N) over `dt_s` at constant velocity
    /// `v_mm_s` (exact for that: `q ← q·e^{−h/τ} + kτv·(1 − e^{−h/τ})`) and
    /// returns their sum.
    pub fn step_viscoelastic_n(&self, q: &mut [f64], v_mm_s: f64, dt_s: f64) -> f64 {
        let mut sum = 0.0;
        for (qi, &(k, tau)) in q.iter_mut().zip(&self.branches) {
            let e = (-dt_s / tau).exp();
            *qi = *qi * e + k * tau * v_mm_s * (1.0 - e);
            sum += *qi;
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_branch_at_constant_rate_approaches_k_tau_v() {
        // One branch, k = 50 N/mm, τ = 0.01 s, v = 20 mm/s: q(t) = kτv(1 − e^{−t/τ});
        // at t = τ: 10·(1 − 1/e) = 6.32121 N; long after: 10 N.
        let m = GeneralizedMaxwell {
            k1_n_per_mm: 0.0,
            k3_n_per_mm3: 0.0,
            branches: vec![(50.0, 0.01)],
        };
        let mut q = [0.0];
        let mut f = 0.0;
        for _ in 0..100 {
            f = m.step_viscoelastic_n(&mut q, 20.0, 1e-4);
        }
        assert!((f - 6.32121).abs() < 1e-4);
        for _ in 0..10_000 {
            f = m.step_viscoelastic_n(&mut q, 20.0, 1e-4);
        }
        assert!((f - 10.0).abs() < 1e-6);
    }

    #[test]
    fn fractional_weights_fall_as_tau_to_minus_alpha() {
        let m = GeneralizedMaxwell::fractional(1.0, 0.0, 100.0, 0.5, 1e-3, 1e-1, 3);
        // τ = 1e-3, 1e-2, 1e-1: weights 31.62, 10, 3.162 (sum 44.78).
        let k: Vec<f64> = m.branches.iter().map(|b| b.0).collect();
        assert!((k[0] - 100.0 * 31.6228 / 44.7851).abs() < 1e-3);
        assert!((k[0] / k[1] - 10f64.sqrt()).abs() < 1e-9);
        assert!((k.iter().sum::<f64>() - 100.0).abs() < 1e-9);
    }
}
