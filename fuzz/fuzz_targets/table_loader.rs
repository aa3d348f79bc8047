//! The table / model-file loader (`--table FILE`, `mre tables`) on arbitrary
//! text. Never a panic; a table it accepts is one the core can evaluate
//! everywhere.
#![no_main]
use libfuzzer_sys::fuzz_target;
use mre_algorithm::model::Branch;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(table) = mre_host::table_file::parse_table_toml(text) else {
        return;
    };
    let (lo, hi) = table.current_range_a();
    assert!(lo.is_finite() && hi.is_finite() && lo <= hi);
    for e in table.entries() {
        for x in [e.x_min_mm, e.x_max_mm, 0.5 * (e.x_min_mm + e.x_max_mm)] {
            for b in [Branch::Compression, Branch::Extension] {
                assert!(table.force_on_branch(x, b, e.current_a).force_n.is_finite());
                let r = table.current_for_branch(x, b, 1000.0);
                assert!(r.current_a.is_finite() && r.current_a >= lo && r.current_a <= hi);
            }
        }
    }
    // Its installation (format 3; the defaults before) is one a board can
    // have, and the image it seals reads back under its CRC.
    assert_eq!(table.installation().invalid_field(), None);
    assert_eq!(mre_algorithm::Table::from_image(&table.image()).as_ref(), Ok(&table));
    // What the loader accepts, `mre tables` can turn into flash source.
    let _ = mre_host::tables::generate_table_source("fuzz", &table, None, None);
});
