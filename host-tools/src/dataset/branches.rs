//! The paper's branch split: compression samples (v > 0) and extension
//! samples (v ≤ 0), as in `mre_core::model::Branch::from_velocity`.
use super::{Recording, Samples};
use mre_core::model::Branch;

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

/// The branch a sample belongs to (v > 0 → compression, else extension).
pub fn branch_of(v_m_s: f64) -> Branch {
    if v_m_s > 0.0 {
        Branch::Compression
    } else {
        Branch::Extension
    }
}

/// Splits samples into (compression, extension).
pub fn split_branches(samples: &Samples) -> (BranchSamples, BranchSamples) {
    let mut compression = BranchSamples::default();
    let mut extension = BranchSamples::default();
    for ((&x, &v), &f) in samples.x_mm.iter().zip(&samples.v_m_s).zip(&samples.force_n) {
        let side = match branch_of(v) {
            Branch::Compression => &mut compression,
            Branch::Extension => &mut extension,
        };
        side.x_mm.push(x);
        side.force_n.push(f);
    }
    (compression, extension)
}

/// Splits and pools several recordings (e.g. all fit recordings at one current).
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
