//! Whole-command output staging: a command's outputs appear all together or
//! not at all.
//!
//! Inside [`command`] every [`write_atomic`] (and every [`stage_folder`]) only
//! *stages* its output: the bytes go to a hidden temporary file (or folder)
//! beside the destination. When the command returns `Ok`, all staged outputs
//! are renamed into place in one step; if any rename fails, the ones already
//! moved are rolled back and the previous outputs are restored. When the
//! command fails (an error, a full disk, a panic), the staged files are
//! deleted and folders created for them are removed again: the previous
//! outputs stay exactly as they were and nothing is left behind.
//!
//! Outside [`command`], [`write_atomic`] publishes each file at once (same
//! temp-file-and-rename, one file per step). The CLI runs every command but
//! `demo` inside [`command`]; `demo` builds its whole output folder with
//! [`stage_folder`] instead, because its later steps read what earlier ones
//! wrote.
//!
//! The output set belongs to the thread that runs the command: write outputs
//! from that thread (rayon workers compute; they do not write).
//!
//! Two outputs of one command with the same destination are an error, never a
//! silent overwrite. Outputs get the ordinary permissions the umask gives
//! (temporary files are created 0666 & !umask, not tempfile's private 0600).
use anyhow::{bail, Context, Result};
use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};

/// File inside every folder mre writes whole (data sets, the demo's output):
/// only such a folder may be replaced (`--force`).
pub const MARKER_FILE: &str = ".mre-output";
const MARKER_TEXT: &str = "This folder was written by mre; `mre ... --force` may replace it.\n";

thread_local! {
    /// The output set of the command running on this thread, if any.
    static ACTIVE: RefCell<Option<OutputSet>> = const { RefCell::new(None) };
}

/// Runs `f` as one command: its outputs are published together when it
/// returns `Ok` and discarded otherwise (see the module docs). A `command`
/// inside another joins the outer one.
pub fn command<T>(f: impl FnOnce() -> Result<T>) -> Result<T> {
    run_command(None, f)
}

/// Runs `f` outside the running command's output set: its writes publish at
/// once. For scratch files a command writes and reads back itself (a
/// recorded campaign in a temporary folder), never for its outputs.
pub fn scratch<T>(f: impl FnOnce() -> Result<T>) -> Result<T> {
    let suspended = ACTIVE.with(|a| a.borrow_mut().take());
    /// Puts the suspended set back however `f` ends, including by a panic.
    struct Restore(Option<OutputSet>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let set = self.0.take();
            let _ = ACTIVE.try_with(|a| *a.borrow_mut() = set);
        }
    }
    let _restore = Restore(suspended);
    f()
}

/// [`command`] with an injected fault, for tests: staging the output after
/// the first `writes` ones fails part-way through its bytes, as a full disk
/// would.
pub fn command_failing_after<T>(writes: usize, f: impl FnOnce() -> Result<T>) -> Result<T> {
    run_command(Some(writes), f)
}

fn run_command<T>(fail_after: Option<usize>, f: impl FnOnce() -> Result<T>) -> Result<T> {
    if ACTIVE.with(|a| a.borrow().is_some()) {
        return f();
    }
    /// Discards the set however `f` ends, including by a panic.
    struct Scope;
    impl Drop for Scope {
        fn drop(&mut self) {
            let _ = ACTIVE.try_with(|a| a.borrow_mut().take());
        }
    }
    ACTIVE.with(|a| {
        *a.borrow_mut() = Some(OutputSet {
            staged: Vec::new(),
            created_dirs: Vec::new(),
            fail_after,
            fail_publish_after: None,
        })
    });
    let scope = Scope;
    let result = f();
    let set = ACTIVE.with(|a| a.borrow_mut().take());
    drop(scope);
    let value = result?;
    if let Some(set) = set {
        set.publish()?;
    }
    Ok(value)
}

