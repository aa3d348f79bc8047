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

/// The functions FMI `version` (2 or 3) declares, read from the standard's
/// own header (`fmi2Functions.h` / `fmi3Functions.h`, shipped with the
/// patched fmi-sys): each line `#define fmiNX fmiNFullName(fmiNX)`.
pub fn fmi_functions(version: u8) -> Vec<String> {
    let header = repo().join(format!(
        "host-tools/fmu/fmi-sys/fmi-standard{version}/headers/fmi{version}Functions.h"
    ));
    let text = std::fs::read_to_string(header).unwrap();
    let full_name = format!("fmi{version}FullName");
    text.lines()
        .filter_map(|l| {
            let mut words = l.split_whitespace();
            match (words.next(), words.next(), words.next()) {
                (Some("#define"), Some(name), Some(full)) if full == format!("{full_name}({name})") => {
                    Some(name.to_owned())
                }
                _ => None,
            }
        })
        .collect()
}

/// Every binary an FMU carries: its path in the archive and its bytes.
pub fn fmu_binaries(fmu: &Path) -> Vec<(String, Vec<u8>)> {
    use std::io::Read;
    let mut zip = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let names: Vec<String> = zip
        .file_names()
        .filter(|n| n.starts_with("binaries/"))
        .map(str::to_owned)
        .collect();
    names
        .into_iter()
        .map(|name| {
            let mut bytes = Vec::new();
            zip.by_name(&name).unwrap().read_to_end(&mut bytes).unwrap();
            (name, bytes)
        })
        .collect()
}

/// An FMU's binaries, checked: in the folders `[linux, windows]` only, the
/// Linux one always, the Windows one where the toolchain is installed (else a
/// note), each exporting every function of `required`.
pub fn checked_binaries(fmu: &Path, [linux, windows]: [&str; 2], required: &[String]) -> Vec<(String, Vec<u8>)> {
    let binaries = fmu_binaries(fmu);
    let names: Vec<&String> = binaries.iter().map(|(n, _)| n).collect();
    let platforms: Vec<&str> = names.iter().filter_map(|n| n.split('/').nth(1)).collect();
    assert!(platforms.contains(&linux), "{names:?}");
    assert!(platforms.iter().all(|p| [linux, windows].contains(p)), "{names:?}");
    if windows_toolchain_installed() {
        assert!(platforms.contains(&windows), "{}: {names:?}", fmu.display());
    } else {
        eprintln!("note: no MinGW-w64 or no x86_64-pc-windows-gnu target: Linux binaries only checked");
    }
    for (name, bytes) in &binaries {
        let exported = exported_symbols(name, bytes);
        let missing: Vec<&String> = required.iter().filter(|f| !exported.contains(f)).collect();
        assert!(
            missing.is_empty(),
            "{}: {name} does not export {missing:?}",
            fmu.display()
        );
    }
    binaries
}

