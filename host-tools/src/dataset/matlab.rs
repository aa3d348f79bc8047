//! MATLAB recordings: `file = "drop01.mat"` with
//! `variables = { time_s = "t", displacement_mm = "x", force_n = "F" }`
//! (unit-named column = variable name). Read through the `matfile` crate
//! (MAT v5 and v7, compressed or not); each variable must be a real numeric
//! vector (one row or one column), or a column picked from a matrix as
//! `x_F[:,3]` (MATLAB's `x_F(:,3)` too; counted from 1), all of one length. The samples then go
//! through the same checks and unit conversions as a CSV file's, with the
//! sample number as the "line" of an error.
//!
//! MAT v7.3 files are HDF5, which `matfile` does not read: they get an error
//! saying how to save as v7.
use super::error::DatasetError;
use super::read::{samples_from_rows, Cell};
use super::Samples;
use std::collections::BTreeMap;
use std::path::Path;

/// How to get a file mre can read, for the v7.3 error.
pub const SAVE_AS_V7: &str = "save it as v7 in MATLAB: save('file.mat', 't', 'x', 'F', '-v7') \
                              (or `save file.mat -v7`; Octave: save -v7 file.mat)";

/// True for a MAT v7.3 (HDF5) file: version 0x0200 in the 128-byte header,
/// or the HDF5 signature after the 512-byte user block.
fn is_v73(bytes: &[u8]) -> bool {
    let version = bytes.get(124..126).map(|v| u16::from_le_bytes([v[0], v[1]]));
    let big_endian = bytes.get(126..128) == Some(b"MI".as_slice());
    let version = version.map(|v| if big_endian { v.swap_bytes() } else { v });
    version == Some(0x0200) || bytes.get(512..520) == Some(b"\x89HDF\r\n\x1a\n".as_slice())
}

fn to_f64(data: &matfile::NumericData) -> Option<Vec<f64>> {
    use matfile::NumericData as D;
    fn real<T: Copy + Into<f64>, I>(r: &[T], imag: &Option<I>) -> Option<Vec<f64>> {
        imag.is_none().then(|| r.iter().map(|&v| v.into()).collect())
    }
    match data {
        D::Double { real: r, imag } => real(r, imag),
        D::Single { real: r, imag } => real(r, imag),
        D::Int8 { real: r, imag } => real(r, imag),
        D::UInt8 { real: r, imag } => real(r, imag),
        D::Int16 { real: r, imag } => real(r, imag),
        D::UInt16 { real: r, imag } => real(r, imag),
        D::Int32 { real: r, imag } => real(r, imag),
        D::UInt32 { real: r, imag } => real(r, imag),
        // 64-bit integers beyond 2^53 lose precision; no recording needs them.
        D::Int64 { real: r, imag } => imag.is_none().then(|| r.iter().map(|&v| v as f64).collect()),
        D::UInt64 { real: r, imag } => imag.is_none().then(|| r.iter().map(|&v| v as f64).collect()),
    }
}

/// A variable's shape as MATLAB prints it (`3001×3`).
pub(super) fn shape(size: &[usize]) -> String {
    let dims: Vec<String> = size.iter().map(|d| d.to_string()).collect();
    dims.join("×")
}

/// `x_F` → (`x_F`, None); `x_F[:,3]` or `x_F(:,3)` → (`x_F`, Some(3)): a
/// column, counted from 1 as MATLAB counts.
fn parse_selection(spec: &str) -> Option<(&str, Option<usize>)> {
    let spec = spec.trim();
    let Some(open) = spec.find(['[', '(']) else {
        return (!spec.is_empty()).then_some((spec, None));
    };
    let close = if spec[open..].starts_with('[') { ']' } else { ')' };
    let inner = spec[open + 1..].strip_suffix(close)?;
    let (rows, col) = inner.split_once(',')?;
    let k: usize = col.trim().parse().ok()?;
    (rows.trim() == ":" && k >= 1 && open > 0).then_some((spec[..open].trim(), Some(k)))
}

