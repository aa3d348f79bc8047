//! Writes a [`Dataset`] in the `docs/dataset-format.md` format:
//! `dataset.toml` plus one comma-separated file per recording with
//! unit-carrying headers (`time_s`, `displacement_mm`, `velocity_m_s`,
//! `force_n`, and `acceleration_m_s2`, `current_a`, `temperature_c` when
//! present).
//!
//! The folder appears whole or not at all (`atomic_write::stage_folder`):
//! everything is written into a temporary folder beside the target and renamed
//! into place. An existing non-empty folder is refused unless `force` is set,
//! and even then replaced only if mre wrote it (its marker file).
use super::{Dataset, Recording, Role, TagValue};
use crate::atomic_write::stage_folder;
use anyhow::{bail, ensure, Context, Result};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Component, Path};

/// Decimal places per column; `None` = shortest exact (round-trip) form.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Precision {
    pub time_s: Option<usize>,
    pub x_mm: Option<usize>,
    pub v_m_s: Option<usize>,
    pub force_n: Option<usize>,
    pub accel_m_s2: Option<usize>,
    pub current_a: Option<usize>,
    pub temperature_c: Option<usize>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WriteOptions {
    /// Replace an existing non-empty folder.
    pub force: bool,
    pub precision: Precision,
}

/// Writes `dataset` into the folder `dir` (see the module docs).
pub fn write_dataset(dataset: &Dataset, dir: &Path, options: &WriteOptions) -> Result<()> {
    let toml_text = dataset_toml(dataset)?;
    let files = dataset
        .recordings
        .iter()
        .map(|rec| Ok((rec.file.clone(), recording_csv(rec, &options.precision)?)))
        .collect::<Result<Vec<_>>>()?;
    // The staging folder is private until it is renamed into place, so its
    // files are written directly.
    stage_folder(dir, options.force, |staging| {
        let write = |name: &str, bytes: &[u8]| {
            let path = staging.join(name);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent)
                    .with_context(|| format!("cannot create {}", dir.join(name).display()))?;
            }
            std::fs::write(&path, bytes).with_context(|| format!("cannot write {}", dir.join(name).display()))
        };
        write("dataset.toml", toml_text.as_bytes())?;
        for (file, bytes) in &files {
            write(file, bytes)?;
        }
        Ok(())
    })
}

/// A TOML string literal (quoted and escaped).
fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_owned()).to_string()
}

/// A TOML float that always reads back as a float.
fn toml_float(v: f64, what: &str) -> Result<String> {
    ensure!(v.is_finite(), "{what} is not finite ({v})");
    Ok(toml::Value::Float(v).to_string())
}

/// A TOML key: bare when it can be, quoted otherwise.
fn toml_key(k: &str) -> String {
    let bare = !k.is_empty() && k.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        k.to_owned()
    } else {
        toml_string(k)
    }
}

/// The `dataset.toml` text for `dataset`. A mass shared by every recording
/// goes into `[defaults]`; otherwise each recording carries its own.
pub fn dataset_toml(dataset: &Dataset) -> Result<String> {
    check_files(dataset)?;
    let mut out = String::new();
    writeln!(out, "name = {}", toml_string(&dataset.name))?;
    let masses: BTreeSet<u64> = dataset
        .recordings
        .iter()
        .filter_map(|r| r.mass_kg.map(f64::to_bits))
        .collect();
    let shared_mass = match (masses.len(), dataset.recordings.iter().all(|r| r.mass_kg.is_some())) {
        (1, true) => dataset.recordings.first().and_then(|r| r.mass_kg),
        _ => None,
    };
    if let Some(m) = shared_mass {
        writeln!(out, "\n[defaults]\nmass_kg = {}", toml_float(m, "mass_kg")?)?;
    }
    for rec in &dataset.recordings {
        let what = |key: &str| format!("{key} of {}", rec.file);
        writeln!(out, "\n[[recording]]")?;
        writeln!(out, "file = {}", toml_string(&rec.file))?;
        writeln!(out, "current_a = {}", toml_float(rec.current_a, &what("current_a"))?)?;
        let role = match rec.role {
            Role::Fit => "fit",
            Role::Validate => "validate",
        };
        writeln!(out, "role = \"{role}\"")?;
        if shared_mass.is_none() {
            if let Some(m) = rec.mass_kg {
                writeln!(out, "mass_kg = {}", toml_float(m, &what("mass_kg"))?)?;
            }
        }
        if let Some(v) = rec.impact_velocity_m_s {
            writeln!(
                out,
                "impact_velocity_m_s = {}",
                toml_float(v, &what("impact_velocity_m_s"))?
            )?;
        }
        if let Some(n) = rec.sequence {
            writeln!(out, "sequence = {n}")?;
        }
        if let Some(t) = rec.temperature_c {
            writeln!(out, "temperature_c = {}", toml_float(t, &what("temperature_c"))?)?;
        }
        if !rec.tags.is_empty() {
            let mut parts = Vec::new();
            for (k, v) in &rec.tags {
                let value = match v {
                    TagValue::Number(x) => toml_float(*x, &what(&format!("tags.{k}")))?,
                    TagValue::Text(s) => toml_string(s),
                };
                parts.push(format!("{} = {value}", toml_key(k)));
            }
            writeln!(out, "tags = {{ {} }}", parts.join(", "))?;
        }
    }
    Ok(out)
}

