//! The nonlinear model families `mre compare` fits beside the paper's
//! polynomial. Each is integrated along a recording's measured x(t), v(t)
//! (stateful ones start from a relaxed state, z = 0, at the first sample).
//!
//! Units inside every family: x in mm, v in m/s, F in N, so stiffnesses are
//! N/mm and damping coefficients N·s/m. Hysteretic variables z are
//! dimensionless and saturate at ±1 (the Bouc–Wen scale redundancy is removed
//! by fixing β + γ = 1; see [`bouc_wen`]).
pub mod bouc_wen;
pub mod bouc_wen_batch;
pub mod dahl;
pub mod exponential;
pub mod kwok_tanh;
pub mod spencer;

use super::tracks::{max_abs, Track};

/// How a family depends on the coil current.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurrentLaw {
    /// One parameter set per fitted current; between currents each
    /// parameter is interpolated linearly (clamped outside the fitted range).
    PerCurrent,
    /// One parameter set for every current, with parameter laws in I inside
    /// the model (Spencer et al. 1997: α, c0, c1 linear in I).
    Joint,
}

/// Data scales the search boxes are built from (fit recordings only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    /// max |F| (N).
    pub force_n: f64,
    /// max |x| (mm).
    pub x_mm: f64,
    /// max |v| (m/s).
    pub v_m_s: f64,
    /// Largest fitted current (A), at least 1e-3.
    pub current_a: f64,
}

impl Scales {
    pub fn of<'a>(tracks: impl IntoIterator<Item = &'a Track>) -> Scales {
        let mut s = Scales {
            force_n: 1e-9,
            x_mm: 1e-9,
            v_m_s: 1e-9,
            current_a: 1e-3,
        };
        for t in tracks {
            s.force_n = s.force_n.max(max_abs(&t.force_n));
            s.x_mm = s.x_mm.max(max_abs(&t.x_mm));
            s.v_m_s = s.v_m_s.max(max_abs(&t.v_m_s));
            s.current_a = s.current_a.max(t.current_a.abs());
        }
        s
    }
}

/// What one model step costs on the board, counted from the family's
/// update and force equations (single precision).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StepCost {
    /// Multiplies, adds, compares and fused multiply–adds.
    pub flops: u32,
    pub divides: u32,
    /// exp / tanh calls.
    pub transcendentals: u32,
    /// Integration sub-steps per control period, typical at 10 kHz (1 if the update is exact).
    pub substeps: u32,
    /// f32 state carried from one sample to the next.
    pub state_floats: u32,
}

impl StepCost {
    /// Cycles on a Cortex-M4F: 1 per flop (FPU single-cycle add/mul, FMA
    /// 3 but pipelined), 14 per divide (VDIV.F32), ~60 per expf/tanhf (libm
    /// polynomial with range reduction), times the sub-steps.
    pub fn cortex_m4f_cycles(&self) -> u32 {
        (self.flops + 14 * self.divides + 60 * self.transcendentals) * self.substeps.max(1)
    }
}

/// The columns a family's force is linear in, for fixed nonlinear parameters:
/// F = offset + Σₖ θₖ·columns[k] (θ = the family's linear parameters).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Basis {
    pub columns: Vec<Vec<f64>>,
    /// A part of the force with no free coefficient (empty = none).
    pub offset: Vec<f64>,
}

impl Basis {
    /// Empties every column, keeping `k` of them with room for `n` samples
    /// (capacity reused; no reallocation while the rows are pushed).
    pub fn reset(&mut self, k: usize, n: usize) {
        self.columns.resize_with(k, Vec::new);
        for c in &mut self.columns {
            c.clear();
            c.reserve(n);
        }
        self.offset.clear();
    }

    /// Appends one sample's column values (in column order).
    #[inline]
    pub fn push_row(&mut self, values: &[f64]) {
        for (c, v) in self.columns.iter_mut().zip(values) {
            c.push(*v);
        }
    }

    /// The force for linear parameters `theta` into `out`.
    pub fn force(&self, theta: &[f64], out: &mut Vec<f64>) {
        let n = self.columns.first().map_or(self.offset.len(), Vec::len);
        out.clear();
        out.resize(n, 0.0);
        if !self.offset.is_empty() {
            out.copy_from_slice(&self.offset);
        }
        for (c, t) in self.columns.iter().zip(theta) {
            for (o, v) in out.iter_mut().zip(c) {
                *o += t * v;
            }
        }
    }
}

