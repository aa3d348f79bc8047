//! Calibration campaigns for `mre diagnose`: shaker/MTS-style data sets whose
//! base law and concealed effects are NOT the candidates' own formulas, with
//! parameters drawn from continuous ranges (never the search grids), on a test
//! pattern (amplitudes, frequencies, currents' roles) unlike the bundled
//! sets the decision rules were tuned on. The estimator never sees this code.
//!
//! | effect | generated as | the candidate fits |
//! |---|---|---|
//! | base law | Dahl / Bouc–Wen, wider parameter ranges | quartics + memory |
//! | `viscous_damping` | shear-thinning `G(I)·c·sgn(v)·|v/v_r|^p`, p 0.4–0.8 | `c(I)·v`, `c·v0·tanh(v/v0)` |
//! | `sensor_delay` | first-order low-pass on the force channel, τ 2–8 ms | a pure shift `F(t − τ)` |
//! | `end_stop` | exponential stiffening `A·(e^{(|x|−x_e)/s} − 1)` | `k_e·(x − x_e)²` |
//! | `inertia` | `m·a` of a mass on a compliant mount (a lagged 0.5–2 ms) | `m·a` |
use super::base_laws::{Hysteresis, HystereticLaw};
use crate::dataset::{Dataset, Recording, Role, Samples, TagValue};
use crate::vocabulary::Effect;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::PathBuf;

/// (amplitude mm, frequency Hz, sample period s): peak speeds 25–75 mm/s,
/// none of the bundled MTS set's pairs.
pub const TESTS: [(f64, f64, f64); 5] = [
    (3.0, 4.0, 2e-3),
    (6.0, 2.0, 2e-3),
    (12.0, 0.8, 2e-3),
    (20.0, 0.4, 4e-3),
    (20.0, 0.2, 4e-3),
];
/// Currents: 0 and 1.2 A fitted, 0.6 A validate.
pub const CURRENTS_A: [(f64, Role); 3] = [(0.0, Role::Fit), (0.6, Role::Validate), (1.2, Role::Fit)];
/// The validate current (for `--validate-current`).
pub const VALIDATE_CURRENT_A: f64 = 0.6;
const CYCLES: f64 = 2.5;

/// A concealed effect in a form the candidates do not share.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "effect", content = "parameters", rename_all = "snake_case")]
pub enum OffModelEffect {
    None,
    ShearThinning {
        c_n: f64,
        v_ref_m_s: f64,
        power: f64,
    },
    LowPassForce {
        tau_s: f64,
    },
    ExponentialStop {
        x_e_mm: f64,
        scale_mm: f64,
        amplitude_n: f64,
        lower_end: bool,
    },
    CompliantMass {
        m_kg: f64,
        lag_s: f64,
    },
}

impl OffModelEffect {
    /// The vocabulary word a correct diagnosis names.
    pub fn kind(&self) -> Effect {
        match self {
            OffModelEffect::None => Effect::None,
            OffModelEffect::ShearThinning { .. } => Effect::ViscousDamping,
            OffModelEffect::LowPassForce { .. } => Effect::SensorDelay,
            OffModelEffect::ExponentialStop { .. } => Effect::EndStop,
            OffModelEffect::CompliantMass { .. } => Effect::Inertia,
        }
    }
}

/// One calibration case: the campaign and its answer.
#[derive(Clone, Debug)]
pub struct CalibrationCase {
    pub dataset: Dataset,
    pub law: HystereticLaw,
    pub effect: OffModelEffect,
    /// RMS of the effect's change to the force over the fit recordings,
    /// over the RMS force: how large it is.
    pub strength: f64,
}

