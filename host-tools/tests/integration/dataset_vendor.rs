//! Vendor exports (docs/dataset-format.md, vendor layouts): MTS 793
//! Specimen.dat, LabVIEW .lvm and NI TDMS files, laid out from each vendor's
//! format description (tests/fixtures/vendor/README.md), load with their
//! units converted and their sign checked; malformed and truncated copies
//! get one clear error sentence, never a panic and never part of the record.
//!
//! Every fixture holds the same drop: 41 samples 0.1 ms apart, peak force
//! 2 kN and peak stroke 5 mm at sample 20 (t = 2 ms). The expected values
//! below come from that description, not from the readers.
use mre_host::dataset::read::parse_recording;
use mre_host::dataset::{Dataset, DatasetError};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/vendor")
        .join(name)
}

/// A folder holding `file` (with `bytes`) and a manifest with `settings`
/// for it (an impact test: mass and impact velocity set).
fn folder(file: &str, bytes: &[u8], settings: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(file), bytes).unwrap();
    let manifest = format!(
        "name = \"vendor\"\n[defaults]\nmass_kg = 5.5\nimpact_velocity_m_s = 2.24\n\n\
         [[recording]]\nfile = \"{file}\"\ncurrent_a = 1.0\n{settings}\n"
    );
    std::fs::write(dir.path().join("dataset.toml"), manifest).unwrap();
    dir
}

fn load(file: &str, bytes: &[u8], settings: &str) -> Result<Dataset, DatasetError> {
    let dir = folder(file, bytes, settings);
    Dataset::load(dir.path())
}

/// The drop as the fixtures describe it, in internal units.
fn check_drop(ds: &Dataset, t0_s: f64) {
    let s = &ds.recordings[0].samples;
    assert_eq!(s.len(), 41);
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
    assert!(close(s.time_s[0], t0_s, 1e-12), "{}", s.time_s[0]);
    assert!(close(s.time_s[40], t0_s + 40.0 * 1e-4, 1e-9), "{}", s.time_s[40]);
    // 2 kN peak at sample 20 → 2000 N; 5 mm peak.
    assert!(close(s.force_n[20], 2000.0, 1e-6), "force {}", s.force_n[20]);
    assert!(close(s.x_mm[20], 5.0, 1e-6), "stroke {}", s.x_mm[20]);
    let peak = s.force_n.iter().cloned().fold(f64::MIN, f64::max);
    assert!(close(peak, 2000.0, 1e-6), "peak {peak}");
}

fn message(e: &DatasetError) -> String {
    let m = e.to_string();
    // A sentence for a person, not a Debug dump.
    assert!(
        !m.contains("{ path") && !m.contains("Error(") && !m.contains("Os {"),
        "{m}"
    );
    m
}

#[test]
fn mts_specimen_dat_loads_with_kn_converted_and_the_declared_flip() {
    let bytes = std::fs::read(fixture("drop_specimen.dat")).unwrap();
    let ds = load("Specimen.dat", &bytes, "sign = { force_kn = -1, displacement_mm = -1 }").unwrap();
    check_drop(&ds, 0.0);
}

#[test]
fn mts_compression_negative_is_refused_without_a_declaration() {
    let bytes = std::fs::read(fixture("drop_specimen.dat")).unwrap();
    let e = load("Specimen.dat", &bytes, "").unwrap_err();
    let m = message(&e);
    assert!(m.contains("looks inverted"), "{m}");
    assert!(m.contains("sign = {"), "{m}");
}

#[test]
fn lvm_reads_decimal_commas_newtons_and_meters_and_its_time_base() {
    let bytes = std::fs::read(fixture("drop.lvm")).unwrap();
    // X0 = 1 ms: the time base starts there.
    check_drop(&load("drop.lvm", &bytes, "").unwrap(), 1e-3);
}

#[test]
fn tdms_reads_both_segments_in_kn_and_mm_on_the_waveform_time_base() {
    let bytes = std::fs::read(fixture("drop.tdms")).unwrap();
    check_drop(&load("drop.tdms", &bytes, "").unwrap(), 0.0);
}