/// A model family, split the separable way: nonlinear parameters q (searched
/// by GSA and refined by LM) and linear ones θ (solved exactly by least
/// squares for every q; variable projection, Golub & Pereyra 1973).
pub trait Family: Sync + Send {
    /// Short name, used in file names and the report (`bouc-wen`, …).
    fn name(&self) -> &'static str;
    /// The equations, for the report.
    fn equations(&self) -> &'static str;
    fn nonlinear_names(&self) -> &'static [&'static str];
    fn linear_names(&self) -> &'static [&'static str];
    fn law(&self) -> CurrentLaw;
    /// Search box (lower, upper) of the nonlinear parameters.
    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>);
    /// The columns (and offset) along `track` for nonlinear parameters `q`.
    /// For [`CurrentLaw::PerCurrent`], `q` is the set at the track's current;
    /// for [`CurrentLaw::Joint`], the whole set. Returns false when `q` is not
    /// admissible (the basis is then unspecified).
    fn basis(&self, q: &[f64], track: &Track, basis: &mut Basis) -> bool;
    fn step_cost(&self) -> StepCost;

    /// An evaluator of J for many q at once over fixed `tracks` (GSA's hot
    /// path), if the family has one faster than projecting each q
    /// ([`crate::compare::fit::objective`]); it must return the same values.
    fn batch_objective(&self, _tracks: &[Track]) -> Option<Box<dyn BatchObjective>> {
        None
    }

    /// Every parameter name: nonlinear first, then linear.
    fn param_names(&self) -> Vec<&'static str> {
        self.nonlinear_names()
            .iter()
            .chain(self.linear_names())
            .copied()
            .collect()
    }

    /// Model force at every sample of `track` for the full parameter vector
    /// (nonlinear then linear) into `out`; false if not admissible.
    fn simulate(&self, p: &[f64], track: &Track, out: &mut Vec<f64>) -> bool {
        let nq = self.nonlinear_names().len();
        if p.len() != nq + self.linear_names().len() {
            return false;
        }
        let mut b = Basis::default();
        if !self.basis(&p[..nq], track, &mut b) {
            return false;
        }
        b.force(&p[nq..], out);
        all_finite(out)
    }
}

/// J for a batch of nonlinear parameter sets (∞ where one is not admissible).
pub trait BatchObjective: Sync + Send {
    fn evaluate(&self, qs: &[Vec<f64>]) -> Vec<f64>;
}

/// Every nonlinear family, in report order.
pub fn all() -> Vec<Box<dyn Family>> {
    vec![
        Box::new(bouc_wen::BoucWen),
        Box::new(spencer::Spencer),
        Box::new(dahl::Dahl),
        Box::new(kwok_tanh::KwokTanh),
        Box::new(exponential::Exponential),
    ]
}

/// Parameter sets per fitted current (ascending) → the set at `current_a`,
/// interpolated linearly between neighbours, clamped outside.
pub fn interpolate_sets(sets: &[(f64, Vec<f64>)], current_a: f64) -> Vec<f64> {
    match sets {
        [] => Vec::new(),
        [(_, only)] => only.clone(),
        _ => {
            let last = sets.len() - 1;
            if current_a <= sets[0].0 {
                return sets[0].1.clone();
            }
            if current_a >= sets[last].0 {
                return sets[last].1.clone();
            }
            let hi = sets.iter().position(|(c, _)| *c >= current_a).unwrap_or(last).max(1);
            let (c0, p0) = (&sets[hi - 1].0, &sets[hi - 1].1);
            let (c1, p1) = (&sets[hi].0, &sets[hi].1);
            let w = (current_a - c0) / (c1 - c0);
            p0.iter().zip(p1).map(|(a, b)| a + w * (b - a)).collect()
        }
    }
}

/// The sign of a displacement increment (0 stays 0).
#[inline]
pub(crate) fn sign(dx: f64) -> f64 {
    if dx > 0.0 {
        1.0
    } else if dx < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The exponential (Dahl) hysteresis operator over one displacement step:
/// dz/dx = σ·(1 − sgn(dx)·z) has the exact solution
/// z ← s + (z − s)·e^(−σ|dx|), s = sgn(dx).
#[inline]
pub fn exponential_step(z: f64, dx_mm: f64, sigma_per_mm: f64) -> f64 {
    let s = sign(dx_mm);
    if s == 0.0 {
        return z;
    }
    s + (z - s) * (-sigma_per_mm * dx_mm.abs()).exp()
}

/// Check every value is finite (a diverged integration is inadmissible).
pub(crate) fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_linear_between_and_clamped_outside() {
        let sets = vec![(0.0, vec![1.0, 10.0]), (1.0, vec![3.0, 20.0])];
        assert_eq!(interpolate_sets(&sets, 0.5), vec![2.0, 15.0]);
        assert_eq!(interpolate_sets(&sets, -1.0), vec![1.0, 10.0]);
        assert_eq!(interpolate_sets(&sets, 2.0), vec![3.0, 20.0]);
    }

    #[test]
    fn every_family_fits_the_projection_accumulators() {
        // `fit::project` accumulates the Gram matrix in fixed-size arrays.
        for f in all() {
            assert!(
                f.linear_names().len() <= crate::compare::fit::MAX_LINEAR,
                "{}",
                f.name()
            );
        }
    }

    #[test]
    fn exponential_step_composes_like_one_step() {
        // The exact solution: two half steps equal one whole step.
        let (z0, dx, sigma) = (-0.3, 0.8, 2.5);
        let once = exponential_step(z0, dx, sigma);
        let twice = exponential_step(exponential_step(z0, dx / 2.0, sigma), dx / 2.0, sigma);
        assert!((once - twice).abs() < 1e-14);
        // By hand: 1 + (−0.3 − 1)·e^(−2) .
        assert!((once - (1.0 - 1.3 * (-2.0f64).exp())).abs() < 1e-14);
    }
}
