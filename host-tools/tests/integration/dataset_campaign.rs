//! A paper-style campaign as a lab's drop tower writes it, through the
//! README's commands: `mre dataset init` → `fit` → `validate` → `diagnose`
//! → `tables`. Force–time records only (no displacement), one drop per
//! current at 2.24 m/s with 5.5 kg, compression negative in the raw file,
//! in the Instron Bluehill raw-data CSV layout.
//!
//! The layout, as the issue (#27) and Instron's Bluehill export describe
//! it: metadata lines, a blank line, a row of quoted channel names and a
//! row of units in parentheses (`"(sec)","(N)"`), then comma-separated data.
use mre_host::plant::synth::draw_base_plant;
use mre_host::plant::{simulate, CurrentSource, ImpactConfig};
use std::fmt::Write;
use std::path::Path;
use std::process::Command;

fn mre(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_mre"))
        .args(args)
        .arg("--quiet")
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "mre {args:?} failed: {text}");
    text
}

/// One drop per current on a simulated damper (with its instrument noise),
/// written as Bluehill writes a raw-data export, load negative in compression.
fn write_campaign(dir: &Path) {
    let plant = draw_base_plant(3);
    for current_a in [0.0, 0.5, 1.0, 1.5, 2.0] {
        let cfg = ImpactConfig {
            mass_kg: 5.5,
            impact_velocity_m_s: 2.24,
            initial_current_a: current_a,
            noise_seed: (current_a * 10.0) as u64,
            ..ImpactConfig::default()
        };
        let t = simulate(&plant, &cfg, CurrentSource::Constant(current_a)).unwrap();
        let h = t.samples[1].time_s - t.samples[0].time_s;
        let mut s = String::from("\"Sample ID:\",\"MRE damper\"\r\n\"Test date:\",\"2024-05-02\"\r\n\r\n");
        s.push_str("\"Time\",\"Load\"\r\n\"(sec)\",\"(N)\"\r\n");
        // 20 pre-trigger samples, as the tower records before contact.
        for k in (1..=20).rev() {
            let _ = write!(s, "{:.6},{:.3}\r\n", -(k as f64) * h, 0.0);
        }
        for p in &t.samples {
            let _ = write!(s, "{:.6},{:.3}\r\n", p.time_s, -p.force_n);
        }
        let name = format!("drop{}A.csv", current_a.to_string().replace('.', "x"));
        std::fs::write(dir.join(name), s).unwrap();
    }
}

#[test]
fn force_time_campaign_goes_through_init_fit_validate_diagnose_tables() {
    let root = tempfile::tempdir().unwrap();
    let data = root.path().join("campaign");
    std::fs::create_dir(&data).unwrap();
    write_campaign(&data);
    let d = data.to_str().unwrap();
    mre(&["dataset", "init", d, "--pattern", "drop{current_a}A"]);
    let manifest = std::fs::read_to_string(data.join("dataset.toml")).unwrap();
    assert!(manifest.contains("columns = [\"time_s\", \"force_n\"]"), "{manifest}");
    assert_eq!(manifest.matches("sign = { force_n = -1 }").count(), 5, "{manifest}");
    assert!(
        manifest.contains("# assumed: `force_n` reads compression negative"),
        "{manifest}"
    );
    // What the file names cannot say: the tower's mass and light-gate velocity.
    let manifest = manifest.replace(
        "[defaults]\n",
        "[defaults]\nmass_kg = 5.5\nimpact_velocity_m_s = 2.24\n",
    );
    std::fs::write(data.join("dataset.toml"), manifest).unwrap();

    let model = root.path().join("model.toml");
    let m = model.to_str().unwrap();
    mre(&["fit", d, "--method", "lsq", "--out", m]);
    let report = root.path().join("validate");
    mre(&["validate", d, "--model", m, "--report", report.to_str().unwrap()]);
    let md = std::fs::read_to_string(report.join("report.md")).unwrap();
    assert!(
        md.contains("integrated from force"),
        "the report says motion was derived: {md}"
    );
    // Every drop is fitted: NRMSE well under 10 % on each recording.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap()).unwrap();
    for r in json["recordings"].as_array().unwrap() {
        assert!(r["nrmse"].as_f64().unwrap() < 0.10, "{r}");
    }
    let diag = root.path().join("diagnose");
    let final_model = root.path().join("final.toml");
    mre(&[
        "diagnose",
        d,
        "--report",
        diag.to_str().unwrap(),
        "--json",
        diag.join("report.json").to_str().unwrap(),
        "--predictions",
        diag.join("predictions").to_str().unwrap(),
        "--model-out",
        final_model.to_str().unwrap(),
    ]);
    let table = root.path().join("generated_table.rs");
    mre(&[
        "tables",
        final_model.to_str().unwrap(),
        "--out",
        table.to_str().unwrap(),
    ]);
    assert!(std::fs::read_to_string(&table).unwrap().contains("crc"));
}
