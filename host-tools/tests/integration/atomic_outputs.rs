//! Whole-command atomicity, command by command: a run that fails part-way
//! (a write failure injected after the first outputs, as a full disk would
//! cause) leaves the previous run's outputs exactly as they were and no
//! temporary file. Each case first checks that a successful second run
//! *does* change the outputs, so the comparison could fail.
use anyhow::Result;
use mre_host::atomic_write::{command, command_failing_after, MARKER_FILE};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// Every file and folder under `root` with its bytes (folders: empty).
fn snapshot(root: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(root).unwrap().display().to_string();
            if p.is_dir() {
                out.insert(format!("{rel}/"), Vec::new());
                walk(root, &p, out);
            } else {
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(root, root, &mut out);
    out
}

/// Runs `old` (the previous outputs), then `new` failing after 1, 2, …
/// `fail_points` outputs; then `new` for real, which must change the tree.
fn check_part_way(root: &Path, fail_points: &[usize], old: impl Fn() -> Result<()>, new: impl Fn() -> Result<()>) {
    command(&old).expect("the first run");
    let before = snapshot(root);
    assert!(!before.is_empty());
    for &n in fail_points {
        let err = command_failing_after(n, &new).expect_err("the injected failure must fail the run");
        assert!(format!("{err:#}").contains("injected write failure"), "{err:#}");
        let after = snapshot(root);
        let leftovers: Vec<&String> = after
            .keys()
            .filter(|k| k.contains(".mre-") && !k.ends_with(MARKER_FILE))
            .collect();
        assert!(
            leftovers.is_empty(),
            "temporary files left after failing at output {}: {leftovers:?}",
            n + 1
        );
        assert!(
            after == before,
            "failing at output {} changed the previous outputs",
            n + 1
        );
    }
    command(&new).expect("the second run");
    assert_ne!(
        snapshot(root),
        before,
        "the second run must change the outputs, or this test proves nothing"
    );
}

#[test]
fn validate_fails_part_way_without_touching_the_previous_report() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report");
    let data = repo("data/mr-damper-mts");
    let run = |model: &str| {
        let (data, report) = (data.clone(), report.clone());
        let model = model.to_owned();
        move || mre_host::validate::run_validate(&data, &model, &[0.5], &report).map(drop)
    };
    let model = repo("models/mr-damper-mts.toml").display().to_string();
    check_part_way(dir.path(), &[1], run(&model), run("paper"));
}

#[test]
fn plot_fails_part_way_without_touching_the_previous_figures() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plots");
    let data = repo("data/mr-damper-mts");
    let run = |model: PathBuf| {
        let (data, out) = (data.clone(), out.clone());
        move || {
            let options = mre_host::plot::PlotOptions { interpolated_a: vec![] };
            mre_host::plot::run_plot(&data, &model, &[0.5], &options, &out).map(drop)
        }
    };
    check_part_way(
        dir.path(),
        &[1, 4],
        run(repo("models/mr-damper-mts.toml")),
        run(repo("data/paper/table4.toml")),
    );
}

#[test]
fn sim_fails_part_way_without_touching_the_previous_report() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("sim");
    let run = |seed: u64| {
        let report = report.clone();
        move || {
            let request = mre_host::plant::closed_loop::SimRequest {
                seed,
                ..Default::default()
            };
            mre_host::plant::closed_loop::run_sim(&request, &report).map(drop)
        }
    };
    check_part_way(dir.path(), &[1, 3], run(0), run(1));
}

#[test]
fn diagnose_fails_part_way_across_its_three_destinations() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().to_path_buf();
    let run = |set: &str| {
        let data = repo("data").join(set);
        let root = root.clone();
        move || {
            let opts = mre_host::diagnose::DiagnoseOptions::default();
            let (rep, json, pred) = (root.join("rep"), root.join("r.json"), root.join("pred"));
            mre_host::diagnose::run_to_files(&data, &opts, &rep, &json, &pred).map(drop)
        }
    };
    // Output 1 is a plot in rep/, output 5 a predictions CSV in pred/.
    check_part_way(dir.path(), &[1, 5], run("drop-none"), run("drop-viscous_damping"));
}

#[test]
fn synth_fails_part_way_keeping_the_previous_set_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    let run = |seed: u64| {
        let out = out.clone();
        move || mre_host::plant::synth::write_synth("none", seed, &out, None, true).map(drop)
    };
    // Output 0 is the data set folder, output 1 the key file.
    check_part_way(dir.path(), &[0, 1], run(1), run(2));
}

#[test]
fn fit_and_tables_fail_without_touching_the_previous_file() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("generated_table.rs");
    let run = |model: PathBuf| {
        let table = table.clone();
        move || mre_host::tables::run_tables(&model, &table).map(drop)
    };
    check_part_way(
        dir.path(),
        &[0],
        run(repo("models/mr-damper-mts.toml")),
        run(repo("data/paper/table4.toml")),
    );
}

