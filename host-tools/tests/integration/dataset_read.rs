//! `Dataset::load`: the spec's format, unit conversion, defaults, and each
//! bad-input case with its exact message.
use mre_host::dataset::{split_branches, Dataset, DatasetError, Role, TagValue};
use std::path::Path;

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

/// A CSV of `n` samples of a 1 Hz, 2 mm sine at 100 Hz with F = 100·x.
fn sine_csv(n: usize) -> String {
    let mut s = String::from("time_s,displacement_mm,velocity_m_s,force_n\n");
    for i in 0..n {
        let t = i as f64 * 0.01;
        let w = 2.0 * std::f64::consts::PI;
        let x = 2.0 * (w * t).sin();
        let v = 2.0 * w * (w * t).cos() * 1e-3;
        s.push_str(&format!("{t},{x},{v},{}\n", 100.0 * x));
    }
    s
}

fn load_err(dir: &Path) -> String {
    Dataset::load(dir).unwrap_err().to_string()
}

#[test]
fn loads_bundled_mts_data() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mr-damper-mts");
    let ds = Dataset::load(&dir).unwrap();
    assert_eq!(ds.recordings.len(), 15);
    let r = &ds.recordings[0];
    assert_eq!(r.file, "2mm5Hz0A.txt");
    // First line: 0 s, -2.6156111e-02 mm, -1.2 mm/s, -90.296201 N.
    assert_eq!(r.samples.x_mm[0], -2.6156111e-02);
    assert!((r.samples.v_m_s[0] - -1.2e-3).abs() < 1e-15);
    assert_eq!(r.samples.force_n[0], -9.0296201e+01);
    assert_eq!(r.samples.len(), 449);
    assert!(!r.velocity_estimated);
    assert_eq!(r.role, Role::Fit);
    assert_eq!(r.tags.get("frequency_hz"), Some(&TagValue::Number(5.0)));
}

#[test]
fn converts_units_inherits_defaults_and_estimates_velocity() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "dataset.toml",
        "name = \"t\"\n[defaults]\nmass_kg = 5.5\ncurrent_a = 0.5\n\n[[recording]]\nfile = \"a.csv\"\n\
         role = \"validate\"\ntemperature_c = 20\n",
    );
    // ms, m and kN: 10 samples of x = 1 mm + 2 mm/s · t, F = 1.5 kN.
    let mut csv = String::from("time_ms,displacement_m,force_kn,ignore\n");
    for i in 0..10 {
        let t_ms = i as f64 * 10.0;
        csv.push_str(&format!("{t_ms},{},1.5,zzz\n", (1.0 + 2.0 * t_ms * 1e-3) * 1e-3));
    }
    write(dir.path(), "a.csv", &csv);
    let ds = Dataset::load(dir.path()).unwrap();
    let r = &ds.recordings[0];
    assert_eq!(r.current_a, 0.5);
    assert_eq!(r.mass_kg, Some(5.5));
    assert_eq!(r.temperature_c, Some(20.0));
    assert_eq!(r.role, Role::Validate);
    assert!((r.samples.time_s[3] - 0.03).abs() < 1e-12);
    assert!((r.samples.x_mm[5] - 1.1).abs() < 1e-9);
    assert_eq!(r.samples.force_n[2], 1500.0);
    // Velocity estimated: a line with slope 2 mm/s = 0.002 m/s, everywhere.
    assert!(r.velocity_estimated);
    for v in &r.samples.v_m_s {
        assert!((v - 0.002).abs() < 1e-9, "{v}");
    }
}

