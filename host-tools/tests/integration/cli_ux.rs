//! What a user of the `mre` binary sees: the HTML page beside a report,
//! no progress output when stderr is not a terminal, shell completions.

use crate::mre_cli::mre;

#[test]
fn validate_writes_a_page_whose_numbers_are_the_json_ones() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report");
    let out = mre()
        .args(["validate", "data/mr-damper-mts", "--model", "paper", "--report"])
        .arg(&report)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // stderr is a pipe here: no progress display.
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap()).unwrap();
    let recordings = json["recordings"].as_array().unwrap();
    assert_eq!(recordings.len(), 15);
    for (i, r) in recordings.iter().enumerate() {
        let rmse = r["rmse_n"].as_f64().unwrap();
        let key = format!("data-json-path=\"report.json#/recordings/{i}/rmse_n\">");
        let at = html.find(&key).unwrap_or_else(|| panic!("no {key}")) + key.len();
        let shown: f64 = html[at..html[at..].find('<').unwrap() + at].parse().unwrap();
        // Four significant digits: within half a unit of the 4th digit.
        assert!(
            (shown - rmse).abs() <= 5e-4 * rmse.abs(),
            "recording {i}: {shown} vs {rmse}"
        );
    }
    assert!(html.contains("<a href=\"report.json\">report.json</a>"));
    assert!(!html.contains("<script"));
}

#[test]
fn quiet_is_accepted_everywhere_and_completions_name_the_commands() {
    let out = mre().args(["completions", "bash", "--quiet"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let script = String::from_utf8(out.stdout).unwrap();
    assert!(script.contains("complete -F _mre"), "a bash completion function");
    for sub in ["demo", "validate", "diagnose", "dataset", "init", "completions"] {
        assert!(script.contains(sub), "completes {sub}");
    }
}
