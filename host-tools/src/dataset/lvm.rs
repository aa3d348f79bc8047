//! LabVIEW Measurement files, `.lvm` (NI, "Specification for the LabVIEW
//! Measurement File (.lvm)", NI tutorial 4139: sections "Header", "Segment
//! Header" and "Special Blocks").
//!
//! The file starts with `LabVIEW Measurement`; a file header of tag rows
//! (`Separator` Tab or Comma, `Decimal_Separator`, `X_Columns` No, One or
//! Multi) ends at `***End_of_Header***`. Each segment then has its own tag
//! rows, one value per channel (`Channels`, `Samples`, `Y_Unit_Label`,
//! `X_Dimension`, `X0`, `Delta_X`), closed by `***End_of_Header***`, a row of
//! column names (`X_Value`, the channels, `Comment`) and the data.
//!
//! Time: the X column when written (`X_Columns` One or Multi, the first X);
//! else X0 + k·Delta_X for sample k of the segment. X must be time
//! (`X_Dimension` Time), in seconds. A file with several segments must list
//! the same channels and units in each; their rows continue the record.
//! A segment holding fewer rows than its `Samples`, or a last line without a
//! line end, is a file cut short and refused; one holding more was written
//! in several writes under one header ("one header only") and is read whole.
//! With `X_Columns Multi` the header rows hold one value per channel over
//! its Y column, blank cells over the X columns. Text in any encoding
//! (`super::text`: a `°C` unit in Windows-1252).
use super::error::DatasetError;
use super::read::Cell;
use super::vendor::{cell, Table, VendorReader};
use std::path::Path;

pub const READER: VendorReader = VendorReader {
    name: "LabVIEW .lvm",
    recognises,
    read,
};

const MAGIC: &[u8] = b"LabVIEW Measurement";
const END_OF_HEADER: &str = "***End_of_Header***";

fn recognises(bytes: &[u8]) -> bool {
    bytes
        .strip_prefix(b"\xEF\xBB\xBF".as_slice())
        .unwrap_or(bytes)
        .starts_with(MAGIC)
}

#[derive(Clone, Copy, PartialEq)]
enum XColumns {
    No,
    One,
    Multi,
}

/// A segment header's tag rows.
#[derive(Default)]
struct SegmentHeader {
    channels: Option<usize>,
    units: Vec<String>,
    x_dimension: Vec<String>,
    x0: Vec<String>,
    delta_x: Vec<String>,
    samples: Option<usize>,
}

