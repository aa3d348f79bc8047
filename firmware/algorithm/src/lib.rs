//! The paper's algorithm and the one control period built on it: the force
//! table and its forward model, the inverse (which current gives a force),
//! the impact law with arming before contact, the velocity estimator, and
//! `control::Controller`, one period from a sample to a coil command with its
//! fault latches and the coil-current monitor (`overcurrent`). Also the
//! installation a table carries and the board's hard limits (`limits`) every
//! configuration is checked against. What the board flies and what the host
//! tools, the simulator and the FMUs link.
//!
//! Why the controller and the limits live here, not in the runtime: `mre pil`
//! and the controller FMU run the very `Controller` the board runs (faults and
//! the sense monitor included) and must match the firmware bit for bit, and the
//! protocol checks every upload against `limits`; in the algorithm crate the
//! host and the protocol link them without linking the runtime.
//!
//! May not: do I/O, touch hardware, allocate, panic, or hold `unsafe` code;
//! it knows nothing of boards, frames, flash, boot or timing (it declares the
//! I/O traits a board implements, `control::{DisplacementSensor, ...}`).
//! Depends on no other crate of the firmware.
//!
//! Data flow of one control period (`control::Controller::step_sample`):
//! `estimate` (velocity from displacement) → `law` (target force for the impact)
//! → `inverse` (current that gives that force, via `model` and `table`) → coil.
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]
// Integer arithmetic says what happens at its edge (checked, saturating or
// wrapping): no overflow panic in a debug build, no silent wrap in release.
// Float arithmetic is not linted (IEEE: no panics).
#![deny(clippy::arithmetic_side_effects)]

pub mod arming;
pub mod control;
pub mod estimate;
pub mod flags;
// The table the image flies, written by `mre tables` beside the image
// (firmware/src/generated_table.rs).
#[path = "../../src/generated_table.rs"]
pub mod generated_table;
pub mod installation;
pub mod inverse;
pub mod law;
pub mod limits;
pub mod math;
pub mod model;
pub mod order;
pub mod overcurrent;
pub mod saturation;
pub mod table;

pub use flags::Flags;
pub use model::Branch;
pub use table::{CurrentEntry, Quartic, Table, TableError};
