//! The drop test: `m·ẍ = m·g − F(x, ẋ, I)` integrated by fixed-step RK4
//! from first contact (x = 0, ẋ = impact velocity), or from
//! [`ImpactConfig::approach_mm`] before it in free fall, until the mass leaves
//! the damper (x back below 0 while moving out).
//!
//! [`PlantStepper`] advances one control period at a time with the coil
//! command held (zero-order hold), so a controller — in process, or the real
//! firmware over a serial link — closes the loop in lockstep. [`simulate`]
//! runs a whole impact on top of it.
use super::effects::ConcealedEffect;
use super::law::LawParams;
use super::measure::MeasurementModel;
use anyhow::{ensure, Result};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// The simulated world: true law, concealed effect, instrument.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Plant {
    pub law: LawParams,
    pub effect: ConcealedEffect,
    pub measurement: MeasurementModel,
}

impl Default for Plant {
    fn default() -> Self {
        Self::nominal()
    }
}

impl Plant {
    /// The calibrated law, no effect, the default instrument.
    pub fn nominal() -> Self {
        Self {
            law: LawParams::nominal(),
            effect: ConcealedEffect::None,
            measurement: MeasurementModel::default(),
        }
    }

    pub fn with_effect(self, effect: ConcealedEffect) -> Self {
        Self { effect, ..self }
    }

    pub fn validate(&self) -> Result<()> {
        self.law.validate()?;
        self.effect.validate()?;
        self.measurement.validate()
    }

    /// The true contact force on the mass (N, ≥ 0) at displacement `x_mm`,
    /// velocity `v_m_s`, coil current `current_a`, in the test at `sequence`.
    pub fn force_n(&self, x_mm: f64, v_m_s: f64, current_a: f64, sequence: u32) -> f64 {
        if x_mm <= 0.0 {
            return 0.0;
        }
        let law = &self.law;
        let gain = law.gain(current_a, self.effect.current_warp());
        let material = gain * law.backbone_n(x_mm) * (1.0 + law.loss_eta * law.loss_direction(v_m_s));
        let force =
            self.effect.softening_factor(sequence) * material + self.effect.added_force_n(x_mm, v_m_s, current_a);
        force.max(0.0)
    }
}

/// One drop and how it is integrated.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImpactConfig {
    pub mass_kg: f64,
    pub impact_velocity_m_s: f64,
    pub gravity_m_s2: f64,
    /// RK4 step (s): 1 µs or finer.
    pub step_s: f64,
    /// Controller period (s): the command is held for this long.
    pub control_period_s: f64,
    /// Give up (and report no separation) after this long in contact.
    pub max_duration_s: f64,
    /// First-order coil time constant L/R (s); `None` = the current follows the command at once.
    pub coil_lag_s: Option<f64>,
    /// Time constant while the coil current falls (s), when switching off is
    /// slower than switching on (eddy currents in the core); `None` = `coil_lag_s`.
    pub coil_lag_off_s: Option<f64>,
    /// The drop starts this far before contact (mm), the mass falling freely,
    /// so a controller sees its approach (x < 0); it still reaches the
    /// contact at `impact_velocity_m_s`. 0 = start at contact.
    pub approach_mm: f64,
    /// The coil driver: with a coil lag the command (A) is the driver's
    /// voltage over R, limited by its supply.
    pub driver: CoilDriver,
    /// Coil current at contact (before the first command).
    pub initial_current_a: f64,
    /// Position of this test in the run order (1 = first), for history effects.
    pub sequence: u32,
    /// Seed of the measurement noise.
    pub noise_seed: u64,
}

impl Default for ImpactConfig {
    /// The paper's drop test (Table 2): 5.5 kg at 2.24 m/s; 10 kHz control,
    /// in the default installation (a model file's is
    /// [`ImpactConfig::for_installation`]).
    fn default() -> Self {
        Self {
            mass_kg: f64::from(mre_algorithm::installation::DEFAULT_INSTALLATION.mass_kg),
            impact_velocity_m_s: 2.24,
            gravity_m_s2: 9.81,
            step_s: 1.0e-6,
            control_period_s: 1.0e-4,
            max_duration_s: 0.5,
            coil_lag_s: None,
            coil_lag_off_s: None,
            approach_mm: 0.0,
            driver: CoilDriver::default(),
            initial_current_a: 0.0,
            sequence: 1,
            noise_seed: 0,
        }
    }
}

