//! Staging, publication, rollback and the folder marker, on real files.
use super::*;

fn listing(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for e in walk(dir) {
        let rel = e.strip_prefix(dir).unwrap().display().to_string();
        let bytes = if e.is_dir() {
            Vec::new()
        } else {
            std::fs::read(&e).unwrap()
        };
        out.push((rel, bytes));
    }
    out.sort();
    out
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut all = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            all.extend(walk(&p));
        }
        all.push(p);
    }
    all
}

fn three_outputs(root: &Path, text: &str) -> Result<()> {
    write_atomic(&root.join("a.txt"), text.as_bytes())?;
    write_atomic(&root.join("sub/b.txt"), text.as_bytes())?;
    write_atomic(&root.join("new/deeper/c.txt"), text.as_bytes())?;
    Ok(())
}

/// A folder holding a previous run's `a.txt` and `sub/b.txt`, and its listing.
fn previous_outputs() -> (tempfile::TempDir, Vec<(String, Vec<u8>)>) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("a.txt"), "old a").unwrap();
    std::fs::write(dir.path().join("sub/b.txt"), "old b").unwrap();
    let before = listing(dir.path());
    (dir, before)
}

#[test]
fn a_failure_part_way_leaves_the_previous_outputs_exactly() {
    let (dir, before) = previous_outputs();
    for n in 0..3 {
        let err = command_failing_after(n, || three_outputs(dir.path(), "new")).unwrap_err();
        assert!(format!("{err:#}").contains("injected write failure"), "{err:#}");
        assert_eq!(listing(dir.path()), before, "after failing at output {}", n + 1);
    }
    command(|| three_outputs(dir.path(), "new")).unwrap();
    let after = listing(dir.path());
    let text = |name: &str| after.iter().find(|(n, _)| n == name).map(|(_, b)| b.clone());
    assert_eq!(text("a.txt").unwrap(), b"new");
    assert_eq!(text("new/deeper/c.txt").unwrap(), b"new");
    assert_eq!(after.len(), 6, "three files, three folders, no leftovers: {after:?}");
}

#[test]
fn a_failed_rename_rolls_back_the_ones_already_published() {
    let (dir, before) = previous_outputs();
    for n in 0..3 {
        let mut set = OutputSet::default();
        set.fail_publish_after = Some(n);
        for name in ["a.txt", "sub/b.txt", "new/deeper/c.txt"] {
            set.stage_file(&dir.path().join(name), b"new").unwrap();
        }
        let err = set.publish().unwrap_err();
        assert!(err.to_string().contains("injected rename failure"));
        assert_eq!(listing(dir.path()), before, "after {n} renames");
    }
}

#[test]
fn an_error_after_staging_publishes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let err = command(|| -> Result<()> {
        three_outputs(dir.path(), "new")?;
        bail!("later step failed")
    })
    .unwrap_err();
    assert_eq!(err.to_string(), "later step failed");
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn two_outputs_to_one_path_are_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("x.csv");
    let err = command(|| {
        write_atomic(&p, b"1")?;
        write_atomic(&dir.path().join(".").join("x.csv"), b"2")
    })
    .unwrap_err();
    assert!(err.to_string().contains("would both be written to"), "{err:#}");
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn a_file_output_never_replaces_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("results");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("keep.txt"), "mine").unwrap();
    let err = command(|| write_atomic(&target, b"model")).unwrap_err();
    assert!(err.to_string().contains("is a folder"), "{err:#}");
    assert_eq!(std::fs::read_to_string(target.join("keep.txt")).unwrap(), "mine");
}

#[cfg(unix)]
#[test]
fn outputs_get_umask_permissions() {
    use std::os::unix::fs::PermissionsExt;
    // The process umask, read back without changing it for long.
    let dir = tempfile::tempdir().unwrap();
    let probe = dir.path().join("probe");
    std::fs::write(&probe, "").unwrap();
    let expected = std::fs::metadata(&probe).unwrap().permissions().mode() & 0o777;
    write_atomic(&dir.path().join("out.txt"), b"x").unwrap();
    let mode = std::fs::metadata(dir.path().join("out.txt"))
        .unwrap()
        .permissions()
        .mode()
        & 0o777;
    assert_eq!(mode, expected, "{mode:o} vs {expected:o}");
    assert_ne!(mode, 0o600);
}

#[test]
fn folders_are_replaced_only_when_mre_wrote_them() {
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("set");
    let fill = |text: &'static str| move |p: &Path| Ok(std::fs::write(p.join("f"), text)?);
    stage_folder(&set, false, fill("one")).unwrap();
    assert!(set.join(MARKER_FILE).is_file());
    let err = stage_folder(&set, false, fill("two")).unwrap_err();
    assert!(err.to_string().contains("--force"), "{err:#}");
    stage_folder(&set, true, fill("two")).unwrap();
    assert_eq!(std::fs::read_to_string(set.join("f")).unwrap(), "two");

    let theirs = dir.path().join("theirs");
    std::fs::create_dir(&theirs).unwrap();
    std::fs::write(theirs.join("thesis.tex"), "years of work").unwrap();
    let err = stage_folder(&theirs, true, fill("x")).unwrap_err();
    assert!(err.to_string().contains("not written by mre"), "{err:#}");
    assert_eq!(
        std::fs::read_to_string(theirs.join("thesis.tex")).unwrap(),
        "years of work"
    );
    let names: Vec<String> = listing(dir.path()).into_iter().map(|(n, _)| n).collect();
    assert!(
        names
            .iter()
            .all(|n| !n.contains(".mre-stage") && !n.contains(".mre-old")),
        "{names:?}"
    );
}

#[test]
fn a_staged_folder_is_discarded_with_its_command() {
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("set");
    stage_folder(&set, true, |p| Ok(std::fs::write(p.join("f"), "old")?)).unwrap();
    let before = listing(dir.path());
    let err = command_failing_after(1, || {
        stage_folder(&set, true, |p| Ok(std::fs::write(p.join("f"), "new")?))?;
        write_atomic(&dir.path().join("key.json"), b"{}")
    })
    .unwrap_err();
    assert!(format!("{err:#}").contains("injected"), "{err:#}");
    assert_eq!(listing(dir.path()), before);
}
