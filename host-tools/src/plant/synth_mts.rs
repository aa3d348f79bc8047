//! `mre synth --campaign mts`: a shaker/MTS-style data set (sinusoidal
//! strokes about the middle, several amplitude–frequency pairs, mixed 1 ms /
//! 5 ms sampling) from a base law outside the paper's class
//! ([`super::base_laws`]: Dahl or Bouc–Wen hysteresis), with one concealed
//! effect or none. As for drops, the answer goes to a key beside the folder.
use super::base_laws::{Hysteresis, HystereticLaw};
use super::synth::stream;
use crate::dataset::{Dataset, Recording, Role, Samples, TagValue};
use crate::vocabulary::{join_names, Effect};
use anyhow::{bail, Context, Result};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::PathBuf;

/// Effects an MTS campaign can conceal (the order is part of the seeded pick).
pub const MTS_EFFECTS: [Effect; 5] = [
    Effect::None,
    Effect::ViscousDamping,
    Effect::SensorDelay,
    Effect::EndStop,
    Effect::Inertia,
];

/// (amplitude mm, frequency Hz, sample period s): the bundled real set's
/// pattern, peak speeds 16–94 mm/s.
pub const MTS_TESTS: [(f64, f64, f64); 5] = [
    (2.0, 5.0, 5e-3),
    (5.0, 3.0, 1e-3),
    (10.0, 1.0, 1e-3),
    (25.0, 0.25, 5e-3),
    (25.0, 0.1, 5e-3),
];
/// Currents: 0 and 1 A are fitted, 0.5 A is written as `validate`.
pub const MTS_CURRENTS_A: [(f64, Role); 3] = [(0.0, Role::Fit), (0.5, Role::Validate), (1.0, Role::Fit)];
/// Whole cycles recorded per test.
pub const MTS_CYCLES: f64 = 2.5;

/// The concealed effect of an MTS campaign.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "effect", content = "parameters", rename_all = "snake_case")]
pub enum MtsEffect {
    None,
    /// True viscosity `c(I)·v` on top of the rate-independent law.
    ViscousDamping {
        c0_n_s_per_m: f64,
    },
    SensorDelay {
        delay_s: f64,
    },
    /// Two-sided stroke: the stop may sit at either end.
    EndStop {
        x_e_mm: f64,
        k_e_n_per_mm2: f64,
        lower_end: bool,
    },
    /// The load cell also carries `m·a`.
    Inertia {
        m_s_kg: f64,
    },
}

impl MtsEffect {
    pub fn kind(&self) -> Effect {
        match self {
            MtsEffect::None => Effect::None,
            MtsEffect::ViscousDamping { .. } => Effect::ViscousDamping,
            MtsEffect::SensorDelay { .. } => Effect::SensorDelay,
            MtsEffect::EndStop { .. } => Effect::EndStop,
            MtsEffect::Inertia { .. } => Effect::Inertia,
        }
    }

    pub fn name(&self) -> &'static str {
        self.kind().name()
    }
}

/// A synthesised MTS campaign with its answer.
#[derive(Clone, Debug)]
pub struct MtsOutput {
    pub dataset: Dataset,
    pub law: HystereticLaw,
    pub effect: MtsEffect,
    pub key: serde_json::Value,
}

/// The base law for a seed: Dahl or Bouc–Wen, parameters around an MR
/// damper like the bundled one (≈ 150 N yield at 0 A, ≈ 6× at 1 A).
pub fn draw_law(seed: u64) -> HystereticLaw {
    let mut rng = stream(seed, 12);
    HystereticLaw {
        hysteresis: if rng.random_bool(0.5) {
            Hysteresis::Dahl
        } else {
            Hysteresis::BoucWen
        },
        k1_n_per_mm: rng.random_range(1.0..3.0),
        k3_n_per_mm3: rng.random_range(0.0..0.002),
        f_y_n: rng.random_range(100.0..200.0),
        x_y_mm: rng.random_range(0.3..1.0),
        gain_per_a: rng.random_range(4.0..7.0),
        viscous_n_s_per_m: 0.0,
    }
}