fn read(path: &Path, bytes: &[u8]) -> Result<Table, DatasetError> {
    let dpath = path.display().to_string();
    let text = super::vendor::text(path, bytes, "an .lvm file is text")?;
    let bad = |line: usize, message: String| DatasetError::BadRecord {
        path: dpath.clone(),
        line,
        message,
    };
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l)).peekable();

    // File header: the separator is not known yet, but tags are one word.
    let mut separator = '\t';
    let mut decimal = '.';
    let mut x_columns = XColumns::One;
    let mut closed = false;
    for (n, line) in lines.by_ref() {
        let (tag, value) = match line.split_once('\t') {
            Some((tag, value)) => (tag, value.trim_end_matches('\t')),
            None => line
                .split_once(',')
                .map_or((line, ""), |(t, v)| (t, v.trim_end_matches(','))),
        };
        let (tag, value) = (tag.trim(), value.trim());
        match tag {
            END_OF_HEADER => {
                closed = true;
                break;
            }
            "Separator" => {
                separator = match value {
                    "Tab" => '\t',
                    "Comma" => ',',
                    other => return Err(bad(n, format!("Separator `{other}` is not Tab or Comma"))),
                }
            }
            "Decimal_Separator" => {
                let mut c = value.chars();
                decimal = match (c.next(), c.next()) {
                    (Some(d), None) => d,
                    _ => return Err(bad(n, format!("Decimal_Separator `{value}` is not one character"))),
                }
            }
            "X_Columns" => {
                x_columns = match value {
                    "No" => XColumns::No,
                    "One" => XColumns::One,
                    "Multi" => XColumns::Multi,
                    other => return Err(bad(n, format!("X_Columns `{other}` is not No, One or Multi"))),
                }
            }
            _ => {}
        }
    }
    if !closed {
        return Err(bad(
            text.lines().count().max(1),
            format!("the file header has no {END_OF_HEADER}: the file is cut short"),
        ));
    }
    if decimal == separator {
        return Err(bad(1, "the decimal separator is the column separator".to_string()));
    }
    let split = |line: &str| -> Vec<String> { line.split(separator).map(|f| f.trim().to_string()).collect() };

    let mut channels: Option<(Vec<String>, usize)> = None;
    let mut rows: Vec<(usize, Vec<Cell>)> = Vec::new();
    let mut notes = Vec::new();
    let mut segment = 0;
    while let Some(&(n, line)) = lines.peek() {
        if line.trim_matches([separator, ' ']).is_empty() {
            lines.next();
            continue;
        }
        segment += 1;
        // Segment header, to its End_of_Header.
        let mut h = SegmentHeader::default();
        let mut closed = false;
        for (n, line) in lines.by_ref() {
            let mut fields = split(line);
            while fields.last().is_some_and(|f| f.is_empty()) {
                fields.pop();
            }
            let Some(tag) = fields.first().cloned() else { continue };
            let mut values: Vec<String> = fields.into_iter().skip(1).collect();
            // LabVIEW writes X_Columns Multi headers with each channel's value
            // over its Y column and a blank cell over each X column.
            let blank_between = values.len() > 1 && values.iter().skip(1).step_by(2).all(String::is_empty);
            if x_columns == XColumns::Multi && blank_between {
                values = values.into_iter().step_by(2).collect();
            }
            match tag.as_str() {
                END_OF_HEADER => {
                    closed = true;
                    break;
                }
                "Channels" => {
                    let c = values.first().and_then(|v| v.parse::<usize>().ok()).filter(|&c| c > 0);
                    h.channels = Some(c.ok_or_else(|| bad(n, "Channels is not a positive count".to_string()))?);
                }
                "Samples" => h.samples = values.first().and_then(|v| v.parse().ok()),
                "Y_Unit_Label" => h.units = values,
                "X_Dimension" => h.x_dimension = values,
                "X0" => h.x0 = values,
                "Delta_X" => h.delta_x = values,
                _ => {}
            }
        }
        if !closed {
            return Err(bad(
                n,
                format!("segment {segment}'s header has no {END_OF_HEADER}: the file is cut short"),
            ));
        }
        let Some(count) = h.channels else {
            return Err(bad(n, format!("segment {segment}'s header has no Channels row")));
        };
        for (tag, values) in [("Y_Unit_Label", &h.units), ("X_Dimension", &h.x_dimension)] {
            if values.len() < count {
                return Err(bad(
                    n,
                    format!(
                        "segment {segment}: {tag} has {} values for {count} channels",
                        values.len()
                    ),
                ));
            }
        }
        if let Some(d) = h.x_dimension.iter().take(count).find(|d| *d != "Time") {
            return Err(bad(
                n,
                format!("segment {segment}: X_Dimension `{d}`; mre reads records against time"),
            ));
        }
        // The column-name row: X_Value, the channels (each after its X with Multi), Comment.
        let Some((names_line, names_row)) = lines.next() else {
            return Err(bad(
                n,
                format!("segment {segment} has no column-name row: the file is cut short"),
            ));
        };
        let names_row = split(names_row);
        let y_columns: Vec<usize> = match x_columns {
            XColumns::No | XColumns::One => (1..=count).collect(),
            XColumns::Multi => (0..count).map(|c| 2 * c + 1).collect(),
        };
        let names: Vec<String> = y_columns
            .iter()
            .map(|&c| names_row.get(c).cloned().unwrap_or_default())
            .collect();
        if names_row.first().map(String::as_str) != Some("X_Value") || names.iter().any(String::is_empty) {
            return Err(bad(
                names_line,
                format!("segment {segment}: expected the column names (X_Value, then {count} channels)"),
            ));
        }
        let block: Vec<String> = std::iter::once("Time (s)".to_string())
            .chain(names.iter().zip(&h.units).map(|(c, u)| format!("{c} ({u})")))
            .collect();
        match &channels {
            None => channels = Some((block.clone(), names_line)),
            Some((first, _)) if *first != block => {
                return Err(bad(
                    names_line,
                    format!(
                        "segment {segment}'s channels ({}) differ from segment 1's ({}); \
                         mre reads one set of channels per file",
                        block[1..].join(", "),
                        first[1..].join(", ")
                    ),
                ))
            }
            Some(_) => {}
        }
        // Time base without X columns: one X0 and Delta_X for all channels.
        let time_base = if x_columns == XColumns::No {
            let number = |v: Option<&String>| v.and_then(|v| v.replace(decimal, ".").parse::<f64>().ok());
            let x0 = number(h.x0.first());
            let dx = number(h.delta_x.first());
            let same = |values: &[String]| values.iter().take(count).all(|v| Some(v) == values.first());
            match (x0, dx) {
                (Some(x0), Some(dx)) if dx > 0.0 && same(&h.x0) && same(&h.delta_x) => Some((x0, dx)),
                _ => {
                    return Err(bad(
                        names_line,
                        format!(
                            "segment {segment}: without X columns the time comes from X0 and Delta_X, \
                             which must be numbers (Delta_X > 0) shared by all channels"
                        ),
                    ))
                }
            }
        } else {
            None
        };
        // Data, to the next blank line or segment header.
        let mut k = 0usize;
        while let Some(&(n, line)) = lines.peek() {
            let fields = split(line);
            let first = fields.first().map(String::as_str).unwrap_or("");
            if line.trim_matches([separator, ' ']).is_empty() || first == "Channels" || first == END_OF_HEADER {
                break;
            }
            lines.next();
            let mut row = Vec::with_capacity(count + 1);
            row.push(match time_base {
                Some((x0, dx)) => Cell::Number(x0 + k as f64 * dx),
                None => cell(first, decimal),
            });
            for &c in &y_columns {
                match fields.get(c) {
                    Some(f) => row.push(cell(f, decimal)),
                    // A short row: counted by the field check as what it is.
                    None => break,
                }
            }
            rows.push((n, row));
            k += 1;
        }
        match h.samples {
            Some(samples) if k < samples => {
                return Err(bad(
                    rows.last().map_or(names_line, |r| r.0),
                    format!("segment {segment} declares {samples} samples but holds {k}: the file is cut short"),
                ))
            }
            // "One header only": later writes add rows under the first
            // write's header, whose Samples counts that write alone.
            Some(samples) if k > samples => notes.push(format!(
                "segment {segment} holds {k} rows under a header of {samples} samples: \
                 {} writes under one header, read as one record",
                k.div_ceil(samples.max(1))
            )),
            _ => {}
        }
    }
    let Some((channels, names_line)) = channels else {
        return Err(bad(text.lines().count().max(1), "no segment with data".to_string()));
    };
    Ok(Table {
        channels,
        names_line,
        rows,
        notes,
    })
}
