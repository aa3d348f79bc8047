//! `mre dataset init DIR`: writes `dataset.toml` for a folder of recordings,
//! asking nothing.
//!
//! - The delimiter (`,` or whitespace) and whether there is a header row are
//!   sniffed from each file.
//! - Header names are mapped to the unit-carrying names of the format
//!   (`Time (ms)` → `time_ms`, `Load [kN]` → `force_kn`); names it cannot
//!   map become `ignore` and are listed in a comment.
//! - Files without a header get their columns from the data: time is the
//!   column that rises steadily, displacement and velocity are the pair where
//!   one is the other's derivative (their ratio gives the units), and force is
//!   what is left. The file-name amplitude, when given, settles mm against m.
//! - `--pattern '{amplitude_mm}mm{frequency_hz}Hz{current_a}A'` reads metadata
//!   from file names, with `x` for the decimal point (`0x5` = 0.5).
//!   `current_a`, `impact_velocity_m_s`, `temperature_c`, `mass_kg` and
//!   `sequence` are recording keys; any other name becomes a tag.
//! - Vendor exports (MTS 793 Specimen.dat, LabVIEW .lvm, NI TDMS:
//!   `super::vendor`) are told by their content; their channel names and
//!   units name the columns.
//! - An existing dataset.toml is never overwritten.
use super::columns::{map_name, parse_header, Quantity};
use anyhow::{bail, Context, Result};
use std::fmt::Write;
use std::path::Path;

/// Extensions taken as recordings.
const DATA_EXTENSIONS: &[&str] = &["txt", "csv", "dat", "tsv", "asc", "lvm", "tdms"];
/// Pattern names that are recording keys rather than tags.
const KEYS: &[&str] = &[
    "current_a",
    "impact_velocity_m_s",
    "temperature_c",
    "mass_kg",
    "sequence",
];

#[derive(Clone, Debug, PartialEq)]
enum Delimiter {
    Comma,
    /// `;` with decimal commas.
    Semicolon,
    Whitespace,
}

/// How one file is laid out, and what was assumed on the way.
#[derive(Clone, Debug, PartialEq)]
struct Layout {
    delimiter: Delimiter,
    /// Unit-named columns; `None` when the file's own header already uses them.
    columns: Option<Vec<String>>,
    /// Said in a comment: unmapped columns, assumed units.
    notes: Vec<String>,
    /// `sign = { … }` for columns that read compression negative.
    sign: Option<String>,
}

/// One `{name}` or literal piece of a file-name pattern.
#[derive(Debug, PartialEq)]
enum Piece {
    Field(String),
    Literal(String),
}

fn parse_pattern(pattern: &str) -> Result<Vec<Piece>> {
    let mut pieces = Vec::new();
    let mut rest = pattern;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix('{') {
            let end = after
                .find('}')
                .with_context(|| format!("pattern `{pattern}`: `{{` without `}}`"))?;
            let name = &after[..end];
            if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                bail!("pattern `{pattern}`: `{{{name}}}` is not a field name (letters, digits, _)");
            }
            if matches!(pieces.last(), Some(Piece::Field(_))) {
                bail!("pattern `{pattern}`: two fields need text between them to be told apart");
            }
            pieces.push(Piece::Field(name.to_string()));
            rest = &after[end + 1..];
        } else {
            let end = rest.find('{').unwrap_or(rest.len());
            pieces.push(Piece::Literal(rest[..end].to_string()));
            rest = &rest[end..];
        }
    }
    if !pieces.iter().any(|p| matches!(p, Piece::Field(_))) {
        bail!("pattern `{pattern}` has no {{field}}");
    }
    Ok(pieces)
}

/// A number in a file name: `x` (or `.`) is the decimal point, `m` or a
/// leading `-` a minus sign (`m0x5` = −0.5).
fn parse_number(text: &str) -> Option<f64> {
    let t = text.replace(['x', 'X'], ".");
    let t = t.strip_prefix('m').map(|r| format!("-{r}")).unwrap_or(t);
    if t.is_empty() || !t.chars().all(|c| c.is_ascii_digit() || c == '.' || c == '-') {
        return None;
    }
    t.parse().ok()
}

/// The fields of a file name (without extension) matched to the pattern;
/// `None` when it does not match.
fn match_pattern(pieces: &[Piece], stem: &str) -> Option<Vec<(String, f64)>> {
    let mut rest = stem;
    let mut values = Vec::new();
    for (i, piece) in pieces.iter().enumerate() {
        match piece {
            Piece::Literal(l) => rest = rest.strip_prefix(l.as_str())?,
            Piece::Field(name) => {
                // The value runs to the next literal (first place it fits), or to the end.
                let end = match pieces.get(i + 1) {
                    Some(Piece::Literal(l)) => rest.get(1..)?.find(l.as_str())? + 1,
                    _ => rest.len(),
                };
                values.push((name.clone(), parse_number(&rest[..end])?));
                rest = &rest[end..];
            }
        }
    }
    rest.is_empty().then_some(values)
}

