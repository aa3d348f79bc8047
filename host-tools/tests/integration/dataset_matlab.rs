//! MATLAB recordings (`file = "….mat"` + `variables`): a .mat copy of the real
//! MR damper data set reads back sample for sample as the text original, and
//! fits, validates and diagnoses to the same results; bad variables, wrong
//! shapes and v7.3 files get clear errors.
use crate::mat_v5;

use mre_host::dataset::Dataset;
use std::path::{Path, PathBuf};

fn mts() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mr-damper-mts")
}

/// The raw columns of a whitespace text file (parsed here, independently of
/// the reader under test).
fn raw_columns(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut cols: Vec<Vec<f64>> = Vec::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        for (i, f) in line.split_whitespace().enumerate() {
            if cols.len() <= i {
                cols.push(Vec::new());
            }
            cols[i].push(f.parse().unwrap());
        }
    }
    cols
}

/// `dir` gets a .mat copy of the MTS data set: same manifest, each file's
/// four columns saved as t, x, v, F column vectors.
fn mat_copy(dir: &Path) {
    let manifest = std::fs::read_to_string(mts().join("dataset.toml")).unwrap();
    let mut converted = String::new();
    for line in manifest.lines() {
        if line.starts_with("delimiter") {
            continue;
        }
        if line.starts_with("columns") {
            converted.push_str(
                "variables = { time_s = \"t\", displacement_mm = \"x\", velocity_mm_s = \"v\", force_n = \"F\" }\n",
            );
            continue;
        }
        converted.push_str(&line.replace(".txt\"", ".mat\""));
        converted.push('\n');
        if let Some(file) = line.strip_prefix("file = \"").and_then(|l| l.strip_suffix(".txt\"")) {
            let c = raw_columns(&mts().join(format!("{file}.txt")));
            let n = c[0].len();
            let bytes = mat_v5::mat_v5(&[
                ("t", n, 1, &c[0]),
                ("x", n, 1, &c[1]),
                ("v", n, 1, &c[2]),
                ("F", n, 1, &c[3]),
            ]);
            std::fs::write(dir.join(format!("{file}.mat")), bytes).unwrap();
        }
    }
    std::fs::write(dir.join("dataset.toml"), converted).unwrap();
}

/// JSON with the file names made comparable (`.mat` → `.txt`, the folder)
/// and the input files' hash (which differs by construction) left out.
fn normalised(v: &impl serde::Serialize, dir: &Path) -> String {
    let mut value = serde_json::to_value(v).unwrap();
    if let Some(model) = value.get_mut("model").and_then(|m| m.as_object_mut()) {
        model.remove("input_sha256");
    }
    value
        .to_string()
        .replace(".mat", ".txt")
        .replace(&dir.display().to_string(), "DATA")
        .replace(&mts().display().to_string(), "DATA")
}

#[test]
fn mat_copy_reads_as_the_text_original() {
    let dir = tempfile::tempdir().unwrap();
    mat_copy(dir.path());
    let text = Dataset::load(&mts()).unwrap();
    let mat = Dataset::load(dir.path()).unwrap();
    assert_eq!(text.recordings.len(), 15);
    assert_eq!(mat.recordings.len(), text.recordings.len());
    for (m, t) in mat.recordings.iter().zip(&text.recordings) {
        assert_eq!(m.file.replace(".mat", ".txt"), t.file);
        assert_eq!(m.current_a, t.current_a);
        assert_eq!(m.tags, t.tags);
        // Same numbers, same unit conversion (velocity given in mm/s).
        assert_eq!(m.samples, t.samples, "{}", m.file);
    }
}

