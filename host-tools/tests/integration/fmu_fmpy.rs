//! FMPy (Python) on `mre fmu`'s FMUs: tests/fmu/check_fmus.py, fed with the
//! FMUs, the core's forces on a recorded drop and `mre sim --controlled`'s
//! result (see the script). Needs `pip install fmpy` (`.ci/run` installs
//! it); without it the test says so and passes, except under CI (`CI` set),
//! where it fails.
use crate::fmu_support;

use fmu_support::*;

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

    write_sim_case(root, 3);

    run_fmpy_script("check_fmus.py", &[root.as_os_str()]);
}
