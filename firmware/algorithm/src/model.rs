//! The forward model: force from displacement, velocity direction and current.
//!
//! Rules (documented in the README too):
//! - Branch: compression when v > 0, extension otherwise. The stateful
//!   [`BranchSelector`] adds a small velocity band so sensor noise near
//!   turn-around does not flip the branch every sample.
//! - Each quartic is evaluated with Horner's scheme.
//! - Between tabulated currents the force is interpolated linearly in current
//!   (the paper's Eq. X, written correctly):
//!   `F(I) = F_k + (I − I_k)/(I_{k+1} − I_k) · (F_{k+1} − F_k)`. A version 2
//!   table with a saturation current `I_s` interpolates linearly in
//!   `w = tanh(I/I_s)` instead (magnetic saturation), and adds each entry's
//!   viscous term `c_k·v` to its quartic before interpolating.
//! - Outside the table's current range the current is clamped
//!   (`CURRENT_CLAMPED`). Outside an entry's fitted stroke, x is clamped to it
//!   (`X_CLAMPED`): a quartic extrapolated beyond its data is meaningless.
//! - NaN or infinite inputs are replaced (x → x_min, current → lowest) and
//!   flagged `NON_FINITE_INPUT`, so the result is always finite.
pub use crate::entry::Branch;
use crate::flags::Flags;
use crate::math;
pub use crate::saturation::interpolation_variable;
use crate::table::{CurrentEntry, Table};

/// Fastest velocity the viscous term takes (m/s): beyond any drop test, and
/// keeps `c·v` finite for any finite v.
pub const VISCOUS_V_LIMIT_M_S: f32 = 100.0;

/// The velocity the viscous term uses: clamped to ±[`VISCOUS_V_LIMIT_M_S`],
/// NaN → 0.
#[inline]
pub fn viscous_velocity(v_m_s: f32) -> f32 {
    // One comparison on the usual path (false for NaN and beyond the limit).
    if math::abs(v_m_s) <= VISCOUS_V_LIMIT_M_S {
        v_m_s
    } else if v_m_s.is_nan() {
        0.0
    } else {
        math::clamp(v_m_s, -VISCOUS_V_LIMIT_M_S, VISCOUS_V_LIMIT_M_S)
    }
}

/// Branch choice with hysteresis: switches to compression only above
/// `+band_m_s` and to extension only below `-band_m_s`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BranchSelector {
    band_m_s: f32,
    branch: Branch,
}

impl BranchSelector {
    /// A non-finite or negative band is treated as zero (no hysteresis).
    pub fn new(band_m_s: f32, initial: Branch) -> Self {
        let band_m_s = if band_m_s.is_finite() && band_m_s > 0.0 {
            band_m_s
        } else {
            0.0
        };
        Self {
            band_m_s,
            branch: initial,
        }
    }

    /// Feeds one velocity sample; NaN keeps the current branch.
    #[inline]
    pub fn update(&mut self, v_m_s: f32) -> Branch {
        if v_m_s > self.band_m_s {
            self.branch = Branch::Compression;
        } else if v_m_s < -self.band_m_s {
            self.branch = Branch::Extension;
        }
        self.branch
    }

    pub fn branch(&self) -> Branch {
        self.branch
    }
}

/// A force with the flags that qualify it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceResult {
    pub force_n: f32,
    pub flags: Flags,
}

impl CurrentEntry {
    /// This entry's quartic for `branch` at `x_mm`, with x clamped to the
    /// fitted stroke.
    #[inline]
    pub fn force_n(&self, x_mm: f32, branch: Branch) -> ForceResult {
        let mut flags = Flags::NONE;
        let x = if !x_mm.is_finite() {
            flags |= Flags::NON_FINITE_INPUT;
            self.x_min_mm
        } else if x_mm < self.x_min_mm || x_mm > self.x_max_mm {
            flags |= Flags::X_CLAMPED;
            math::clamp(x_mm, self.x_min_mm, self.x_max_mm)
        } else {
            x_mm
        };
        let quartic = match branch {
            Branch::Compression => &self.compression,
            Branch::Extension => &self.extension,
        };
        ForceResult {
            force_n: quartic.eval(x),
            flags,
        }
    }
}

/// Where a current falls in the table: between entries `lower` and `lower + 1`
/// at fraction `t` ∈ [0, 1) — or exactly on one entry with `t = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentSegment {
    pub lower: usize,
    pub t: f32,
    pub flags: Flags,
}

