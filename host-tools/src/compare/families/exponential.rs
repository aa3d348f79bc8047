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
use super::{all_finite, exponential_step, Basis, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct Exponential;

pub const LAYERS: usize = 3;

impl Family for Exponential {
    fn name(&self) -> &'static str {
        "exponential"
    }

    fn equations(&self) -> &'static str {
        "F = k0·x + c0·v + f0 + Σ_{j=1..3} a_j·z_j; dz_j/dx = σ_j(1 − sgn(ẋ)·z_j)"
    }

    fn nonlinear_names(&self) -> &'static [&'static str] {
        &["log10_sigma1_per_mm", "log10_sigma2_per_mm", "log10_sigma3_per_mm"]
    }

    fn linear_names(&self) -> &'static [&'static str] {
        &["k0_n_mm", "c0_n_s_m", "f0_n", "a1_n", "a2_n", "a3_n"]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::PerCurrent
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        let (lo, hi) = log_sigma_range(s);
        let third = (hi - lo) / LAYERS as f64;
        // Layer 1 is the fastest.
        let lower = (0..LAYERS).map(|j| hi - (j + 1) as f64 * third).collect();
        let upper = (0..LAYERS).map(|j| hi - j as f64 * third).collect();
        (lower, upper)
    }

    fn basis(&self, q: &[f64], track: &Track, b: &mut Basis) -> bool {
        let &[l1, l2, l3] = q else { return false };
        let sigma = [10f64.powf(l1), 10f64.powf(l2), 10f64.powf(l3)];
        b.reset(3 + LAYERS, track.len());
        let mut z = [0.0; LAYERS];
        let mut x_prev = track.x_mm.first().copied().unwrap_or(0.0);
        for (&x, &v) in track.x_mm.iter().zip(&track.v_m_s) {
            let dx = x - x_prev;
            x_prev = x;
            for (zj, s) in z.iter_mut().zip(sigma) {
                *zj = exponential_step(*zj, dx, s);
            }
            b.push_row(&[x, v, 1.0, z[0], z[1], z[2]]);
        }
        b.columns[3..].iter().all(|c| all_finite(c))
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
