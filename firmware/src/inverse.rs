//! The inverse model: which coil current gives a wanted force.
//!
//! At fixed x and branch the forward model is piecewise linear in current,
//! with a knot at every tabulated current. The answer is the lowest current at
//! which that polyline equals the target, solved exactly on its segment. The
//! force need not grow with current (the paper's 2 A loop lies below its 1.5 A
//! loop in places), so segments are scanned from the lowest current up rather
//! than bisected. If no current gives the target, the knot with the nearest
//! force is returned and flagged `SATURATED_HIGH` or `SATURATED_LOW`.
use crate::flags::Flags;
use crate::model::Branch;
use crate::table::{CurrentEntry, Table};

/// A current with the flags that qualify it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentResult {
    pub current_a: f32,
    pub flags: Flags,
}

impl Table {
    /// Lowest current whose interpolated force on `branch` at `x_mm` equals
    /// `target_force_n`; see the module docs for the saturated cases.
    ///
    /// One pass from the lowest current up: each entry's quartic is evaluated
    /// only when the scan reaches it, and the pass stops at the first segment
    /// that brackets the target, keeping the nearest force seen for the
    /// unreachable case. When x lies in every entry's stroke
    /// (the usual case) the per-entry clamps are skipped.
    pub fn current_for_branch(&self, x_mm: f32, branch: Branch, target_force_n: f32) -> CurrentResult {
        let entries = self.entries();
        let Some(first) = entries.first() else {
            return CurrentResult {
                current_a: 0.0,
                flags: Flags::TABLE_FAULT,
            };
        };
        if !target_force_n.is_finite() {
            return CurrentResult {
                current_a: first.current_a,
                flags: Flags::NON_FINITE_INPUT,
            };
        }
        if self.in_shared_stroke(x_mm) {
            return match branch {
                Branch::Compression => solve(entries, target_force_n, |e| e.compression.eval(x_mm)),
                Branch::Extension => solve(entries, target_force_n, |e| e.extension.eval(x_mm)),
            };
        }
        // Some entry clamps x. A non-finite x is evaluated at each entry's
        // x_min, as the forward model does (and flagged as non-finite only).
        let (x_mm, flag) = if x_mm.is_finite() {
            (x_mm, Flags::X_CLAMPED)
        } else {
            (f32::NEG_INFINITY, Flags::NON_FINITE_INPUT)
        };
        let mut r = solve(entries, target_force_n, |e| e.force_n(x_mm, branch).force_n);
        r.flags |= flag;
        r
    }

    /// [`Table::current_for_branch`] with the branch from the sign of `v_m_s`.
    pub fn current_for(&self, x_mm: f32, v_m_s: f32, target_force_n: f32) -> CurrentResult {
        let mut r = self.current_for_branch(x_mm, Branch::from_velocity(v_m_s), target_force_n);
        if !v_m_s.is_finite() {
            r.flags |= Flags::NON_FINITE_INPUT;
        }
        r
    }
}

/// The inverse over entries whose force at the fixed x is `force_at`.
#[inline(always)]
fn solve(
    entries: &[CurrentEntry],
    target_force_n: f32,
    mut force_at: impl FnMut(&CurrentEntry) -> f32,
) -> CurrentResult {
    let Some(first) = entries.first() else {
        return CurrentResult {
            current_a: 0.0,
            flags: Flags::TABLE_FAULT,
        };
    };
    let mut f0 = force_at(first);
    let mut i0 = first.current_a;
    if f0 == target_force_n {
        return CurrentResult {
            current_a: i0,
            flags: Flags::NONE,
        };
    }
    let below = f0 < target_force_n;
    // Until a crossing, every force lies on the `below` side of the target,
    // so the nearest one so far is the largest (below) or smallest (above).
    // Ties keep the lowest current.
    let mut nearest = (i0, f0);
    for entry in entries.iter().skip(1) {
        let force = force_at(entry);
        // A sign change, or touching the target from above.
        if (force < target_force_n) != below || force == target_force_n {
            let t = (target_force_n - f0) / (force - f0);
            return CurrentResult {
                current_a: i0 + t * (entry.current_a - i0),
                flags: Flags::NONE,
            };
        }
        if (below && force > nearest.1) || (!below && force < nearest.1) {
            nearest = (entry.current_a, force);
        }
        f0 = force;
        i0 = entry.current_a;
    }
    let side = if below {
        Flags::SATURATED_HIGH
    } else {
        Flags::SATURATED_LOW
    };
    CurrentResult {
        current_a: nearest.0,
        flags: side,
    }
}
