//! The table file format (TOML) that host tools read and write.
//!
//! ```toml
//! format_version = 2            # optional; 1 (default, the paper's model), 2 or 3
//! [terms]                       # version 2 only; every key optional, 0 = absent
//! saturation_current_a = 0.8    # interpolate in tanh(I/I_s) instead of I
//! sensor_delay_s = 0.0002       # the controller's x/v samples lag the motion
//! coil_tau_s = 0.002            # coil current lags its drive command (L/R)
//! [[current]]
//! current_a = 0.0               # ascending, at most 8 entries
//! compression = [a1, a2, a3, a4, a5]   # F = a1·x⁴ + … + a5, highest power first
//! extension   = [a1, a2, a3, a4, a5]   # x in mm, F in N
//! x_min_mm = 0.0                # fitted stroke (optional, see below)
//! x_max_mm = 1.1531
//! viscous_n_s_per_m = 0.0       # version 2 on: + c(I)·v, interpolated like the quartics
//! [installation]                # version 3: see [`read_installation`]
//! ```
//!
//! An `[installation]` section makes the table format 3 (the installation is
//! carried in flash under the CRC); format 3 without one carries
//! `DEFAULT_INSTALLATION`.
//!
//! If `x_min_mm`/`x_max_mm` are absent (as in the paper's `table4.toml`), the
//! stroke defaults to `[0, first crossing of the two branches above 0]`:
//! the point where the loop closes. Other top-level tables (metadata such as
//! `[fit]` or the paper's `[[table5]]`) are ignored by this reader; unknown
//! keys inside a `[[current]]` entry are an error.
use anyhow::{bail, Context, Result};
use mre_algorithm::installation::{Installation, DEFAULT_INSTALLATION};
use mre_algorithm::table::{CurrentEntry, Quartic, Table};
use serde::Deserialize;
use std::path::Path;

#[derive(Debug, Deserialize)]
struct TableToml {
    format_version: Option<u16>,
    terms: Option<TermsToml>,
    installation: Option<toml::Table>,
    current: Vec<CurrentToml>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct TermsToml {
    #[serde(default)]
    saturation_current_a: f64,
    #[serde(default)]
    sensor_delay_s: f64,
    #[serde(default)]
    coil_tau_s: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CurrentToml {
    current_a: f64,
    compression: [f64; 5],
    extension: [f64; 5],
    x_min_mm: Option<f64>,
    x_max_mm: Option<f64>,
    viscous_n_s_per_m: Option<f64>,
    /// Fit metadata written by `mre fit`; not part of the flash table.
    #[serde(default)]
    #[allow(dead_code)]
    fit: Option<toml::Table>,
}

/// Where `--table` points: the built-in paper table or a file.
pub fn load_table(spec: &str) -> Result<Table> {
    if spec == "paper" {
        return Table::paper().map_err(|e| anyhow::anyhow!("built-in paper table is corrupt: {e}"));
    }
    read_table_file(Path::new(spec))
}

pub fn read_table_file(path: &Path) -> Result<Table> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read table file {}", path.display()))?;
    parse_table_toml(&text).with_context(|| format!("in table file {}", path.display()))
}

/// The `[model] input_sha256` a model file records (the hash of the data
/// set it was fitted on), if it has one. A plain table file has none.
pub fn read_dataset_sha256(path: &Path) -> Result<Option<String>> {
    #[derive(Deserialize)]
    struct Doc {
        model: Option<Meta>,
    }
    #[derive(Deserialize)]
    struct Meta {
        input_sha256: Option<String>,
    }
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read table file {}", path.display()))?;
    let doc: Doc = toml::from_str(&text).with_context(|| format!("in table file {}", path.display()))?;
    let sha = doc.model.and_then(|m| m.input_sha256);
    if let Some(s) = &sha {
        if s.len() != 64 || !s.bytes().all(|b| b.is_ascii_hexdigit()) {
            bail!(
                "in table file {}: [model] input_sha256 is not 64 hex digits",
                path.display()
            );
        }
    }
    Ok(sha)
}

/// A model file's `[installation]` (every key optional; absent keys keep
/// `mre_algorithm::installation::DEFAULT_INSTALLATION`'s value; the keys are
/// `Installation::FIELD_NAMES`, docs/dataset-format.md lists them):
///
/// ```toml
/// [installation]
/// mass_kg = 3.0             # the drop or striker mass
/// usable_stroke_mm = 9.0    # stroke the damper may use from first contact
/// coil_rating_a = 2.0       # the coil's continuous rating
/// ```
///
/// `None` when the file has no such section.
pub fn read_installation(path: &Path) -> Result<Option<Installation>> {
    read_installation_section(path, "table file")?
        .map(|t| installation_from_toml(&t))
        .transpose()
        .with_context(|| format!("in table file {}", path.display()))
}

/// A file's `[installation]` section as written, `None` when it has none;
/// `what` names the file in errors ("table file", "model file").
pub fn read_installation_section(path: &Path, what: &str) -> Result<Option<toml::Table>> {
    #[derive(Deserialize)]
    struct Doc {
        installation: Option<toml::Table>,
    }
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {what} {}", path.display()))?;
    let doc: Doc = toml::from_str(&text).with_context(|| format!("in {what} {}", path.display()))?;
    Ok(doc.installation)
}

/// The position of an `[installation]` key in `Installation::FIELD_NAMES`
/// (and in `Installation::to_array`), `None` for an unknown key.
pub fn installation_field_index(key: &str) -> Option<usize> {
    Installation::FIELD_NAMES.iter().position(|n| *n == key)
}

/// An `[installation]` section's values over the defaults: unknown keys and
/// non-numbers are errors.
pub fn installation_from_toml(section: &toml::Table) -> Result<Installation> {
    let mut values = DEFAULT_INSTALLATION.to_array();
    for (key, value) in section {
        let Some(k) = installation_field_index(key) else {
            bail!(
                "[installation] has an unknown key `{key}` (known: {})",
                Installation::FIELD_NAMES.join(", ")
            );
        };
        let v = match value {
            toml::Value::Float(f) => *f,
            toml::Value::Integer(i) => *i as f64,
            _ => bail!("[installation] {key} must be a number"),
        };
        values[k] = v as f32;
    }
    Ok(Installation::from_array(values))
}

/// The `[installation]` section for `installation`, every key written.
pub fn installation_to_toml(installation: &Installation) -> String {
    let mut s = String::from("[installation]\n");
    for (name, v) in Installation::FIELD_NAMES.iter().zip(installation.to_array()) {
        s.push_str(&format!("{name} = {v:?}\n"));
    }
    s
}

/// `mass_kg = 5.5, usable_stroke_mm = 12, …`: every value, for people.
pub fn installation_summary(installation: &Installation) -> String {
    let values = Installation::FIELD_NAMES.iter().zip(installation.to_array());
    values.map(|(n, v)| format!("{n} = {v}")).collect::<Vec<_>>().join(", ")
}

/// Where a flash table's installation came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InstallationSource {
    /// The model file's `[installation]`.
    ModelFile,
    /// The model file has none: `DEFAULT_INSTALLATION`.
    Defaults,
}