/// Draws `effect` sized to several percent of the force.
pub fn draw_mts_effect(effect: Effect, rng: &mut ChaCha8Rng, law: &HystereticLaw) -> Result<MtsEffect> {
    Ok(match effect {
        Effect::None => MtsEffect::None,
        // 0.15–0.3 of the 0 A yield at the fastest test (94 mm/s).
        Effect::ViscousDamping => MtsEffect::ViscousDamping {
            c0_n_s_per_m: law.f_y_n * rng.random_range(0.15..0.3) / 0.094,
        },
        Effect::SensorDelay => MtsEffect::SensorDelay {
            delay_s: rng.random_range(3e-3..8e-3),
        },
        // Beyond the 10 mm tests, reached by the 25 mm ones at different
        // depths only through the other currents: adds 0.5–1× the 0 A yield
        // at full stroke.
        Effect::EndStop => {
            let depth_mm = rng.random_range(12.0..18.0);
            let over = 25.0 - depth_mm;
            let lower_end = rng.random_bool(0.5);
            MtsEffect::EndStop {
                x_e_mm: if lower_end { -depth_mm } else { depth_mm },
                k_e_n_per_mm2: law.f_y_n * rng.random_range(0.5..1.0) / (over * over),
                lower_end,
            }
        }
        // a reaches (2π·5)²·2 mm ≈ 2 m/s² in the 5 Hz test.
        Effect::Inertia => MtsEffect::Inertia {
            m_s_kg: law.f_y_n * rng.random_range(0.1..0.2) / 2.0,
        },
        other => bail!(
            "unknown MTS effect `{other}`; expected one of {}",
            join_names(&MTS_EFFECTS)
        ),
    })
}

/// Synthesises an MTS campaign for (effect, seed); `effect` may be `random`.
pub fn synthesize_mts(effect: &str, seed: u64) -> Result<MtsOutput> {
    let kind = if effect == "random" {
        MTS_EFFECTS[stream(seed, 11).random_range(0..MTS_EFFECTS.len())]
    } else {
        Effect::from_name(effect).with_context(|| {
            format!(
                "unknown MTS effect `{effect}`; expected one of {}",
                join_names(&MTS_EFFECTS)
            )
        })?
    };
    let law = draw_law(seed);
    let effect = draw_mts_effect(kind, &mut stream(seed, 13), &law)?;
    synthesize_mts_with(&law, &effect, seed)
}

