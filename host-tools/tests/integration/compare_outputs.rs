//! `mre compare` end to end on the bundled MTS data with a tiny search
//! budget: the report's schema, its numbers recomputed from the written
//! predictions, and that held-out recordings never influence any fit.
use mre_host::compare::fit::Budget;
use mre_host::compare::{compare, run_compare, CompareOptions};
use mre_host::dataset::{Dataset, Role};
use mre_host::fit::gsa::GsaParams;
use std::path::Path;

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mr-damper-mts")
}

fn tiny(skip_diagnosis: bool) -> CompareOptions {
    CompareOptions {
        budget: Budget {
            gsa: GsaParams {
                agents: 6,
                iters: 4,
                ..GsaParams::default()
            },
            gsa_samples_per_track: 150,
            lm_samples_per_track: 300,
            lm_patience: 2,
        },
        poly_gsa: GsaParams {
            agents: 10,
            iters: 10,
            ..GsaParams::default()
        },
        skip_diagnosis,
        ..CompareOptions::default()
    }
}

#[test]
fn report_schema_and_numbers_match_the_written_predictions() {
    let dir = tempfile::tempdir().unwrap();
    let r = run_compare(&data(), &tiny(true), dir.path()).unwrap();
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("report.json")).unwrap()).unwrap();
    let families = json["families"].as_array().unwrap();
    // lsq, GSA and five nonlinear families (diagnosis skipped here).
    assert_eq!(families.len(), 7);
    for f in families {
        for key in [
            "name",
            "parameters",
            "n_parameters",
            "fit_nrmse",
            "heldout_nrmse",
            "aic",
            "bic",
            "fit_time_s",
        ] {
            assert!(f.get(key).is_some(), "{} lacks {key}", f["name"]);
        }
        let name = f["name"].as_str().unwrap();
        // The family's column, named by hand from the report's rule: force_<name>_n, + and - as _.
        let column = match name {
            "polynomial-lsq" => "force_polynomial_lsq_n".to_string(),
            "polynomial-gsa" => "force_polynomial_gsa_n".to_string(),
            "bouc-wen" => "force_bouc_wen_n".to_string(),
            "kwok-tanh" => "force_kwok_tanh_n".to_string(),
            other => format!("force_{other}_n"),
        };
        // Recompute both means from the CSVs: NRMSE = RMSE / (max − min of F measured), docs/error-measure.md.
        let (mut fit, mut held) = (Vec::new(), Vec::new());
        for rec in f["recordings"].as_array().unwrap() {
            let file = rec["file"].as_str().unwrap();
            let stem = Path::new(file).file_stem().unwrap().to_str().unwrap();
            let csv = std::fs::read_to_string(dir.path().join("predictions").join(format!("{stem}.csv"))).unwrap();
            let mut lines = csv.lines();
            let header: Vec<&str> = lines.next().unwrap().split(',').collect();
            assert_eq!(header[..2], ["time_s", "force_measured_n"]);
            assert_eq!(header.len(), 2 + 7, "one column per family");
            let at = header
                .iter()
                .position(|h| *h == column)
                .unwrap_or_else(|| panic!("no {column}"));
            let (mut sse, mut n, mut lo, mut hi) = (0.0, 0usize, f64::INFINITY, f64::NEG_INFINITY);
            for l in lines {
                let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
                sse += (v[1] - v[at]).powi(2);
                lo = lo.min(v[1]);
                hi = hi.max(v[1]);
                n += 1;
            }
            let nrmse = (sse / n as f64).sqrt() / (hi - lo);
            if rec["current_a"].as_f64() == Some(0.5) {
                assert_eq!(rec["role"], "validate");
                held.push(nrmse);
            } else {
                fit.push(nrmse);
            }
        }
        assert_eq!((fit.len(), held.len()), (10, 5), "{name}");
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        // The CSVs round model forces to 1 mN, so each recomputed RMSE is within
        // 0.5 mN of the report's; every recording's force range exceeds 100 N
        // here, so the NRMSEs agree within 0.0005 / 100 = 5e-6.
        assert!((f["fit_nrmse"].as_f64().unwrap() - mean(&fit)).abs() < 5e-6, "{name}");
        assert!(
            (f["heldout_nrmse"].as_f64().unwrap() - mean(&held)).abs() < 5e-6,
            "{name}"
        );
    }
    assert!(r.best_heldout.is_some());
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(md.contains("predicts the held-out recordings best"));
    // The error measure is defined once, as docs/error-measure.md words it.
    assert_eq!(md.matches("NRMSE = RMSE / (max F − min F)").count(), 1);
    assert!(!md.contains("NRMSE = NRMSE"));
    for stem in ["0A_2mm5Hz0A", "0p5A_10mm1Hz0x5A", "1A_25mm0x1Hz1A"] {
        for ext in ["png", "svg"] {
            assert!(
                dir.path().join("plots").join(format!("{stem}.{ext}")).is_file(),
                "{stem}.{ext}"
            );
        }
    }
}

