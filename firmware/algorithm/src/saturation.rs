//! The inverse's way back from a segment fraction to a current under
//! magnetic saturation, fitted when the table is built so that the control
//! period pays for a polynomial only: no divide, no logarithm, no series.
//!
//! Under saturation the model interpolates linearly in `w = tanh(I/I_s)`,
//! so on the segment from knot `w0` (current `i0`) to `w1` the inverse's
//! fraction `t` gives
//! `I(t) = i0 + I_s·(atanh(w0 + t·Δw) − atanh(w0))`, `Δw = fl(w1 − w0)`
//! (what the core computed every period before, through the addition
//! theorem, a divide and a series to u¹³). `I` is analytic on `0 ≤ t ≤ 1`:
//! its nearest singularity, `w = 1`, lies `1/ρ` half-widths from the
//! segment's centre `wc`, `ρ = h/(1 − wc)`, `h = Δw/2`. On a segment with
//! `ρ ≤` [`RHO_MAX`] (and `h/(1 + wc)` too) the fit is:
//! 1. the Taylor series of `I` around `wc` in `y = (w − wc)/h`, from the
//!    closed-form derivatives of atanh,
//!    `a_n = I_s/(2n)·(ρⁿ − (−ρ₊)ⁿ)`, `ρ₊ = h/(1 + wc)`, for
//!    `n = 1…`[`TAYLOR_TERMS`] (the constant is left out: see 3); the terms
//!    past it sum to at most `I_s/(2(N+1))·(ρ^(N+1)/(1 − ρ) + ρ₊^(N+1)/(1 − ρ₊))`;
//! 2. economized with Chebyshev polynomials down to degree [`DEGREE`]:
//!    each `a_n·yⁿ` removed is replaced by `a_n·(yⁿ − 2^(1−n)·T_n(y))`, of
//!    lower degree, which is off by at most `|a_n|·2^(1−n)·T_n(y_max)` (the
//!    range is `|y| ≤ y_max`, a hair above 1 where the centre rounds);
//! 3. rewritten in t (`y = 2t − 1 − δ/h`, δ the centre's rounding, exact
//!    by TwoSum) and its constant replaced by `i0`: the map is then off by
//!    at most twice the truncations of 1 and 2 (once at t, once at 0);
//! 4. `c1` raised, if need be, until the f32 polynomial reaches `i1` at
//!    t = 1, so that the inverse's clamp to `i1` gives a tabulated current
//!    back exactly (each raise is added to the bound).
//!
//! The bound of each fit ([`Fitted::bound_a`]) adds the truncations, the
//! f32 rounding of the fit (a running bound: every operation within 2⁻²³ of
//! the magnitudes that went into it) and of the period's Horner evaluation
//! (the coefficient of tᵏ rounded 2k + 1 times). Where a ratio exceeds
//! [`RHO_MAX`], or the bound exceeds [`TOLERANCE_PER_A`] of the segment's
//! upper current (1 A at least), or the polynomial could fall below `i0`
//! for some `0 < t ≤ 1`, the segment keeps the exact map (`I_s·atanh(w0 +
//! t·Δw)` through the logarithm, out of line). `tests/tests/core/saturation.rs`
//! checks the bound against f64's atanh on random segments and on the
//! flown entries (the generated table's five currents at I_s = 1.5 A, as
//! `ModelTerms::EVERY_TERM`: bounds 1.3–2.7·10⁻⁶ A, measured ≤ 3·10⁻⁷ A).
use crate::math;

/// The variable the interpolation between currents is linear in: `I`, or
/// `tanh(I/I_s)` when `saturation_current_a > 0`.
#[inline]
pub fn interpolation_variable(current_a: f32, saturation_current_a: f32) -> f32 {
    if saturation_current_a > 0.0 {
        math::tanh(current_a / saturation_current_a)
    } else {
        current_a
    }
}

/// Degree of the polynomial in t: 7 multiply-adds per period.
pub const DEGREE: usize = 7;
/// Terms of the Taylor series before economizing (the series' tail past
/// them is in the bound): with ρ ≤ [`RHO_MAX`] it is below 10⁻⁷ of I_s.
pub const TAYLOR_TERMS: usize = 14;
/// Largest `ρ = h/(1 − wc)` a segment is fitted for: beyond it the
/// economized tail and the Taylor series' both grow past f32's precision.
/// The flown entries at I_s = 1.5 A reach 0.29.
pub const RHO_MAX: f32 = 0.35;
/// Largest bound (A per A of the segment's upper current, at least 1 A)
/// a fitted segment may have: a few f32 ulps of the current.
pub const TOLERANCE_PER_A: f32 = 2.0e-6;

