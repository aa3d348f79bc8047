//! MTS 793 MultiPurpose TestWare `Specimen.dat` (MTS Series 793 Application
//! User Manual, Model 793.10 MPT, "About Specimen.dat Files"; the data file
//! header also in "Data Acquisition Process Descriptions" > "Data File
//! Header").
//!
//! The first line declares the layout:
//! `MTS793|progName|sLanguage|version|iDelim|sDecimal|sDate|sTime|iCountry|iDate|iTime|sCode`,
//! iDelim 0 = space (Plain), 1 = comma with quoted text (Lotus), 2 = tab
//! (Excel); sDecimal is the decimal separator. Free header lines follow,
//! then a row of channel names, a row of their units, and the data. MPT may
//! repeat the whole header before each data buffer; a repeat must name the
//! same channels and units, and its rows continue the record.
//!
//! Plain files are refused: their names (`Axial Force`) hold the separator.
//! A file whose last line has no line end was cut short and is refused; one
//! cut at a line end cannot be told from a shorter test.
use super::error::DatasetError;
use super::read::Cell;
use super::vendor::{cell, Table, VendorReader};
use std::path::Path;

pub const READER: VendorReader = VendorReader {
    name: "MTS 793 Specimen.dat",
    recognises,
    read,
};

const SIGNATURE: &str = "MTS793|";

fn unquote(s: &str) -> &str {
    let s = s.trim();
    s.strip_prefix('"').and_then(|r| r.strip_suffix('"')).unwrap_or(s)
}

fn is_header_line(line: &str) -> bool {
    unquote(line).starts_with(SIGNATURE)
}

fn recognises(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF".as_slice()).unwrap_or(bytes);
    let head = &bytes[..bytes.len().min(64)];
    let head = String::from_utf8_lossy(head);
    is_header_line(head.lines().next().unwrap_or(""))
}

/// Delimiter and decimal separator declared by a header line.
fn layout(line: &str, bad: &dyn Fn(String) -> DatasetError) -> Result<(char, char), DatasetError> {
    let fields: Vec<&str> = unquote(line).split('|').collect();
    if fields.len() < 6 {
        return Err(bad(format!(
            "the MTS793 header line has {} fields; the manual's layout has 12 \
             (MTS793|progName|sLanguage|version|iDelim|sDecimal|…)",
            fields.len()
        )));
    }
    let delimiter = match fields[4] {
        "1" => ',',
        "2" => '\t',
        "0" => {
            return Err(bad(
                "a Plain (space-delimited) MPT file, whose channel names hold spaces; export it as Excel \
                 (tab) or Lotus (comma) on the Specimen tab of the MPT Options Editor"
                    .to_string(),
            ))
        }
        other => {
            return Err(bad(format!(
                "iDelim `{other}` in the MTS793 header line is not 0, 1 or 2"
            )))
        }
    };
    let mut decimal = fields[5].chars();
    let decimal = match (decimal.next(), decimal.next()) {
        (Some(d), None) if d != delimiter && !d.is_ascii_digit() => d,
        _ => {
            return Err(bad(format!(
                "decimal separator `{}` in the MTS793 header line cannot be read with delimiter `{}`",
                fields[5],
                delimiter.escape_default()
            )))
        }
    };
    Ok((delimiter, decimal))
}

fn split(line: &str, delimiter: char) -> Vec<String> {
    let mut fields: Vec<String> = line.split(delimiter).map(|f| unquote(f).to_string()).collect();
    // Excel-mode rows end with a tab.
    while fields.last().is_some_and(|f| f.is_empty()) {
        fields.pop();
    }
    fields
}

fn read(path: &Path, bytes: &[u8]) -> Result<Table, DatasetError> {
    let dpath = path.display().to_string();
    let text = super::vendor::text(path, bytes, "an MTS Specimen.dat is ANSI text")?;
    let bad = |line: usize, message: String| DatasetError::BadRecord {
        path: dpath.clone(),
        line,
        message,
    };
    let mut channels: Option<(Vec<String>, usize)> = None;
    let mut rows = Vec::new();
    let mut format: Option<(char, char)> = None;
    // Rows of the current header block, before its first data row.
    let mut pending: Vec<(usize, Vec<String>)> = Vec::new();
    let mut in_data = false;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        if is_header_line(line) {
            format = Some(layout(line, &|m| bad(n, m))?);
            pending.clear();
            in_data = false;
            continue;
        }
        let Some((delimiter, decimal)) = format else {
            return Err(bad(n, "no MTS793 header line above the data".to_string()));
        };
        if line.trim().is_empty() {
            continue;
        }
        let fields = split(line, delimiter);
        let numeric = |f: &String| matches!(cell(f, decimal), Cell::Number(_)) || f.parse::<f64>().is_ok();
        if in_data {
            rows.push((n, fields.iter().map(|f| cell(f, decimal)).collect()));
            continue;
        }
        if fields.is_empty() || !fields.iter().all(numeric) {
            pending.push((n, fields));
            continue;
        }
        // The first data row of a block: names and units are the two rows above.
        let [.., (names_line, names), (_, units)] = pending.as_slice() else {
            return Err(bad(
                n,
                "data without a row of channel names and a row of units above it".to_string(),
            ));
        };
        if names.len() != fields.len() || units.len() != fields.len() {
            return Err(bad(
                *names_line,
                format!(
                    "{} channel names and {} units over {} data fields",
                    names.len(),
                    units.len(),
                    fields.len()
                ),
            ));
        }
        let block: Vec<String> = names.iter().zip(units).map(|(c, u)| format!("{c} ({u})")).collect();
        match &channels {
            None => channels = Some((block, *names_line)),
            Some((first, _)) if *first != block => {
                return Err(bad(
                    *names_line,
                    format!(
                        "this data buffer's channels ({}) differ from the first buffer's ({}); \
                         mre reads one set of channels per file",
                        block.join(", "),
                        first.join(", ")
                    ),
                ))
            }
            Some(_) => {}
        }
        in_data = true;
        rows.push((n, fields.iter().map(|f| cell(f, decimal)).collect()));
    }
    let Some((channels, names_line)) = channels else {
        return Err(bad(
            text.lines().count().max(1),
            "no data rows (a row of channel names, a row of units, then numbers)".to_string(),
        ));
    };
    Ok(Table {
        channels,
        names_line,
        rows,
    })
}
