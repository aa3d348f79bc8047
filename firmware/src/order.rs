//! Where a table's forces rise with current: proven once, when the table is
//! built, so that the inverse can skip work every period.
//!
//! The inverse scans the entries from the lowest current up and, for a target
//! it cannot reach, keeps the nearest force seen, because in general the
//! force need not rise with current (the paper's 2 A loop lies below its
//! 1.5 A loop in places; the generated table's 1.5 A and 2 A compression
//! quartics cross at x ≈ 0.44 mm). Where the forces do rise strictly with
//! current, the answer needs less: a target below entry 0's force is answered
//! by entry 0 alone, a target above the last entry's by the last, and a
//! bracketing scan need not carry the nearest force. That shortcut must give
//! the scan's answer bit for bit, so "rise strictly" has to hold for the f32
//! forces the core computes, not only for the exact quartics.
//!
//! The proof, per branch and per pair of neighbouring entries (k, k + 1):
//! split the shared stroke into [`PROOF_STEPS`] equal pieces; on each piece
//! `[a, b]` with midpoint `c` the exact difference `D = F_{k+1} − F_k`
//! satisfies `D(x) ≥ D(c) − L·|x − c|`, where `L = Σ i·|d_i|·X^{i−1}` bounds
//! `|D'|` for `|x| ≤ X = max(|a|, |b|)`; `D(c)` is computed in f32 from two
//! Horner evaluations whose error is at most `EVAL_ERR · Σ|c_i|·X^i` each
//! (Horner with separate multiply and add has at most 8 roundings: γ₈ ≈
//! 4.8e-7 of that sum; `EVAL_ERR` is twice it). The piece is proven when that
//! lower bound, less both evaluations' errors again (for the f32 forces at
//! any x of the piece), stays above zero. Walking down from the top of the
//! stroke, the first piece that fails ends the region: the forces rise from
//! its upper end on. Each pair's smallest margin over the region then says
//! how fast the mass may move before the viscous terms (`c_k·v`, interpolated
//! with the quartics) could reorder the entries.
use crate::math::abs;
use crate::model::Branch;
use crate::table::{CurrentEntry, Quartic, MAX_CURRENTS};

/// Pieces of the shared stroke the proof checks (0.03 mm each on a 15 mm
/// stroke): fine enough to end within a few hundredths of a millimetre of a
/// crossing, and a few thousand quartics per table build (not per period).
pub const PROOF_STEPS: u32 = 512;
/// How much finer the pieces get next to a crossing (2¹⁰: a few
/// hundredths of a micrometre), so that the proven regions reach nearly to it.
const REFINE: f32 = 1024.0;

/// A bound on one f32 Horner evaluation's error, relative to `Σ|c_i|·|x|^i`:
/// twice γ₈ (8 roundings at 2⁻²⁴ each).
const EVAL_ERR: f32 = 1.0e-6;
/// f32's unit roundoff, doubled, for the proof's own sums and the viscous
/// terms' roundings.
const ROUND: f32 = 2.0 * f32::EPSILON;

/// Where the forces on one branch rise strictly with current.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ascending {
    /// From here to the top of the shared stroke (+∞: nowhere).
    pub from_mm: f32,
    /// Below this speed (m/s) the viscous terms cannot reorder the entries
    /// there (+∞ when every entry has the same viscous coefficient).
    pub v_max_m_s: f32,
}

impl Ascending {
    pub const NOWHERE: Ascending = Ascending {
        from_mm: f32::INFINITY,
        v_max_m_s: 0.0,
    };
}

/// Where one entry's force on one branch is strictly the largest: from the
/// bottom of the shared stroke up to `to_mm`. Near contact every force is
/// close to 0 and the fitted entries' order is noise, but the largest one
/// stays the largest for a while; there a target above it is answered by
/// that entry alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Top {
    /// Up to here from the bottom of the shared stroke (−∞: nowhere).
    pub to_mm: f32,
    pub index: usize,
    pub v_max_m_s: f32,
}

impl Top {
    pub const NOWHERE: Top = Top {
        to_mm: f32::NEG_INFINITY,
        index: 0,
        v_max_m_s: 0.0,
    };
}

/// The proof above for `branch` of `entries` on the shared stroke
/// `[lo_mm, hi_mm]` (every entry fitted on it), with viscous coefficients
/// `viscous` (same index as the entries).
pub fn ascending(
    entries: &[CurrentEntry],
    viscous: &[f32; MAX_CURRENTS],
    branch: Branch,
    lo_mm: f32,
    hi_mm: f32,
) -> Ascending {
    let mut pairs = [(0, 0); MAX_CURRENTS];
    for (k, p) in pairs.iter_mut().enumerate() {
        *p = (k, k + 1);
    }
    let n = entries.len().saturating_sub(1);
    match prove(
        entries,
        viscous,
        branch,
        lo_mm,
        hi_mm,
        pairs.get(..n).unwrap_or(&[]),
        Walk::Down,
    ) {
        Some((from_mm, v_max_m_s)) => Ascending { from_mm, v_max_m_s },
        None => Ascending::NOWHERE,
    }
}