/// Writes `bytes` to `path`: staged when inside [`command`], else at once
/// (same-folder temporary file renamed into place).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    with_set(|set| set.stage_file(path, bytes))
}

/// Like [`write_atomic`], for text produced by a closure that may fail:
/// nothing is written unless the closure succeeds.
pub fn write_atomic_with(path: &Path, produce: impl FnOnce(&mut Vec<u8>) -> Result<()>) -> Result<()> {
    let mut buf = Vec::new();
    produce(&mut buf)?;
    write_atomic(path, &buf)
}

/// Builds the folder `dest` whole: `fill` writes into an empty private
/// folder (plain writes; nothing there is visible until publication), a
/// [`MARKER_FILE`] is added, and the folder is staged (inside [`command`]) or
/// renamed into place at once.
///
/// An existing empty folder is replaced. A non-empty one only when `replace`
/// is set *and* it holds the marker, i.e. mre wrote it.
pub fn stage_folder(dest: &Path, replace: bool, fill: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    check_replaceable(dest, replace)?;
    let parent = parent_of(dest);
    let mut created = Vec::new();
    let staged = (|| {
        create_parents(parent, &mut created)?;
        let mut builder = tempfile::Builder::new();
        builder.prefix(".mre-stage-");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o777));
        }
        let tmp = interrupt::create_tracked(|| builder.tempdir_in(parent), |t| t.path())
            .with_context(|| format!("cannot create a temporary folder in {}", parent.display()))?;
        fill(tmp.path())?;
        std::fs::write(tmp.path().join(MARKER_FILE), MARKER_TEXT)
            .with_context(|| format!("cannot write {}", dest.join(MARKER_FILE).display()))?;
        Ok(tmp)
    })();
    let tmp = match staged {
        Ok(tmp) => tmp,
        Err(e) => {
            remove_created(&created);
            return Err(e);
        }
    };
    with_set(|set| {
        set.created_dirs.extend(created);
        if set.fail_after == Some(set.staged.len()) {
            bail!("cannot write {}: injected write failure (disk full)", dest.display());
        }
        set.push(Staged::Folder {
            tmp,
            dest: dest.to_path_buf(),
        })
    })
}

/// Refuses to replace a non-folder, or a non-empty folder mre did not write.
fn check_replaceable(dest: &Path, replace: bool) -> Result<()> {
    let Ok(meta) = std::fs::symlink_metadata(dest) else {
        return Ok(());
    };
    if !meta.is_dir() {
        bail!("{} exists and is not a folder", dest.display());
    }
    let non_empty = std::fs::read_dir(dest)
        .with_context(|| format!("cannot read {}", dest.display()))?
        .next()
        .is_some();
    if !non_empty {
        return Ok(());
    }
    if !replace {
        bail!("{} exists and is not empty; pass --force to replace it", dest.display());
    }
    if !dest.join(MARKER_FILE).is_file() {
        bail!(
            "{} was not written by mre (it has no {MARKER_FILE} file); not replacing it: move it away or choose another folder",
            dest.display()
        );
    }
    Ok(())
}

/// Runs `f` on the active set, or on a one-output set published at once.
fn with_set(f: impl FnOnce(&mut OutputSet) -> Result<()>) -> Result<()> {
    match ACTIVE.with(|a| a.borrow_mut().take()) {
        Some(mut set) => {
            let result = f(&mut set);
            ACTIVE.with(|a| *a.borrow_mut() = Some(set));
            result
        }
        None => {
            let mut set = OutputSet::default();
            f(&mut set)?;
            set.publish()
        }
    }
}

enum Staged {
    File { tmp: tempfile::TempPath, dest: PathBuf },
    Folder { tmp: tempfile::TempDir, dest: PathBuf },
}

impl Staged {
    fn dest(&self) -> &Path {
        match self {
            Staged::File { dest, .. } | Staged::Folder { dest, .. } => dest,
        }
    }
}

