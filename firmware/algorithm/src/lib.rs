//! The MRE damper's algorithm (`mre_algorithm`): the paper's model and the
//! impact law, and the one control period built on them, as pure functions
//! of sampled values. What the board flies and what the host tools, the
//! simulator and the FMUs link.
//!
//! What is here:
//! - the model: `entry` (one current's two quartics), `table` (the entries,
//!   the format 2 terms and the installation under a CRC, validated when
//!   built), `saturation`, `order` (facts proven when a table is built),
//!   `model` (force from x, v, I) and `inverse` (the current for a force);
//! - the law: `law` (impact law, coil-lag inversion, delay prediction),
//!   `arming` (the current before contact), `estimate` (velocity from x);
//! - the period: `control::Controller` (a sample in, a coil current out, with
//!   its fault latches, overrun accounting and statistics) and `overcurrent`
//!   (the coil-current monitor the controller runs before each step);
//! - data: `installation`, `limits` (the board's hard limits),
//!   `generated_table` (the built-in table), `flags`, `math`.
//!
//! Why the controller, the monitor and the limits are here, not in the
//! runtime: `mre pil` and the controller FMU fly the board's `Controller`
//! bit for bit (faults and the sense monitor included), and host-tools may
//! link only this crate and the protocol; the protocol checks every upload
//! against `limits`. They stay pure: the board passes the sample, the shunt
//! reading, whether the period overran and its cycle count in as values.
//!
//! May not: do I/O or know a board: no sensor or coil traits (the runtime's
//! `io`), no registers, clock, watchdog, boot, frames or flash; no heap, no
//! panics, no `unsafe`. Depends on no other crate of the firmware. Its
//! modules import one way (no circle): `math`, `flags`, `entry`,
//! `saturation`, `installation`, `overcurrent`, `estimate` at the bottom,
//! then `order`, `table`, `model`, `inverse`, `arming`, `law`, `control`,
//! `limits`.
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
pub mod entry;
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
