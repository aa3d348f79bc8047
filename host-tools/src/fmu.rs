//! `mre fmu`: the model file as FMI 3.0 FMUs, or FMI 2.0 ones with
//! `--fmi-version 2` (the same libraries, which export both APIs; a 2.0
//! model description, `mre_fmu::fmi2::describe`, and 2.0's platform
//! folders `linux64`, `win64`). `damper.fmu` is the damper
//! (x, v, I in, force out); `controller.fmu` the impact controller as the
//! board runs it. Both evaluate through `mre_algorithm` (crate `mre-fmu`).
//!
//! An FMU is a zip of
//! - `modelDescription.xml` (`mre_fmu::describe`),
//! - `binaries/x86_64-linux/mre_damper.so` (or `mre_controller.so`): the
//!   `cdylib` of `host-tools/fmu/damper` (`…/controller`), and
//!   `binaries/x86_64-windows/mre_damper.dll` when it was cross-built
//!   (MinGW-w64 and the Rust target installed) or is in the libraries'
//!   `x86_64-windows/` folder,
//! - `resources/table.page`: the table and the control configuration as the
//!   board's flash page (`mre_fmu::page`), and `resources/model.toml`, the
//!   model file it came from (for people; the library reads only the page),
//! - `documentation/index.html`: the model, its variables with units and
//!   ranges, the source data set, the table's CRC and how to wire it.
//!
//! `generationDateAndTime` is `$SOURCE_DATE_EPOCH` when set (reproducible
//! builds), else the time of writing.
//!
//! The libraries: `$MRE_FMU_LIB_DIR` if set; else, in a source checkout,
//! `cargo build --release` of the two `cdylib` crates into the workspace's
//! target folder, sharing the host build's dependencies, their libraries
//! copied to `<target>/fmu-libraries` (crate::cargo_build); else the folder of
//! the running `mre`.
use crate::atomic_write::write_atomic_with;
use anyhow::{anyhow, bail, Context, Result};
use mre_algorithm::control::ControlConfig;
use mre_algorithm::Table;
use mre_fmu::describe::{Describe, Kind};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The FMI platform folder of the libraries this build packs.
pub const PLATFORM: &str = "x86_64-linux";

/// The FMI platform folder of the Windows libraries, packed beside the Linux
/// ones when `libraries/x86_64-windows/` holds them.
pub const WINDOWS_PLATFORM: &str = "x86_64-windows";

/// The Rust target and the MinGW-w64 linker the Windows libraries need.
const WINDOWS_TARGET: &str = "x86_64-pc-windows-gnu";
const WINDOWS_LINKER: &str = "x86_64-w64-mingw32-gcc";

/// FMI 2.0's platform folders for the same libraries (FMI 2.0 §2.3).
pub const PLATFORM_V2: &str = "linux64";
pub const WINDOWS_PLATFORM_V2: &str = "win64";

/// Which FMI standard the FMUs follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FmiVersion {
    V2,
    #[default]
    V3,
}

impl FmiVersion {
    /// The binaries' platform folders: (Linux, Windows).
    fn platforms(self) -> (&'static str, &'static str) {
        match self {
            FmiVersion::V2 => (PLATFORM_V2, WINDOWS_PLATFORM_V2),
            FmiVersion::V3 => (PLATFORM, WINDOWS_PLATFORM),
        }
    }
}

/// What `mre fmu` was asked for.
#[derive(Clone, Debug)]
pub struct FmuRequest {
    pub model: PathBuf,
    /// damper.fmu's path; controller.fmu goes beside it.
    pub out: PathBuf,
    pub controller: bool,
    pub fmi: FmiVersion,
}

/// The controller's configuration: `mre sim`'s and `mre pil`'s for the
/// model file's installation (the table's: its `[installation]`, else the
/// defaults), at `mre sim`'s control rate (10 kHz).
pub fn installation(table: &Table) -> Result<ControlConfig> {
    let setup = crate::plant::closed_loop::SimSetup::for_installation(
        crate::plant::stepper::Plant::nominal(),
        *table.installation(),
    );
    crate::pil::sim::control_config(&setup)
        .map_err(|e| anyhow!("the installation's control configuration is invalid: {e:#}"))
}

