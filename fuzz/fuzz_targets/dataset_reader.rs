//! The dataset reader on arbitrary bytes: a recording file (both delimiters)
//! and, from the same bytes, a `dataset.toml`. Never a panic; whatever is
//! accepted holds the reader's promises.
#![no_main]
use libfuzzer_sys::fuzz_target;
use mre_host::dataset::columns::Quantity;
use mre_host::dataset::read::parse_recording;
use mre_host::dataset::Dataset;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A folder with one valid recording, for manifests to point at.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("mre-fuzz-dataset-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut csv = String::from("time_s,displacement_mm,force_n\n");
        for i in 0..12 {
            csv.push_str(&format!("{},{},{}\n", i as f64 * 0.01, i as f64 * 0.1, i as f64 * 5.0));
        }
        std::fs::write(dir.join("a.csv"), csv).unwrap();
        dir
    })
}

fn within(values: &[f64], q: Quantity) -> bool {
    let (min, max, _) = q.plausible_range();
    values.iter().all(|v| (min..=max).contains(v))
}

fuzz_target!(|data: &[u8]| {
    for whitespace in [false, true] {
        if let Ok(s) = parse_recording(data, whitespace, "fuzz.csv") {
            let n = s.time_s.len();
            assert!(n >= mre_host::dataset::read::MIN_SAMPLES);
            // Force, or (an accelerometer drop record) acceleration it is derived from at load.
            assert!(s.force_n.len() == n || (s.force_n.is_empty() && s.accel_m_s2.as_ref().is_some_and(|a| a.len() == n)));
            // Motion is complete, or absent: a force-only record (a drop
            // tower's, or one whose displacement channel is not a name mre
            // knows) gets it derived at load from mass and impact velocity.
            let motion = (s.x_mm.len(), s.v_m_s.len());
            assert!(motion == (n, n) || motion == (0, 0), "motion {motion:?} of {n} samples");
            assert!(s.time_s.windows(2).all(|w| w[1] > w[0]), "time increases");
            assert!(within(&s.time_s, Quantity::Time));
            assert!(within(&s.x_mm, Quantity::Displacement));
            assert!(within(&s.force_n, Quantity::Force));
            assert!(within(&s.v_m_s, Quantity::Velocity), "velocity, measured or estimated");
        }
    }
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(ds) = Dataset::from_manifest(folder(), text) {
            for r in &ds.recordings {
                assert!(r.current_a.is_finite());
                assert!(!r.samples.time_s.is_empty());
            }
        }
    }
});
