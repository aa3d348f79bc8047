//! Text as labs write it (issue 41 item 2): tied time stamps at an export's
//! resolution, a units row under the names, CRLF line ends in error lines,
//! a Bluehill-style preamble. No real Bluehill export with a licence that
//! allows redistribution was found: these files are written by hand after
//! the layout the issue reports (a `Results Table 1 : Specimen 1` line, a
//! blank line, quoted names over quoted units in parentheses), and each
//! expected value is worked out by hand in the test.
use mre_host::dataset::Dataset;
use std::fmt::Write as _;
use std::path::Path;

fn load(dir: &Path, data: &str, settings: &str) -> Result<Dataset, String> {
    std::fs::write(dir.join("r.csv"), data).unwrap();
    let manifest = format!("[[recording]]\nfile = \"r.csv\"\ncurrent_a = 0.5\n{settings}\n");
    std::fs::write(dir.join("dataset.toml"), manifest).unwrap();
    Dataset::load(dir).map_err(|e| e.to_string())
}

/// 30 rows sampled at 300 Hz with time written at 0.01 s: each stamp three
/// times. Row k: stamp 0.01·⌊k/3⌋, x = k mm, F = 10·k N.
fn tied_rows() -> String {
    let mut s = String::new();
    for k in 0..30 {
        writeln!(s, "{:.2},{k},{}", 0.01 * (k / 3) as f64, 10 * k).unwrap();
    }
    s
}

#[test]
fn tied_time_stamps_are_kept_in_order_and_spread_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let ds = load(
        dir.path(),
        &format!("time_s,displacement_mm,force_n\n{}", tied_rows()),
        "",
    )
    .unwrap();
    let r = &ds.recordings[0];
    assert_eq!(r.samples.len(), 30, "every row kept");
    for k in 0..30 {
        // By hand: the three rows of a stamp at +0, +1/3 and +2/3 of the 0.01 s step.
        let t = 0.01 * (k / 3) as f64 + 0.01 * (k % 3) as f64 / 3.0;
        assert!(
            (r.samples.time_s[k] - t).abs() < 1e-12,
            "row {k}: {} vs {t}",
            r.samples.time_s[k]
        );
        assert_eq!(r.samples.x_mm[k], k as f64, "order kept");
    }
    // 10 stamps × 2 repeats; the first repeat is row 2 of the data, line 3.
    let note = r.notes.iter().find(|n| n.contains("time stamp")).expect("a note");
    assert!(
        note.starts_with("20 rows") && note.contains("line 3") && note.contains("0.01 s"),
        "{note}"
    );
}

#[test]
fn time_that_goes_back_is_still_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut rows = tied_rows();
    rows.push_str("0.05,30,300\n");
    let e = load(dir.path(), &format!("time_s,displacement_mm,force_n\n{rows}"), "").unwrap_err();
    // Line 32: the header, 30 rows, then the row whose 0.05 s is below 0.09 s.
    assert!(e.contains("line 32") && e.contains("does not increase"), "{e}");
}

/// The Bluehill layout: preamble, blank line, names, units, data.
fn bluehill(eol: &str, unit_load: &str, rows: &str) -> String {
    let mut s = String::new();
    for line in [
        "Results Table 1 : Specimen 1",
        "",
        "\"Time\",\"Extension\",\"Load\"",
        &format!("\"(sec)\",\"(mm)\",\"({unit_load})\""),
    ] {
        s.push_str(line);
        s.push_str(eol);
    }
    for line in rows.lines() {
        s.push_str(line);
        s.push_str(eol);
    }
    s
}

#[test]
fn a_bluehill_preamble_is_skipped_and_its_units_row_sets_the_scale() {
    let dir = tempfile::tempdir().unwrap();
    let ds = load(dir.path(), &bluehill("\n", "kN", &tied_rows()), "").unwrap();
    let r = &ds.recordings[0];
    assert_eq!(r.samples.len(), 30);
    // Load in kN: row 4 reads 40 → 40 000 N; Extension in mm.
    assert_eq!(r.samples.force_n[4], 40_000.0);
    assert_eq!(r.samples.x_mm[4], 4.0);
    let notes = r.notes.join(" | ");
    assert!(notes.contains("skipped"), "{notes}");
    assert!(
        notes.contains("units row (line 4)") && notes.contains("force_kn"),
        "{notes}"
    );
    // The same with the load in N: the units row, not the names, sets the scale.
    let ds = load(dir.path(), &bluehill("\n", "N", &tied_rows()), "").unwrap();
    assert_eq!(ds.recordings[0].samples.force_n[4], 40.0);
}

