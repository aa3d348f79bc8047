//! Sign conventions (docs/dataset-format.md, "sign"): compression reads
//! positive force and displacement; `sign` flips a column; a recording that
//! contradicts its declaration is refused naming the column; `dataset init`
//! writes the flip it detects as an assumption.
use mre_host::dataset::init::manifest_for;
use mre_host::dataset::Dataset;
use std::fmt::Write;
use std::path::Path;

/// A half-sine impact of 10 ms: x to 8 mm, F to 3 kN (compression
/// positive), each multiplied by the given signs as an instrument writes it.
fn impact_csv(x_sign: f64, f_sign: f64) -> String {
    let mut s = String::from("time_s,displacement_mm,force_n\n");
    for k in 0..=100 {
        let th = std::f64::consts::PI * k as f64 / 100.0;
        let _ = writeln!(
            s,
            "{},{},{}",
            k as f64 * 1e-4,
            x_sign * 8.0 * th.sin(),
            f_sign * 3000.0 * th.sin()
        );
    }
    s
}

fn set(dir: &Path, csv: &str, extra: &str) -> Result<Dataset, String> {
    std::fs::write(dir.join("d.csv"), csv).unwrap();
    let toml = format!(
        "name = \"s\"\n[defaults]\nmass_kg = 5.5\n{extra}\n[[recording]]\nfile = \"d.csv\"\ncurrent_a = 1.0\nimpact_velocity_m_s = 2.24\n"
    );
    std::fs::write(dir.join("dataset.toml"), toml).unwrap();
    Dataset::load(dir).map_err(|e| e.to_string())
}

#[test]
fn compression_negative_force_is_refused_naming_the_column() {
    let dir = tempfile::tempdir().unwrap();
    let e = set(dir.path(), &impact_csv(1.0, -1.0), "").unwrap_err();
    assert!(e.contains("the force column looks inverted"), "{e}");
    assert!(e.contains("sign = { force_n = -1 }"), "{e}");
    let e = set(dir.path(), &impact_csv(-1.0, 1.0), "").unwrap_err();
    assert!(e.contains("the displacement column looks inverted"), "{e}");
}

#[test]
fn a_declared_sign_flips_the_column() {
    let dir = tempfile::tempdir().unwrap();
    let ds = set(dir.path(), &impact_csv(1.0, -1.0), "sign = { force_n = -1 }").unwrap();
    let f = &ds.recordings[0].samples.force_n;
    assert!((f[50] - 3000.0).abs() < 1e-9, "{}", f[50]);
    // Per recording too (the recording's own table overrides [defaults]).
    let csv = impact_csv(-1.0, -1.0);
    std::fs::write(dir.path().join("d.csv"), csv).unwrap();
    std::fs::write(
        dir.path().join("dataset.toml"),
        "name = \"s\"\n[[recording]]\nfile = \"d.csv\"\ncurrent_a = 1.0\nmass_kg = 5.5\n\
         sign = { force_n = -1, displacement_mm = -1 }\n",
    )
    .unwrap();
    let ds = Dataset::load(dir.path()).unwrap();
    assert!(ds.recordings[0].samples.x_mm[50] > 7.9);
}

#[test]
fn a_recording_that_contradicts_its_declaration_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let e = set(dir.path(), &impact_csv(1.0, 1.0), "sign = { force_n = -1 }").unwrap_err();
    assert!(
        e.contains("the force column looks inverted after the declared sign"),
        "{e}"
    );
    let e = set(dir.path(), &impact_csv(1.0, 1.0), "sign = { force_n = 2 }").unwrap_err();
    assert!(e.contains("a sign is 1 or -1"), "{e}");
    let e = set(dir.path(), &impact_csv(1.0, 1.0), "sign = { load = -1 }").unwrap_err();
    assert!(e.contains("`load` is not a column name"), "{e}");
}

#[test]
fn init_writes_the_flip_it_detects_as_an_assumption() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("drop1A.csv"), impact_csv(1.0, -1.0)).unwrap();
    std::fs::write(dir.path().join("drop2A.csv"), impact_csv(1.0, 1.0)).unwrap();
    let toml = manifest_for(dir.path(), Some("drop{current_a}A"), None).unwrap();
    assert!(
        toml.contains("# assumed: `force_n` reads compression negative"),
        "{toml}"
    );
    assert_eq!(toml.matches("sign = { force_n = -1 }").count(), 1, "{toml}");
    let rec1 = toml.find("file = \"drop1A.csv\"").unwrap();
    let rec2 = toml.find("file = \"drop2A.csv\"").unwrap();
    let flip = toml.find("sign = { force_n = -1 }").unwrap();
    assert!(rec1 < flip && flip < rec2, "the flip belongs to drop1A: {toml}");
    // With it the set loads, compression positive.
    std::fs::write(dir.path().join("dataset.toml"), &toml).unwrap();
    let ds = Dataset::load(dir.path()).unwrap();
    assert!(ds.recordings.iter().all(|r| r.samples.force_n[50] > 0.0));
}
