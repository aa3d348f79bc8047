//! The published fmi-sys runs bindgen here (which needs libclang); this copy
//! ships the generated bindings in `src/*/bindings.rs` and only compiles
//! FMI 2.0's variadic logger shim.
fn main() {
    #[cfg(feature = "fmi2")]
    cc::Build::new()
        .file("src/fmi2/logger.c")
        .include("fmi-standard2/headers")
        .compile("liblogger.a");
    println!("cargo:rerun-if-changed=src/fmi2/logger.c");
}
