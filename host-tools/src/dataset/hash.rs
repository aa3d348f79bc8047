//! A fingerprint of a data set's input files, recorded in model files so a
//! model can be traced to the exact data it was fitted on.
use super::Dataset;
use anyhow::{Context, Result};
use sha2::{Digest, Sha256};

/// SHA-256 (hex) over `dataset.toml` and each listed file in listed order,
/// each preceded by its name and byte length.
pub fn input_sha256(ds: &Dataset) -> Result<String> {
    let mut h = Sha256::new();
    let names = std::iter::once("dataset.toml").chain(ds.recordings.iter().map(|r| r.file.as_str()));
    for name in names {
        let path = ds.root.join(name);
        let bytes = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        h.update(name.as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(&bytes);
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}
