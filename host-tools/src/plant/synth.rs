//! `mre synth`: a blind drop-impact data set from a randomised plant with one
//! concealed effect (or none). The answer goes to a key file beside the
//! folder, never inside it.
//!
//! Everything random is drawn from the seed through separate ChaCha8 streams
//! (effect choice, base plant, effect parameters, test campaign), and every
//! recording's noise has its own seed, so the output is byte-identical for a
//! seed whatever the thread count.
use super::effects::{draw_effect, ConcealedEffect, Effect, EffectScale, DROP_EFFECTS, INSTRUMENTED_EFFECTS};
use super::law::LawParams;
use super::measure::MeasurementModel;
use super::stepper::{simulate, CurrentSource, ImpactConfig, Plant, Trajectory};
use crate::atomic_write::write_atomic;
use crate::dataset::write::{write_dataset, Precision, WriteOptions};
use crate::dataset::{Dataset, Recording, Role, Samples, TagValue};
use anyhow::{ensure, Context, Result};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A controlled impact: the coil command steps from `from_a` to `to_a`
/// during compression, so a lagging coil shows (the only tests that reveal
/// `coil_lag`; every campaign has them, so the plan never gives the effect away).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlledImpact {
    pub from_a: f64,
    pub to_a: f64,
    /// Nominal impact velocity (drop height).
    pub velocity_m_s: f64,
}

/// The test campaign.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthPlan {
    pub fit_currents_a: Vec<f64>,
    pub validate_currents_a: Vec<f64>,
    /// Nominal impact velocities (drop heights).
    pub velocities_m_s: Vec<f64>,
    /// Tests per (current, velocity).
    pub repeats: u32,
    pub mass_kg: f64,
    /// Step-command tests (role `validate`), one each.
    pub controlled: Vec<ControlledImpact>,
    /// Time after contact at which the controlled impacts' command steps (s).
    pub step_at_s: f64,
    /// A drop height per current: when set, each constant-current test's
    /// velocities are scaled so that the fastest one reaches this stroke
    /// (mm) on the plant, so the stiff currents are recorded over the whole
    /// stroke as the soft ones are (see [`SynthPlan::full_stroke`]). `None`:
    /// the same velocities at every current (the paper's drop test).
    pub full_stroke_mm: Option<f64>,
    /// A second drop mass (kg): when set, every even-numbered repeat of a
    /// constant-current test drops this mass instead of `mass_kg` (an
    /// instrumented drop tower's carriage with or without its added-mass
    /// plates), from the height that gives it the same impact energy:
    /// velocities × √(mass_kg / second_mass_kg). Controlled impacts keep
    /// `mass_kg`.
    pub second_mass_kg: Option<f64>,
    /// A striker accelerometer: when set, every recording has an
    /// `acceleration_m_s2` column.
    pub accelerometer: Option<Accelerometer>,
}

/// The striker accelerometer of an instrumented drop tower. It records the
/// drop mass's acceleration ẍ (positive compressing, the derivative of the
/// velocity channel: +g in free fall, g − F/M in contact).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Accelerometer {
    /// Noise, 1 σ (m/s²).
    pub noise_m_s2: f64,
    /// One ADC count (m/s²).
    pub lsb_m_s2: f64,
}

impl Default for Accelerometer {
    /// A ±500 g piezo-electric accelerometer on a 16-bit channel, 2 m/s²
    /// of noise (the 2 A drops of the light carriage reach ~2500 m/s²).
    fn default() -> Self {
        Self {
            noise_m_s2: 2.0,
            lsb_m_s2: 2.0 * 500.0 * 9.81 / 65_536.0,
        }
    }
}

