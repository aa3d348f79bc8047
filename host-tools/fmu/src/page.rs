//! `resources/table.page`: the table and the control configuration as the
//! board's flash page holds them.
use mre_algorithm::control::ControlConfig;
use mre_algorithm::Table;
use mre_protocol::flash_table::{self, RamPage, PAGE_BYTES};
use std::path::Path;

/// The resource file both FMUs read.
pub const PAGE_FILE: &str = "table.page";

/// The page the board would store for `table` and `cfg`.
pub fn page_bytes(table: &Table, cfg: &ControlConfig) -> Result<Vec<u8>, String> {
    let mut page = RamPage::erased();
    flash_table::store(&mut page, table, cfg)
        .map_err(|e| format!("the table cannot be stored as a flash page: {}", e.as_str()))?;
    Ok(page.bytes.to_vec())
}

/// Reads `resources/table.page` through the core's loader.
pub fn load(resource_dir: &Path) -> Result<(Table, ControlConfig), String> {
    let path = resource_dir.join(PAGE_FILE);
    let bytes = std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let bytes: [u8; PAGE_BYTES] = bytes.try_into().map_err(|b: Vec<u8>| {
        format!(
            "{} holds {} bytes, not a {PAGE_BYTES}-byte flash page",
            path.display(),
            b.len()
        )
    })?;
    flash_table::load(&mut RamPage { bytes })
        .map_err(|e| format!("{} was refused by the board's loader: {}", path.display(), e.as_str()))
}
