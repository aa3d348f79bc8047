//! Host tests of the no_std control core through its public API, one module per
//! area, linked into one test binary (`cargo test -p mre-tests --test core law::`
//! runs one module).

mod arbitrary_tables;
mod arming;
mod augmented;
mod boot;
mod calibration;
mod control;
mod estimate;
mod flash_table;
mod frame;
mod installation_table;
mod inverse;
mod law;
mod law_arming;
mod law_terms;
mod limits;
mod math;
mod no_panic;
mod order;
mod overcurrent;
mod pacing;
mod paper_table;
mod saturation;
mod status;
mod table_bounds;
mod upload;
mod watchdog;
