//! Where a table's forces rise with current: proven once, when the table is
//! built, so that the inverse can skip work every period.
//!
//! The inverse scans the entries from the lowest current up and, for a target
//! it cannot reach, keeps the nearest force seen, because in general the
//! force need not rise with current (the paper's 2 A loop lies below its
//! 1.5 A loop in places; the generated table's 1.5 A and 2 A compression
//! quartics cross at x ≈ 0.435 mm). Where the forces do rise strictly with
//! current, the answer needs less: a target below entry 0's force is
//! answered by entry 0 alone and the scan need not carry the nearest force.
//! Near contact, where every force is close to 0 and the fitted entries'
//! order is noise, one entry still stays the largest for a while: there a
//! target above it is answered by it alone. And entry 0 (the lowest current)
//! usually gives the smallest force nearly down to contact, even where the
//! others cross: there a target below it is answered by it alone. Each
//! shortcut must give the scan's answer bit for bit, so the order has to hold
//! for the f32 forces the core computes, not only for the exact quartics.
//!
//! The proof, per branch and per pair of entries (low, high): walk over the
//! shared stroke in pieces of 1/[`PROOF_STEPS`] of it, halving a piece that
//! fails (down to 1/[`REFINE`] of that) so that a proven region ends close to
//! a crossing. On a piece `[a, b]` with midpoint `c` the exact difference
//! `D = F_high − F_low` satisfies `D(x) ≥ D(c) − L·|x − c|`, where
//! `L = Σ i·|d_i|·X^{i−1}` bounds `|D'|` for `|x| ≤ X = max(|a|, |b|)`.
//! `D(c)` is computed in f32 from two Horner evaluations, each within
//! `EVAL_ERR · Σ|c_i|·X^i` of the exact value (Horner with separate multiply
//! and add rounds at most 8 times: γ₈ ≈ 4.8e-7 of that sum; `EVAL_ERR` is
//! twice it). The piece is proven when that lower bound, less both
//! evaluations' errors again (for the f32 forces at any x of the piece),
//! stays above zero.
//!
//! A viscous term adds `c_k·v` to entry k's force (the inverse computes
//! `fl(fl(Q_k) + fl(c_k·v))`), which can reorder the entries at speed. A
//! table with one gets its facts proven for a range of velocities only: the
//! branch's own sign up to [`ORDER_V_MAX_M_S`] (compression `0 ≤ v ≤ V`,
//! extension `−V ≤ v ≤ 0`), and the inverse uses them only there. The exact
//! difference `Q_h − Q_l + (c_h − c_l)·v` is linear in v, so on that range it
//! is least at one of its ends: the proof adds `min(0, Δc·v)` over both ends
//! to the quartics' bound, less the rounding of the two products and the two
//! sums (each within f32's unit roundoff of its magnitude; the last
//! subtraction of the bound keeps its sign exactly). On the compression
//! branch, where `c` does not fall with current (`Δc ≥ 0`), the viscous term
//! only widens the gap, so the quartics' facts hold there for every
//! `0 ≤ v ≤ V`; a falling `c` narrows them, and near contact, where the
//! quartics are all close to 0, can leave none (`ModelTerms::EVERY_TERM`).
//! The "largest entry" fact is not proven with a viscous term: near contact
//! the largest entry changes with the velocity, and the inverse does not use
//! it then (its path cost the full scan more than it saved, BENCHMARKS.md).
use crate::entry::{Branch, CurrentEntry, Quartic, MAX_CURRENTS};
use crate::math::abs;

/// Fastest speed (m/s) the facts of a table with a viscous term are proven
/// for: the velocity transducer's full scale (firmware/README.md), twice the
/// paper's 2.24 m/s drop. A faster sample takes the full scan (exact, slower).
pub const ORDER_V_MAX_M_S: f32 = 5.0;

/// Pieces of the shared stroke the proof walks (0.03 mm each on a 15 mm
/// stroke): a few thousand quartics per table build, not per period.
pub const PROOF_STEPS: u32 = 512;
/// How much finer a piece may get next to a crossing (2¹⁰: a few hundredths
/// of a micrometre), so that the proven regions reach nearly to it.
const REFINE: f32 = 1024.0;

/// A bound on one f32 Horner evaluation's error, relative to `Σ|c_i|·|x|^i`:
/// twice γ₈ (8 roundings at 2⁻²⁴ each).
const EVAL_ERR: f32 = 1.0e-6;
/// f32's unit roundoff, doubled, for the proof's own arithmetic.
const ROUND: f32 = 2.0 * f32::EPSILON;

