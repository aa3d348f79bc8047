//! FMPy (Python) on `mre fmu`'s FMUs: tests/fmu/check_fmus.py, fed with the
//! FMUs, the core's forces on a recorded drop and `mre sim --controlled`'s
//! result (see the script). Needs `pip install fmpy` (`.ci/run` installs
//! it); without it the test says so and passes, except under CI (`CI` set),
//! where it fails.
use crate::fmu_support;

use fmu_support::*;
use mre_host::plant::closed_loop::{run_comparison, setup_for, RunSpec, SimRequest};
use std::process::Command;

#[test]
fn fmpy_validates_evaluates_and_closes_the_loop() {
    if !fmpy_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();

    // A model with every term, and the core's force along a recorded drop.
    let every = root.join("every-term");
    std::fs::create_dir_all(&every).unwrap();
    let table = every_term_table();
    std::fs::write(every.join("model.toml"), mre_host::table_file::table_to_toml(&table)).unwrap();
    mre_fmu(&every.join("model.toml"), &every, true);
    write_trace_csv(&table, &root.join("trace.csv"));

    // What `mre sim --controlled` runs (its defaults), the model it flies, and its outcome.
    let request = SimRequest::default();
    let setup = setup_for(&request).unwrap();
    let sim_dir = root.join("sim");
    std::fs::create_dir_all(&sim_dir).unwrap();
    let text = mre_host::control_bench::diagnosed_model_file(&setup.plant, setup.impact.noise_seed).unwrap();
    std::fs::write(sim_dir.join("model.toml"), &text).unwrap();
    mre_fmu(&sim_dir.join("model.toml"), &sim_dir, true);
    let cmp = run_comparison(&setup, &[RunSpec::Controlled]).unwrap();
    let s = cmp.runs[0].summary;
    let impact = mre_host::plant::closed_loop::controlled_impact(
        &setup,
        &mre_host::table_file::parse_table_toml(&text).unwrap(),
    );
    let sim = serde_json::json!({
        "peak_force_n": s.peak_force_n,
        "max_stroke_mm": s.max_stroke_mm,
        "mass_kg": impact.mass_kg,
        "gravity_m_s2": impact.gravity_m_s2,
        "impact_velocity_m_s": impact.impact_velocity_m_s,
        "initial_current_a": impact.initial_current_a,
        "step_s": impact.step_s,
        "max_duration_s": impact.max_duration_s,
        "coil_lag_s": impact.coil_lag_s,
        "drive_range_a": impact.driver.command_range_a(),
    });
    std::fs::write(root.join("sim.json"), sim.to_string()).unwrap();

    let script = repo().join("tests/fmu/check_fmus.py");
    let o = Command::new("python3").arg(&script).arg(root).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    eprintln!("{out}{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "FMPy checks failed:\n{out}");
    assert!(out.contains("all FMPy checks passed"));
}
