//! The committed flash table (`firmware/src/generated_table.rs`) must be what
//! `mre tables` generates from the committed model (`models/drop-full-stroke.toml`),
//! and that model must be what `mre fit` makes of the bundled drop tests.
use mre_algorithm::table::Table;
use mre_host::table_file::{read_dataset_sha256, read_flash_table, read_table_file};
use mre_host::tables::generate_table_source;
use std::path::Path;

const MODEL: &str = "models/drop-full-stroke.toml";
const DATASET: &str = "data/drop-full-stroke";

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

#[test]
fn committed_generated_table_matches_the_committed_model() {
    let (table, source) = read_flash_table(&root().join(MODEL)).unwrap();
    let sha = read_dataset_sha256(&root().join(MODEL)).unwrap();
    let generated = generate_table_source(MODEL, &table, sha.as_deref(), Some(source));
    let committed = include_str!("../../../firmware/src/generated_table.rs");
    assert!(
        generated == committed,
        "firmware/src/generated_table.rs is stale: run `cargo run --release -p host-tools -- tables {MODEL}`"
    );
}

#[test]
fn generated_image_validates_and_equals_the_model() {
    let from_flash = Table::from_image(&mre_algorithm::generated_table::GENERATED_TABLE).unwrap();
    let (from_model, _) = read_flash_table(&root().join(MODEL)).unwrap();
    assert_eq!(from_flash, from_model);
    // The model's entries and terms, carried in format 3 with its installation.
    let fitted = read_table_file(&root().join(MODEL)).unwrap();
    assert_eq!(
        (from_flash.entries(), from_flash.terms()),
        (fitted.entries(), fitted.terms())
    );
    assert_eq!(from_flash.version(), 3);
    // The drop tests' five fit currents, 0–2 A.
    assert_eq!(from_flash.current_range_a(), (0.0, 2.0));
    assert_eq!(from_flash.entries().len(), 5);
}

#[test]
fn committed_model_is_the_fit_of_the_bundled_drop_tests() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("model.toml");
    let options = mre_host::fit::FitOptions {
        method: mre_host::fit::Method::Lsq,
        ..Default::default()
    };
    mre_host::fit::run_fit(&root().join(DATASET), &options, &[], &out).unwrap();
    // The fit now writes its installation (the set's 5.5 kg, the defaults
    // for the rest: the default installation); the committed file predates
    // the section and flies the defaults.
    assert_eq!(
        read_table_file(&out).unwrap(),
        read_table_file(&root().join(MODEL))
            .unwrap()
            .carrying(mre_algorithm::installation::DEFAULT_INSTALLATION)
            .unwrap()
    );
    // The flash image names the data set it came from.
    assert_eq!(
        read_dataset_sha256(&out).unwrap().as_deref(),
        Some(mre_algorithm::generated_table::SOURCE_DATASET_SHA256)
    );
}

#[test]
fn generated_table_covers_the_usable_stroke() {
    // The full-stroke campaign drops every current hard enough to reach
    // 15 mm (data/generate.sh), so every entry's quartic covers the 12 mm
    // usable stroke the law plans over: no entry is clamped inside it.
    let t = Table::from_image(&mre_algorithm::generated_table::GENERATED_TABLE).unwrap();
    for e in t.entries() {
        assert!(e.x_max_mm >= 12.0, "{} A covers only {} mm", e.current_a, e.x_max_mm);
    }
    assert!(t.entries().iter().all(|e| e.x_min_mm <= 0.0));
}

#[test]
fn corrupting_the_image_is_caught_by_its_crc() {
    let mut entries = mre_algorithm::generated_table::GENERATED_ENTRIES;
    entries[1].extension.coeffs[2] += 1.0;
    let image = mre_algorithm::table::TableImage {
        entries: &entries,
        ..mre_algorithm::generated_table::GENERATED_TABLE
    };
    assert!(matches!(
        Table::from_image(&image),
        Err(mre_algorithm::TableError::CrcMismatch { .. })
    ));
}

#[test]
fn paper_table_generates_source_with_its_known_crc() {
    // The paper table's CRC is computed by the core at compile time; the
    // generator must print the same value.
    let paper = Table::paper().unwrap();
    let src = generate_table_source("paper", &paper, None, None);
    assert!(src.contains(&format!("crc32: {:#010x},", mre_algorithm::table::PAPER_TABLE4.crc32)));
    assert!(src.contains("current_a: 2.0,"));
    assert!(src.contains("compression: Quartic::new([-6619.6, 19772.0, -24021.0, 19016.0, -105.53]),"));
}

