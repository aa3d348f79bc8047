//! The few math functions the core needs, written out (or routed through
//! micromath) so the host runs the same arithmetic as the board (std's
//! versions would hide differences in host tests).
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

/// Hyperbolic tangent `1 − 2/(e^{2u} + 1)` with [`exp`]. Saturates to ±1
/// for large |u|; a NaN input gives −1 (the model only passes finite values).
#[inline]
pub fn tanh(u: f32) -> f32 {
    1.0 - 2.0 / (exp(2.0 * u) + 1.0)
}

/// Inverse hyperbolic tangent `½·ln((1+w)/(1−w))` for `|w| < 1`, with [`ln`].
#[inline]
pub fn atanh(w: f32) -> f32 {
    0.5 * ln((1.0 + w) / (1.0 - w))
}

/// `e^x` to about 2e-7 relative (Cephes' `exp2f`: `2^n · 2^f`, n the nearest
/// integer to x·log2 e, a degree 6 polynomial for 2^f on |f| ≤ ½), in ~20
/// instructions without a table: cheap enough for the control period, and
/// four orders more precise than micromath's `exp`, so a tanh and its atanh
/// agree without a Newton step. The exponent is clamped to 2^±126 (so
/// `tanh` reaches exactly ±1 and nothing overflows); NaN gives 2^−126.
#[inline]
pub fn exp(x: f32) -> f32 {
    const P: [f32; 6] = [
        1.535_336_2e-4,
        1.339_887_4e-3,
        9.618_437e-3,
        5.550_332_5e-2,
        2.402_264_8e-1,
        6.931_472e-1,
    ];
    let y = clamp(x * core::f32::consts::LOG2_E, -126.0, 126.0);
    // Round to nearest (`as` truncates towards zero).
    let n = (y + if y < 0.0 { -0.5 } else { 0.5 }) as i32;
    let f = y - n as f32;
    let [p0, p1, p2, p3, p4, p5] = P;
    let two_f = 1.0 + f * (((((p0 * f + p1) * f + p2) * f + p3) * f + p4) * f + p5);
    // 2^n from its exponent bits: n + 127 is in 1..=253, a normal number.
    two_f * f32::from_bits((n.wrapping_add(127) as u32) << 23)
}

/// Natural logarithm of a positive normal `y` to about 1e-7: `y = 2^e·m`
/// with m in [√½, √2), `ln m = 2·atanh((m−1)/(m+1))` by its series to s⁹.
/// Zero, subnormal, infinite or NaN `y` give a finite but meaningless value:
/// callers keep `y` in range.
#[inline]
pub fn ln(y: f32) -> f32 {
    let bits = y.to_bits();
    let mut e = (((bits >> 23) & 0xff) as i32).wrapping_sub(127);
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > core::f32::consts::SQRT_2 {
        m *= 0.5;
        e = e.wrapping_add(1);
    }
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let series = (((s2 * (1.0 / 9.0) + 1.0 / 7.0) * s2 + 1.0 / 5.0) * s2 + 1.0 / 3.0) * s2 + 1.0;
    e as f32 * core::f32::consts::LN_2 + 2.0 * s * series
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
        i = i.wrapping_add(1);
    }
    sum
}
