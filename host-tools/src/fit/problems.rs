//! From a data set to the fitting problems: the `fit`-role recordings pooled
//! per current, split into compression and extension by the shared branch
//! rule (`dataset::split_branches`: |v| inside a recording's noise band is left out).
use crate::dataset::{split_pooled, BranchSamples, Dataset, Role};
use anyhow::{bail, Result};
use mre_algorithm::model::Branch;

/// The samples of one (current, branch) pair.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchProblem {
    pub current_a: f64,
    pub branch: Branch,
    pub samples: BranchSamples,
}

/// The distinct currents of the `fit` recordings, ascending.
pub fn fit_currents(ds: &Dataset) -> Vec<f64> {
    let mut currents: Vec<f64> = ds
        .recordings
        .iter()
        .filter(|r| r.role == Role::Fit)
        .map(|r| r.current_a)
        .collect();
    currents.sort_by(f64::total_cmp);
    currents.dedup();
    currents
}

/// Compression then extension for each fit current, ascending.
pub fn branch_problems(ds: &Dataset) -> Result<Vec<BranchProblem>> {
    let currents = fit_currents(ds);
    if currents.is_empty() {
        bail!("data set `{}` has no recordings with role = \"fit\"", ds.name);
    }
    if currents.len() > mre_algorithm::table::MAX_CURRENTS {
        bail!(
            "data set has {} fit currents; a table holds at most {}",
            currents.len(),
            mre_algorithm::table::MAX_CURRENTS
        );
    }
    let mut out = Vec::with_capacity(2 * currents.len());
    for &c in &currents {
        let (compression, extension) =
            split_pooled(ds.recordings.iter().filter(|r| r.role == Role::Fit && r.current_a == c));
        for (branch, samples) in [(Branch::Compression, compression), (Branch::Extension, extension)] {
            if samples.len() < 5 {
                bail!(
                    "{c} A has only {} {} samples; a quartic needs at least 5",
                    samples.len(),
                    super::branch_name(branch)
                );
            }
            out.push(BranchProblem {
                current_a: c,
                branch,
                samples,
            });
        }
    }
    Ok(out)
}

/// Marks recordings at the given currents as `validate`, so they are
/// predicted by interpolation instead of fitted.
pub fn hold_out(ds: &mut Dataset, currents_a: &[f64]) {
    for r in &mut ds.recordings {
        r.role = r.role_holding_out(currents_a);
    }
}