/// Case `seed`: 2 in 5 without an effect, the rest one effect each in turn.
pub fn case(seed: u64) -> anyhow::Result<CalibrationCase> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xca1b_0000);
    let law = HystereticLaw {
        hysteresis: if rng.random_bool(0.5) {
            Hysteresis::Dahl
        } else {
            Hysteresis::BoucWen
        },
        k1_n_per_mm: rng.random_range(0.5..4.0),
        k3_n_per_mm3: rng.random_range(0.0..0.004),
        f_y_n: rng.random_range(60.0..260.0),
        x_y_mm: rng.random_range(0.2..1.5),
        gain_per_a: rng.random_range(2.5..8.0),
        viscous_n_s_per_m: 0.0,
    };
    let fastest_m_s = TESTS
        .iter()
        .map(|(a, f, _)| 1e-3 * a * 2.0 * PI * f)
        .fold(0.0, f64::max);
    let effect = match seed % 10 {
        0 | 5 | 2 | 7 => OffModelEffect::None,
        1 | 6 => OffModelEffect::ShearThinning {
            // 10–30 % of the 0 A yield at the fastest test.
            c_n: law.f_y_n * rng.random_range(0.1..0.3),
            v_ref_m_s: fastest_m_s,
            power: rng.random_range(0.4..0.8),
        },
        3 => OffModelEffect::LowPassForce {
            tau_s: rng.random_range(2e-3..8e-3),
        },
        4 | 9 => {
            let x_e_mm = 20.0 * rng.random_range(0.55..0.85);
            OffModelEffect::ExponentialStop {
                x_e_mm,
                scale_mm: rng.random_range(1.5..4.0),
                // 0.4–1 × the 0 A yield at full stroke.
                amplitude_n: law.f_y_n * rng.random_range(0.4..1.0),
                lower_end: rng.random_bool(0.5),
            }
        }
        _ => OffModelEffect::CompliantMass {
            // a peaks at (2π·4)²·3 mm ≈ 1.9 m/s²: 10–25 % of the yield there.
            m_kg: law.f_y_n * rng.random_range(0.1..0.25) / 1.9,
            lag_s: rng.random_range(0.5e-3..2e-3),
        },
    };
    let force_sigma_n = rng.random_range(1.0..4.0);
    build(&law, &effect, force_sigma_n, &mut rng, seed)
}

/// First-order low-pass of `y` (time constant `tau_s`), exact for a
/// piecewise-constant input, started at the first value.
fn low_pass(y: &[f64], dt_s: f64, tau_s: f64) -> Vec<f64> {
    let k = (-dt_s / tau_s).exp();
    let mut s = y.first().copied().unwrap_or(0.0);
    y.iter()
        .map(|&u| {
            s = k * s + (1.0 - k) * u;
            s
        })
        .collect()
}