#[test]
fn held_out_recordings_never_influence_the_fit() {
    let ds = Dataset::load(&data()).unwrap();
    let mut tampered = ds.clone();
    for r in tampered.recordings.iter_mut().filter(|r| r.current_a == 0.5) {
        for f in &mut r.samples.force_n {
            *f = 3.0 * *f + 500.0;
        }
    }
    let options = tiny(false);
    let a = compare(&ds, &options).unwrap();
    let b = compare(&tampered, &options).unwrap();
    assert_eq!(a.outcomes.len(), 8);
    for (x, y) in a.outcomes.iter().zip(&b.outcomes) {
        assert_eq!(x.parameters, y.parameters, "{}: parameters moved", x.name);
        for (t, (p, q)) in a.tracks.iter().zip(x.predictions.iter().zip(&y.predictions)) {
            // Every prediction, held-out ones included, depends on fit data only.
            let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(p), bits(q), "{} on {} ({:?})", x.name, t.file, t.role);
        }
    }
    assert!(a.tracks.iter().any(|t| t.role == Role::Validate));
}

/// The bundled MTS data cut to `files` (name, current), loaded.
fn subset(files: &[(&str, f64)]) -> (tempfile::TempDir, Dataset) {
    let dir = tempfile::tempdir().unwrap();
    let mut toml = String::from(
        "name = \"subset\"\n[defaults]\ndelimiter = \"whitespace\"\n\
         columns = [\"time_s\", \"displacement_mm\", \"velocity_mm_s\", \"force_n\"]\n",
    );
    for (file, current_a) in files {
        std::fs::copy(data().join(file), dir.path().join(file)).unwrap();
        toml.push_str(&format!(
            "[[recording]]\nfile = \"{file}\"\ncurrent_a = {current_a:?}\n"
        ));
    }
    std::fs::write(dir.path().join("dataset.toml"), toml).unwrap();
    let ds = Dataset::load(dir.path()).unwrap();
    (dir, ds)
}

/// Four recordings, 0.5 A held out: three are left to fit, fewer than the
/// diagnosis's five cross-validation folds. The comparison says so and scores
/// the other families instead of failing an internal check.
#[test]
fn four_recordings_leave_out_the_diagnosis_and_say_why() {
    let (_dir, ds) = subset(&[
        ("10mm1Hz0A.txt", 0.0),
        ("10mm1Hz0x5A.txt", 0.5),
        ("10mm1Hz1A.txt", 1.0),
        ("25mm0x1Hz0A.txt", 0.0),
    ]);
    let c = compare(&ds, &tiny(false)).unwrap();
    assert!(c.outcomes.iter().all(|o| o.name != "polynomial+diagnose"));
    assert_eq!(c.left_out.len(), 1);
    assert_eq!(c.left_out[0].family, "polynomial+diagnose");
    assert!(c.left_out[0].missing.contains("5 folds"), "{}", c.left_out[0].missing);
    assert!(c.left_out[0].missing.contains("has 3"), "{}", c.left_out[0].missing);
    // Every other family is still fitted and scored on the held-out recording.
    assert_eq!(c.outcomes.len(), 7, "two polynomials and five nonlinear families");
}