/// Outputs staged so far; dropping it unpublished deletes them.
#[derive(Default)]
struct OutputSet {
    staged: Vec<Staged>,
    /// Folders created to hold staged outputs, outermost first.
    created_dirs: Vec<PathBuf>,
    /// Fault injection: the output after this many fails part-way.
    fail_after: Option<usize>,
    /// Fault injection (unit tests): renaming the output after this many fails.
    fail_publish_after: Option<usize>,
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        self.staged.clear();
        remove_created(&self.created_dirs);
    }
}

fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Creates `dir` and its missing ancestors, recording each one created.
fn create_parents(dir: &Path, created: &mut Vec<PathBuf>) -> Result<()> {
    let missing: Vec<&Path> = dir
        .ancestors()
        .take_while(|d| !d.as_os_str().is_empty() && !d.exists())
        .collect();
    for d in missing.into_iter().rev() {
        std::fs::create_dir(d).with_context(|| format!("cannot create folder {}", d.display()))?;
        created.push(d.to_path_buf());
    }
    Ok(())
}

/// Removes folders this command created, innermost first, if still empty.
fn remove_created(created: &[PathBuf]) {
    for d in created.iter().rev() {
        let _ = std::fs::remove_dir(d);
    }
}

pub(crate) fn same_path(a: &Path, b: &Path) -> bool {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    abs(a) == abs(b)
}

impl OutputSet {
    fn push(&mut self, entry: Staged) -> Result<()> {
        if self.staged.iter().any(|s| same_path(s.dest(), entry.dest())) {
            bail!(
                "two outputs of this command would both be written to {}; nothing was written",
                entry.dest().display()
            );
        }
        self.staged.push(entry);
        Ok(())
    }

    fn stage_file(&mut self, path: &Path, bytes: &[u8]) -> Result<()> {
        if self.staged.iter().any(|s| same_path(s.dest(), path)) {
            bail!(
                "two outputs of this command would both be written to {}; nothing was written",
                path.display()
            );
        }
        // Never move a folder aside (and delete it) to put a file in its place.
        if std::fs::symlink_metadata(path).is_ok_and(|m| m.is_dir()) {
            bail!("{} is a folder; the output file cannot replace it", path.display());
        }
        let dir = parent_of(path);
        create_parents(dir, &mut self.created_dirs)?;
        let mut builder = tempfile::Builder::new();
        builder.prefix(".mre-").suffix(".tmp");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let mut tmp = interrupt::create_tracked(|| builder.tempfile_in(dir), |t| t.path())
            .with_context(|| format!("cannot create a temporary file in {}", dir.display()))?;
        let injected = self.fail_after == Some(self.staged.len());
        let written = if injected {
            tmp.write_all(&bytes[..bytes.len() / 2])
                .and_then(|()| Err(std::io::Error::other("injected write failure (disk full)")))
        } else {
            tmp.write_all(bytes).and_then(|()| tmp.as_file().sync_all())
        };
        written.with_context(|| format!("cannot write {}", path.display()))?;
        self.push(Staged::File {
            tmp: tmp.into_temp_path(),
            dest: path.to_path_buf(),
        })
    }

    /// Renames every staged output into place; on a failure, undoes the
    /// ones already moved and restores what they replaced.
    fn publish(mut self) -> Result<()> {
        let mut done: Vec<Published> = Vec::new();
        for (k, entry) in std::mem::take(&mut self.staged).into_iter().enumerate() {
            let result = match self.fail_publish_after {
                Some(n) if n == k => Err(anyhow::anyhow!("injected rename failure")),
                _ => publish_one(entry),
            };
            match result {
                Ok(p) => done.push(p),
                Err(e) => {
                    for p in done.into_iter().rev() {
                        p.undo();
                    }
                    return Err(e);
                }
            }
        }
        for p in done {
            p.discard_old();
        }
        self.created_dirs.clear();
        Ok(())
    }
}

