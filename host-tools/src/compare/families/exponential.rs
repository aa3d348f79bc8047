//! An exponential-type hysteresis model in the spirit of the paper's Fig. 15
//! comparator (a multi-layer exponential-based Preisach model): three layers
//! of exponential hysterons, each the exact Dahl operator with its own rate,
//!
//! F = k0·x + c0·v + f0 + Σⱼ aⱼ·zⱼ,  dzⱼ/dx = σⱼ·(1 − sgn(ẋ)·zⱼ),  j = 1..3.
//!
//! A weighted sum of exponential play operators is a Preisach-type model with
//! an exponential kernel; the layers split the log10 σ range into thirds (fast,
//! middle, slow), which removes the permutation symmetry. Per-current
//! parameters, interpolated. (The paper does not print its comparator's
//! equations, so this is the family, not a copy of reference [23].)
use super::dahl::log_sigma_range;
use super::{all_finite, exponential_step, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct Exponential;

pub const LAYERS: usize = 3;

impl Family for Exponential {
    fn name(&self) -> &'static str {
        "exponential"
    }

    fn equations(&self) -> &'static str {
        "F = k0·x + c0·v + f0 + Σ_{j=1..3} a_j·z_j; dz_j/dx = σ_j(1 − sgn(ẋ)·z_j); per current, interpolated"
    }

    fn param_names(&self) -> &'static [&'static str] {
        &[
            "k0_n_mm",
            "c0_n_s_m",
            "f0_n",
            "a1_n",
            "a2_n",
            "a3_n",
            "log10_sigma1_per_mm",
            "log10_sigma2_per_mm",
            "log10_sigma3_per_mm",
        ]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::PerCurrent
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        let (f, x, v) = (s.force_n, s.x_mm, s.v_m_s);
        let (lo, hi) = log_sigma_range(s);
        let third = (hi - lo) / LAYERS as f64;
        let mut lower = vec![-f / x, 0.0, -0.5 * f, 0.0, 0.0, 0.0];
        let mut upper = vec![2.0 * f / x, 2.0 * f / v, 0.5 * f, 2.0 * f, 2.0 * f, 2.0 * f];
        for j in 0..LAYERS {
            // Layer 1 is the fastest.
            lower.push(hi - (j + 1) as f64 * third);
            upper.push(hi - j as f64 * third);
        }
        (lower, upper)
    }

    fn simulate(&self, p: &[f64], track: &Track, out: &mut Vec<f64>) -> bool {
        let &[k0, c0, f0, a1, a2, a3, l1, l2, l3] = p else { return false };
        let a = [a1, a2, a3];
        let sigma = [10f64.powf(l1), 10f64.powf(l2), 10f64.powf(l3)];
        out.clear();
        let mut z = [0.0; LAYERS];
        let mut x_prev = track.x_mm.first().copied().unwrap_or(0.0);
        for (&x, &v) in track.x_mm.iter().zip(&track.v_m_s) {
            let dx = x - x_prev;
            x_prev = x;
            let mut f = k0 * x + c0 * v + f0;
            for j in 0..LAYERS {
                z[j] = exponential_step(z[j], dx, sigma[j]);
                f += a[j] * z[j];
            }
            out.push(f);
        }
        all_finite(out)
    }

    fn step_cost(&self) -> StepCost {
        StepCost {
            flops: 6 + 3 * 7,
            divides: 0,
            transcendentals: 3,
            substeps: 1,
            state_floats: 4,
        }
    }
}
