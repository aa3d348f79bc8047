//! `Dataset::load`: reads `dataset.toml` and the recording files it lists
//! (`docs/dataset-format.md`, a contract). Every rejection is one
//! [`DatasetError`] naming file, line and column.
use super::columns::{parse_header, required_columns, Quantity};
use super::error::DatasetError;
use super::motion::MotionSource;
use super::velocity::estimate_velocity_m_s;
use super::{Dataset, Recording, Role, Samples, TagValue};
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use toml::Spanned;

/// A recording with fewer samples cannot be fitted (a quartic per branch needs
/// 5 samples, and there are two branches).
pub const MIN_SAMPLES: usize = 10;

const TOP_KEYS: &[&str] = &["name", "defaults", "recording"];
/// Keys a `[[recording]]` may set; `[defaults]` may set all but `file`.
const RECORDING_KEYS: &[&str] = &[
    "file",
    "current_a",
    "role",
    "mass_kg",
    "impact_velocity_m_s",
    "impact_velocity_uncertainty_m_s",
    "sequence",
    "temperature_c",
    "tags",
    "delimiter",
    "columns",
    "variables",
    "sign",
    "block",
];

/// Plausible ranges of the numeric settings (key, min, max, unit): a value
/// outside is a typo or a unit mix-up, rejected at load.
pub const SETTING_BOUNDS: &[(&str, f64, f64, &str)] = &[
    ("current_a", -100.0, 100.0, "A"),
    ("mass_kg", 1e-6, 1e4, "kg"),
    ("impact_velocity_m_s", -100.0, 100.0, "m/s"),
    ("impact_velocity_uncertainty_m_s", 0.0, 100.0, "m/s"),
    ("temperature_c", -273.15, 1000.0, "°C"),
];

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
enum Delimiter {
    #[serde(rename = ",")]
    Comma,
    /// `;` with a decimal comma, as spreadsheets in German, French or
    /// Spanish locales save CSV.
    #[serde(rename = ";")]
    Semicolon,
    Whitespace,
}

/// One `[[recording]]` or the `[defaults]` table (which may not set `file`).
#[derive(Default, Deserialize)]
struct Settings {
    file: Option<Spanned<String>>,
    current_a: Option<Spanned<f64>>,
    role: Option<Role>,
    mass_kg: Option<Spanned<f64>>,
    impact_velocity_m_s: Option<Spanned<f64>>,
    /// The light gate's uncertainty, for an accelerometer record's report.
    impact_velocity_uncertainty_m_s: Option<Spanned<f64>>,
    sequence: Option<u32>,
    temperature_c: Option<Spanned<f64>>,
    tags: Option<BTreeMap<String, TagValue>>,
    delimiter: Option<Delimiter>,
    columns: Option<Spanned<Vec<String>>>,
    /// For a .mat file: unit-named column → MATLAB variable name.
    variables: Option<Spanned<BTreeMap<String, String>>>,
    /// Column name → +1 or −1: flips what an instrument reports.
    sign: Option<Spanned<BTreeMap<String, i64>>>,
    /// An MTS Specimen.dat's data block (1-based), instead of the longest.
    block: Option<Spanned<usize>>,
}

#[derive(Deserialize)]
struct Manifest {
    #[serde(default)]
    name: String,
    #[serde(default)]
    defaults: Settings,
    #[serde(default)]
    recording: Vec<Settings>,
}

/// 1-based line of a byte offset.
fn line_of(text: &str, offset: usize) -> usize {
    position_of(text, offset).0
}

/// 1-based line and column (in characters) of a byte offset.
pub fn position_of(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset.min(text.len())).unwrap_or(text);
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
    (line, before[line_start..].chars().count() + 1)
}

/// A TOML syntax or type error in `dataset.toml`, with line and column.
fn syntax_error(mpath: &str, text: &str, e: &toml::de::Error) -> DatasetError {
    let (line, column) = e.span().map_or((1, 1), |s| position_of(text, s.start));
    DatasetError::Syntax {
        path: mpath.to_string(),
        line,
        column,
        message: e.message().trim().to_string(),
    }
}

impl Dataset {
    /// Loads the data set in folder `dir` (its `dataset.toml` and every listed file).
    pub fn load(dir: &Path) -> Result<Dataset, DatasetError> {
        let manifest_path = dir.join("dataset.toml");
        let mpath = manifest_path.display().to_string();
        let text = std::fs::read_to_string(&manifest_path).map_err(|e| DatasetError::Unreadable {
            path: mpath.clone(),
            reason: e.to_string(),
        })?;
        Self::from_manifest(dir, &text)
    }