/// One segment's map from fraction to current.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct SegmentMap {
    /// `I(t) ≈ i0 + t·(c[0] + t·(c[1] + … + t·c[6]))`: the coefficients of
    /// t¹…t⁷ (A).
    pub coeffs: [f32; DEGREE],
    /// True when the polynomial is used; false: the exact map. (32 bytes
    /// in all, so the inverse indexes segments with a shift.)
    pub fitted: bool,
}

/// A fitted segment and its error bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fitted {
    pub map: SegmentMap,
    /// How far (A) the polynomial's f32 value (before the clamp to the
    /// upper current) may lie from the exact map for any `0 ≤ t ≤ 1`.
    pub bound_a: f32,
}

impl SegmentMap {
    /// Not fitted: the exact map (and a linear table's segments).
    pub const EXACT: SegmentMap = SegmentMap {
        coeffs: [0.0; DEGREE],
        fitted: false,
    };

    /// The fit for the segment from knot `w0` (current `i0`) to `w1`
    /// (current `i1`) at saturation current `i_s`, or `None` when it would
    /// not be within the tolerance. Knots are the table's
    /// (`-1 < w0 < w1 < 1`, checked when it is built).
    pub fn fit(w0: f32, w1: f32, i_s: f32, i0: f32, i1: f32) -> Option<Fitted> {
        // The exact map's geometry: the knots and Δw = fl(w1 − w0), as the
        // forward model interpolates; h = Δw/2 is exact. The centre rounds:
        // `delta` is exactly how far (TwoSum), and the map from t to y
        // below takes it into account.
        let h = 0.5 * (w1 - w0);
        let wc = w0 + h;
        let delta = -two_sum_error(w0, h);
        // y = (w − wc)/h runs over [−y_max, y_max] for 0 ≤ t ≤ 1 (a hair
        // past ±1 by the centre's rounding), so the series' ratios and the
        // Chebyshev bounds below are taken there.
        let y_max = (1.0 + math::abs(delta / h)) * (1.0 + 4.0 * EPS);
        let (r, r_plus) = (h / (1.0 - wc), h / (1.0 + wc));
        let (rho, rho_plus) = (r * y_max, r_plus * y_max);
        // `!(a ≤ b)`: NaN fails too.
        if !(h > 0.0 && rho <= RHO_MAX && rho_plus <= RHO_MAX && i_s > 0.0 && i_s.is_finite()) {
            return None;
        }
        const N: usize = TAYLOR_TERMS;
        // The loops below run once per segment when a table is built; with
        // their bounds opaque to the optimizer they stay loops (fully
        // unrolled they were 4 KB of the 64 KiB flash).
        let (n_max, degree, max_raises) = core::hint::black_box((N, DEGREE, 8));
        // Taylor coefficients in y, and a running bound on each one's
        // rounding error (absolute).
        let mut a = [0.0f32; N + 1];
        let mut err = [0.0f32; N + 1];
        // a_0 stays 0: the polynomial's constant is i0 (see below).
        let (mut pm, mut pp) = (1.0f32, 1.0f32);
        let mut n = 1;
        while n <= n_max {
            pm *= r;
            pp *= r_plus;
            let s = if n % 2 == 1 { pm + pp } else { pm - pp };
            let v = i_s * s / n.wrapping_mul(2) as f32;
            // 2n + 4 roundings, each relative to at most |pm| + |pp|.
            set(&mut a, n, v);
            set(
                &mut err,
                n,
                n.wrapping_mul(2).wrapping_add(4) as f32 * EPS * i_s * (pm + pp) / n.wrapping_mul(2) as f32,
            );
            n = n.wrapping_add(1);
        }
        // The series' tail on |y| ≤ y_max: |a_n|·y_maxⁿ ≤ I_s/(2n)·(ρⁿ + ρ₊ⁿ).
        let tail = |q: f32| {
            let mut p = q;
            for _ in 0..n_max {
                p *= q;
            }
            p / (1.0 - q)
        };
        // `truncation`: how far the exact economized polynomial F may lie
        // from Q(y) = I_s·(atanh(wc + h·y) − atanh(w0)) − Q's value at y = 0
        // (its Taylor constant, left out above) on the range.
        let mut truncation = i_s / (2 * (N + 1)) as f32 * (tail(rho) + tail(rho_plus)) * (1.0 + 64.0 * EPS);
        // Economize: remove a_n·yⁿ for n = N … DEGREE + 1.
        let mut n = n_max;
        while n > degree {
            let c = get(&a, n) * pow2(1i32.wrapping_sub(n as i32));
            // Dropped: c·T_n(y), at most |c|·T_n(y_max) on the range, and
            // a_n's own error times |y|ⁿ.
            truncation += (math::abs(c) + get(&err, n)) * chebyshev_at(n, y_max) * (1.0 + 64.0 * EPS);
            // T_n's coefficient of y^(n−2j), from 2^(n−1) for j = 0 by
            // t_{j+1} = −t_j·(n−2j)(n−2j−1)/(4(j+1)(n−j−1)): integers, exact
            // in u32 (and in f32: below 2²⁴ up to n = 14).
            // n ≤ DEGREE + 1 (a few tens): no step below wraps or overflows;
            // the wrapping forms only say so to the overflow lint.
            let mut t_j: u32 = 1u32.wrapping_shl(n.wrapping_sub(1) as u32);
            let mut j: usize = 0;
            while j.wrapping_add(1).wrapping_mul(2) <= n {
                let m = n.wrapping_sub(j.wrapping_mul(2));
                let numerator = m.wrapping_mul(m.wrapping_sub(1)) as u32;
                let denominator = 4usize
                    .wrapping_mul(j.wrapping_add(1))
                    .wrapping_mul(n.wrapping_sub(j).wrapping_sub(1).max(1)) as u32;
                t_j = t_j.wrapping_mul(numerator).checked_div(denominator).unwrap_or(0);
                j = j.wrapping_add(1);
                let tk = if j % 2 == 1 { -(t_j as f32) } else { t_j as f32 };
                let k = n.wrapping_sub(j.wrapping_mul(2));
                let v = get(&a, k) - c * tk;
                let e = get(&err, k) + math::abs(c * tk) * 2.0 * EPS + math::abs(v) * EPS;
                set(&mut a, k, v);
                set(&mut err, k, e);
            }
            set(&mut a, n, 0.0);
            n = n.wrapping_sub(1);
        }
        // w = w0 + t·Δw is y = 2t − s with s = 1 + δ/h: substitute
        // y = z − s (repeated synthetic division), then z = 2t (exact
        // powers of two). The rounding of s moves w by about ε·h.
        let shift = 1.0 + delta / h;
        let mut i = 0;
        while i < degree {
            let mut j = degree.wrapping_sub(1);
            loop {
                let v = get(&a, j) - shift * get(&a, j.wrapping_add(1));
                let e = get(&err, j)
                    + shift * get(&err, j.wrapping_add(1))
                    + 2.0 * math::abs(v) * EPS
                    + 2.0 * EPS * math::abs(shift * get(&a, j.wrapping_add(1)));
                set(&mut a, j, v);
                set(&mut err, j, e);
                if j == i {
                    break;
                }
                j = j.wrapping_sub(1);
            }
            i = i.wrapping_add(1);
        }
        // In t the polynomial is P(t) = i0 + Σ_{k≥1} c_k·tᵏ: its constant
        // is dropped, so P − i0 = F(t) − F(t = 0) and the exact map is
        // i0 + Q(t) − Q(t = 0): off by at most twice the truncation.
        let mut bound = 2.0 * truncation;
        let mut coeffs = [0.0f32; DEGREE];
        let mut magnitude = 0.0f32;
        let mut horner = 0.0f32;
        let mut scale = 1.0f32;
        let mut k = 0;
        while k < degree {
            scale *= 2.0;
            let c = get(&a, k.wrapping_add(1)) * scale;
            set(&mut coeffs, k, c);
            bound += get(&err, k.wrapping_add(1)) * scale;
            magnitude += math::abs(c);
            // Horner rounds c_k·tᵏ 2k + 1 times (k multiplies, k + 1 adds).
            horner += k.wrapping_mul(2).wrapping_add(3) as f32 * math::abs(c);
            k = k.wrapping_add(1);
        }
        // The period's Horner, t ≤ 1 (unit roundoff 2⁻²⁴ = EPS/2, each
        // term rounded up by the 1 + 64·EPS below): the coefficients'
        // roundings and the last addition's, relative to its result.
        bound += 0.5 * EPS * (horner + math::abs(i0) + magnitude);
        // At t = 1 the inverse must give i1 exactly (a tabulated force maps
        // back to its current): raise c1 until the f32 polynomial (the
        // same evaluation as the period's) reaches i1, so the clamp to i1
        // settles it; each raise moves P by at most its size.
        let mut raises: u32 = 0;
        loop {
            let deficit = i1 - value_at_one(&coeffs, i0);
            // (A NaN deficit ends it too: the checks below then refuse the fit.)
            if deficit.is_nan() || deficit <= 0.0 || raises >= max_raises {
                break;
            }
            let Some(c1) = coeffs.first_mut() else {
                break;
            };
            // At least one ulp of c1 (an ulp of i1 may be below it).
            let ulp = math::abs(*c1) * EPS;
            let raise = if deficit > ulp { deficit } else { ulp };
            *c1 += raise;
            bound += raise * (1.0 + 4.0 * EPS);
            raises = raises.wrapping_add(1);
        }
        let reaches_i1 = value_at_one(&coeffs, i0) >= i1;
        let c1 = get(&coeffs, 0);
        let rest_sum = magnitude - math::abs(c1);
        // For 0 < t ≤ 1 the sum after i0 is t·(c1 + t·(…)) with
        // |t·(…)| ≤ Σ|c_k|, k ≥ 2: positive with margin, so the f32 value
        // never falls below i0 and only the upper end needs the clamp.
        let rises = c1 > rest_sum * (1.0 + 64.0 * EPS) + 16.0 * EPS * magnitude;
        let tolerance = TOLERANCE_PER_A * if math::abs(i1) > 1.0 { math::abs(i1) } else { 1.0 };
        if !(bound <= tolerance && rises && reaches_i1) {
            return None;
        }
        Some(Fitted {
            map: SegmentMap { coeffs, fitted: true },
            bound_a: bound,
        })
    }