/// The delimiter, told from the last non-blank, non-`#` line: the data (a
/// preamble line above it, `Results Table 1 : Specimen 1`, says nothing
/// about it). Only the delimiter: the rows themselves are read once, by the
/// loader (`super::read::text_rows`).
fn sniff_delimiter(text: &str) -> Result<Delimiter> {
    let Some(last) = text
        .trim_start_matches('\u{feff}')
        .lines()
        .map(str::trim)
        .rfind(|l| !l.is_empty() && !l.starts_with('#'))
    else {
        bail!("no data lines")
    };
    // `;` first: its decimal commas would otherwise read as delimiters.
    // A tab-separated line whose fields read as numbers with decimal commas
    // (LabVIEW's spreadsheet text in a German locale) is blank-separated.
    let tab_decimal_comma = last.contains('\t')
        && last
            .split_whitespace()
            .all(|f| f.replacen(',', ".", 1).parse::<f64>().is_ok());
    Ok(if last.contains(';') {
        Delimiter::Semicolon
    } else if last.contains(',') && !tab_decimal_comma {
        Delimiter::Comma
    } else {
        Delimiter::Whitespace
    })
}

fn is_number(s: &str) -> bool {
    s.parse::<f64>().is_ok_and(f64::is_finite)
}

/// Slope of `y` on `x` through the origin, and the correlation of the two.
fn slope_and_correlation(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy, mut sxy0, mut sxx0) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
        sxy0 += a * b;
        sxx0 += a * a;
    }
    let r = if sxx > 0.0 && syy > 0.0 {
        sxy / (sxx * syy).sqrt()
    } else {
        0.0
    };
    (if sxx0 > 0.0 { sxy0 / sxx0 } else { 0.0 }, r)
}

/// The power of ten nearest to `k`, if `k` is within a factor 2 of it.
fn decade(k: f64) -> Option<i32> {
    if k <= 0.0 || !k.is_finite() {
        return None;
    }
    let e = k.log10().round() as i32;
    ((k / 10f64.powi(e)).log2().abs() < 1.0).then_some(e)
}

/// Columns of a file without a header, told from the data (module docs).
fn infer_columns(data: &[Vec<f64>], amplitude_mm: Option<f64>, notes: &mut Vec<String>) -> Result<Vec<String>> {
    let n_cols = data.len();
    let mut names: Vec<Option<String>> = vec![None; n_cols];
    let rising = |c: &Vec<f64>| c.windows(2).all(|w| w[1] > w[0]);
    let time = (0..n_cols)
        .find(|&i| rising(&data[i]))
        .context("no column rises steadily, so none can be time; give the file a header row")?;
    let t = &data[time];
    let step = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let time_ms = step >= 1.0;
    names[time] = Some(if time_ms { "time_ms" } else { "time_s" }.into());
    let t_s: Vec<f64> = t.iter().map(|v| if time_ms { v * 1e-3 } else { *v }).collect();
    notes.push(format!(
        "time: column {} (rises steadily; {} s per sample taken as {})",
        time + 1,
        crate::html::json::format_number(step),
        if time_ms { "ms" } else { "s" }
    ));

    // Displacement and velocity: the pair where one is the other's derivative.
    let derivative = |c: &[f64]| -> Vec<f64> {
        (1..c.len() - 1)
            .map(|k| (c[k + 1] - c[k - 1]) / (t_s[k + 1] - t_s[k - 1]))
            .collect()
    };
    let mut best: Option<(usize, usize, f64, f64)> = None;
    for a in (0..n_cols).filter(|&i| i != time) {
        let da = derivative(&data[a]);
        for b in (0..n_cols).filter(|&i| i != time && i != a) {
            let (k, r) = slope_and_correlation(&da, &data[b][1..data[b].len() - 1]);
            if r > 0.9 && best.is_none_or(|(.., rb)| r > rb) {
                best = Some((a, b, k, r));
            }
        }
    }
    let (x, v, k, r) = best.context(
        "no two columns are displacement and its derivative (velocity), so the columns cannot be told apart; \
         give the file a header row",
    )?;
    // Displacement unit from the file-name amplitude when known, else mm.
    let half_range = {
        let c = &data[x];
        let (lo, hi) = c.iter().fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
        (hi - lo) / 2.0
    };
    let x_in_m = match amplitude_mm.map(|a| decade(half_range / a)) {
        Some(Some(-3)) => true,
        Some(Some(0)) => false,
        Some(_) => bail!(
            "column {} (displacement) spans ±{} but the file name says amplitude {} mm: neither mm nor m",
            x + 1,
            crate::html::json::format_number(half_range),
            amplitude_mm.unwrap_or_default()
        ),
        None => {
            notes.push(format!(
                "displacement: column {} taken as mm (no amplitude in the file name)",
                x + 1
            ));
            false
        }
    };
    // v ≈ k · dx/dt: k = 1 same length unit, 10⁻³ or 10³ the other one.
    let v_in_m = match (x_in_m, decade(k)) {
        (true, Some(0)) | (false, Some(-3)) => true,
        (false, Some(0)) | (true, Some(3)) => false,
        _ => bail!(
            "column {} follows the derivative of column {} (correlation {r:.3}) with factor {k:.3e}, \
             which is no unit conversion; give the file a header row",
            v + 1,
            x + 1
        ),
    };
    names[x] = Some(if x_in_m { "displacement_m" } else { "displacement_mm" }.into());
    names[v] = Some(if v_in_m { "velocity_m_s" } else { "velocity_mm_s" }.into());
    notes.push(format!(
        "displacement: column {}, velocity: column {} (its derivative; correlation {r:.3}, factor {k:.4})",
        x + 1,
        v + 1
    ));
    // Force: what is left (the largest if several).
    let rest: Vec<usize> = (0..n_cols).filter(|&i| names[i].is_none()).collect();
    let peak = |i: usize| data[i].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let force = rest
        .iter()
        .copied()
        .max_by(|&a, &b| peak(a).total_cmp(&peak(b)))
        .context("no column is left for force")?;
    names[force] = Some("force_n".into());
    notes.push(format!("force: column {} taken as N; check the unit", force + 1));
    for i in rest.into_iter().filter(|&i| i != force) {
        notes.push(format!("column {} not recognised: ignored", i + 1));
    }
    Ok(names
        .into_iter()
        .map(|n| n.unwrap_or_else(|| "ignore".into()))
        .collect())
}

