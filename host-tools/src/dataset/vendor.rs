//! Vendor exports that are not a plain table (docs/dataset-format.md,
//! vendor layouts): each format is one file with a [`VendorReader`], listed
//! once in [`READERS`]. A reader recognises its files by their content and
//! turns one into a [`Table`]: channel names with their units, and rows of
//! values. The dispatch then names the columns (`columns` in dataset.toml,
//! else from the channel names and units) and checks and converts the rows
//! as it does a CSV file's.
use super::columns::{map_name, parse_header, required_columns};
use super::error::DatasetError;
use super::read::{samples_from_rows, Cell};
use super::Samples;
use std::path::Path;

/// One vendor format.
pub struct VendorReader {
    /// As the vendor names it, for messages and `mre dataset init`.
    pub name: &'static str,
    /// True when the bytes are this format's (a signature, never the extension).
    pub recognises: fn(&[u8]) -> bool,
    /// Reads the file; `path` names it in errors (and is opened by formats
    /// whose crate reads from a path).
    pub read: fn(&Path, &[u8]) -> Result<Table, DatasetError>,
}

/// A vendor file's channels and rows, before any unit conversion.
pub struct Table {
    /// Each channel as `Name (unit)`, e.g. `Axial Force (kN)`.
    pub channels: Vec<String>,
    /// Line (or sample number, for a binary file) of the names, for errors.
    pub names_line: usize,
    /// (line or sample number, one cell per channel).
    pub rows: Vec<(usize, Vec<Cell>)>,
    /// What the reader chose or assumed (skipped blocks, extra writes), for
    /// `mre dataset init` to show.
    pub notes: Vec<String>,
}

/// Every vendor format mre reads: registering a new one is one line here.
pub const READERS: &[VendorReader] = &[super::mts::READER, super::lvm::READER, super::tdms::READER];

/// The reader for these bytes, if a vendor format's.
pub fn recognise(bytes: &[u8]) -> Option<&'static VendorReader> {
    READERS.iter().find(|r| (r.recognises)(bytes))
}

/// The unit-carrying names of a table's channels, `ignore` for a channel
/// whose name and unit mre cannot tell (a command signal, a spare input, a
/// date), and those channels.
pub fn column_names(table: &Table) -> (Vec<String>, Vec<String>) {
    let mut ignored = Vec::new();
    let names = table
        .channels
        .iter()
        .map(|c| {
            map_name(c).unwrap_or_else(|| {
                ignored.push(c.clone());
                "ignore".to_string()
            })
        })
        .collect();
    (names, ignored)
}

/// Why `names` (from [`column_names`]) cannot load, if they cannot: a
/// quantity twice, or no time or no force channel. The message lists the
/// file's channels and the names mre accepts, so `columns` can be written.
pub fn unusable(reader: &VendorReader, table: &Table, names: &[String]) -> Option<String> {
    let why = match parse_header(names, "", 1) {
        Err(DatasetError::DuplicateColumn { name, column, .. }) => {
            format!("channel {column} also reads as `{name}`")
        }
        Err(e) => e.to_string(),
        Ok(layout) => match required_columns(&layout, "", 1) {
            Err(DatasetError::MissingColumn { quantity, accepted, .. }) => {
                format!("no {quantity} channel mre can tell (names it accepts: {accepted})")
            }
            Err(e) => e.to_string(),
            Ok(()) => return None,
        },
    };
    Some(format!(
        "{} channels {}: {why}; name the channels in dataset.toml, in file order, e.g. \
         columns = [\"time_s\", \"force_kn\", \"ignore\"] (docs/dataset-format.md)",
        reader.name,
        table.channels.join(", ")
    ))
}

/// What dataset.toml says about a vendor file: `columns` names the channels
/// in file order, `block` picks an MTS data block; both located at
/// `mpath`:`line`, for errors.
pub struct Settings<'a> {
    pub columns: Option<&'a [String]>,
    pub block: Option<usize>,
    pub mpath: &'a str,
    pub line: usize,
}

/// Samples of a vendor file. Without `columns` the names come from the
/// file's channel names and units.
pub fn read_samples(
    reader: &VendorReader,
    path: &Path,
    bytes: &[u8],
    settings: Settings<'_>,
    notes: &mut Vec<String>,
) -> Result<(Samples, bool), DatasetError> {
    let Settings {
        columns,
        block,
        mpath,
        line: columns_line,
    } = settings;
    let dpath = path.display().to_string();
    // `block` picks one of an MTS file's data blocks (the others hold one).
    let table = match block {
        None => (reader.read)(path, bytes)?,
        Some(k) if reader.name == super::mts::READER.name => super::mts::read_block(path, bytes, Some(k))?,
        Some(_) => {
            return Err(DatasetError::Manifest {
                path: mpath.to_string(),
                line: columns_line,
                message: format!(
                    "`block` picks a data block of an MTS 793 Specimen.dat; `{dpath}` is a {} file",
                    reader.name
                ),
            })
        }
    };
    let (names, name_path, name_line) = match columns {
        Some(c) => (c.to_vec(), mpath, columns_line),
        None => {
            let (names, _) = column_names(&table);
            if let Some(message) = unusable(reader, &table, &names) {
                return Err(DatasetError::BadRecord {
                    path: dpath.clone(),
                    line: table.names_line,
                    message,
                });
            }
            (names, dpath.as_str(), table.names_line)
        }
    };
    if names.len() != table.channels.len() {
        return Err(DatasetError::Manifest {
            path: mpath.to_string(),
            line: columns_line,
            message: format!(
                "`columns` names {} columns but the {} file `{dpath}` has {} channels: {}",
                names.len(),
                reader.name,
                table.channels.len(),
                table.channels.join(", ")
            ),
        });
    }
    notes.extend(table.notes);
    samples_from_rows(&dpath, &names, name_path, name_line, table.rows.into_iter(), notes)
}

/// A number written with `decimal` as its decimal separator, as a cell
/// (text, so a bad value is reported as written).
pub fn cell(text: &str, decimal: char) -> Cell {
    let t = text.trim();
    if decimal == '.' {
        Cell::Text(t.to_string())
    } else {
        match t.replace(decimal, ".").parse::<f64>() {
            Ok(v) => Cell::Number(v),
            Err(_) => Cell::Text(t.to_string()),
        }
    }
}

/// The text of a vendor text export, in whatever encoding it was written
/// (`super::text`: UTF-8, UTF-16 with a mark, Windows-1252, GBK, …). Binary
/// bytes are refused at their line (`what` says what the file should be,
/// e.g. "an .lvm file is text"), and so is a file whose last line has no
/// line end (a copy cut short).
pub fn text<'a>(path: &Path, bytes: &'a [u8], what: &str) -> Result<std::borrow::Cow<'a, str>, DatasetError> {
    let bad = |line: usize, message: String| DatasetError::BadRecord {
        path: path.display().to_string(),
        line,
        message,
    };
    let text = super::text::decode(bytes)
        .map_err(|line| bad(line, format!("binary bytes (NUL) where text was expected ({what})")))?
        .text;
    if !text.ends_with('\n') {
        return Err(bad(
            text.lines().count().max(1),
            "the last line has no line end: the file is cut short".to_string(),
        ));
    }
    Ok(text)
}