    /// Like [`Dataset::load`], with the `dataset.toml` text given (the
    /// recording files are still read from `dir`).
    pub fn from_manifest(dir: &Path, text: &str) -> Result<Dataset, DatasetError> {
        let mpath = dir.join("dataset.toml").display().to_string();
        check_keys(text, &mpath)?;
        let manifest: Manifest = toml::from_str(text).map_err(|e| syntax_error(&mpath, text, &e))?;

        let mut first_line_of_file: HashMap<String, usize> = HashMap::new();
        let mut recordings = Vec::with_capacity(manifest.recording.len());
        for (index, s) in manifest.recording.iter().enumerate() {
            let Some(file_key) = &s.file else {
                return Err(DatasetError::Manifest {
                    path: mpath,
                    line: 1,
                    message: format!("[[recording]] #{} has no `file`", index + 1),
                });
            };
            let line = line_of(text, file_key.span().start);
            let file = file_key.get_ref().clone();
            if let Some(&first_line) = first_line_of_file.get(&file) {
                return Err(DatasetError::DuplicateFile {
                    path: mpath,
                    line,
                    file,
                    first_line,
                });
            }
            first_line_of_file.insert(file.clone(), line);
            let d = &manifest.defaults;
            let finite = |v: Option<&Spanned<f64>>, key: &str| -> Result<Option<f64>, DatasetError> {
                let Some(sv) = v else { return Ok(None) };
                let value = *sv.get_ref();
                let (line, column) = position_of(text, sv.span().start);
                if !value.is_finite() {
                    return Err(DatasetError::NonFiniteSetting {
                        path: mpath.clone(),
                        line,
                        key: key.to_string(),
                        value,
                    });
                }
                match SETTING_BOUNDS.iter().find(|(k, ..)| *k == key) {
                    Some(&(_, min, max, unit)) if !(min..=max).contains(&value) => {
                        Err(DatasetError::SettingOutOfRange {
                            path: mpath.clone(),
                            line,
                            column,
                            key: key.to_string(),
                            value,
                            min,
                            max,
                            unit,
                        })
                    }
                    _ => Ok(Some(value)),
                }
            };
            let current_a = match finite(s.current_a.as_ref().or(d.current_a.as_ref()), "current_a")? {
                Some(c) => c,
                None => {
                    return Err(DatasetError::Manifest {
                        path: mpath,
                        line,
                        message: format!("recording `{file}` has no `current_a`"),
                    })
                }
            };
            let data_path = dir.join(&file);
            if !data_path.is_file() {
                return Err(DatasetError::FileAbsent {
                    path: mpath,
                    line,
                    file,
                });
            }
            let columns = s.columns.as_ref().or(d.columns.as_ref());
            let delimiter = s.delimiter.or(d.delimiter).unwrap_or(Delimiter::Comma);
            let is_mat = Path::new(&file)
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("mat"));
            let variables = s.variables.as_ref().or(d.variables.as_ref());
            let mut notes = Vec::new();
            let (samples, velocity_estimated) = match (is_mat, variables) {
                (true, Some(v)) => super::matlab::read_samples(
                    &data_path,
                    v.get_ref(),
                    &mpath,
                    line_of(text, v.span().start),
                    &mut notes,
                )?,
                (true, None) => {
                    return Err(DatasetError::Manifest {
                        path: mpath,
                        line,
                        message: format!(
                            "`{file}` is a MATLAB file: give its variables, e.g. \
                             variables = {{ time_s = \"t\", displacement_mm = \"x\", force_n = \"F\" }}"
                        ),
                    })
                }
                (false, _) => {
                    let block = s
                        .block
                        .as_ref()
                        .or(d.block.as_ref())
                        .map(|b| (*b.get_ref(), line_of(text, b.span().start)));
                    read_samples(&data_path, delimiter, columns, block, &mpath, text, &mut notes)?
                }
            };
            let mass_kg = finite(s.mass_kg.as_ref().or(d.mass_kg.as_ref()), "mass_kg")?;
            let impact_velocity_m_s = finite(
                s.impact_velocity_m_s.as_ref().or(d.impact_velocity_m_s.as_ref()),
                "impact_velocity_m_s",
            )?;
            let mut samples = samples;
            let sign = s.sign.as_ref().or(d.sign.as_ref());
            let declared = match sign {
                Some(sign) => apply_signs(&mut samples, sign.get_ref(), &mpath, line_of(text, sign.span().start))?,
                None => Vec::new(),
            };
            // An accelerometer drop record: the force from the striker's
            // acceleration and the drop mass (super::accelerometer).
            let mut accelerometer = None;
            if samples.force_n.is_empty() {
                let dv0 = finite(
                    s.impact_velocity_uncertainty_m_s
                        .as_ref()
                        .or(d.impact_velocity_uncertainty_m_s.as_ref()),
                    "impact_velocity_uncertainty_m_s",
                )?;
                accelerometer = Some(force_from_accelerometer(
                    &mut samples,
                    &file,
                    mass_kg,
                    impact_velocity_m_s,
                    dv0,
                    &mpath,
                    line,
                )?);
            }
            let impact = mass_kg.is_some() || impact_velocity_m_s.is_some();
            let check = |samples: &Samples, measured_v: bool| {
                let found = super::sign::inverted_columns(
                    &samples.force_n,
                    (!samples.x_mm.is_empty()).then_some(samples.x_mm.as_slice()),
                    measured_v.then_some(samples.v_m_s.as_slice()),
                    samples.accel_m_s2.as_deref(),
                );
                match found.first() {
                    Some(inv) if impact => return Err(inverted_error(&mpath, line, &file, inv, &declared)),
                    _ => {}
                }
                // Every record, impact or not: the work on the damper while loading.
                match super::sign::negative_work(&samples.force_n, &samples.x_mm) {
                    Some(inv) if !samples.x_mm.is_empty() => Err(inverted_error(&mpath, line, &file, &inv, &declared)),
                    _ => Ok(()),
                }
            };
            check(&samples, !velocity_estimated && !samples.x_mm.is_empty())?;
            let motion_from = if samples.x_mm.is_empty() {
                Some(derive_motion(
                    &mut samples,
                    &file,
                    mass_kg,
                    impact_velocity_m_s,
                    accelerometer,
                    &mpath,
                    line,
                )?)
            } else {
                None
            };
            recordings.push(Recording {
                file,
                current_a,
                role: s.role.or(d.role).unwrap_or(Role::Fit),
                mass_kg,
                impact_velocity_m_s,
                sequence: s.sequence.or(d.sequence),
                temperature_c: finite(s.temperature_c.as_ref().or(d.temperature_c.as_ref()), "temperature_c")?,
                tags: s.tags.clone().or_else(|| d.tags.clone()).unwrap_or_default(),
                samples,
                velocity_estimated,
                motion_from,
                notes,
            });
        }
        Ok(Dataset {
            name: manifest.name,
            root: dir.to_path_buf(),
            recordings,
        })
    }
}

