//! What real DAQ exports and spreadsheets write: a byte-order mark, CRLF line
//! ends, quoted header names, comment lines, whitespace-delimited columns; and
//! values no instrument can produce, rejected at load with file, line and column.
use mre_host::dataset::{Dataset, DatasetError};
use std::path::Path;

const MANIFEST: &str = "name = \"daq\"\n[[recording]]\nfile = \"a.csv\"\ncurrent_a = 0.5\n";

/// 12 samples of x = i·0.1 mm, F = 50·x N, t = i·0.01 s, one line each.
fn rows(sep: &str, eol: &str) -> String {
    (0..12)
        .map(|i| {
            let x = i as f64 * 0.1;
            format!("{}{sep}{x}{sep}{}{eol}", i as f64 * 0.01, 50.0 * x)
        })
        .collect()
}

fn load(dir: &Path, manifest: &str, data: &[u8]) -> Result<Dataset, DatasetError> {
    std::fs::write(dir.join("dataset.toml"), manifest).unwrap();
    std::fs::write(dir.join("a.csv"), data).unwrap();
    Dataset::load(dir)
}

fn check_samples(ds: &Dataset) {
    let s = &ds.recordings[0].samples;
    assert_eq!(s.len(), 12);
    assert_eq!(s.time_s[3], 0.03);
    assert_eq!(s.x_mm[5], 0.5);
    assert_eq!(s.force_n[5], 25.0);
}

#[test]
fn an_excel_export_loads() {
    // UTF-8 BOM, quoted header names, CRLF, a comment line before the header
    // and one between samples, a blank line at the end.
    let mut text =
        String::from("\u{feff}# exported 2026-11-22 by the DAQ\r\n\"time_s\",\"displacement_mm\",\"force_n\"\r\n");
    let body = rows(",", "\r\n");
    let (first, rest) = body.split_at(body.find("\r\n").unwrap() + 2);
    text.push_str(first);
    text.push_str("# channel 2 re-zeroed\r\n");
    text.push_str(rest);
    text.push_str("\r\n");
    let dir = tempfile::tempdir().unwrap();
    check_samples(&load(dir.path(), MANIFEST, text.as_bytes()).unwrap());
}

#[test]
fn spaces_around_names_and_quote_all_numbers_load() {
    let mut text = String::from(" time_s , displacement_mm , force_n \n");
    for line in rows(",", "\n").lines() {
        let quoted: Vec<String> = line.split(',').map(|f| format!("\"{f}\"")).collect();
        text.push_str(&quoted.join(","));
        text.push('\n');
    }
    let dir = tempfile::tempdir().unwrap();
    check_samples(&load(dir.path(), MANIFEST, text.as_bytes()).unwrap());
}

#[test]
fn a_whitespace_file_with_bom_crlf_tabs_and_comments_loads() {
    let mut text = String::from("\u{feff}# MTS export\r\n\"time_s\"\t\"displacement_mm\"   \"force_n\"\r\n");
    text.push_str(&rows("\t  ", "\r\n"));
    let manifest = MANIFEST.replace("[[recording]]", "[defaults]\ndelimiter = \"whitespace\"\n[[recording]]");
    let dir = tempfile::tempdir().unwrap();
    check_samples(&load(dir.path(), &manifest, text.as_bytes()).unwrap());
}

#[test]
fn an_absurd_force_is_rejected_at_load_with_file_line_and_column() {
    let mut text = String::from("time_s,displacement_mm,force_n\n");
    text.push_str(&rows(",", "\n"));
    // Line 5 (the 4th sample) gets a force of 1e300 N.
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    lines[4] = "0.03,0.3,1e300".into();
    let dir = tempfile::tempdir().unwrap();
    let err = load(dir.path(), MANIFEST, lines.join("\n").as_bytes()).unwrap_err();
    let file = dir.path().join("a.csv").display().to_string();
    assert_eq!(
        err.to_string(),
        format!(
            "{file}: line 5, column 3 (force_n): `1e300` is outside the plausible force range [-10000000, 10000000] N"
        )
    );
}

#[test]
fn a_displacement_in_metres_written_as_millimetres_of_a_kilometre_is_rejected() {
    // 2 m in a `displacement_m` column is 2000 mm: beyond the 1 m bound.
    let mut text = String::from("time_s,displacement_m,force_n\n");
    for i in 0..12 {
        text.push_str(&format!("{},{},1\n", i as f64 * 0.01, if i == 7 { 2.0 } else { 0.001 }));
    }
    let dir = tempfile::tempdir().unwrap();
    let err = load(dir.path(), MANIFEST, text.as_bytes()).unwrap_err();
    assert!(
        matches!(err, DatasetError::OutOfRange { line: 9, column: 2, .. }),
        "{err}"
    );
}

#[test]
fn an_absurd_current_in_the_manifest_is_rejected_with_line_and_column() {
    let mut text = String::from("time_s,displacement_mm,force_n\n");
    text.push_str(&rows(",", "\n"));
    let manifest = "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 500.0\n";
    let dir = tempfile::tempdir().unwrap();
    let err = load(dir.path(), manifest, text.as_bytes()).unwrap_err();
    let m = dir.path().join("dataset.toml").display().to_string();
    assert_eq!(
        err.to_string(),
        format!("{m}: line 3, column 13: `current_a` = 500 is outside the plausible range [-100, 100] A")
    );
}

