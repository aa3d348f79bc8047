//! The data set writer against the contract `docs/dataset-format.md`:
//! write, then parse back with the `toml` and `csv` crates independently.
use mre_host::dataset::write::{write_dataset, Precision, WriteOptions};
use mre_host::dataset::{Dataset, Recording, Role, Samples, TagValue};
use std::collections::BTreeMap;
use std::path::PathBuf;

fn recording(file: &str, current_a: f64, role: Role) -> Recording {
    Recording {
        file: file.to_owned(),
        current_a,
        role,
        mass_kg: Some(5.5),
        impact_velocity_m_s: Some(2.24),
        sequence: Some(3),
        temperature_c: Some(24.5),
        tags: BTreeMap::from([
            ("amplitude_mm".to_owned(), TagValue::Number(10.0)),
            ("rig".to_owned(), TagValue::Text("drop \"A\"".to_owned())),
        ]),
        samples: Samples {
            time_s: vec![0.0, 0.00005, 0.0001],
            x_mm: vec![0.0, 0.1125, 0.2249],
            v_m_s: vec![2.24, 2.2391, 2.2376],
            force_n: vec![0.0, 150.25, 301.5],
            accel_m_s2: None,
            current_a: Some(vec![1.0, 1.0, 0.95]),
            temperature_c: None,
        },
        velocity_estimated: false,
        motion_from: None,
        notes: Vec::new(),
    }
}

fn dataset() -> Dataset {
    Dataset {
        name: "round trip, 5.5 kg".to_owned(),
        root: PathBuf::new(),
        recordings: vec![
            recording("a.csv", 1.0, Role::Fit),
            recording("sub/b.csv", 0.3, Role::Validate),
        ],
    }
}

#[test]
fn writes_spec_toml_and_unit_headers_that_parse_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    write_dataset(&dataset(), &out, &WriteOptions::default()).unwrap();

    let text = std::fs::read_to_string(out.join("dataset.toml")).unwrap();
    let doc: toml::Table = text.parse().unwrap();
    assert_eq!(doc["name"].as_str(), Some("round trip, 5.5 kg"));
    assert_eq!(doc["defaults"]["mass_kg"].as_float(), Some(5.5));
    let recs = doc["recording"].as_array().unwrap();
    assert_eq!(recs.len(), 2);
    let b = recs[1].as_table().unwrap();
    assert_eq!(b["file"].as_str(), Some("sub/b.csv"));
    assert_eq!(b["current_a"].as_float(), Some(0.3));
    assert_eq!(b["role"].as_str(), Some("validate"));
    assert_eq!(b["impact_velocity_m_s"].as_float(), Some(2.24));
    assert_eq!(b["sequence"].as_integer(), Some(3));
    assert_eq!(b["temperature_c"].as_float(), Some(24.5));
    assert_eq!(b["tags"]["amplitude_mm"].as_float(), Some(10.0));
    assert_eq!(b["tags"]["rig"].as_str(), Some("drop \"A\""));
    // Only keys the spec defines (the reader rejects unknown ones).
    let allowed = [
        "file",
        "current_a",
        "role",
        "impact_velocity_m_s",
        "sequence",
        "temperature_c",
        "tags",
        "mass_kg",
    ];
    for r in recs {
        assert!(r.as_table().unwrap().keys().all(|k| allowed.contains(&k.as_str())));
    }

    let mut reader = csv::Reader::from_path(out.join("sub/b.csv")).unwrap();
    let headers: Vec<String> = reader.headers().unwrap().iter().map(str::to_owned).collect();
    assert_eq!(
        headers,
        ["time_s", "displacement_mm", "velocity_m_s", "force_n", "current_a"]
    );
    let rows: Vec<Vec<f64>> = reader
        .records()
        .map(|r| r.unwrap().iter().map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 3);
    assert_eq!(
        rows[2],
        vec![0.0001, 0.2249, 2.2376, 301.5, 0.95],
        "shortest round-trip form is exact"
    );
}

#[test]
fn precision_rounds_each_column() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    let options = WriteOptions {
        force: false,
        precision: Precision {
            force_n: Some(0),
            time_s: Some(5),
            ..Precision::default()
        },
    };
    write_dataset(&dataset(), &out, &options).unwrap();
    let text = std::fs::read_to_string(out.join("a.csv")).unwrap();
    assert_eq!(text.lines().nth(2), Some("0.00005,0.1125,2.2391,150,1"));
}

#[test]
fn refuses_to_overwrite_and_bad_data_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    write_dataset(&dataset(), &out, &WriteOptions::default()).unwrap();
    let before = std::fs::read(out.join("a.csv")).unwrap();
    let err = write_dataset(&dataset(), &out, &WriteOptions::default()).unwrap_err();
    assert!(format!("{err:#}").contains("--force"), "{err:#}");

    // A NaN sample: clear error naming file, sample and column; old folder untouched.
    let mut bad = dataset();
    bad.recordings[0].samples.force_n[1] = f64::NAN;
    let err = write_dataset(
        &bad,
        &out,
        &WriteOptions {
            force: true,
            ..Default::default()
        },
    )
    .unwrap_err();
    let msg = format!("{err:#}");
    assert!(
        msg.contains("a.csv") && msg.contains("sample 2") && msg.contains("force_n"),
        "{msg}"
    );
    assert_eq!(std::fs::read(out.join("a.csv")).unwrap(), before);
    let fresh = dir.path().join("fresh");
    assert!(write_dataset(&bad, &fresh, &WriteOptions::default()).is_err());
    assert!(!fresh.exists(), "a failed run leaves no folder");
    // Failing part-way: the folder is complete in staging, then the command fails.
    let err = mre_host::atomic_write::command_failing_after(0, || {
        write_dataset(
            &dataset(),
            &dir.path().join("fresh").join("deeper"),
            &WriteOptions::default(),
        )
    })
    .unwrap_err();
    assert!(format!("{err:#}").contains("injected write failure"), "{err:#}");
    assert!(
        !fresh.exists(),
        "a failed run leaves no folder, not even the parents it created"
    );
    // No staging leftovers beside the target.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("set")]);

    // Duplicates and paths escaping the folder are refused.
    let mut dup = dataset();
    dup.recordings[1].file = "a.csv".to_owned();
    assert!(write_dataset(&dup, &dir.path().join("dup"), &WriteOptions::default()).is_err());
    let mut escape = dataset();
    escape.recordings[1].file = "../x.csv".to_owned();
    assert!(write_dataset(&escape, &dir.path().join("esc"), &WriteOptions::default()).is_err());

    // --force replaces the folder; an empty existing folder needs no force.
    let mut changed = dataset();
    changed.recordings.truncate(1);
    write_dataset(
        &changed,
        &out,
        &WriteOptions {
            force: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(!out.join("sub/b.csv").exists());
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    write_dataset(&dataset(), &empty, &WriteOptions::default()).unwrap();
}