/// The canonical column name of a quantity, for messages and `sign`.
fn canonical_name(q: Quantity) -> &'static str {
    match q {
        Quantity::Time => "time_s",
        Quantity::Displacement => "displacement_mm",
        Quantity::Velocity => "velocity_m_s",
        Quantity::Acceleration => "acceleration_m_s2",
        Quantity::Force => "force_n",
        Quantity::Current => "current_a",
        Quantity::Temperature => "temperature_c",
    }
}

/// Applies `sign = { force_n = -1, … }` to the samples; returns the
/// quantities declared −1.
fn apply_signs(
    samples: &mut Samples,
    sign: &BTreeMap<String, i64>,
    mpath: &str,
    line: usize,
) -> Result<Vec<Quantity>, DatasetError> {
    let mut flipped = Vec::new();
    for (name, &value) in sign {
        let bad = |message: String| DatasetError::Manifest {
            path: mpath.to_string(),
            line,
            message,
        };
        let layout = parse_header(std::slice::from_ref(name), mpath, line).map_err(|_| {
            bad(format!(
                "sign: `{name}` is not a column name (e.g. force_n, displacement_mm)"
            ))
        })?;
        let Some((quantity, _)) = layout[0] else {
            return Err(bad("sign: `ignore` has no sign".to_string()));
        };
        if value != 1 && value != -1 {
            return Err(bad(format!("sign: `{name} = {value}`; a sign is 1 or -1")));
        }
        if value == 1 {
            continue;
        }
        let channel: Option<&mut Vec<f64>> = match quantity {
            Quantity::Force => Some(&mut samples.force_n),
            Quantity::Displacement => Some(&mut samples.x_mm),
            Quantity::Velocity => Some(&mut samples.v_m_s),
            Quantity::Acceleration => samples.accel_m_s2.as_mut(),
            Quantity::Current => samples.current_a.as_mut(),
            _ => None,
        };
        let Some(channel) = channel else {
            return Err(bad(format!("sign: `{name}` cannot be flipped")));
        };
        channel.iter_mut().for_each(|v| *v = -*v);
        flipped.push(quantity);
    }
    Ok(flipped)
}

/// The refusal of a recording whose column reads compression negative.
fn inverted_error(
    mpath: &str,
    line: usize,
    file: &str,
    inv: &super::sign::Inverted,
    declared: &[Quantity],
) -> DatasetError {
    let name = canonical_name(inv.quantity);
    let q = inv.quantity.describe();
    let message = if declared.contains(&inv.quantity) {
        format!(
            "`{file}`: the {q} column looks inverted after the declared sign {{ {name} = -1 }}: {}; \
             compression must read positive force and displacement (docs/dataset-format.md, sign); \
             remove the declaration for this recording",
            inv.evidence
        )
    } else {
        format!(
            "`{file}`: the {q} column looks inverted: {}; compression must read positive force and \
             displacement (docs/dataset-format.md, sign); if the instrument reads it that way, declare \
             sign = {{ {name} = -1 }} for this recording or in [defaults]",
            inv.evidence
        )
    };
    DatasetError::Manifest {
        path: mpath.to_string(),
        line,
        message,
    }
}

/// Velocity and displacement of a record without displacement, from its
/// acceleration (when recorded) or its force, the drop mass and the impact
/// velocity (`super::motion`).
fn derive_motion(
    samples: &mut Samples,
    file: &str,
    mass_kg: Option<f64>,
    impact_velocity_m_s: Option<f64>,
    accelerometer: Option<super::accelerometer::IntegrationUncertainty>,
    mpath: &str,
    line: usize,
) -> Result<MotionSource, DatasetError> {
    let missing = |what: &str| DatasetError::Manifest {
        path: mpath.to_string(),
        line,
        message: format!(
            "`{file}` has no displacement column, so its motion is integrated from force and time \
             (docs/dataset-format.md, force–time drop records); that needs {what}"
        ),
    };
    let v0 = impact_velocity_m_s.ok_or_else(|| missing("`impact_velocity_m_s`"))?;
    let source = if let (Some(uncertainty), Some(mass_kg)) = (accelerometer, mass_kg) {
        MotionSource::Accelerometer {
            mass_kg,
            impact_velocity_m_s: v0,
            uncertainty,
        }
    } else if samples.accel_m_s2.is_some() {
        MotionSource::Acceleration {
            impact_velocity_m_s: v0,
        }
    } else {
        MotionSource::Force {
            mass_kg: mass_kg.ok_or_else(|| missing("`mass_kg` (or an acceleration column)"))?,
            impact_velocity_m_s: v0,
        }
    };
    let window = super::motion::derive_motion(samples, source).ok_or_else(|| DatasetError::Manifest {
        path: mpath.to_string(),
        line,
        message: format!("`{file}`: no force above zero, so no contact to integrate from"),
    })?;
    if samples.len() < MIN_SAMPLES {
        return Err(DatasetError::Manifest {
            path: mpath.to_string(),
            line,
            message: format!(
                "`{file}`: the contact (force above {} % of its peak) spans {} samples; a fit needs {MIN_SAMPLES}",
                super::motion::CONTACT_FRACTION * 100.0,
                window.end - window.start
            ),
        });
    }
    Ok(source)
}

