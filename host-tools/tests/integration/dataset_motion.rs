//! Force–time drop records (docs/dataset-format.md): simulated drops with
//! only time and force kept are rebuilt into motion by the ISO 6603-2
//! integration, and compared with the simulator's own motion.
use mre_host::dataset::motion::{MotionSource, G_M_S2};
use mre_host::dataset::{Dataset, Role};
use mre_host::fit::{fit_dataset, model_file, FitOptions, Method};
use mre_host::plant::synth::{draw_base_plant, write_synth};
use mre_host::plant::{simulate, CurrentSource, ImpactConfig, Plant, Trajectory};
use mre_host::table_file::parse_table_toml;
use std::fmt::Write;
use std::path::Path;

const MASS_KG: f64 = 5.5;
const V0_M_S: f64 = 2.24;
/// Free-fall samples written before the contact (a drop tower's pre-trigger).
const PRE_CONTACT: usize = 25;

fn ideal_plant(seed: u64) -> Plant {
    let p = draw_base_plant(seed);
    Plant {
        measurement: p.measurement.ideal(),
        ..p
    }
}

fn drop(plant: &Plant, current_a: f64) -> Trajectory {
    let cfg = ImpactConfig {
        mass_kg: MASS_KG,
        impact_velocity_m_s: V0_M_S,
        initial_current_a: current_a,
        ..ImpactConfig::default()
    };
    simulate(plant, &cfg, CurrentSource::Constant(current_a)).unwrap()
}

/// `time_s,force_n` with `PRE_CONTACT` zero-force samples before contact.
fn force_time_csv(t: &Trajectory) -> String {
    let h = t.samples[1].time_s - t.samples[0].time_s;
    let mut s = String::from("time_s,force_n\n");
    for k in (1..=PRE_CONTACT).rev() {
        let _ = writeln!(s, "{:e},0", -(k as f64) * h);
    }
    for p in &t.samples {
        let _ = writeln!(s, "{:e},{:e}", p.time_s, p.force_n);
    }
    s
}

fn write_force_time_set(dir: &Path, drops: &[(f64, Trajectory)]) {
    let mut toml = format!("name = \"force-time\"\n[defaults]\nmass_kg = {MASS_KG}\nimpact_velocity_m_s = {V0_M_S}\n");
    for (i, (current_a, t)) in drops.iter().enumerate() {
        let file = format!("drop{i}.csv");
        std::fs::write(dir.join(&file), force_time_csv(t)).unwrap();
        let _ = write!(toml, "\n[[recording]]\nfile = \"{file}\"\ncurrent_a = {current_a}\n");
    }
    std::fs::write(dir.join("dataset.toml"), toml).unwrap();
}

/// The trapezoidal rule's error bound, interval by interval (step h, f = F/m):
/// - where F is smooth, |E_v| ≤ h³·max|f''|/12 ≈ h·|Δ²F|/(12 m) (the larger
///   second difference at the interval's ends);
/// - over the turn-around, where the model switches branch and F jumps,
///   |E_v| ≤ h·|ΔF|/(2 m) (a step inside one interval).
///
/// The x error is the v error carried to each sample plus the rule's own
/// error on v (v'' = −F'/m): h²·|ΔF|/(12 m) per smooth interval,
/// h²·|ΔF|/(2 m) over the switch. Returns the bounds at every sample.
fn trapezoid_bounds(t: &Trajectory) -> (Vec<f64>, Vec<f64>) {
    let f: Vec<f64> = t.samples.iter().map(|s| s.force_n).collect();
    let n = f.len();
    let d2 = |k: usize| {
        if k == 0 || k + 1 >= n {
            0.0
        } else {
            (f[k + 1] - 2.0 * f[k] + f[k - 1]).abs()
        }
    };
    let (mut tol_v, mut tol_x_mm) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n - 1 {
        let h = t.samples[i + 1].time_s - t.samples[i].time_s;
        let df = (f[i + 1] - f[i]).abs();
        let switch = (t.samples[i].v_m_s > 0.0) != (t.samples[i + 1].v_m_s > 0.0);
        let (ev, ex) = if switch {
            (h * df / (2.0 * MASS_KG), h * h * df / (2.0 * MASS_KG))
        } else {
            (
                h * d2(i).max(d2(i + 1)) / (12.0 * MASS_KG),
                h * h * df / (12.0 * MASS_KG),
            )
        };
        tol_v[i + 1] = tol_v[i] + ev;
        tol_x_mm[i + 1] = tol_x_mm[i] + (h * tol_v[i + 1] + ex) * 1e3;
    }
    (tol_v, tol_x_mm)
}

