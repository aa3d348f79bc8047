//! The model file `mre fit` writes (TOML). It is a table file
//! ([`crate::table_file`]) with metadata: `[model]` (ignored by the table
//! reader) and a `fit` sub-table in each `[[current]]`, so `--table model.toml`
//! works in every command.
use super::{branch_name, BranchFit, FitOptions, Method};
use crate::installation::StatedInstallation;
use anyhow::{bail, Context, Result};
use mre_algorithm::model::Branch;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelFile {
    pub format_version: u16,
    pub model: ModelMeta,
    pub current: Vec<CurrentModel>,
    /// The rig the model is for, written as `[installation]` (format 3):
    /// from the data set's metadata and `--installation` options, the
    /// defaults for the rest ([`StatedInstallation`] says which).
    #[serde(skip)]
    pub installation: Option<StatedInstallation>,
}

impl ModelFile {
    /// The model carrying `installation` (format 3).
    pub fn with_installation(self, installation: StatedInstallation) -> Self {
        Self {
            format_version: mre_algorithm::table::FORMAT_VERSION_3,
            installation: Some(installation),
            ..self
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelMeta {
    pub dataset: String,
    /// SHA-256 of dataset.toml and every listed file (see `dataset::hash`).
    pub input_sha256: String,
    /// gsa, lsq or both.
    pub method: String,
    /// Which solution the coefficients are: "lsq" or "gsa".
    pub table_coefficients: String,
    pub objective: String,
    pub seed: u64,
    pub agents: usize,
    pub iters: usize,
    pub g0: f64,
    pub alpha: f64,
    pub final_kbest_pct: f64,
    pub bounds: String,
    pub velocity_estimated: bool,
    /// Currents whose recordings were held out of the fit (`--hold-out-current`),
    /// so `validate` and `plot` can tell what the model never saw.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub held_out_current_a: Vec<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurrentModel {
    pub current_a: f64,
    pub compression: [f64; 5],
    pub extension: [f64; 5],
    pub x_min_mm: f64,
    pub x_max_mm: f64,
    pub fit: CurrentFit,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurrentFit {
    pub compression: BranchFitMeta,
    pub extension: BranchFitMeta,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BranchFitMeta {
    pub samples: usize,
    pub x_min_mm: f64,
    pub x_max_mm: f64,
    /// The performance index of the table coefficients.
    pub rmse_n: f64,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub lsq_rmse_n: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gsa_rmse_n: Option<f64>,
    /// GSA RMSE / lsq RMSE (1 = optimal).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gsa_over_lsq: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gsa_coefficients: Option<[f64; 5]>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gsa_lower: Option<[f64; 5]>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gsa_upper: Option<[f64; 5]>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gsa_evaluations: Option<usize>,
    /// Best-so-far RMSE after each GSA iteration.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gsa_convergence_rmse_n: Option<Vec<f64>>,
}

pub const OBJECTIVE: &str =
    "rmse_n: root-mean-square error (N) between recorded force and the branch quartic over the \
                             branch's samples";

fn branch_meta(b: &BranchFit) -> BranchFitMeta {
    BranchFitMeta {
        samples: b.samples,
        x_min_mm: b.x_min_mm,
        x_max_mm: b.x_max_mm,
        rmse_n: b.chosen.rmse_n,
        lsq_rmse_n: b.lsq.as_ref().map(|s| s.rmse_n),
        gsa_rmse_n: b.gsa.as_ref().map(|g| g.solution.rmse_n),
        gsa_over_lsq: b.gap_ratio(),
        gsa_coefficients: b.gsa.as_ref().map(|g| g.solution.coeffs),
        gsa_lower: b.gsa.as_ref().map(|g| g.search_box.lower),
        gsa_upper: b.gsa.as_ref().map(|g| g.search_box.upper),
        gsa_evaluations: b.gsa.as_ref().map(|g| g.evaluations),
        gsa_convergence_rmse_n: b.gsa.as_ref().map(|g| g.convergence_rmse_n.clone()),
    }
}

/// Assembles the model file from branch fits (compression/extension pairs).
pub fn build(
    dataset: &str,
    input_sha256: &str,
    velocity_estimated: bool,
    fits: &[BranchFit],
    options: &FitOptions,
) -> Result<ModelFile> {
    let mut current = Vec::new();
    for pair in fits.chunks(2) {
        let [c, e] = pair else {
            bail!("branch fits must come in compression/extension pairs");
        };
        if c.branch != Branch::Compression || e.branch != Branch::Extension || c.current_a != e.current_a {
            bail!("branch fits must come in compression/extension pairs at one current");
        }
        current.push(CurrentModel {
            current_a: c.current_a,
            compression: c.chosen.coeffs,
            extension: e.chosen.coeffs,
            x_min_mm: c.x_min_mm.min(e.x_min_mm),
            x_max_mm: c.x_max_mm.max(e.x_max_mm),
            fit: CurrentFit {
                compression: branch_meta(c),
                extension: branch_meta(e),
            },
        });
    }
    let g = &options.gsa;
    Ok(ModelFile {
        format_version: mre_algorithm::table::FORMAT_VERSION_2,
        model: ModelMeta {
            dataset: dataset.to_string(),
            input_sha256: input_sha256.to_string(),
            method: options.method.label().to_string(),
            table_coefficients: if options.method == Method::Gsa { "gsa" } else { "lsq" }.to_string(),
            objective: OBJECTIVE.to_string(),
            seed: g.seed,
            agents: g.agents,
            iters: g.iters,
            g0: g.g0,
            alpha: g.alpha,
            final_kbest_pct: g.final_kbest_pct,
            bounds: options.bounds.label().to_string(),
            velocity_estimated,
            held_out_current_a: Vec::new(),
        },
        current,
        installation: None,
    })
}

/// TOML text, checked to load as a table before it is returned.
pub fn to_toml(model: &ModelFile) -> Result<String> {
    let mut text = toml::to_string(model).context("cannot render the model file")?;
    if let Some(stated) = &model.installation {
        text.push('\n');
        text.push_str(&crate::table_file::installation_to_toml(&stated.installation));
    }
    crate::table_file::parse_table_toml(&text).context("the fitted model is not a valid table")?;
    Ok(format!(
        "# Written by `mre fit`. A table file: `--table` reads [[current]]; [model] and `fit` are metadata.\n\
         # Coefficients highest power first: F = a1·x⁴ + a2·x³ + a3·x² + a4·x + a5 (x in mm, F in N).\n{text}"
    ))
}

/// Writes the model file atomically.
pub fn write(path: &Path, model: &ModelFile) -> Result<()> {
    let text = to_toml(model)?;
    crate::atomic_write::write_atomic(path, text.as_bytes())
}

pub fn read(path: &Path) -> Result<ModelFile> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read model file {}", path.display()))?;
    toml::from_str(&text).with_context(|| format!("in model file {}", path.display()))
}

impl CurrentFit {
    pub fn branch(&self, b: Branch) -> &BranchFitMeta {
        match b {
            Branch::Compression => &self.compression,
            Branch::Extension => &self.extension,
        }
    }
}

/// "compression"/"extension" label, re-exported for report writers.
pub fn label(b: Branch) -> &'static str {
    branch_name(b)
}