#[test]
fn estimated_velocity_follows_a_noisy_sine_through_turnaround() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "dataset.toml",
        "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 0\n",
    );
    // 10 mm, 1 Hz at 1 kHz; ±5 µm uniform noise (well above quantisation).
    let mut csv = String::from("time_s,displacement_mm,force_n\n");
    let w = 2.0 * std::f64::consts::PI;
    for i in 0..1000 {
        let t = i as f64 * 1e-3;
        let x = 10.0 * (w * t).sin() + rng.random_range(-0.005..0.005);
        csv.push_str(&format!("{t},{x},0\n"));
    }
    write(dir.path(), "a.csv", &csv);
    let r = &Dataset::load(dir.path()).unwrap().recordings[0];
    // True v = 10 mm · ω cos(ωt) → 0.0628 m/s peak. Central difference noise
    // would be ~0.005 mm/1 ms·0.7 = 3.5 mm/s; the 7-point quadratic gives < 1 mm/s.
    for (i, v) in r.samples.v_m_s.iter().enumerate().skip(3).take(990) {
        let t = i as f64 * 1e-3;
        let truth = 10.0 * w * (w * t).cos() * 1e-3;
        assert!((v - truth).abs() < 2e-3, "sample {i}: {v} vs {truth}");
    }
    // At turn-around (t = 0.25 s, v = 0) the estimate stays near zero.
    assert!(r.samples.v_m_s[250].abs() < 2e-3);
}

#[test]
fn splits_branches_by_velocity_sign_leaving_out_the_noise_band() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "dataset.toml",
        "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 1\n",
    );
    write(dir.path(), "a.csv", &sine_csv(100));
    let r = &Dataset::load(dir.path()).unwrap().recordings[0];
    let (c, e) = split_branches(&r.samples);
    // v = 4π·cos(2πt) mm/s, t = 0.01·i. Its second difference is
    // −(2π·0.01)²·v, median |·| at |cos| = 0.707: 3.5e-5 m/s, so the noise
    // estimate is 1.4826·3.5e-5/√6 = 2.1e-5 and the band 4.2e-5 m/s. Only
    // t = 0.25 and 0.75 (cos ≈ 1e-16) fall in it; the nearest others have
    // |v| = 4π·sin(0.02π) = 0.79 mm/s. Compression: t < 0.25 (25) and t > 0.75
    // (24); extension: 0.26..=0.74 (49).
    assert_eq!((c.len(), e.len()), (49, 49));
}

fn one_recording(dir: &Path, csv: &str) {
    write(
        dir,
        "dataset.toml",
        "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 1.0\n",
    );
    write(dir, "a.csv", csv);
}

#[test]
fn error_unknown_key_names_key_and_line() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "dataset.toml",
        "[[recording]]\nfile = \"a.csv\"\ncurent_a = 1.0\n",
    );
    let m = dir.path().join("dataset.toml").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!("{m}: line 3: unknown key `curent_a` in [[recording]]")
    );
    write(dir.path(), "dataset.toml", "[defaults]\nmas_kg = 1\n");
    assert_eq!(
        load_err(dir.path()),
        format!("{m}: line 2: unknown key `mas_kg` in [defaults]")
    );
}

#[test]
fn error_missing_required_column() {
    let dir = tempfile::tempdir().unwrap();
    one_recording(dir.path(), "time_s,displacement_mm\n0,0\n");
    let f = dir.path().join("a.csv").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!(
            "{f}: line 1: missing required column for force (one of force_n, force_kn, force_lbf; \
             or, for an accelerometer drop record with mass_kg, acceleration_m_s2, acceleration_g)"
        )
    );
}

#[test]
fn error_unknown_column_name() {
    let dir = tempfile::tempdir().unwrap();
    one_recording(dir.path(), "time_s,displacement_cm,force_n\n");
    let f = dir.path().join("a.csv").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!(
            "{f}: line 1, column 2: unknown column name `displacement_cm` (accepted: time_s, time_ms, \
             displacement_mm, displacement_m, displacement_in, velocity_m_s, velocity_mm_s, acceleration_m_s2, \
             acceleration_g, force_n, force_kn, force_lbf, current_a, temperature_c, ignore)"
        )
    );
}

