//! The few math functions the core needs, routed through micromath so the host
//! runs the same approximations as the board (std's exact versions would hide
//! differences in host tests).
use micromath::F32Ext;

#[inline]
pub fn abs(x: f32) -> f32 {
    F32Ext::abs(x)
}

/// `x` clamped to `[lo, hi]`; NaN maps to `lo`. Never panics (unlike `f32::clamp`
/// with bad bounds).
#[inline]
pub fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    if x >= lo {
        if x <= hi {
            x
        } else {
            hi
        }
    } else {
        lo
    }
}

/// Square root to f32 precision: micromath's fast estimate refined by two
/// Newton steps. For configuration-time quantities, not the hot path.
pub fn sqrt_precise(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 || !x.is_finite() {
        return F32Ext::sqrt(x);
    }
    let mut y = F32Ext::sqrt(x);
    for _ in 0..2 {
        y = 0.5 * (y + x / y);
    }
    y
}

/// Hyperbolic tangent from micromath's `exp`: `1 − 2/(e^{2u} + 1)`. Saturates
/// to ±1 for large |u| (e^{2u} overflows to +inf or underflows to 0), never NaN
/// for a non-NaN input.
#[inline]
pub fn tanh(u: f32) -> f32 {
    1.0 - 2.0 / (F32Ext::exp(2.0 * u) + 1.0)
}

/// Inverse hyperbolic tangent `½·ln((1+w)/(1−w))` for `|w| < 1` (±inf at ±1).
#[inline]
pub fn atanh(w: f32) -> f32 {
    0.5 * F32Ext::ln((1.0 + w) / (1.0 - w))
}

/// `e^x` to f32 precision for configuration-time constants (micromath's
/// `exp` is ~1e-3 off, too coarse for a coil model the host checks against
/// std): `e^n·e^f` with n the integer part (repeated products of e) and a
/// 12-term Taylor series of the fraction. Up to 80 multiplies: not for the
/// per-period path. Clamped to e^±80.
pub fn exp_precise(x: f32) -> f32 {
    if x.is_nan() {
        return x;
    }
    let x = clamp(x, -80.0, 80.0);
    let n = x as i32; // towards zero: |f| < 1
    let f = x - n as f32;
    let mut term = 1.0f32;
    let mut sum = 1.0f32;
    let mut k = 1.0f32;
    while k <= 12.0 {
        term *= f / k;
        sum += term;
        k += 1.0;
    }
    let base = if n < 0 {
        1.0 / core::f32::consts::E
    } else {
        core::f32::consts::E
    };
    let mut i = 0;
    while i < n.unsigned_abs() {
        sum *= base;
        i += 1;
    }
    sum
}
