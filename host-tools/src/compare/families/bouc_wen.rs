//! Bouc–Wen (Wen 1976), as used for MR dampers:
//!
//! F = c0·v + k0·x + α·z + f0,
//! dz/dx = (1 − z²·(β·sgn(ẋ·z) + γ)) / x_y   (exponent n = 2),
//!
//! with β + γ = 1 so z saturates at ±1 and α is the hysteretic force
//! amplitude (the classical A, β, γ have one redundant scale). The shape
//! parameter r = β − γ ∈ [−1, 1] sets how sharply the loop turns on
//! reversal. Per-current parameters, interpolated between currents.
use super::{all_finite, sign, Basis, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct BoucWen;

/// dz/dx·x_y for the n = 2 loop with β + γ = 1, shape r = β − γ.
#[inline]
pub fn shape_rate(z: f64, s: f64, r: f64) -> f64 {
    let beta = 0.5 * (1.0 + r);
    let gamma = 0.5 * (1.0 - r);
    let same = if s * z >= 0.0 { 1.0 } else { -1.0 };
    1.0 - z * z * (beta * same + gamma)
}

/// Sub-steps of the midpoint rule for a displacement step `dx`, so that one
/// sub-step moves z by a small fraction of its range (|dz/dx| ≤ 2/x_y).
#[inline]
pub fn substeps(dx_mm: f64, x_y_mm: f64) -> usize {
    ((dx_mm.abs() / x_y_mm * 8.0).ceil() as usize).clamp(1, 64)
}

/// z after moving by `dx` (midpoint rule on the displacement).
#[inline]
pub fn step(z: f64, dx_mm: f64, x_y_mm: f64, r: f64) -> f64 {
    let s = sign(dx_mm);
    if s == 0.0 {
        return z;
    }
    let m = substeps(dx_mm, x_y_mm);
    let h = dx_mm / m as f64 / x_y_mm;
    let mut z = z;
    for _ in 0..m {
        let mid = z + 0.5 * h * shape_rate(z, s, r);
        z += h * shape_rate(mid, s, r);
    }
    z
}

impl Family for BoucWen {
    fn name(&self) -> &'static str {
        "bouc-wen"
    }

    fn equations(&self) -> &'static str {
        "F = c0·v + k0·x + α·z + f0; dz/dx = (1 − z²(β·sgn(ẋz) + γ))/x_y, n = 2, β + γ = 1, r = β − γ"
    }

    fn nonlinear_names(&self) -> &'static [&'static str] {
        &["x_y_mm", "r"]
    }

    fn linear_names(&self) -> &'static [&'static str] {
        &["c0_n_s_m", "k0_n_mm", "alpha_n", "f0_n"]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::PerCurrent
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        (vec![0.0005 * s.x_mm, -1.0], vec![0.5 * s.x_mm, 1.0])
    }

    fn basis(&self, q: &[f64], track: &Track, b: &mut Basis) -> bool {
        let &[x_y, r] = q else { return false };
        if !(x_y > 0.0) || !(-1.0..=1.0).contains(&r) {
            return false;
        }
        b.reset(4);
        let mut z = 0.0;
        let mut x_prev = track.x_mm.first().copied().unwrap_or(0.0);
        for (&x, &v) in track.x_mm.iter().zip(&track.v_m_s) {
            z = step(z, x - x_prev, x_y, r);
            x_prev = x;
            for (c, value) in b.columns.iter_mut().zip([v, x, z, 1.0]) {
                c.push(value);
            }
        }
        all_finite(&b.columns[2])
    }

    fn step_cost(&self) -> StepCost {
        // Per sub-step: two rate evaluations (~8 flops each) + 4; force 6; sub-step count 1 div.
        StepCost {
            flops: 26,
            divides: 2,
            transcendentals: 0,
            substeps: 2,
            state_floats: 2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loading_branch_follows_tanh_closed_form() {
        // From z0 on a monotone ramp with z ≥ 0, dz/dx = (1 − z²)/x_y whatever r:
        // z(x) = tanh(x/x_y + atanh(z0)).
        let (x_y, z0) = (0.4, 0.1);
        let mut z = z0;
        let dx = 0.01;
        for k in 1..=200 {
            z = step(z, dx, x_y, 0.3);
            let want = (k as f64 * dx / x_y + f64::atanh(z0)).tanh();
            assert!((z - want).abs() < 1e-6, "at step {k}: {z} vs {want}");
        }
    }
}
