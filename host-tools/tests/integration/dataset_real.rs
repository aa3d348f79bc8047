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

/// The first largest value and its index (the peak load a test reads off the file).
fn largest(values: &[f64]) -> (usize, f64) {
    values
        .iter()
        .copied()
        .enumerate()
        .fold((0, f64::MIN), |a, (i, f)| if f > a.1 { (i, f) } else { a })
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

// --- Lab text exports: Bluehill CSV, MTS TestSuite CSV ---------------------

/// `init` on a bare folder, then only the current filled in, as a lab
/// would; the manifest it wrote and the loaded data set.
fn init_then_load(name: &str, file: &str) -> (String, Dataset) {
    let dir = bare(name, file);
    let text = mre_host::dataset::init::manifest_for(dir.path(), None, Some("lab")).unwrap();
    let filled = text.replace(
        &format!("file = \"{file}\""),
        &format!("file = \"{file}\"\ncurrent_a = 0.0"),
    );
    assert_ne!(filled, text, "{text}");
    std::fs::write(dir.path().join("dataset.toml"), &filled).unwrap();
    let ds = Dataset::load(dir.path()).unwrap();
    (text, ds)
}

/// Real artifact: an Instron Bluehill raw-data export (pymechtest's test
/// data, CRLF): 8 result lines and a blank line above `Time, Extension,
/// Load, Tensile strain (Strain 1), Tensile stress` over `(s),(mm),(N),(%),
/// (MPa)` (lines 10–11), quoted values, loads of 1000 N and more written
/// with digit grouping (`"3,802.00708"`). Data lines 12–290: 279 rows, as
/// pymechtest's own test counts them.
#[test]
fn bluehill_export_with_digit_grouping_loads_after_init_with_only_the_current() {
    let name = "bluehill_pymechtest_tens_yield_1.csv";
    let (manifest, ds) = init_then_load(name, "Specimen_RawData_1.csv");
    assert!(
        manifest.contains(r#"columns = ["time_s", "displacement_mm", "force_n", "ignore", "ignore"]"#),
        "{manifest}"
    );
    let rec = &ds.recordings[0];
    let s = &rec.samples;
    assert_eq!(s.len(), 279);
    // Line 12: "0.00000","0.00319","499.71045",…
    assert!(close(s.time_s[0], 0.0, 1e-12) && close(s.x_mm[0], 0.00319, 1e-12));
    assert!(close(s.force_n[0], 499.71045, 1e-9));
    // Line 290: "46.46200","0.45269","2,252.98486",…
    assert!(close(s.time_s[278], 46.462, 1e-9) && close(s.force_n[278], 2252.98486, 1e-9));
    // Line 281 holds the peak, "3,802.00708" N at 46.332 s (awk over lines
    // 12–290). The file's own results agree: 188.43817 MPa at tensile
    // strength over 1.989 mm × 10.144 mm (lines 5–7) is 3801.99 N.
    let (k, peak) = largest(&s.force_n);
    assert!(
        close(peak, 3802.00708, 1e-9) && close(s.time_s[k], 46.332, 1e-9),
        "{peak} at {k}"
    );
    assert!(close(peak, 188.43817 * 1.989 * 10.144, 0.1));
    // The reader says what it skipped (lines 1–8, 10, 11; line 9 is blank).
    let notes = rec.notes.join(" | ");
    assert!(
        notes.contains("10 row(s) above the first data row skipped (lines 1–11"),
        "{notes}"
    );
}

/// The same Bluehill file without `columns`: the names and the units row
/// are found under the results lines, strain and stress are ignored, and
/// the notes say so.
#[test]
fn bluehill_export_loads_without_columns_and_notes_what_it_ignored() {
    let ds = load("bluehill_pymechtest_tens_yield_1.csv", "b.csv", "").unwrap();
    let rec = &ds.recordings[0];
    assert_eq!(rec.samples.len(), 279);
    assert!(close(rec.samples.force_n[269], 3802.00708, 1e-9));
    let notes = rec.notes.join(" | ");
    assert!(
        notes.contains("8 line(s) above the column names (line 10) skipped"),
        "{notes}"
    );
    assert!(notes.contains("the units row (line 11) read with the names"), "{notes}");
    assert!(
        notes.contains("channels not read (ignored): `Tensile strain (Strain 1) (%)`, `Tensile stress (MPa)`"),
        "{notes}"
    );
}

/// Real artifact: an Instron Bluehill 2.0 raw-data export of a cyclic
/// compression test (the example data of the R package bluer, CC0; CRLF):
/// `Text Inputs : Specimen label,"22L.3"` and `General : Start Date,…` over a
/// blank line, then `Time,Extension,Load,Segment ID,Total Cycle Count`
/// (line 4) over `(sec),(mm),(N),,` (line 5: the counters have empty units);
/// data lines 6–18016, 18 011 rows over three cycles. Compression reads
/// negative in both load and extension (the crosshead moves down 10 mm, the
/// load falls to -53 N): init flips both and says so, and the manifest
/// loads once the current is filled in.
#[test]
fn bluehill_cyclic_compression_export_is_flipped_by_init_and_loads() {
    let (manifest, ds) = init_then_load("bluehill_bluer_vero_clear_ccyclic_6.csv", "Specimen_RawData_6.csv");
    assert!(
        manifest.contains(r#"columns = ["time_s", "displacement_mm", "force_n", "ignore", "ignore"]"#),
        "{manifest}"
    );
    assert!(
        manifest.contains("sign = { force_n = -1, displacement_mm = -1 }"),
        "{manifest}"
    );
    let s = &ds.recordings[0].samples;
    assert_eq!(s.len(), 18_011);
    // Line 6: 0.00000,-2.04726,-4.31900,22476,0 (flipped).
    assert!(close(s.time_s[0], 0.0, 1e-12) && close(s.x_mm[0], 2.04726, 1e-12));
    assert!(close(s.force_n[0], 4.319, 1e-12));
    // Line 18016: 360.06000,-2.04555,0.28068,22412,2.
    assert!(close(s.time_s[18_010], 360.06, 1e-9) && close(s.force_n[18_010], -0.28068, 1e-12));
    // Line 3006 holds the largest compression, -52.97507 N at 59.98 s and
    // -12.04026 mm (a script over lines 6–18016).
    let (k, peak) = largest(&s.force_n);
    assert!(close(peak, 52.97507, 1e-9) && k == 3000, "{peak} at {k}");
    assert!(close(s.time_s[k], 59.98, 1e-9) && close(s.x_mm[k], 12.04026, 1e-9));
}

/// Real artifact: an MTS TestSuite export in a German locale (BAM's
/// E-modulus test, UTF-8 with a byte-order mark): `;`, quoted fields,
/// decimal commas (`-7,89761571695635E-05` too), four preamble lines and two
/// empty ones, names `Zeit; Laufzeit; Ch 1 Kraft Sollwert; Ch 1 Kraft; Ch 1
/// Weg; …` (line 7) over a bare units row `sec; sec; kN; kN; mm; …` (line 8),
/// data lines 9–958 (950 rows). Two clocks: the first is the time. It reads
/// compression negative; init flips force and stroke and says so.
#[test]
fn mts_testsuite_semicolon_export_loads_after_init_with_only_the_current() {
    let (manifest, ds) = init_then_load("mts_testsuite_deu_emodul_run3.csv", "run3.csv");
    assert!(manifest.contains("delimiter = \";\""), "{manifest}");
    assert!(
        manifest.contains("column `Laufzeit sec` is a second clock: ignored (time is column 1, `Zeit sec`)"),
        "{manifest}"
    );
    assert!(
        manifest.contains("sign = { force_kn = -1, displacement_mm = -1 }"),
        "{manifest}"
    );
    let s = &ds.recordings[0].samples;
    assert_eq!(s.len(), 950);
    // Line 9: "159,8212890625"; …; "-40,41028125" (Ch 1 Kraft, kN); "-0,00757277030061232" (mm).
    assert!(close(s.time_s[0], 159.8212890625, 1e-12));
    assert!(close(s.force_n[0], 40_410.281_25, 1e-6), "{}", s.force_n[0]);
    assert!(close(s.x_mm[0], 0.00757277030061232, 1e-15));
    // Line 958: "349,806640625"; …; "-40,343453125"; "-0,0145405529110576".
    assert!(close(s.time_s[949], 349.806640625, 1e-12));
    assert!(close(s.force_n[949], 40_343.453_125, 1e-6));
    assert!(close(s.x_mm[949], 0.0145405529110576, 1e-15));
    // Line 138 holds the largest load, -134,766296875 kN at 185,646484375 s
    // (awk over lines 9–958).
    let (k, peak) = largest(&s.force_n);
    assert!(close(peak, 134_766.296_875, 1e-6) && k == 129, "{peak} at {k}");
}

/// The same TestSuite file loaded with no manifest columns: the header is
/// found under the preamble, `Laufzeit` is a second clock, and the command
/// (`Ch 1 Kraft Sollwert`) and extensometers are not read, all noted.
#[test]
fn mts_testsuite_export_loads_without_columns() {
    let ds = load(
        "mts_testsuite_deu_emodul_run3.csv",
        "run3.csv",
        "delimiter = \";\"\nsign = { force_kn = -1, displacement_mm = -1 }",
    )
    .unwrap();
    let rec = &ds.recordings[0];
    assert_eq!(rec.samples.len(), 950);
    assert!(close(rec.samples.force_n[129], 134_766.296_875, 1e-6));
    let notes = rec.notes.join(" | ");
    assert!(notes.contains("`Laufzeit (sec)` (a second clock)"), "{notes}");
    assert!(notes.contains("`Ch 1 Kraft Sollwert (kN)`"), "{notes}");
}

// --- Recording notes reach the reports ---------------------------------------

/// The real Bluehill export in a folder with the manifest `mre dataset init`
/// writes for it, only the current filled in (as a lab would).
fn bluehill_after_init() -> tempfile::TempDir {
    let dir = bare("bluehill_pymechtest_tens_yield_1.csv", "Specimen_RawData_1.csv");
    let text = mre_host::dataset::init::manifest_for(dir.path(), None, Some("lab")).unwrap();
    let text = text.replace(
        "file = \"Specimen_RawData_1.csv\"",
        "file = \"Specimen_RawData_1.csv\"\ncurrent_a = 0.0",
    );
    std::fs::write(dir.path().join("dataset.toml"), text).unwrap();
    dir
}

/// Real artifact (the Bluehill export above): what its reader assumed
/// reaches where a user reads about the data set: `mre dataset check`
/// prints it per recording, and the validation report (report.md and
/// report.json) carries it.
#[test]
fn reading_notes_reach_dataset_check_and_the_validation_report() {
    let dir = bluehill_after_init();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mre"))
        .args(["dataset", "check"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let printed = String::from_utf8(out.stdout).unwrap();
    // 279 rows, lines 12–290 of the file (by hand).
    assert!(
        printed.contains("| Specimen_RawData_1.csv | 0 | fit | 279 |"),
        "{printed}"
    );
    assert!(printed.contains("## Reading notes"), "{printed}");
    assert!(
        printed.contains("- `Specimen_RawData_1.csv`:\n  - 10 row(s) above the first data row skipped (lines 1–11"),
        "{printed}"
    );

    let ds = Dataset::load(dir.path()).unwrap();
    let table = mre_algorithm::table::Table::paper().unwrap();
    let report = mre_host::validate::validate(&ds, &table, "paper");
    let md = mre_host::validate::report::markdown(&report);
    assert!(
        md.contains("- `Specimen_RawData_1.csv`: 10 row(s) above the first data row skipped (lines 1–11"),
        "{md}"
    );
    let out = tempfile::tempdir().unwrap();
    mre_host::validate::report::write(out.path(), &report).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("report.json")).unwrap()).unwrap();
    let notes = json["recordings"][0]["reading_notes"].as_array().unwrap();
    assert!(notes[0]
        .as_str()
        .unwrap()
        .starts_with("10 row(s) above the first data row skipped"));
}

/// Real artifact (the Bluehill export above): the validation's HTML page
/// (`index.html`, rendered from report.md) shows the reading notes per
/// recording, as HTML: the file name as code, the note as text. The note's
/// lines 1–11 are the file's own (metadata, names, units; counted by hand).
#[test]
fn reading_notes_reach_the_validation_html_page() {
    let dir = bluehill_after_init();
    let out = tempfile::tempdir().unwrap();
    mre_host::validate::run_validate(dir.path(), "paper", &[], out.path()).unwrap();
    let html = std::fs::read_to_string(out.path().join("index.html")).unwrap();
    assert!(html.contains("<p>Reading notes: what the readers assumed"), "{html}");
    assert!(
        html.contains(
            "<li><code>Specimen_RawData_1.csv</code>: 10 row(s) above the first data row skipped (lines 1–11"
        ),
        "{html}"
    );
}

/// The TestSuite file with its two force channels renamed (`Ch 1 Kraft` →
/// `Ch 1 Foo` on line 7; one stated change): `init` refuses it, naming the
/// line the names are on as an editor counts it (BOM, 4 preamble lines and
/// 2 empty ones above), and writes no manifest.
#[test]
fn init_names_the_physical_line_of_the_names_it_cannot_read() {
    let dir = bare("mts_testsuite_deu_emodul_run3.csv", "run3.csv");
    let text = std::fs::read_to_string(dir.path().join("run3.csv")).unwrap();
    let changed = text.replacen(
        "\"Ch 1 Kraft Sollwert \";\"Ch 1 Kraft \"",
        "\"Ch 1 Foo Sollwert \";\"Ch 1 Foo \"",
        1,
    );
    assert_ne!(changed, text);
    std::fs::write(dir.path().join("run3.csv"), changed).unwrap();
    let e = mre_host::dataset::init::manifest_for(dir.path(), None, Some("x"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("run3.csv: line 7: missing required column for force"), "{e}");
    assert!(!dir.path().join("dataset.toml").exists());
}
