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
use crate::table::{Table, MAX_CURRENTS};

/// A current with the flags that qualify it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentResult {
    pub current_a: f32,
    pub flags: Flags,
}

impl Table {
    /// Lowest current whose interpolated force on `branch` at `x_mm` equals
    /// `target_force_n`; see the module docs for the saturated cases.
    pub fn current_for_branch(&self, x_mm: f32, branch: Branch, target_force_n: f32) -> CurrentResult {
        let entries = self.entries();
        let (lowest_a, _) = self.current_range_a();
        if !target_force_n.is_finite() {
            return CurrentResult {
                current_a: lowest_a,
                flags: Flags::NON_FINITE_INPUT,
            };
        }

        let mut flags = Flags::NONE;
        let mut forces = [0f32; MAX_CURRENTS];
        for (slot, entry) in forces.iter_mut().zip(entries) {
            let r = entry.force_n(x_mm, branch);
            flags |= r.flags;
            *slot = r.force_n;
        }
        let forces = forces.get(..entries.len()).unwrap_or(&[]);

        // First segment that brackets the target, from the lowest current up.
        let mut previous: Option<(f32, f32)> = None;
        for (entry, &force) in entries.iter().zip(forces) {
            if force == target_force_n {
                return CurrentResult {
                    current_a: entry.current_a,
                    flags,
                };
            }
            if let Some((i0, f0)) = previous {
                if (f0 < target_force_n) != (force < target_force_n) {
                    let t = (target_force_n - f0) / (force - f0);
                    let current_a = i0 + t * (entry.current_a - i0);
                    return CurrentResult { current_a, flags };
                }
            }
            previous = Some((entry.current_a, force));
        }

        // Unreachable: the nearest force is the largest or smallest knot.
        let above_all = forces.iter().all(|&f| f < target_force_n);
        let mut best: Option<(f32, f32)> = None;
        for (entry, &force) in entries.iter().zip(forces) {
            let better = match best {
                None => true,
                Some((_, best_force)) if above_all => force > best_force,
                Some((_, best_force)) => force < best_force,
            };
            if better {
                best = Some((entry.current_a, force));
            }
        }
        flags |= if above_all {
            Flags::SATURATED_HIGH
        } else {
            Flags::SATURATED_LOW
        };
        let current_a = best.map_or(lowest_a, |(current_a, _)| current_a);
        CurrentResult { current_a, flags }
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
