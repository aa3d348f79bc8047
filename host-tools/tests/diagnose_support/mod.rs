//! Small synthetic data sets with a known generating law, for the diagnosis
//! tests. The law is inside the paper's model structure (a function of
//! displacement, branch and current only), so any added term is the only
//! thing missing.
#![allow(dead_code)]
use mre_host::dataset::{Dataset, Recording, Role, Samples};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// What is added to the law.
#[derive(Clone, Copy, Debug)]
pub enum Added {
    None,
    /// `+ c·v` (N·s/m).
    Viscous {
        c_n_s_per_m: f64,
    },
    /// `F_meas(t) = F(t − τ)`.
    Delay {
        tau_s: f64,
    },
    /// `× (1 − Δ·(1 − e^{−(n−1)/n0}))` with n the test's `sequence`.
    Softening {
        delta: f64,
        n0: f64,
    },
    /// The material sees the coil command through a first-order lag τ.
    CoilLag {
        tau_s: f64,
    },
}

/// Controlled impacts added by [`dataset_with_steps`]: (from, to) command in A.
pub const STEPS_A: [(f64, f64); 4] = [(0.0, 1.0), (1.0, 0.0), (0.25, 0.75), (0.75, 0.25)];
/// The command switches half a sample before this sample (so the recorded
/// value changes at it): a third of the way into the stroke.
pub const STEP_SAMPLE: usize = 80;

/// The coil current after a command step at `t_step` from `from` to `to`,
/// through a first-order lag `tau_s` (0 = none): the closed form.
pub fn lagged_step_a(from: f64, to: f64, t: f64, t_step: f64, tau_s: f64) -> f64 {
    if t < t_step {
        from
    } else if tau_s <= 0.0 {
        to
    } else {
        to + (from - to) * (-(t - t_step) / tau_s).exp()
    }
}

/// [`dataset`] plus four `validate` controlled impacts (3 mm stroke) whose
/// command steps between currents mid-stroke ([`STEPS_A`]), recorded per
/// sample in the `current_a` column. Only `Added::CoilLag` changes them.
pub fn dataset_with_steps(added: Added, seed: u64) -> Dataset {
    let mut ds = dataset(
        match added {
            Added::CoilLag { .. } => Added::None,
            other => other,
        },
        seed,
    );
    let tau_s = match added {
        Added::CoilLag { tau_s } => tau_s,
        _ => 0.0,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x57e9);
    let noise = Normal::new(0.0, 1.0).expect("valid");
    let t_step = (STEP_SAMPLE as f64 - 0.5) * SAMPLE_PERIOD_S;
    for (k, &(from, to)) in STEPS_A.iter().enumerate() {
        let mut s = Samples::default();
        let mut command = Vec::new();
        for i in 0..SAMPLES {
            let t = i as f64 * SAMPLE_PERIOD_S;
            let (x, v) = kinematics(3.0, t);
            // The law is linear in current, so the law at the coil's current
            // is what the paper's interpolation gives at that current.
            let current = lagged_step_a(from, to, t, t_step, tau_s);
            s.time_s.push(t);
            s.x_mm.push(x);
            s.v_m_s.push(v);
            s.force_n.push(law_n(x, v > 0.0, current) + noise.sample(&mut rng));
            command.push(if i >= STEP_SAMPLE { to } else { from });
        }
        s.current_a = Some(command);
        ds.recordings.push(Recording {
            file: format!("step{k}_i{from}-{to}.csv"),
            current_a: from,
            role: Role::Validate,
            mass_kg: None,
            impact_velocity_m_s: None,
            sequence: Some(19 + k as u32),
            temperature_c: None,
            tags: BTreeMap::new(),
            samples: s,
            velocity_estimated: false,
            motion_from: None,
            notes: Vec::new(),
        });
    }
    ds
}

pub const SAMPLE_PERIOD_S: f64 = 1.0e-4;
const SAMPLES: usize = 240;

/// The law: stiffness grows with current; unloading carries 60 % of loading.
pub fn law_n(x_mm: f64, compressing: bool, current_a: f64) -> f64 {
    let k = 100.0 * (1.0 + 2.0 * current_a);
    let f = k * (x_mm + 0.05 * x_mm * x_mm);
    if compressing {
        f
    } else {
        0.6 * f
    }
}

/// A half-sine stroke of amplitude `x_max_mm` over the recording.
fn kinematics(x_max_mm: f64, t: f64) -> (f64, f64) {
    let period = SAMPLES as f64 * SAMPLE_PERIOD_S;
    let w = std::f64::consts::PI / period;
    (x_max_mm * (w * t).sin(), x_max_mm * w * (w * t).cos() / 1000.0)
}