#[test]
fn a_toml_syntax_error_names_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    // Line 3: `current_a = 0.5.5`; the parser stops at the second `.`, column 16.
    let manifest = "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 0.5.5\n";
    let err = load(dir.path(), manifest, b"").unwrap_err();
    assert!(
        matches!(
            err,
            DatasetError::Syntax {
                line: 3,
                column: 16,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("dataset.toml: line 3, column 16: "), "{err}");
}

#[test]
fn a_file_that_is_not_text_names_its_line() {
    // Bytes that are not UTF-8 are read in the legacy encoding they look
    // like (here Windows-1252 `ÿþ`), and a field that is not a number is
    // named at its line and column, as written.
    let mut text = b"time_s,displacement_mm,force_n\n0,0,0\n".to_vec();
    text.extend_from_slice(b"0.01,\xff\xfe,1\n");
    let dir = tempfile::tempdir().unwrap();
    let err = load(dir.path(), MANIFEST, &text).unwrap_err().to_string();
    assert!(
        err.contains("line 3, column 2") && err.contains("is not a number"),
        "{err}"
    );
}

#[test]
fn an_absurd_estimated_velocity_is_rejected_at_load() {
    // Samples 1 ns apart with 0.1 mm between them: 10⁵ m/s, far beyond the
    // 100 m/s bound; the velocity column is missing, so it is estimated.
    let mut text = String::from("time_s,displacement_mm,force_n\n");
    for i in 0..12 {
        text.push_str(&format!("{},{},1\n", i as f64 * 1e-9, i as f64 * 0.1));
    }
    let dir = tempfile::tempdir().unwrap();
    let err = load(dir.path(), MANIFEST, text.as_bytes()).unwrap_err();
    assert!(
        matches!(&err, DatasetError::OutOfRange { line: 2, column: 2, name, .. } if name.contains("estimated")),
        "{err}"
    );
}

/// Spreadsheets and lab software save in the system's encoding: a comment
/// line in Windows-1252 (`Prüfer`), in GBK (`试样`), and the whole file as
/// UTF-16 with its byte-order mark all load; NUL bytes without a UTF-16
/// mark are binary and refused at their line. (No real CSV export with a
/// licence that allows redistribution was found; these are built here.)
#[test]
fn csv_in_legacy_encodings_and_utf16_loads() {
    let text = |comment: &str| format!("# {comment}\ntime_s,displacement_mm,force_n\n{}", rows(",", "\n"));
    let cases: Vec<(&str, Vec<u8>)> = vec![
        (
            "windows-1252",
            encoding_rs::WINDOWS_1252.encode(&text("Prüfer: Müller")).0.into_owned(),
        ),
        ("GBK", encoding_rs::GBK.encode(&text("试样 1 号")).0.into_owned()),
        ("UTF-16LE", {
            let mut b = vec![0xFF, 0xFE];
            b.extend(text("Prüfer").encode_utf16().flat_map(u16::to_le_bytes));
            b
        }),
    ];
    for (what, bytes) in cases {
        assert!(
            std::str::from_utf8(&bytes).is_err(),
            "{what}: not UTF-8, so the case tests decoding"
        );
        let dir = tempfile::tempdir().unwrap();
        let ds = load(dir.path(), MANIFEST, &bytes).unwrap_or_else(|e| panic!("{what}: {e}"));
        check_samples(&ds);
    }
    let dir = tempfile::tempdir().unwrap();
    let mut binary = text("x").into_bytes();
    // Byte 40 is on line 3 ("# x\n" and the 31-byte header row come first).
    binary[40] = 0;
    let e = load(dir.path(), MANIFEST, &binary).unwrap_err().to_string();
    assert!(e.contains("line 3") && e.contains("binary bytes (NUL)"), "{e}");
}

/// `;` with decimal commas and CRLF, as a spreadsheet in a German, French
/// or Spanish locale saves CSV: `delimiter = ";"` reads it, and `mre dataset
/// init` writes that line itself.
#[test]
fn semicolon_files_with_decimal_commas_load_and_init_says_so() {
    let body = rows(";", "\r\n").replace('.', ",");
    let text = format!("time_s;displacement_mm;force_n\r\n{body}");
    let dir = tempfile::tempdir().unwrap();
    let manifest = MANIFEST.replace("current_a = 0.5\n", "current_a = 0.5\ndelimiter = \";\"\n");
    check_samples(&load(dir.path(), &manifest, text.as_bytes()).unwrap());
    // Read as `,` it is refused at its header, not misread.
    let e = load(dir.path(), MANIFEST, text.as_bytes()).unwrap_err().to_string();
    assert!(
        e.contains("line 1") && e.contains("unknown column name `time_s;displacement_mm;force_n`"),
        "{e}"
    );

    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a0x5A.csv"), &text).unwrap();
    let toml = mre_host::dataset::init::manifest_for(dir.path(), Some("a{current_a}A"), None).unwrap();
    assert!(toml.contains("delimiter = \";\""), "{toml}");
    std::fs::write(dir.path().join("dataset.toml"), &toml).unwrap();
    check_samples(&Dataset::load(dir.path()).unwrap());
}