impl Default for SynthPlan {
    /// 9 currents × 3 velocities × 2 repeats = 54 constant-current recordings,
    /// plus 6 controlled impacts = 60.
    fn default() -> Self {
        let step = |from_a, to_a, velocity_m_s| ControlledImpact {
            from_a,
            to_a,
            velocity_m_s,
        };
        Self {
            fit_currents_a: vec![0.0, 0.5, 1.0, 1.5, 2.0],
            validate_currents_a: vec![0.3, 0.7, 1.3, 1.7],
            velocities_m_s: vec![1.4, 1.8, 2.24],
            repeats: 2,
            mass_kg: 5.5,
            // Up and down steps, large and small, between tabulated currents
            // (so the paper's interpolation is exact at each command).
            controlled: vec![
                step(0.0, 2.0, 2.24),
                step(2.0, 0.0, 2.24),
                step(0.5, 1.5, 1.8),
                step(1.5, 0.5, 1.8),
                step(0.0, 1.0, 1.4),
                step(2.0, 1.0, 1.4),
            ],
            // 0.8 ms after contact the mass has slowed by < 15 % (x 1.1–1.8
            // mm), and at least 1.8 ms of compression follow at the new command:
            // the shortest compression of any plant synth draws is 2.65 ms
            // (2 A, stiffest law).
            step_at_s: 0.8e-3,
            full_stroke_mm: None,
            second_mass_kg: None,
            accelerometer: None,
        }
    }
}

impl SynthPlan {
    /// The default campaign with a drop height per current chosen so that
    /// the fastest test of every current reaches `stroke_mm`: a model fitted
    /// on it covers the whole usable stroke at every current instead of
    /// being clamped beyond where the stiff currents stop the paper's drop.
    pub fn full_stroke(stroke_mm: f64) -> Self {
        Self {
            full_stroke_mm: Some(stroke_mm),
            ..Self::default()
        }
    }

    /// The default campaign on an instrumented drop tower: a striker
    /// accelerometer, and every second repeat dropped with the carriage's
    /// added mass removed (2.75 kg instead of 5.5 kg). The only drop
    /// campaign in which `inertia` is identifiable: at one mass `a = g −
    /// F/M`, so `m_s·a` is a scale on F that the quartics absorb; with two
    /// masses the same force comes with two accelerations.
    pub fn instrumented() -> Self {
        Self {
            second_mass_kg: Some(2.75),
            accelerometer: Some(Accelerometer::default()),
            ..Self::default()
        }
    }

    /// Can `inertia` be identified from this campaign? It needs the
    /// acceleration recorded and not proportional to the force: two drop
    /// masses (so at least two repeats) and an accelerometer.
    pub fn reveals_inertia(&self) -> bool {
        self.accelerometer.is_some() && self.repeats >= 2 && self.second_mass_kg.is_some_and(|m| m != self.mass_kg)
    }

    /// The effects `random` picks from on this campaign.
    pub fn effects(&self) -> &'static [Effect] {
        if self.reveals_inertia() {
            &INSTRUMENTED_EFFECTS
        } else {
            &DROP_EFFECTS
        }
    }

    /// The drop mass of a constant-current test's `repeat` (1-based).
    fn mass_for_repeat_kg(&self, repeat: u32) -> f64 {
        match self.second_mass_kg {
            Some(m) if repeat.is_multiple_of(2) => m,
            _ => self.mass_kg,
        }
    }

    /// Impact velocity factor of a drop of `mass_kg`: the same impact energy
    /// as `self.mass_kg` at the planned velocity, so both masses reach about
    /// the same stroke (an end stop is met by both; the force ranges overlap).
    fn energy_matched_factor(&self, mass_kg: f64) -> f64 {
        (self.mass_kg / mass_kg).sqrt()
    }

    /// Every drop mass of the constant-current tests.
    fn drop_masses_kg(&self) -> Vec<f64> {
        std::iter::once(self.mass_kg).chain(self.second_mass_kg).collect()
    }
}

