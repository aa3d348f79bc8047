//! The performance index the fit minimises: the **root-mean-square error**
//! (N) between the recorded force and the branch quartic over that branch's
//! samples, `J(a) = √( Σᵢ (Fᵢ − p_a(xᵢ))² / n )`.
//!
//! `p_a` is linear in its coefficients, so the sum of squares is a quadratic
//! form in them: `SSE(c) = cᵀMc − 2bᵀc + Σ F²` with `M = ΦᵀΦ`, `b = ΦᵀF`
//! (Φ = the 5 monomials of each sample). [`BranchMoments`] precomputes M, b and
//! ΣF² once, so one evaluation costs ~60 flops whatever the number of samples.
//! The moments are taken in u = (x − centre)/scale ∈ [−1, 1] so M stays well
//! conditioned; raw coefficients are mapped to u first.
//! [`rmse_by_samples`] is the direct sample-by-sample sum, for comparison.
use super::poly::{eval, Scaling};

#[derive(Clone, Debug, PartialEq)]
pub struct BranchMoments {
    pub scaling: Scaling,
    pub n: usize,
    /// M[j][k] = Σ u^(4−j)·u^(4−k) (highest power first, like the coefficients).
    m: [[f64; 5]; 5],
    b: [f64; 5],
    sum_f2: f64,
    /// Raw → u coefficients is linear: c = T·a, precomputed.
    to_scaled: [[f64; 5]; 5],
}

impl BranchMoments {
    pub fn new(x_mm: &[f64], force_n: &[f64]) -> BranchMoments {
        let scaling = Scaling::for_samples(x_mm);
        let mut m = [[0.0; 5]; 5];
        let mut b = [0.0; 5];
        let mut sum_f2 = 0.0;
        for (&x, &f) in x_mm.iter().zip(force_n) {
            let u = scaling.u(x);
            let u2 = u * u;
            let phi = [u2 * u2, u2 * u, u2, u, 1.0];
            for j in 0..5 {
                for k in j..5 {
                    m[j][k] += phi[j] * phi[k];
                }
                b[j] += phi[j] * f;
            }
            sum_f2 += f * f;
        }
        // Mirror the upper triangle.
        #[allow(clippy::needless_range_loop)]
        for j in 0..5 {
            for k in 0..j {
                m[j][k] = m[k][j];
            }
        }
        let mut to_scaled = [[0.0; 5]; 5];
        for col in 0..5 {
            let mut unit = [0.0; 5];
            unit[col] = 1.0;
            let image = scaling.raw_to_scaled(&unit);
            for row in 0..5 {
                to_scaled[row][col] = image[row];
            }
        }
        BranchMoments {
            to_scaled,
            scaling,
            n: x_mm.len().min(force_n.len()),
            m,
            b,
            sum_f2,
        }
    }

    /// Sum of squared errors for raw coefficients (highest first, x in mm).
    #[inline]
    pub fn sse(&self, raw: &[f64; 5]) -> f64 {
        let mut c = [0.0; 5];
        for (ci, row) in c.iter_mut().zip(&self.to_scaled) {
            *ci = row.iter().zip(raw).map(|(t, a)| t * a).sum();
        }
        let mut quad = 0.0;
        let mut lin = 0.0;
        for j in 0..5 {
            let row: f64 = (0..5).map(|k| self.m[j][k] * c[k]).sum();
            quad += c[j] * row;
            lin += self.b[j] * c[j];
        }
        // Rounding can push an exact fit a hair below zero.
        (quad - 2.0 * lin + self.sum_f2).max(0.0)
    }

    /// The performance index: RMSE in N.
    #[inline]
    pub fn rmse(&self, raw: &[f64; 5]) -> f64 {
        if self.n == 0 {
            return 0.0;
        }
        (self.sse(raw) / self.n as f64).sqrt()
    }
}

/// The same RMSE, summed sample by sample (Horner in raw x).
pub fn rmse_by_samples(x_mm: &[f64], force_n: &[f64], raw: &[f64; 5]) -> f64 {
    let n = x_mm.len().min(force_n.len());
    if n == 0 {
        return 0.0;
    }
    let sse: f64 = x_mm
        .iter()
        .zip(force_n)
        .map(|(&x, &f)| (f - eval(raw, x)).powi(2))
        .sum();
    (sse / n as f64).sqrt()
}