/// What is proven about one branch's forces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrderFacts {
    /// From here to the top of the shared stroke every entry's force is
    /// above the one below it (+∞: nowhere).
    pub ascending_from_mm: f32,
    /// From here to the top of the shared stroke entry 0 gives strictly the
    /// smallest force (+∞: nowhere); at or below `ascending_from_mm`.
    pub bottom_from_mm: f32,
    /// From the bottom of the shared stroke up to here, entry `top` gives
    /// strictly the largest force (−∞: nowhere; not proven with a viscous
    /// term, which the inverse would not use it for).
    pub top_to_mm: f32,
    pub top: usize,
    /// The viscous term's velocities (m/s, after its clamp) the facts hold
    /// for; every velocity (±∞) without a viscous term.
    pub v_min_m_s: f32,
    pub v_max_m_s: f32,
}

impl OrderFacts {
    pub const NONE: OrderFacts = OrderFacts {
        ascending_from_mm: f32::INFINITY,
        bottom_from_mm: f32::INFINITY,
        top_to_mm: f32::NEG_INFINITY,
        top: 0,
        v_min_m_s: f32::INFINITY,
        v_max_m_s: f32::NEG_INFINITY,
    };

    /// The facts for `branch` of `entries` with viscous coefficients
    /// `viscous` (same index; all 0: none) on the shared stroke
    /// `[lo_mm, hi_mm]` (every entry fitted on it; none if it is empty).
    pub fn prove(entries: &[CurrentEntry], viscous: &[f32], branch: Branch, lo_mm: f32, hi_mm: f32) -> OrderFacts {
        // An empty (or non-finite) shared stroke proves nothing.
        if !lo_mm.is_finite() || !hi_mm.is_finite() || lo_mm >= hi_mm {
            return OrderFacts::NONE;
        }
        let mut quartics = [Quartic::new([0.0; 5]); MAX_CURRENTS];
        for (q, e) in quartics.iter_mut().zip(entries) {
            *q = match branch {
                Branch::Compression => e.compression,
                Branch::Extension => e.extension,
            };
        }
        let quartics = quartics.get(..entries.len()).unwrap_or(&[]);
        let mut c = [0.0f32; MAX_CURRENTS];
        for (c, v) in c.iter_mut().zip(viscous) {
            *c = *v;
        }
        let c = c.get(..entries.len()).unwrap_or(&[]);
        // The velocity range: every one without a viscous term (it adds
        // exactly 0), else the branch's sign up to ORDER_V_MAX_M_S.
        let viscous_free = c.iter().all(|c| *c == 0.0);
        let (v_min_m_s, v_max_m_s) = if viscous_free {
            (f32::NEG_INFINITY, f32::INFINITY)
        } else {
            match branch {
                Branch::Compression => (0.0, ORDER_V_MAX_M_S),
                Branch::Extension => (-ORDER_V_MAX_M_S, 0.0),
            }
        };
        let ends = [v_min_m_s, v_max_m_s];
        let coeff = |k: usize| c.get(k).copied().unwrap_or(0.0);
        let rises = |low: usize, high: usize, a: f32, b: f32| match (quartics.get(low), quartics.get(high)) {
            (Some(ql), Some(qh)) => rise_with_viscous(ql, qh, (coeff(low), coeff(high)), ends, a, b) > 0.0,
            _ => false,
        };
        // Neighbours rise, walking down from the top of the stroke.
        let rising = |a: f32, b: f32| (1..quartics.len()).all(|k| rises(k.wrapping_sub(1), k, a, b));
        let ascending_from_mm = walk(lo_mm, hi_mm, true, rising).unwrap_or(f32::INFINITY);
        // Entry 0 below every other entry (implied where they all rise).
        let lowest = |a: f32, b: f32| (1..quartics.len()).all(|k| rises(0, k, a, b));
        let bottom_from_mm = walk(lo_mm, hi_mm, true, lowest)
            .unwrap_or(f32::INFINITY)
            .min(ascending_from_mm);
        // The largest entry at the bottom, and how far up it stays so. Not
        // with a viscous term: near contact, where every quartic is close
        // to 0, the largest entry changes with the velocity, and the inverse
        // does not use this fact then (see `plan_current_v`).
        let mut top = 0;
        let mut top_to_mm = f32::NEG_INFINITY;
        if viscous_free {
            let mut best = f32::NEG_INFINITY;
            for (k, q) in quartics.iter().enumerate() {
                let f = q.eval(lo_mm);
                if f > best {
                    (best, top) = (f, k);
                }
            }
            let largest = |a: f32, b: f32| (0..quartics.len()).all(|k| k == top || rises(k, top, a, b));
            top_to_mm = walk(lo_mm, hi_mm, false, largest).unwrap_or(f32::NEG_INFINITY);
        }
        OrderFacts {
            ascending_from_mm,
            bottom_from_mm,
            top_to_mm,
            top,
            v_min_m_s,
            v_max_m_s,
        }
    }
}

