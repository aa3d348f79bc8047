//! Puts the repository's `memory.x` on the linker search path for the board
//! image. Host builds (tests, clippy) do not link with it.
use std::{env, fs, path::PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=../memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        return;
    }
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default());
    let memory = fs::read("../memory.x").unwrap_or_else(|e| panic!("reading ../memory.x: {e}"));
    fs::write(out.join("memory.x"), memory).unwrap_or_else(|e| panic!("writing memory.x: {e}"));
    println!("cargo:rustc-link-search={}", out.display());
}