impl InstallationSource {
    pub fn describe(&self) -> &'static str {
        match self {
            InstallationSource::ModelFile => "the model file's [installation]",
            InstallationSource::Defaults => "DEFAULT_INSTALLATION, as the model file has no [installation]",
        }
    }
}

/// A model file's table as the board flies it: format 3, carrying the
/// file's installation (or the defaults, said so), checked against the
/// board's hard limits (`mre_algorithm::limits::BOARD`), which the board would
/// otherwise refuse it by.
pub fn read_flash_table(path: &Path) -> Result<(Table, InstallationSource)> {
    let table = read_table_file(path)?;
    let source = if read_installation(path)?.is_some() {
        InstallationSource::ModelFile
    } else {
        InstallationSource::Defaults
    };
    let table = if table.version() >= mre_algorithm::table::FORMAT_VERSION_3 {
        table
    } else {
        table
            .carrying(DEFAULT_INSTALLATION)
            .map_err(|e| anyhow::anyhow!("invalid table: {e}"))?
    };
    check_installation_limits(table.installation()).with_context(|| format!("in table file {}", path.display()))?;
    Ok((table, source))
}

/// The board's hard limits on an installation, as a sentence naming the value.
pub fn check_installation_limits(installation: &Installation) -> Result<()> {
    use mre_algorithm::limits::{check_installation, BOARD};
    if let Err(limit) = check_installation(installation, &BOARD) {
        let range = limit.range(&BOARD);
        bail!(
            "[installation] {} = {} is outside the board's limits {} to {} ({})",
            limit.name(),
            limit.value(installation),
            range.min,
            range.max,
            limit.why()
        );
    }
    Ok(())
}