/// [`rise_lower_bound`] for the forces with their viscous terms `c = (c_low,
/// c_high)` at any velocity between `ends` (±∞: no viscous term, both 0).
fn rise_with_viscous(low: &Quartic, high: &Quartic, c: (f32, f32), ends: [f32; 2], a: f32, b: f32) -> f32 {
    let r = rise_lower_bound(low, high, a, b);
    let (c_low, c_high) = c;
    if c_low == 0.0 && c_high == 0.0 {
        // Both add exactly 0 (f + 0·v = f for a finite v).
        return r;
    }
    let [v_lo, v_hi] = ends;
    if !v_lo.is_finite() || !v_hi.is_finite() {
        return f32::NAN;
    }
    // The exact viscous difference is linear in v: least at an end.
    let dc = c_high - c_low;
    let worst = (dc * v_lo).min(dc * v_hi).min(0.0);
    // Rounding: the two products and the two sums (each within f32's unit
    // roundoff of its magnitude, bounded by the quartics' magnitude bound
    // and |c|·|v|), the difference dc and its products; ROUND is twice the
    // unit roundoff and every term is counted twice over.
    let v_abs = abs(v_lo).max(abs(v_hi));
    let x_abs = abs(a).max(abs(b));
    let visc_abs = (abs(c_low) + abs(c_high)) * v_abs;
    let magnitude = low.magnitude_bound(x_abs) + high.magnitude_bound(x_abs) + visc_abs;
    r + worst - 4.0 * ROUND * (magnitude + visc_abs + abs(worst))
}

/// Walks pieces of `[lo_mm, hi_mm]` from its top (`down`) or bottom while
/// `proven(a, b)` holds for each, halving a piece that fails; returns where
/// the proven region ends (`None`: no piece proven).
fn walk(lo_mm: f32, hi_mm: f32, down: bool, proven: impl Fn(f32, f32) -> bool) -> Option<f32> {
    let base_mm = (hi_mm - lo_mm) / PROOF_STEPS as f32;
    let mut width_mm = base_mm;
    let mut at_mm = if down { hi_mm } else { lo_mm };
    let mut edge_mm = None;
    // Each step proves a piece at least `base / REFINE` wide or halves the
    // width: bounded (the cap is far above what a table needs).
    for _ in 0..PROOF_STEPS * 8 {
        let (a, b) = if down && at_mm > lo_mm {
            ((at_mm - width_mm).max(lo_mm), at_mm)
        } else if !down && at_mm < hi_mm {
            (at_mm, (at_mm + width_mm).min(hi_mm))
        } else {
            break;
        };
        if proven(a, b) {
            at_mm = if down { a } else { b };
            edge_mm = Some(at_mm);
            width_mm = base_mm.min(2.0 * width_mm);
        } else {
            // Closer to a crossing the margin shrinks: smaller pieces prove
            // more of the way to it.
            width_mm *= 0.5;
            if width_mm < base_mm / REFINE {
                break;
            }
        }
    }
    edge_mm
}

/// A lower bound of `high(x) − low(x)` as the core computes both in f32,
/// for every x in `[a, b]` (NaN or ≤ 0: not proven).
fn rise_lower_bound(low: &Quartic, high: &Quartic, a: f32, b: f32) -> f32 {
    let c = 0.5 * (a + b);
    // The farthest point of [a, b] from c, rounded up.
    let r = (b - c).max(c - a) * (1.0 + ROUND);
    let x_abs = abs(a).max(abs(b));
    // Both evaluations' error bound anywhere in [a, b] (c included).
    let eval_err = EVAL_ERR * (low.magnitude_bound(x_abs) + high.magnitude_bound(x_abs));
    // |D'| ≤ Σ i·|d_i|·X^{i−1}, d the coefficient differences (highest power first).
    let [h4, h3, h2, h1, _] = high.coeffs;
    let [l4, l3, l2, l1, _] = low.coeffs;
    let slope =
        (((4.0 * abs(h4 - l4)) * x_abs + 3.0 * abs(h3 - l3)) * x_abs + 2.0 * abs(h2 - l2)) * x_abs + abs(h1 - l1);
    let d = high.eval(c) - low.eval(c);
    let spread = slope * (1.0 + 16.0 * ROUND) * r;
    // The exact difference on [a, b] is at least `d − eval_err − spread`
    // (less the rounding of d and of this sum); the f32 forces at any x of
    // the piece may each be off by their share of `eval_err` again.
    d - 2.0 * eval_err - spread - 4.0 * ROUND * (abs(d) + eval_err + spread)
}