/// The path of controller.fmu for damper.fmu at `out`.
pub fn controller_path(out: &Path) -> PathBuf {
    out.with_file_name("controller.fmu")
}

/// Writes damper.fmu (and controller.fmu); returns the paths written.
pub fn run_fmu(request: &FmuRequest) -> Result<Vec<PathBuf>> {
    // A bad model file is reported before the libraries are built.
    read_model(&request.model)?;
    let libraries = library_dir()?;
    run_fmu_with(request, &libraries)
}

fn read_model(path: &Path) -> Result<(String, Table)> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read model file {}", path.display()))?;
    let table =
        crate::table_file::parse_table_toml(&text).with_context(|| format!("in model file {}", path.display()))?;
    Ok((text, table))
}

/// [`run_fmu`] with the FMU libraries in `libraries`.
pub fn run_fmu_with(request: &FmuRequest, libraries: &Path) -> Result<Vec<PathBuf>> {
    let (text, table) = read_model(&request.model)?;
    let cfg = installation(&table)?;
    let page = mre_fmu::page::page_bytes(&table, &cfg).map_err(|e| anyhow!(e))?;
    let source = request
        .model
        .file_name()
        .map_or_else(|| "model".to_owned(), |n| n.to_string_lossy().into_owned());
    let mut kinds = vec![(Kind::Damper, request.out.clone())];
    if request.controller {
        kinds.push((Kind::Controller, controller_path(&request.out)));
    }
    let date = generation_date(std::env::var("SOURCE_DATE_EPOCH").ok().as_deref())?;
    let provenance = Provenance::of(&text);
    for (kind, path) in &kinds {
        let mut describe = describe_for(*kind, &source, &table, &cfg);
        describe.generation_date_and_time = Some(date.clone());
        let html = documentation(*kind, request.fmi, &describe, &source, &provenance, &table, &cfg);
        let xml = match request.fmi {
            FmiVersion::V3 => mre_fmu::describe::model_description(*kind, &describe),
            FmiVersion::V2 => mre_fmu::fmi2::describe::model_description(*kind, &describe),
        }
        .map_err(|e| anyhow!(e))?;
        let library = libraries.join(library_file(*kind));
        let binary =
            std::fs::read(&library).with_context(|| format!("cannot read the FMU library {}", library.display()))?;
        let dll = libraries.join(WINDOWS_PLATFORM).join(windows_library_file(*kind));
        let windows = match std::fs::read(&dll) {
            Ok(bytes) => Some(bytes),
            Err(_) => {
                eprintln!(
                    "note: {} carries Linux binaries only (no {}; building it needs rustup target {WINDOWS_TARGET} and {WINDOWS_LINKER})",
                    path.display(),
                    dll.display()
                );
                None
            }
        };
        write_atomic_with(path, |buf| {
            pack(
                buf,
                *kind,
                request.fmi,
                &xml,
                &binary,
                windows.as_deref(),
                &page,
                &text,
                &html,
            )
        })?;
    }
    Ok(kinds.into_iter().map(|(_, p)| p).collect())
}

/// The FMU's `version`: mre's, and the table's CRC (which identifies the model).
pub fn fmu_version(table: &Table) -> String {
    format!("{}+table.{:08x}", env!("CARGO_PKG_VERSION"), table.crc32())
}

/// `generationDateAndTime` (ISO 8601, UTC, to the second): `source_date_epoch`
/// (seconds since 1970, the reproducible-builds convention) if given, else now.
pub fn generation_date(source_date_epoch: Option<&str>) -> Result<String> {
    let seconds = match source_date_epoch {
        Some(text) => text
            .trim()
            .parse::<i64>()
            .with_context(|| format!("SOURCE_DATE_EPOCH={text:?} is not a whole number of seconds"))?,
        None => std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| i64::try_from(d.as_secs()).unwrap_or(i64::MAX)),
    };
    let (days, secs) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    let (y, m, d) = civil_from_days(days);
    Ok(format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs % 3600 / 60,
        secs % 60
    ))
}

