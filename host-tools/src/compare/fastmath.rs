//! Branch-free e^x, atan x and tan x the compiler can vectorise (libm's are calls,
//! so a loop over agents that calls them stays scalar). Used by the Bouc–Wen
//! batch objective ([`super::families::bouc_wen_batch`]). The e^x notes:
//!
//! Method: x = n·ln2 + r with |r| ≤ ln2/2 (Cody–Waite, ln2 split in two so
//! n·ln2_hi is exact), e^r by its Taylor polynomial of degree 12 (truncation
//! ≤ 0.3466¹³/13! < 1.7e-16), times 2ⁿ built in the exponent bits.
//! Max relative error against libm over [−708, 709]: < 1e-15 (checked in the
//! tests below on a dense grid). Arguments are clamped to [−708, 709], so
//! e^x for x < −708 is ≈ 3e-308 instead of 0 (irrelevant where it is used:
//! it multiplies numbers ≤ 2), and NaN stays NaN.

const LOG2_E: f64 = std::f64::consts::LOG2_E;
/// ln 2 in two parts (fdlibm's): the high one ends in 21 zero bits, so n·LN2_HI is exact for |n| ≤ 1024.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// 1.5·2⁵²: adding it rounds to an integer held in the low mantissa bits.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// 1/k! for k = 0..=12, the Taylor coefficients of e^r.
const INV_FACT: [f64; 13] = {
    let mut c = [1.0; 13];
    let mut k = 1;
    while k < 13 {
        c[k] = c[k - 1] / k as f64;
        k += 1;
    }
    c
};

/// e^x (see the module comment for the error bound), a·b + c unfused.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    exp_with(x, |a, b, c| a * b + c)
}

/// e^x with fused multiply–adds: only where the CPU has them (a software
/// `mul_add` is slow), e.g. inside a `#[target_feature(enable = "fma")]` function.
#[inline(always)]
pub fn exp_fma(x: f64) -> f64 {
    exp_with(x, f64::mul_add)
}

#[inline(always)]
fn exp_with(x: f64, madd: impl Fn(f64, f64, f64) -> f64) -> f64 {
    let x = x.clamp(-708.0, 709.0);
    let k = madd(x, LOG2_E, ROUND);
    let n = k - ROUND;
    let r = madd(-n, LN2_LO, madd(-n, LN2_HI, x));
    let mut p = INV_FACT[12];
    for c in INV_FACT[..12].iter().rev() {
        p = madd(p, r, *c);
    }
    // 2ⁿ: n sits in the low bits of k (two's complement around ROUND's bits).
    // Split in two factors so n = 1024 (x near 709) does not overflow the exponent.
    let n_bits = k.to_bits().wrapping_sub(ROUND.to_bits());
    let half = (n_bits as i64) >> 1;
    let a = f64::from_bits(((half + 1023) as u64) << 52);
    let b = f64::from_bits((((n_bits as i64 - half) + 1023) as u64) << 52);
    p * a * b
}

/// (atan s − s)/s³ as a polynomial in y = s² on [0, tan²(π/8)]: a degree-10
/// least-squares fit on Chebyshev nodes (error < 4e-16, so atan's relative
/// error is a few ulps; checked against libm below).
const ATAN_POLY: [f64; 11] = [
    -0.3333333333333335,
    0.19999999999997126,
    -0.1428571428502076,
    0.11111111043129134,
    -0.09090905678973416,
    0.07692208135254462,
    -0.06664855640322435,
    0.05861088135346978,
    -0.051006087729044296,
    0.03966411104101012,
    -0.01970063453203222,
];

/// atan x, branch-free: Cephes' reduction of |x| to |s| ≤ tan(π/8)
/// (s = −1/|x| beyond tan(3π/8), (|x| − 1)/(|x| + 1) beyond tan(π/8); one
/// divide), then s + s³·P(s²). Max relative error against libm < 1e-15 (tests).
#[inline(always)]
pub fn atan(x: f64) -> f64 {
    const TAN_PI_8: f64 = 0.41421356237309503;
    const TAN_3PI_8: f64 = 2.414213562373095;
    let a = x.abs();
    let (num, den, offset) = if a > TAN_3PI_8 {
        (-1.0, a, std::f64::consts::FRAC_PI_2)
    } else if a > TAN_PI_8 {
        (a - 1.0, a + 1.0, std::f64::consts::FRAC_PI_4)
    } else {
        (a, 1.0, 0.0)
    };
    let s = num / den;
    let y = s * s;
    let mut p = ATAN_POLY[10];
    for c in ATAN_POLY[..10].iter().rev() {
        p = p * y + c;
    }
    (offset + (s + s * y * p)).copysign(x)
}

