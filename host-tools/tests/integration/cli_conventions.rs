//! One name per concept across subcommands, outputs where `--out` says and
//! nowhere else, what a fit held out recorded in its model file, and an
//! interrupted command that leaves nothing behind.
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::mre_cli::{mre, repo};

fn help(sub: &str) -> String {
    let out = mre().args([sub, "--help"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn every_command_that_holds_currents_out_names_it_hold_out_current() {
    for sub in ["fit", "validate", "plot", "diagnose", "compare", "bench-diagnose"] {
        let text = help(sub);
        assert!(text.contains("--hold-out-current"), "{sub} --help: {text}");
        assert!(!text.contains("--validate-current"), "{sub} shows the old flag");
    }
    // Folders of outputs are --out; --report is an old name kept hidden.
    for sub in ["validate", "diagnose", "compare", "sim", "pil"] {
        let text = help(sub);
        assert!(text.contains("--out <OUT>"), "{sub} --help: {text}");
        assert!(!text.contains("--report"), "{sub} shows the old flag --report");
    }
}

#[test]
fn old_flags_still_work_as_hidden_aliases() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report");
    let out = mre()
        .args(["validate", "data/mr-damper-mts", "--model", "paper", "--report"])
        .arg(&report)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(report.join("report.json").is_file());
}

#[test]
fn fit_records_the_currents_it_held_out() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.toml");
    // Given out of order and twice: the file lists each once, ascending.
    let out = mre()
        .args([
            "fit",
            "data/mr-damper-mts",
            "--method",
            "lsq",
            "--hold-out-current",
            "1,0.5,1",
            "--out",
        ])
        .arg(&model)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let file: toml::Table = std::fs::read_to_string(&model).unwrap().parse().unwrap();
    let held = file["model"]["held_out_current_a"].as_array().unwrap();
    let held: Vec<f64> = held.iter().map(|v| v.as_float().unwrap()).collect();
    assert_eq!(held, vec![0.5, 1.0]);
    // Only 0 A is left to fit: the model file has that one entry.
    assert_eq!(file["current"].as_array().unwrap().len(), 1);
}

#[test]
fn tables_without_out_outside_a_checkout_creates_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let model = repo().join("models/drop-full-stroke.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_mre"))
        .current_dir(dir.path())
        .arg("tables")
        .arg(&model)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--out"), "the error names the fix: {stderr}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "created {left:?}");
}

#[test]
fn diagnose_writes_its_json_and_predictions_inside_out_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("diag");
    let out = mre()
        .args(["diagnose", "data/mr-damper-mts", "--folds", "3", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out_dir.join("report.md").is_file());
    assert!(out_dir.join("report.json").is_file());
    assert!(out_dir.join("predictions").is_dir());
    // Nothing beside the folder it was given.
    let beside: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(beside, vec![std::ffi::OsString::from("diag")]);
}

/// SIGTERM (as `kill` and CI runners send it) to a running demo: it exits 130
/// and leaves neither its output nor its staging folder.
#[cfg(unix)]
#[test]
fn an_interrupted_demo_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let mut child = mre()
        .args(["demo", "--out"])
        .arg(&out_dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let staging = |d: &Path| {
        std::fs::read_dir(d)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with(".mre-"))
            .map(|e| e.path())
            .collect::<Vec<_>>()
    };
    // Wait until the demo has staged something (it fits first, for seconds).
    let mut waited = 0;
    while staging(dir.path()).is_empty() && waited < 600 {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the demo ended before it was interrupted"
        );
        std::thread::sleep(std::time::Duration::from_millis(100));
        waited += 1;
    }
    assert!(!staging(dir.path()).is_empty(), "the demo staged nothing in 60 s");
    let killed = Command::new("kill")
        .arg("-TERM")
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(staging(dir.path()), Vec::<PathBuf>::new(), "staging left behind");
    assert!(!out_dir.exists(), "a half-written output folder");
}
