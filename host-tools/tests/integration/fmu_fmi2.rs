//! FMI 2.0 FMUs (`mre fmu --fmi-version 2`, issue 43) and the Model
//! Exchange damper's branch event, checked by FMPy (tests/fmu/check_fmi2.py,
//! see the script for what each check expects and why) and, here, the fmi2
//! functions every binary in the 2.0 FMUs exports. Without FMPy the FMPy
//! tests say so and pass, except under CI (`CI` set), where they fail.
use crate::fmu_support;

use fmu_support::*;
use std::path::Path;

/// v2/ (damper.fmu, controller.fmu with FMI 2.0) and v3/damper.fmu of the
/// every-term model, and trace.csv: the recorded drive and the core's force
/// (the contract test adds the closed loop's FMUs and sim.json, `write_sim_case`).
fn write_fmus(root: &Path) {
    let table = every_term_table();
    let model = root.join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&table)).unwrap();
    for (version, controller) in [(2, true), (3, false)] {
        let dir = root.join(format!("v{version}"));
        std::fs::create_dir_all(&dir).unwrap();
        mre_fmu_version(&model, &dir, controller, version);
    }
    write_trace_csv(&table, &root.join("trace.csv"));
}

#[test]
fn fmi2_fmus_validate_simulate_keep_the_contract_and_close_the_loop() {
    if !fmpy_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_fmus(dir.path());
    write_sim_case(dir.path(), 2);
    run_fmpy_script("check_fmi2.py", &[dir.path().as_os_str()]);
}

#[test]
fn model_exchange_damper_switches_branch_at_state_events() {
    if !fmpy_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_fmus(dir.path());
    run_fmpy_script("check_fmi2.py", &["--events".as_ref(), dir.path().as_os_str()]);
}

#[test]
fn every_fmi2_binary_exports_every_fmi2_function() {
    let required = fmi_functions(2);
    // Counted by hand in the header: 25 common (version, logging, instance, 4 modes,
    // 8 getters and setters, 6 FMU state, directional derivative), 10 Model Exchange,
    // 9 Co-Simulation.
    assert_eq!(required.len(), 44, "{required:?}");
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&every_term_table())).unwrap();
    let damper = mre_fmu_version(&model, dir.path(), true, 2);
    for fmu in [damper.clone(), mre_host::fmu::controller_path(&damper)] {
        // FMI 2.0's platform folders (FMI 2.0 §2.3), not 3.0's.
        checked_binaries(&fmu, ["linux64", "win64"], &required);
    }
}