/// Sniffs one text file's layout from its bytes.
fn sniff(path: &Path, bytes: &[u8], amplitude_mm: Option<f64>) -> Result<Layout> {
    // In the encoding it was written in, as the loader reads it (super::text);
    // decoded once, for the delimiter and the rows both.
    let decoded = super::text::decode(bytes)
        .map_err(|line| anyhow::anyhow!("binary bytes (NUL) at line {line}: not a text recording"))?;
    let delimiter = sniff_delimiter(&decoded.text)?;
    // The rows as the loader will read them (quoted fields, CRLF, digit grouping).
    let (lines, records): (Vec<usize>, Vec<Vec<String>>) = super::read::text_rows(
        &decoded.text,
        match delimiter {
            Delimiter::Comma => ',',
            Delimiter::Semicolon => ';',
            Delimiter::Whitespace => ' ',
        },
        &path.display().to_string(),
    )
    .map_err(|e| anyhow::anyhow!("{e}"))?
    .into_iter()
    .unzip();
    if records.is_empty() {
        bail!("no data lines");
    }
    let mut notes = Vec::new();
    // Rows above the first all-numeric one: vendor metadata, then the name
    // row, and under it perhaps a units row (`(sec),(mm),(N)`, Bluehill;
    // `sec;kN`, MTS TestSuite), told as the loader tells it.
    let first_data = records
        .iter()
        .position(|r| r.iter().all(|f| is_number(f)))
        .unwrap_or(records.len());
    let header = first_data > 0;
    if header {
        let with_units = first_data >= 2
            && super::read::is_units_row(&records[first_data - 1])
            && records[first_data - 2].len() == records[first_data - 1].len();
        // The line of the names, for errors (blank and `#` lines counted).
        let names_line = lines[first_data - if with_units { 2 } else { 1 }];
        let raw_names: Vec<String> = match first_data {
            n if with_units => {
                notes.push("units from the units row under the names".to_string());
                records[n - 2]
                    .iter()
                    .zip(&records[n - 1])
                    .map(|(name, unit)| format!("{name} {unit}"))
                    .collect()
            }
            n => records[n - 1].clone(),
        };
        if first_data > 1 {
            notes.push(format!(
                "{} rows above the data skipped (metadata, names, units)",
                first_data
            ));
        }
        let mut names: Vec<String> = raw_names
            .iter()
            .map(|raw| match map_name(raw) {
                Some(n) => n,
                None => {
                    notes.push(format!("column `{raw}` not recognised: ignored"));
                    "ignore".into()
                }
            })
            .collect();
        // Two clocks (MTS TestSuite's `Zeit` and `Laufzeit`, test and run
        // time) both read as time: the first is the time, the others are
        // ignored, and said so. Two forces or strokes stay an error: which
        // one is meant cannot be told.
        let is_time = |n: &str| {
            matches!(
                parse_header(&[n.to_string()], "", 1).as_deref(),
                Ok([Some((Quantity::Time, _))])
            )
        };
        if let Some(first) = names.iter().position(|n| is_time(n)) {
            for i in first + 1..names.len() {
                if is_time(&names[i]) {
                    notes.push(format!(
                        "column `{}` is a second clock: ignored (time is column {}, `{}`)",
                        raw_names[i],
                        first + 1,
                        raw_names[first]
                    ));
                    names[i] = "ignore".into();
                }
            }
        }
        let layout =
            parse_header(&names, &path.display().to_string(), names_line).map_err(|e| anyhow::anyhow!("{e}"))?;
        // Never a manifest that cannot load: no time or no force is refused
        // here, with the file's columns and the names mre accepts.
        super::columns::required_columns(&layout, &path.display().to_string(), names_line).map_err(|e| {
            anyhow::anyhow!(
                "{e}; the file's columns are {}; name them with `columns` by hand (docs/dataset-format.md)",
                raw_names
                    .iter()
                    .map(|n| format!("`{n}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?;
        let unchanged = first_data == 1 && names.iter().zip(&records[0]).all(|(n, raw)| n == raw);
        let sign = detect_flip(&names, &records[first_data..], &mut notes);
        return Ok(Layout {
            delimiter,
            columns: (!unchanged).then_some(names),
            notes,
            sign,
        });
    }
    let width = records[0].len();
    let mut data = vec![Vec::new(); width];
    for r in &records {
        if r.len() != width || !r.iter().all(|f| is_number(f)) {
            break;
        }
        for (c, f) in r.iter().enumerate() {
            data[c].push(f.parse::<f64>().unwrap_or(f64::NAN));
        }
    }
    if data[0].len() < 5 {
        bail!("fewer than 5 numeric rows to tell the columns from");
    }
    let columns = infer_columns(&data, amplitude_mm, &mut notes)?;
    let sign = detect_flip(&columns, &records, &mut notes);
    Ok(Layout {
        delimiter,
        columns: Some(columns),
        notes,
        sign,
    })
}

/// The `sign = { … }` that makes an impact record read compression
/// positive (`super::sign`), with the evidence as an assumption in `notes`;
/// `None` when nothing looks inverted or the record is not one-sided.
fn detect_flip(names: &[String], rows: &[Vec<String>], notes: &mut Vec<String>) -> Option<String> {
    let layout = parse_header(names, "", 1).ok()?;
    // In internal units (N, mm), as `super::sign` reports them.
    let column = |q: Quantity| -> Option<(usize, Vec<f64>)> {
        let i = layout.iter().position(|c| matches!(c, Some((qq, _)) if *qq == q))?;
        let scale = layout[i].map_or(1.0, |(_, factor)| factor);
        let values = rows
            .iter()
            .map_while(|r| r.get(i).and_then(|f| f.parse::<f64>().ok()))
            .map(|v| v * scale)
            .collect();
        Some((i, values))
    };
    let (fi, force) = column(Quantity::Force)?;
    if force.is_empty() {
        return None;
    }
    let x = column(Quantity::Displacement);
    let mut found = if super::sign::one_sided(&force) {
        super::sign::inverted_columns(&force, x.as_ref().map(|(_, v)| v.as_slice()), None, None)
    } else {
        Vec::new()
    };
    // The load checks the work while loading on every record: the flips
    // written must leave it positive, or the manifest would not load.
    if let Some((_, xs)) = &x {
        let flipped = |c: &[f64], q: Quantity| -> Vec<f64> {
            let s = if found.iter().any(|i| i.quantity == q) {
                -1.0
            } else {
                1.0
            };
            c.iter().map(|v| v * s).collect()
        };
        let (f2, x2) = (flipped(&force, Quantity::Force), flipped(xs, Quantity::Displacement));
        if super::sign::negative_work(&f2, &x2).is_some() {
            // Flip the column the mean-sign checks did not flip (force when neither).
            let q = if found.iter().any(|i| i.quantity == Quantity::Force) {
                Quantity::Displacement
            } else {
                Quantity::Force
            };
            match found.iter().position(|i| i.quantity == q) {
                Some(i) => {
                    found.remove(i);
                }
                None => found.push(super::sign::Inverted {
                    quantity: q,
                    evidence: "the work done on the damper while loading is negative otherwise".to_string(),
                }),
            }
        }
    }
    let mut flips = Vec::new();
    for inv in &found {
        let i = if inv.quantity == Quantity::Force {
            fi
        } else {
            x.as_ref()?.0
        };
        flips.push(format!("{} = -1", names[i]));
        notes.push(format!(
            "assumed: `{}` reads compression negative ({}), so `sign` flips it; check",
            names[i], inv.evidence
        ));
    }
    (!flips.is_empty()).then(|| format!("sign = {{ {} }}", flips.join(", ")))
}

/// A number as TOML writes it (always with a decimal point, so it reads
/// back as a float).
fn toml_number(v: f64) -> String {
    toml::Value::Float(v).to_string()
}

/// A string as a TOML basic string.
fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

fn columns_line(columns: &[String]) -> String {
    let quoted: Vec<String> = columns.iter().map(|c| toml_string(c)).collect();
    format!("columns = [{}]", quoted.join(", "))
}

struct Found {
    file: String,
    layout: Layout,
    fields: Vec<(String, f64)>,
    /// For a .mat file: its `variables = { … }` line.
    variables: Option<String>,
    /// A vendor export: its notes and `columns` go with the recording.
    vendor: bool,
}

/// The `variables` line of a .mat file: each real vector whose name maps to
/// a unit name (as header names do); the others are listed in `notes`.
fn sniff_mat(path: &Path, notes: &mut Vec<String>) -> Result<String> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mat = matfile::MatFile::parse(bytes.as_slice())
        .map_err(|e| anyhow::anyhow!("not a MATLAB v5/v7 MAT-file ({e}); a v7.3 file must be saved with -v7"))?;
    let mut pairs: Vec<(String, String)> = Vec::new();
    let found: Vec<String> = mat
        .arrays()
        .iter()
        .map(|a| format!("{} ({})", a.name(), super::matlab::shape(a.size())))
        .collect();
    for a in mat.arrays() {
        let vector = a.size().iter().filter(|&&d| d != 1).count() <= 1;
        match map_name(a.name()).filter(|_| vector) {
            Some(column) if !pairs.iter().any(|(c, _)| *c == column) => pairs.push((column, a.name().to_string())),
            _ => notes.push(format!(
                "variable `{}` not recognised ({}): not read",
                a.name(),
                super::matlab::shape(a.size())
            )),
        }
    }
    let names: Vec<String> = pairs.iter().map(|(c, _)| c.clone()).collect();
    let layout = parse_header(&names, &path.display().to_string(), 1).map_err(|e| anyhow::anyhow!("{e}"))?;
    super::columns::required_columns(&layout, &path.display().to_string(), 1).map_err(|e| {
        anyhow::anyhow!(
            "{e}; the file holds {}; name the variables by hand, a matrix column as in \
             variables = {{ time_s = \"t\", force_n = \"x_F[:,3]\" }} (docs/dataset-format.md)",
            if found.is_empty() {
                "no variables".to_string()
            } else {
                found.join(", ")
            }
        )
    })?;
    let inner: Vec<String> = pairs.iter().map(|(c, v)| format!("{c} = {}", toml_string(v))).collect();
    Ok(format!("variables = {{ {} }}", inner.join(", ")))
}

/// The layout of a vendor export (`super::vendor`): its channels named from
/// their names and units, `ignore` (listed in `notes`) where that fails;
/// `columns` always set, so no `[defaults]` columns apply to it.
fn sniff_vendor(reader: &super::vendor::VendorReader, path: &Path, bytes: &[u8]) -> Result<Layout> {
    let table = (reader.read)(path, bytes).map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut notes = vec![format!(
        "{}: channels {} (names and units from the file)",
        reader.name,
        table.channels.join(", ")
    )];
    notes.extend(table.notes.iter().cloned());
    let (names, ignored) = super::vendor::column_names(&table);
    notes.extend(ignored.iter().map(|c| format!("channel `{c}` not recognised: ignored")));
    // Never a manifest that cannot load: say what was found and what is accepted.
    if let Some(why) = super::vendor::unusable(reader, &table, &names) {
        anyhow::bail!("{}: {why}", path.display());
    }
    let rows: Vec<Vec<String>> = table
        .rows
        .iter()
        .map(|(_, cells)| cells.iter().map(|c| c.to_string()).collect())
        .collect();
    let sign = detect_flip(&names, &rows, &mut notes);
    Ok(Layout {
        delimiter: Delimiter::Comma,
        columns: Some(names),
        notes,
        sign,
    })
}

/// The text of `dataset.toml` for the recordings in `dir`.
pub fn manifest_for(dir: &Path, pattern: Option<&str>, name: Option<&str>) -> Result<String> {
    let pieces = pattern.map(parse_pattern).transpose()?;
    let mut files: Vec<String> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot read folder {}", dir.display()))?
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    files.sort();
    let mut found = Vec::new();
    let mut skipped = Vec::new();
    for file in files {
        let path = dir.join(&file);
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let is_mat = ext == "mat";
        if !DATA_EXTENSIONS.contains(&ext.as_str()) && !is_mat {
            if file != "dataset.toml" {
                skipped.push(format!(
                    "{file}: not a recording (.{}, .mat)",
                    DATA_EXTENSIONS.join(", .")
                ));
            }
            continue;
        }
        let stem = path.file_stem().unwrap_or_default().to_string_lossy().into_owned();
        let fields = match &pieces {
            Some(p) => match match_pattern(p, &stem) {
                Some(f) => f,
                None => {
                    skipped.push(format!("{file}: name does not match the pattern"));
                    continue;
                }
            },
            None => Vec::new(),
        };
        let amplitude_mm = fields.iter().find(|(k, _)| k == "amplitude_mm").map(|(_, v)| *v);
        if is_mat {
            let mut notes = Vec::new();
            match sniff_mat(&path, &mut notes) {
                Ok(line) => found.push(Found {
                    file,
                    layout: Layout {
                        delimiter: Delimiter::Comma,
                        columns: None,
                        notes,
                        sign: None,
                    },
                    fields,
                    variables: Some(line),
                    vendor: false,
                }),
                Err(e) => skipped.push(format!("{file}: {e:#}")),
            }
            continue;
        }
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) => {
                skipped.push(format!("{file}: cannot read it: {e}"));
                continue;
            }
        };
        let reader = super::vendor::recognise(&bytes);
        let vendor = reader.is_some();
        let sniffed = match reader {
            Some(reader) => sniff_vendor(reader, &path, &bytes),
            None => sniff(&path, &bytes, amplitude_mm),
        };
        match sniffed {
            Ok(layout) => found.push(Found {
                file,
                layout,
                fields,
                variables: None,
                vendor,
            }),
            Err(e) => skipped.push(format!("{file}: {e:#}")),
        }
    }
    if found.is_empty() {
        let why = if skipped.is_empty() {
            "the folder is empty".to_string()
        } else {
            skipped.join("; ")
        };
        bail!("no recordings found in {}: {why}", dir.display());
    }
    // Grouped by current (the model's main variable), then by the pattern's
    // other fields in pattern order, then by name.
    let key = |f: &Found, k: &str| f.fields.iter().find(|(n, _)| n == k).map(|(_, v)| *v);
    let order: Vec<String> = pieces
        .iter()
        .flatten()
        .filter_map(|p| match p {
            Piece::Field(n) if n != "current_a" => Some(n.clone()),
            _ => None,
        })
        .collect();
    found.sort_by(|a, b| {
        let mut ord = key(a, "current_a")
            .unwrap_or(f64::NAN)
            .total_cmp(&key(b, "current_a").unwrap_or(f64::NAN));
        for k in &order {
            ord = ord.then(key(a, k).unwrap_or(f64::NAN).total_cmp(&key(b, k).unwrap_or(f64::NAN)));
        }
        ord.then(a.file.cmp(&b.file))
    });

    // The layout most files share goes to [defaults]; the others set their own.
    let mut counts: Vec<(&Layout, usize)> = Vec::new();
    for f in found.iter().filter(|f| f.variables.is_none() && !f.vendor) {
        match counts
            .iter_mut()
            .find(|(l, _)| l.delimiter == f.layout.delimiter && l.columns == f.layout.columns)
        {
            Some((_, n)) => *n += 1,
            None => counts.push((&f.layout, 1)),
        }
    }
    let common = counts
        .iter()
        .max_by_key(|(_, n)| *n)
        .map(|(l, _)| (*l).clone())
        .unwrap_or(Layout {
            delimiter: Delimiter::Comma,
            columns: None,
            notes: Vec::new(),
            sign: None,
        });
    let same = |l: &Layout| l.delimiter == common.delimiter && l.columns == common.columns;

    let title = name.map(str::to_owned).unwrap_or_else(|| {
        std::path::absolute(dir)
            .ok()
            .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| "recordings".into())
    });
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Written by `mre dataset init`{}.",
        pattern.map(|p| format!(" --pattern '{p}'")).unwrap_or_default()
    );
    let _ = writeln!(
        s,
        "# Check the units and fill in what file names cannot say (docs/dataset-format.md)."
    );
    if !found.iter().any(|f| key(f, "current_a").is_some()) {
        let _ = writeln!(
            s,
            "# current_a: not in the file names; set it for every recording (or pass --pattern)."
        );
    }
    for line in &skipped {
        let _ = writeln!(s, "# skipped {line}");
    }
    let _ = writeln!(s, "name = {}\n\n[defaults]", toml_string(&title));
    let write_layout = |s: &mut String, l: &Layout| {
        match l.delimiter {
            Delimiter::Whitespace => {
                let _ = writeln!(s, "delimiter = \"whitespace\"");
            }
            Delimiter::Semicolon => {
                let _ = writeln!(s, "delimiter = \";\"");
            }
            Delimiter::Comma => {}
        }
        if let Some(c) = &l.columns {
            let _ = writeln!(s, "{}", columns_line(c));
        }
    };
    // A sign is per recording: its assumption goes with the recording.
    for note in common.notes.iter().filter(|n| !n.starts_with("assumed:")) {
        let _ = writeln!(s, "# {note}");
    }
    write_layout(&mut s, &common);
    for f in &found {
        let _ = writeln!(s, "\n[[recording]]");
        // A .mat file says its own variables; delimiter and columns do not apply.
        // A vendor file names all its channels itself (never the defaults' `columns`).
        let own = f.variables.is_none() && !f.vendor && !same(&f.layout);
        if own || f.variables.is_some() || f.vendor {
            for note in &f.layout.notes {
                let _ = writeln!(s, "# {note}");
            }
        }
        if !own && f.variables.is_none() && !f.vendor && f.layout.sign.is_some() {
            for note in f.layout.notes.iter().filter(|n| n.starts_with("assumed:")) {
                let _ = writeln!(s, "# {note}");
            }
        }
        let _ = writeln!(s, "file = {}", toml_string(&f.file));
        if let Some(sign) = &f.layout.sign {
            let _ = writeln!(s, "{sign}");
        }
        let mut tags = Vec::new();
        for (k, v) in &f.fields {
            if k == "sequence" {
                let _ = writeln!(s, "sequence = {}", *v as i64);
            } else if KEYS.contains(&k.as_str()) {
                let _ = writeln!(s, "{k} = {}", toml_number(*v));
            } else {
                tags.push(format!("{k} = {}", toml_number(*v)));
            }
        }
        if !tags.is_empty() {
            let _ = writeln!(s, "tags = {{ {} }}", tags.join(", "));
        }
        if let Some(line) = &f.variables {
            let _ = writeln!(s, "{line}");
        }
        if let (true, Some(c)) = (f.vendor, &f.layout.columns) {
            let _ = writeln!(s, "{}", columns_line(c));
        }
        if own {
            if f.layout.delimiter != common.delimiter {
                let d = match f.layout.delimiter {
                    Delimiter::Whitespace => "whitespace",
                    Delimiter::Semicolon => ";",
                    Delimiter::Comma => ",",
                };
                let _ = writeln!(s, "delimiter = \"{d}\"");
            }
            if f.layout.columns != common.columns {
                match &f.layout.columns {
                    Some(c) => {
                        let _ = writeln!(s, "{}", columns_line(c));
                    }
                    None => {
                        let _ = writeln!(s, "# this file's header names its columns");
                    }
                }
            }
        }
    }
    Ok(s)
}

