//! No decision reads a `validate` recording it does not name as read: the
//! validate stage (`diagnose::validate_terms`) decides the terms only
//! validate recordings show on the deciding half of them and lists those
//! (`Selection::validate_read`). Replace every other validate recording's
//! forces with anything, and every decision (which terms are in the library,
//! their inclusion and held-out gains, which are named) and every fitted
//! parameter and interval stays bit-identical. Only the figures scored on
//! those recordings (the independent check) may move.
use mre_host::dataset::{Dataset, Role};
use mre_host::diagnose::{diagnose, DiagnoseOptions, Diagnosis};
use std::path::Path;

/// Everything the diagnosis decided or fitted, as text (f64 bit patterns
/// through `{:?}`, which prints the shortest round-tripping decimal).
fn decisions(d: &Diagnosis) -> Vec<String> {
    let s = &d.selection;
    let mut out = vec![format!("baseline table {:?}", d.baseline_table)];
    out.push(format!("not identifiable {:?}", s.not_identifiable));
    for c in &s.candidates {
        out.push(format!(
            "{:?}: named {} inclusion {:?} nested gain {:?} plain {:?} share {:?} terms {:?}",
            c.effect, c.named, c.inclusion, c.gain.ratio, c.gain_plain, c.share, c.own
        ));
    }
    out.push(format!(
        "final terms {:?} beta {:?} delta {:?}",
        s.final_model.terms, s.final_model.solution.beta, s.final_model.solution.delta
    ));
    for f in &d.findings {
        for (name, p) in &f.parameters {
            out.push(format!("{} {name} = {:?} ci {:?}", f.effect.name(), p.value, p.ci95));
        }
    }
    out
}

/// The forces of the validate recordings not in `read` replaced:
/// time-reversed, tripled and offset by 500 N (anything would do; this
/// keeps them finite).
fn scrambled(ds: &Dataset, read: &[String]) -> Dataset {
    let mut out = ds.clone();
    let mut n = 0;
    for r in out
        .recordings
        .iter_mut()
        .filter(|r| r.role == Role::Validate && !read.contains(&r.file))
    {
        let f = &mut r.samples.force_n;
        f.reverse();
        for v in f.iter_mut() {
            *v = 3.0 * *v + 500.0;
        }
        n += 1;
    }
    assert!(n >= 2, "the data set needs validate recordings");
    out
}

fn check(dir: &str) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(dir);
    let ds = Dataset::load(&root).expect("bundled data set");
    let opts = DiagnoseOptions::default();
    let a = diagnose(&ds, &opts).expect("diagnosis");
    let read: Vec<String> = a
        .selection
        .validate_read
        .iter()
        .map(|&i| a.prep.recs[i].file.clone())
        .collect();
    let b = diagnose(&scrambled(&ds, &read), &opts).expect("diagnosis");
    let (da, db) = (decisions(&a), decisions(&b));
    assert!(
        !a.findings.is_empty(),
        "{dir}: the effect should be found, or the test checks little"
    );
    for (x, y) in da.iter().zip(&db) {
        assert_eq!(x, y, "{dir}: a decision or parameter read the validate recordings");
    }
    assert_eq!(da.len(), db.len(), "{dir}");
}

/// The scale route (softening over the run order) read the validate
/// recordings' gains; the noise gates the force noise of every recording.
#[test]
fn softening_is_decided_without_the_validate_recordings() {
    check("data/drop-stress_softening");
}

/// `hysteresis_memory` was accepted on every recording; the delay's
/// refinement and the parameter bootstrap resampled every recording.
#[test]
fn a_delay_is_decided_without_the_validate_recordings() {
    check("data/drop-sensor_delay");
}
