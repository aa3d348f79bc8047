//! The inverse model: which coil current gives a wanted force.
//!
//! At fixed x, v and branch the forward model is piecewise linear in current
//! (in `tanh(I/I_s)` under a version 2 saturation term), with a knot at every
//! tabulated current. The answer is the lowest current at which that polyline
//! equals the target, solved exactly on its segment (under saturation the
//! current is then mapped back through atanh: by a polynomial fitted per
//! segment when the table is built, within a bound proven there,
//! `saturation.rs`). The
//! force need not grow with current (the paper's 2 A loop lies below its 1.5 A
//! loop in places), so segments are scanned from the lowest current up rather
//! than bisected. If no current gives the target, the knot with the nearest
//! force is returned and flagged `SATURATED_HIGH` or `SATURATED_LOW`. Where
//! the table's forces are proven to rise with current, or one entry's to be
//! the largest (`order.rs`, when the table is built), the same answer comes
//! from fewer quartics and without carrying the nearest force.
use crate::flags::Flags;
use crate::math;
use crate::model::Branch;
use crate::table::{CurrentEntry, Entries, Table};

/// A current with the flags that qualify it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentResult {
    pub current_a: f32,
    pub flags: Flags,
}

/// [`CurrentResult`] with what the law reuses from the same scan
/// ([`Table::plan_current_v`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanResult {
    pub current_a: f32,
    pub flags: Flags,
    /// The model's force at `current_a`: the target when it is met, else
    /// the nearest force (N). The law keeps it as the force one period old.
    pub force_n: f32,
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
        self.current_for_branch_v(x_mm, 0.0, branch, target_force_n)
    }

    /// [`Table::current_for_branch`] at velocity `v_m_s`, which a version 2
    /// table's viscous term depends on (see [`crate::model::viscous_velocity`]).
    pub fn current_for_branch_v(&self, x_mm: f32, v_m_s: f32, branch: Branch, target_force_n: f32) -> CurrentResult {
        let r = self.checked_current_v(x_mm, v_m_s, branch, target_force_n);
        CurrentResult {
            current_a: r.current_a,
            flags: r.flags,
        }
    }

    /// [`Table::current_for_branch_v`] with the force at the result, for the
    /// law (inlined there, so the scan is the same code). The law's inputs
    /// spare it three checks the public inverse makes: `target_force_n` is
    /// finite, `|v_m_s|` is within [`crate::model::VISCOUS_V_LIMIT_M_S`],
    /// and v ≥ 0 on `branch` = compression (the law plans only while
    /// compressing). Outside them the answer is unspecified (at worst a
    /// NaN current, on which the law fails safe with `TABLE_FAULT`).
    #[inline(always)]
    pub(crate) fn plan_current_v(&self, x_mm: f32, v_m_s: f32, target_force_n: f32) -> PlanResult {
        let branch = Branch::Compression;
        if self.has_viscous() {
            let facts = self.order_facts(branch);
            // v ≥ 0 ≥ the compression facts' lowest velocity.
            let in_range = || v_m_s <= facts.v_max_m_s;
            self.solve_viscous(x_mm, v_m_s, branch, target_force_n, in_range)
        } else {
            self.solve_at(x_mm, branch, target_force_n, || true, true, |_, f| f)
        }
    }

    /// The inverse at any inputs: a non-finite target is answered with the
    /// lowest current, flagged; the viscous term's velocity is clamped.
    #[inline(always)]
    fn checked_current_v(&self, x_mm: f32, v_m_s: f32, branch: Branch, target_force_n: f32) -> PlanResult {
        if !target_force_n.is_finite() {
            return PlanResult {
                current_a: self.entry_array().first().current_a,
                flags: Flags::NON_FINITE_INPUT,
                force_n: 0.0,
            };
        }
        if self.has_viscous() {
            let v = crate::model::viscous_velocity(v_m_s);
            let facts = self.order_facts(branch);
            let in_range = || v >= facts.v_min_m_s && v <= facts.v_max_m_s;
            self.solve_viscous(x_mm, v, branch, target_force_n, in_range)
        } else {
            // No rate term: nothing per entry beyond the quartic, and the
            // facts hold at any velocity.
            self.solve_at(x_mm, branch, target_force_n, || true, true, |_, f| f)
        }
    }

    /// The inverse with each entry's viscous term at velocity `v` (within
    /// the clamp). A viscous term can reorder the entries at speed: the
    /// order facts hold for the velocities they were proven for only
    /// (`in_range`, asked only where a fact's x region applies). No
    /// "largest entry" fact: near contact it rarely holds at every
    /// velocity, and its path cost the full scan there 7 instructions.
    #[inline(always)]
    fn solve_viscous(
        &self,
        x_mm: f32,
        v: f32,
        branch: Branch,
        target_force_n: f32,
        in_range: impl Fn() -> bool,
    ) -> PlanResult {
        let c = &self.terms().viscous_n_s_per_m;
        self.solve_at(x_mm, branch, target_force_n, in_range, false, |k, f| {
            f + c.get(k).copied().unwrap_or(0.0) * v
        })
    }

    /// The inverse with entry k's quartic force `f` replaced by `with_extra(k, f)`
    /// (the identity without a rate term, so nothing is added per entry).
    #[inline(always)]
    fn solve_at(
        &self,
        x_mm: f32,
        branch: Branch,
        target_force_n: f32,
        in_range: impl Fn() -> bool,
        use_top: bool,
        with_extra: impl Fn(usize, f32) -> f32,
    ) -> PlanResult {
        let entries = self.entry_array();
        // Where the forces are proven to rise with current, or one entry's
        // to be the largest (order.rs), the same answer as the scan below
        // comes from fewer quartics.
        let order = self.order_facts(branch);
        // Below `scan_below_mm` (the ascending region's start, at most just
        // above the shared stroke) an x in the shared stroke needs only its
        // lower end tested; NaN fails every comparison: clamped path.
        let in_stroke = if x_mm < self.scan_below_mm(branch) {
            if x_mm >= self.shared_x_min_mm() {
                if use_top && x_mm <= order.top_to_mm && in_range() {
                    let bottom = || x_mm >= order.bottom_from_mm;
                    let r = match branch {
                        Branch::Compression => solve_below_top(entries, order.top, target_force_n, bottom, |k, e| {
                            with_extra(k, e.compression.eval(x_mm))
                        }),
                        Branch::Extension => solve_below_top(entries, order.top, target_force_n, bottom, |k, e| {
                            with_extra(k, e.extension.eval(x_mm))
                        }),
                    };
                    return self.current_of(r);
                }
                true
            } else {
                false
            }
        } else if x_mm <= self.shared_x_max_mm() {
            if in_range() {
                let r = match branch {
                    Branch::Compression => {
                        solve_ascending(entries, target_force_n, |k, e| with_extra(k, e.compression.eval(x_mm)))
                    }
                    Branch::Extension => {
                        solve_ascending(entries, target_force_n, |k, e| with_extra(k, e.extension.eval(x_mm)))
                    }
                };
                return self.current_of(r);
            }
            true
        } else {
            false
        };
        if in_stroke {
            // Entry 0 proven the smallest: asked only when a target lies
            // below it (the region lies in the shared stroke).
            let bottom = || x_mm >= order.bottom_from_mm && in_range();
            let r = match branch {
                Branch::Compression => solve(entries, target_force_n, bottom, |k, e| {
                    with_extra(k, e.compression.eval(x_mm))
                }),
                Branch::Extension => solve(entries, target_force_n, bottom, |k, e| {
                    with_extra(k, e.extension.eval(x_mm))
                }),
            };
            return self.current_of(r);
        }
        // Some entry clamps x. A non-finite x is evaluated at each entry's
        // x_min, as the forward model does (and flagged as non-finite only).
        let (flag, x_mm) = if x_mm.is_finite() {
            (Flags::X_CLAMPED, x_mm)
        } else {
            (Flags::NON_FINITE_INPUT, f32::NEG_INFINITY)
        };
        // A clamped entry's force is its precomputed stroke end.
        let r = solve(
            entries,
            target_force_n,
            || false,
            |k, e| with_extra(k, self.clamped_force_n(k, e, branch, x_mm)),
        );
        let mut r = self.current_of(r);
        r.flags |= flag;
        r
    }

    /// The current at fraction `t` of segment `lower` (t = 0 and t = 1:
    /// exactly the entries' currents): linear in I, or under saturation
    /// through the segment's map (`saturation.rs`): the polynomial fitted
    /// when the table was built, inlined (out of line, a call and its
    /// register moves cost the control step ~15 instructions), else the
    /// exact atanh.
    #[inline]
    fn current_of(&self, s: Solution) -> PlanResult {
        let (i0, i1) = (s.i0, s.i1);
        // A knot's result is its current. A bracket's t is above 0 (the
        // target differs from the force at its lower end; an underflow to
        // 0 maps to i0 anyway): every site sets `on_knot` as a constant,
        // so the compiler drops this test where it is known.
        let current_a = if s.on_knot {
            i0
        } else {
            // A fitted segment first (one test for the saturated tables'
            // usual case); a linear table's segments are never fitted.
            let map = self.segment_map(s.lower);
            if map.fitted {
                let current_a = map.eval(i0, s.t);
                // At least i1 at t = 1, never below i0 (`saturation.rs`).
                if current_a > i1 {
                    i1
                } else {
                    current_a
                }
            } else if s.t >= 1.0 {
                i1
            } else if self.saturated() {
                self.exact_saturated_current_a(s, i0, i1)
            } else {
                i0 + s.t * (i1 - i0)
            }
        };
        PlanResult {
            current_a,
            flags: s.flags,
            force_n: s.force_n,
        }
    }

    /// The current at fraction `0 < t < 1` of segment `lower` under
    /// saturation where no polynomial was fitted (`saturation.rs`):
    /// `I_s·atanh(w0 + t·Δw)` through the logarithm.
    #[inline(never)]
    fn exact_saturated_current_a(&self, s: Solution, i0: f32, i1: f32) -> f32 {
        let w0 = self.knot(s.lower);
        let w = w0 + s.t * (self.knot(s.lower.wrapping_add(1)) - w0);
        math::clamp(self.terms().saturation_current_a * math::atanh(w), i0, i1)
    }

    /// [`Table::current_for_branch_v`] with the branch from the sign of `v_m_s`.
    pub fn current_for(&self, x_mm: f32, v_m_s: f32, target_force_n: f32) -> CurrentResult {
        let mut r = self.current_for_branch_v(x_mm, v_m_s, Branch::from_velocity(v_m_s), target_force_n);
        if !v_m_s.is_finite() {
            r.flags |= Flags::NON_FINITE_INPUT;
        }
        r
    }
}

