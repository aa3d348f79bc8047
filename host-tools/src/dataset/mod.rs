//! Recording data sets (`docs/dataset-format.md`, a contract other tools
//! read): the in-memory types every host module shares.
//!
//! Internal units: time s, displacement mm, velocity m/s, acceleration m/s²,
//! force N, current A, temperature °C. Host analysis runs in f64 and converts
//! to f32 only at the call into the core (which is what the board computes).
pub mod accelerometer;
pub mod branches;
pub mod columns;
pub mod error;
pub mod hash;
pub mod init;
pub mod lvm;
pub mod matlab;
pub mod motion;
pub mod mts;
pub mod read;
pub mod sign;
pub mod summary;
pub mod tdms;
pub mod text;
pub mod velocity;
pub mod vendor;

pub use branches::{split_branches, split_pooled, BranchSamples};
pub use error::DatasetError;

use std::collections::BTreeMap;
use std::path::PathBuf;

/// What a recording is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// Used to build the model.
    Fit,
    /// Never fitted; only predicted (e.g. intermediate currents).
    Validate,
}

/// A free covariate from `tags = { … }`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum TagValue {
    Number(f64),
    Text(String),
}

/// Per-sample channels, all the same length, in internal units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    pub time_s: Vec<f64>,
    pub x_mm: Vec<f64>,
    pub v_m_s: Vec<f64>,
    pub force_n: Vec<f64>,
    pub accel_m_s2: Option<Vec<f64>>,
    /// Measured coil current per sample, if recorded.
    pub current_a: Option<Vec<f64>>,
    pub temperature_c: Option<Vec<f64>>,
}

impl Samples {
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }
}

/// One test: its metadata from `dataset.toml` and its samples.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    /// Path relative to the data set folder, as listed.
    pub file: String,
    /// Coil current held during the test.
    pub current_a: f64,
    pub role: Role,
    pub mass_kg: Option<f64>,
    pub impact_velocity_m_s: Option<f64>,
    /// Position in the run order (1 = first).
    pub sequence: Option<u32>,
    pub temperature_c: Option<f64>,
    pub tags: BTreeMap<String, TagValue>,
    pub samples: Samples,
    /// True when the file had no velocity column and it was estimated.
    pub velocity_estimated: bool,
    /// Set when the file had no displacement: velocity and displacement were
    /// integrated from force or acceleration (docs/dataset-format.md).
    pub motion_from: Option<motion::MotionSource>,
    /// What the reader assumed or chose reading the file (tied time stamps
    /// spread, a preamble skipped, a vendor block picked), for reports.
    pub notes: Vec<String>,
}

impl Recording {
    /// Its role when the recordings at `held_out_a` are held out (predicted
    /// by interpolation, never fitted): `validate` at those currents, its
    /// own role otherwise.
    pub fn role_holding_out(&self, held_out_a: &[f64]) -> Role {
        if held_out_a.iter().any(|&c| (c - self.current_a).abs() < 1e-9) {
            Role::Validate
        } else {
            self.role
        }
    }
}

/// A data set folder, loaded.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    pub name: String,
    pub root: PathBuf,
    pub recordings: Vec<Recording>,
}

// Writing data sets (`dataset.toml` + CSV files), atomically.
pub mod write;

/// The distinct coil currents among `currents_a`, ascending (two currents
/// closer than a nanoampere are one: they are the same setting written twice).
pub fn distinct_currents_a(currents_a: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut sorted: Vec<f64> = currents_a.into_iter().collect();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    sorted
}