    /// The fitted map at `0 < t ≤ 1` (the period's Horner, the same on host
    /// and board), before the caller's clamp to the upper current: at
    /// t = 1 it is at least i1 (so the clamp gives exactly i1), and above
    /// 0 never below i0.
    #[inline(always)]
    pub fn eval(&self, i0: f32, t: f32) -> f32 {
        let [c1, c2, c3, c4, c5, c6, c7] = self.coeffs;
        ((((((c7 * t + c6) * t + c5) * t + c4) * t + c3) * t + c2) * t + c1) * t + i0
    }
}

/// f32's unit roundoff (2⁻²⁴), doubled for the bound's own arithmetic.
const EPS: f32 = f32::EPSILON;

/// `T_n(y)` for `y ≥ 1` (where it is largest on `[−y, y]`), rounded up
/// generously; with `y_max` ≈ 1 about 1.
fn chebyshev_at(n: usize, y: f32) -> f32 {
    let (mut prev, mut cur) = (1.0f32, y);
    for _ in 1..n {
        (prev, cur) = (cur, 2.0 * y * cur - prev);
    }
    cur * (1.0 + 8.0 * n as f32 * EPS)
}

/// The rounding error of `a + b`: `(a + b) − fl(a + b)`, exactly (Knuth's
/// TwoSum, no condition on the operands' order).
fn two_sum_error(a: f32, b: f32) -> f32 {
    let s = a + b;
    let bb = s - a;
    (a - (s - bb)) + (b - bb)
}

fn pow2(e: i32) -> f32 {
    // Exponents here are within ±TAYLOR_TERMS: normal numbers.
    f32::from_bits((e.wrapping_add(127) as u32) << 23)
}

// `get` and `set` stay calls: the fit's loops (table build only) then stay
// small instead of being unrolled around checked loads and stores.
#[inline(never)]
fn get(a: &[f32], k: usize) -> f32 {
    a.get(k).copied().unwrap_or(0.0)
}

#[inline(never)]
fn set(a: &mut [f32], k: usize, v: f32) {
    if let Some(slot) = a.get_mut(k) {
        *slot = v;
    }
}

/// The fitted polynomial at t = 1, as the period evaluates it (out of
/// line: called a few times per segment at table build).
#[inline(never)]
fn value_at_one(coeffs: &[f32; DEGREE], i0: f32) -> f32 {
    SegmentMap {
        coeffs: *coeffs,
        fitted: true,
    }
    .eval(i0, 1.0)
}
