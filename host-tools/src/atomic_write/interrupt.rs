//! An interrupted command (Ctrl-C, SIGTERM, SIGHUP) leaves nothing behind: the
//! staging files and folders it had created are removed before it exits with
//! status 130. Without this, killing `mre demo` left its whole staging folder
//! (tens of MB, named `.mre-stage-…`) beside `--out`.
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Staging paths created by this process. One that was published has been
/// renamed away, so removing it again does nothing.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Records a staging file or folder for removal on interruption.
pub(super) fn track(path: &Path) {
    if let Ok(mut live) = LIVE.lock() {
        live.push(path.to_path_buf());
    }
}

/// Removes every staging path still on disk (outputs already published are
/// left as they are: they were complete when renamed into place).
pub fn remove_staging() {
    let paths = LIVE.lock().map(|live| live.clone()).unwrap_or_default();
    for path in paths.iter().rev() {
        match std::fs::symlink_metadata(path) {
            Ok(meta) if meta.is_dir() => drop(std::fs::remove_dir_all(path)),
            Ok(_) => drop(std::fs::remove_file(path)),
            Err(_) => {}
        }
    }
}

/// Installs the handler once per process: staging removed, exit status 130
/// (128 + SIGINT, what shells report for Ctrl-C).
pub fn install() -> anyhow::Result<()> {
    ctrlc::set_handler(|| {
        remove_staging();
        eprintln!("interrupted: no output was written");
        std::process::exit(130);
    })
    .map_err(|e| anyhow::anyhow!("cannot install the interrupt handler: {e}"))
}
