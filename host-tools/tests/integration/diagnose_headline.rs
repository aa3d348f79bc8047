//! The headline per effect is the nested held-out improvement, and the 95 %
//! interval printed beside it resamples the recordings that ratio is
//! computed over: the fit recordings, the only ones a decision reads.
use crate::diagnose_support;
use diagnose_support::{dataset, Added};
use mre_host::diagnose::heldout::bootstrap_ratio_ci95;
use mre_host::diagnose::{diagnose, report, summary_line, DiagnoseOptions};

#[test]
fn the_headline_interval_resamples_the_recordings_of_its_ratio() {
    // 0.5 A as validate: the decision pool (fit recordings) is then a strict
    // subset of the recordings the headline ratio covers.
    let opts = DiagnoseOptions {
        validate_currents_a: vec![0.5],
        ..DiagnoseOptions::default()
    };
    let d = diagnose(&dataset(Added::Viscous { c_n_s_per_m: 400.0 }, 2), &opts).expect("diagnosis");
    let f = d
        .findings
        .iter()
        .find(|f| f.effect.name() == "viscous_damping")
        .expect("viscous damping found");
    let (b, a) = (&f.nested.sse_before, &f.nested.sse_after);
    let m = d.prep.fit_indices().len();
    assert_eq!((b.len(), a.len()), (m, m), "one held-out SSE per fit recording");
    assert!(
        d.prep.recs.iter().any(|r| !r.is_fit()),
        "the set must hold validate recordings for the check to bite"
    );
    // The ratio, recomputed here from the per-recording SSEs over every recording.
    let ratio = (b.iter().sum::<f64>() / a.iter().sum::<f64>()).sqrt();
    assert!((f.heldout_improvement_nested - ratio).abs() < 1e-12 * ratio);
    // The interval over the same recordings, and not over the fit ones only.
    let every: Vec<usize> = (0..m).collect();
    let same = bootstrap_ratio_ci95(b, a, &every, &opts.thresholds);
    assert_eq!(f.ratio_ci95, same, "interval not over the ratio's recordings");
    assert!(
        f.ratio_ci95[0] <= ratio && ratio <= f.ratio_ci95[1],
        "{ratio} outside {:?}",
        f.ratio_ci95
    );
    // The JSON, the summary line and the report lead with the nested figure
    // and its interval.
    let j = report::report_json(&d);
    let e = j
        .effects
        .iter()
        .find(|e| e.name == "viscous_damping")
        .expect("in the JSON");
    assert_eq!(e.heldout_improvement_nested, f.heldout_improvement_nested);
    assert_eq!(e.heldout_improvement_nested_ci95, same);
    let shown = e.heldout_improvement_nested;
    assert!(summary_line(&j).contains(&format!("viscous_damping ({shown:.2}× held out, nested)")));
    let md = report::report_markdown(&d, &j);
    assert!(
        md.contains(&format!(
            "**viscous_damping**: {:.2}× held out, nested: the rest of the model chosen without each held-out fold (95 % CI {:.2}–{:.2}×",
            shown, same[0], same[1]
        )),
        "{md}"
    );
}
