//! The paper's algorithm: the force table and its forward model, the inverse
//! (which current gives a force), the impact law with arming before contact,
//! and the velocity estimator. What the board flies and what the host tools,
//! the simulator and the FMUs link for the physics.
//!
//! May not: do I/O, touch hardware, allocate, panic, or hold `unsafe` code;
//! it knows nothing of boards, frames, flash or faults beyond the flags a
//! period's decision carries. Depends on no other crate of the firmware.
//!
//! Data flow of one control period:
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
pub mod estimate;
pub mod flags;
pub mod installation;
pub mod inverse;
pub mod law;
pub mod math;
pub mod model;
pub mod order;
pub mod saturation;
pub mod table;

pub use flags::Flags;
pub use model::Branch;
pub use table::{CurrentEntry, Quartic, Table, TableError};