/// The force of a record with acceleration and no force column,
/// F = m·(g − a), the accelerometer's offset removed from `samples`.
fn force_from_accelerometer(
    samples: &mut Samples,
    file: &str,
    mass_kg: Option<f64>,
    v0_m_s: Option<f64>,
    dv0_m_s: Option<f64>,
    mpath: &str,
    line: usize,
) -> Result<super::accelerometer::IntegrationUncertainty, DatasetError> {
    let refuse = |why: String| DatasetError::Manifest {
        path: mpath.to_string(),
        line,
        message: format!("`{file}` is an accelerometer drop record (acceleration, no force): {why}"),
    };
    let Some(mass_kg) = mass_kg else {
        return Err(refuse(
            "its force is m·(g − a), which needs the drop mass `mass_kg` (docs/dataset-format.md, \
             accelerometer drop records)"
                .to_string(),
        ));
    };
    let Some(accel) = samples.accel_m_s2.as_mut() else {
        return Err(refuse("no acceleration column".to_string()));
    };
    let (force_n, uncertainty) =
        super::accelerometer::force_from_acceleration(&samples.time_s, accel, mass_kg, v0_m_s.unwrap_or(0.0), dv0_m_s)
            .map_err(|r| refuse(r.sentence(canonical_name(Quantity::Acceleration))))?;
    samples.force_n = force_n;
    Ok(uncertainty)
}

/// Rejects keys the format does not define, naming the key and its line.
fn check_keys(text: &str, mpath: &str) -> Result<(), DatasetError> {
    let doc = toml::de::DeTable::parse(text).map_err(|e| syntax_error(mpath, text, &e))?;
    let unknown = |key: &Spanned<toml::de::DeString<'_>>, section: &str| DatasetError::UnknownKey {
        path: mpath.to_string(),
        line: line_of(text, key.span().start),
        key: key.get_ref().to_string(),
        section: section.to_string(),
    };
    for (key, value) in doc.get_ref() {
        match key.get_ref().as_ref() {
            "defaults" => {
                if let Some(t) = value.get_ref().as_table() {
                    for (k, _) in t {
                        if k.get_ref() == "file" || !RECORDING_KEYS.contains(&k.get_ref().as_ref()) {
                            return Err(unknown(k, "[defaults]"));
                        }
                    }
                }
            }
            "recording" => {
                if let Some(arr) = value.get_ref().as_array() {
                    for item in arr.iter() {
                        if let Some(t) = item.get_ref().as_table() {
                            if !t.keys().any(|k| k.get_ref() == "file") {
                                return Err(DatasetError::Manifest {
                                    path: mpath.to_string(),
                                    line: line_of(text, item.span().start),
                                    message: "[[recording]] has no `file`".to_string(),
                                });
                            }
                            for (k, _) in t {
                                if !RECORDING_KEYS.contains(&k.get_ref().as_ref()) {
                                    return Err(unknown(k, "[[recording]]"));
                                }
                            }
                        }
                    }
                }
            }
            k if TOP_KEYS.contains(&k) => {}
            _ => return Err(unknown(key, "the top level")),
        }
    }
    Ok(())
}

/// The rows of a text recording as the loader reads them (quotes and CRLF
/// handled, decimal commas and digit grouping read), for `mre dataset
/// init`, which must see the file as the loader will. `text` is the file
/// already decoded (`super::text::decode`): init decodes each file once and
/// reads both its delimiter and its rows from that text.
/// `delimiter`: `,`, `;`, or anything else for whitespace.
/// Each row comes with its line in the file.
pub(super) fn text_rows(text: &str, delimiter: char, dpath: &str) -> Result<Vec<(usize, Vec<String>)>, DatasetError> {
    let delimiter = match delimiter {
        ',' => Delimiter::Comma,
        ';' => Delimiter::Semicolon,
        _ => Delimiter::Whitespace,
    };
    records_in(text, delimiter, dpath)
}

/// The non-comment records of a recording file as (line, fields): the
/// bytes decoded (`super::text`, a byte-order mark skipped), then
/// [`records_in`].
fn records(bytes: &[u8], delimiter: Delimiter, dpath: &str) -> Result<Vec<(usize, Vec<String>)>, DatasetError> {
    // Any encoding a lab's software writes (super::text), as UTF-8 from here on.
    let decoded = super::text::decode(bytes).map_err(|line| DatasetError::BadRecord {
        path: dpath.to_string(),
        line,
        message: "binary bytes (NUL) where a text recording was expected".to_string(),
    })?;
    records_in(&decoded.text, delimiter, dpath)
}

/// The records of decoded text as (line, fields): through the csv crate for
/// `,` and `;` (quotes, CRLF), split on runs of blanks for `whitespace`;
/// lines starting with `#` and blank lines are ignored.
fn records_in(text: &str, delimiter: Delimiter, dpath: &str) -> Result<Vec<(usize, Vec<String>)>, DatasetError> {
    // CRLF as LF: the csv crate counts a blank CRLF line short, which put
    // every later line number one too low.
    let text = match text.contains("\r\n") {
        true => std::borrow::Cow::Owned(text.replace("\r\n", "\n")),
        false => std::borrow::Cow::Borrowed(text),
    };
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    match delimiter {
        Delimiter::Comma | Delimiter::Semicolon => {
            let semicolon = delimiter == Delimiter::Semicolon;
            let mut reader = csv::ReaderBuilder::new()
                .delimiter(if semicolon { b';' } else { b',' })
                .has_headers(false)
                .flexible(true)
                .trim(csv::Trim::All)
                .comment(Some(b'#'))
                .from_reader(bytes);
            for record in reader.records() {
                let record = record.map_err(|e| DatasetError::BadRecord {
                    path: dpath.to_string(),
                    line: e.position().map_or(1, |p| p.line() as usize),
                    message: match e.kind() {
                        csv::ErrorKind::Utf8 { err, .. } => format!("field {} is not UTF-8 text", err.field() + 1),
                        _ => e.to_string(),
                    },
                })?;
                let line = record.position().map_or(1, |p| record_line(bytes, p));
                if record.iter().all(str::is_empty) {
                    continue;
                }
                let field = |f: &str| if semicolon { decimal_comma(f) } else { grouped(f) };
                out.push((line, record.iter().map(field).collect()));
            }
        }
        Delimiter::Whitespace => {
            let text = std::str::from_utf8(bytes).map_err(|e| DatasetError::BadRecord {
                path: dpath.to_string(),
                line: bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1,
                message: "not UTF-8 text".to_string(),
            })?;
            for (i, line) in text.lines().enumerate() {
                let trimmed = line.trim();
                if trimmed.is_empty() || trimmed.starts_with('#') {
                    continue;
                }
                // A comma inside a blank-separated field is a decimal comma
                // (LabVIEW's spreadsheet text in a German locale: `0,001\t1,25`).
                let fields = trimmed
                    .split_whitespace()
                    .map(|f| decimal_comma(f.trim_matches('"')))
                    .collect();
                out.push((i + 1, fields));
            }
        }
    }
    Ok(out)
}

