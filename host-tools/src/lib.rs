//! `mre` host tools: everything that needs `std`. Each command is a library
//! function here; `main.rs` only parses arguments.
//!
//! Links two of the firmware's crates and never copies them: the algorithm
//! (`mre_algorithm`: table, model, law, the control period `mre pil` checks the
//! image against, the board's hard limits) and the protocol (`mre_protocol`:
//! frames, the table page). Not the runtime (boot, watchdog, calibration):
//! only the board image links it.
pub mod atomic_write;
pub mod cargo_build;
pub mod compare;
pub mod control_bench;
pub mod dataset;
pub mod demo;
pub mod diagnose;
pub mod diagnose_bench;
pub mod error_measure;
pub mod fit;
pub mod fmu;
pub mod html;
pub mod installation;
pub mod linalg;
pub mod loops;
pub mod pil;
pub mod plant;
pub mod plot;
pub mod progress;
pub mod signal;
pub mod table_file;
pub mod tables;
pub mod upload;
pub mod validate;
pub mod vocabulary;
