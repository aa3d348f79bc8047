//! The MRE damper runtime (`mre_runtime`): what runs around the control
//! period on a board: `io` (the sensor and coil traits a board implements,
//! one period over them, the coil's open-loop duty), `boot` (reset causes,
//! the boot plan, the power-on self-test, the coil after a panic or
//! HardFault), `calibration` (current-sense and sensor zeros), `watchdog`
//! (check-ins), `pacing` (missed periods) and `status` (the LED's codes).
//!
//! The period itself (`mre_algorithm::control::Controller`, with its fault
//! latches and the coil-current monitor) and the board's hard limits are the
//! algorithm crate's: the host flies them and does not link this crate. The
//! frames, the upload receiver and the table page codec are the protocol
//! crate's (`mre_protocol`).
//!
//! May not: touch hardware or registers, allocate, panic, or hold `unsafe`
//! code; a board implements the I/O traits. Depends on the algorithm
//! (`mre_algorithm`) only, on no board and not on the protocol; its modules
//! use none of each other. Only the board image (and the firmware tests in
//! tests/) link it.
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
pub mod io;
pub mod pacing;
pub mod status;
pub mod watchdog;
