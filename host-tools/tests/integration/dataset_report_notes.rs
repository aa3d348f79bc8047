//! Reading notes (`dataset::summary::recording_notes`) reach every report
//! that lists its data: here the diagnosis's report.md, report.json and HTML
//! page, as the validation's and the comparison's already do
//! (dataset_real.rs, compare_outputs.rs).
use crate::diagnose_support;
use diagnose_support::{dataset, Added};
use mre_host::dataset::write::{write_dataset, WriteOptions};
use mre_host::diagnose::{run_to_files, DiagnoseOptions};

/// Physics (the diagnosis support's simulated damper, + 400 N·s/m) with one
/// hand-written change: a line of instrument metadata written above one
/// file's header, as lab exports have. The loader skips it and notes it;
/// the diagnosis's outputs say so for that file only.
#[test]
fn reading_notes_reach_the_diagnosis_report() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    write_dataset(
        &dataset(Added::Viscous { c_n_s_per_m: 400.0 }, 7),
        &data,
        &WriteOptions::default(),
    )
    .unwrap();
    let file = data.join("i0_x2_r1.csv");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, format!("Instrument: drop rig 2\n{text}")).unwrap();
    let (rep, json, pred) = (
        dir.path().join("rep"),
        dir.path().join("r.json"),
        dir.path().join("pred"),
    );
    run_to_files(&data, &DiagnoseOptions::default(), &rep, &json, &pred).expect("diagnose");

    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let notes = v["reading_notes"].as_array().expect("reading_notes in report.json");
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert_eq!(notes[0]["file"], "i0_x2_r1.csv");
    let first = notes[0]["notes"][0].as_str().unwrap();
    assert!(first.contains("skipped"), "{first}");

    let md = std::fs::read_to_string(rep.join("report.md")).unwrap();
    assert!(md.contains("Reading notes: what the readers assumed"), "{md}");
    assert!(md.contains(&format!("- `i0_x2_r1.csv`: {first}")), "{md}");
    assert!(!md.contains("- `i0_x2_r2.csv`:"), "a file read as written has no notes");
    let html = std::fs::read_to_string(rep.join("index.html")).unwrap();
    assert!(html.contains("<li><code>i0_x2_r1.csv</code>: "), "{html}");
}

/// Physics (the same simulated damper) written without its velocity column,
/// so the reader estimates velocity in every file. The report says so once,
/// in its velocity sentence, not again per file: before, every file's line in
/// the reading-notes paragraph repeated it.
#[test]
fn an_estimated_velocity_is_stated_once_in_the_diagnosis_report() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let mut ds = dataset(Added::Viscous { c_n_s_per_m: 400.0 }, 7);
    for rec in &mut ds.recordings {
        // The writer leaves an estimated velocity out of the file.
        rec.velocity_estimated = true;
    }
    write_dataset(&ds, &data, &WriteOptions::default()).unwrap();
    let header = std::fs::read_to_string(data.join("i0_x2_r1.csv")).unwrap();
    assert!(!header.lines().next().unwrap().contains("velocity"), "{header}");
    let (rep, json, pred) = (
        dir.path().join("rep"),
        dir.path().join("r.json"),
        dir.path().join("pred"),
    );
    run_to_files(&data, &DiagnoseOptions::default(), &rep, &json, &pred).expect("diagnose");

    let md = std::fs::read_to_string(rep.join("report.md")).unwrap();
    let n = ds.recordings.len();
    assert!(
        md.contains(&format!("in {n} of {n} recordings estimated from displacement")),
        "{md}"
    );
    assert_eq!(md.matches("estimated from displacement").count(), 1, "{md}");
    // The json keeps every file's full notes for programs.
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(v["reading_notes"].as_array().map(Vec::len), Some(n));
}