/// Longest coil time constant the simulator takes (s): real MR dampers
/// measure 5–20 ms; beyond 100 ms it is a unit mistake (as `mre_algorithm`'s
/// `MAX_TERM_TIME_S`).
pub const MAX_COIL_TAU_S: f64 = 0.1;

/// A voltage-source coil driver: `L·di/dt = V − R·i` with `V = R·command`
/// limited to the supply, so with `τ = L/R` the current follows the command
/// through a first-order lag whose input saturates at `±V_s/R`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CoilDriver {
    pub resistance_ohm: f64,
    pub supply_v: f64,
    /// A half bridge can drive −V_s (fast decay); a low-side switch only 0 V.
    pub reverse: bool,
}

impl Default for CoilDriver {
    /// The board's coil drive (firmware/README.md): 12 V half bridge, 4 Ω
    /// coil, the installation's (`mre_algorithm::installation`).
    fn default() -> Self {
        use mre_algorithm::installation::DEFAULT_INSTALLATION as I;
        Self {
            resistance_ohm: f64::from(I.coil_resistance_ohm),
            supply_v: f64::from(I.supply_v),
            reverse: true,
        }
    }
}

impl CoilDriver {
    /// The command range (A) the supply allows: `[−V_s/R or 0, V_s/R]`.
    pub fn command_range_a(&self) -> (f64, f64) {
        let max = self.supply_v / self.resistance_ohm;
        (if self.reverse { -max } else { 0.0 }, max)
    }

    /// Inductance (H) of a coil with time constant `tau_s`.
    pub fn inductance_h(&self, tau_s: f64) -> f64 {
        tau_s * self.resistance_ohm
    }
}

/// What the instrument recorded at one instant (x, v, force are measured
/// values), with the coil command and the coil current.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Sample {
    pub time_s: f64,
    pub x_mm: f64,
    pub v_m_s: f64,
    pub force_n: f64,
    /// Command held during the period that ended at this sample.
    pub command_a: f64,
    /// Coil current at this sample (the command after the coil lag).
    pub current_a: f64,
}

/// The true (not measured) outcome of an impact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ImpactSummary {
    pub peak_force_n: f64,
    /// Largest deceleration of the mass, `F/m − g` (m/s²).
    pub peak_deceleration_m_s2: f64,
    /// Largest jerk `|Δ(F/m)|/T` (m/s³) between control-period boundaries
    /// (T = the control period): what an occupant feels, on the true force.
    pub peak_jerk_m_s3: f64,
    pub max_stroke_mm: f64,
    /// Speed at which the mass leaves the damper (m/s, ≥ 0), if it did.
    pub rebound_velocity_m_s: Option<f64>,
    pub contact_time_s: f64,
}

/// A recorded impact.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Trajectory {
    /// Measured samples on the instrument's grid, from contact to separation.
    pub samples: Vec<Sample>,
    pub summary: ImpactSummary,
}