/// One output moved into place, and where the output it replaced went.
struct Published {
    dest: PathBuf,
    old: Option<PathBuf>,
    is_dir: bool,
}

impl Published {
    fn remove(path: &Path, is_dir: bool) {
        let _ = if is_dir {
            std::fs::remove_dir_all(path)
        } else {
            std::fs::remove_file(path)
        };
    }

    fn undo(self) {
        Self::remove(&self.dest, self.is_dir);
        if let Some(old) = &self.old {
            let _ = std::fs::rename(old, &self.dest);
        }
    }

    fn discard_old(self) {
        if let Some(old) = &self.old {
            let old_is_dir = std::fs::symlink_metadata(old).is_ok_and(|m| m.is_dir());
            Self::remove(old, old_is_dir);
        }
    }
}

/// Moves an existing `dest` to a fresh hidden name beside it.
fn move_aside(dest: &Path) -> Result<Option<PathBuf>> {
    let Ok(meta) = std::fs::symlink_metadata(dest) else {
        return Ok(None);
    };
    let dir = parent_of(dest);
    let builder = {
        let mut b = tempfile::Builder::new();
        b.prefix(".mre-old-");
        b
    };
    // Reserve a name of the same kind, then rename over it (POSIX rename
    // replaces an empty folder by a folder and a file by a file).
    let aside = if meta.is_dir() {
        builder.tempdir_in(dir).map(|d| d.keep())
    } else {
        builder
            .tempfile_in(dir)
            .and_then(|f| f.into_temp_path().keep().map_err(|e| e.error))
    }
    .with_context(|| format!("cannot create a temporary name in {}", dir.display()))?;
    if let Err(e) = std::fs::rename(dest, &aside) {
        Published::remove(&aside, meta.is_dir());
        return Err(e).with_context(|| format!("cannot move {} aside", dest.display()));
    }
    Ok(Some(aside))
}

fn publish_one(entry: Staged) -> Result<Published> {
    let is_dir = matches!(entry, Staged::Folder { .. });
    let dest = entry.dest().to_path_buf();
    let old = move_aside(&dest)?;
    let moved = match entry {
        Staged::File { tmp, dest } => tmp.persist(&dest).map_err(|e| e.error),
        Staged::Folder { tmp, dest } => {
            let path = tmp.keep();
            std::fs::rename(&path, &dest).inspect_err(|_| {
                let _ = std::fs::remove_dir_all(&path);
            })
        }
    };
    if let Err(e) = moved {
        if let Some(old) = &old {
            let _ = std::fs::rename(old, &dest);
        }
        return Err(e).with_context(|| format!("cannot move the new output into {}", dest.display()));
    }
    Ok(Published { dest, old, is_dir })
}

/// The files `dir` will hold once this command's outputs are published: its
/// staged files there and the files already on disk (hidden ones left out),
/// each as (destination, path to read its bytes from now), sorted by name.
/// Lets a report page written last (the HTML report) see the outputs that
/// were staged before it.
pub fn files_in(dir: &Path) -> Vec<(PathBuf, PathBuf)> {
    let mut files: Vec<(PathBuf, PathBuf)> = ACTIVE.with(|a| {
        a.borrow()
            .iter()
            .flat_map(|set| set.staged.iter())
            .filter_map(|s| match s {
                Staged::File { tmp, dest } if same_path(parent_of(dest), dir) => {
                    Some((dest.clone(), tmp.to_path_buf()))
                }
                _ => None,
            })
            .collect()
    });
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let path = e.path();
            let hidden = e.file_name().to_string_lossy().starts_with('.');
            let staged = files.iter().any(|(d, _)| same_path(d, &path));
            if !hidden && !staged && path.is_file() {
                files.push((path.clone(), path));
            }
        }
    }
    files.sort_by(|a, b| a.0.file_name().cmp(&b.0.file_name()));
    files
}

pub mod interrupt;
#[cfg(test)]
mod tests;