/// Where the inverse landed: fraction `t` of the segment from entry `lower`
/// (current `i0`) to `lower + 1` (`i1`); t = 0: on entry `lower` itself.
/// The scan carries the currents so the result needs no second lookup.
#[derive(Clone, Copy, Debug)]
struct Solution {
    /// On entry `lower` itself (t = 0): no segment to map through.
    on_knot: bool,
    lower: usize,
    i0: f32,
    i1: f32,
    t: f32,
    flags: Flags,
    /// The force at the result (the target when met).
    force_n: f32,
}

/// The inverse over entries whose force at the fixed x is `force_at(index, entry)`.
// `!(force < target)` on purpose: a NaN force must end the below-target scan
// (as the comparison `(force < target) != below` did), in one comparison.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[inline(always)]
fn solve(
    entries: Entries<'_>,
    target_force_n: f32,
    bottom: impl Fn() -> bool,
    mut force_at: impl FnMut(usize, &CurrentEntry) -> f32,
) -> Solution {
    let first = entries.first();
    let f0 = force_at(0, first);
    solve_from(entries, first, f0, target_force_n, bottom, force_at)
}

/// [`solve`] once entry 0 (`first`)'s force `f0` is known. `bottom`: entry
/// 0's force is proven strictly the smallest (`order.rs`), so a target below
/// it is answered by entry 0 without scanning the rest.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[inline(always)]
fn solve_from(
    entries: Entries<'_>,
    first: &CurrentEntry,
    mut f0: f32,
    target_force_n: f32,
    bottom: impl Fn() -> bool,
    mut force_at: impl FnMut(usize, &CurrentEntry) -> f32,
) -> Solution {
    // One loop per side of the target, so each entry costs one comparison
    // for the crossing. Until a crossing, every force lies on the starting
    // side, so the nearest one so far is the largest (below) or smallest
    // (above); ties keep the lowest current. A saturated result reports the
    // top (or bottom) segment, not the nearest entry's, so the scan need not
    // carry an index.
    let mut nearest = (f0, first.current_a);
    let mut i_prev = first.current_a;
    if f0 < target_force_n {
        for (k, entry) in entries.rest() {
            if k >= entries.len {
                break;
            }
            let force = force_at(k, entry);
            // Reaching the target (or a NaN force, which brackets nothing
            // sensible but must not pass for "below").
            if !(force < target_force_n) {
                return bracket(k, (i_prev, entry.current_a), f0, force, target_force_n);
            }
            if force > nearest.0 {
                nearest = (force, entry.current_a);
            }
            (f0, i_prev) = (force, entry.current_a);
        }
        return saturated(entries.last_index(), nearest.1, nearest.0, Flags::SATURATED_HIGH);
    }
    if f0 == target_force_n {
        return saturated(0, first.current_a, f0, Flags::NONE);
    }
    if bottom() {
        // Entry 0 is proven the smallest force: nothing falls to the target.
        return saturated(0, first.current_a, f0, Flags::SATURATED_LOW);
    }
    // Every force so far lies above the target, the nearest lowest of them,
    // so a force that falls to the target falls below the nearest first: an
    // entry at or above the nearest costs one comparison. (Near contact,
    // where the fitted entries cross, this is the long scan: a target below
    // them all.) A NaN entry 0 is never the nearer: every force is then
    // tested against the target, and none replaces it.
    for (k, entry) in entries.rest() {
        if k >= entries.len {
            break;
        }
        let force = force_at(k, entry);
        if !(force >= nearest.0) {
            // Falling to or through the target from above.
            if force <= target_force_n {
                return bracket(k, (i_prev, entry.current_a), f0, force, target_force_n);
            }
            if force < nearest.0 {
                nearest = (force, entry.current_a);
            }
        }
        (f0, i_prev) = (force, entry.current_a);
    }
    saturated(0, nearest.1, nearest.0, Flags::SATURATED_LOW)
}