/// The line a csv record is on, as an editor numbers it: the csv crate
/// places a record after blank or `#` lines at the first of them.
fn record_line(bytes: &[u8], p: &csv::Position) -> usize {
    let mut line = p.line() as usize;
    let mut at = (p.byte() as usize).min(bytes.len());
    while let Some(end) = bytes[at..].iter().position(|&b| b == b'\n') {
        let this = &bytes[at..at + end];
        if !(this.iter().all(|&b| b == b'\r') || this.first() == Some(&b'#')) {
            break;
        }
        line += 1;
        at += end + 1;
    }
    line
}

/// A field of a `;` file: `1,5` is the number 1.5, and `1.004,5` or
/// `1 004,5` (digits grouped in threes, as a spreadsheet in a German or
/// French locale writes them) is 1004.5; other text is kept as written (a
/// name, or a bad value reported as written).
fn decimal_comma(f: &str) -> String {
    let dotted = f.replacen(',', ".", 1);
    if !f.contains('.') && dotted.parse::<f64>().is_ok() {
        return dotted;
    }
    if let Some((int, frac)) = f.split_once(',') {
        if let Some(digits) = ungroup(int, &['.', ' ', '\u{a0}', '\u{202f}']) {
            let number = format!("{digits}.{frac}");
            if frac.chars().all(|c| c.is_ascii_digit()) && number.parse::<f64>().is_ok() {
                return number;
            }
        }
    }
    f.to_owned()
}

/// A field of a comma-separated file: `1,004.80328` (quoted, digits grouped
/// in threes before a decimal point, as Bluehill writes loads of 1000 N and
/// more) is 1004.80328. Without a decimal point `1,004` could be a decimal
/// comma too, so it is kept as written (and refused as not a number).
fn grouped(f: &str) -> String {
    if let Some((int, frac)) = f.split_once('.') {
        if let Some(digits) = ungroup(int, &[',']) {
            let number = format!("{digits}.{frac}");
            if number.parse::<f64>().is_ok() {
                return number;
            }
        }
    }
    f.to_owned()
}

/// `int` without its group separators when it is digits grouped in threes
/// by one of `separators` (`-1,004` → `-1004`); `None` when it is not
/// grouped that way (no separator at all is `None` too).
fn ungroup(int: &str, separators: &[char]) -> Option<String> {
    let (sign, body) = match int.strip_prefix(['-', '+']) {
        Some(rest) => (&int[..1], rest),
        None => ("", int),
    };
    let sep = body.chars().find(|c| separators.contains(c))?;
    let groups: Vec<&str> = body.split(sep).collect();
    let digits = |g: &str| g.chars().all(|c| c.is_ascii_digit());
    let ok = groups.len() > 1
        && (1..=3).contains(&groups[0].len())
        && groups.iter().all(|g| digits(g))
        && groups[1..].iter().all(|g| g.len() == 3);
    ok.then(|| format!("{sign}{}", groups.concat()))
}

fn read_samples(
    path: &Path,
    delimiter: Delimiter,
    columns: Option<&Spanned<Vec<String>>>,
    block: Option<(usize, usize)>,
    mpath: &str,
    manifest_text: &str,
    notes: &mut Vec<String>,
) -> Result<(Samples, bool), DatasetError> {
    let dpath = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| DatasetError::Unreadable {
        path: dpath.clone(),
        reason: e.to_string(),
    })?;
    if let Some(reader) = super::vendor::recognise(&bytes) {
        let (names, line) = match (columns, block) {
            (Some(c), _) => (Some(c.get_ref().as_slice()), line_of(manifest_text, c.span().start)),
            (None, Some((_, line))) => (None, line),
            (None, None) => (None, 1),
        };
        let block = block.map(|(k, _)| k);
        let settings = super::vendor::Settings {
            columns: names,
            block,
            mpath,
            line,
        };
        return super::vendor::read_samples(reader, path, &bytes, settings, notes);
    }
    if let Some((_, line)) = block {
        return Err(DatasetError::Manifest {
            path: mpath.to_string(),
            line,
            message: format!("`block` picks a data block of an MTS 793 Specimen.dat; `{dpath}` is not one"),
        });
    }
    parse_samples(&bytes, delimiter, columns, &dpath, mpath, manifest_text, notes)
}

/// Parses one recording file with a header row, or a vendor export
/// (`super::vendor`), as [`Dataset::load`] does (`whitespace`: the
/// `delimiter = "whitespace"` format). `path` names the file in errors (a
/// TDMS file is read from it).
pub fn parse_recording(bytes: &[u8], whitespace: bool, path: &str) -> Result<Samples, DatasetError> {
    if let Some(reader) = super::vendor::recognise(bytes) {
        return super::vendor::read_samples(
            reader,
            Path::new(path),
            bytes,
            super::vendor::Settings {
                columns: None,
                block: None,
                mpath: "",
                line: 0,
            },
            &mut Vec::new(),
        )
        .map(|(samples, _)| samples);
    }
    let delimiter = if whitespace {
        Delimiter::Whitespace
    } else {
        Delimiter::Comma
    };
    parse_samples(bytes, delimiter, None, path, "", "", &mut Vec::new()).map(|(samples, _)| samples)
}

