//! The committed drop-impact data sets in `data/` are exactly what
//! `data/generate.sh` produces (same seed → same bytes), and stay small.
use mre_host::plant::synth::write_synth;
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
        assert_eq!(sorted_files(&committed), sorted_files(&fresh), "{effect}: file list");
        for name in sorted_files(&fresh) {
            let bytes = std::fs::read(committed.join(&name)).unwrap();
            total_bytes += bytes.len() as u64;
            assert!(
                bytes == std::fs::read(fresh.join(&name)).unwrap(),
                "{effect}/{name} differs: rerun data/generate.sh"
            );
        }
        let committed_key = std::fs::read(data_dir().join(format!("keys/drop-{effect}.json"))).unwrap();
        assert_eq!(committed_key, std::fs::read(&key).unwrap(), "{effect}: key");
        assert!(
            !committed.join(format!("drop-{effect}.json")).exists(),
            "key outside the set"
        );
    }
    assert!(total_bytes < 4_000_000, "bundled sets total {total_bytes} bytes");
}
