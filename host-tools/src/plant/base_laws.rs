//! Base laws outside the paper's class, for shaker/MTS-style campaigns: an
//! elastic backbone plus a rate-independent hysteretic force with an internal
//! state z (Dahl or Bouc–Wen), optionally with true viscosity on top (a
//! Bingham-plastic MR damper: yield plus post-yield viscosity).
//!
//! z evolves with displacement, not time (`dz/dx`), so the loops are the same
//! at every speed: any rate dependence in the force comes from the explicit
//! viscous term alone.
use serde::Serialize;

/// The hysteretic state's evolution law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Hysteresis {
    /// `dz/d|x| = (sgn(ẋ) − z)/x_y`: exponential approach to ±1 over x_y.
    Dahl,
    /// Bouc–Wen with A = 1, n = 2, β = γ = ½:
    /// `dz/d|x| = (sgn(ẋ) − β·z|z| − γ·sgn(ẋ)·z²)/x_y`, a sharper knee than Dahl.
    BoucWen,
}

/// `F = G(I)·(k1·x + k3·x³ + f_y·z) + c(I)·v`, x in mm, v in m/s.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HystereticLaw {
    pub hysteresis: Hysteresis,
    pub k1_n_per_mm: f64,
    pub k3_n_per_mm3: f64,
    /// Yield (friction) force at 0 A (N).
    pub f_y_n: f64,
    /// Displacement over which the state switches (mm).
    pub x_y_mm: f64,
    /// Field gain per ampere: `G(I) = 1 + gain_per_a·I`.
    pub gain_per_a: f64,
    /// Post-yield viscosity at 0 A (N·s/m), scaled by G(I); 0 for none.
    pub viscous_n_s_per_m: f64,
}

impl HystereticLaw {
    /// A fixed MR-damper-like law for tests and examples: 150 N yield over
    /// 0.5 mm, 2 N/mm + 0.001 N/mm³ backbone, gain 1 + 5·I.
    pub fn example(hysteresis: Hysteresis, viscous_n_s_per_m: f64) -> Self {
        HystereticLaw {
            hysteresis,
            k1_n_per_mm: 2.0,
            k3_n_per_mm3: 0.001,
            f_y_n: 150.0,
            x_y_mm: 0.5,
            gain_per_a: 5.0,
            viscous_n_s_per_m,
        }
    }

    pub fn gain(&self, current_a: f64) -> f64 {
        1.0 + self.gain_per_a * current_a.max(0.0)
    }

    /// `dz/d|x|` (1/mm), the change per unit travel in direction `dir` (±1).
    fn dz_per_travel(&self, z: f64, dir: f64) -> f64 {
        match self.hysteresis {
            // Exponential approach to ±1 over x_y.
            Hysteresis::Dahl => (dir - z) / self.x_y_mm,
            // ż = ẋ − β|ẋ|·z|z| − γ·ẋ·z² (A = 1, n = 2, β = γ = ½), per |ẋ|.
            Hysteresis::BoucWen => (dir - 0.5 * z * z.abs() - 0.5 * dir * z * z) / self.x_y_mm,
        }
    }

    /// Advances z over the displacement step `dx_mm` (sub-stepped so each
    /// piece is at most x_y/20, midpoint rule), staying in [−1, 1].
    pub fn advance(&self, z: f64, dx_mm: f64) -> f64 {
        if dx_mm == 0.0 {
            return z;
        }
        let dir = dx_mm.signum();
        let pieces = ((dx_mm.abs() / (0.05 * self.x_y_mm)).ceil() as usize).max(1);
        let h = dx_mm.abs() / pieces as f64;
        let mut z = z;
        for _ in 0..pieces {
            let k1 = self.dz_per_travel(z, dir);
            let k2 = self.dz_per_travel(z + 0.5 * h * k1, dir);
            z = (z + h * k2).clamp(-1.0, 1.0);
        }
        z
    }

    /// The force (N) at state z.
    pub fn force_n(&self, x_mm: f64, v_m_s: f64, z: f64, current_a: f64) -> f64 {
        let g = self.gain(current_a);
        g * (self.k1_n_per_mm * x_mm + self.k3_n_per_mm3 * x_mm.powi(3) + self.f_y_n * z)
            + g * self.viscous_n_s_per_m * v_m_s
    }

    /// Forces along a displacement history, starting from z = 0 at x[0].
    pub fn forces_n(&self, x_mm: &[f64], v_m_s: &[f64], current_a: f64) -> Vec<f64> {
        let mut z = 0.0;
        let mut prev = x_mm.first().copied().unwrap_or(0.0);
        x_mm.iter()
            .zip(v_m_s)
            .map(|(&x, &v)| {
                z = self.advance(z, x - prev);
                prev = x;
                self.force_n(x, v, z, current_a)
            })
            .collect()
    }
}