impl Table {
    /// Locates `current_a` in the table, clamping it to the tabulated range.
    pub fn segment(&self, current_a: f32) -> CurrentSegment {
        let entries = self.entries();
        let (lo, hi) = self.current_range_a();
        let last = entries.len().saturating_sub(1);
        if !current_a.is_finite() {
            return CurrentSegment {
                lower: 0,
                t: 0.0,
                flags: Flags::NON_FINITE_INPUT,
            };
        }
        if current_a <= lo {
            let flags = if current_a < lo {
                Flags::CURRENT_CLAMPED
            } else {
                Flags::NONE
            };
            return CurrentSegment {
                lower: 0,
                t: 0.0,
                flags,
            };
        }
        if current_a >= hi {
            let flags = if current_a > hi {
                Flags::CURRENT_CLAMPED
            } else {
                Flags::NONE
            };
            return CurrentSegment {
                lower: last,
                t: 0.0,
                flags,
            };
        }
        // lo < current_a < hi, so some pair brackets it.
        let w = interpolation_variable(current_a, self.terms().saturation_current_a);
        for (k, pair) in entries.windows(2).enumerate() {
            if let [_, b] = pair {
                if current_a < b.current_a {
                    let (w0, w1) = (self.knot(k), self.knot(k.wrapping_add(1)));
                    // In [0, 1) even if the approximate tanh strays by an ulp.
                    let t = math::clamp((w - w0) / (w1 - w0), 0.0, 1.0);
                    return CurrentSegment {
                        lower: k,
                        t,
                        flags: Flags::NONE,
                    };
                }
            }
        }
        CurrentSegment {
            lower: last,
            t: 0.0,
            flags: Flags::NONE,
        }
    }

    /// Force on a given branch at `x_mm` and `current_a` (interpolated), at
    /// rest: a version 2 table's viscous term is left out (see
    /// [`Table::force_on_branch_v`]).
    pub fn force_on_branch(&self, x_mm: f32, branch: Branch, current_a: f32) -> ForceResult {
        self.force_on_branch_v(x_mm, 0.0, branch, current_a)
    }

    /// Force on a given branch at `x_mm`, velocity `v_m_s` (for the viscous
    /// term only, see [`viscous_velocity`]) and `current_a`.
    pub fn force_on_branch_v(&self, x_mm: f32, v_m_s: f32, branch: Branch, current_a: f32) -> ForceResult {
        let seg = self.segment(current_a);
        let entries = self.entries();
        let v = viscous_velocity(v_m_s);
        // Inside every entry's stroke no x is clamped: the quartic alone, with
        // the same result and no flag, without the per-entry range checks.
        let shared = self.in_shared_stroke(x_mm);
        let at = |e: &CurrentEntry| {
            if shared {
                let quartic = match branch {
                    Branch::Compression => &e.compression,
                    Branch::Extension => &e.extension,
                };
                ForceResult {
                    force_n: quartic.eval(x_mm),
                    flags: Flags::NONE,
                }
            } else {
                e.force_n(x_mm, branch)
            }
        };
        let lower = match entries.get(seg.lower) {
            Some(e) => {
                let mut r = at(e);
                r.force_n += self.viscous(seg.lower) * v;
                r
            }
            None => {
                return ForceResult {
                    force_n: 0.0,
                    flags: Flags::TABLE_FAULT,
                }
            }
        };
        let mut flags = seg.flags | lower.flags;
        let force_n = match entries.get(seg.lower.wrapping_add(1)) {
            Some(upper_entry) if seg.t > 0.0 => {
                let upper = at(upper_entry);
                flags |= upper.flags;
                let upper_n = upper.force_n + self.viscous(seg.lower.wrapping_add(1)) * v;
                lower.force_n + seg.t * (upper_n - lower.force_n)
            }
            _ => lower.force_n,
        };
        ForceResult { force_n, flags }
    }

    /// The model: force at `x_mm` with the branch picked from the sign of
    /// `v_m_s` (no hysteresis; the controller uses [`BranchSelector`]), plus
    /// a version 2 table's viscous term.
    pub fn force(&self, x_mm: f32, v_m_s: f32, current_a: f32) -> ForceResult {
        let mut r = self.force_on_branch_v(x_mm, v_m_s, Branch::from_velocity(v_m_s), current_a);
        if !v_m_s.is_finite() {
            r.flags |= Flags::NON_FINITE_INPUT;
        }
        r
    }
}
