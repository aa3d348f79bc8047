//! Bouc–Wen (Wen 1976), as used for MR dampers:
//!
//! F = c0·v + k0·x + α·z + f0,
//! dz/dx = (1 − z²·(β·sgn(ẋ·z) + γ)) / x_y   (exponent n = 2),
//!
//! with β + γ = 1 so z saturates at ±1 and α is the hysteretic force
//! amplitude (the classical A, β, γ have one redundant scale). The shape
//! parameter r = β − γ ∈ [−1, 3] sets how sharply the loop turns on
//! reversal; x_y is searched as log10 x_y. Per-current parameters, interpolated between currents.
use super::{all_finite, sign, Basis, BatchObjective, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct BoucWen;

/// The shape r = β − γ may exceed 1 (γ < 0: the loop turns even faster on
/// reversal); β + γ = 1 keeps z bounded for any r ≥ −1.
pub const MAX_R: f64 = 3.0;

/// log10 x_y (mm): yield displacements from x_max/2000 to x_max/2, searched in
/// log so that small ones are as easy to reach as large ones.
pub fn log_x_y_range(s: &Scales) -> (f64, f64) {
    ((0.0005 * s.x_mm).log10(), (0.5 * s.x_mm).log10())
}

/// dz/dx·x_y for the n = 2 loop with β + γ = 1, shape r = β − γ.
#[inline]
pub fn shape_rate(z: f64, s: f64, r: f64) -> f64 {
    let beta = 0.5 * (1.0 + r);
    let gamma = 0.5 * (1.0 - r);
    let same = if s * z >= 0.0 { 1.0 } else { -1.0 };
    1.0 - z * z * (beta * same + gamma)
}

/// z after moving by `dx`, exactly. Mirrored so the motion is positive
/// (w = sgn(dx)·z, u = |dx|/x_y): while w < 0 (just after a reversal)
/// dw/du = 1 + r·w², solved by tan/tanh up to w = 0; from there dw/du = 1 − w²,
/// w = tanh(atanh(w) + u).
#[inline]
pub fn step(z: f64, dx_mm: f64, x_y_mm: f64, r: f64) -> f64 {
    let s = sign(dx_mm);
    if s == 0.0 {
        return z;
    }
    let mut w = s * z;
    let mut u = dx_mm.abs() / x_y_mm;
    if w < 0.0 {
        let (end, used) = towards_zero(w, u, r);
        if used >= u {
            return s * end;
        }
        w = 0.0;
        u -= used;
    }
    s * (w.atanh() + u).tanh()
}

/// [`step`] along a path, carrying a = atanh(w) while loading so a sample
/// in the same direction costs one tanh (tanh(atanh(tanh a) + u) = tanh(a + u)).
#[derive(Clone, Copy, Debug)]
pub struct Loop {
    pub z: f64,
    dir: f64,
    loading: bool,
    a: f64,
}

impl Default for Loop {
    fn default() -> Self {
        Loop {
            z: 0.0,
            dir: 0.0,
            loading: false,
            a: 0.0,
        }
    }
}

impl Loop {
    /// z after moving by `dx` (the same as [`step`]).
    #[inline]
    pub fn advance(&mut self, dx_mm: f64, x_y_mm: f64, r: f64) -> f64 {
        let s = sign(dx_mm);
        if s == 0.0 {
            return self.z;
        }
        let mut u = dx_mm.abs() / x_y_mm;
        if s == self.dir && self.loading {
            self.a += u;
            self.z = s * self.a.tanh();
            return self.z;
        }
        self.dir = s;
        let mut w = s * self.z;
        if w < 0.0 {
            let (end, used) = towards_zero(w, u, r);
            if used >= u {
                self.loading = false;
                self.z = s * end;
                return self.z;
            }
            w = 0.0;
            u -= used;
        }
        self.loading = true;
        self.a = w.atanh() + u;
        self.z = s * self.a.tanh();
        self.z
    }
}

/// From w < 0 along dw/du = 1 + r·w² for at most `u`: (w reached, u used);
/// stops at w = 0.
#[inline]
fn towards_zero(w: f64, u: f64, r: f64) -> (f64, f64) {
    let phase = unloading_phase(w, r);
    let need = -phase;
    if u >= need {
        (0.0, need)
    } else {
        (unloading_w(phase + u, r), u)
    }
}

/// |r| below this counts as r = 0 (dw/du = 1).
pub const FLAT: f64 = 1e-12;

/// The unloading branch dw/du = 1 + r·w² (w ≤ 0) in a variable that grows
/// like u: φ = atan(√r·w)/√r (r > 0), atanh(√|r|·w)/√|r| (r < 0; −∞ where
/// w = −1/√|r| stands still), w (r = 0). w reaches 0 at φ = 0.
#[inline]
pub fn unloading_phase(w: f64, r: f64) -> f64 {
    if r > FLAT {
        let q = r.sqrt();
        (q * w).atan() / q
    } else if r < -FLAT {
        let q = (-r).sqrt();
        (q * w).max(-1.0).atanh() / q
    } else {
        w
    }
}

/// w at phase φ ≤ 0 of [`unloading_phase`].
#[inline]
pub fn unloading_w(phase: f64, r: f64) -> f64 {
    if r > FLAT {
        let q = r.sqrt();
        (q * phase).tan() / q
    } else if r < -FLAT {
        let q = (-r).sqrt();
        (q * phase).tanh() / q
    } else {
        phase
    }
}

impl Family for BoucWen {
    fn name(&self) -> &'static str {
        "bouc-wen"
    }

    fn equations(&self) -> &'static str {
        "F = c0·v + k0·x + α·z + f0; dz/dx = (1 − z²(β·sgn(ẋz) + γ))/x_y, n = 2, β + γ = 1, r = β − γ"
    }

    fn nonlinear_names(&self) -> &'static [&'static str] {
        &["log10_x_y_mm", "r"]
    }

    fn linear_names(&self) -> &'static [&'static str] {
        &["c0_n_s_m", "k0_n_mm", "alpha_n", "f0_n"]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::PerCurrent
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        let (lo, hi) = log_x_y_range(s);
        (vec![lo, -1.0], vec![hi, MAX_R])
    }

    fn basis(&self, q: &[f64], track: &Track, b: &mut Basis) -> bool {
        let &[log_x_y, r] = q else { return false };
        let x_y = 10f64.powf(log_x_y);
        if x_y.is_nan() || x_y <= 0.0 || !(-1.0..=MAX_R).contains(&r) {
            return false;
        }
        b.reset(4, track.len());
        let mut hysteresis = Loop::default();
        let mut x_prev = track.x_mm.first().copied().unwrap_or(0.0);
        for (&x, &v) in track.x_mm.iter().zip(&track.v_m_s) {
            let z = hysteresis.advance(x - x_prev, x_y, r);
            x_prev = x;
            b.push_row(&[v, x, z, 1.0]);
        }
        all_finite(&b.columns[2])
    }

    fn step_cost(&self) -> StepCost {
        // Mirroring and branch logic ~10, the force 6; up to tan/atan and atanh/tanh
        // after a reversal (2 otherwise) and 2 divides.
        StepCost {
            flops: 16,
            divides: 2,
            transcendentals: 4,
            substeps: 1,
            state_floats: 2,
        }
    }

    fn batch_objective(&self, tracks: &[Track]) -> Option<Box<dyn BatchObjective>> {
        Some(Box::new(super::bouc_wen_batch::BoucWenBatch::new(tracks)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_step_agrees_with_a_fine_midpoint_integration() {
        // An independent integrator: the midpoint rule on dz/dx·x_y = shape_rate, 10⁵ steps.
        for (z0, dx, r) in [(-0.9, 1.3, 0.6), (0.4, -0.7, -0.5), (-0.2, 0.9, 0.0), (0.95, 0.4, 1.0)] {
            let x_y = 0.5;
            let (m, s) = (100_000, sign(dx));
            let h = dx / m as f64 / x_y;
            let mut z: f64 = z0;
            for _ in 0..m {
                let mid = z + 0.5 * h * shape_rate(z, s, r);
                z += h * shape_rate(mid, s, r);
            }
            let exact = step(z0, dx, x_y, r);
            assert!((exact - z).abs() < 1e-6, "z0 {z0}, dx {dx}, r {r}: {exact} vs {z}");
        }
    }

    #[test]
    fn carried_loop_matches_the_step_by_step_solution() {
        let (x_y, r) = (0.3, 0.7);
        let (mut z, mut path) = (0.0, Loop::default());
        for i in 0..3000 {
            let dx = 0.05 * (i as f64 * 0.013).cos() + if i % 97 == 0 { -0.2 } else { 0.0 };
            z = step(z, dx, x_y, r);
            assert!((path.advance(dx, x_y, r) - z).abs() < 1e-9, "sample {i}");
        }
    }

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
