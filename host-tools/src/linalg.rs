//! Least squares, shared by every host fit (the paper's quartics, the
//! diagnosis's augmented models). Solved by Householder QR on a column-scaled
//! design matrix, never by the normal equations: x⁴ columns make those
//! ill-conditioned (κ(AᵀA) = κ(A)²).
use anyhow::{bail, Result};
use nalgebra::{DMatrix, DVector};

/// The solution of `min ‖A·β − y‖²`.
#[derive(Clone, Debug)]
pub struct LeastSquares {
    pub coeffs: Vec<f64>,
    /// Sum of squared residuals at the optimum.
    pub sse: f64,
}

/// Solves `min ‖A·β − y‖²` for a tall, full-rank `A` (rows = samples).
/// Columns are scaled to unit RMS first and the scaling undone afterwards.
pub fn solve(a: &DMatrix<f64>, y: &DVector<f64>) -> Result<LeastSquares> {
    let (rows, cols) = a.shape();
    if rows != y.len() {
        bail!("design matrix has {rows} rows but the target has {}", y.len());
    }
    if rows < cols || cols == 0 {
        bail!("least squares needs at least as many samples ({rows}) as unknowns ({cols})");
    }
    let mut scaled = a.clone();
    let mut scale = vec![1.0; cols];
    for (j, mut col) in scaled.column_iter_mut().enumerate() {
        let rms = (col.norm_squared() / rows as f64).sqrt();
        if !rms.is_finite() || rms == 0.0 {
            bail!("column {j} of the design matrix is zero or not finite");
        }
        col /= rms;
        scale[j] = rms;
    }
    let qr = scaled.qr();
    let r = qr.r();
    // Rank check: a tiny diagonal of R means a column is (nearly) dependent.
    let r_max = (0..cols).map(|i| r[(i, i)].abs()).fold(0.0, f64::max);
    if (0..cols).any(|i| r[(i, i)].abs() <= 1e-12 * r_max) {
        bail!("the design matrix is rank deficient: the data cannot determine every coefficient");
    }
    // Qᵀ·y by applying the Householder reflections to y: forming Q itself
    // (rows × cols) was a sixth of `mre sim`'s time.
    let mut qty = y.clone();
    qr.q_tr_mul(&mut qty);
    let qty = qty.rows(0, cols).into_owned();
    let beta_scaled = match r.solve_upper_triangular(&qty) {
        Some(b) => b,
        None => bail!("triangular solve failed"),
    };
    let coeffs: Vec<f64> = beta_scaled.iter().zip(&scale).map(|(b, s)| b / s).collect();
    let fitted = a * DVector::from_column_slice(&coeffs);
    let sse = (y - fitted).norm_squared();
    Ok(LeastSquares { coeffs, sse })
}