fn parse_samples(
    bytes: &[u8],
    delimiter: Delimiter,
    columns: Option<&Spanned<Vec<String>>>,
    dpath: &str,
    mpath: &str,
    manifest_text: &str,
    notes: &mut Vec<String>,
) -> Result<(Samples, bool), DatasetError> {
    let dpath = dpath.to_string();
    let mut lines = records(bytes, delimiter, &dpath)?.into_iter();

    // Column names come from `columns` in dataset.toml, or from the header row.
    let (names, name_path, name_line): (Vec<String>, &str, usize) = match columns {
        Some(c) => {
            // Header rows that `columns` renames (`Force (kN)` → `force_kn`,
            // as `mre dataset init` writes), and a vendor's metadata and
            // units rows above the data, are skipped: every row before the
            // first all-numeric one.
            let mut skipped: Option<(usize, usize, usize)> = None;
            while let Some((n, _)) = lines
                .as_slice()
                .first()
                .filter(|(_, f)| f.iter().any(|x| x.parse::<f64>().is_err()))
            {
                let (first, _, count) = skipped.unwrap_or((*n, *n, 0));
                skipped = Some((first, *n, count + 1));
                lines.next();
            }
            if let Some((first, last, count)) = skipped {
                notes.push(format!(
                    "{count} row(s) above the first data row skipped (lines {first}–{last}: the file's names, \
                     metadata, units), as `columns` names the columns"
                ));
            }
            (c.get_ref().clone(), mpath, line_of(manifest_text, c.span().start))
        }
        None if lines
            .as_slice()
            .first()
            .is_some_and(|(_, f)| f.iter().all(|x| x.parse::<f64>().is_ok())) =>
        {
            let (line, fields) = &lines.as_slice()[0];
            return Err(DatasetError::BadRecord {
                path: dpath.clone(),
                line: *line,
                message: format!(
                    "holds {} numbers, not column names: the file has no header; name its columns in \
                     dataset.toml, e.g. columns = [\"time_s\", \"force_n\"] (docs/dataset-format.md)",
                    fields.len()
                ),
            });
        }
        None => match header(&mut lines, notes) {
            Some((n, names)) => (names, &dpath, n),
            None => {
                return Err(DatasetError::TooFewSamples {
                    path: dpath,
                    line: 1,
                    count: 0,
                    min: MIN_SAMPLES,
                })
            }
        },
    };
    let rows = lines.map(|(n, f)| (n, f.into_iter().map(Cell::Text).collect()));
    samples_from_rows(&dpath, &names, name_path, name_line, rows, notes)
}

/// Units a units row under the names may hold (lower case, brackets
/// stripped): the ones [`super::columns::map_name`] reads, and a few it
/// does not, so the row is still told from a data row.
const UNIT_WORDS: &[&str] = &[
    "s", "sec", "secs", "ms", "min", "mm", "m", "in", "cm", "n", "kn", "lbf", "kgf", "g", "m/s", "mm/s", "m/s^2",
    "m/s²", "a", "ma", "v", "mv", "°c", "degc", "c", "%", "mpa", "kpa", "pa", "-", "",
    // Strain, stress and angle units a testing machine's export carries next to force and stroke.
    "mm/mm", "in/in", "m/m", "n/mm²", "n/mm^2", "n/mm2", "psi", "ksi", "gpa", "j", "nm", "n·m", "deg", "°", "µm", "μm",
    "um", "µs", "us", "h", "hz", "kg",
];

pub(super) fn is_units_row(fields: &[String]) -> bool {
    fields.iter().any(|f| !f.is_empty())
        && fields.iter().all(|f| {
            let u = f.trim().trim_matches(|c| "()[]".contains(c)).trim().to_lowercase();
            UNIT_WORDS.contains(&u.as_str())
        })
}

