//! The MRE damper runtime (`mre_core`): one control period over I/O traits
//! (`control`), fault latching, over-current and sense monitoring, boot
//! decisions and the power-on self-test, watchdog check-ins, calibration,
//! pacing and the status LED's codes; the board's hard limits. The frames,
//! the upload receiver and the table page codec are the protocol crate's
//! (`mre_protocol`), which depends on this one.
//!
//! May not: touch hardware or registers, allocate, panic, or hold `unsafe`
//! code; a board implements the I/O traits. Depends on the algorithm
//! (`mre_algorithm`, re-exported under its old paths: `mre_core::table`, ...)
//! and on no board. The board image and the host tools link it, so the host
//! runs the board's code.
#![cfg_attr(not(test), no_std)]
// Pure logic: unsafe code belongs to the board layer (firmware/src/board/).
#![forbid(unsafe_code)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]
// Integer arithmetic says what happens at its edge (checked, saturating or
// wrapping): no overflow panic in a debug build, no silent wrap in release.
// Float arithmetic is not linted (IEEE: no panics).
#![deny(clippy::arithmetic_side_effects)]

pub mod boot;
pub mod calibration;
pub mod control;
// The table the image flies, written by `mre tables` beside the image
// (firmware/src/generated_table.rs).
#[path = "../../src/generated_table.rs"]
pub mod generated_table;
pub mod limits;
pub mod overcurrent;
pub mod pacing;
pub mod status;
pub mod watchdog;

// The algorithm (issue 40): its modules under their old paths, so
// `mre_core::table` and `crate::law` keep naming the same items.
pub use mre_algorithm::{arming, estimate, flags, installation, inverse, law, math, model, order, saturation, table};
pub use mre_algorithm::{Branch, CurrentEntry, Flags, Quartic, Table, TableError};
