//! The `mre` binary under test, run from the repository root (where `data/` is).
use std::path::{Path, PathBuf};
use std::process::Command;

pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub fn mre() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_mre"));
    c.current_dir(repo());
    c
}