/// The header of a file without `columns`: its first row when that names
/// columns mre reads (as the format asks). Otherwise, as labs' software
/// writes: the names are the row above the first all-numeric row, or two
/// above when the row between is a units row (`(sec)`, `(N)`), which is
/// joined to the names (`Load` over `(N)` → `force_n`); rows above the
/// names (a Bluehill `Results Table 1 : Specimen 1`, a date) are skipped
/// and noted. Leaves `lines` at the first data row.
fn header(
    lines: &mut std::vec::IntoIter<(usize, Vec<String>)>,
    notes: &mut Vec<String>,
) -> Option<(usize, Vec<String>)> {
    let rows = lines.as_slice();
    let first = rows.first()?.clone();
    let numeric = |f: &[String]| f.iter().all(|x| x.parse::<f64>().is_ok());
    let reads = |names: &[String]| parse_header(names, "", 1).is_ok();
    let data = rows.iter().position(|(_, f)| numeric(f));
    let plan = match data {
        Some(d) if !reads(&first.1) && d >= 1 => {
            let units = d >= 2 && is_units_row(&rows[d - 1].1) && rows[d - 2].1.len() == rows[d - 1].1.len();
            let names_at = if units { d - 2 } else { d - 1 };
            let (line, raw) = &rows[names_at];
            let joined: Vec<String> = raw
                .iter()
                .enumerate()
                .map(|(i, name)| {
                    let unit = units.then(|| rows[d - 1].1[i].trim().trim_matches(|c| "()[]".contains(c)).trim());
                    match unit {
                        Some(u) if !u.is_empty() => format!("{name} ({u})"),
                        _ => name.clone(),
                    }
                })
                .collect();
            // In an instrument's layout (a units row, or rows above the
            // names) a channel that maps to nothing (strain, stress, a
            // command) is ignored, as the vendor readers ignore it; a second
            // clock too (MTS TestSuite's `Zeit` and `Laufzeit`): the first is
            // the time. A plain first-row header keeps unknown names, so a
            // misspelt `displacement_cm` is still refused by name.
            let export = units || names_at > 0;
            let mut ignored = Vec::new();
            let mut time_at = None;
            let names: Vec<String> = joined
                .iter()
                .enumerate()
                .map(|(i, j)| match super::columns::map_name(j) {
                    Some(n) if export && n.starts_with("time_") && time_at.is_some() => {
                        ignored.push(format!("`{j}` (a second clock)"));
                        "ignore".to_string()
                    }
                    Some(n) => {
                        if n.starts_with("time_") {
                            time_at = Some(i);
                        }
                        n
                    }
                    None if export => {
                        ignored.push(format!("`{j}`"));
                        "ignore".to_string()
                    }
                    None => raw[i].clone(),
                })
                .collect();
            if !ignored.is_empty() {
                notes.push(format!("channels not read (ignored): {}", ignored.join(", ")));
            }
            Some((names_at, *line, names, units, d))
        }
        _ => None,
    };
    match plan {
        Some((names_at, line, names, units, d)) => {
            if names_at > 0 {
                notes.push(format!(
                    "{names_at} line(s) above the column names (line {line}) skipped, from line {}",
                    rows[0].0
                ));
            }
            if units {
                notes.push(format!(
                    "the units row (line {}) read with the names: {}",
                    rows[d - 1].0,
                    names.join(", ")
                ));
            } else if names != rows[names_at].1 {
                notes.push(format!("the column names (line {line}) read as {}", names.join(", ")));
            }
            for _ in 0..d {
                lines.next();
            }
            Some((line, names))
        }
        None => lines.next(),
    }
}

/// Spreads runs of tied time stamps (s) evenly up to the next stamp: an
/// export that writes time at 0.01 s while sampling faster repeats each
/// stamp, and its rows are in order. A run at the end takes the step before
/// it. `Err(k)`: sample `k` cannot be placed (every stamp the same).
fn spread_tied_times(time_s: &mut [f64], lines: &[usize], notes: &mut Vec<String>) -> Result<(), usize> {
    let n = time_s.len();
    let mut tied = 0;
    let mut first_line = None;
    let mut resolution = f64::INFINITY;
    for w in time_s.windows(2) {
        if w[1] > w[0] {
            resolution = resolution.min(w[1] - w[0]);
        }
    }
    let mut i = 0;
    // The stamp of the run before, as written (its rows are spread by now).
    let mut previous_stamp = None;
    while i < n {
        let mut j = i + 1;
        while j < n && time_s[j] == time_s[i] {
            j += 1;
        }
        let stamp = time_s[i];
        if j - i > 1 {
            let step = match (j < n, previous_stamp) {
                (true, _) => time_s[j] - stamp,
                (false, Some(p)) => stamp - p,
                (false, None) => return Err(1.min(n - 1)),
            };
            let t0 = time_s[i];
            for (k, t) in time_s[i..j].iter_mut().enumerate() {
                *t = t0 + step * k as f64 / (j - i) as f64;
            }
            tied += j - i - 1;
            first_line.get_or_insert(lines.get(i + 1).copied().unwrap_or(0));
        }
        previous_stamp = Some(stamp);
        i = j;
    }
    if let Some(line) = first_line {
        notes.push(format!(
            "{tied} rows repeat the time stamp of the row before (first at line {line}): the export writes \
             time at {} s, coarser than it samples; kept in order, their times spread evenly up to the next stamp",
            (resolution * 1e9).round() / 1e9
        ));
    }
    Ok(())
}

/// One field of a recording: text from a CSV file, or a number from a
/// MATLAB file (already binary).
pub enum Cell {
    Text(String),
    Number(f64),
}

impl std::fmt::Display for Cell {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Cell::Text(t) => f.write_str(t),
            Cell::Number(v) => write!(f, "{v}"),
        }
    }
}