/// A held-out current outside the fitted ones cannot be interpolated: the
/// error names it and the currents there are.
#[test]
fn a_held_out_current_outside_the_fitted_ones_is_named() {
    let (_dir, ds) = subset(&[("10mm1Hz0A.txt", 0.0), ("10mm1Hz0x5A.txt", 0.5), ("10mm1Hz1A.txt", 1.0)]);
    let options = CompareOptions {
        hold_out_a: vec![1.0],
        ..tiny(true)
    };
    let e = compare(&ds, &options).unwrap_err().to_string();
    assert!(e.contains("held-out 1 A not between two fitted currents"), "{e}");
    assert!(e.contains("[0.0, 0.5]"), "{e}");
}

/// Real artifact with one stated change: three bundled MTS recordings, one
/// with a line of channel names written above its data (hand-written, as
/// lab exports have). The loader skips that line and notes it; the
/// comparison's report.md and its HTML page say so for that file only.
#[test]
fn reading_notes_reach_the_comparison_page() {
    let (dir, _) = subset(&[("10mm1Hz0A.txt", 0.0), ("10mm1Hz0x5A.txt", 0.5), ("10mm1Hz1A.txt", 1.0)]);
    let named = dir.path().join("10mm1Hz0x5A.txt");
    let text = std::fs::read_to_string(&named).unwrap();
    std::fs::write(&named, format!("Time Position Velocity Load\n{text}")).unwrap();
    let out = tempfile::tempdir().unwrap();
    let r = run_compare(dir.path(), &tiny(true), out.path()).unwrap();
    assert_eq!(r.reading_notes.len(), 1, "{:?}", r.reading_notes);
    assert_eq!(r.reading_notes[0].file, "10mm1Hz0x5A.txt");
    // Line 1 is the names row added above.
    let md = std::fs::read_to_string(out.path().join("report.md")).unwrap();
    assert!(
        md.contains("- `10mm1Hz0x5A.txt`: 1 row(s) above the first data row skipped (lines 1–1"),
        "{md}"
    );
    let html = std::fs::read_to_string(out.path().join("index.html")).unwrap();
    assert!(
        html.contains("<li><code>10mm1Hz0x5A.txt</code>: 1 row(s) above the first data row skipped (lines 1–1"),
        "{html}"
    );
    assert!(
        !html.contains("<code>10mm1Hz0A.txt</code>:"),
        "a file read as written has no notes"
    );
}

/// Real artifact with one stated change: three bundled MTS recordings, the
/// velocity column of one set to `ignore` in the manifest. Its velocity is
/// then estimated from displacement (docs/dataset-format.md), and the
/// comparison's notes say so for that file, as `mre validate`'s do
/// (`dataset::summary::recording_notes`); the comparison used to list only
/// the readers' own notes and left this out.
#[test]
fn comparison_notes_say_velocity_was_estimated() {
    let (dir, _) = subset(&[("10mm1Hz0A.txt", 0.0), ("10mm1Hz0x5A.txt", 0.5), ("10mm1Hz1A.txt", 1.0)]);
    let manifest = dir.path().join("dataset.toml");
    let toml = std::fs::read_to_string(&manifest).unwrap().replace(
        "file = \"10mm1Hz0x5A.txt\"\n",
        "file = \"10mm1Hz0x5A.txt\"\ncolumns = [\"time_s\", \"displacement_mm\", \"ignore\", \"force_n\"]\n",
    );
    std::fs::write(&manifest, toml).unwrap();
    let out = tempfile::tempdir().unwrap();
    let r = run_compare(dir.path(), &tiny(true), out.path()).unwrap();
    assert_eq!(r.reading_notes.len(), 1, "{:?}", r.reading_notes);
    assert_eq!(r.reading_notes[0].file, "10mm1Hz0x5A.txt");
    assert!(
        r.reading_notes[0]
            .notes
            .iter()
            .any(|n| n.starts_with("velocity estimated from displacement")),
        "{:?}",
        r.reading_notes
    );
    let md = std::fs::read_to_string(out.path().join("report.md")).unwrap();
    assert!(
        md.contains("- `10mm1Hz0x5A.txt`: velocity estimated from displacement"),
        "{md}"
    );
}