/// The proleptic Gregorian date of `days` since 1970-01-01 (H. Hinnant's
/// `civil_from_days`: eras of 400 years from 0000-03-01).
fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn describe_for(kind: Kind, source: &str, table: &Table, cfg: &ControlConfig) -> Describe {
    let (lo, hi) = table.current_range_a();
    let ranges = mre_fmu::ranges::input_ranges(kind, table);
    let version = fmu_version(table);
    let generation_tool = format!("mre {} (rust-fmi fmi-export 0.3)", env!("CARGO_PKG_VERSION"));
    match kind {
        Kind::Damper => Describe {
            model_name: format!("mre damper ({source})"),
            description: format!(
                "MRE impact damper identified by mre from {source} (table format {}, CRC-32 {:#010x}, {} currents {lo}–{hi} A): \
                 force from displacement, velocity and coil current, evaluated by the board's control core",
                table.version(),
                table.crc32(),
                table.entries().len()
            ),
            stop_time_s: 0.05,
            step_size_s: f64::from(cfg.period_s()),
            ranges,
            version,
            generation_tool,
            generation_date_and_time: None,
        },
        Kind::Controller => Describe {
            model_name: format!("mre impact controller ({source})"),
            description: format!(
                "MRE impact controller as the board runs it at {} Hz with {source} (CRC-32 {:#010x}): \
                 {} kg within {} mm of stroke; measured displacement and velocity in, commanded coil current and drive voltage out",
                cfg.rate_hz,
                table.crc32(),
                cfg.law.mass_kg,
                cfg.law.stroke_max_mm
            ),
            stop_time_s: 0.05,
            step_size_s: f64::from(cfg.period_s()),
            ranges,
            version,
            generation_tool,
            generation_date_and_time: None,
        },
    }
}

/// Where the model file says its table came from (`[model]` of `mre fit`'s files).
#[derive(Clone, Debug, Default)]
struct Provenance {
    dataset: Option<String>,
    input_sha256: Option<String>,
    method: Option<String>,
}

impl Provenance {
    fn of(model_toml: &str) -> Self {
        let model = model_toml
            .parse::<toml::Table>()
            .ok()
            .and_then(|t| t.get("model").and_then(|m| m.as_table()).cloned())
            .unwrap_or_default();
        let text = |key: &str| model.get(key).and_then(|v| v.as_str()).map(str::to_owned);
        Provenance {
            dataset: text("dataset"),
            input_sha256: text("input_sha256"),
            method: text("method"),
        }
    }
}

fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `documentation/index.html` of `kind`: what an engineer needs to load it
/// without this repository (the model, the variables with units and declared
/// ranges, the data it came from, the table's CRC, the wiring).
fn documentation(
    kind: Kind,
    fmi: FmiVersion,
    describe: &Describe,
    source: &str,
    provenance: &Provenance,
    table: &Table,
    cfg: &ControlConfig,
) -> String {
    let e = escape_html;
    let mut rows = String::new();
    for v in mre_fmu::describe::variables(kind) {
        let range = describe.ranges.iter().find(|r| r.name == v.name).map_or_else(
            || "–".to_owned(),
            |r| format!("{} … {} (nominal {})", r.min, r.max, r.nominal),
        );
        rows += &format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            e(&v.name),
            v.causality,
            v.unit.unwrap_or("–"),
            e(&range),
            e(&v.description)
        );
    }
    let unknown = || "not recorded in the model file".to_owned();
    let terms = table.terms();
    let (lo, hi) = table.current_range_a();
    let wiring = match kind {
        Kind::Damper => format!(
            "<p>Connect the vehicle's damper compression (m, positive into the damper, 0 at first contact) to \
             <code>displacement_m</code>, its rate (m/s, positive compressing) to <code>velocity_m_s</code>, \
             and the coil current to <code>current_a</code>; apply <code>force_n</code> to the impacting mass \
             (positive resisting compression). The coil current lags its drive by <code>coil_tau_s</code> \
             ({} s): with <code>controller.fmu</code>, feed its <code>coil_current_a</code> (the drive through \
             that lag) to <code>current_a</code>. Co-Simulation: any step (the force is an algebraic function \
             of the inputs); the default experiment steps at {} s. Model Exchange: the velocity is the event \
             indicator of the branch switch (the force jumps where it changes sign); the branch is held between \
             events, so let the solver handle the indicator's zero crossings as state events.</p>",
            terms.coil_tau_s, describe.step_size_s
        ),
        Kind::Controller => format!(
            "<p>Feed the measured compression (m) and its rate (m/s) to <code>displacement_m</code> and \
             <code>velocity_m_s</code> and step with the control period, <code>control_period_s</code> = {} s \
             (the board's {} Hz); the outputs hold between ticks. Close the loop through the coil: its \
             drive goes through the coil's lag (τ = {} s, from the damper's <code>coil_tau_s</code>) to the \
             damper's <code>current_a</code>. The law plans for {} kg within {} mm of stroke.</p>",
            describe.step_size_s, cfg.rate_hz, terms.coil_tau_s, cfg.law.mass_kg, cfg.law.stroke_max_mm
        ),
    };
    let (set, warning) = match fmi {
        FmiVersion::V2 => ("fmi2SetReal", "fmi2Warning"),
        FmiVersion::V3 => ("fmi3SetFloat64", "fmi3Warning"),
    };
    let out_of_range = format!(
        "<p>Inputs outside their declared range, and NaN or infinite inputs, make \
        <code>{set}</code> return <code>{warning}</code> with a log message (enable logging to see \
        it). The value is still used as the board's core uses it: the damper clamps the displacement to each \
        tabulated current's fitted stroke and the current to the table; a NaN displacement counts as the \
        stroke's start, a NaN current as the lowest, a NaN velocity as the extension branch without viscous \
        force. The controller passes them to its sensor checks, which latch its fail-safe current.</p>"
    );
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head><meta charset=\"utf-8\"><title>{title}</title></head>\n<body>\n\
         <h1>{title}</h1>\n<p>{description}</p>\n\
         <h2>Variables</h2>\n<table border=\"1\">\n<tr><th>Name</th><th>Causality</th><th>Unit</th>\
         <th>Declared range</th><th>Description</th></tr>\n{rows}</table>\n{out_of_range}\n\
         <h2>Wiring</h2>\n{wiring}\n\
         <h2>Source</h2>\n<ul>\n<li>Model file: <code>{source}</code> (in this FMU as \
         <code>resources/model.toml</code>; the library reads <code>resources/table.page</code>, the board's \
         flash page)</li>\n<li>Data set: {dataset}</li>\n<li>Data set SHA-256: <code>{sha}</code></li>\n\
         <li>Fit method: {method}</li>\n<li>Table: format {format}, {n} currents {lo}–{hi} A, CRC-32 \
         <code>{crc:#010x}</code></li>\n</ul>\n\
         <p>FMU version {version}, generated by {tool} at {date}.</p>\n</body>\n</html>\n",
        title = e(&describe.model_name),
        description = e(&describe.description),
        source = e(source),
        dataset = e(&provenance.dataset.clone().unwrap_or_else(unknown)),
        sha = e(&provenance.input_sha256.clone().unwrap_or_else(unknown)),
        method = e(&provenance.method.clone().unwrap_or_else(unknown)),
        format = table.version(),
        n = table.entries().len(),
        crc = table.crc32(),
        version = e(&describe.version),
        tool = e(&describe.generation_tool),
        date = e(describe.generation_date_and_time.as_deref().unwrap_or("")),
    )
}

/// The shared library's file name on this platform.
pub fn library_file(kind: Kind) -> String {
    format!("lib{}.so", kind.model_identifier())
}

/// The Windows library's file name (the model identifier, as FMI requires).
pub fn windows_library_file(kind: Kind) -> String {
    format!("{}.dll", kind.model_identifier())
}

#[allow(clippy::too_many_arguments)]
fn pack(
    buf: &mut Vec<u8>,
    kind: Kind,
    fmi: FmiVersion,
    xml: &str,
    binary: &[u8],
    windows: Option<&[u8]>,
    page: &[u8],
    model_toml: &str,
    html: &str,
) -> Result<()> {
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(buf));
    let deflate = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let (linux, windows_platform) = fmi.platforms();
    let mut files: Vec<(String, &[u8])> = vec![
        ("modelDescription.xml".to_owned(), xml.as_bytes()),
        (format!("binaries/{linux}/{}.so", kind.model_identifier()), binary),
        (format!("resources/{}", mre_fmu::page::PAGE_FILE), page),
        ("resources/model.toml".to_owned(), model_toml.as_bytes()),
        ("documentation/index.html".to_owned(), html.as_bytes()),
    ];
    if let Some(dll) = windows {
        files.push((
            format!("binaries/{windows_platform}/{}", windows_library_file(kind)),
            dll,
        ));
    }
    for (name, bytes) in files {
        zip.start_file(name, deflate)?;
        zip.write_all(bytes)?;
    }
    zip.finish()?;
    Ok(())
}