pub fn parse_table_toml(text: &str) -> Result<Table> {
    use mre_algorithm::table::{
        ModelTerms, FORMAT_VERSION, FORMAT_VERSION_1, FORMAT_VERSION_2, FORMAT_VERSION_3, MAX_CURRENTS,
    };
    let doc: TableToml = toml::from_str(text)?;
    let declared = doc.format_version.unwrap_or(FORMAT_VERSION_1);
    if !(FORMAT_VERSION_1..=FORMAT_VERSION).contains(&declared) {
        bail!("format_version = {declared} is not supported (expected {FORMAT_VERSION_1} to {FORMAT_VERSION})");
    }
    let has_viscous = doc.current.iter().any(|c| c.viscous_n_s_per_m.is_some());
    if declared == FORMAT_VERSION_1 && (doc.terms.is_some() || has_viscous) {
        bail!("[terms] and viscous_n_s_per_m need format_version = {FORMAT_VERSION_2}");
    }
    let installation = doc.installation.as_ref().map(installation_from_toml).transpose()?;
    let version = if installation.is_some() {
        FORMAT_VERSION_3
    } else {
        declared
    };
    if doc.current.len() > MAX_CURRENTS {
        bail!("{} [[current]] entries, at most {MAX_CURRENTS} fit", doc.current.len());
    }
    let mut entries = Vec::with_capacity(doc.current.len());
    for (i, c) in doc.current.iter().enumerate() {
        let (x_min_mm, x_max_mm) = match (c.x_min_mm, c.x_max_mm) {
            (Some(lo), Some(hi)) => (lo, hi),
            (None, None) => match first_branch_crossing_mm(&c.compression, &c.extension, 0.0, 10.0) {
                Some(hi) => (0.0, hi),
                None => bail!(
                    "[[current]] #{} ({} A): no x_min_mm/x_max_mm and the branches never cross in 0..10 mm; \
                     give the fitted stroke explicitly",
                    i + 1,
                    c.current_a
                ),
            },
            _ => bail!(
                "[[current]] #{} ({} A): give both x_min_mm and x_max_mm, or neither",
                i + 1,
                c.current_a
            ),
        };
        entries.push(CurrentEntry {
            current_a: c.current_a as f32,
            compression: Quartic::new(c.compression.map(|v| v as f32)),
            extension: Quartic::new(c.extension.map(|v| v as f32)),
            x_min_mm: x_min_mm as f32,
            x_max_mm: x_max_mm as f32,
        });
    }
    let table = if declared == FORMAT_VERSION_1 && version == FORMAT_VERSION_1 {
        Table::new(&entries)
    } else {
        let t = doc.terms.unwrap_or_default();
        let mut terms = ModelTerms {
            saturation_current_a: t.saturation_current_a as f32,
            sensor_delay_s: t.sensor_delay_s as f32,
            coil_tau_s: t.coil_tau_s as f32,
            ..ModelTerms::NONE
        };
        for (slot, c) in terms.viscous_n_s_per_m.iter_mut().zip(&doc.current) {
            *slot = c.viscous_n_s_per_m.unwrap_or(0.0) as f32;
        }
        if version >= FORMAT_VERSION_3 {
            Table::with_installation(&entries, terms, installation.unwrap_or(DEFAULT_INSTALLATION))
        } else {
            Table::with_terms(&entries, terms)
        }
    };
    table.map_err(|e| anyhow::anyhow!("invalid table: {e}"))
}

/// Renders a table in this format (round-trips through [`parse_table_toml`]).
pub fn table_to_toml(table: &Table) -> String {
    let mut s = format!("format_version = {}\n", table.version());
    let v2 = table.version() >= mre_algorithm::table::FORMAT_VERSION_2;
    let t = table.terms();
    if v2 {
        s.push_str(&format!(
            "\n[terms]\nsaturation_current_a = {:?}\nsensor_delay_s = {:?}\ncoil_tau_s = {:?}\n",
            t.saturation_current_a, t.sensor_delay_s, t.coil_tau_s
        ));
    }
    for (e, c) in table.entries().iter().zip(t.viscous_n_s_per_m) {
        s.push_str(&format!(
            "\n[[current]]\ncurrent_a = {:?}\ncompression = {:?}\nextension = {:?}\nx_min_mm = {:?}\nx_max_mm = {:?}\n",
            e.current_a, e.compression.coeffs, e.extension.coeffs, e.x_min_mm, e.x_max_mm
        ));
        if v2 {
            s.push_str(&format!("viscous_n_s_per_m = {c:?}\n"));
        }
    }
    if table.version() >= mre_algorithm::table::FORMAT_VERSION_3 {
        s.push('\n');
        s.push_str(&installation_to_toml(table.installation()));
    }
    s
}

fn horner(c: &[f64; 5], x: f64) -> f64 {
    c.iter().fold(0.0, |acc, &a| acc * x + a)
}

/// First x in `(lo, hi]` where the two quartics are equal, to 1e-9 mm.
/// The branches start apart at the loop's origin, so a crossing right at `lo`
/// is skipped.
pub fn first_branch_crossing_mm(c: &[f64; 5], e: &[f64; 5], lo: f64, hi: f64) -> Option<f64> {
    let diff = |x: f64| horner(c, x) - horner(e, x);
    const STEPS: usize = 10_000;
    let h = (hi - lo) / STEPS as f64;
    // Skip the first 1 % so a near-zero start does not count as closing.
    let start = STEPS / 100;
    let mut a = lo + start as f64 * h;
    let mut fa = diff(a);
    for k in start + 1..=STEPS {
        let b = lo + k as f64 * h;
        let fb = diff(b);
        if fa == 0.0 {
            return Some(a);
        }
        if fa.signum() != fb.signum() {
            let (mut l, mut r, mut fl) = (a, b, fa);
            for _ in 0..100 {
                let m = 0.5 * (l + r);
                let fm = diff(m);
                if fm.signum() == fl.signum() {
                    l = m;
                    fl = fm;
                } else {
                    r = m;
                }
            }
            return Some(0.5 * (l + r));
        }
        a = b;
        fa = fb;
    }
    None
}