#[test]
fn mat_data_set_fits_validates_and_diagnoses_like_the_text_one() {
    let dir = tempfile::tempdir().unwrap();
    mat_copy(dir.path());
    let out = tempfile::tempdir().unwrap();
    let options = mre_host::fit::FitOptions {
        method: mre_host::fit::Method::Lsq,
        ..Default::default()
    };
    let mut models = Vec::new();
    let mut reports = Vec::new();
    let mut diagnoses = Vec::new();
    for (k, data) in [mts(), dir.path().to_path_buf()].iter().enumerate() {
        let o = out.path().join(k.to_string());
        let model = o.join("model.toml");
        let run = mre_host::fit::run_fit(data, &options, &[0.5], &model).unwrap();
        models.push(normalised(&run.model, data));
        let r =
            mre_host::validate::run_validate(data, &model.display().to_string(), &[0.5], &o.join("validate")).unwrap();
        reports.push(normalised(&r.recordings, data));
        let opts = mre_host::diagnose::options_from_cli(None, Some("frequency_hz".into()), 5, vec![0.5], 1).unwrap();
        let d = mre_host::diagnose::run_to_files(
            data,
            &opts,
            &o.join("diag"),
            &o.join("diag/report.json"),
            &o.join("pred"),
        )
        .unwrap();
        diagnoses.push(normalised(&d, data));
        assert!(o.join("validate/index.html").is_file() && o.join("diag/index.html").is_file());
    }
    assert_eq!(models[0], models[1]);
    assert_eq!(reports[0], reports[1]);
    assert_eq!(diagnoses[0], diagnoses[1]);
}