/// Recording paths must be relative, stay inside the folder, and be unique.
fn check_files(dataset: &Dataset) -> Result<()> {
    let mut seen = BTreeSet::new();
    for rec in &dataset.recordings {
        let path = Path::new(&rec.file);
        let inside = !rec.file.is_empty()
            && path.components().all(|c| matches!(c, Component::Normal(_)))
            && path
                .file_name()
                .is_some_and(|n| n != "dataset.toml" && n != crate::atomic_write::MARKER_FILE);
        ensure!(
            inside,
            "recording file `{}` must be a relative path inside the data set folder",
            rec.file
        );
        ensure!(
            seen.insert(rec.file.as_str()),
            "recording file `{}` is listed twice",
            rec.file
        );
    }
    Ok(())
}

/// One column of a recording file.
struct Column<'a> {
    header: &'static str,
    values: &'a [f64],
    decimals: Option<usize>,
}

/// The CSV bytes of one recording (header row + samples).
pub fn recording_csv(rec: &Recording, precision: &Precision) -> Result<Vec<u8>> {
    let s = &rec.samples;
    let n = s.len();
    ensure!(n > 0, "{}: no samples", rec.file);
    let mut columns = vec![
        Column {
            header: "time_s",
            values: &s.time_s,
            decimals: precision.time_s,
        },
        Column {
            header: "displacement_mm",
            values: &s.x_mm,
            decimals: precision.x_mm,
        },
    ];
    // An estimated velocity is not a measurement: leave it to the reader.
    if !rec.velocity_estimated && !s.v_m_s.is_empty() {
        columns.push(Column {
            header: "velocity_m_s",
            values: &s.v_m_s,
            decimals: precision.v_m_s,
        });
    }
    columns.push(Column {
        header: "force_n",
        values: &s.force_n,
        decimals: precision.force_n,
    });
    let optional = [
        ("acceleration_m_s2", &s.accel_m_s2, precision.accel_m_s2),
        ("current_a", &s.current_a, precision.current_a),
        ("temperature_c", &s.temperature_c, precision.temperature_c),
    ];
    for (header, values, decimals) in optional {
        if let Some(values) = values {
            columns.push(Column {
                header,
                values,
                decimals,
            });
        }
    }
    for c in &columns {
        ensure!(
            c.values.len() == n,
            "{}: column {} has {} values, time has {n}",
            rec.file,
            c.header,
            c.values.len()
        );
        if let Some(i) = c.values.iter().position(|v| !v.is_finite()) {
            bail!("{}: sample {} of {} is not finite", rec.file, i + 1, c.header);
        }
    }
    if let Some(i) = s.time_s.windows(2).position(|w| w[1] <= w[0]) {
        bail!("{}: time does not increase at sample {}", rec.file, i + 2);
    }

    let mut writer = csv::Writer::from_writer(Vec::with_capacity(n * 40));
    writer.write_record(columns.iter().map(|c| c.header))?;
    let mut row = Vec::with_capacity(columns.len());
    for i in 0..n {
        row.clear();
        for c in &columns {
            let v = c.values[i];
            row.push(match c.decimals {
                Some(d) => format!("{v:.d$}"),
                None => format!("{v}"),
            });
        }
        writer.write_record(&row)?;
    }
    writer.into_inner().context("cannot finish CSV")
}