#[test]
fn columns_in_the_manifest_rename_a_vendor_files_channels() {
    // The LabVIEW file's channels renamed by hand: displacement ignored, so
    // the motion is derived from force (force–time record).
    let bytes = std::fs::read(fixture("drop.lvm")).unwrap();
    let ds = load("drop.lvm", &bytes, "columns = [\"time_s\", \"force_n\", \"ignore\"]").unwrap();
    let r = &ds.recordings[0];
    assert!(r.motion_from.is_some(), "motion derived from force");
    // Too few names for the channels: said, with the channels listed.
    let e = load("drop.lvm", &bytes, "columns = [\"time_s\", \"force_n\"]").unwrap_err();
    let m = message(&e);
    assert!(m.contains("names 2 columns") && m.contains("Load (Newtons)"), "{m}");
}

#[test]
fn unknown_channels_ask_for_columns() {
    // An unknown channel is ignored; when it was the only force, the file
    // cannot load and the message lists the channels and the names accepted.
    let text = std::fs::read_to_string(fixture("drop_specimen.dat")).unwrap();
    let text = text.replace("Axial Force", "Strain Gauge 3");
    let e = load("Specimen.dat", text.as_bytes(), "").unwrap_err();
    let m = message(&e);
    assert!(m.contains("Strain Gauge 3 (kN)") && m.contains("columns = ["), "{m}");
    assert!(m.contains("no force channel") && m.contains("force_kn"), "{m}");
}

#[test]
fn mts_buffers_with_other_channels_are_another_record_and_the_longest_is_read() {
    // The second buffer (21 rows) renames a channel: two records, 20 and 21
    // rows; the longer is read, the shorter skipped.
    let text = std::fs::read_to_string(fixture("drop_specimen.dat")).unwrap();
    let bad = text
        .replacen("Axial Force\t", "Axial Load\t", 2)
        .replacen("Axial Load\t", "Axial Force\t", 1);
    assert_ne!(bad, text);
    let samples = parse_recording(bad.as_bytes(), false, "Specimen.dat").unwrap();
    assert_eq!(samples.len(), 21);
}

#[test]
fn malformed_mts_files_get_a_sentence() {
    let text = std::fs::read_to_string(fixture("drop_specimen.dat")).unwrap();
    let cases = [
        (
            text.replacen("MTS793|MPT|ENU|1|2|", "MTS793|MPT|ENU|1|0|", 1),
            "Plain (space-delimited)",
        ),
        (text.replacen("Sec\tmm\tkN\t\r\n", "", 1), "channel names and"),
        (text.replacen("0.0005\t", "0.0005x\t", 1), "0.0005x"),
        (text.replacen("|.|", "|\t|", 1), "decimal separator"),
    ];
    for (bad, expected) in cases {
        assert_ne!(bad, text, "the case changes the file");
        let e = load(
            "Specimen.dat",
            bad.as_bytes(),
            "sign = { force_n = -1, displacement_mm = -1 }",
        )
        .unwrap_err();
        let m = message(&e);
        assert!(m.contains(expected), "expected `{expected}` in: {m}");
    }
}

#[test]
fn malformed_lvm_files_get_a_sentence() {
    let text = std::fs::read_to_string(fixture("drop.lvm")).unwrap();
    let cases = [
        (
            text.replacen("X_Dimension\tTime\tTime", "X_Dimension\tFrequency\tFrequency", 1),
            "X_Dimension `Frequency`",
        ),
        (
            text.replacen(
                "Delta_X\t1,000000E-4\t1,000000E-4",
                "Delta_X\t1,000000E-4\t2,000000E-4",
                1,
            ),
            "Delta_X",
        ),
        (text.replacen("X_Columns\tNo", "X_Columns\tSome", 1), "X_Columns `Some`"),
        (text.replacen("\t156,918191\t", "\t156;918191\t", 1), "156;918191"),
        (
            text.replacen("Samples\t41\t41", "Samples\t42\t42", 1),
            "declares 42 samples but holds 41",
        ),
    ];
    for (bad, expected) in cases {
        assert_ne!(bad, text, "the case changes the file");
        let m = message(&load("drop.lvm", bad.as_bytes(), "").unwrap_err());
        assert!(m.contains(expected), "expected `{expected}` in: {m}");
    }
}

