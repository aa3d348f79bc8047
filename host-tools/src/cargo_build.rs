//! Builds that `mre` runs itself from a source checkout: the FMU libraries
//! and the firmware images. They go into the workspace's own target folder
//! (or `$CARGO_TARGET_DIR`), so they reuse the dependencies the host build
//! already compiled instead of compiling them again elsewhere.
//!
//! Cargo puts a binary at one path per target and profile whatever its
//! features, so two firmware variants overwrite each other's ELF. Each build
//! here therefore copies what it made to a folder named after its variant,
//! holding a lock from the build to the copy so that threads of one process
//! (the tests) never copy each other's image.
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;

/// One file cargo reported building.
#[derive(Debug, Clone)]
pub struct Artifact {
    /// The cargo target's name (`mre-firmware`, `mre_damper`).
    pub target_name: String,
    /// Its outputs (a library's `.so` / `.dll` / `.rlib`, a binary's executable).
    pub files: Vec<PathBuf>,
}

/// Serialises build-then-copy within this process (see the module docs).
static BUILD_THEN_COPY: Mutex<()> = Mutex::new(());

/// Runs `cargo <args>` in `root` and returns the artifacts it reports. Cargo's
/// diagnostics go to stderr as usual; a failed build is an error naming `what`.
pub fn cargo_build(root: &Path, args: &[&str], what: &str) -> Result<Vec<Artifact>> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(root)
        .args(args)
        .args(["--quiet", "--message-format=json-render-diagnostics"])
        .stderr(Stdio::inherit())
        .output()
        .with_context(|| format!("cannot run cargo to build {what}"))?;
    if !output.status.success() {
        bail!(
            "building {what} failed (cargo {}: {}); cargo's output above names the cause",
            args.join(" "),
            output.status
        );
    }
    Ok(String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| serde_json::from_str::<serde_json::Value>(line).ok())
        .filter(|m| m["reason"] == "compiler-artifact")
        .map(|m| Artifact {
            target_name: m["target"]["name"].as_str().unwrap_or_default().to_string(),
            files: m["filenames"]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|f| f.as_str().map(PathBuf::from))
                .collect(),
        })
        .collect())
}

/// Builds with `cargo <args>` and copies the files of `target_name` that
/// `keep` accepts into `into` (created), under the process-wide lock. Returns
/// the copies.
pub fn build_and_copy(
    root: &Path,
    args: &[&str],
    what: &str,
    target_names: &[&str],
    keep: impl Fn(&Path) -> bool,
    into: impl FnOnce(&Path) -> PathBuf,
) -> Result<Vec<PathBuf>> {
    let _held = BUILD_THEN_COPY.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let artifacts = cargo_build(root, args, what)?;
    let files: Vec<&PathBuf> = artifacts
        .iter()
        .filter(|a| target_names.contains(&a.target_name.as_str()))
        .flat_map(|a| &a.files)
        .filter(|f| keep(f))
        .collect();
    let Some(first) = files.first() else {
        bail!(
            "cargo {} reported no file of {}",
            args.join(" "),
            target_names.join(", ")
        );
    };
    let dir = into(first);
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut copies = Vec::new();
    for file in files {
        let name = file.file_name().context("an artifact without a file name")?;
        let copy = dir.join(name);
        // Copy beside, then rename: a reader never sees half a library.
        let partial = dir.join(format!(".{}.partial", name.to_string_lossy()));
        std::fs::copy(file, &partial).with_context(|| format!("cannot copy {}", file.display()))?;
        std::fs::rename(&partial, &copy).with_context(|| format!("cannot write {}", copy.display()))?;
        copies.push(copy);
    }
    Ok(copies)
}

/// The firmware image of the cargo alias `alias` (`fw`, `fw-nucleo`, `fw-pil`,
/// `fw-pil-rtt`; .cargo/config.toml), built and copied to
/// `<target>/images/<alias>/mre-firmware`. Returns that path.
pub fn firmware_image(root: &Path, alias: &str) -> Result<PathBuf> {
    let copies = build_and_copy(
        root,
        &[alias],
        &format!("the firmware image (cargo {alias})"),
        &["mre-firmware"],
        |f| f.extension().is_none(),
        // <target>/thumbv7em-none-eabihf/firmware/mre-firmware → <target>/images/<alias>
        |elf| {
            elf.ancestors()
                .nth(3)
                .map_or_else(|| root.join("target"), Path::to_path_buf)
                .join("images")
                .join(alias)
        },
    )?;
    copies
        .into_iter()
        .next()
        .with_context(|| format!("cargo {alias} reported no image"))
}