/// Reads the `variables` of a .mat file as samples. `mpath`/`line` locate
/// the `variables` setting in dataset.toml, for errors about it.
pub(super) fn read_samples(
    path: &Path,
    variables: &BTreeMap<String, String>,
    mpath: &str,
    line: usize,
    notes: &mut Vec<String>,
) -> Result<(Samples, bool), DatasetError> {
    let dpath = path.display().to_string();
    let unreadable = |reason: String| DatasetError::Unreadable {
        path: dpath.clone(),
        reason,
    };
    let setting = |message: String| DatasetError::Manifest {
        path: mpath.to_string(),
        line,
        message,
    };
    let bytes = std::fs::read(path).map_err(|e| unreadable(e.to_string()))?;
    if is_v73(&bytes) {
        return Err(unreadable(format!(
            "a MATLAB v7.3 (HDF5) file, which mre does not read; {SAVE_AS_V7}"
        )));
    }
    let mat = matfile::MatFile::parse(bytes.as_slice())
        .map_err(|e| unreadable(format!("not a MATLAB v5/v7 MAT-file ({e})")))?;
    let file = path.file_name().unwrap_or_default().to_string_lossy();
    let mut names = Vec::with_capacity(variables.len());
    let mut columns: Vec<(&str, Vec<f64>)> = Vec::with_capacity(variables.len());
    for (column, spec) in variables {
        let (var, pick) = parse_selection(spec).ok_or_else(|| {
            setting(format!(
                "`{spec}` (for {column}) is not a variable name or a column of one such as `x_F[:,3]`"
            ))
        })?;
        let Some(array) = mat.find_by_name(var) else {
            let have: Vec<&str> = mat.arrays().iter().map(|a| a.name()).collect();
            return Err(setting(format!(
                "`{file}` has no numeric variable `{var}` (for {column}); it has: {}",
                if have.is_empty() {
                    "none".to_string()
                } else {
                    have.join(", ")
                }
            )));
        };
        let size = array.size();
        let values = to_f64(array.data())
            .ok_or_else(|| setting(format!("`{file}`: variable `{var}` (for {column}) is complex")))?;
        let values = match pick {
            Some(k) => {
                let (&[rows, cols], true) = (size.as_slice(), (1..=size.get(1).copied().unwrap_or(0)).contains(&k))
                else {
                    return Err(setting(format!(
                        "`{file}`: `{spec}` (for {column}) picks column {k} of `{var}`, which is {}",
                        shape(size)
                    )));
                };
                // MATLAB stores a matrix column by column.
                match values.get((k - 1) * rows..k * rows) {
                    Some(column) if values.len() == rows * cols => column.to_vec(),
                    _ => {
                        return Err(setting(format!(
                            "`{file}`: variable `{var}` holds fewer values than its shape"
                        )))
                    }
                }
            }
            None => values,
        };
        if pick.is_none() && size.iter().filter(|&&d| d != 1).count() > 1 {
            return Err(setting(format!(
                "`{file}`: variable `{var}` (for {column}) is {}; a column needs a vector (one row or one column), \
                 or pick one of its columns: {column} = \"{var}[:,1]\"",
                shape(size)
            )));
        }
        if let Some((first, v0)) = columns.first() {
            if v0.len() != values.len() {
                return Err(setting(format!(
                    "`{file}`: variable `{var}` has {} samples but `{first}` has {}",
                    values.len(),
                    v0.len()
                )));
            }
        }
        names.push(column.clone());
        columns.push((spec.as_str(), values));
    }
    let n = columns.first().map_or(0, |(_, v)| v.len());
    let rows = (0..n).map(|k| (k + 1, columns.iter().map(|(_, c)| Cell::Number(c[k])).collect()));
    samples_from_rows(&dpath, &names, mpath, line, rows, notes)
}

/// The tests' MAT-file writer (shared with the integration tests).
#[cfg(test)]
#[path = "../../tests/support/mat_v5.rs"]
pub(super) mod mat_v5;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_picked_as_matlab_writes_them() {
        assert_eq!(parse_selection("x_F[:,3]"), Some(("x_F", Some(3))));
        assert_eq!(parse_selection(" x_F(:, 2) "), Some(("x_F", Some(2))));
        assert_eq!(parse_selection("F"), Some(("F", None)));
        assert_eq!(parse_selection("x_F[:,0]"), None);
        assert_eq!(parse_selection("x_F[1,:]"), None);
        assert_eq!(parse_selection("x_F[:,3"), None);
        assert_eq!(parse_selection("[:,3]"), None);
    }

    #[test]
    fn v73_is_told_from_its_header() {
        assert!(is_v73(&mat_v5::mat_v73_header()));
        assert!(!is_v73(&mat_v5::mat_v5(&[("t", 1, 2, &[0.0, 1.0])])));
    }
}
