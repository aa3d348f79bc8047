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
//! repeat the whole header before each data buffer, and exports in the
//! operator's language put a block header (`Data Acquisition`,
//! `Datenerfassung`, …) above each buffer; buffers naming the same channels
//! continue one record. A file may hold several records (a time series and
//! a short peak table): the longest is read, the others are named in notes.
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

/// One data buffer: its channels (`Name (unit)`), the line of its names,
/// and its rows.
struct Block {
    channels: Vec<String>,
    names_line: usize,
    rows: Vec<(usize, Vec<Cell>)>,
}

fn read(path: &Path, bytes: &[u8]) -> Result<Table, DatasetError> {
    read_block(path, bytes, None)
}

/// Reads record `block` (1-based, in file order; buffers naming the same
/// channels are one record), or the longest when `None` (`block` in
/// dataset.toml, docs/dataset-format.md).
pub fn read_block(path: &Path, bytes: &[u8], block: Option<usize>) -> Result<Table, DatasetError> {
    let dpath = path.display().to_string();
    let text = super::vendor::text(path, bytes, "an MTS Specimen.dat is text")?;
    let bad = |line: usize, message: String| DatasetError::BadRecord {
        path: dpath.clone(),
        line,
        message,
    };
    let blocks = blocks(&text, &bad)?;
    choose(blocks, block).map_err(|m| bad(1, m))?.ok_or_else(|| {
        bad(
            text.lines().count().max(1),
            "no data rows (a row of channel names, a row of units, then numbers)".to_string(),
        )
    })
}

/// Every data buffer in file order. A buffer is a row of names, a row of
/// units and the numeric rows under them; any other text line (the MTS793
/// line, a per-block header such as `Data Acquisition` or `Datenerfassung`
/// in the export's language, operator information) ends it.
fn blocks(text: &str, bad: &dyn Fn(usize, String) -> DatasetError) -> Result<Vec<Block>, DatasetError> {
    let mut out: Vec<Block> = Vec::new();
    let mut format: Option<(char, char)> = None;
    // Text rows since the last data row: the names and units are its last two.
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
        if line.trim_matches([delimiter, ' ', '\t']).is_empty() {
            continue;
        }
        let fields = split(line, delimiter);
        let numeric = |f: &String| matches!(cell(f, decimal), Cell::Number(_)) || f.parse::<f64>().is_ok();
        let row = |fields: &[String]| (n, fields.iter().map(|f| cell(f, decimal)).collect::<Vec<Cell>>());
        // Inside a buffer, a row as wide as its names with a number in it is
        // data (a bad cell is reported as written, later); a text line ends it.
        if let Some(block) = out.last_mut().filter(|_| in_data) {
            if fields.len() == block.channels.len() && fields.iter().any(numeric) {
                block.rows.push(row(&fields));
                continue;
            }
        }
        if fields.is_empty() || !fields.iter().all(numeric) {
            pending.push((n, fields));
            in_data = false;
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
        out.push(Block {
            channels: names.iter().zip(units).map(|(c, u)| format!("{c} ({u})")).collect(),
            names_line: *names_line,
            rows: vec![row(&fields)],
        });
        pending.clear();
        in_data = true;
    }
    Ok(out)
}

/// The time series: buffers with the same channels continue one record
/// (MPT repeats the header before each buffer), and the record with the
/// most rows is taken. The others (a peak or cycle table, a second
/// process's data) are skipped and named in the table's notes.
/// `pick` (1-based) takes another record; `Err` when there is no such record.
fn choose(blocks: Vec<Block>, pick: Option<usize>) -> Result<Option<Table>, String> {
    let mut records: Vec<Block> = Vec::new();
    for b in blocks {
        match records.iter_mut().find(|r| r.channels == b.channels) {
            Some(r) => r.rows.extend(b.rows),
            None => records.push(b),
        }
    }
    let describe = |i: usize, r: &Block| {
        format!(
            "{}: {} rows at line {} ({})",
            i + 1,
            r.rows.len(),
            r.names_line,
            r.channels.join(", ")
        )
    };
    let index = match pick {
        Some(k) if (1..=records.len()).contains(&k) => k - 1,
        Some(k) => {
            let list: Vec<String> = records.iter().enumerate().map(|(i, r)| describe(i, r)).collect();
            return Err(format!(
                "`block = {k}`, but the file holds {} data block(s): {}",
                records.len(),
                list.join("; ")
            ));
        }
        None => match (0..records.len()).max_by_key(|&i| (records[i].rows.len(), std::cmp::Reverse(i))) {
            Some(i) => i,
            None => return Ok(None),
        },
    };
    let why = match pick {
        Some(k) => format!("`block = {k}` picks another"),
        None => "the longest block is the time series (`block = N` picks another)".to_string(),
    };
    let notes = records
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != index)
        .map(|(i, r)| format!("skipped data block {}: {why}", describe(i, r)))
        .collect();
    let chosen = records.swap_remove(index);
    Ok(Some(Table {
        channels: chosen.channels,
        names_line: chosen.names_line,
        rows: chosen.rows,
        notes,
    }))
}