/// The entry with the largest force at the bottom of the shared stroke, and
/// how far up it provably stays strictly the largest.
pub fn top(entries: &[CurrentEntry], viscous: &[f32; MAX_CURRENTS], branch: Branch, lo_mm: f32, hi_mm: f32) -> Top {
    let mut index = 0;
    let mut best = f32::NEG_INFINITY;
    for (k, e) in entries.iter().enumerate() {
        let f = quartic(e, branch).eval(lo_mm);
        if f > best {
            (best, index) = (f, k);
        }
    }
    let mut pairs = [(0, 0); MAX_CURRENTS];
    let mut n = 0;
    for k in (0..entries.len()).filter(|k| *k != index) {
        if let Some(p) = pairs.get_mut(n) {
            *p = (k, index);
            n += 1;
        }
    }
    match prove(
        entries,
        viscous,
        branch,
        lo_mm,
        hi_mm,
        pairs.get(..n).unwrap_or(&[]),
        Walk::Up,
    ) {
        Some((to_mm, v_max_m_s)) => Top {
            to_mm,
            index,
            v_max_m_s,
        },
        None => Top::NOWHERE,
    }
}

fn quartic(e: &CurrentEntry, branch: Branch) -> Quartic {
    match branch {
        Branch::Compression => e.compression,
        Branch::Extension => e.extension,
    }
}

/// Which end of the stroke the proven region starts from.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Walk {
    /// From the top down: returns the region's lower end.
    Down,
    /// From the bottom up: returns the region's upper end.
    Up,
}

/// Proves `F_high > F_low` (as f32, see the module docs) for every
/// `(low, high)` of `pairs`, piece by piece from one end of `[lo_mm, hi_mm]`
/// until a piece fails. Returns the region's other end and the speed below
/// which the viscous terms keep the order; `None` if no piece is proven.
fn prove(
    entries: &[CurrentEntry],
    viscous: &[f32; MAX_CURRENTS],
    branch: Branch,
    lo_mm: f32,
    hi_mm: f32,
    pairs: &[(usize, usize)],
    walk: Walk,
) -> Option<(f32, f32)> {
    // `!(lo < hi)`: an empty shared stroke (or NaN) proves nothing.
    if !(lo_mm < hi_mm) || !lo_mm.is_finite() || !hi_mm.is_finite() {
        return None;
    }
    let q = |k: usize| entries.get(k).map(|e| quartic(e, branch));
    // Each pair's smallest proven margin so far (N).
    let mut margin_n = [f32::INFINITY; MAX_CURRENTS];
    let base_mm = (hi_mm - lo_mm) / PROOF_STEPS as f32;
    let mut width_mm = base_mm;
    let mut edge_mm = None;
    let mut at_mm = match walk {
        Walk::Down => hi_mm,
        Walk::Up => lo_mm,
    };
    // Each step either proves a piece at least `base / 2^REFINE` wide or
    // halves the width: bounded (the cap is far above what a table needs).
    for _ in 0..PROOF_STEPS * 8 {
        let (a, b) = match walk {
            Walk::Down if at_mm > lo_mm => ((at_mm - width_mm).max(lo_mm), at_mm),
            Walk::Up if at_mm < hi_mm => (at_mm, (at_mm + width_mm).min(hi_mm)),
            _ => break,
        };
        let mut piece_margin_n = [f32::INFINITY; MAX_CURRENTS];
        let proven = pairs.iter().zip(piece_margin_n.iter_mut()).all(|(&(low, high), m)| {
            let (Some(low), Some(high)) = (q(low), q(high)) else {
                return false;
            };
            *m = rise_lower_bound(&low, &high, a, b);
            // `> 0` is false for NaN too.
            *m > 0.0
        });
        if proven {
            for (m, p) in margin_n.iter_mut().zip(piece_margin_n) {
                *m = m.min(p);
            }
            at_mm = if walk == Walk::Down { a } else { b };
            edge_mm = Some(at_mm);
            width_mm = base_mm.min(2.0 * width_mm);
        } else {
            // Closer to a crossing the margin shrinks: smaller pieces
            // prove more of the way to it.
            width_mm *= 0.5;
            if width_mm < base_mm / REFINE {
                break;
            }
        }
    }
    let edge_mm = edge_mm?;
    // The viscous terms add `(c_high − c_low)·v` to each pair's difference,
    // and their products and sums round: bounded at the region's largest |x|.
    let x_abs = match walk {
        Walk::Down => abs(edge_mm).max(abs(hi_mm)),
        Walk::Up => abs(lo_mm).max(abs(edge_mm)),
    };
    let mut v_max_m_s = f32::INFINITY;
    for (&(low, high), m) in pairs.iter().zip(margin_n) {
        let c = |k: usize| viscous.get(k).copied().unwrap_or(0.0);
        let (c0, c1) = (c(low), c(high));
        let rate = abs(c1 - c0) * (1.0 + ROUND) + 4.0 * ROUND * (abs(c0) + abs(c1));
        if rate == 0.0 {
            continue;
        }
        let sizes =
            q(low).map_or(0.0, |p| p.magnitude_bound(x_abs)) + q(high).map_or(0.0, |p| p.magnitude_bound(x_abs));
        // Half the speed at which the margin would be used up.
        let v = 0.5 * (m - 2.0 * ROUND * sizes) / rate;
        v_max_m_s = if v > 0.0 { v_max_m_s.min(v) } else { 0.0 };
    }
    Some((edge_mm, v_max_m_s))
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
