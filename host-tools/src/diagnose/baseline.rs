//! Stage 1: the paper's model, fitted by least squares on the `fit`
//! recordings (or a given table), predicting every recording through the
//! core's own `force_on_branch` (linear interpolation at validate currents,
//! x clamped to the fitted stroke), exactly as the board would.
use super::design::{Designs, Layout, Solution, Terms, QUARTIC_TERMS};
use super::prepared::Prepared;
use anyhow::{anyhow, Result};
use mre_algorithm::model::Branch;
use mre_algorithm::table::{CurrentEntry, Quartic, Table};

/// The baseline table from a least-squares solution of the plain design.
pub fn table_from_solution(prep: &Prepared, sol: &Solution) -> Result<Table> {
    let layout = Layout::new(prep.currents_a.len(), &Terms::default());
    let mut entries = Vec::new();
    for (k, &c) in prep.currents_a.iter().enumerate() {
        // The core stores highest power first.
        let quartic = |comp: bool| {
            let mut q = [0f32; QUARTIC_TERMS];
            for p in 0..QUARTIC_TERMS {
                q[QUARTIC_TERMS - 1 - p] = sol.beta[layout.quartic_col(k, comp, p)] as f32;
            }
            Quartic::new(q)
        };
        let xs = prep
            .fit_indices()
            .into_iter()
            .filter(|&i| prep.recs[i].current_a == c)
            .flat_map(|i| prep.recs[i].x_mm.iter().copied());
        let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
        entries.push(CurrentEntry {
            current_a: c as f32,
            compression: quartic(true),
            extension: quartic(false),
            x_min_mm: lo as f32,
            x_max_mm: hi as f32,
        });
    }
    Table::new(&entries).map_err(|e| anyhow!("baseline table: {e}"))
}

/// Fits the paper's model on all fit recordings.
pub fn fit_table(prep: &Prepared) -> Result<Table> {
    let d = Designs::build(prep, &Terms::default());
    let sol = d.solve(prep, &prep.fit_indices())?;
    table_from_solution(prep, &sol)
}

/// Every recording predicted by `table` (branch from the sign of velocity,
/// at the recorded current of each sample).
pub fn predict_all(prep: &Prepared, table: &Table) -> Vec<Vec<f64>> {
    prep.recs
        .iter()
        .map(|r| {
            (0..r.len())
                .map(|t| {
                    let (x, v) = (r.x_mm[t], r.v_m_s[t]);
                    table
                        .force_on_branch(x as f32, Branch::from_velocity(v as f32), r.current_at(t) as f32)
                        .force_n as f64
                })
                .collect()
        })
        .collect()
}
