//! The forward model: force from displacement, velocity direction and current.
//!
//! Rules (documented in the README too):
//! - Branch: compression when v > 0, extension otherwise. The stateful
//!   [`BranchSelector`] adds a small velocity band so sensor noise near
//!   turn-around does not flip the branch every sample.
//! - Each quartic is evaluated with Horner's scheme.
//! - Between tabulated currents the force is interpolated linearly in current
//!   (the paper's Eq. X, written correctly):
//!   `F(I) = F_k + (I − I_k)/(I_{k+1} − I_k) · (F_{k+1} − F_k)`.
//! - Outside the table's current range the current is clamped
//!   (`CURRENT_CLAMPED`). Outside an entry's fitted stroke, x is clamped to it
//!   (`X_CLAMPED`): a quartic extrapolated beyond its data is meaningless.
//! - NaN or infinite inputs are replaced (x → x_min, current → lowest) and
//!   flagged `NON_FINITE_INPUT`, so the result is always finite.
use crate::flags::Flags;
use crate::math;
use crate::table::{CurrentEntry, Table};

/// Which of an entry's two quartics applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Branch {
    /// Loading, v > 0.
    Compression,
    /// Unloading, v ≤ 0.
    Extension,
}

impl Branch {
    /// The paper's rule: compression when v > 0, else extension (NaN → extension).
    #[inline]
    pub fn from_velocity(v_m_s: f32) -> Branch {
        if v_m_s > 0.0 {
            Branch::Compression
        } else {
            Branch::Extension
        }
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
        for (k, pair) in entries.windows(2).enumerate() {
            if let [a, b] = pair {
                if current_a < b.current_a {
                    let t = (current_a - a.current_a) / (b.current_a - a.current_a);
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

    /// Force on a given branch at `x_mm` and `current_a` (interpolated).
    pub fn force_on_branch(&self, x_mm: f32, branch: Branch, current_a: f32) -> ForceResult {
        let seg = self.segment(current_a);
        let entries = self.entries();
        let lower = match entries.get(seg.lower) {
            Some(e) => e.force_n(x_mm, branch),
            None => {
                return ForceResult {
                    force_n: 0.0,
                    flags: Flags::TABLE_FAULT,
                }
            }
        };
        let mut flags = seg.flags | lower.flags;
        let force_n = match entries.get(seg.lower + 1) {
            Some(upper_entry) if seg.t > 0.0 => {
                let upper = upper_entry.force_n(x_mm, branch);
                flags |= upper.flags;
                lower.force_n + seg.t * (upper.force_n - lower.force_n)
            }
            _ => lower.force_n,
        };
        ForceResult { force_n, flags }
    }

    /// The paper's model: force at `x_mm` with the branch picked from the sign
    /// of `v_m_s` (no hysteresis; the controller uses [`BranchSelector`]).
    pub fn force(&self, x_mm: f32, v_m_s: f32, current_a: f32) -> ForceResult {
        let mut r = self.force_on_branch(x_mm, Branch::from_velocity(v_m_s), current_a);
        if !v_m_s.is_finite() {
            r.flags |= Flags::NON_FINITE_INPUT;
        }
        r
    }
}
