//! A branch-free e^x the compiler can vectorise (libm's `exp` is a call, so
//! a loop over agents that calls it stays scalar). Used by the Bouc–Wen
//! batch objective ([`super::families::bouc_wen_batch`]).
//!
//! Method: x = n·ln2 + r with |r| ≤ ln2/2 (Cody–Waite, ln2 split in two so
//! n·ln2_hi is exact), e^r by its Taylor polynomial of degree 12 (truncation
//! ≤ 0.3466¹³/13! < 1.7e-16), times 2ⁿ built in the exponent bits.
//! Max relative error against libm over [−708, 709]: < 1e-15 (checked in the
//! tests below on a dense grid). Arguments are clamped to [−708, 709], so
//! e^x for x < −708 is ≈ 3e-308 instead of 0 (irrelevant where it is used:
//! it multiplies numbers ≤ 2), and NaN stays NaN.

const LOG2_E: f64 = std::f64::consts::LOG2_E;
/// ln 2 in two parts: the high one has 32 trailing zero bits, so n·LN2_HI is exact for |n| < 2²⁰.
const LN2_HI: f64 = 6.931_471_803_691_238_2e-1;
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
/// 1.5·2⁵²: adding it rounds to an integer held in the low mantissa bits.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// e^x (see the module comment for the error bound).
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    let x = x.clamp(-708.0, 709.0);
    let k = x * LOG2_E + ROUND;
    let n = k - ROUND;
    let r = (x - n * LN2_HI) - n * LN2_LO;
    // Horner on 1/j!: 1 + r(1 + r/2(1 + r/3(…(1 + r/12)))).
    let mut p = 1.0 + r * (1.0 / 12.0);
    p = 1.0 + r * (1.0 / 11.0) * p;
    p = 1.0 + r * (1.0 / 10.0) * p;
    p = 1.0 + r * (1.0 / 9.0) * p;
    p = 1.0 + r * (1.0 / 8.0) * p;
    p = 1.0 + r * (1.0 / 7.0) * p;
    p = 1.0 + r * (1.0 / 6.0) * p;
    p = 1.0 + r * (1.0 / 5.0) * p;
    p = 1.0 + r * (1.0 / 4.0) * p;
    p = 1.0 + r * (1.0 / 3.0) * p;
    p = 1.0 + r * 0.5 * p;
    p = 1.0 + r * p;
    // 2ⁿ: n sits in the low bits of k (two's complement around ROUND's bits).
    // Split in two factors so n = 1024 (x near 709) does not overflow the exponent.
    let n_bits = k.to_bits().wrapping_sub(ROUND.to_bits());
    let half = (n_bits as i64) >> 1;
    let a = f64::from_bits(((half + 1023) as u64) << 52);
    let b = f64::from_bits((((n_bits as i64 - half) + 1023) as u64) << 52);
    p * a * b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_libm_to_1e15_relative_over_the_whole_range() {
        let mut worst = 0.0f64;
        let mut x = -708.0;
        while x <= 709.0 {
            let rel = (exp(x) - x.exp()).abs() / x.exp();
            worst = worst.max(rel);
            x += 0.000_731;
        }
        assert!(worst < 1e-15, "worst relative error {worst:e}");
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
