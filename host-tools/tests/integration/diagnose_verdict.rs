//! Issue 38, item 1: three verdicts. On too little data with a residual far
//! above the noise the verdict is an effect or `inconclusive` (with a reason
//! and the experiment that would decide), never `none`; near the noise it is
//! `none` however little data; and the report never counts more folds than
//! there are recordings.
use crate::diagnose_support;

use diagnose_support::{dataset, Added};
use mre_host::dataset::Dataset;
use mre_host::diagnose::verdict::Verdict;
use mre_host::diagnose::{diagnose, report, DiagnoseOptions};
use std::path::Path;

fn keep(mut ds: Dataset, files: &[&str]) -> Dataset {
    ds.recordings.retain(|r| files.contains(&r.file.as_str()));
    assert_eq!(ds.recordings.len(), files.len(), "every named recording is in the set");
    ds
}

/// Four real MR-damper tests, one 2 mm 5 Hz test at each current and a 5 mm
/// 3 Hz test at 1 A: the baseline leaves a residual of hundreds of newtons
/// against a force noise under 1 N (the damper's rate dependence and memory,
/// which the full set finds). Before issue 38 the report said "No missing
/// physics found" and "5 cross-validation folds" here.
fn four_real_recordings() -> Dataset {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mr-damper-mts");
    let ds = Dataset::load(&root).expect("bundled data set");
    keep(ds, &["2mm5Hz0A.txt", "2mm5Hz0x5A.txt", "2mm5Hz1A.txt", "5mm3Hz1A.txt"])
}

#[test]
fn four_recordings_far_above_the_noise_are_never_none() {
    let d = diagnose(&four_real_recordings(), &DiagnoseOptions::default()).expect("diagnose");
    // The default plan asks for 5 folds; 4 recordings make 4.
    assert_eq!(d.prep.n_folds, 4);
    let v = &d.verdict;
    assert!(
        v.residual_over_noise > 20.0,
        "residual {}× noise",
        v.residual_over_noise
    );
    match v.verdict {
        Verdict::Found => assert!(!d.findings.is_empty()),
        Verdict::Inconclusive => {
            assert!(!v.reasons.is_empty());
            assert!(v.reasons.iter().any(|r| r.code == "too_few_folds"), "{:?}", v.reasons);
            assert!(v.reasons.iter().all(|r| !r.experiment.is_empty()));
        }
        Verdict::None => panic!(
            "`none` on 4 recordings with a residual {}× the noise",
            v.residual_over_noise
        ),
    }
    let json = report::report_json(&d);
    let md = report::report_markdown(&d, &json);
    assert!(md.contains("4 cross-validation folds"), "{md}");
    assert!(!md.contains("5 cross-validation folds"));
    assert!(!md.contains("Verdict: none"));
}

#[test]
fn four_recordings_at_the_noise_are_none() {
    // The law is in the model class and nothing is added, and each held-out
    // test has a repeat of the same stroke in training: the held-out residual
    // is the 1 N noise, and there is nothing left to find however few tests.
    // (With strokes 2 and 4 mm instead, the 4 mm test is predicted by a
    // quartic fitted to 2 mm: extrapolation leaves ~14× the noise, rightly
    // inconclusive.)
    let ds = keep(
        dataset(Added::None, 3),
        &["i0_x4_r1.csv", "i0_x4_r2.csv", "i1_x4_r1.csv", "i1_x4_r2.csv"],
    );
    let d = diagnose(&ds, &DiagnoseOptions::default()).expect("diagnose");
    assert_eq!(d.verdict.verdict, Verdict::None, "{:?}", d.verdict);
    assert!(d.verdict.residual_over_noise < 5.0);
}

#[test]
fn ample_data_at_the_noise_are_none_with_five_folds() {
    let d = diagnose(&dataset(Added::None, 4), &DiagnoseOptions::default()).expect("diagnose");
    assert_eq!(d.prep.n_folds, 5);
    assert_eq!(d.verdict.verdict, Verdict::None, "{:?}", d.verdict);
}
