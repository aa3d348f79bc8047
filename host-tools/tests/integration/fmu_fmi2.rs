//! FMI 2.0 FMUs (`mre fmu --fmi-version 2`, issue 43) and the Model
//! Exchange damper's branch event, checked by FMPy (tests/fmu/check_fmi2.py,
//! see the script for what each check expects and why) and, here, the fmi2
//! functions every binary in the 2.0 FMUs exports. Without FMPy the FMPy
//! tests say so and pass, except under CI (`CI` set), where they fail.
use crate::fmu_support;

use fmu_support::*;
use std::io::Read;
use std::path::Path;
use std::process::Command;

fn fmpy_available() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import fmpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var_os("CI").is_none(),
            "FMPy is missing on CI: .ci/run must `pip install fmpy`"
        );
        eprintln!("skipped: FMPy is not installed (pip install fmpy)");
    }
    ok
}

/// v2/ (damper.fmu, controller.fmu with FMI 2.0) and v3/damper.fmu of the
/// every-term model, and trace.csv: the recorded drive and the core's force.
fn write_fmus(root: &Path) {
    let table = every_term_table();
    let model = root.join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&table)).unwrap();
    for (version, controller) in [(2, true), (3, false)] {
        let dir = root.join(format!("v{version}"));
        std::fs::create_dir_all(&dir).unwrap();
        mre_fmu_version(&model, &dir, controller, version);
    }
    let mut csv = String::from("displacement_m,velocity_m_s,current_a,force_core_n\n");
    for s in trace() {
        csv += &format!(
            "{:e},{:e},{:e},{:e}\n",
            s.x_mm * 1e-3,
            s.v_m_s,
            s.current_a,
            core_force_n(&table, &s)
        );
    }
    std::fs::write(root.join("trace.csv"), csv).unwrap();
}

fn run_script(args: &[&std::ffi::OsStr]) {
    let script = repo().join("tests/fmu/check_fmi2.py");
    let o = Command::new("python3").arg(&script).args(args).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    eprintln!("{out}{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "FMPy checks failed:\n{out}");
    assert!(out.contains("all FMPy checks passed"));
}

#[test]
fn fmi2_fmus_validate_simulate_and_keep_the_contract() {
    if !fmpy_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_fmus(dir.path());
    run_script(&[dir.path().as_os_str()]);
}

#[test]
fn model_exchange_damper_switches_branch_at_state_events() {
    if !fmpy_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_fmus(dir.path());
    run_script(&["--events".as_ref(), dir.path().as_os_str()]);
}

/// The functions FMI 2.0 declares, from the standard's header
/// (`fmi2Functions.h`, shipped with the patched fmi-sys): each line
/// `#define fmi2X fmi2FullName(fmi2X)`.
fn fmi2_functions() -> Vec<String> {
    let header = repo().join("host-tools/fmu/fmi-sys/fmi-standard2/headers/fmi2Functions.h");
    let text = std::fs::read_to_string(header).unwrap();
    text.lines()
        .filter_map(|l| {
            let mut words = l.split_whitespace();
            match (words.next(), words.next(), words.next()) {
                (Some("#define"), Some(name), Some(full)) if full == format!("fmi2FullName({name})") => {
                    Some(name.to_owned())
                }
                _ => None,
            }
        })
        .collect()
}

#[test]
fn every_fmi2_binary_exports_every_fmi2_function() {
    use object::read::Object;
    let required = fmi2_functions();
    // Counted by hand in the header: 25 common (version, logging, instance, 4 modes,
    // 8 getters and setters, 6 FMU state, directional derivative), 10 Model Exchange,
    // 9 Co-Simulation.
    assert_eq!(required.len(), 44, "{required:?}");
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&every_term_table())).unwrap();
    let damper = mre_fmu_version(&model, dir.path(), true, 2);
    for fmu in [damper.clone(), mre_host::fmu::controller_path(&damper)] {
        let mut zip = zip::ZipArchive::new(std::fs::File::open(&fmu).unwrap()).unwrap();
        let names: Vec<String> = zip.file_names().map(str::to_owned).collect();
        let binaries: Vec<&String> = names.iter().filter(|n| n.starts_with("binaries/")).collect();
        // FMI 2.0's platform folders (FMI 2.0 §2.3), not 3.0's.
        let platforms: Vec<&str> = binaries.iter().filter_map(|n| n.split('/').nth(1)).collect();
        assert!(platforms.contains(&"linux64"), "{binaries:?}");
        assert!(
            platforms.iter().all(|p| ["linux64", "win64"].contains(p)),
            "{binaries:?}"
        );
        if crate::fmu_support::windows_toolchain_installed() {
            assert!(platforms.contains(&"win64"), "{}: {binaries:?}", fmu.display());
        } else {
            eprintln!("note: no MinGW-w64 or no x86_64-pc-windows-gnu target: Linux binaries only checked");
        }
        for name in binaries {
            let mut bytes = Vec::new();
            zip.by_name(name).unwrap().read_to_end(&mut bytes).unwrap();
            let file = object::File::parse(&*bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
            let exported: Vec<String> = file
                .exports()
                .unwrap()
                .filter_map(|e| e.ok()?.name().name().map(|n| String::from_utf8_lossy(n).into_owned()))
                .collect();
            let missing: Vec<&String> = required.iter().filter(|f| !exported.contains(f)).collect();
            assert!(
                missing.is_empty(),
                "{}: {name} does not export {missing:?}",
                fmu.display()
            );
        }
    }
}
