//! Where an installation's values come from, value by value, so every
//! command can say it: `mre fit` and `mre diagnose --model-out` write a model
//! file's `[installation]` from the data set's metadata and `--installation
//! KEY=VALUE` options; `mre sim`, `mre pil`, `mre bench-control` and the demo
//! read it back from a model file. What neither gives keeps
//! `DEFAULT_INSTALLATION`'s value, and the statement says so.
use crate::dataset::Dataset;
use crate::table_file::{
    check_installation_limits, installation_field_index, installation_from_toml, read_installation_section,
};
use anyhow::{bail, Context, Result};
use mre_algorithm::installation::{Installation, DEFAULT_INSTALLATION, FIELD_COUNT};
use std::path::Path;

/// Where one value came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// `DEFAULT_INSTALLATION` (with why, when a source was there but did not decide).
    Default(Option<String>),
    /// The data set's metadata (e.g. every recording's `mass_kg`).
    Dataset,
    /// A model file's `[installation]`.
    ModelFile(String),
    /// A command-line option.
    Option,
}

/// An installation and where each of its values came from.
#[derive(Clone, Debug, PartialEq)]
pub struct StatedInstallation {
    pub installation: Installation,
    /// In `Installation::FIELD_NAMES` order.
    pub origins: [Origin; FIELD_COUNT],
}

impl Default for StatedInstallation {
    fn default() -> Self {
        Self {
            installation: DEFAULT_INSTALLATION,
            origins: std::array::from_fn(|_| Origin::Default(None)),
        }
    }
}

impl StatedInstallation {
    /// A model file's `[installation]`: the keys it has, the defaults for
    /// the rest (all of them when it has no such section).
    pub fn from_model_file(path: &Path) -> Result<Self> {
        let mut stated = Self::default();
        let Some(section) = read_installation_section(path, "model file")? else {
            return Ok(stated);
        };
        stated.installation =
            installation_from_toml(&section).with_context(|| format!("in model file {}", path.display()))?;
        for key in section.keys() {
            if let Some(k) = installation_field_index(key) {
                stated.origins[k] = Origin::ModelFile(path.display().to_string());
            }
        }
        stated.check()?;
        Ok(stated)
    }

    /// What a data set's metadata says: the drop mass when every recording
    /// that declares one declares the same (a campaign with two drop masses
    /// has no one installation mass: the default stays, said so).
    pub fn from_dataset(ds: &Dataset) -> Self {
        let mut stated = Self::default();
        let mut masses_kg: Vec<f64> = ds.recordings.iter().filter_map(|r| r.mass_kg).collect();
        masses_kg.sort_by(f64::total_cmp);
        masses_kg.dedup();
        let k = installation_field_index("mass_kg").unwrap_or(0);
        match masses_kg.as_slice() {
            [] => {}
            [one_kg] => {
                let mut candidate = stated.installation;
                candidate.mass_kg = *one_kg as f32;
                if check_installation_limits(&candidate).is_ok() {
                    stated.installation = candidate;
                    stated.origins[k] = Origin::Dataset;
                } else {
                    stated.origins[k] = Origin::Default(Some(format!(
                        "the data set's mass {one_kg} kg is outside the board's limits"
                    )));
                }
            }
            several => {
                let list: Vec<String> = several.iter().map(|m| format!("{m}")).collect();
                stated.origins[k] = Origin::Default(Some(format!(
                    "the data set declares several masses ({} kg)",
                    list.join(", ")
                )));
            }
        }
        stated
    }

    /// `KEY=VALUE` options (`Installation::FIELD_NAMES`) over these values.
    pub fn with_options(mut self, options: &[String]) -> Result<Self> {
        for option in options {
            let Some((key, value)) = option.split_once('=') else {
                bail!("`--installation {option}`: expected KEY=VALUE, e.g. mass_kg=3");
            };
            let key = key.trim();
            let Some(k) = installation_field_index(key) else {
                bail!(
                    "`--installation {option}`: unknown key `{key}` (known: {})",
                    Installation::FIELD_NAMES.join(", ")
                );
            };
            let v: f32 = value
                .trim()
                .parse()
                .with_context(|| format!("`--installation {option}`: `{value}` is not a number"))?;
            let mut values = self.installation.to_array();
            values[k] = v;
            self.installation = Installation::from_array(values);
            self.origins[k] = Origin::Option;
        }
        self.check()?;
        Ok(self)
    }

    /// Refuses what the board would: a non-positive value, an inverted
    /// impact range, a value outside the board's hard limits.
    pub fn check(&self) -> Result<()> {
        if let Some(name) = self.installation.invalid_field() {
            bail!("[installation] {name} must be a finite positive value (and impact_v_min_m_s ≤ impact_v_max_m_s)");
        }
        check_installation_limits(&self.installation)
    }

    /// One line for people: which values came from where.
    pub fn describe(&self) -> String {
        let mut groups: Vec<(String, Vec<String>)> = Vec::new();
        let values = self.installation.to_array();
        for ((name, v), origin) in Installation::FIELD_NAMES.iter().zip(values).zip(&self.origins) {
            let from = match origin {
                Origin::Default(None) => "the defaults (DEFAULT_INSTALLATION)".to_owned(),
                Origin::Default(Some(why)) => format!("the defaults, as {why}"),
                Origin::Dataset => "the data set's metadata".to_owned(),
                Origin::ModelFile(path) => format!("{path}'s [installation]"),
                Origin::Option => "--installation".to_owned(),
            };
            let item = format!("{name} = {v}");
            match groups.iter_mut().find(|(f, _)| *f == from) {
                Some((_, items)) => items.push(item),
                None => groups.push((from, vec![item])),
            }
        }
        let parts: Vec<String> = groups
            .into_iter()
            .map(|(from, items)| format!("{} from {from}", items.join(", ")))
            .collect();
        format!("installation: {}", parts.join("; "))
    }
}