/// [`solve`] where the forces are proven to rise strictly with current
/// (`order.rs`): a target at or below entry 0's force is answered by entry 0,
/// and the first entry at or above the target brackets it; none: the last
/// entry, the largest force. The scan's answer, without the nearest force.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[inline(always)]
fn solve_ascending(
    entries: Entries<'_>,
    target_force_n: f32,
    mut force_at: impl FnMut(usize, &CurrentEntry) -> f32,
) -> Solution {
    let first = entries.first();
    let f0 = force_at(0, first);
    if !(f0 < target_force_n) {
        let side = if f0 == target_force_n {
            Flags::NONE
        } else {
            Flags::SATURATED_LOW
        };
        return saturated(0, first.current_a, f0, side);
    }
    let (mut f_prev, mut i_prev) = (f0, first.current_a);
    for (k, entry) in entries.rest() {
        if k >= entries.len {
            break;
        }
        let force = force_at(k, entry);
        if !(force < target_force_n) {
            return bracket(k, (i_prev, entry.current_a), f_prev, force, target_force_n);
        }
        (f_prev, i_prev) = (force, entry.current_a);
    }
    saturated(entries.last_index(), i_prev, f_prev, Flags::SATURATED_HIGH)
}

/// [`solve`] where entry `top` is proven to give strictly the largest force
/// (`order.rs`): a target above it is answered by it, and a target below it
/// is first reached at or before it, so the scan from below needs no
/// nearest force and stops at `top`. A target at or below entry 0's force
/// takes the scan from above.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[inline(always)]
fn solve_below_top(
    entries: Entries<'_>,
    top: usize,
    target_force_n: f32,
    bottom: impl Fn() -> bool,
    mut force_at: impl FnMut(usize, &CurrentEntry) -> f32,
) -> Solution {
    let first = entries.first();
    let Some(top_entry) = entries.all.get(top) else {
        return saturated(0, 0.0, 0.0, Flags::TABLE_FAULT);
    };
    let f0 = force_at(0, first);
    if !(f0 < target_force_n) {
        return solve_from(entries, first, f0, target_force_n, bottom, force_at);
    }
    let f_top = force_at(top, top_entry);
    if f_top < target_force_n {
        return saturated(entries.last_index(), top_entry.current_a, f_top, Flags::SATURATED_HIGH);
    }
    let (mut f_prev, mut i_prev) = (f0, first.current_a);
    for (k, entry) in entries.rest() {
        if k >= top {
            break;
        }
        let force = force_at(k, entry);
        if !(force < target_force_n) {
            return bracket(k, (i_prev, entry.current_a), f_prev, force, target_force_n);
        }
        (f_prev, i_prev) = (force, entry.current_a);
    }
    bracket(top, (i_prev, top_entry.current_a), f_prev, f_top, target_force_n)
}

/// The target lies between entry `k − 1` (force `f0`) and entry `k` (`f1`),
/// whose currents are `currents`.
#[inline(always)]
fn bracket(k: usize, currents: (f32, f32), f0: f32, f1: f32, target_force_n: f32) -> Solution {
    Solution {
        on_knot: false,
        lower: k.wrapping_sub(1),
        i0: currents.0,
        i1: currents.1,
        t: (target_force_n - f0) / (f1 - f0),
        flags: Flags::NONE,
        force_n: target_force_n,
    }
}

/// On entry `lower` (current `current_a`) itself: the target was met
/// there, or no segment brackets it and this is the nearest knot, flagged
/// with its side.
#[inline(always)]
fn saturated(lower: usize, current_a: f32, force_n: f32, side: Flags) -> Solution {
    Solution {
        on_knot: true,
        lower,
        i0: current_a,
        i1: current_a,
        t: 0.0,
        flags: side,
        force_n,
    }
}