#[test]
fn crlf_files_name_the_line_of_a_bad_value() {
    let dir = tempfile::tempdir().unwrap();
    // Data row 5 (k = 4) is bad: lines 1–4 preamble, blank, names, units, so line 9.
    let bad: String = tied_rows()
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 4 {
                "0.01,abc,40\n".to_string()
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    for eol in ["\n", "\r\n"] {
        let e = load(dir.path(), &bluehill(eol, "N", &bad), "").unwrap_err();
        assert!(e.contains("line 9,") && e.contains("`abc`"), "{eol:?}: {e}");
        // With a plain header: line 6.
        let plain = format!("time_s,displacement_mm,force_n{eol}{}", bad.replace('\n', eol));
        let e = load(dir.path(), &plain, "").unwrap_err();
        assert!(e.contains("line 6,") && e.contains("`abc`"), "{eol:?}: {e}");
        let ws = plain.replace(',', " ");
        let e = load(dir.path(), &ws, "delimiter = \"whitespace\"").unwrap_err();
        assert!(e.contains("line 6,") && e.contains("`abc`"), "{eol:?} whitespace: {e}");
    }
}

/// LabVIEW's "Write To Spreadsheet File" in a German locale: no header,
/// tab-separated, decimal commas (`%.6f`). A 5 kg drop: 2000 rows at 10 kHz,
/// force a 4 ms half-sine of 3 kN from row 500 (t = 50 ms).
fn labview_headerless() -> String {
    let mut s = String::new();
    for k in 0..2000 {
        let t = k as f64 * 1e-4;
        let f = if (500..=540).contains(&k) {
            3000.0 * (std::f64::consts::PI * (k - 500) as f64 / 40.0).sin()
        } else {
            0.0
        };
        writeln!(
            s,
            "{}\t{}",
            format!("{t:.6}").replace('.', ","),
            format!("{f:.6}").replace('.', ",")
        )
        .unwrap();
    }
    s
}

#[test]
fn labview_headerless_text_loads_with_columns_in_the_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let settings =
        "delimiter = \"whitespace\"\ncolumns = [\"time_s\", \"force_n\"]\nmass_kg = 5.0\nimpact_velocity_m_s = 2.0";
    let ds = load(dir.path(), &labview_headerless(), settings).unwrap();
    let s = &ds.recordings[0].samples;
    // The peak, row 520: t = 0.052 s, F = 3000 N (sin π/2), read through the decimal commas.
    let k = s
        .force_n
        .iter()
        .cloned()
        .enumerate()
        .fold((0, f64::MIN), |b, (i, f)| if f > b.1 { (i, f) } else { b })
        .0;
    assert_eq!(s.force_n[k], 3000.0);
    assert!((s.time_s[k] - 0.052).abs() < 1e-12, "{}", s.time_s[k]);
    // Trimmed to the contact: row 500 (the last zero) ± 10 rows, to row 539 + 10.
    assert!((s.time_s[0] - 0.049).abs() < 1e-12, "{}", s.time_s[0]);
    assert_eq!(s.len(), 60, "rows 490 to 549");
    // Without `columns`, the refusal says the file has no header and how to name it.
    let e = load(dir.path(), &labview_headerless(), "delimiter = \"whitespace\"").unwrap_err();
    assert!(
        e.contains("line 1") && e.contains("no header") && e.contains("columns ="),
        "{e}"
    );
}

/// Unit scale factors (issue 41 item 8), from their definitions: 1 in =
/// 25.4 mm, 1 lbf = 0.453 592 37 kg × 9.806 65 m/s² = 4.448 221 615 260 5 N.
/// A Bluehill file in inches and pound-force, read from its units row, and
/// the same names given as `columns`; then `mre dataset init`'s manifest for
/// it loads with only the current filled in.
#[test]
fn inches_and_pound_force_scale_and_init_writes_a_manifest_that_loads() {
    let dir = tempfile::tempdir().unwrap();
    let mut rows = String::new();
    for k in 0..20 {
        writeln!(rows, "{:.2},{}.5,{}", 0.01 * k as f64, k, 100 * k).unwrap();
    }
    let file = bluehill("\r\n", "lbf", &rows).replace("\"(mm)\"", "\"(in)\"");
    let ds = load(dir.path(), &file, "").unwrap();
    let s = &ds.recordings[0].samples;
    // Row 3: 3.5 in, 300 lbf.
    assert!((s.x_mm[3] - 3.5 * 25.4).abs() < 1e-9, "{}", s.x_mm[3]);
    assert!(
        (s.force_n[3] - 300.0 * 0.453_592_37 * 9.806_65).abs() < 1e-9,
        "{}",
        s.force_n[3]
    );
    let named = load(
        dir.path(),
        &file,
        "columns = [\"time_s\", \"displacement_in\", \"force_lbf\"]",
    )
    .unwrap();
    assert_eq!(named.recordings[0].samples, *s);

    std::fs::remove_file(dir.path().join("dataset.toml")).unwrap();
    let manifest = mre_host::dataset::init::manifest_for(dir.path(), None, None).unwrap();
    assert!(
        manifest.contains("displacement_in") && manifest.contains("force_lbf"),
        "{manifest}"
    );
    let filled = manifest.replacen("[defaults]\n", "[defaults]\ncurrent_a = 1.0\n", 1);
    let ds = Dataset::from_manifest(dir.path(), &filled).unwrap_or_else(|e| panic!("{e}\n{filled}"));
    assert_eq!(ds.recordings[0].samples, *s);
}

/// `mre dataset init` on a file with no force column refuses it, naming the
/// file's columns and the names mre accepts, rather than write a manifest
/// of `ignore` columns that fails later (issue 41 item 8).
#[test]
fn init_refuses_a_text_file_without_force_naming_its_columns() {
    let dir = tempfile::tempdir().unwrap();
    let mut data = String::from("Time (s),Strain (%)\n");
    for k in 0..12 {
        writeln!(data, "{},{}", k as f64 * 0.1, k).unwrap();
    }
    std::fs::write(dir.path().join("r.csv"), data).unwrap();
    let e = format!(
        "{:#}",
        mre_host::dataset::init::manifest_for(dir.path(), None, None).unwrap_err()
    );
    assert!(
        e.contains("missing required column for force")
            && e.contains("force_lbf")
            && e.contains("`Time (s)`, `Strain (%)`"),
        "{e}"
    );
}
