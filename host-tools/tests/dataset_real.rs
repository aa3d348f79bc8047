//! Real instrument exports (tests/fixtures/vendor/README.md, "Real exports"):
//! files written by MTS 793, LabVIEW and NI software, copied unmodified from
//! public repositories. Expected values are read off the files by hand (line
//! numbers given) or taken from the reference reader's own tests (lvm_read,
//! npTDMS), never from mre's output.
use mre_host::dataset::{Dataset, DatasetError};
use std::path::{Path, PathBuf};

fn real(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/vendor/real")
        .join(name)
}

/// A folder holding the real file as `file` and a manifest listing it with
/// `settings` (only the current, as a lab fills it in, unless told).
fn folder(name: &str, file: &str, settings: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(real(name), dir.path().join(file)).unwrap();
    let manifest = format!("name = \"real\"\n\n[[recording]]\nfile = \"{file}\"\ncurrent_a = 0.0\n{settings}\n");
    std::fs::write(dir.path().join("dataset.toml"), manifest).unwrap();
    dir
}

fn load(name: &str, file: &str, settings: &str) -> Result<Dataset, DatasetError> {
    Dataset::load(folder(name, file, settings).path())
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

// --- MTS 793, German locale -------------------------------------------------

/// BAM's E-modulus test: ISO-8859-1 (`Prüfer`, `Länge`), decimal comma,
/// `Datenerfassung` block headers. Line 14 names the channels `Datum, Laufzeit,
/// Ch 1 Kraft Sollwert, Ch 1 Kraft, Ch 1 Weg, 1944 B, 1281068, 2157`, line 15
/// their units `d, s, kN, kN, mm, mm, mm, mm`; data lines 16–587 (572 rows).
/// Lines 589–593 are a second block, a two-row peak table of other channels.
#[test]
fn mts_german_latin1_export_reads_its_time_series_and_skips_the_peak_table() {
    let ds = load("mts793_deu_emodul_specimen.dat", "specimen.dat", "").unwrap();
    let s = &ds.recordings[0].samples;
    assert_eq!(s.len(), 572);
    // Line 16: 41883  34,306641  -1  -1,0232348  -5,6224585 …
    assert!(close(s.time_s[0], 34.306641, 1e-9), "{}", s.time_s[0]);
    assert!(close(s.force_n[0], -1023.2348, 1e-6), "{}", s.force_n[0]);
    assert!(close(s.x_mm[0], -5.6224585, 1e-9), "{}", s.x_mm[0]);
    // Line 587: 41883  319,80664  0  0,7769894  2,712491 …
    assert!(close(s.time_s[571], 319.80664, 1e-9));
    assert!(close(s.force_n[571], 776.9894, 1e-6));
    assert!(close(s.x_mm[571], 2.712491, 1e-9));
    // Line 110 holds the series' lowest force, -147,16052 kN (awk over
    // lines 16–587); the peak table's -147,20456 kN (line 593) is no sample.
    let lowest = s.force_n.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(close(lowest, -147_160.52, 1e-6), "{lowest}");
}
