//! `mre diagnose` as a user runs it: relative output paths (a bare JSON file
//! name) from the working directory, stderr in sentences, nothing partial
//! written when it fails.
mod diagnose_support;
use diagnose_support::{dataset, Added};
use mre_host::dataset::write::{write_dataset, WriteOptions};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn diagnose_in(cwd: &Path, data: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mre"))
        .current_dir(cwd)
        .arg("diagnose")
        .arg(data)
        .args(["--report", "rep", "--json", "diag.json", "--predictions", "pred"])
        .output()
        .expect("run mre")
}

/// A data set with viscous damping added, written to a fresh folder (kept
/// while the returned guard lives).
fn viscous_data_set() -> (tempfile::TempDir, PathBuf) {
    let data_dir = tempfile::tempdir().expect("tempdir");
    let data = data_dir.path().join("data");
    write_dataset(
        &dataset(Added::Viscous { c_n_s_per_m: 400.0 }, 3),
        &data,
        &WriteOptions::default(),
    )
    .expect("write");
    (data_dir, data)
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("ls")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

// Catches resolving `--json` against the report folder (diag.json lands in
// rep/, the listing check fails). Its stderr check did not catch a Debug dump
// of each failing variant's `Terms`: no variant fails on this data.
#[test]
fn a_bare_json_file_name_works_and_stderr_holds_sentences_only() {
    let (_data_dir, data) = viscous_data_set();
    let cwd = tempfile::tempdir().expect("tempdir");
    let out = diagnose_in(cwd.path(), &data);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_eq!(names_in(cwd.path()), ["diag.json", "pred", "rep"]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(cwd.path().join("diag.json")).expect("json")).expect("parse");
    assert_eq!(json["effects"][0]["name"], "viscous_damping");
    let html = std::fs::read_to_string(cwd.path().join("rep/index.html")).expect("page");
    assert!(html.contains("diag.json"), "the page does not list the JSON");
    assert!(!names_in(&cwd.path().join("pred")).is_empty());
    // No Rust Debug dumps, and not dozens of lines.
    for dump in ["{", "}", "Some(", "None", "Terms"] {
        assert!(!stderr.contains(dump), "stderr holds `{dump}`:\n{stderr}");
    }
    assert!(stderr.lines().count() <= 3, "{stderr}");
}

// Writing the predictions before the report folder is made is not caught
// here: outputs are staged and only committed when every one succeeds.
#[test]
fn a_failing_run_writes_nothing_and_says_why_in_a_sentence() {
    let (_data_dir, data) = viscous_data_set();
    // A file where the report folder must go: the run fails at the end.
    let cwd = tempfile::tempdir().expect("tempdir");
    std::fs::write(cwd.path().join("rep"), "not a folder").expect("write");
    let out = diagnose_in(cwd.path(), &data);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(names_in(cwd.path()), ["rep"], "{stderr}");
    assert_eq!(
        std::fs::read_to_string(cwd.path().join("rep")).expect("rep"),
        "not a folder"
    );
    assert!(stderr.contains("rep"), "{stderr}");
    for dump in ["{", "Some(", "None", "panicked"] {
        assert!(!stderr.contains(dump), "stderr holds `{dump}`:\n{stderr}");
    }
}
