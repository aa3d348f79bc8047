//! The committed flash table (`firmware/src/generated_table.rs`) must be what
//! `mre tables` generates from the committed model (`models/mr-damper-mts.toml`).
use mre_core::table::Table;
use mre_host::table_file::read_table_file;
use mre_host::tables::generate_table_source;
use std::path::Path;

const MODEL: &str = "models/mr-damper-mts.toml";

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

#[test]
fn committed_generated_table_matches_the_committed_model() {
    let table = read_table_file(&root().join(MODEL)).unwrap();
    let generated = generate_table_source(MODEL, &table);
    let committed = include_str!("../../firmware/src/generated_table.rs");
    assert!(
        generated == committed,
        "firmware/src/generated_table.rs is stale: run `cargo run --release -p host-tools -- tables {MODEL}`"
    );
}

#[test]
fn generated_image_validates_and_equals_the_model() {
    let from_flash = Table::from_image(&mre_core::generated_table::GENERATED_TABLE).unwrap();
    let from_model = read_table_file(&root().join(MODEL)).unwrap();
    assert_eq!(from_flash, from_model);
    assert_eq!(from_flash.entries().len(), 3);
}

#[test]
fn corrupting_the_image_is_caught_by_its_crc() {
    let mut entries = mre_core::generated_table::GENERATED_ENTRIES;
    entries[1].extension.coeffs[2] += 1.0;
    let image = mre_core::table::TableImage {
        entries: &entries,
        ..mre_core::generated_table::GENERATED_TABLE
    };
    assert!(matches!(
        Table::from_image(&image),
        Err(mre_core::TableError::CrcMismatch { .. })
    ));
}

#[test]
fn paper_table_generates_source_with_its_known_crc() {
    // The paper table's CRC is computed by the core at compile time; the
    // generator must print the same value.
    let paper = Table::paper().unwrap();
    let src = generate_table_source("paper", &paper);
    assert!(src.contains(&format!("crc32: {:#010x},", mre_core::table::PAPER_TABLE4.crc32)));
    assert!(src.contains("current_a: 2.0,"));
    assert!(src.contains("compression: Quartic::new([-6619.6, 19772.0, -24021.0, 19016.0, -105.53]),"));
}