fn build(
    law: &HystereticLaw,
    effect: &OffModelEffect,
    force_sigma_n: f64,
    rng: &mut ChaCha8Rng,
    seed: u64,
) -> anyhow::Result<CalibrationCase> {
    let force_noise = Normal::new(0.0, force_sigma_n)?;
    let x_noise = Normal::new(0.0, 0.003)?;
    let v_noise = Normal::new(0.0, 0.3e-3)?;
    let (mut added_ss, mut force_ss) = (0.0, 0.0);
    let mut recordings = Vec::new();
    for &(current_a, role) in &CURRENTS_A {
        for &(amp_mm, f_hz, dt_s) in &TESTS {
            let w = 2.0 * PI * f_hz;
            // One whole cycle before recording, so the state is on its steady loop.
            let pre = (1.0 / f_hz / dt_s).round() as usize;
            let n = (CYCLES / f_hz / dt_s).round() as usize;
            let t_all: Vec<f64> = (0..pre + n).map(|k| (k as f64 - pre as f64) * dt_s).collect();
            let x: Vec<f64> = t_all.iter().map(|t| amp_mm * (w * t).sin()).collect();
            let v: Vec<f64> = t_all.iter().map(|t| 1e-3 * amp_mm * w * (w * t).cos()).collect();
            let a: Vec<f64> = t_all.iter().map(|t| -1e-3 * amp_mm * w * w * (w * t).sin()).collect();
            let base = law.forces_n(&x, &v, current_a);
            let g = law.gain(current_a);
            let added: Vec<f64> = match *effect {
                OffModelEffect::ShearThinning { c_n, v_ref_m_s, power } => v
                    .iter()
                    .map(|v| g * c_n * v.signum() * (v.abs() / v_ref_m_s).powf(power))
                    .collect(),
                OffModelEffect::ExponentialStop {
                    x_e_mm,
                    scale_mm,
                    amplitude_n,
                    lower_end,
                } => x
                    .iter()
                    .map(|&x| {
                        let depth = if lower_end { -x - x_e_mm } else { x - x_e_mm };
                        let f = if depth > 0.0 {
                            amplitude_n * ((depth / scale_mm).exp() - 1.0) / (((20.0 - x_e_mm) / scale_mm).exp() - 1.0)
                        } else {
                            0.0
                        };
                        if lower_end {
                            -f
                        } else {
                            f
                        }
                    })
                    .collect(),
                OffModelEffect::CompliantMass { m_kg, lag_s } => {
                    low_pass(&a, dt_s, lag_s).iter().map(|a| m_kg * a).collect()
                }
                _ => vec![0.0; x.len()],
            };
            let true_force: Vec<f64> = base.iter().zip(&added).map(|(b, e)| b + e).collect();
            let measured = match *effect {
                OffModelEffect::LowPassForce { tau_s } => low_pass(&true_force, dt_s, tau_s),
                _ => true_force.clone(),
            };
            if role == Role::Fit {
                for k in pre..pre + n {
                    let d = measured[k] - base[k];
                    added_ss += d * d;
                    force_ss += base[k] * base[k];
                }
            }
            let mut tags = BTreeMap::new();
            tags.insert("amplitude_mm".to_owned(), TagValue::Number(amp_mm));
            tags.insert("frequency_hz".to_owned(), TagValue::Number(f_hz));
            let keep = pre..pre + n;
            recordings.push(Recording {
                file: format!("{amp_mm}mm{f_hz}Hz{current_a}A.csv"),
                current_a,
                role,
                mass_kg: None,
                impact_velocity_m_s: None,
                sequence: None,
                temperature_c: None,
                tags,
                motion_from: None,
                notes: Vec::new(),
                samples: Samples {
                    time_s: t_all[keep.clone()].iter().map(|t| t.max(0.0)).collect(),
                    x_mm: x[keep.clone()].iter().map(|x| x + x_noise.sample(rng)).collect(),
                    v_m_s: v[keep.clone()].iter().map(|v| v + v_noise.sample(rng)).collect(),
                    force_n: measured[keep].iter().map(|f| f + force_noise.sample(rng)).collect(),
                    accel_m_s2: None,
                    current_a: None,
                    temperature_c: None,
                },
                velocity_estimated: false,
            });
        }
    }
    Ok(CalibrationCase {
        dataset: Dataset {
            name: format!("calibration campaign, {:?} base law, seed {seed}", law.hysteresis),
            root: PathBuf::new(),
            recordings,
        },
        law: *law,
        effect: effect.clone(),
        strength: (added_ss / force_ss.max(1e-300)).sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_low_pass_lags_a_slow_sine_by_its_time_constant() {
        // Group delay of a first-order low-pass at ωτ ≪ 1 is τ.
        let (dt, tau, f) = (1e-4, 2e-3, 2.0);
        let w = 2.0 * PI * f;
        let y: Vec<f64> = (0..20_000).map(|k| (w * k as f64 * dt).sin()).collect();
        let out = low_pass(&y, dt, tau);
        // Zero crossing upward in the last cycles: the input's at k·dt = 1.0 s.
        let k0 = (1.0 / dt) as usize;
        let cross = (k0..k0 + 200).find(|&k| out[k - 1] < 0.0 && out[k] >= 0.0).unwrap();
        let lag_s = (cross as f64 - k0 as f64) * dt;
        assert!((lag_s - tau).abs() < 2.0 * dt, "lag {lag_s} s");
    }

    #[test]
    fn every_effect_appears_and_none_twice_in_five() {
        let kinds: Vec<Effect> = (0..10).map(|s| case(s).unwrap().effect.kind()).collect();
        assert_eq!(kinds.iter().filter(|k| **k == Effect::None).count(), 4);
        for e in [
            Effect::ViscousDamping,
            Effect::SensorDelay,
            Effect::EndStop,
            Effect::Inertia,
        ] {
            assert!(kinds.contains(&e), "{e:?}");
        }
    }
}
