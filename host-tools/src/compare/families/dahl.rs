//! Dahl's friction model as used for MR dampers (Zhou, Wang, Zhu 2006):
//!
//! F = k0·x + c0·v + Fd·z + f0,  dz/dx = σ·(1 − sgn(ẋ)·z),
//!
//! z ∈ [−1, 1], σ (1/mm) the inverse transition length, stepped exactly
//! ([`super::exponential_step`]). σ is searched as log10 σ. Per-current
//! parameters, interpolated between currents.
use super::{all_finite, exponential_step, Basis, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct Dahl;

/// The log10 σ range (1/mm): transition lengths from 2·x_max down to x_max/2000.
pub fn log_sigma_range(s: &Scales) -> (f64, f64) {
    ((0.5 / s.x_mm).log10(), (2000.0 / s.x_mm).log10())
}

impl Family for Dahl {
    fn name(&self) -> &'static str {
        "dahl"
    }

    fn equations(&self) -> &'static str {
        "F = k0·x + c0·v + Fd·z + f0; dz/dx = σ(1 − sgn(ẋ)·z)"
    }

    fn nonlinear_names(&self) -> &'static [&'static str] {
        &["log10_sigma_per_mm"]
    }

    fn linear_names(&self) -> &'static [&'static str] {
        &["k0_n_mm", "c0_n_s_m", "fd_n", "f0_n"]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::PerCurrent
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        let (lo, hi) = log_sigma_range(s);
        (vec![lo], vec![hi])
    }

    fn basis(&self, q: &[f64], track: &Track, b: &mut Basis) -> bool {
        let &[log_sigma] = q else { return false };
        let sigma = 10f64.powf(log_sigma);
        b.reset(4, track.len());
        let mut z = 0.0;
        let mut x_prev = track.x_mm.first().copied().unwrap_or(0.0);
        for (&x, &v) in track.x_mm.iter().zip(&track.v_m_s) {
            z = exponential_step(z, x - x_prev, sigma);
            x_prev = x;
            b.push_row(&[x, v, z, 1.0]);
        }
        all_finite(&b.columns[2])
    }

    fn step_cost(&self) -> StepCost {
        // dx, |dx|, sign, exp argument, the update (3), the force (6).
        StepCost {
            flops: 14,
            divides: 0,
            transcendentals: 1,
            substeps: 1,
            state_floats: 2,
        }
    }
}
