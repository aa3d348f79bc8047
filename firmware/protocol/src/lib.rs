//! The wire and flash protocol: the 24-byte PIL/upload frames (`frame`), the
//! table upload receiver and its commit answers (`upload`), and the flash
//! page codec of an uploaded table (`flash_table`). The board and the host
//! tools (`mre pil`, `mre upload`) link the same code.
//!
//! May not: touch hardware, allocate, panic, or hold `unsafe` code (a board
//! implements `flash_table::TablePage`). Depends on the algorithm only (the
//! table a page carries, the control configuration a blob carries, the
//! board's hard limits, the controller's at-rest gate), not on the runtime:
//! the host tools link it without the board's runtime. Nothing depends on it
//! but the image, the host tools and their FMUs, fuzz and the tests. Its
//! modules import one way: `upload` → `flash_table` → `frame`.
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]
// Integer arithmetic says what happens at its edge (checked, saturating or
// wrapping): no overflow panic in a debug build, no silent wrap in release.
#![deny(clippy::arithmetic_side_effects)]

pub mod flash_table;
pub mod frame;
pub mod upload;