/// (tan h − h)/h³ as a polynomial in y = h² on [0, (π/8)²]: a degree-9
/// least-squares fit on Chebyshev nodes (error < 3e-16).
const TAN_POLY: [f64; 10] = [
    0.3333333333333334,
    0.1333333333333435,
    0.05396825396616787,
    0.021869488693363005,
    0.008863229673937694,
    0.0035922499266114022,
    0.001454341848985352,
    0.000600809005919011,
    0.0001955562344868153,
    0.00018045189595954563,
];

/// tan x for |x| < π/2, branch-free: b = |x| (or π/2 − |x| beyond π/4, the
/// cotangent side), T = tan(b/2) = h + h³·P(h²), then the double-angle
/// formula 2T/(1 − T²) or its inverse (one divide). Max relative error
/// against libm < 1e-15 for |x| ≤ 1.4 (tests); it grows towards π/2, where
/// π/2 − |x| loses digits (the Bouc–Wen phase stays within ±π/3).
#[inline(always)]
pub fn tan(x: f64) -> f64 {
    let a = x.abs();
    let cot = a > std::f64::consts::FRAC_PI_4;
    let h = 0.5 * if cot { std::f64::consts::FRAC_PI_2 - a } else { a };
    let y = h * h;
    let mut p = TAN_POLY[9];
    for c in TAN_POLY[..9].iter().rev() {
        p = p * y + c;
    }
    let t = h + h * y * p;
    let (two_t, one_minus) = (2.0 * t, 1.0 - t * t);
    let (num, den) = if cot { (one_minus, two_t) } else { (two_t, one_minus) };
    (num / den).copysign(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_libm_to_1e15_relative_over_the_whole_range() {
        let (mut worst, mut worst_fma) = (0.0f64, 0.0f64);
        let mut x = -708.0;
        while x <= 709.0 {
            worst = worst.max((exp(x) - x.exp()).abs() / x.exp());
            worst_fma = worst_fma.max((exp_fma(x) - x.exp()).abs() / x.exp());
            x += 0.000_731;
        }
        assert!(worst < 1e-15, "worst relative error {worst:e}");
        assert!(worst_fma < 1e-15, "worst relative error with FMA {worst_fma:e}");
    }

    #[test]
    fn atan_matches_libm_to_1e15_relative() {
        let mut worst = 0.0f64;
        // Dense near 0 and around the reduction thresholds, sparse far out.
        let mut x = 1e-8;
        while x < 1e8 {
            for v in [x, -x] {
                worst = worst.max((atan(v) - v.atan()).abs() / v.atan().abs());
            }
            x *= 1.0 + 1e-4;
        }
        assert!(worst < 1e-15, "worst relative error {worst:e}");
        assert_eq!(atan(0.0), 0.0);
        assert_eq!(atan(f64::INFINITY), std::f64::consts::FRAC_PI_2);
        assert!(atan(f64::NAN).is_nan());
    }

    #[test]
    fn tan_matches_libm_to_1e15_relative_up_to_1_4() {
        let mut worst = 0.0f64;
        for i in 1..=1_400_000 {
            let x = i as f64 * 1e-6;
            for v in [x, -x] {
                worst = worst.max((tan(v) - v.tan()).abs() / v.tan().abs());
            }
        }
        assert!(worst < 1e-15, "worst relative error {worst:e}");
        assert_eq!(tan(0.0), 0.0);
        assert!(tan(f64::NAN).is_nan());
    }

    #[test]
    fn exact_points_and_edges() {
        // e^0 = 1 and e^(k·ln2) = 2^k up to the rounding of k·ln2 itself.
        assert_eq!(exp(0.0), 1.0);
        for k in [-1000i32, -20, -1, 1, 10, 1000] {
            let x = k as f64 * std::f64::consts::LN_2;
            if (-708.0..=709.0).contains(&x) {
                let want = 2f64.powi(k);
                assert!((exp(x) / want - 1.0).abs() < 1e-13, "k {k}");
            }
        }
        assert!(exp(-1e6) < 1e-300 && exp(-1e6) >= 0.0);
        assert!(exp(709.0).is_finite());
        assert!(exp(f64::NAN).is_nan());
    }
}
