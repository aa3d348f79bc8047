//! The paper's branch split, by the one rule `fit` and `diagnose` share
//! ([`crate::signal::clear_branch`]): compression v > 0, extension v ≤ 0, and
//! samples with |v| inside the recording's own velocity-noise band
//! ([`crate::signal::branch_band_m_s`]) left out, their branch being chance.
use super::{Recording, Samples};
use crate::signal::{branch_band_m_s, clear_branch};
use mre_algorithm::model::Branch;

/// The (x, F) samples of one branch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BranchSamples {
    pub x_mm: Vec<f64>,
    pub force_n: Vec<f64>,
}

impl BranchSamples {
    pub fn len(&self) -> usize {
        self.x_mm.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x_mm.is_empty()
    }

    pub fn extend_from(&mut self, other: &BranchSamples) {
        self.x_mm.extend_from_slice(&other.x_mm);
        self.force_n.extend_from_slice(&other.force_n);
    }
}

/// Splits one recording's samples into (compression, extension), leaving out
/// those whose |v| is inside the band computed from this recording's velocity.
pub fn split_branches(samples: &Samples) -> (BranchSamples, BranchSamples) {
    let band_m_s = branch_band_m_s(&samples.v_m_s);
    let mut compression = BranchSamples::default();
    let mut extension = BranchSamples::default();
    for ((&x, &v), &f) in samples.x_mm.iter().zip(&samples.v_m_s).zip(&samples.force_n) {
        let side = match clear_branch(v, band_m_s) {
            Some(Branch::Compression) => &mut compression,
            Some(Branch::Extension) => &mut extension,
            None => continue,
        };
        side.x_mm.push(x);
        side.force_n.push(f);
    }
    (compression, extension)
}

/// Splits each recording by its own band, then pools them (e.g. all fit
/// recordings at one current).
pub fn split_pooled<'a>(recordings: impl IntoIterator<Item = &'a Recording>) -> (BranchSamples, BranchSamples) {
    let mut compression = BranchSamples::default();
    let mut extension = BranchSamples::default();
    for r in recordings {
        let (c, e) = split_branches(&r.samples);
        compression.extend_from(&c);
        extension.extend_from(&e);
    }
    (compression, extension)
}
