//! The committed drop-impact data sets in `data/` are exactly what
//! `data/generate.sh` produces (same seed → same bytes), and stay small.
use mre_host::plant::synth::{write_synth, write_synth_with_plan, SynthPlan};
use std::path::{Path, PathBuf};

const BUNDLED: [(&str, u64); 7] = [
    ("none", 101),
    ("viscous_damping", 102),
    ("sensor_delay", 103),
    ("stress_softening", 104),
    ("end_stop", 105),
    ("magnetic_saturation", 106),
    ("coil_lag", 107),
];

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

fn sorted_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

/// The committed set equals the freshly generated one file for file, byte
/// for byte; returns its size in bytes.
fn assert_same_files(committed: &Path, fresh: &Path) -> u64 {
    assert_eq!(
        sorted_files(committed),
        sorted_files(fresh),
        "{}: file list",
        committed.display()
    );
    let mut total_bytes = 0u64;
    for name in sorted_files(fresh) {
        let bytes = std::fs::read(committed.join(&name)).unwrap();
        total_bytes += bytes.len() as u64;
        assert!(
            bytes == std::fs::read(fresh.join(&name)).unwrap(),
            "{}/{name} differs: rerun data/generate.sh",
            committed.display()
        );
    }
    total_bytes
}

#[test]
fn bundled_sets_match_the_generating_script() {
    let script = std::fs::read_to_string(data_dir().join("generate.sh")).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let mut total_bytes = 0u64;
    for (effect, seed) in BUNDLED {
        assert!(
            script.contains(&format!("gen {effect} {seed}\n")),
            "generate.sh lists {effect} {seed}"
        );
        let committed = data_dir().join(format!("drop-{effect}"));
        let fresh = tmp.path().join(format!("drop-{effect}"));
        let key = tmp.path().join(format!("drop-{effect}.json"));
        write_synth(effect, seed, &fresh, Some(&key), false).unwrap();
        total_bytes += assert_same_files(&committed, &fresh);
        let committed_key = std::fs::read(data_dir().join(format!("keys/drop-{effect}.json"))).unwrap();
        assert_eq!(committed_key, std::fs::read(&key).unwrap(), "{effect}: key");
        assert!(
            !committed.join(format!("drop-{effect}.json")).exists(),
            "key outside the set"
        );
    }
    assert!(total_bytes < 4_000_000, "bundled sets total {total_bytes} bytes");
}

/// The full-stroke campaign (the data set the flown model is fitted on) is
/// what its generate.sh line produces, and its drops reach the stroke at
/// every current: the fastest recording of each current reaches the 15 mm
/// it was aimed at, less the drop-height scatter (0.5 % in velocity, so
/// about as much in stroke) — well past the 12 mm usable stroke.
#[test]
fn full_stroke_set_matches_the_generating_script_and_reaches_the_stroke() {
    let script = std::fs::read_to_string(data_dir().join("generate.sh")).unwrap();
    assert!(script.contains(
        "synth --effect none --seed 108 --full-stroke-mm 15 --out data/drop-full-stroke --key data/keys/drop-full-stroke.json"
    ));
    let tmp = tempfile::tempdir().unwrap();
    let committed = data_dir().join("drop-full-stroke");
    let fresh = tmp.path().join("drop-full-stroke");
    let key = tmp.path().join("drop-full-stroke.json");
    let output = write_synth_with_plan("none", 108, &SynthPlan::full_stroke(15.0), &fresh, Some(&key), false).unwrap();
    let total_bytes = assert_same_files(&committed, &fresh);
    assert_eq!(
        std::fs::read(data_dir().join("keys/drop-full-stroke.json")).unwrap(),
        std::fs::read(&key).unwrap()
    );
    assert!(total_bytes < 600_000, "{total_bytes} bytes");
    for current_a in [0.0, 0.5, 1.0, 1.5, 2.0] {
        let reach_mm = output
            .dataset
            .recordings
            .iter()
            .filter(|r| r.current_a == current_a && !r.file.starts_with("step"))
            .flat_map(|r| r.samples.x_mm.iter().copied())
            .fold(0.0f64, f64::max);
        assert!(reach_mm >= 14.85, "{current_a} A reaches {reach_mm} mm");
    }
}
