//! The identified damper and the impact controller as FMI 3.0 and FMI 2.0
//! models (the 2.0 functions in [`fmi2`], over the same models).
//!
//! Both evaluate through `mre_algorithm`, the code the board runs. An FMU carries
//! its table and installation as `resources/table.page`: the 2 KiB flash
//! page the board stores after `mre upload` (`mre_protocol::flash_table`), read
//! back through the core's own loader (magic, CRC, table and configuration
//! validation) when the FMU is instantiated.
//!
//! Each model is exported by its own `cdylib` (`damper/`, `controller/`:
//! one FMI library per FMU). This crate holds the models and their
//! `modelDescription.xml` ([`describe`]), which `mre fmu` writes beside the
//! library.
pub mod controller;
pub mod damper;
pub mod describe;
pub mod export;
pub mod fmi2;
pub mod page;
pub mod ranges;

pub use controller::Controller;
pub use damper::Damper;
