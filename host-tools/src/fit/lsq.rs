//! The exact least-squares optimum of one branch quartic. The model is linear
//! in its 5 coefficients, so the optimum is one QR solve
//! ([`mre_host::linalg::solve`](crate::linalg::solve)) on the design matrix in
//! u = (x − centre)/scale ∈ [−1, 1], converted back to raw x (mm) powers.
use super::poly::{min_max, Scaling};
use anyhow::{bail, Result};
use nalgebra::{DMatrix, DVector};

/// A fitted branch quartic.
#[derive(Clone, Debug, PartialEq)]
pub struct QuarticFit {
    /// Highest power first, x in mm, F in N (the table layout).
    pub coeffs: [f64; 5],
    /// Sum of squared residuals (N²).
    pub sse: f64,
    /// √(SSE / n), N.
    pub rmse_n: f64,
}

/// Least-squares quartic through (x, F). Needs at least 5 samples at 5
/// distinct x values.
pub fn fit_quartic(x_mm: &[f64], force_n: &[f64]) -> Result<QuarticFit> {
    let n = x_mm.len();
    if n != force_n.len() {
        bail!("{n} displacement samples but {} force samples", force_n.len());
    }
    if n < 5 {
        bail!("a quartic needs at least 5 samples, got {n}");
    }
    let (lo, hi) = min_max(x_mm);
    if lo >= hi {
        bail!("all samples have the same displacement ({lo} mm): no quartic can be fitted");
    }
    let scaling = Scaling::for_range(lo, hi);
    let design = DMatrix::from_fn(n, 5, |i, j| scaling.u(x_mm[i]).powi(4 - j as i32));
    let target = DVector::from_column_slice(force_n);
    let solution = crate::linalg::solve(&design, &target)?;
    let scaled: [f64; 5] = [
        solution.coeffs[0],
        solution.coeffs[1],
        solution.coeffs[2],
        solution.coeffs[3],
        solution.coeffs[4],
    ];
    Ok(QuarticFit {
        coeffs: scaling.scaled_to_raw(&scaled),
        sse: solution.sse,
        rmse_n: (solution.sse / n as f64).sqrt(),
    })
}