/// Where the coil current comes from.
pub enum CurrentSource<'a> {
    /// Held for the whole impact (passive damper).
    Constant(f64),
    /// A command that varies with time since contact (s → A), applied every RK4 step.
    Function(Box<dyn Fn(f64) -> f64 + 'a>),
    /// A controller: sampled (measured) x in mm and v in m/s in, command in A
    /// out, called once per control period; the command is held until the next call.
    Controller(Box<dyn FnMut(f32, f32) -> f32 + 'a>),
}

/// Integrator state: displacement (m), velocity (m/s).
#[derive(Clone, Copy, Debug)]
struct State {
    x_m: f64,
    v_m_s: f64,
}

/// Advances a drop one control period at a time (the lockstep API).
pub struct PlantStepper {
    plant: Plant,
    cfg: ImpactConfig,
    steps_per_period: u64,
    steps_per_sample: u64,
    step: u64,
    /// Step index of the next recorded sample.
    next_sample_step: u64,
    state: State,
    command_a: f64,
    current_a: f64,
    rng: ChaCha8Rng,
    /// True force after every step (index = step), for the force channel's delay.
    force_history_n: Vec<f64>,
    samples: Vec<Sample>,
    summary: ImpactSummary,
    finished: bool,
}

/// `period / step` when it is a whole number.
fn whole_steps(period_s: f64, step_s: f64, what: &str) -> Result<u64> {
    let n = (period_s / step_s).round();
    ensure!(
        n >= 1.0 && ((n * step_s - period_s) / period_s).abs() < 1e-9,
        "{what} ({period_s} s) must be a whole number of integration steps ({step_s} s)"
    );
    Ok(n as u64)
}

impl PlantStepper {
    /// Starts a drop at first contact and records the first sample.
    pub fn new(plant: &Plant, cfg: &ImpactConfig) -> Result<Self> {
        plant.validate()?;
        let finite = [
            cfg.mass_kg,
            cfg.impact_velocity_m_s,
            cfg.gravity_m_s2,
            cfg.step_s,
            cfg.control_period_s,
            cfg.max_duration_s,
            cfg.initial_current_a,
            cfg.approach_mm,
        ];
        ensure!(
            finite.iter().all(|v| v.is_finite()),
            "impact settings must be finite: {cfg:?}"
        );
        ensure!(cfg.mass_kg > 0.0, "mass must be positive");
        ensure!(
            cfg.impact_velocity_m_s > 0.0,
            "impact velocity must be positive (towards the damper)"
        );
        ensure!(
            cfg.step_s > 0.0 && cfg.step_s <= 1.0e-6,
            "RK4 step must be in (0, 1 µs]"
        );
        ensure!(cfg.max_duration_s > 0.0, "max duration must be positive");
        for tau_s in [cfg.coil_lag_s, cfg.coil_lag_off_s].into_iter().flatten() {
            ensure!(
                tau_s.is_finite() && tau_s > 0.0 && tau_s <= MAX_COIL_TAU_S,
                "the coil time constant must be more than 0 and at most {} ms (it was {} ms)",
                MAX_COIL_TAU_S * 1e3,
                tau_s * 1e3
            );
        }
        ensure!(
            cfg.coil_lag_off_s.is_none() || cfg.coil_lag_s.is_some(),
            "a switch-off time constant needs a coil time constant (`coil_lag_s`) too"
        );
        ensure!(
            cfg.approach_mm >= 0.0 && cfg.impact_velocity_m_s.powi(2) > 2.0 * cfg.gravity_m_s2 * cfg.approach_mm * 1e-3,
            "the approach ({} mm) must be at least 0 and shorter than the free fall that reaches {} m/s",
            cfg.approach_mm,
            cfg.impact_velocity_m_s
        );
        let d = &cfg.driver;
        ensure!(
            d.resistance_ohm.is_finite() && d.resistance_ohm > 0.0 && d.supply_v.is_finite() && d.supply_v > 0.0,
            "coil driver needs a positive resistance and supply voltage: {d:?}"
        );
        let steps_per_period = whole_steps(cfg.control_period_s, cfg.step_s, "control period")?;
        let steps_per_sample = whole_steps(plant.measurement.sample_period_s, cfg.step_s, "sample period")?;
        ensure!(
            steps_per_period % steps_per_sample == 0,
            "the control period must be a whole number of sample periods, so the controller sees recorded samples"
        );
        let mut stepper = Self {
            plant: plant.clone(),
            cfg: cfg.clone(),
            steps_per_period,
            steps_per_sample,
            step: 0,
            next_sample_step: 0,
            // Free fall over the approach: v² = v_c² − 2·g·a.
            state: State {
                x_m: -cfg.approach_mm * 1e-3,
                v_m_s: if cfg.approach_mm > 0.0 {
                    (cfg.impact_velocity_m_s.powi(2) - 2.0 * cfg.gravity_m_s2 * cfg.approach_mm * 1e-3).sqrt()
                } else {
                    cfg.impact_velocity_m_s
                },
            },
            command_a: cfg.initial_current_a,
            current_a: cfg.initial_current_a,
            rng: ChaCha8Rng::seed_from_u64(cfg.noise_seed),
            force_history_n: vec![0.0],
            samples: Vec::new(),
            summary: ImpactSummary {
                peak_force_n: 0.0,
                peak_deceleration_m_s2: -cfg.gravity_m_s2,
                peak_jerk_m_s3: 0.0,
                max_stroke_mm: 0.0,
                rebound_velocity_m_s: None,
                contact_time_s: 0.0,
            },
            finished: false,
        };
        stepper.record_sample();
        Ok(stepper)
    }

    pub fn config(&self) -> &ImpactConfig {
        &self.cfg
    }

    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// True once the mass has left the damper (or the time limit was hit).
    pub fn is_finished(&self) -> bool {
        self.finished
    }

    /// Time since contact (s).
    pub fn time_s(&self) -> f64 {
        self.step as f64 * self.cfg.step_s
    }

    /// The latest recorded sample (at contact: the first one).
    pub fn last_sample(&self) -> Sample {
        self.samples.last().copied().unwrap_or(Sample {
            time_s: 0.0,
            x_mm: 0.0,
            v_m_s: self.cfg.impact_velocity_m_s,
            force_n: 0.0,
            command_a: self.command_a,
            current_a: self.current_a,
        })
    }

    /// Holds `command_a` for one control period and returns the sample
    /// measured at its end (what the controller sees next). After the impact
    /// has finished it does nothing and returns the last sample.
    pub fn step_period(&mut self, command_a: f32) -> Sample {
        let command_a = f64::from(command_a);
        self.advance(self.steps_per_period, |_| command_a);
        self.last_sample()
    }

    /// Runs `steps` RK4 steps with the command given per step by `command`
    /// (time since contact → A).
    fn advance(&mut self, steps: u64, command: impl Fn(f64) -> f64) {
        for _ in 0..steps {
            if self.finished {
                return;
            }
            self.command_a = command(self.time_s());
            self.update_coil();
            self.rk4_step();
            self.step += 1;
            self.after_step();
        }
    }

    fn update_coil(&mut self) {
        self.current_a = match self.cfg.coil_lag_s {
            Some(tau_on_s) => {
                // The voltage the supply can give, over R: the current's target.
                let (lo, hi) = self.cfg.driver.command_range_a();
                let drive_a = self.command_a.clamp(lo, hi);
                // Falling towards zero: the switch-off time constant.
                let falling = drive_a.abs() < self.current_a.abs();
                let tau_s = match self.cfg.coil_lag_off_s {
                    Some(tau_off_s) if falling => tau_off_s,
                    _ => tau_on_s,
                };
                self.current_a + (drive_a - self.current_a) * (1.0 - (-self.cfg.step_s / tau_s).exp())
            }
            None => self.command_a,
        };
    }

    fn force_at(&self, s: State) -> f64 {
        self.plant
            .force_n(s.x_m * 1.0e3, s.v_m_s, self.current_a, self.cfg.sequence)
    }

    fn derivative(&self, s: State) -> State {
        let force_n = self.force_at(s);
        State {
            x_m: s.v_m_s,
            v_m_s: self.cfg.gravity_m_s2 - force_n / self.cfg.mass_kg,
        }
    }

    fn rk4_step(&mut self) {
        let h = self.cfg.step_s;
        let s = self.state;
        let at = |d: State, k: f64| State {
            x_m: s.x_m + k * d.x_m,
            v_m_s: s.v_m_s + k * d.v_m_s,
        };
        let k1 = self.derivative(s);
        let k2 = self.derivative(at(k1, h / 2.0));
        let k3 = self.derivative(at(k2, h / 2.0));
        let k4 = self.derivative(at(k3, h));
        let previous = self.state;
        self.state = State {
            x_m: s.x_m + h / 6.0 * (k1.x_m + 2.0 * k2.x_m + 2.0 * k3.x_m + k4.x_m),
            v_m_s: s.v_m_s + h / 6.0 * (k1.v_m_s + 2.0 * k2.v_m_s + 2.0 * k3.v_m_s + k4.v_m_s),
        };
        if self.state.x_m < 0.0 && self.state.v_m_s < 0.0 {
            // Separation: interpolate the speed to the instant x crosses 0.
            let frac = previous.x_m / (previous.x_m - self.state.x_m);
            let v_out = previous.v_m_s + frac * (self.state.v_m_s - previous.v_m_s);
            self.summary.rebound_velocity_m_s = Some(-v_out);
            self.summary.contact_time_s = (self.step as f64 + frac) * h;
            self.finished = true;
        }
    }

    fn after_step(&mut self) {
        let force_n = self.force_at(self.state);
        self.force_history_n.push(force_n);
        let s = &mut self.summary;
        s.peak_force_n = s.peak_force_n.max(force_n);
        s.peak_deceleration_m_s2 = s
            .peak_deceleration_m_s2
            .max(force_n / self.cfg.mass_kg - self.cfg.gravity_m_s2);
        s.max_stroke_mm = s.max_stroke_mm.max(self.state.x_m * 1.0e3);
        if self.step.is_multiple_of(self.steps_per_period) {
            let previous_n = self.force_history_n[(self.step - self.steps_per_period) as usize];
            let jerk = (force_n - previous_n).abs() / (self.cfg.mass_kg * self.cfg.control_period_s);
            s.peak_jerk_m_s3 = s.peak_jerk_m_s3.max(jerk);
        }
        let state_bad = !(self.state.x_m.is_finite() && self.state.v_m_s.is_finite());
        if !self.finished && (self.time_s() >= self.cfg.max_duration_s || state_bad) {
            self.summary.contact_time_s = self.time_s();
            self.finished = true;
        }
        if !self.finished && self.step >= self.next_sample_step {
            self.record_sample();
        }
    }

    /// True force `delay_s` ago (0 before contact), interpolated between steps.
    fn delayed_force_n(&self, delay_s: f64) -> f64 {
        let at = self.step as f64 - delay_s / self.cfg.step_s;
        if at < 0.0 {
            return 0.0;
        }
        let i = at.floor() as usize;
        let frac = at - at.floor();
        let f0 = self.force_history_n.get(i).copied().unwrap_or(0.0);
        let f1 = self.force_history_n.get(i + 1).copied().unwrap_or(f0);
        f0 + frac * (f1 - f0)
    }

    fn record_sample(&mut self) {
        self.next_sample_step = self.step + self.steps_per_sample;
        let m = &self.plant.measurement;
        let true_force_n = self.delayed_force_n(self.plant.effect.force_delay_s());
        let (x_mm, v_m_s) = (self.state.x_m * 1.0e3, self.state.v_m_s);
        let x_mm = MeasurementModel::read(x_mm, m.x_noise_mm, m.x_lsb_mm, &mut self.rng);
        let v_m_s = MeasurementModel::read(v_m_s, m.v_noise_m_s, m.v_lsb_m_s, &mut self.rng);
        let force_n = MeasurementModel::read(true_force_n, m.force_noise_n, m.force_lsb_n, &mut self.rng);
        self.samples.push(Sample {
            time_s: self.time_s(),
            x_mm,
            v_m_s,
            force_n,
            command_a: self.command_a,
            current_a: self.current_a,
        });
    }

    /// Ends the run and hands over what was recorded.
    pub fn into_trajectory(self) -> Trajectory {
        Trajectory {
            samples: self.samples,
            summary: self.summary,
        }
    }
}

/// Runs one whole impact with the coil current from `current`.
pub fn simulate(plant: &Plant, cfg: &ImpactConfig, current: CurrentSource<'_>) -> Result<Trajectory> {
    let mut stepper = PlantStepper::new(plant, cfg)?;
    match current {
        CurrentSource::Constant(current_a) => {
            ensure!(current_a.is_finite(), "constant current must be finite");
            while !stepper.is_finished() {
                stepper.advance(stepper.steps_per_period, |_| current_a);
            }
        }
        CurrentSource::Function(command) => {
            while !stepper.is_finished() {
                stepper.advance(stepper.steps_per_period, |t| {
                    let c = command(t);
                    if c.is_finite() {
                        c
                    } else {
                        0.0
                    }
                });
            }
        }
        CurrentSource::Controller(mut controller) => {
            let mut sample = stepper.last_sample();
            while !stepper.is_finished() {
                let command_a = controller(sample.x_mm as f32, sample.v_m_s as f32);
                // A controller that returns NaN gets 0 A (documented safe state).
                let command_a = if command_a.is_finite() { command_a } else { 0.0 };
                sample = stepper.step_period(command_a);
            }
        }
    }
    Ok(stepper.into_trajectory())
}