/// Writes `DIR/dataset.toml`; refuses when one exists.
pub fn run_init(dir: &Path, pattern: Option<&str>, name: Option<&str>) -> Result<std::path::PathBuf> {
    let dest = dir.join("dataset.toml");
    if dest.exists() {
        bail!(
            "{} exists; mre dataset init never overwrites it (move it away to start again)",
            dest.display()
        );
    }
    let text = manifest_for(dir, pattern, name)?;
    crate::atomic_write::write_atomic(&dest, text.as_bytes())?;
    Ok(dest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_reads_numbers_with_x_for_the_point() {
        let p = parse_pattern("{amplitude_mm}mm{frequency_hz}Hz{current_a}A").unwrap();
        assert_eq!(
            match_pattern(&p, "25mm0x25Hz0x5A").unwrap(),
            vec![
                ("amplitude_mm".to_string(), 25.0),
                ("frequency_hz".to_string(), 0.25),
                ("current_a".to_string(), 0.5)
            ]
        );
        assert_eq!(match_pattern(&p, "25mm0x25Hz").map(|_| ()), None);
        assert_eq!(match_pattern(&p, "25mmabcHz1A").map(|_| ()), None);
        assert!(parse_pattern("{a}{b}").is_err());
        assert!(parse_pattern("plain").is_err());
        assert_eq!(parse_number("m1x5"), Some(-1.5));
    }

    #[test]
    fn header_names_map_to_unit_names() {
        assert_eq!(map_name("Time (ms)").as_deref(), Some("time_ms"));
        assert_eq!(map_name("Load [kN]").as_deref(), Some("force_kn"));
        assert_eq!(map_name("velocity_mm_s").as_deref(), Some("velocity_mm_s"));
        assert_eq!(map_name("Velocity (mm/s)").as_deref(), Some("velocity_mm_s"));
        assert_eq!(map_name("Disp (m)").as_deref(), Some("displacement_m"));
        assert_eq!(map_name("Strain gauge 3"), None);
    }

    /// x = A sin(2π f t) in m, v its derivative in mm/s, force in N: the
    /// columns shuffled, no header.
    #[test]
    fn headerless_columns_are_told_from_the_physics() {
        let dir = tempfile::tempdir().unwrap();
        let mut text = String::new();
        for k in 0..200 {
            let t = k as f64 * 0.01;
            let w = 2.0 * std::f64::consts::PI * 0.5;
            let x_m = 0.01 * (w * t).sin();
            let v_mm_s = 10.0 * w * (w * t).cos();
            let f_n = 300.0 * (w * t).sin() + 50.0 * (w * t).cos();
            text.push_str(&format!("{f_n:.6}\t{t:.3}\t{v_mm_s:.6}\t{x_m:.8}\n"));
        }
        std::fs::write(dir.path().join("10mm0x5Hz2A.txt"), &text).unwrap();
        let toml = manifest_for(dir.path(), Some("{amplitude_mm}mm{frequency_hz}Hz{current_a}A"), None).unwrap();
        let v: toml::Value = toml::from_str(&toml).unwrap();
        assert_eq!(
            v["defaults"]["columns"],
            toml::Value::try_from(["force_n", "time_s", "velocity_mm_s", "displacement_m"]).unwrap(),
            "{toml}"
        );
        assert_eq!(v["recording"][0]["current_a"].as_float(), Some(2.0));
        // The manifest loads as a data set.
        std::fs::write(dir.path().join("dataset.toml"), &toml).unwrap();
        let ds = crate::dataset::Dataset::load(dir.path()).unwrap();
        assert!((ds.recordings[0].samples.x_mm.iter().cloned().fold(0.0, f64::max) - 10.0).abs() < 0.01);
    }

    #[test]
    fn unknown_header_columns_are_ignored_and_listed() {
        let dir = tempfile::tempdir().unwrap();
        let mut text = String::from("Time (s),Displacement (mm),Force (kN),Strain\n");
        for k in 0..20 {
            text.push_str(&format!("{},{},{},1\n", k as f64 * 0.1, k, 2 * k));
        }
        std::fs::write(dir.path().join("a.csv"), &text).unwrap();
        let toml = manifest_for(dir.path(), None, Some("t")).unwrap();
        assert!(toml.contains("# column `Strain` not recognised: ignored"), "{toml}");
        assert!(
            toml.contains("columns = [\"time_s\", \"displacement_mm\", \"force_kn\", \"ignore\"]"),
            "{toml}"
        );
        assert!(toml.contains("# current_a: not in the file names"), "{toml}");
        // With a current added, it loads: the renamed header row is skipped, kN converted.
        let toml = toml.replace("file = \"a.csv\"", "file = \"a.csv\"\ncurrent_a = 0.0");
        std::fs::write(dir.path().join("dataset.toml"), &toml).unwrap();
        let ds = crate::dataset::Dataset::load(dir.path()).unwrap();
        assert_eq!(ds.recordings[0].samples.len(), 20);
        assert_eq!(ds.recordings[0].samples.force_n[3], 6000.0);
    }

    #[test]
    fn mat_files_get_their_variables_mapped() {
        use crate::dataset::matlab::mat_v5::mat_v5;
        let dir = tempfile::tempdir().unwrap();
        let t: Vec<f64> = (0..30).map(|k| k as f64 * 1e-3).collect();
        // Compressed while the force rises (the load's work check).
        let x: Vec<f64> = (0..30).map(|k| (k as f64 * 0.05).sin()).collect();
        let f: Vec<f64> = (0..30).map(|k| k as f64).collect();
        let bytes = mat_v5(&[
            ("t", 30, 1, &t),
            ("x", 30, 1, &x),
            ("F", 30, 1, &f),
            ("gain", 1, 1, &[2.0]),
        ]);
        std::fs::write(dir.path().join("drop0x5A.mat"), bytes).unwrap();
        let toml = manifest_for(dir.path(), Some("drop{current_a}A"), None).unwrap();
        assert!(
            toml.contains(r#"variables = { time_s = "t", displacement_mm = "x", force_n = "F" }"#),
            "{toml}"
        );
        assert!(toml.contains("# variable `gain` not recognised"), "{toml}");
        std::fs::write(dir.path().join("dataset.toml"), &toml).unwrap();
        let ds = crate::dataset::Dataset::load(dir.path()).unwrap();
        assert_eq!(ds.recordings[0].current_a, 0.5);
        assert_eq!(ds.recordings[0].samples.force_n, f);
    }

    #[test]
    fn an_existing_manifest_is_never_replaced() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("dataset.toml"), "name = \"mine\"\n").unwrap();
        let e = run_init(dir.path(), None, None).unwrap_err();
        assert!(e.to_string().contains("never overwrites"), "{e}");
        assert_eq!(
            std::fs::read_to_string(dir.path().join("dataset.toml")).unwrap(),
            "name = \"mine\"\n"
        );
    }

    /// Hand-written evidence: a Windows-1252 file (`Prüfkraft`, byte 0xFC),
    /// the case where decoding runs the encoding guess. `init` reads its
    /// delimiter and its rows from one decoding: text::decode runs once for
    /// the file (it ran twice before, once per reading).
    #[test]
    fn init_decodes_each_file_once() {
        let dir = tempfile::tempdir().unwrap();
        let mut bytes = b"Zeit (s);Weg (mm);Pr\xfcfkraft (N)\n".to_vec();
        for k in 0..8 {
            bytes.extend(format!("0,{k};{k},5;{}\n", 10 * k).into_bytes());
        }
        std::fs::write(dir.path().join("latin1.csv"), &bytes).unwrap();
        crate::dataset::text::DECODES.with(|n| n.set(0));
        let toml = manifest_for(dir.path(), None, None).unwrap();
        assert_eq!(crate::dataset::text::DECODES.with(|n| n.get()), 1, "{toml}");
        assert!(
            toml.contains(r#"columns = ["time_s", "displacement_mm", "force_n"]"#),
            "{toml}"
        );
    }
}