/// The campaign for a given law and effect (noise from `seed`).
pub fn synthesize_mts_with(law: &HystereticLaw, effect: &MtsEffect, seed: u64) -> Result<MtsOutput> {
    let mut law = *law;
    if let MtsEffect::ViscousDamping { c0_n_s_per_m } = *effect {
        law.viscous_n_s_per_m = c0_n_s_per_m;
    }
    let mut rng = stream(seed, 14);
    let force_noise = Normal::new(0.0, 2.0)?;
    let x_noise = Normal::new(0.0, 0.003)?;
    let v_noise = Normal::new(0.0, 0.3e-3)?;
    let mut recordings = Vec::new();
    for &(current_a, role) in &MTS_CURRENTS_A {
        for &(amp_mm, f_hz, dt_s) in &MTS_TESTS {
            let w = 2.0 * PI * f_hz;
            let n = (MTS_CYCLES / f_hz / dt_s).round() as usize;
            let time_s: Vec<f64> = (0..n).map(|k| k as f64 * dt_s).collect();
            let x: Vec<f64> = time_s.iter().map(|t| amp_mm * (w * t).sin()).collect();
            let v: Vec<f64> = time_s.iter().map(|t| 1e-3 * amp_mm * w * (w * t).cos()).collect();
            let a: Vec<f64> = time_s.iter().map(|t| -1e-3 * amp_mm * w * w * (w * t).sin()).collect();
            // The true force, with the effect, evaluated at the true time.
            // The rig cycles before it records: the law runs one whole cycle
            // first, so z starts on the steady loop, not the virgin curve.
            let pre = (1.0 / f_hz / dt_s).round() as usize;
            let true_force = |x: &[f64], v: &[f64], a: &[f64]| -> Vec<f64> {
                let shifted = |k: usize| k as f64 * dt_s - pre as f64 * dt_s;
                let x0: Vec<f64> = (0..pre).map(|k| amp_mm * (w * shifted(k)).sin()).collect();
                let warm: Vec<f64> = x0.iter().chain(x).copied().collect();
                let vw: Vec<f64> = vec![0.0; pre].into_iter().chain(v.iter().copied()).collect();
                let mut f = law.forces_n(&warm, &vw, current_a).split_off(pre);
                for (k, fk) in f.iter_mut().enumerate() {
                    *fk += match *effect {
                        MtsEffect::EndStop {
                            x_e_mm,
                            k_e_n_per_mm2,
                            lower_end,
                        } => k_e_n_per_mm2 * crate::diagnose::design::end_stop_shape(x[k], x_e_mm, lower_end),
                        MtsEffect::Inertia { m_s_kg } => m_s_kg * a[k],
                        _ => 0.0,
                    };
                }
                f
            };
            let force = match *effect {
                // The load cell channel lags: F_meas(t) = F(t − τ), with the
                // law run on the earlier motion.
                MtsEffect::SensorDelay { delay_s } => {
                    let ts: Vec<f64> = time_s.iter().map(|t| t - delay_s).collect();
                    let xd: Vec<f64> = ts.iter().map(|t| amp_mm * (w * t).sin()).collect();
                    let vd: Vec<f64> = ts.iter().map(|t| 1e-3 * amp_mm * w * (w * t).cos()).collect();
                    let ad: Vec<f64> = ts.iter().map(|t| -1e-3 * amp_mm * w * w * (w * t).sin()).collect();
                    true_force(&xd, &vd, &ad)
                }
                _ => true_force(&x, &v, &a),
            };
            let mut tags = BTreeMap::new();
            tags.insert("amplitude_mm".to_owned(), TagValue::Number(amp_mm));
            tags.insert("frequency_hz".to_owned(), TagValue::Number(f_hz));
            recordings.push(Recording {
                file: format!("{amp_mm}mm{f_hz}Hz{current_a}A.csv"),
                current_a,
                role,
                mass_kg: None,
                impact_velocity_m_s: None,
                sequence: None,
                temperature_c: None,
                tags,
                samples: Samples {
                    x_mm: x.iter().map(|x| x + x_noise.sample(&mut rng)).collect(),
                    v_m_s: v.iter().map(|v| v + v_noise.sample(&mut rng)).collect(),
                    force_n: force.iter().map(|f| f + force_noise.sample(&mut rng)).collect(),
                    time_s,
                    accel_m_s2: None,
                    current_a: None,
                    temperature_c: None,
                },
                velocity_estimated: false,
                motion_from: None,
                notes: Vec::new(),
            });
        }
    }
    let key = serde_json::json!({
        "effect": effect.name(),
        "parameters": serde_json::to_value(effect)?.get("parameters").cloned().unwrap_or(serde_json::json!({})),
        "seed": seed,
        "law": law,
        "generator": "mre synth --campaign mts",
    });
    Ok(MtsOutput {
        dataset: Dataset {
            name: format!("synthetic MTS campaign, {:?} base law, seed {seed}", law.hysteresis),
            root: PathBuf::new(),
            recordings,
        },
        law,
        effect: effect.clone(),
        key,
    })
}

/// `mre synth --campaign mts`: writes the campaign to `out` and its key to
/// `key_path` (default beside the folder, never inside it).
pub fn write_synth_mts(
    effect: &str,
    seed: u64,
    out: &std::path::Path,
    key_path: Option<&std::path::Path>,
    force: bool,
) -> Result<MtsOutput> {
    super::synth::write_blind(out, key_path, force, || {
        let output = synthesize_mts(effect, seed)?;
        Ok((output.dataset.clone(), output.key.clone(), output))
    })
}
