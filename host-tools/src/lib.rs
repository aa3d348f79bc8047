//! `mre` host tools: everything that needs `std`. Each command is a library
//! function here; `main.rs` only parses arguments.
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