#[test]
fn version_1_model_files_still_load_and_version_2_files_carry_their_terms() {
    use mre_host::table_file::{parse_table_toml, table_to_toml};
    // The real MR damper model was written before version 2.
    let v1 = read_table_file(&root().join("models/mr-damper-mts.toml")).unwrap();
    assert_eq!(v1.version(), 1);
    assert!(v1.terms().is_none());
    let v2_text = r#"
format_version = 2
[terms]
saturation_current_a = 0.8
coil_tau_s = 0.002
[[current]]
current_a = 0.0
compression = [0.0, 0.0, 0.0, 100.0, 0.0]
extension = [0.0, 0.0, 0.0, 50.0, 0.0]
x_min_mm = 0.0
x_max_mm = 12.0
viscous_n_s_per_m = 40.0
[[current]]
current_a = 2.0
compression = [0.0, 0.0, 0.0, 900.0, 0.0]
extension = [0.0, 0.0, 0.0, 450.0, 0.0]
x_min_mm = 0.0
x_max_mm = 4.0
"#;
    let t = parse_table_toml(v2_text).unwrap();
    assert_eq!(t.version(), 2);
    assert_eq!(t.terms().saturation_current_a, 0.8);
    assert_eq!(t.terms().sensor_delay_s, 0.0);
    assert_eq!(t.terms().coil_tau_s, 0.002);
    assert_eq!(t.terms().viscous_n_s_per_m[..2], [40.0, 0.0]);
    assert_eq!(parse_table_toml(&table_to_toml(&t)).unwrap(), t);
    // Terms need version 2; a version 1 file with them is an error, not ignored.
    let err = format!(
        "{:#}",
        parse_table_toml(&v2_text.replace("format_version = 2", "format_version = 1")).unwrap_err()
    );
    assert!(err.contains("format_version = 2"), "{err}");
    let err = format!(
        "{:#}",
        parse_table_toml(&v2_text.replace("0.002", "-0.002")).unwrap_err()
    );
    assert!(err.contains("coil_tau_s"), "{err}");
}

#[test]
fn mre_tables_carries_a_model_s_installation_and_refuses_one_outside_the_limits() {
    use mre_host::table_file::{table_to_toml, InstallationSource};
    use mre_host::tables::run_tables_stated;
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(root().join(MODEL)).unwrap();
    let lab = dir.path().join("lab.toml");
    std::fs::write(
        &lab,
        format!("{base}\n[installation]\nmass_kg = 3.0\nusable_stroke_mm = 9\ncoil_rating_a = 1.5\n"),
    )
    .unwrap();
    let out = dir.path().join("generated_table.rs");
    let (table, source) = run_tables_stated(&lab, &out).unwrap();
    assert_eq!(source, InstallationSource::ModelFile);
    assert_eq!(table.version(), 3);
    let i = table.installation();
    assert_eq!((i.mass_kg, i.usable_stroke_mm, i.coil_rating_a), (3.0, 9.0, 1.5));
    // Keys the file does not give keep the defaults (12 V, 4 Ω).
    assert_eq!((i.supply_v, i.coil_resistance_ohm), (12.0, 4.0));
    let src = std::fs::read_to_string(&out).unwrap();
    assert!(
        src.contains("    mass_kg: 3.0,\n    usable_stroke_mm: 9.0,\n    coil_rating_a: 1.5,"),
        "{src}"
    );
    assert!(src.contains(&format!("crc32: {:#010x},", table.crc32())));
    // The table file round-trips with its installation.
    let again = mre_host::table_file::parse_table_toml(&table_to_toml(&table)).unwrap();
    assert_eq!(again, table);

    // Without the section: the defaults, and the source says so.
    let (_, source) = run_tables_stated(&root().join(MODEL), &out).unwrap();
    assert_eq!(source, InstallationSource::Defaults);
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("DEFAULT_INSTALLATION, as the model file has no [installation]"));

    // A 3 A coil on the 2 A board: refused by name, nothing written.
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, format!("{base}\n[installation]\ncoil_rating_a = 3.0\n")).unwrap();
    let bad_out = dir.path().join("bad_table.rs");
    let err = format!("{:#}", run_tables_stated(&bad, &bad_out).unwrap_err());
    assert!(
        err.contains("[installation] coil_rating_a = 3 is outside the board's limits 1 to 2"),
        "{err}"
    );
    assert!(!bad_out.exists());
    // An unknown key is an error, not ignored.
    std::fs::write(&bad, format!("{base}\n[installation]\nmass_lb = 3.0\n")).unwrap();
    let err = format!("{:#}", run_tables_stated(&bad, &bad_out).unwrap_err());
    assert!(err.contains("unknown key `mass_lb`"), "{err}");
}
