//! `mre diagnose` end to end on small data sets with a known generating law.
use crate::diagnose_support;
use diagnose_support::{dataset, dataset_with_steps, law_n, Added, SAMPLE_PERIOD_S};
use mre_host::diagnose::{diagnose, report, DiagnoseOptions};

fn names(d: &mre_host::diagnose::Diagnosis) -> Vec<&'static str> {
    d.findings.iter().map(|f| f.effect.name()).collect()
}

#[test]
fn no_effect_is_invented_when_the_law_fits_the_model() {
    let d = diagnose(&dataset(Added::None, 1), &DiagnoseOptions::default()).expect("diagnosis");
    assert!(d.findings.is_empty(), "invented {:?}", names(&d));
    // The law is a quadratic per branch and current: the baseline fits it to the noise (1 N).
    let j = report::report_json(&d);
    assert!(j.baseline.rmse_n < 1.5, "baseline RMSE {}", j.baseline.rmse_n);
    assert_eq!(j.baseline, j.final_);
}

#[test]
fn viscous_damping_is_found_with_its_coefficient() {
    let c = 400.0;
    let d = diagnose(
        &dataset(Added::Viscous { c_n_s_per_m: c }, 2),
        &DiagnoseOptions::default(),
    )
    .expect("diagnosis");
    assert_eq!(names(&d).first(), Some(&"viscous_damping"));
    let f = &d.findings[0];
    assert!(f.heldout_improvement > 2.0, "improvement {}", f.heldout_improvement);
    // Linear or saturating form: with v0 ≫ v, v0·tanh(v/v0) ≈ v, so c is c either way.
    for current in ["0", "0.5", "1"] {
        let p = &f.parameters[&format!("c_at_{current}a_n_s_per_m")];
        assert!((p.value - c).abs() < 0.15 * c, "c at {current} A = {}", p.value);
        // The interval covers the true c, not merely its own estimate.
        assert!(p.ci95[0] <= c && c <= p.ci95[1], "c at {current} A: {:?}", p.ci95);
    }
}

#[test]
fn sensor_delay_is_found_near_the_true_shift() {
    let tau = 3.0 * SAMPLE_PERIOD_S;
    let d = diagnose(&dataset(Added::Delay { tau_s: tau }, 3), &DiagnoseOptions::default()).expect("diagnosis");
    assert_eq!(names(&d).first(), Some(&"sensor_delay"));
    let found = d.findings[0].parameters["tau_s"].value;
    // The grid has points at 2, 3 and 4 samples: within one grid step.
    assert!((found - tau).abs() < 1.01 * SAMPLE_PERIOD_S, "tau {found}");
}

#[test]
fn unidentifiable_candidates_say_what_would_identify_them() {
    let d = diagnose(&dataset(Added::None, 4), &DiagnoseOptions::default()).expect("diagnosis");
    let j = report::report_json(&d);
    let listed: Vec<&str> = j.not_identifiable.iter().map(|n| n.name.as_str()).collect();
    // No validate recordings at intermediate currents; one current per test.
    assert!(listed.contains(&"magnetic_saturation"), "{listed:?}");
    assert!(listed.contains(&"coil_lag"), "{listed:?}");
    assert!(j.not_identifiable.iter().all(|n| !n.needs.is_empty()));
}

#[test]
fn the_baseline_reproduces_the_generating_law_through_the_core() {
    let d = diagnose(&dataset(Added::None, 5), &DiagnoseOptions::default()).expect("diagnosis");
    // Evaluate the fitted table (core `force_on_branch`) against the law, noise-free.
    for (current, x) in [(0.0, 1.0), (0.5, 2.5), (1.0, 3.5)] {
        for compressing in [true, false] {
            let branch = if compressing {
                mre_algorithm::model::Branch::Compression
            } else {
                mre_algorithm::model::Branch::Extension
            };
            let model = d
                .baseline_table
                .force_on_branch(x as f32, branch, current as f32)
                .force_n as f64;
            let truth = law_n(x, compressing, current);
            assert!((model - truth).abs() < 2.0, "{current} A, x {x}: {model} vs {truth}");
        }
    }
}

#[test]
fn stress_softening_is_found_with_its_depth() {
    // n0 = 4 is on the searched grid; Δ is solved, so it should come back close.
    let added = Added::Softening { delta: 0.15, n0: 4.0 };
    let d = diagnose(&dataset(added, 6), &DiagnoseOptions::default()).expect("diagnosis");
    assert_eq!(names(&d).first(), Some(&"stress_softening"));
    let p = &d.findings[0].parameters;
    assert!((p["delta"].value - 0.15).abs() < 0.02, "delta {}", p["delta"].value);
    assert_eq!(p["n0"].value, 4.0);
}

#[test]
fn coil_lag_is_found_with_its_time_constant_on_controlled_impacts() {
    // 0.6 ms = 6 samples: off the √2 grid (5.66, 8), so the refinement matters.
    let tau = 6.0 * SAMPLE_PERIOD_S;
    let d = diagnose(
        &dataset_with_steps(Added::CoilLag { tau_s: tau }, 7),
        // The controlled impacts are validate recordings, the lag's only evidence.
        &DiagnoseOptions::with_validate_evidence(),
    )
    .expect("diagnosis");
    assert_eq!(names(&d), vec!["coil_lag"]);
    let p = &d.findings[0].parameters["time_constant_s"];
    assert!((p.value - tau).abs() < 0.1 * tau, "tau {} vs {tau}", p.value);
    // Not asserted: that the interval covers the true τ. It does not here
    // (measured 2026-11-26): the re-chosen τ of the bootstrap is too narrow;
    // open, see DIAGNOSE.md "Known limits".
    assert!(
        d.findings[0].heldout_improvement > 2.0,
        "{}",
        d.findings[0].heldout_improvement
    );
    // Only the controlled impacts change: the per-recording table shows their steps.
    let md = report::report_markdown(&d, &report::report_json(&d));
    assert!(md.contains("| step0_i0-1.csv | Validate | 0→1 |"), "{md}");
}

#[test]
fn controlled_impacts_without_a_lag_are_explained_by_the_recorded_current() {
    let d = diagnose(
        &dataset_with_steps(Added::None, 8),
        &DiagnoseOptions::with_validate_evidence(),
    )
    .expect("diagnosis");
    assert!(d.findings.is_empty(), "invented {:?}", names(&d));
    let j = report::report_json(&d);
    // coil_lag was testable here, and the baseline interpolates at each sample's current.
    assert!(j.not_identifiable.iter().all(|n| n.name != "coil_lag"));
    assert!(j.baseline.rmse_n < 1.5, "baseline RMSE {}", j.baseline.rmse_n);
}
