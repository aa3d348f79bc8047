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

/// BAM's cube compression test (2024): the two-row peak table comes first
/// (lines 14–17, `Ch 1 Weg`, `Ch 1 Prüfkraft`), the time series after it
/// (names line 21: `Datum, Tageszeit, Laufzeit, Ch 1 Weg, Ch 1 Prüfkraft`
/// over `d, d, s, mm, kN`; data lines 23–504, 482 rows). The peak table no
/// longer hides the series.
#[test]
fn mts_peak_table_first_does_not_hide_the_time_series() {
    let ds = load("mts793_deu_cube_compression_specimen.dat", "specimen.dat", "").unwrap();
    let s = &ds.recordings[0].samples;
    assert_eq!(s.len(), 482);
    // Line 23: 45349  0,40462285  35,414063  -0,0020439089  -16,605667
    assert!(close(s.time_s[0], 35.414063, 1e-9));
    assert!(close(s.x_mm[0], -0.0020439089, 1e-12));
    assert!(close(s.force_n[0], -16_605.667, 1e-6));
    // Line 492 holds the series' lowest force (awk over lines 23–504).
    let lowest = s.force_n.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(close(lowest, -1_061_380.7, 1e-3), "{lowest}");
    // Line 504: … 131,70801  4,8337913  0,41905928
    assert!(close(s.time_s[481], 131.70801, 1e-9) && close(s.force_n[481], 419.05928, 1e-6));
}

/// The German record with its displacement negated (lines 16–587, fifth
/// field; one stated change): force and displacement now read opposite
/// ways, the work on the specimen while loading is negative (by hand, awk
/// over lines 16–110: +15.0 J of 35.2 J gross before the change), and the
/// record is refused naming the fix, though it is no impact.
#[test]
fn mts_record_whose_loading_work_is_negative_names_the_sign_fix() {
    let bytes = std::fs::read(real("mts793_deu_emodul_specimen.dat")).unwrap();
    let mut out = Vec::new();
    for (i, line) in bytes.split_inclusive(|&b| b == b'\n').enumerate() {
        if !(15..587).contains(&i) {
            out.extend_from_slice(line);
            continue;
        }
        let mut fields: Vec<Vec<u8>> = line.split(|&b| b == b'\t').map(<[u8]>::to_vec).collect();
        let weg = &mut fields[4];
        if weg.first() == Some(&b'-') {
            weg.remove(0);
        } else {
            weg.insert(0, b'-');
        }
        out.extend_from_slice(&fields.join(&b'\t'));
    }
    assert_ne!(out, bytes);
    let dir = folder("mts793_deu_emodul_specimen.dat", "specimen.dat", "");
    std::fs::write(dir.path().join("specimen.dat"), &out).unwrap();
    let e = Dataset::load(dir.path()).unwrap_err().to_string();
    assert!(
        e.contains("sign = { force_n = -1 }") && e.contains("passive damper takes work"),
        "{e}"
    );
}

// --- LabVIEW .lvm (lvm_read's test data) -------------------------------------

fn lvm_table(name: &str) -> Result<mre_host::dataset::vendor::Table, DatasetError> {
    let path = real(name);
    let bytes = std::fs::read(&path).unwrap();
    (mre_host::dataset::lvm::READER.read)(&path, &bytes)
}

fn number(c: &mre_host::dataset::read::Cell) -> f64 {
    c.to_string().parse().unwrap()
}

/// `Samples 8192` in the one header, 16 384 data rows (lines 23–16406): two
/// writes under one header. lvm_read reads all rows; so does mre.
#[test]
fn lvm_two_writes_under_one_header_are_read_whole() {
    let t = lvm_table("lvm_read_long_single_header_multi_ch.lvm").unwrap();
    assert_eq!(t.rows.len(), 16_384);
    assert_eq!(t.channels, ["Time (s)", "F (g)", "m_1 (m/s^2)", "m_2 (m/s^2)"]);
    // X_Columns No: time = X0 + k·Delta_X, Delta_X 0.000977, continuing
    // into the second write (row 8192, line 8215: 0.052115 0.210231 0.276808).
    let row = &t.rows[8192];
    assert_eq!(row.0, 8215);
    assert!(close(number(&row.1[0]), 8192.0 * 0.000977, 1e-9));
    assert!(close(number(&row.1[1]), 0.052115, 1e-12));
    assert!(close(number(&row.1[3]), 0.276808, 1e-12));
    // Line 16406, the last: 0.052073 0.235689 0.263686.
    let last = t.rows.last().unwrap();
    assert_eq!(last.0, 16_406);
    assert!(close(number(&last.1[2]), 0.235689, 1e-12));
    assert!(
        t.notes.iter().any(|n| n.contains("2 writes under one header")),
        "{:?}",
        t.notes
    );
}

