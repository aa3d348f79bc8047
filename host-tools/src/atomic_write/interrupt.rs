//! An interrupted command (Ctrl-C, SIGTERM, SIGHUP) leaves nothing behind: the
//! staging files and folders it had created are removed before it exits with
//! status 130. Without this, killing `mre demo` left its whole staging folder
//! (tens of MB, named `.mre-stage-…`) beside `--out`.
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::Duration;

/// Staging paths created by this process. One that was published has been
/// renamed away, so removing it again does nothing.
static LIVE: Registry = Registry::new();

/// The staging paths one process created, for removal on interruption.
pub(crate) struct Registry {
    paths: Mutex<Vec<PathBuf>>,
}

impl Registry {
    pub(crate) const fn new() -> Self {
        Self {
            paths: Mutex::new(Vec::new()),
        }
    }

    /// Creates a staging file or folder with `create` and records it, both
    /// under the lock [`Registry::remove_all`] takes: an interruption between
    /// the two would otherwise leave a path nobody removes.
    pub(crate) fn create_tracked<T>(
        &self,
        create: impl FnOnce() -> std::io::Result<T>,
        path_of: impl Fn(&T) -> &Path,
    ) -> std::io::Result<T> {
        let mut paths = self.paths.lock().unwrap_or_else(PoisonError::into_inner);
        let created = create()?;
        paths.push(path_of(&created).to_path_buf());
        Ok(created)
    }

    /// Removes every recorded path still on disk. The command's own thread
    /// keeps running meanwhile and may be writing into a folder being
    /// removed, faster than `remove_dir_all` unlinks (which then fails with
    /// "directory not empty"). So each path is first renamed aside, which
    /// makes every later write under its old name fail, and then removed;
    /// this repeats until every path has stayed gone for two rounds (at most
    /// 100). The lock is held throughout, so no new staging path appears.
    pub(crate) fn remove_all(&self) {
        let paths = self.paths.lock().unwrap_or_else(PoisonError::into_inner);
        let mut quiet_rounds = 0;
        for round in 0..100 {
            let mut found = false;
            for path in paths.iter().rev() {
                if std::fs::symlink_metadata(path).is_err() {
                    continue;
                }
                found = true;
                let aside = aside_name(path, round);
                let doomed = if std::fs::rename(path, &aside).is_ok() {
                    aside
                } else {
                    path.clone()
                };
                match std::fs::symlink_metadata(&doomed) {
                    Ok(meta) if meta.is_dir() => drop(std::fs::remove_dir_all(&doomed)),
                    Ok(_) => drop(std::fs::remove_file(&doomed)),
                    Err(_) => {}
                }
            }
            quiet_rounds = if found { 0 } else { quiet_rounds + 1 };
            if quiet_rounds == 2 {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

/// `<name>-removing-<round>` beside `path`: the same folder, so the rename
/// is atomic, and still a `.mre-` name should removal fail.
fn aside_name(path: &Path, round: usize) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!("-removing-{round}"));
    path.with_file_name(name)
}

/// [`Registry::create_tracked`] on this process's registry.
pub(super) fn create_tracked<T>(
    create: impl FnOnce() -> std::io::Result<T>,
    path_of: impl Fn(&T) -> &Path,
) -> std::io::Result<T> {
    LIVE.create_tracked(create, path_of)
}

/// Removes every staging path still on disk (outputs already published are
/// left as they are: they were complete when renamed into place).
pub fn remove_staging() {
    LIVE.remove_all();
}

/// Set when the handler starts, before it removes anything.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Called by `main` before it exits: once interrupted, the command's own
/// result does not count. Its step may have failed only because the handler
/// renamed its staging folder away ("cannot read … model.toml"), and exiting
/// with that error (status 1) would race the handler's status 130; so this
/// thread waits for the handler to finish and exit the process.
pub fn defer_to_handler_if_interrupted() {
    while INTERRUPTED.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Installs the handler once per process: staging removed, exit status 130
/// (128 + SIGINT, what shells report for Ctrl-C).
pub fn install() -> anyhow::Result<()> {
    ctrlc::set_handler(|| {
        INTERRUPTED.store(true, Ordering::SeqCst);
        remove_staging();
        eprintln!("interrupted: no output was written");
        std::process::exit(130);
    })
    .map_err(|e| anyhow::anyhow!("cannot install the interrupt handler: {e}"))
}

#[cfg(test)]
mod tests {
    use super::Registry;
    use std::sync::atomic::{AtomicBool, Ordering};

    /// A writer keeps adding files to a staging folder while it is removed,
    /// as the demo's own thread does when SIGTERM arrives mid-step. One pass
    /// of `remove_dir_all` loses that race ("directory not empty"); the
    /// repeated removal must leave nothing, in every one of 20 trials.
    #[test]
    fn a_folder_written_into_during_removal_is_still_removed() {
        let parent = tempfile::tempdir().unwrap();
        for trial in 0..20 {
            let registry = Registry::new();
            let staging = registry
                .create_tracked(
                    || tempfile::Builder::new().prefix(".mre-stage-").tempdir_in(parent.path()),
                    |t| t.path(),
                )
                .unwrap()
                .keep();
            for n in 0..200 {
                std::fs::write(staging.join(format!("seed{n}")), b"x").unwrap();
            }
            let stop = AtomicBool::new(false);
            std::thread::scope(|s| {
                s.spawn(|| {
                    let mut n = 0u64;
                    // Writes fail once the folder is gone; keep trying, as
                    // a running step would, until the trial ends.
                    while !stop.load(Ordering::Relaxed) {
                        drop(std::fs::write(staging.join(format!("w{n}")), b"x"));
                        n += 1;
                    }
                });
                registry.remove_all();
                let left = staging.exists();
                stop.store(true, Ordering::Relaxed);
                assert!(!left, "trial {trial}: the staging folder survived its removal");
            });
        }
    }
}
