//! Shared by the FMU tests: a model file with every format-2 term, the FMUs
//! `mre fmu` makes of it, and a recorded drop to drive them with.
#![allow(dead_code)] // each test uses part of it
use mre_algorithm::table::{ModelTerms, PAPER_TABLE4_ENTRIES};
use mre_algorithm::Table;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The bundled recording the damper is driven with.
pub const RECORDING: &str = "data/drop-viscous_damping/i1.0_v2.24_r1.csv";

pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The paper's Table 4 with every term (saturation, sensor delay, coil τ, a viscous term).
pub fn every_term_table() -> Table {
    Table::with_terms(&PAPER_TABLE4_ENTRIES, ModelTerms::EVERY_TERM).expect("valid table")
}

/// Runs `mre fmu MODEL --out DIR/damper.fmu [--controller]`; panics with its stderr on failure.
pub fn mre_fmu(model: &Path, dir: &Path, controller: bool) -> PathBuf {
    mre_fmu_version(model, dir, controller, 3)
}

/// [`mre_fmu`] with `--fmi-version VERSION` (2 or 3).
pub fn mre_fmu_version(model: &Path, dir: &Path, controller: bool, version: u8) -> PathBuf {
    let out = dir.join("damper.fmu");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mre"));
    cmd.arg("fmu").arg(model).arg("--out").arg(&out).arg("--quiet");
    cmd.arg("--fmi-version").arg(version.to_string());
    if controller {
        cmd.arg("--controller");
    }
    let o = cmd.output().expect("run mre fmu");
    assert!(
        o.status.success(),
        "mre fmu failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// One sample of the drive: x (mm, as recorded), v (m/s), coil current (A).
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub x_mm: f64,
    pub v_m_s: f64,
    pub current_a: f64,
}

/// The recording's displacement and velocity, with the coil current swept
/// over −0.2…2.2 A (below, across and above the tabulated 0–2 A) so every
/// path of the interpolation is taken.
pub fn trace() -> Vec<Sample> {
    let mut reader = csv::Reader::from_path(repo().join(RECORDING)).expect("recording");
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.expect("row")).collect();
    let n = rows.len();
    rows.iter()
        .enumerate()
        .map(|(k, r)| Sample {
            x_mm: r[1].parse().expect("displacement"),
            v_m_s: r[2].parse().expect("velocity"),
            current_a: -0.2 + 2.4 * k as f64 / (n - 1) as f64,
        })
        .collect()
}

/// The core's force at a sample, fed as the board's sensors feed it (mm, f32).
pub fn core_force_n(table: &Table, s: &Sample) -> f32 {
    table.force(s.x_mm as f32, s.v_m_s as f32, s.current_a as f32).force_n
}

/// Where the MinGW-w64 linker and the Rust target are installed, `mre fmu`
/// must pack Windows binaries (FMI 2.0 and 3.0 alike).
pub fn windows_toolchain_installed() -> bool {
    std::process::Command::new("x86_64-w64-mingw32-gcc")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
        && std::process::Command::new("rustup")
            .args(["target", "list", "--installed"])
            .output()
            .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("x86_64-pc-windows-gnu"))
}