#[test]
fn rebuilt_motion_matches_the_simulator_within_the_trapezoid_bound() {
    let plant = ideal_plant(3);
    let drops: Vec<(f64, Trajectory)> = [0.0, 1.0, 2.0].iter().map(|&c| (c, drop(&plant, c))).collect();
    let dir = tempfile::tempdir().unwrap();
    write_force_time_set(dir.path(), &drops);
    let ds = Dataset::load(dir.path()).unwrap();
    for ((current_a, truth), rec) in drops.iter().zip(&ds.recordings) {
        assert_eq!(
            rec.motion_from,
            Some(MotionSource::Force {
                mass_kg: MASS_KG,
                impact_velocity_m_s: V0_M_S
            })
        );
        let s = &rec.samples;
        // The contact is found at t = 0 and the pre-trigger kept (10 samples).
        let contact = s
            .time_s
            .iter()
            .position(|&t| t.abs() < 1e-12)
            .expect("contact sample kept");
        assert_eq!(contact, 10, "{current_a} A: pre-trigger samples kept");
        assert_eq!(s.x_mm[contact], 0.0);
        // Before contact the striker falls freely: v = v0 + g t.
        assert!((s.v_m_s[0] - (V0_M_S + G_M_S2 * s.time_s[0])).abs() < 1e-12);
        let (tol_v, tol_x_mm) = trapezoid_bounds(truth);
        let (mut compared, mut worst_v, mut worst_x) = (0, 0.0f64, 0.0f64);
        for (k, p) in truth.samples.iter().enumerate() {
            let i = contact + k;
            if i >= s.len() {
                break;
            }
            assert!((s.time_s[i] - p.time_s).abs() < 1e-9);
            let (dv, dx) = ((s.v_m_s[i] - p.v_m_s).abs(), (s.x_mm[i] - p.x_mm).abs());
            assert!(
                dv <= tol_v[k] + 1e-9 && dx <= tol_x_mm[k] + 1e-9,
                "{current_a} A, t = {} s: |Δv| {dv:.2e} m/s (bound {:.2e}), |Δx| {dx:.2e} mm (bound {:.2e})",
                p.time_s,
                tol_v[k],
                tol_x_mm[k]
            );
            compared += 1;
            worst_v = worst_v.max(dv);
            worst_x = worst_x.max(dx);
        }
        let last = tol_x_mm.len() - 1;
        eprintln!(
            "{current_a} A: {compared} samples, worst |Δv| {worst_v:.1e} m/s, |Δx| {worst_x:.1e} mm; bound at the end \
             {:.1e} m/s, {:.1e} mm; stroke {:.2} mm",
            tol_v[last], tol_x_mm[last], truth.summary.max_stroke_mm
        );
        assert!(
            compared > 50,
            "{current_a} A: the record was trimmed to {compared} samples"
        );
        // The bound is a real constraint, not a blanket: well under the stroke.
        assert!(
            tol_x_mm[last] < 0.05 * truth.summary.max_stroke_mm,
            "{} mm",
            tol_x_mm[last]
        );
    }
}

