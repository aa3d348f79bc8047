//! Kwok's hyperbolic-tangent model (Kwok, Ha, Nguyen, Li, Samali,
//! "A novel hysteretic model for magnetorheological fluid dampers", 2006):
//!
//! F = c·v + k·x + α·tanh(β·v + δ·sgn(x)) + f0,
//!
//! stateless (the hysteresis comes from the velocity and the sign of x).
//! β (s/m) is searched as log10 β. Per-current parameters, interpolated.
use super::{all_finite, sign, Basis, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct KwokTanh;

impl Family for KwokTanh {
    fn name(&self) -> &'static str {
        "kwok-tanh"
    }

    fn equations(&self) -> &'static str {
        "F = c·v + k·x + α·tanh(β·v + δ·sgn(x)) + f0"
    }

    fn nonlinear_names(&self) -> &'static [&'static str] {
        &["log10_beta_s_m", "delta"]
    }

    fn linear_names(&self) -> &'static [&'static str] {
        &["c_n_s_m", "k_n_mm", "alpha_n", "f0_n"]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::PerCurrent
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        let v = s.v_m_s;
        (vec![(0.5 / v).log10(), -2.0], vec![(2000.0 / v).log10(), 2.0])
    }

    fn basis(&self, q: &[f64], track: &Track, b: &mut Basis) -> bool {
        let &[log_beta, delta] = q else { return false };
        let beta = 10f64.powf(log_beta);
        b.reset(4, track.len());
        for (&x, &v) in track.x_mm.iter().zip(&track.v_m_s) {
            let z = (beta * v + delta * sign(x)).tanh();
            b.push_row(&[v, x, z, 1.0]);
        }
        all_finite(&b.columns[2])
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