/// Checks and converts rows (line, cells) under unit-named columns `names`
/// (named at `name_path`:`name_line`) into samples in internal units;
/// the bool is true when velocity was estimated. What the reader assumed
/// (tied time stamps spread) goes to `notes`.
pub(super) fn samples_from_rows(
    dpath: &str,
    names: &[String],
    name_path: &str,
    name_line: usize,
    rows: impl Iterator<Item = (usize, Vec<Cell>)>,
    notes: &mut Vec<String>,
) -> Result<(Samples, bool), DatasetError> {
    let dpath = dpath.to_string();
    let layout = parse_header(names, name_path, name_line)?;
    required_columns(&layout, name_path, name_line)?;

    let mut channels: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut last_line = name_line;
    let mut sample_lines = Vec::new();
    let time_col = layout.iter().position(|c| matches!(c, Some((Quantity::Time, _))));
    for (n, f) in rows {
        last_line = n;
        sample_lines.push(n);
        if f.len() != names.len() {
            return Err(DatasetError::FieldCount {
                path: dpath,
                line: n,
                found: f.len(),
                expected: names.len(),
            });
        }
        for (col, text) in f.iter().enumerate() {
            let Some((quantity, scale)) = layout[col] else { continue };
            let value: f64 = match text {
                Cell::Number(v) => *v,
                Cell::Text(t) => t.parse().map_err(|_| DatasetError::NotANumber {
                    path: dpath.clone(),
                    line: n,
                    column: col + 1,
                    name: names[col].clone(),
                    text: t.clone(),
                })?,
            };
            if !value.is_finite() {
                return Err(DatasetError::NotFinite {
                    path: dpath,
                    line: n,
                    column: col + 1,
                    name: names[col].clone(),
                    text: text.to_string(),
                });
            }
            let value = value * scale;
            let (min, max, _) = quantity.plausible_range();
            if !(min..=max).contains(&value) {
                return Err(DatasetError::OutOfRange {
                    path: dpath,
                    line: n,
                    column: col + 1,
                    name: names[col].clone(),
                    text: text.to_string(),
                    quantity,
                });
            }
            if quantity == Quantity::Time && Some(col) == time_col {
                if let Some(&previous_s) = channels[col].last() {
                    // A tie is the export's clock resolution (spread below);
                    // time going back is refused.
                    if value < previous_s {
                        return Err(DatasetError::TimeNotIncreasing {
                            path: dpath,
                            line: n,
                            column: col + 1,
                            name: names[col].clone(),
                            time_s: value,
                            previous_s,
                        });
                    }
                }
            }
            channels[col].push(value);
        }
    }
    if let Some(c) = time_col {
        spread_tied_times(&mut channels[c], &sample_lines, notes).map_err(|k| DatasetError::TimeNotIncreasing {
            path: dpath.clone(),
            line: sample_lines[k],
            column: c + 1,
            name: names[c].clone(),
            time_s: channels[c][k],
            previous_s: channels[c][k - 1],
        })?;
    }
    let count = time_col.map_or(0, |c| channels[c].len());
    if count < MIN_SAMPLES {
        return Err(DatasetError::TooFewSamples {
            path: dpath,
            line: last_line,
            count,
            min: MIN_SAMPLES,
        });
    }
    let take = |q: Quantity, channels: &mut Vec<Vec<f64>>| -> Option<Vec<f64>> {
        layout
            .iter()
            .position(|c| matches!(c, Some((qq, _)) if *qq == q))
            .map(|i| std::mem::take(&mut channels[i]))
    };
    let time_s = take(Quantity::Time, &mut channels).unwrap_or_default();
    let x_mm = take(Quantity::Displacement, &mut channels).unwrap_or_default();
    let force_n = take(Quantity::Force, &mut channels).unwrap_or_default();
    // Without displacement, both are derived later from force or
    // acceleration (`super::motion`), and a velocity column is not used.
    let velocity = take(Quantity::Velocity, &mut channels);
    let (v_m_s, estimated) = match (velocity, x_mm.is_empty()) {
        (_, true) => (Vec::new(), false),
        (Some(v), false) => (v, false),
        (None, false) => (estimate_velocity_m_s(&time_s, &x_mm), true),
    };
    if estimated {
        // Samples closer in time than the displacement allows give an absurd
        // velocity: reject it here rather than in the fit.
        let (min, max, _) = Quantity::Velocity.plausible_range();
        if let Some(k) = v_m_s.iter().position(|v| !(min..=max).contains(v)) {
            let column = layout
                .iter()
                .position(|c| matches!(c, Some((Quantity::Displacement, _))));
            return Err(DatasetError::OutOfRange {
                path: dpath,
                line: sample_lines.get(k).copied().unwrap_or(last_line),
                column: column.map_or(0, |c| c + 1),
                name: format!("velocity estimated from {}", column.map_or("x", |c| names[c].as_str())),
                text: format!("{}", v_m_s[k]),
                quantity: Quantity::Velocity,
            });
        }
    }
    let samples = Samples {
        accel_m_s2: take(Quantity::Acceleration, &mut channels),
        current_a: take(Quantity::Current, &mut channels),
        temperature_c: take(Quantity::Temperature, &mut channels),
        time_s,
        x_mm,
        v_m_s,
        force_n,
    };
    Ok((samples, estimated))
}

#[cfg(test)]
mod tests {
    use super::{decimal_comma, grouped, records, Delimiter};

    /// Hand-written: a record after blank lines is on its own line, as an
    /// editor numbers it (names on line 3, data on 5), LF or CRLF.
    #[test]
    fn lines_after_blank_lines_are_numbered_as_written() {
        for eol in ["\n", "\r\n"] {
            let text = ["# c", "", "a,b", "", "1,2", ""].join(eol);
            let rows = records(text.as_bytes(), Delimiter::Comma, "f").unwrap();
            let lines: Vec<usize> = rows.iter().map(|(n, _)| *n).collect();
            assert_eq!(lines, [3, 5], "{eol:?}");
        }
    }

    /// Hand-written fields: digit grouping as spreadsheets and Bluehill write it.
    #[test]
    fn grouped_digits_read_as_one_number_and_ambiguous_ones_are_kept() {
        // Comma-separated file, quoted field (pymechtest's Bluehill export: "1,004.80328").
        assert_eq!(grouped("1,004.80328"), "1004.80328");
        assert_eq!(grouped("-12,345,678.5"), "-12345678.5");
        // `1,004` could be 1.004 with a decimal comma: kept, so it is refused as written.
        assert_eq!(grouped("1,004"), "1,004");
        assert_eq!(grouped("1,00.5"), "1,00.5");
        assert_eq!(grouped("1234,567.0"), "1234,567.0");
        // `;` file with decimal comma: `.`, space and no-break spaces group.
        assert_eq!(decimal_comma("0,5"), "0.5");
        assert_eq!(decimal_comma("1.004,25"), "1004.25");
        assert_eq!(decimal_comma("-2 500,0"), "-2500.0");
        assert_eq!(decimal_comma("1\u{a0}234\u{202f}567,8"), "1\u{a0}234\u{202f}567,8");
        assert_eq!(decimal_comma("1\u{202f}234,5"), "1234.5");
        assert_eq!(decimal_comma("1.5"), "1.5");
        assert_eq!(decimal_comma("Last"), "Last");
    }
}