#[test]
fn error_non_numeric_value() {
    let dir = tempfile::tempdir().unwrap();
    let mut csv = sine_csv(20);
    csv = csv.replacen("\n0.05,", "\n0.05,abc,", 1);
    // Line 7 holds t = 0.05 (header is line 1); its x field became "abc" and
    // the old x moved right, so the row has one field too many.
    one_recording(dir.path(), &csv);
    let f = dir.path().join("a.csv").display().to_string();
    assert_eq!(load_err(dir.path()), format!("{f}: line 7: 5 fields, expected 4"));
    let csv = sine_csv(20).replace("\n0.05,", "\n0.05,zz");
    one_recording(dir.path(), &csv);
    let err = load_err(dir.path());
    assert!(
        err.starts_with(&format!("{f}: line 7, column 2 (displacement_mm): `zz")),
        "{err}"
    );
    assert!(err.ends_with("` is not a number"), "{err}");
}

#[test]
fn error_non_finite_value() {
    let dir = tempfile::tempdir().unwrap();
    let csv = "time_s,displacement_mm,force_n\n0,0,1\n0.1,0,NaN\n";
    one_recording(dir.path(), csv);
    let f = dir.path().join("a.csv").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!("{f}: line 3, column 3 (force_n): `NaN` is not finite")
    );
    one_recording(dir.path(), "time_s,displacement_mm,force_n\n0,inf,1\n");
    assert_eq!(
        load_err(dir.path()),
        format!("{f}: line 2, column 2 (displacement_mm): `inf` is not finite")
    );
}

#[test]
fn error_time_not_increasing() {
    let dir = tempfile::tempdir().unwrap();
    // Time going back (a tie is an export's resolution: dataset_lab_text.rs).
    one_recording(dir.path(), "time_s,displacement_mm,force_n\n0,0,1\n0.2,0,1\n0.1,0,1\n");
    let f = dir.path().join("a.csv").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!("{f}: line 4, column 1 (time_s): time 0.1 s does not increase (previous sample 0.2 s)")
    );
}

#[test]
fn error_too_few_samples() {
    let dir = tempfile::tempdir().unwrap();
    one_recording(dir.path(), &sine_csv(9));
    let f = dir.path().join("a.csv").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!("{f}: line 10: only 9 samples; a fit needs at least 10")
    );
}

#[test]
fn error_listed_file_absent() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "dataset.toml",
        "name = \"x\"\n\n[[recording]]\nfile = \"gone.csv\"\ncurrent_a = 0\n",
    );
    let m = dir.path().join("dataset.toml").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!("{m}: line 4: listed file `gone.csv` does not exist")
    );
}

#[test]
fn error_duplicate_file_entry() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "dataset.toml",
        "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 0\n[[recording]]\nfile = \"a.csv\"\ncurrent_a = 1\n",
    );
    write(dir.path(), "a.csv", &sine_csv(20));
    let m = dir.path().join("dataset.toml").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!("{m}: line 5: file `a.csv` is listed twice (first on line 2)")
    );
}

#[test]
fn error_non_finite_current_and_bad_role() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a.csv", &sine_csv(20));
    write(
        dir.path(),
        "dataset.toml",
        "[[recording]]\nfile = \"a.csv\"\ncurrent_a = nan\n",
    );
    let m = dir.path().join("dataset.toml").display().to_string();
    assert_eq!(
        load_err(dir.path()),
        format!("{m}: line 3: `current_a` must be a finite number, got NaN")
    );
    write(
        dir.path(),
        "dataset.toml",
        "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 1\nrole = \"fitt\"\n",
    );
    assert_eq!(
        load_err(dir.path()),
        // `role = "fitt"`: the value starts at column 8.
        format!("{m}: line 4, column 8: unknown variant `fitt`, expected `fit` or `validate`")
    );
}

#[test]
fn error_variants_are_matchable() {
    let dir = tempfile::tempdir().unwrap();
    one_recording(dir.path(), "time_s,displacement_mm,force_n\n0,0,1\n-1,0,1\n");
    assert!(matches!(
        Dataset::load(dir.path()),
        Err(DatasetError::TimeNotIncreasing { line: 3, column: 1, .. })
    ));
}