/// The synthetic paper campaign (measurement noise, light-gate error of
/// 3 mm/s) fitted once on the simulator's recorded motion and once on motion
/// rebuilt from its force and recorded impact velocity.
///
/// Tolerance: the light gate's 3σ = 9 mm/s over a contact of T ≤ 15 ms
/// shifts x by ≤ 0.14 mm (Δx = Δv0·t), the force noise integrates to far
/// less; at the stiffest branch's slope (peak / stroke, ≈ 0.6 kN/mm) that is
/// ≤ 80 N, about 3 % of the 2 A peak. The two models' forces on the true
/// trajectories must agree within 3 % of each current's peak force (RMS).
#[test]
fn fit_from_rebuilt_motion_equals_fit_from_true_motion() {
    let synth_dir = tempfile::tempdir().unwrap();
    let synth = synth_dir.path().join("set");
    write_synth("none", 5, &synth, None, false).unwrap();
    let mut truth = Dataset::load(&synth).unwrap();
    truth.recordings.retain(|r| r.role == Role::Fit);
    let dir = tempfile::tempdir().unwrap();
    let mut toml = String::from("name = \"rebuilt\"\n");
    for (i, r) in truth.recordings.iter().enumerate() {
        let mut csv = String::from("time_s,force_n\n");
        for (t, f) in r.samples.time_s.iter().zip(&r.samples.force_n) {
            let _ = writeln!(csv, "{t:e},{f:e}");
        }
        let file = format!("r{i}.csv");
        std::fs::write(dir.path().join(&file), csv).unwrap();
        let _ = write!(
            toml,
            "\n[[recording]]\nfile = \"{file}\"\ncurrent_a = {}\nmass_kg = {}\nimpact_velocity_m_s = {}\n",
            r.current_a,
            r.mass_kg.unwrap(),
            r.impact_velocity_m_s.unwrap()
        );
    }
    std::fs::write(dir.path().join("dataset.toml"), toml).unwrap();
    let rebuilt = Dataset::load(dir.path()).unwrap();
    let options = FitOptions {
        method: Method::Lsq,
        ..FitOptions::default()
    };
    let a = fit_dataset(&truth, &options).unwrap();
    let b = fit_dataset(&rebuilt, &options).unwrap();
    let table = |m| parse_table_toml(&model_file::to_toml(m).unwrap()).unwrap();
    let (table_a, table_b) = (table(&a.model), table(&b.model));
    for current_a in [0.0, 0.5, 1.0, 1.5, 2.0] {
        let recs: Vec<_> = truth.recordings.iter().filter(|r| r.current_a == current_a).collect();
        let peak = recs
            .iter()
            .flat_map(|r| r.samples.force_n.iter())
            .fold(0.0f64, |m, f| m.max(*f));
        let (mut sum, mut n) = (0.0, 0usize);
        for r in &recs {
            for (x, v) in r.samples.x_mm.iter().zip(&r.samples.v_m_s) {
                let fa = table_a.force(*x as f32, *v as f32, current_a as f32).force_n as f64;
                let fb = table_b.force(*x as f32, *v as f32, current_a as f32).force_n as f64;
                sum += (fa - fb).powi(2);
                n += 1;
            }
        }
        let rms = (sum / n as f64).sqrt();
        eprintln!("{current_a} A: rebuilt-vs-true model RMS difference {rms:.1} N of peak {peak:.0} N");
        assert!(rms < 0.03 * peak, "{current_a} A: {rms:.1} N ≥ 3 % of {peak:.0} N");
    }
}

/// The drift study (BENCHMARKS rows): one 2 A drop rebuilt with a load-cell
/// offset δF or an impact-velocity error Δv0, against the closed form
/// Δx = −δF·t²/(2m) and Δx = Δv0·t at the end of contact. The trapezoidal
/// rule integrates constants and ramps exactly, so the measured drift must
/// equal the closed form to rounding (1e-9 mm). Print the table with
/// `cargo test -p host-tools --test integration dataset_motion::drift -- --nocapture`.
#[test]
fn drift_study_matches_the_closed_form() {
    let truth = drop(&ideal_plant(3), 2.0);
    let rebuild = |offset_n: f64, dv0: f64| {
        let dir = tempfile::tempdir().unwrap();
        let mut csv = String::from("time_s,force_n\n");
        for p in &truth.samples {
            let _ = writeln!(csv, "{:e},{:e}", p.time_s, p.force_n + offset_n);
        }
        std::fs::write(dir.path().join("d.csv"), csv).unwrap();
        let toml = format!(
            "name = \"drift\"\n[[recording]]\nfile = \"d.csv\"\ncurrent_a = 2.0\nmass_kg = {MASS_KG}\nimpact_velocity_m_s = {}\n",
            V0_M_S + dv0
        );
        std::fs::write(dir.path().join("dataset.toml"), toml).unwrap();
        Dataset::load(dir.path()).unwrap().recordings.remove(0).samples
    };
    let base = rebuild(0.0, 0.0);
    let n = base.len();
    let t_end = base.time_s[n - 1];
    eprintln!(
        "| error | drift of x at t = {:.2} ms (mm) | closed form (mm) | share of stroke (%) |",
        t_end * 1e3
    );
    eprintln!("|---|---|---|---|");
    for (offset_n, dv0) in [
        (5.0, 0.0),
        (20.0, 0.0),
        (50.0, 0.0),
        (0.0, 0.01),
        (0.0, 0.05),
        (20.0, 0.05),
    ] {
        let s = rebuild(offset_n, dv0);
        assert_eq!(s.time_s, base.time_s, "the same contact and window");
        let drift_mm = s.x_mm[n - 1] - base.x_mm[n - 1];
        let closed_mm = (-offset_n * t_end * t_end / (2.0 * MASS_KG) + dv0 * t_end) * 1e3;
        eprintln!(
            "| δF = {offset_n} N, Δv0 = {dv0} m/s | {drift_mm:.4} | {closed_mm:.4} | {:.2} |",
            100.0 * drift_mm.abs() / truth.summary.max_stroke_mm
        );
        assert!((drift_mm - closed_mm).abs() < 1e-9, "{drift_mm} against {closed_mm}");
    }
}