/// 3 currents × 3 strokes (speeds) × 2 repeats, shuffled run order in `sequence`.
pub fn dataset(added: Added, seed: u64) -> Dataset {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let noise = Normal::new(0.0, 1.0).expect("valid");
    let mut recordings = Vec::new();
    let order = [7, 3, 12, 1, 16, 9, 5, 18, 2, 14, 11, 6, 17, 4, 10, 15, 8, 13];
    let mut n = 0;
    for current_a in [0.0, 0.5, 1.0] {
        for x_max_mm in [2.0, 3.0, 4.0] {
            for repeat in 1..=2 {
                let mut s = Samples::default();
                for i in 0..SAMPLES {
                    let t = i as f64 * SAMPLE_PERIOD_S;
                    let (x, v) = kinematics(x_max_mm, t);
                    let (xf, vf) = match added {
                        Added::Delay { tau_s } => kinematics(x_max_mm, (t - tau_s).max(0.0)),
                        _ => (x, v),
                    };
                    let mut f = law_n(xf, vf > 0.0, current_a);
                    if let Added::Viscous { c_n_s_per_m } = added {
                        f += c_n_s_per_m * v;
                    }
                    if let Added::Softening { delta, n0 } = added {
                        let n = f64::from(order[n]);
                        f *= 1.0 - delta * (1.0 - (-(n - 1.0) / n0).exp());
                    }
                    s.time_s.push(t);
                    s.x_mm.push(x);
                    s.v_m_s.push(v);
                    s.force_n.push(f + noise.sample(&mut rng));
                }
                recordings.push(Recording {
                    file: format!("i{current_a}_x{x_max_mm}_r{repeat}.csv"),
                    current_a,
                    role: Role::Fit,
                    mass_kg: None,
                    impact_velocity_m_s: None,
                    sequence: Some(order[n]),
                    temperature_c: None,
                    tags: BTreeMap::new(),
                    samples: s,
                    velocity_estimated: false,
                    motion_from: None,
                    notes: Vec::new(),
                });
                n += 1;
            }
        }
    }
    Dataset {
        name: "diagnose test".into(),
        root: PathBuf::new(),
        recordings,
    }
}

/// A campaign of fit recordings at each of `currents_a` and each
/// `(amplitude mm, frequency Hz)` of `tests`, named `a{A}_f{f}_i{I}.csv`,
/// with seeded Gaussian noise: `noise_n` on the force, `v_noise_m_s` on the
/// recorded velocity (the force is computed from the true one).
pub struct Campaign<'a> {
    pub name: &'a str,
    pub currents_a: &'a [f64],
    pub tests: &'a [(f64, f64)],
    pub noise_n: f64,
    pub v_noise_m_s: f64,
    pub seed: u64,
}

impl Campaign<'_> {
    /// The motion `motion(A, f)` = (t, x, v) and the force `force(x, v, I)`
    /// (whole recordings) of each test.
    #[allow(clippy::type_complexity)]
    pub fn build(
        &self,
        motion: impl Fn(f64, f64) -> (Vec<f64>, Vec<f64>, Vec<f64>),
        force: impl Fn(&[f64], &[f64], f64) -> Vec<f64>,
    ) -> Dataset {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let f_noise = Normal::new(0.0, self.noise_n).expect("a finite force noise");
        let v_noise = Normal::new(0.0, self.v_noise_m_s).expect("a finite velocity noise");
        let mut recordings = Vec::new();
        for &current_a in self.currents_a {
            for &(amp_mm, freq_hz) in self.tests {
                let (time_s, x_mm, v_true) = motion(amp_mm, freq_hz);
                let force_n = force(&x_mm, &v_true, current_a)
                    .into_iter()
                    .map(|f| f + f_noise.sample(&mut rng))
                    .collect();
                let v_m_s = if self.v_noise_m_s > 0.0 {
                    v_true.iter().map(|v| v + v_noise.sample(&mut rng)).collect()
                } else {
                    v_true
                };
                recordings.push(fit_recording(
                    format!("a{amp_mm}_f{freq_hz}_i{current_a}.csv"),
                    current_a,
                    Samples {
                        time_s,
                        x_mm,
                        v_m_s,
                        force_n,
                        ..Samples::default()
                    },
                ));
            }
        }
        Dataset {
            name: self.name.into(),
            root: PathBuf::new(),
            recordings,
        }
    }
}

/// A fit recording that carries only its current (no mass, run order or tags).
pub fn fit_recording(file: String, current_a: f64, samples: Samples) -> Recording {
    Recording {
        file,
        current_a,
        role: Role::Fit,
        mass_kg: None,
        impact_velocity_m_s: None,
        sequence: None,
        temperature_c: None,
        tags: BTreeMap::new(),
        samples,
        velocity_estimated: false,
        motion_from: None,
        notes: Vec::new(),
    }
}