/// X_Columns Multi: header rows with a blank cell over each X column
/// (`Samples 51200 ␉ ␉ 51200`). The file holds 3 of the 51 200 samples it
/// declares (lvm_read's authors cut it): refused as cut short, the true
/// reason, after its Multi header was read (channels and units right).
#[test]
fn lvm_x_columns_multi_header_is_read_and_the_cut_file_called_cut() {
    let e = lvm_table("lvm_read_multi_time_column.lvm").err().unwrap().to_string();
    assert!(
        e.contains("declares 51200 samples but holds 3: the file is cut short"),
        "{e}"
    );
    assert!(!e.contains("X_Dimension"), "{e}");
}

/// `X_Columns No`, decimal comma, `Newtons` and `m/s^2` (lvm_read's test:
/// first value 0.914018). A hammer test, not a damper record, so it is read
/// as a table: the channels with their units, the time base and the values.
#[test]
fn lvm_decimal_comma_newtons_and_the_time_base() {
    let t = lvm_table("lvm_read_short.lvm").unwrap();
    assert_eq!(
        t.channels,
        [
            "Time (s)",
            "Excitation (Trigger) (Newtons)",
            "Response (Trigger) (m/s^2)"
        ]
    );
    assert_eq!(t.rows.len(), 10);
    assert!(close(number(&t.rows[0].1[1]), 0.914018, 1e-12));
    // Delta_X 3,906250E-5: the last sample (line 33: ␉0,680572␉1,212775) at 9 × 39.0625 µs.
    let last = &t.rows[9];
    assert_eq!(last.0, 33);
    assert!(close(number(&last.1[0]), 9.0 * 3.90625e-5, 1e-15));
    assert!(close(number(&last.1[2]), 1.212775, 1e-12));
}

/// `°C` written as the Windows-1252 byte 0xB0 (`Temperatura (°C)`): read as
/// text, not refused as "not text". The file has pressure, temperature and
/// volume, no force: refused for that, its channels listed.
#[test]
fn lvm_windows_1252_unit_is_text_and_a_file_without_force_says_so() {
    let t = lvm_table("lvm_read_with_comments.lvm").unwrap();
    assert_eq!(t.channels[2], "Temperatura (°C) (°C)");
    assert!(close(number(&t.rows[0].1[1]), 1.833787, 1e-12), "lvm_read's test value");
    let e = load("lvm_read_with_comments.lvm", "c.lvm", "").unwrap_err().to_string();
    assert!(
        e.contains("no force channel") && e.contains("Temperatura (°C) (°C)"),
        "{e}"
    );
}

// --- NI TDMS (npTDMS's test data) --------------------------------------------

fn tdms_table(name: &str) -> Result<mre_host::dataset::vendor::Table, DatasetError> {
    let path = real(name);
    let bytes = std::fs::read(&path).unwrap();
    (mre_host::dataset::tdms::READER.read)(&path, &bytes)
}

/// Written by LabVIEW: 9 segments with incremental metadata (lead-in
/// flags 0x6 / 0xE), three groups holding a channel `Dev1_port3_line7 -
/// line 0`: the raw group (segment 4: 20 000 uint8 bytes from byte 1678,
/// read by hand as 0, 1, 0, 1, …) and two decimated levels (segment 8:
/// 400 + 8 bytes; npTDMS's test reads Level1 as 0, 1, 0, 1, …). mre reads
/// the longest group as the record and names the skipped ones.
#[test]
fn tdms_multi_segment_labview_file_reads_its_longest_group() {
    let t = tdms_table("nptdms_Digital_Input.tdms").unwrap();
    assert_eq!(t.channels, ["Time (s)", "Dev1_port3_line7 - line 0"]);
    assert_eq!(t.rows.len(), 20_000);
    for (k, row) in t.rows.iter().take(10).enumerate() {
        assert_eq!(number(&row.1[1]), (k % 2) as f64, "sample {k}");
    }
    let skipped = t.notes.join("; ");
    assert!(skipped.contains("Decimated Data_Level1` (400 values"), "{skipped}");
    assert!(skipped.contains("Decimated Data_Level2` (8 values"), "{skipped}");
}