#[test]
fn tdms_files_the_reader_cannot_take_whole_are_refused() {
    let bytes = std::fs::read(fixture("drop.tdms")).unwrap();
    let with_toc = |toc_bit: u32| {
        let mut b = bytes.clone();
        let toc = u32::from_le_bytes([b[4], b[5], b[6], b[7]]) | toc_bit;
        b[4..8].copy_from_slice(&toc.to_le_bytes());
        b
    };
    // The first segment's raw data written twice (two chunks): the crate
    // would read one and lose the other.
    let first_end = 28 + u64::from_le_bytes(bytes[12..20].try_into().unwrap()) as usize;
    let raw_start = 28 + u64::from_le_bytes(bytes[20..28].try_into().unwrap()) as usize;
    let mut two_chunks = bytes[..first_end].to_vec();
    two_chunks.extend_from_slice(&bytes[raw_start..first_end]);
    let next = (first_end - 28 + (first_end - raw_start)) as u64;
    two_chunks[12..20].copy_from_slice(&next.to_le_bytes());
    two_chunks.extend_from_slice(&bytes[first_end..]);
    // A value count no file can hold (the Force channel's, after its path,
    // raw-index length, type and dimension).
    let path = b"/'Drop'/'Force'";
    let at = bytes.windows(path.len()).position(|w| w == path).unwrap() + path.len() + 12;
    let mut huge_count = bytes.clone();
    huge_count[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    let cases = [
        (two_chunks, "account for"),
        (huge_count, "corrupt TDMS header"),
        (with_toc(1 << 5), "interleaved"),
        (with_toc(1 << 6), "big-endian"),
        (with_toc(1 << 7), "DAQmx"),
        (bytes[..bytes.len() - 8].to_vec(), "cut short"),
        (bytes[..20].to_vec(), "cut short in the lead-in"),
    ];
    for (bad, expected) in cases {
        let m = message(&load("drop.tdms", &bad, "").unwrap_err());
        assert!(m.contains(expected), "expected `{expected}` in: {m}");
    }
}

/// Cut at every byte, a file loads whole or not at all: an error, or a
/// record that is the start of the full one, sample for sample, where the
/// cut leaves a complete shorter file (MTS, which states no sample count, cut
/// at a line end; TDMS cut between segments). Never a panic.
#[test]
fn truncated_files_never_load_in_part() {
    for (name, settings) in [
        ("drop_specimen.dat", "sign = { force_n = -1, displacement_mm = -1 }"),
        ("drop.lvm", ""),
        ("drop.tdms", ""),
    ] {
        let bytes = std::fs::read(fixture(name)).unwrap();
        let full = load(name, &bytes, settings).unwrap().recordings.remove(0).samples;
        let dir = folder(name, &bytes, settings);
        // Where a cut leaves a complete file: line ends (MTS); the end of the
        // first TDMS segment (lead-in + its next-segment offset, bytes 12..20).
        let complete = |cut: usize| match name {
            "drop_specimen.dat" => bytes[..cut].ends_with(b"\n"),
            "drop.tdms" => {
                let next = u64::from_le_bytes(bytes[12..20].try_into().unwrap());
                cut as u64 == 28 + next
            }
            _ => false,
        };
        let mut loaded_short = 0;
        for cut in 0..bytes.len() {
            std::fs::write(dir.path().join(name), &bytes[..cut]).unwrap();
            match Dataset::load(dir.path()) {
                Err(e) => {
                    message(&e);
                }
                Ok(ds) => {
                    let s = &ds.recordings[0].samples;
                    let n = s.len();
                    assert!(complete(cut), "{name} cut at {cut} loaded {n} samples");
                    assert_eq!(s.time_s[..], full.time_s[..n], "{name} cut at {cut}");
                    assert_eq!(s.force_n[..], full.force_n[..n], "{name} cut at {cut}");
                    assert_eq!(s.x_mm[..], full.x_mm[..n], "{name} cut at {cut}");
                    loaded_short += 1;
                }
            }
        }
        if name != "drop.lvm" {
            assert!(loaded_short > 0, "{name}: a complete shorter file loads");
        }
    }
}

#[test]
fn the_bytes_entry_point_reads_vendor_files_too() {
    // What the fuzz target calls: the same dispatch as Dataset::load.
    let bytes = std::fs::read(fixture("drop.lvm")).unwrap();
    let s = parse_recording(&bytes, false, "drop.lvm").unwrap();
    assert_eq!(s.len(), 41);
    let e = parse_recording(&bytes[..bytes.len() / 2], false, "drop.lvm").unwrap_err();
    message(&e);
}

#[test]
fn dataset_init_recognises_each_vendor_file() {
    for (name, current) in [("drop_specimen.dat", "1x0"), ("drop.lvm", "1x5"), ("drop.tdms", "2x0")] {
        let dir = tempfile::tempdir().unwrap();
        let ext = Path::new(name).extension().unwrap().to_string_lossy();
        let file = format!("drop{current}A.{ext}");
        std::fs::copy(fixture(name), dir.path().join(&file)).unwrap();
        let toml = mre_host::dataset::init::manifest_for(dir.path(), Some("drop{current_a}A"), None).unwrap();
        assert!(toml.contains("(names and units from the file)"), "{toml}");
        if name.ends_with(".dat") {
            // MTS reads compression negative: the flip is written, as an assumption.
            assert!(
                toml.contains("sign = { force_kn = -1, displacement_mm = -1 }"),
                "{toml}"
            );
            assert!(toml.contains("# assumed:"), "{toml}");
            // The evidence in N: the mean of 2000·sin(πk/40) N over the
            // loading branch k = 0..20 is 1259.60 N (as written, 5 decimals of kN).
            assert!(toml.contains("is -1259.60"), "{toml}");
        } else {
            assert!(!toml.contains("sign ="), "{toml}");
        }
        // What init wrote loads, given the drop's mass and velocity.
        let toml = toml.replace("[defaults]", "[defaults]\nmass_kg = 5.5\nimpact_velocity_m_s = 2.24");
        let ds = Dataset::from_manifest(dir.path(), &toml).unwrap_or_else(|e| panic!("{name}: {e}\n{toml}"));
        check_drop(&ds, if name.ends_with(".lvm") { 1e-3 } else { 0.0 });
    }
}

/// The fuzz target's seeds (fuzz/seeds/dataset_reader) replayed through its
/// entry point with its promises: the vendor seeds read whole.
#[test]
fn fuzz_seeds_hold_the_readers_promises() {
    let seeds = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/seeds/dataset_reader");
    let mut vendor_seeds = 0;
    for entry in std::fs::read_dir(&seeds).unwrap() {
        let path = entry.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        let name = path.to_string_lossy().into_owned();
        for whitespace in [false, true] {
            if let Ok(s) = parse_recording(&bytes, whitespace, &name) {
                let n = s.len();
                assert!(n >= mre_host::dataset::read::MIN_SAMPLES, "{name}");
                // Force, or (an accelerometer drop record) acceleration it is derived from at load.
                assert!(
                    s.force_n.len() == n
                        || (s.force_n.is_empty() && s.accel_m_s2.as_ref().is_some_and(|a| a.len() == n)),
                    "{name}"
                );
                // Motion complete, or absent (a force-only record: derived at load).
                let motion = (s.x_mm.len(), s.v_m_s.len());
                assert!(motion == (n, n) || motion == (0, 0), "{name}: motion {motion:?} of {n}");
                assert!(s.time_s.windows(2).all(|w| w[1] > w[0]), "{name}: time increases");
            }
        }
        if ["specimen.dat", "drop.lvm", "drop.tdms"]
            .iter()
            .any(|v| name.ends_with(v))
        {
            let s = parse_recording(&bytes, false, &name).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(s.len(), 41, "{name}");
            vendor_seeds += 1;
        }
    }
    assert_eq!(vendor_seeds, 3, "one seed per vendor format");
}

/// The same LabVIEW file written with X columns (`X_Columns One`: one X
/// before the channels; `Multi`: an X before each channel, "Header" in the
/// specification): time is read from the first X column.
#[test]
fn lvm_x_columns_one_and_multi_give_the_time() {
    let text = std::fs::read_to_string(fixture("drop.lvm")).unwrap();
    for mode in ["One", "Multi"] {
        let mut out = String::new();
        let (mut k, mut in_data) = (0, false);
        for line in text.split_inclusive("\r\n") {
            let body = line.trim_end_matches("\r\n");
            if body == "X_Columns\tNo" {
                out.push_str(&format!("X_Columns\t{mode}\r\n"));
            } else if body == "X_Value\tLoad\tDisplacement\tComment" {
                in_data = true;
                out.push_str(match mode {
                    "One" => line,
                    _ => "X_Value\tLoad\tX_Value\tDisplacement\tComment\r\n",
                });
            } else if let Some(values) = body.strip_prefix('\t').filter(|_| in_data) {
                // 1 ms + k·0.1 ms, written with the file's decimal comma.
                let t = format!("{:.6}", 1e-3 + k as f64 * 1e-4).replace('.', ",");
                let (load, disp) = values.split_once('\t').unwrap();
                let row = match mode {
                    "One" => format!("{t}\t{load}\t{disp}"),
                    _ => format!("{t}\t{load}\t{t}\t{disp}"),
                };
                out.push_str(&row);
                out.push_str("\r\n");
                k += 1;
            } else {
                out.push_str(line);
            }
        }
        assert_eq!(k, 41);
        let ds = load("drop.lvm", out.as_bytes(), "").unwrap_or_else(|e| panic!("{mode}: {e}"));
        check_drop(&ds, 1e-3);
    }
}

/// One folder holding a Bluehill-style CSV with `columns` in `[defaults]`
/// and the three vendor files: each vendor recording names its own columns,
/// so the defaults' do not apply to it, and all load.
#[test]
fn dataset_init_keeps_vendor_columns_apart_from_the_defaults() {
    let dir = tempfile::tempdir().unwrap();
    for (name, current) in [("drop_specimen.dat", "1x0"), ("drop.lvm", "1x5"), ("drop.tdms", "2x0")] {
        let ext = Path::new(name).extension().unwrap().to_string_lossy();
        std::fs::copy(fixture(name), dir.path().join(format!("drop{current}A.{ext}"))).unwrap();
    }
    let mut csv = String::from("Time (ms),Force (kN),Displacement (mm)\n");
    for k in 0..41 {
        let s = (std::f64::consts::PI * k as f64 / 40.0).sin();
        csv.push_str(&format!("{},{},{}\n", k as f64 * 0.1, 2.0 * s, 5.0 * s));
    }
    std::fs::write(dir.path().join("drop0x5A.csv"), csv).unwrap();
    let toml = mre_host::dataset::init::manifest_for(dir.path(), Some("drop{current_a}A"), None).unwrap();
    let defaults = &toml[toml.find("[defaults]").unwrap()..toml.find("[[recording]]").unwrap()];
    assert!(
        defaults.contains("columns = [\"time_ms\", \"force_kn\", \"displacement_mm\"]"),
        "{toml}"
    );
    assert!(!defaults.contains("MTS") && !defaults.contains("LabVIEW"), "{toml}");
    let toml = toml.replace("[defaults]", "[defaults]\nmass_kg = 5.5\nimpact_velocity_m_s = 2.24");
    let ds = Dataset::from_manifest(dir.path(), &toml).unwrap_or_else(|e| panic!("{e}\n{toml}"));
    assert_eq!(ds.recordings.len(), 4);
    for r in &ds.recordings {
        let peak = r.samples.force_n.iter().cloned().fold(f64::MIN, f64::max);
        assert!((peak - 2000.0).abs() < 1e-6, "{}: peak {peak}", r.file);
    }
}
