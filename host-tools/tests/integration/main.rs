//! Integration tests of the host tools, one module per area, linked into one test
//! binary so the dependencies are linked once (`cargo test -p host-tools --test
//! integration dataset_read::` runs one module).
// Shared helpers (directories beside this binary).
#[path = "../diagnose_support/mod.rs"]
mod diagnose_support;
#[path = "../fmu_support/mod.rs"]
mod fmu_support;
#[path = "../support/mat_v5.rs"]
mod mat_v5;
mod mre_cli;
#[path = "../support/tool_rule.rs"]
mod tool_rule;

mod atomic_outputs;
mod branch_rule;
mod cli_conventions;
mod cli_ux;
mod compare_families;
mod compare_outputs;
mod control_bench;
mod dataset_accelerometer;
mod dataset_campaign;
mod dataset_daq;
mod dataset_init;
mod dataset_lab_text;
mod dataset_matlab;
mod dataset_motion;
mod dataset_read;
mod dataset_real;
mod dataset_report_notes;
mod dataset_sign;
mod dataset_vendor;
mod diagnose_accelerometer;
mod diagnose_cli;
mod diagnose_coil_tau;
mod diagnose_coulomb;
mod diagnose_delay;
mod diagnose_endstop;
mod diagnose_headline;
mod diagnose_oracle;
mod diagnose_outputs;
mod diagnose_outside_memory;
mod diagnose_outside_viscous;
mod diagnose_physical;
mod diagnose_pipeline;
mod diagnose_rate;
mod diagnose_real_bench;
mod diagnose_softening;
mod diagnose_start;
mod diagnose_terms;
mod diagnose_unexplained;
mod diagnose_validate_blind;
mod diagnose_validate_terms;
mod diagnose_verdict;
mod fit;
mod fmu;
mod fmu_fmi2;
mod fmu_fmpy;
mod fmu_windows;
mod installation;
mod installation_sources;
mod model_cmd;
mod plant_bundled_data;
mod plant_closed_loop;
mod plant_dataset_write;
mod plant_physics;
mod plant_synth;
mod plant_synth_inertia;
mod plot;
mod rehost;
mod tables;
mod validate;
