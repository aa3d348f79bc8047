//! The MRE damper control core: pure `no_std` logic, f32, no heap, no panics.
//!
//! The firmware binary and the host tools (`mre`) both link this crate, so the
//! host simulates exactly the arithmetic that runs on the board.
//!
//! Data flow of one control period:
//! `estimate` (velocity from displacement) → `law` (target force for the impact)
//! → `inverse` (current that gives that force, via `model` and `table`) → coil.
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
pub mod flash_table;
pub mod frame;
pub mod generated_table;
pub mod limits;
pub mod overcurrent;
pub mod pacing;
pub mod status;
pub mod upload;
pub mod watchdog;

// The algorithm (issue 40): its modules under their old paths, so
// `mre_core::table` and `crate::law` keep naming the same items.
pub use mre_algorithm::{arming, estimate, flags, installation, inverse, law, math, model, order, saturation, table};
pub use mre_algorithm::{Branch, CurrentEntry, Flags, Quartic, Table, TableError};
