//! The output contract: report.json keys, predictions CSVs, report.md, and
//! nothing written when the input is bad.
use crate::diagnose_support;
use diagnose_support::{dataset, Added};
use mre_host::dataset::write::{write_dataset, WriteOptions};
use mre_host::diagnose::{run_to_files, DiagnoseOptions};

#[test]
fn outputs_follow_the_contract() {
    let dir = tempfile::tempdir().expect("tempdir");
    let data = dir.path().join("data");
    write_dataset(
        &dataset(Added::Viscous { c_n_s_per_m: 400.0 }, 7),
        &data,
        &WriteOptions::default(),
    )
    .expect("write");
    let (rep, json, pred) = (
        dir.path().join("rep"),
        dir.path().join("r.json"),
        dir.path().join("pred"),
    );
    run_to_files(&data, &DiagnoseOptions::default(), &rep, &json, &pred).expect("diagnose");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).expect("json")).expect("parse");
    let mut keys: Vec<&str> = v.as_object().expect("object").keys().map(|k| k.as_str()).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "baseline",
            "effects",
            "final",
            "not_identifiable",
            "unexplained",
            "verdict"
        ]
    );
    assert_eq!(v["verdict"]["verdict"], "found");
    assert!(v["verdict"]["reasons"].as_array().expect("reasons").is_empty());
    assert!(v["unexplained"].is_array());
    for m in ["baseline", "final"] {
        assert!(v[m]["rmse_n"].is_f64() && v[m]["nrmse"].is_f64());
    }
    let e = &v["effects"][0];
    assert_eq!(e["name"], "viscous_damping");
    for k in [
        "parameters",
        "evidence",
        "rmse_n_before",
        "rmse_n_after",
        "heldout_improvement",
        "heldout_improvement_nested",
        "heldout_improvement_nested_ci95",
    ] {
        assert!(!e[k].is_null(), "missing {k}");
    }
    // The law is in the model class plus c·v: the final model leaves the
    // 1 N noise (and the CSV's rounding) only, and the baseline misses
    // c·v (400 N·s/m × up to 0.52 m/s, partly absorbed by the quartics).
    let (base, fin) = (
        v["baseline"]["rmse_n"].as_f64().expect("rmse"),
        v["final"]["rmse_n"].as_f64().expect("rmse"),
    );
    assert!(fin < 1.3, "final RMSE {fin} N");
    assert!(base > 2.0 * fin, "baseline {base} N, final {fin} N");
    let csvs: Vec<_> = std::fs::read_dir(&pred).expect("pred dir").collect();
    assert_eq!(csvs.len(), 18);
    let one = std::fs::read_to_string(pred.join("i0_x2_r1.predictions.csv")).expect("csv");
    assert_eq!(
        one.lines().next(),
        Some("time_s,force_measured_n,force_baseline_n,force_final_n")
    );
    assert_eq!(one.lines().count(), 241);
    let md = std::fs::read_to_string(rep.join("report.md")).expect("md");
    assert!(md.contains("viscous_damping") && md.contains("loops_worst.png"));
    for png in ["residual_map.png", "residual_covariates.png", "loops_worst.png"] {
        assert!(std::fs::metadata(rep.join(png)).expect(png).len() > 1000);
    }
}

#[test]
fn a_run_failing_part_way_writes_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let data = dir.path().join("data");
    write_dataset(
        &dataset(Added::Viscous { c_n_s_per_m: 400.0 }, 7),
        &data,
        &WriteOptions::default(),
    )
    .expect("write");
    let (rep, json, pred) = (
        dir.path().join("rep"),
        dir.path().join("r.json"),
        dir.path().join("pred"),
    );
    // The plots and some predictions are staged; the 6th output fails.
    let err = mre_host::atomic_write::command_failing_after(5, || {
        run_to_files(&data, &DiagnoseOptions::default(), &rep, &json, &pred)
    })
    .expect_err("injected failure");
    assert!(format!("{err:#}").contains("injected write failure"), "{err:#}");
    assert!(!rep.exists() && !json.exists() && !pred.exists());
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("ls")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("data")]);
}