/// The symbols an ELF or PE binary exports.
pub fn exported_symbols(name: &str, bytes: &[u8]) -> Vec<String> {
    use object::read::Object;
    let file = object::File::parse(bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
    file.exports()
        .unwrap()
        .filter_map(|e| e.ok()?.name().name().map(|n| String::from_utf8_lossy(n).into_owned()))
        .collect()
}

/// Whether FMPy can be imported. Without it an FMPy test says so and
/// passes, except under CI (`CI` set), where it fails: `.ci/run` installs it.
pub fn fmpy_available() -> bool {
    let ok = std::process::Command::new("python3")
        .args(["-c", "import fmpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    crate::tool_rule::installed_or_skipped(ok, "FMPy", "`pip install fmpy`")
}

/// Runs `tests/fmu/SCRIPT ARGS…` (an FMPy check script), echoes its lines,
/// and fails unless every check passed (its last line says so).
pub fn run_fmpy_script(script: &str, args: &[&std::ffi::OsStr]) {
    let o = Command::new("python3")
        .arg(repo().join("tests/fmu").join(script))
        .args(args)
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    eprintln!("{out}{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "FMPy checks failed:\n{out}");
    assert!(out.contains("all FMPy checks passed"));
}

/// `path` as the FMPy scripts read a recorded drop: inputs in SI units and
/// the core's force at each sample.
pub fn write_trace_csv(table: &Table, path: &Path) {
    let mut csv = String::from("displacement_m,velocity_m_s,current_a,force_core_n\n");
    for s in trace() {
        csv += &format!(
            "{:e},{:e},{:e},{:e}\n",
            s.x_mm * 1e-3,
            s.v_m_s,
            s.current_a,
            core_force_n(table, &s)
        );
    }
    std::fs::write(path, csv).unwrap();
}

/// Whether Wine can run the FMUs' Windows DLLs here: `wine` on the path and
/// the MinGW-w64 toolchain that builds the DLLs and the importer
/// (tests/fmu/fmu_run.c). Without them a Wine test says so and passes,
/// except under CI (`CI` set), where it fails: `.ci/run` installs both.
pub fn wine_available() -> bool {
    let wine = Command::new("wine")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    let toolchain = windows_toolchain_installed();
    let (missing, install) = if wine {
        ("MinGW-w64 or the x86_64-pc-windows-gnu target", "install it")
    } else {
        ("Wine", "`apt-get install wine wine64`")
    };
    crate::tool_rule::installed_or_skipped(wine && toolchain, missing, install)
}

/// tests/fmu/fmu_run.c built for Linux (`DIR/fmu_run`) and for Windows
/// (`DIR/fmu_run.exe`), and beside the latter the `bcryptprimitives.dll`
/// shim Wine 8.0 lacks (tests/fmu/bcryptprimitives_shim.c says why).
pub fn build_fmu_run(dir: &Path) -> (PathBuf, PathBuf) {
    let src = repo().join("tests/fmu");
    let headers = repo().join("host-tools/fmu/fmi-sys");
    let includes = [
        format!("-I{}", headers.join("fmi-standard2/headers").display()),
        format!("-I{}", headers.join("fmi-standard3/headers").display()),
    ];
    let linux = dir.join("fmu_run");
    let windows = dir.join("fmu_run.exe");
    let shim = dir.join("bcryptprimitives.dll");
    let builds = [
        ("cc", "fmu_run.c", &includes[..], &linux, "-ldl"),
        (
            "x86_64-w64-mingw32-gcc",
            "fmu_run.c",
            &includes[..],
            &windows,
            "-lkernel32",
        ),
        (
            "x86_64-w64-mingw32-gcc",
            "bcryptprimitives_shim.c",
            &["-shared".to_owned()][..],
            &shim,
            "-ladvapi32",
        ),
    ];
    for (compiler, source, flags, out, lib) in builds {
        let o = Command::new(compiler)
            .args(["-std=c99", "-O2", "-Wall", "-Werror"])
            .args(flags)
            .arg(src.join(source))
            .arg("-o")
            .arg(out)
            .arg(lib)
            .output()
            .expect("run the C compiler");
        assert!(
            o.status.success(),
            "{compiler} {source}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    (linux, windows)
}

/// An attribute of the XML element that has `name="NAME"` (`name` None: the
/// first element with the attribute), read by hand from a model description.
pub fn xml_attr(xml: &str, name: Option<&str>, attr: &str) -> String {
    let (start, end) = match name {
        Some(n) => {
            let at = xml
                .find(&format!(" name=\"{n}\""))
                .unwrap_or_else(|| panic!("no variable {n}"));
            (xml[..at].rfind('<').unwrap(), at + xml[at..].find('>').unwrap())
        }
        None => (0, xml.len()),
    };
    let element = &xml[start..end];
    let key = format!(" {attr}=\"");
    let from = element.find(&key).unwrap_or_else(|| panic!("no {attr} in {element}")) + key.len();
    element[from..from + element[from..].find('"').unwrap()].to_owned()
}

/// One binary of an unpacked FMU run by `fmu_run` (Linux directly, a
/// Windows `.exe` under Wine in the prefix `wine_prefix`):
/// `inputs` per step, the named outputs back per step with the worst status
/// of the step's calls, all as exact f64s.
pub struct FmuRun<'a> {
    pub importer: &'a Path,
    pub library: &'a Path,
    pub fmi_version: u8,
    pub unpacked: &'a Path,
    pub inputs: &'a [&'a str],
    pub outputs: &'a [&'a str],
    /// Wine's prefix (made on first use, ~700 MB): a folder the test removes,
    /// so no run leaves it in target/ (.ci/run's 3 GB budget).
    pub wine_prefix: &'a Path,
}

impl FmuRun<'_> {
    pub fn run(&self, steps: &[Vec<f64>]) -> Vec<(u8, Vec<f64>)> {
        let xml = std::fs::read_to_string(self.unpacked.join("modelDescription.xml")).unwrap();
        let token = xml_attr(
            &xml,
            None,
            if self.fmi_version == 2 {
                "guid"
            } else {
                "instantiationToken"
            },
        );
        let step_s: f64 = xml_attr(&xml, None, "stepSize").parse().unwrap();
        let vrs = |names: &[&str]| {
            names
                .iter()
                .map(|n| xml_attr(&xml, Some(n), "valueReference"))
                .collect::<Vec<_>>()
                .join(",")
        };
        let windows = self.importer.extension().is_some_and(|e| e == "exe");
        let resources = self.unpacked.join("resources");
        // What an importer on each platform passes (FMI 3.0 §2.3.1: a native path
        // with a trailing separator; FMI 2.0 §2.1.5: a file URI). Wine maps Z: to /.
        let resources = match (windows, self.fmi_version) {
            (true, 3) => format!("Z:{}\\", resources.display()).replace('/', "\\"),
            (true, _) => format!("file:///Z:{}", resources.display()),
            (false, 3) => format!("{}/", resources.display()),
            (false, _) => format!("file://{}", resources.display()),
        };
        let dir = self.unpacked.join(if windows { "run-windows" } else { "run-linux" });
        std::fs::create_dir_all(&dir).unwrap();
        let bits = |x: f64| format!("{:016x}", x.to_bits());
        let text: String = steps
            .iter()
            .map(|s| s.iter().map(|&x| bits(x)).collect::<Vec<_>>().join(" ") + "\n")
            .collect();
        std::fs::write(dir.join("in.txt"), text).unwrap();
        let mut cmd = Command::new("timeout");
        cmd.arg("600");
        if windows {
            // No debug output, no Mono/Gecko install dialogs, no windows.
            cmd.arg("wine")
                .env("WINEPREFIX", self.wine_prefix)
                .env("WINEDEBUG", "-all")
                .env("WINEDLLOVERRIDES", "mscoree,mshtml=")
                .env_remove("DISPLAY");
        }
        let o = cmd
            .arg(self.importer)
            .arg(self.library)
            .arg(self.fmi_version.to_string())
            .arg(token)
            .arg(resources)
            .arg(bits(step_s))
            .arg(vrs(self.inputs))
            .arg(vrs(self.outputs))
            .arg(dir.join("in.txt"))
            .arg(dir.join("out.txt"))
            .output()
            .expect("run fmu_run");
        assert!(
            o.status.success(),
            "{} on {}: {}",
            self.importer.display(),
            self.library.display(),
            String::from_utf8_lossy(&o.stderr)
        );
        let out = std::fs::read_to_string(dir.join("out.txt")).unwrap();
        out.lines()
            .map(|l| {
                let mut words = l.split_whitespace();
                let status = words.next().unwrap().parse().unwrap();
                let values = words
                    .map(|w| f64::from_bits(u64::from_str_radix(w, 16).unwrap()))
                    .collect();
                (status, values)
            })
            .collect()
    }
}

/// Unpacks an FMU into `dir`.
pub fn unpack_fmu(fmu: &Path, dir: &Path) {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    zip.extract(dir).unwrap();
}

/// `ROOT/sim/damper.fmu`, `ROOT/sim/controller.fmu` (FMI `version`) of the
/// model `mre sim --controlled` flies with its defaults, and `ROOT/sim.json`:
/// that run's peak force and stroke and the settings the FMPy scripts' falling
/// mass needs to fly the same drop (tests/fmu/fmpy_common.py, `closed_loop`).
pub fn write_sim_case(root: &Path, version: u8) {
    use mre_host::plant::closed_loop::{controlled_impact, run_comparison, setup_for, RunSpec, SimRequest};
    let request = SimRequest::default();
    let setup = setup_for(&request).unwrap();
    let sim_dir = root.join("sim");
    std::fs::create_dir_all(&sim_dir).unwrap();
    let text = mre_host::control_bench::diagnosed_model_file(&setup.plant, setup.impact.noise_seed).unwrap();
    std::fs::write(sim_dir.join("model.toml"), &text).unwrap();
    mre_fmu_version(&sim_dir.join("model.toml"), &sim_dir, true, version);
    let cmp = run_comparison(&setup, &[RunSpec::Controlled]).unwrap();
    let s = cmp.runs[0].summary;
    let impact = controlled_impact(&setup, &mre_host::table_file::parse_table_toml(&text).unwrap());
    let sim = serde_json::json!({
        "peak_force_n": s.peak_force_n,
        "max_stroke_mm": s.max_stroke_mm,
        "mass_kg": impact.mass_kg,
        "gravity_m_s2": impact.gravity_m_s2,
        "impact_velocity_m_s": impact.impact_velocity_m_s,
        "initial_current_a": impact.initial_current_a,
        "step_s": impact.step_s,
        "max_duration_s": impact.max_duration_s,
        "coil_lag_s": impact.coil_lag_s,
        "drive_range_a": impact.driver.command_range_a(),
    });
    std::fs::write(root.join("sim.json"), sim.to_string()).unwrap();
}
