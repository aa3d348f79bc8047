//! Kwok's hyperbolic-tangent model (Kwok, Ha, Nguyen, Li, Samali,
//! "A novel hysteretic model for magnetorheological fluid dampers", 2006):
//!
//! F = c·v + k·x + α·tanh(β·v + δ·sgn(x)) + f0,
//!
//! stateless (the hysteresis comes from the velocity and the sign of x).
//! β (s/m) is searched as log10 β. Per-current parameters, interpolated.
use super::{all_finite, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct KwokTanh;

/// The model force at one sample (parameters as in [`Family::param_names`]).
#[inline]
pub fn force(p: &[f64; 6], x_mm: f64, v_m_s: f64) -> f64 {
    let [c, k, alpha, log_beta, delta, f0] = *p;
    let sgn_x = if x_mm > 0.0 {
        1.0
    } else if x_mm < 0.0 {
        -1.0
    } else {
        0.0
    };
    c * v_m_s + k * x_mm + alpha * (10f64.powf(log_beta) * v_m_s + delta * sgn_x).tanh() + f0
}

impl Family for KwokTanh {
    fn name(&self) -> &'static str {
        "kwok-tanh"
    }

    fn equations(&self) -> &'static str {
        "F = c·v + k·x + α·tanh(β·v + δ·sgn(x)) + f0; per current, interpolated"
    }

    fn param_names(&self) -> &'static [&'static str] {
        &["c_n_s_m", "k_n_mm", "alpha_n", "log10_beta_s_m", "delta", "f0_n"]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::PerCurrent
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        let (f, x, v) = (s.force_n, s.x_mm, s.v_m_s);
        (
            vec![0.0, -f / x, 0.0, (0.5 / v).log10(), -2.0, -0.5 * f],
            vec![2.0 * f / v, 2.0 * f / x, 2.0 * f, (2000.0 / v).log10(), 2.0, 0.5 * f],
        )
    }

    fn simulate(&self, p: &[f64], track: &Track, out: &mut Vec<f64>) -> bool {
        let Ok(p) = <[f64; 6]>::try_from(p) else { return false };
        out.clear();
        out.extend(track.x_mm.iter().zip(&track.v_m_s).map(|(&x, &v)| force(&p, x, v)));
        all_finite(out)
    }

    fn step_cost(&self) -> StepCost {
        // β is stored linear on the board; sign, the tanh argument (3), the force (6).
        StepCost {
            flops: 11,
            divides: 0,
            transcendentals: 1,
            substeps: 1,
            state_floats: 0,
        }
    }
}