/// The folder holding both FMU libraries (see the module docs).
pub fn library_dir() -> Result<PathBuf> {
    if let Some(dir) = std::env::var_os("MRE_FMU_LIB_DIR") {
        return Ok(PathBuf::from(dir));
    }
    let root = crate::pil::qemu::workspace_root();
    if root.join("host-tools/fmu/Cargo.toml").is_file() {
        return build_libraries(&root);
    }
    let exe = std::env::current_exe().context("cannot locate the running mre")?;
    let dir = exe.parent().map(Path::to_path_buf).unwrap_or_default();
    if dir.join(library_file(Kind::Damper)).is_file() {
        return Ok(dir);
    }
    bail!(
        "no FMU libraries: set MRE_FMU_LIB_DIR to the folder holding {} and {}, or run mre from a source checkout",
        library_file(Kind::Damper),
        library_file(Kind::Controller)
    )
}

/// The FMU crates' library names (`[lib] name` of host-tools/fmu/damper and …/controller).
const LIBRARY_TARGETS: [&str; 2] = ["mre_damper", "mre_controller"];

/// `cargo build --release` of both FMU crates into the workspace's target
/// folder (crate::cargo_build), their libraries copied to `<target>/fmu-libraries`.
fn build_libraries(root: &Path) -> Result<PathBuf> {
    let packages = ["-p", "mre-fmu-damper", "-p", "mre-fmu-controller"];
    let linux = crate::cargo_build::build_and_copy(
        root,
        &[&["build", "--release"][..], &packages[..]].concat(),
        "the FMU libraries",
        &LIBRARY_TARGETS,
        |f| f.extension().is_some_and(|e| e == "so"),
        // <target>/release/libmre_damper.so → <target>/fmu-libraries
        |lib| lib.ancestors().nth(2).unwrap_or(root).join("fmu-libraries"),
    )?;
    let Some(folder) = linux.first().and_then(|lib| lib.parent()).map(Path::to_path_buf) else {
        bail!("building the FMU libraries reported no library");
    };
    if let Err(why) = build_windows_libraries(root, &folder) {
        eprintln!("note: no Windows binaries in the FMUs: {why}");
    }
    Ok(folder)
}

/// Cross-builds both FMU crates for Windows x86_64 (MinGW-w64) and copies
/// the DLLs into `folder/x86_64-windows/`; `Err` says what is missing.
fn build_windows_libraries(root: &Path, folder: &Path) -> std::result::Result<(), String> {
    let found = |program: &str, arg: &str| {
        Command::new(program)
            .arg(arg)
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if !found(WINDOWS_LINKER, "--version") {
        return Err(format!(
            "{WINDOWS_LINKER} is not installed (Debian: apt-get install gcc-mingw-w64-x86-64)"
        ));
    }
    let libdir = Command::new("rustc")
        .args(["--print", "target-libdir", "--target", WINDOWS_TARGET])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()));
    if !libdir.is_some_and(|d| d.is_dir()) {
        return Err(format!(
            "the Rust target {WINDOWS_TARGET} is not installed (rustup target add {WINDOWS_TARGET})"
        ));
    }
    crate::cargo_build::build_and_copy(
        root,
        &[
            "build",
            "--release",
            "--target",
            WINDOWS_TARGET,
            "-p",
            "mre-fmu-damper",
            "-p",
            "mre-fmu-controller",
        ],
        &format!("the FMU libraries for {WINDOWS_TARGET}"),
        &LIBRARY_TARGETS,
        |f| f.extension().is_some_and(|e| e == "dll"),
        |_| folder.join(WINDOWS_PLATFORM),
    )
    .map(|_| ())
    .map_err(|e| format!("{e:#}"))
}
