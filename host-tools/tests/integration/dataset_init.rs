//! `mre dataset init` (the binary users run) on a copy of the bundled MTS
//! recordings without their dataset.toml reproduces the committed one,
//! apart from comments; it never overwrites an existing one.
use std::path::{Path, PathBuf};
use std::process::Command;

fn mts() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mr-damper-mts")
}

const PATTERN: &str = "{amplitude_mm}mm{frequency_hz}Hz{current_a}A";

fn init(dir: &Path, name: &str) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_mre"))
        .args(["dataset", "init"])
        .arg(dir)
        .args(["--pattern", PATTERN, "--name", name])
        .output()
        .unwrap()
}

#[test]
fn reproduces_the_committed_mts_manifest() {
    let committed_text = std::fs::read_to_string(mts().join("dataset.toml")).unwrap();
    let committed: toml::Value = toml::from_str(&committed_text).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for e in std::fs::read_dir(mts()).unwrap() {
        let e = e.unwrap();
        if e.file_name() != "dataset.toml" {
            std::fs::copy(e.path(), dir.path().join(e.file_name())).unwrap();
        }
    }
    let name = committed["name"].as_str().unwrap();
    let out = init(dir.path(), name);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let written_text = std::fs::read_to_string(dir.path().join("dataset.toml")).unwrap();
    let written: toml::Value = toml::from_str(&written_text).unwrap();
    assert_eq!(written, committed, "written:\n{written_text}");
    // It loads as the committed one does.
    let a = mre_host::dataset::Dataset::load(dir.path()).unwrap();
    let b = mre_host::dataset::Dataset::load(&mts()).unwrap();
    assert_eq!(a.recordings, b.recordings);

    // A second run refuses and leaves the file as it was.
    let again = init(dir.path(), "other");
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("never overwrites"));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("dataset.toml")).unwrap(),
        written_text
    );
}