/// A one-recording .mat data set with the given variables and mapping.
fn one_file(dir: &Path, vars: &[(&str, usize, usize, &[f64])], variables: &str) -> String {
    std::fs::write(dir.join("drop01.mat"), mat_v5::mat_v5(vars)).unwrap();
    std::fs::write(
        dir.join("dataset.toml"),
        format!("name = \"m\"\n\n[[recording]]\nfile = \"drop01.mat\"\ncurrent_a = 1.0\nvariables = {variables}\n"),
    )
    .unwrap();
    match Dataset::load(dir) {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn units_bad_names_and_wrong_shapes() {
    let dir = tempfile::tempdir().unwrap();
    let t: Vec<f64> = (0..20).map(|k| k as f64).collect(); // ms
                                                           // Compressed while the force rises (a passive damper takes work while loaded).
    let x: Vec<f64> = (0..20).map(|k| (k as f64 * 0.08).sin() * 0.004).collect(); // m
    let f: Vec<f64> = (0..20).map(|k| k as f64 * 0.5).collect(); // kN
    let vars = [
        ("t", 1, 20, t.as_slice()),
        ("x", 20, 1, x.as_slice()),
        ("F", 20, 1, f.as_slice()),
    ];
    // Unit suffixes convert as for CSV (a row vector is fine too).
    let ok = r#"{ time_ms = "t", displacement_m = "x", force_kn = "F" }"#;
    assert_eq!(one_file(dir.path(), &vars, ok), "");
    let ds = Dataset::load(dir.path()).unwrap();
    let s = &ds.recordings[0].samples;
    assert_eq!(s.time_s[3], 3.0 * 1e-3);
    assert_eq!(s.x_mm[5], x[5] * 1e3);
    assert_eq!(s.force_n[4], 2.0 * 1e3);
    assert!(ds.recordings[0].velocity_estimated);

    let e = one_file(
        dir.path(),
        &vars,
        r#"{ time_ms = "t", displacement_m = "pos", force_kn = "F" }"#,
    );
    assert!(
        e.contains("no numeric variable `pos`") && e.contains("it has: t, x, F"),
        "{e}"
    );

    let two_rows: Vec<f64> = x.iter().chain(&x).cloned().collect();
    let e = one_file(
        dir.path(),
        &[("t", 1, 20, &t), ("x", 2, 20, &two_rows), ("F", 20, 1, &f)],
        ok,
    );
    assert!(e.contains("`x`") && e.contains("2×20") && e.contains("vector"), "{e}");

    let e = one_file(
        dir.path(),
        &[("t", 1, 20, &t), ("x", 19, 1, &x[..19]), ("F", 20, 1, &f)],
        ok,
    );
    assert!(e.contains("`x` has 19") && e.contains("20 samples"), "{e}");

    let e = one_file(
        dir.path(),
        &vars,
        r#"{ time_ms = "t", displacement_furlong = "x", force_kn = "F" }"#,
    );
    assert!(e.contains("unknown column name `displacement_furlong`"), "{e}");

    // Time running backwards is caught by the same checks as for CSV.
    let back: Vec<f64> = t.iter().rev().cloned().collect();
    let e = one_file(
        dir.path(),
        &[("t", 20, 1, &back), ("x", 20, 1, &x), ("F", 20, 1, &f)],
        ok,
    );
    assert!(e.contains("time"), "{e}");
}

/// The load error for `drop01.mat` holding `bytes`, listed with `variables`
/// (a `variables = …` line, or "" for none).
fn load_error(dir: &Path, bytes: &[u8], variables: &str) -> String {
    std::fs::write(dir.join("drop01.mat"), bytes).unwrap();
    std::fs::write(
        dir.join("dataset.toml"),
        format!("[[recording]]\nfile = \"drop01.mat\"\ncurrent_a = 1.0\n{variables}\n"),
    )
    .unwrap();
    Dataset::load(dir).unwrap_err().to_string()
}

#[test]
fn v73_and_missing_variables_get_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let vars = r#"variables = { time_s = "t", displacement_mm = "x", force_n = "F" }"#;
    let e = load_error(dir.path(), &mat_v5::mat_v73_header(), vars);
    assert!(e.contains("v7.3") && e.contains("-v7"), "{e}");

    let e = load_error(dir.path(), &mat_v5::mat_v73_header(), "");
    assert!(e.contains("MATLAB file") && e.contains("variables"), "{e}");

    let e = load_error(dir.path(), &b"not a mat file at all, just text".repeat(8), vars);
    assert!(e.contains("not a MATLAB v5/v7 MAT-file"), "{e}");
}

/// The issue's case: a 3001×3 `x_F` holding position (mm), velocity (m/s)
/// and force (N) column by column; `x_F[:,3]` picks the force.
#[test]
fn a_matrix_column_is_picked_as_matlab_numbers_it() {
    let dir = tempfile::tempdir().unwrap();
    let n = 3001;
    let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-5).collect();
    let x: Vec<f64> = t.iter().map(|t| 5.0 * (t * 100.0).sin()).collect();
    let v: Vec<f64> = t.iter().map(|t| 0.5 * (t * 100.0).cos()).collect();
    let f: Vec<f64> = t.iter().map(|t| 1000.0 * (t * 100.0).sin() + 3.0).collect();
    // MATLAB stores a matrix column by column: x, then v, then F.
    let x_f: Vec<f64> = x.iter().chain(&v).chain(&f).cloned().collect();
    let vars = [("t", n, 1, t.as_slice()), ("x_F", n, 3, x_f.as_slice())];
    let picks = r#"{ time_s = "t", displacement_mm = "x_F[:,1]", velocity_m_s = "x_F(:,2)", force_n = "x_F[:,3]" }"#;
    assert_eq!(one_file(dir.path(), &vars, picks), "");
    let s = Dataset::load(dir.path()).unwrap().recordings.remove(0).samples;
    assert_eq!(s.x_mm, x);
    assert_eq!(s.v_m_s, v);
    assert_eq!(s.force_n, f);

    // A column the matrix does not have, and a bad selection, are said.
    let e = one_file(
        dir.path(),
        &vars,
        r#"{ time_s = "t", displacement_mm = "x_F[:,1]", force_n = "x_F[:,4]" }"#,
    );
    assert!(e.contains("picks column 4") && e.contains("3001×3"), "{e}");
    let e = one_file(dir.path(), &vars, r#"{ time_s = "t", force_n = "x_F[2,:]" }"#);
    assert!(e.contains("x_F[2,:]") && e.contains("x_F[:,3]"), "{e}");
    // The whole matrix for one column: the error shows how to pick one.
    let e = one_file(dir.path(), &vars, r#"{ time_s = "t", force_n = "x_F" }"#);
    assert!(e.contains("3001×3") && e.contains("x_F[:,1]"), "{e}");
}

/// `mre dataset init` on a .mat file it cannot map lists what it found.
#[test]
fn init_lists_the_variables_and_shapes_it_cannot_map() {
    let dir = tempfile::tempdir().unwrap();
    let t: Vec<f64> = (0..30).map(|k| k as f64 * 1e-3).collect();
    let x_f: Vec<f64> = (0..90).map(|k| k as f64).collect();
    std::fs::write(
        dir.path().join("drop1A.mat"),
        mat_v5::mat_v5(&[("t", 30, 1, &t), ("x_F", 30, 3, &x_f)]),
    )
    .unwrap();
    let e = mre_host::dataset::init::manifest_for(dir.path(), None, None).unwrap_err();
    let m = format!("{e:#}");
    assert!(m.contains("t (30×1)") && m.contains("x_F (30×3)"), "{m}");
    assert!(m.contains("x_F[:,3]"), "{m}");
}