#[test]
fn diagnose_refuses_colliding_prediction_names() {
    // `a.csv` and `a.txt` would both become `a.predictions.csv`.
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    std::fs::create_dir(&data).unwrap();
    let src = repo("data/drop-none");
    for e in std::fs::read_dir(&src).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, data.join(p.file_name().unwrap())).unwrap();
    }
    // One more recording: the first one again, as `.txt`.
    std::fs::copy(src.join("i0.0_v1.40_r1.csv"), data.join("i0.0_v1.40_r1.txt")).unwrap();
    let mut manifest = std::fs::read_to_string(src.join("dataset.toml")).unwrap();
    manifest.push_str("\n[[recording]]\nfile = \"i0.0_v1.40_r1.txt\"\ncurrent_a = 0.0\n");
    std::fs::write(data.join("dataset.toml"), manifest).unwrap();
    let out = dir.path().join("out");
    let err = command(|| {
        let opts = mre_host::diagnose::DiagnoseOptions::default();
        mre_host::diagnose::run_to_files(&data, &opts, &out.join("rep"), &out.join("r.json"), &out.join("pred"))
    })
    .unwrap_err();
    assert!(format!("{err:#}").contains("would both be written to"), "{err:#}");
    assert!(format!("{err:#}").contains(".predictions.csv"), "{err:#}");
    assert!(!out.exists(), "nothing is written");
}

#[test]
fn synth_keeps_an_existing_key_file_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    let key = dir.path().join("set.key.json");
    std::fs::write(&key, "the answer to last week's blind test").unwrap();
    let err = command(|| mre_host::plant::synth::write_synth("none", 1, &out, None, false)).unwrap_err();
    assert!(format!("{err:#}").contains("--force"), "{err:#}");
    assert_eq!(
        std::fs::read_to_string(&key).unwrap(),
        "the answer to last week's blind test"
    );
    assert!(!out.exists());
}

#[test]
fn force_replaces_only_a_folder_mre_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("thesis");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("chapter1.tex"), "years of work").unwrap();
    let err = command(|| mre_host::plant::synth::write_synth("none", 1, &out, None, true)).unwrap_err();
    assert!(format!("{err:#}").contains("not written by mre"), "{err:#}");
    assert_eq!(
        std::fs::read_to_string(out.join("chapter1.tex")).unwrap(),
        "years of work"
    );
    assert!(!dir.path().join("thesis.key.json").exists());
}

/// A real full disk, through the binary users run: `mre plot` onto a small
/// tmpfs filled so that only half of the new figures fit. Needs root (to
/// mount); elsewhere it says SKIPPED on stderr.
#[test]
fn the_cli_on_a_full_disk_keeps_the_previous_outputs() {
    use std::io::Write;
    use std::process::Command;
    let dir = tempfile::tempdir().unwrap();
    let mnt = dir.path().join("mnt");
    std::fs::create_dir(&mnt).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=16m", "tmpfs"])
        .arg(&mnt)
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("SKIPPED the_cli_on_a_full_disk_keeps_the_previous_outputs: cannot mount a tmpfs (needs root)");
        return;
    }
    struct Unmount(PathBuf);
    impl Drop for Unmount {
        fn drop(&mut self) {
            let _ = Command::new("umount").arg(&self.0).status();
        }
    }
    let _unmount = Unmount(mnt.clone());
    let out = mnt.join("plots");
    let plot = |model: &str| {
        Command::new(env!("CARGO_BIN_EXE_mre"))
            .arg("plot")
            .arg(repo("data/mr-damper-mts"))
            .arg("--model")
            .arg(repo(model))
            .args(["--hold-out-current", "0.5", "--out"])
            .arg(&out)
            .output()
            .unwrap()
    };
    let first = plot("models/mr-damper-mts.toml");
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    let before = snapshot(&mnt);
    let total: usize = before.values().map(Vec::len).sum();

    // Fill the disk, then free half the size of one run's outputs.
    let filler = mnt.join("filler");
    let mut f = std::fs::File::create(&filler).unwrap();
    let chunk = vec![0u8; 64 * 1024];
    let mut written = 0u64;
    while f.write_all(&chunk).is_ok() {
        written += chunk.len() as u64;
    }
    drop(f);
    std::fs::OpenOptions::new()
        .write(true)
        .open(&filler)
        .unwrap()
        .set_len(written.saturating_sub(total as u64 / 2))
        .unwrap();
    let with_filler = snapshot(&mnt);

    let second = plot("data/paper/table4.toml");
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(!second.status.success(), "the run must fail on the full disk");
    assert!(stderr.contains("No space left on device"), "{stderr}");
    let after = snapshot(&mnt);
    let leftovers: Vec<&String> = after.keys().filter(|k| k.contains(".mre-")).collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    assert!(after == with_filler, "the previous figures changed on a full disk");

    std::fs::remove_file(&filler).unwrap();
    let third = plot("data/paper/table4.toml");
    assert!(third.status.success(), "{}", String::from_utf8_lossy(&third.stderr));
    assert_ne!(
        snapshot(&mnt),
        before,
        "with space the second model's figures replace the first's"
    );
}