/// The impact velocity (m/s, to 0.01) at which a drop of `mass_kg` at
/// constant `current_a` reaches `stroke_mm` on `plant`: bisection on the
/// velocity (the peak stroke grows with it).
pub fn velocity_reaching(plant: &Plant, mass_kg: f64, current_a: f64, stroke_mm: f64) -> Result<f64> {
    ensure!(
        stroke_mm.is_finite() && stroke_mm > 0.0,
        "the full stroke must be positive, got {stroke_mm} mm"
    );
    let reach = |v: f64| -> Result<f64> {
        let cfg = ImpactConfig {
            mass_kg,
            impact_velocity_m_s: v,
            initial_current_a: current_a,
            ..ImpactConfig::default()
        };
        Ok(simulate(plant, &cfg, CurrentSource::Constant(current_a))?
            .summary
            .max_stroke_mm)
    };
    let (mut lo, mut hi) = (0.1f64, 30.0f64);
    ensure!(
        reach(hi)? >= stroke_mm,
        "{current_a} A: even {hi} m/s does not reach {stroke_mm} mm"
    );
    // 0.1–30 m/s to 0.005 m/s: 13 halvings.
    while hi - lo > 0.005 {
        let mid = 0.5 * (lo + hi);
        if reach(mid)? >= stroke_mm {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok((hi * 100.0).ceil() / 100.0)
}

/// Decimal places written per column: below each channel's resolution.
pub const SYNTH_PRECISION: Precision = Precision {
    time_s: Some(5),
    x_mm: Some(4),
    v_m_s: Some(4),
    force_n: Some(1),
    accel_m_s2: Some(2),
    current_a: Some(3),
    temperature_c: Some(2),
};

/// A synthesised data set with its (secret) answer.
#[derive(Clone, Debug)]
pub struct SynthOutput {
    pub dataset: Dataset,
    pub plant: Plant,
    pub seed: u64,
    /// The key file's content: effect, parameters, seed, base law, instrument.
    pub key: serde_json::Value,
}

/// A seed's independent random stream `id`.
pub(crate) fn stream(seed: u64, id: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(id);
    rng
}

/// `random` → one of [`DROP_EFFECTS`] (`none` included) picked by the seed;
/// any other name (`inertia` included) is checked and returned.
pub fn resolve_effect_name(effect: &str, seed: u64) -> Result<Effect> {
    resolve_effect_name_from(effect, seed, &DROP_EFFECTS)
}

/// [`resolve_effect_name`] with `random` picking from the effects `plan` can reveal.
pub fn resolve_effect_name_for(effect: &str, seed: u64, plan: &SynthPlan) -> Result<Effect> {
    resolve_effect_name_from(effect, seed, plan.effects())
}

fn resolve_effect_name_from(effect: &str, seed: u64, random_from: &[Effect]) -> Result<Effect> {
    if effect == "random" {
        let i = stream(seed, 1).random_range(0..random_from.len());
        return Ok(random_from[i]);
    }
    Effect::from_name(effect)
        .filter(|e| INSTRUMENTED_EFFECTS.contains(e))
        .with_context(|| {
            format!(
                "unknown effect `{effect}`; expected one of {} or `random`",
                crate::vocabulary::join_names(&INSTRUMENTED_EFFECTS)
            )
        })
}

/// The base plant for a seed: law parameters and noise varied around the
/// calibrated values, so a diagnosis cannot pass by memorising one plant.
pub fn draw_base_plant(seed: u64) -> Plant {
    let mut rng = stream(seed, 2);
    let nominal = LawParams::nominal();
    let mut gain_knots = nominal.gain_knots;
    for k in 1..gain_knots.len() {
        gain_knots[k] *= rng.random_range(0.95..1.05);
        gain_knots[k] = gain_knots[k].max(gain_knots[k - 1] * 1.005);
    }
    let law = LawParams {
        k1_n_per_mm: nominal.k1_n_per_mm * rng.random_range(0.92..1.08),
        k3_n_per_mm3: nominal.k3_n_per_mm3 * rng.random_range(0.85..1.15),
        loss_eta: rng.random_range(0.42..0.58),
        turn_velocity_m_s: rng.random_range(0.002..0.005),
        gain_knots,
    };
    let measurement = MeasurementModel {
        force_noise_n: rng.random_range(3.0..15.0),
        x_noise_mm: rng.random_range(0.003..0.015),
        v_noise_m_s: rng.random_range(0.001..0.004),
        ..MeasurementModel::default()
    };
    Plant {
        law,
        effect: ConcealedEffect::None,
        measurement,
    }
}

/// Sizes effects against the longest-stroke test of the plan (lowest
/// current, fastest drop) on the plant without any effect.
pub fn effect_scale(base: &Plant, plan: &SynthPlan) -> Result<EffectScale> {
    let lowest_a = plan
        .fit_currents_a
        .iter()
        .chain(&plan.validate_currents_a)
        .copied()
        .fold(f64::INFINITY, f64::min);
    let fastest = plan.velocities_m_s.iter().copied().fold(0.0, f64::max);
    let mut longest = EffectScale {
        longest_stroke_mm: 0.0,
        peak_force_at_longest_n: 0.0,
    };
    for mass_kg in plan.drop_masses_kg() {
        let cfg = ImpactConfig {
            mass_kg,
            impact_velocity_m_s: fastest * plan.energy_matched_factor(mass_kg),
            ..ImpactConfig::default()
        };
        let s = simulate(base, &cfg, CurrentSource::Constant(lowest_a))?.summary;
        if s.max_stroke_mm > longest.longest_stroke_mm {
            longest = EffectScale {
                longest_stroke_mm: s.max_stroke_mm,
                peak_force_at_longest_n: s.peak_force_n,
            };
        }
    }
    Ok(longest)
}

/// The plant for (effect, seed): the seed's base plant plus the effect with
/// parameters drawn from the seed.
pub fn draw_plant(effect: &str, seed: u64, plan: &SynthPlan) -> Result<Plant> {
    let kind = resolve_effect_name_for(effect, seed, plan)?;
    let base = draw_base_plant(seed);
    let scale = effect_scale(&base, plan)?;
    let effect = draw_effect(kind, &mut stream(seed, 3), scale)?;
    Ok(base.with_effect(effect))
}

/// One planned test.
struct Test {
    current_a: f64,
    /// Controlled impacts: the command after the step.
    step_to_a: Option<f64>,
    role: Role,
    nominal_velocity_m_s: f64,
    repeat: u32,
    mass_kg: f64,
    /// Name the mass in the file (campaigns with two drop masses).
    mass_in_name: bool,
    sequence: u32,
    actual_velocity_m_s: f64,
    recorded_velocity_m_s: f64,
    temperature_c: f64,
    noise_seed: u64,
}

impl Test {
    fn new(current_a: f64, step_to_a: Option<f64>, role: Role, nominal_velocity_m_s: f64, repeat: u32) -> Self {
        Self {
            current_a,
            step_to_a,
            role,
            nominal_velocity_m_s,
            repeat,
            mass_kg: 0.0,
            mass_in_name: false,
            sequence: 0,
            actual_velocity_m_s: nominal_velocity_m_s,
            recorded_velocity_m_s: nominal_velocity_m_s,
            temperature_c: 0.0,
            noise_seed: 0,
        }
    }

    fn file_name(&self) -> String {
        match self.step_to_a {
            Some(to_a) => format!(
                "step_i{:.1}-{:.1}_v{:.2}.csv",
                self.current_a, to_a, self.nominal_velocity_m_s
            ),
            None if self.mass_in_name => format!(
                "i{:.1}_v{:.2}_m{:.2}_r{}.csv",
                self.current_a, self.nominal_velocity_m_s, self.mass_kg, self.repeat
            ),
            None => format!(
                "i{:.1}_v{:.2}_r{}.csv",
                self.current_a, self.nominal_velocity_m_s, self.repeat
            ),
        }
    }
}

/// `plant`: the plant the drop heights of a full-stroke plan are chosen on.
fn plan_tests(plan: &SynthPlan, seed: u64, plant: &Plant) -> Result<Vec<Test>> {
    ensure!(plan.repeats >= 1, "at least one repeat");
    ensure!(
        plan.drop_masses_kg().iter().all(|m| m.is_finite() && *m > 0.0),
        "drop masses must be positive"
    );
    ensure!(!plan.velocities_m_s.is_empty(), "at least one impact velocity");
    ensure!(
        plan.step_at_s.is_finite() && plan.step_at_s > 0.0,
        "the controlled impacts' step time must be positive"
    );
    let mut tests = Vec::new();
    let roles = [
        (Role::Fit, &plan.fit_currents_a),
        (Role::Validate, &plan.validate_currents_a),
    ];
    let fastest = plan.velocities_m_s.iter().copied().fold(0.0, f64::max);
    for (role, currents) in roles {
        for &current_a in currents.iter() {
            // The same drop heights at every current, or scaled per current
            // so the fastest reaches the full stroke.
            let scale = match plan.full_stroke_mm {
                Some(stroke_mm) => velocity_reaching(plant, plan.mass_kg, current_a, stroke_mm)? / fastest,
                None => 1.0,
            };
            for &v in &plan.velocities_m_s {
                for repeat in 1..=plan.repeats {
                    let mass_kg = plan.mass_for_repeat_kg(repeat);
                    let v = (v * scale * plan.energy_matched_factor(mass_kg) * 100.0).round() / 100.0;
                    tests.push(Test {
                        mass_kg,
                        mass_in_name: plan.second_mass_kg.is_some(),
                        ..Test::new(current_a, None, role, v, repeat)
                    });
                }
            }
        }
    }
    for c in &plan.controlled {
        tests.push(Test {
            mass_kg: plan.mass_kg,
            ..Test::new(c.from_a, Some(c.to_a), Role::Validate, c.velocity_m_s, 1)
        });
    }
    let mut rng = stream(seed, 4);
    // Shuffled run order.
    let mut order: Vec<usize> = (0..tests.len()).collect();
    order.shuffle(&mut rng);
    for (position, &i) in order.iter().enumerate() {
        tests[i].sequence = position as u32 + 1;
    }
    // Drop-height scatter (0.5 %), light-gate error (3 mm/s), lab temperature
    // drifting slowly over the campaign (it has no effect on the law).
    let scatter = Normal::new(0.0, 0.005)?;
    let gate = Normal::new(0.0, 0.003)?;
    let drift = Normal::new(0.0, 0.05)?;
    let mut temperature_by_sequence = Vec::with_capacity(tests.len());
    let mut t: f64 = rng.random_range(21.0..25.0);
    for _ in 0..tests.len() {
        temperature_by_sequence.push(t);
        t += drift.sample(&mut rng);
    }
    for test in &mut tests {
        test.actual_velocity_m_s = test.nominal_velocity_m_s * (1.0 + scatter.sample(&mut rng));
        test.recorded_velocity_m_s = ((test.actual_velocity_m_s + gate.sample(&mut rng)) * 1000.0).round() / 1000.0;
        test.temperature_c = (temperature_by_sequence[test.sequence as usize - 1] * 10.0).round() / 10.0;
        test.noise_seed = rng.random();
    }
    Ok(tests)
}

/// Runs one test and returns what the instruments recorded.
///
/// With an accelerometer or a striker below the load cell (`inertia`) the
/// plant runs on an ideal instrument and is measured here: both need the
/// true acceleration at each sample, `a = g − F/M` with F the undelayed
/// contact force, which the stepper does not record. The load cell then
/// reads `F(t − τ) + m_s·a` (τ of `sensor_delay`, m_s of `inertia`; one
/// effect per plant), every channel with its noise and ADC step.
fn record(
    plant: &Plant,
    cfg: &ImpactConfig,
    source: CurrentSource<'_>,
    command_per_sample: bool,
    accelerometer: Option<&Accelerometer>,
) -> Result<Samples> {
    let m_s_kg = plant.effect.inertia_mass_kg();
    if accelerometer.is_none() && m_s_kg == 0.0 {
        return Ok(to_samples(&simulate(plant, cfg, source)?, command_per_sample, None));
    }
    let ideal = Plant {
        measurement: plant.measurement.ideal(),
        ..plant.clone()
    };
    let mut t = simulate(&ideal, cfg, source)?;
    let m = &plant.measurement;
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.noise_seed);
    let mut accel = Vec::with_capacity(t.samples.len());
    for s in &mut t.samples {
        let a_m_s2 = cfg.gravity_m_s2 - plant.force_n(s.x_mm, s.v_m_s, s.current_a, cfg.sequence) / cfg.mass_kg;
        s.x_mm = MeasurementModel::read(s.x_mm, m.x_noise_mm, m.x_lsb_mm, &mut rng);
        s.v_m_s = MeasurementModel::read(s.v_m_s, m.v_noise_m_s, m.v_lsb_m_s, &mut rng);
        s.force_n = MeasurementModel::read(s.force_n + m_s_kg * a_m_s2, m.force_noise_n, m.force_lsb_n, &mut rng);
        if let Some(acc) = accelerometer {
            accel.push(MeasurementModel::read(a_m_s2, acc.noise_m_s2, acc.lsb_m_s2, &mut rng));
        }
    }
    Ok(to_samples(&t, command_per_sample, accelerometer.map(|_| accel)))
}

/// `command_per_sample`: write the coil command as the `current_a` column.
fn to_samples(t: &Trajectory, command_per_sample: bool, accel_m_s2: Option<Vec<f64>>) -> Samples {
    Samples {
        time_s: t.samples.iter().map(|s| s.time_s).collect(),
        x_mm: t.samples.iter().map(|s| s.x_mm).collect(),
        v_m_s: t.samples.iter().map(|s| s.v_m_s).collect(),
        force_n: t.samples.iter().map(|s| s.force_n).collect(),
        accel_m_s2,
        // The command (what the rig logs), not the coil current, so a lag
        // stays concealed.
        current_a: command_per_sample.then(|| t.samples.iter().map(|s| s.command_a).collect()),
        temperature_c: None,
    }
}

/// The controlled impacts' command: `from_a` until `step_at_s` after
/// contact, then `to_a`. The switch is decided at integration-step
/// resolution (half a step of tolerance), so it falls exactly on `step_at_s`
/// whatever the rounding of the step times.
pub fn step_command(from_a: f64, to_a: f64, step_at_s: f64, step_s: f64) -> impl Fn(f64) -> f64 {
    move |t: f64| if t < step_at_s - 0.5 * step_s { from_a } else { to_a }
}

/// Synthesises a whole data set in memory with the default plan.
pub fn synthesize(effect: &str, seed: u64) -> Result<SynthOutput> {
    synthesize_with_plan(effect, seed, &SynthPlan::default())
}

/// Synthesises a whole data set in memory (no disk).
pub fn synthesize_with_plan(effect: &str, seed: u64, plan: &SynthPlan) -> Result<SynthOutput> {
    synthesize_plant(draw_plant(effect, seed, plan)?, seed, plan)
}

/// The campaign of `plan` recorded on a given plant (`mre bench-control` sets the coil τ).
pub fn synthesize_plant(plant: Plant, seed: u64, plan: &SynthPlan) -> Result<SynthOutput> {
    let tests = plan_tests(plan, seed, &plant)?;
    let recordings = tests
        .par_iter()
        .map(|test| {
            // The coil is energised at the initial command before contact,
            // so a constant-current test has no transient even with a lag.
            let cfg = ImpactConfig {
                mass_kg: test.mass_kg,
                impact_velocity_m_s: test.actual_velocity_m_s,
                coil_lag_s: plant.effect.coil_lag_s(),
                initial_current_a: test.current_a,
                sequence: test.sequence,
                noise_seed: test.noise_seed,
                ..ImpactConfig::default()
            };
            let source = match test.step_to_a {
                Some(to_a) => {
                    CurrentSource::Function(Box::new(step_command(test.current_a, to_a, plan.step_at_s, cfg.step_s)))
                }
                None => CurrentSource::Constant(test.current_a),
            };
            let samples = record(
                &plant,
                &cfg,
                source,
                test.step_to_a.is_some(),
                plan.accelerometer.as_ref(),
            )?;
            let mut tags = BTreeMap::new();
            if test.step_to_a.is_some() {
                let ms = (plan.step_at_s * 1.0e6).round() / 1.0e3;
                tags.insert("step_at_ms".to_owned(), TagValue::Number(ms));
            }
            Ok(Recording {
                file: test.file_name(),
                current_a: test.current_a,
                role: test.role,
                mass_kg: Some(test.mass_kg),
                impact_velocity_m_s: Some(test.recorded_velocity_m_s),
                sequence: Some(test.sequence),
                temperature_c: Some(test.temperature_c),
                tags,
                samples,
                velocity_estimated: false,
                motion_from: None,
                notes: Vec::new(),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let dataset = Dataset {
        name: match plan.second_mass_kg {
            Some(m) => format!("synthetic drop impact, {} and {m} kg, seed {seed}", plan.mass_kg),
            None => format!("synthetic drop impact, {} kg, seed {seed}", plan.mass_kg),
        },
        root: PathBuf::new(),
        recordings,
    };
    let key = key_json(&plant, seed, plan)?;
    Ok(SynthOutput {
        dataset,
        plant,
        seed,
        key,
    })
}

/// The answer key. Plain drop campaigns keep the key's original fields (the
/// bundled keys stay byte-identical); an instrumented campaign adds its
/// masses and accelerometer, and an effect the campaign cannot reveal is
/// marked `"identifiable": false` with the reason, so a benchmark neither
/// counts a miss as a failure nor a guess as a hit.
fn key_json(plant: &Plant, seed: u64, plan: &SynthPlan) -> Result<serde_json::Value> {
    let effect = serde_json::to_value(&plant.effect)?;
    let parameters = effect
        .get("parameters")
        .cloned()
        .unwrap_or_else(|| serde_json::json!({}));
    let mut key = serde_json::json!({
        "effect": plant.effect.name(),
        "parameters": parameters,
        "seed": seed,
        "law": plant.law,
        "measurement": plant.measurement,
        "generator": "mre synth",
    });
    if let Some(m) = plan.second_mass_kg {
        key["drop_masses_kg"] = serde_json::json!([plan.mass_kg, m]);
    }
    if let Some(acc) = &plan.accelerometer {
        key["accelerometer"] = serde_json::to_value(acc)?;
    }
    if plant.effect.kind() == Effect::Inertia && !plan.reveals_inertia() {
        key["identifiable"] = serde_json::json!(false);
        key["not_identifiable_because"] = serde_json::json!(
            "one drop mass and no accelerometer: in a free drop a = g − F/M, so the striker's m_s·a is the \
             scale 1 − m_s/M on the force, which the quartics absorb (record acceleration with two drop \
             masses: `mre synth --campaign instrumented`)"
        );
    }
    Ok(key)
}

/// Can the key's effect be identified from its campaign? (`false` only when
/// the key says so.)
pub fn key_identifiable(key: &serde_json::Value) -> bool {
    key.get("identifiable")
        .and_then(serde_json::Value::as_bool)
        .unwrap_or(true)
}

/// Where the key goes by default: `<folder>.key.json` beside the folder.
pub fn default_key_path(out: &Path) -> PathBuf {
    let mut name = out
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_else(|| "dataset".into());
    name.push(".key.json");
    out.with_file_name(name)
}

/// `mre synth`: writes the data set to `out` and its key to `key_path`
/// (default [`default_key_path`]). The key may not be inside `out`.
pub fn write_synth(effect: &str, seed: u64, out: &Path, key_path: Option<&Path>, force: bool) -> Result<SynthOutput> {
    write_synth_with_plan(effect, seed, &SynthPlan::default(), out, key_path, force)
}

/// [`write_synth`] with a given campaign plan (`mre synth --full-stroke-mm`).
pub fn write_synth_with_plan(
    effect: &str,
    seed: u64,
    plan: &SynthPlan,
    out: &Path,
    key_path: Option<&Path>,
    force: bool,
) -> Result<SynthOutput> {
    write_blind(out, key_path, force, || {
        let output = synthesize_with_plan(effect, seed, plan)?;
        Ok((output.dataset.clone(), output.key.clone(), output))
    })
}

/// Writes a synthesised data set to `out` and its key to `key_path`
/// (default [`default_key_path`]), refusing a key inside `out` before
/// anything is synthesised or written.
pub fn write_blind<T>(
    out: &Path,
    key_path: Option<&Path>,
    force: bool,
    make: impl FnOnce() -> Result<(Dataset, serde_json::Value, T)>,
) -> Result<T> {
    let key_path = key_path.map_or_else(|| default_key_path(out), Path::to_path_buf);
    let inside = |p: &Path| -> bool {
        let abs = |q: &Path| std::path::absolute(q).unwrap_or_else(|_| q.to_path_buf());
        abs(p).starts_with(abs(out))
    };
    ensure!(
        !inside(&key_path),
        "the key file {} must not be inside the data set folder {} (the diagnosis must be blind)",
        key_path.display(),
        out.display()
    );
    ensure!(
        force || !key_path.exists(),
        "the key file {} exists; pass --force to replace it",
        key_path.display()
    );
    let (dataset, key, output) = make()?;
    let options = WriteOptions {
        force,
        precision: SYNTH_PRECISION,
    };
    write_dataset(&dataset, out, &options)?;
    let mut key_text = serde_json::to_string_pretty(&key)?;
    key_text.push('\n');
    write_atomic(&key_path, key_text.as_bytes())?;
    Ok(output)
}