/// DAQmx raw data (npTDMS reads it by applying the DAQmx scalers): refused
/// for that reason, not as corrupt or cut short.
#[test]
fn tdms_daqmx_raw_file_is_refused_for_its_true_reason() {
    let e = tdms_table("nptdms_raw1.tdms").err().unwrap().to_string();
    assert!(e.contains("DAQmx raw data"), "{e}");
    assert!(!e.contains("corrupt") && !e.contains("cut short"), "{e}");
}

// --- mre dataset init on real files ------------------------------------------

/// A folder holding only `name` as `file`, no manifest.
fn bare(name: &str, file: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(real(name), dir.path().join(file)).unwrap();
    dir
}

/// init on BAM's record: compression reads negative in both force and
/// displacement (force below zero while loading; the work positive). init
/// flips both, says so, and the manifest loads once the current is filled in.
#[test]
fn init_flips_a_compression_negative_mts_record_and_its_manifest_loads() {
    let dir = bare("mts793_deu_emodul_specimen.dat", "specimen.dat");
    let text = mre_host::dataset::init::manifest_for(dir.path(), None, Some("bam")).unwrap();
    assert!(
        text.contains("sign = { force_kn = -1, displacement_mm = -1 }"),
        "{text}"
    );
    assert!(
        text.contains("assumed: `force_kn` reads compression negative"),
        "{text}"
    );
    assert!(text.contains("skipped data block 2: 2 rows at line 590"), "{text}");
    // The lab fills in the current, nothing else.
    let text = text.replace("file = \"specimen.dat\"", "file = \"specimen.dat\"\ncurrent_a = 0.0");
    std::fs::write(dir.path().join("dataset.toml"), text).unwrap();
    let ds = Dataset::load(dir.path()).unwrap();
    let s = &ds.recordings[0].samples;
    // Line 16, flipped: -1,0232348 kN → +1023.2348 N; -5,6224585 mm → +5.6224585 mm.
    assert!(close(s.force_n[0], 1023.2348, 1e-6) && close(s.x_mm[0], 5.6224585, 1e-9));
}

/// init never writes a manifest that cannot load: a file without force
/// (pressure, temperature, volume) fails naming its channels and the names
/// accepted.
#[test]
fn init_refuses_a_file_without_force_naming_its_channels() {
    let dir = bare("lvm_read_with_comments.lvm", "c.lvm");
    let e = mre_host::dataset::init::manifest_for(dir.path(), None, Some("x"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no force channel") && e.contains("force_n, force_kn, force_lbf"),
        "{e}"
    );
    assert!(e.contains("Temperatura (°C) (°C)"), "{e}");
    assert!(!dir.path().join("dataset.toml").exists());
}

/// `block = N` picks a data block of an MTS file (issue 41 item 3). BAM's
/// cube test holds two (the peak table at line 15, the series at line 21):
/// `block = 2` is the series the default takes (482 rows, as above);
/// `block = 1`, the peak table, has no time channel and is refused for
/// that; `block = 3` lists the two there are; an LabVIEW file refuses the key.
#[test]
fn mts_block_in_the_manifest_picks_the_data_block() {
    let name = "mts793_deu_cube_compression_specimen.dat";
    let ds = load(name, "specimen.dat", "block = 2").unwrap();
    assert_eq!(ds.recordings[0].samples.len(), 482);
    let notes = ds.recordings[0].notes.join(" | ");
    assert!(notes.contains("skipped data block 1: 2 rows at line 15"), "{notes}");
    let e = load(name, "specimen.dat", "block = 1").unwrap_err().to_string();
    assert!(e.contains("no time channel"), "{e}");
    let e = load(name, "specimen.dat", "block = 3").unwrap_err().to_string();
    assert!(
        e.contains("`block = 3`, but the file holds 2 data block(s): 1: 2 rows at line 15")
            && e.contains("2: 482 rows at line 21"),
        "{e}"
    );
    let e = load("lvm_read_short.lvm", "short.lvm", "block = 1")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`block` picks a data block of an MTS 793 Specimen.dat"),
        "{e}"
    );
}
