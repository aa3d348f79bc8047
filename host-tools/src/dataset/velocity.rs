//! Velocity from displacement when a recording has no velocity column.
//!
//! Method: a local quadratic least-squares fit (Savitzky–Golay, order 2) of
//! x(t) over a window of ±`HALF_WINDOW` samples, differentiated at the sample.
//! A quadratic follows the curvature at turn-around (where x(t) peaks and a
//! finite difference of noisy samples flips sign at random), and averaging
//! 2·HALF_WINDOW + 1 samples cuts white-noise gain: for uniform spacing h and
//! noise σ in x, the derivative's noise is σ·√(3/(h²·k(k+1)(2k+1))) (k = half
//! window; ≈ 0.19·σ/h for k = 3, against 0.71·σ/h for a central difference).
//! Near the ends the window is shifted inside the record and the quadratic
//! differentiated off-centre. Time may be non-uniform: the fit uses real t.
//! The phase lag is zero in the interior (symmetric window).
pub const HALF_WINDOW: usize = 3;

/// v in m/s from t in s and x in mm (same length, t strictly increasing).
pub fn estimate_velocity_m_s(time_s: &[f64], x_mm: &[f64]) -> Vec<f64> {
    let n = time_s.len().min(x_mm.len());
    let width = (2 * HALF_WINDOW + 1).min(n);
    (0..n)
        .map(|i| {
            if width < 3 {
                return 0.0;
            }
            let start = i.saturating_sub(HALF_WINDOW).min(n - width);
            let ts = &time_s[start..start + width];
            let xs = &x_mm[start..start + width];
            quadratic_slope(ts, xs, time_s[i]) * 1e-3
        })
        .collect()
}

/// Slope at `t0` of the least-squares quadratic through (ts, xs).
fn quadratic_slope(ts: &[f64], xs: &[f64], t0: f64) -> f64 {
    // Fit x = c0 + c1·τ + c2·τ² with τ = t − t0, so the slope at t0 is c1.
    // Normal equations are fine here: 3 unknowns, τ centred on the window.
    // τ is scaled by the window span so the 3×3 system is well conditioned.
    let span = ts.iter().map(|t| (t - t0).abs()).fold(0.0, f64::max);
    if span <= 0.0 {
        return 0.0;
    }
    let mut s = [0.0f64; 5];
    let mut r = [0.0f64; 3];
    for (&t, &x) in ts.iter().zip(xs) {
        let tau = (t - t0) / span;
        let mut p = 1.0;
        for k in 0..5 {
            s[k] += p;
            if k < 3 {
                r[k] += p * x;
            }
            p *= tau;
        }
    }
    let m = nalgebra::Matrix3::new(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
    let rhs = nalgebra::Vector3::new(r[0], r[1], r[2]);
    match m.lu().solve(&rhs) {
        Some(c) if c[1].is_finite() => c[1] / span,
        _ => 0.0,
    }
}
