//! The impact-mitigation law: the controller's job in one function.
//!
//! A mass `m` moving into the damper at `v` (m/s) at stroke `x`, with usable
//! stroke `s_max`, is stopped within the remaining stroke `r = s_max − x` by
//! the constant force `F* = m·v²/(2r) + m·g` (energy balance with gravity
//! still pushing). The law asks the inverse model for the current that gives
//! `F*`, then applies the rebound policy, an output clamp and a slew-rate
//! limit. Untrusted inputs (NaN, ±inf, out of range) command the fail-safe
//! current instead.
//!
//! With a version 2 table the law also compensates what diagnosis found:
//! - **sensor delay** `d`: the sampled x, v are predicted `d` ahead with the
//!   model's own deceleration, `x + v·d`, `v + (g − F/m)·d`, F the model's
//!   force at the last plan's current (one period old);
//! - **coil lag** τ: the law keeps a model of the coil current (first order,
//!   `i += α·(u − i)`, `α = 1 − e^{−T/τ}`), and commands the drive `u` that
//!   brings the modelled current to the wanted current in one period
//!   (inverse of the lag), clamped to the driver's range (the supply voltage
//!   over the coil resistance, [`LawConfig::drive_min_a`]…`drive_max_a`). The
//!   wanted current itself stays within the coil's current limits. Because
//!   the coil can only decay so fast, the wanted current is also capped so
//!   that, decaying at the driver's limit, it can still meet what the plan
//!   wants 0.1 τ ahead (predictive command), that current extrapolated from
//!   the plan's change over the last period: no second model evaluation.
//!
//! **Arming** a lagging coil before contact (`crate::arming`):
//! - between impacts (extension branch, x at contact) the law holds the
//!   robust current: the lowest the model says stops the fastest impact the
//!   installation expects ([`LawConfig::impact_v_max_m_s`]) within the
//!   usable stroke (or [`LawConfig::armed_current_a`] when no range is set);
//! - on the approach (x < −[`CONTACT_MM`], moving in: the displacement sensor
//!   sees the mass before contact) it predicts the impact velocity from the
//!   sample, `v_c = √(v² + 2·g·|x|)` (free fall over the gap), and drives the
//!   coil to the current the model says stops a `v_c` impact within the
//!   stroke, from the first approach sample on. A board whose sensor does
//!   not see the approach has no prediction and stays at the robust current.
//!
//! A **force observer** closes the loop on the model itself: over each period
//! whose command the model says gives a force F (inverse inside the table,
//! the command neither capped, slewed nor clamped by the driver), the sampled
//! velocity's change says what the plant gave, `m·(g − Δv/T)`. An
//! exponential average of the difference (weight
//! [`LawConfig::observer_gain`] per period) is added to the force the law
//! asks the inverse for. It matters most with a lagging coil: the inversion
//! of a τ that diagnosis got 13 % wrong leaves the coil short of the model's
//! current for milliseconds, the plan re-plans that deficit upwards, and the
//! peak grows (`mre bench-control`, τ = 2 ms: 1.51× the limit without the
//! observer, 1.11× with it; BENCHMARKS.md). The estimate is clamped to
//! ±[`FORCE_ERROR_LIMIT_N`] and starts from 0 at every re-arm between impacts
//! (extension branch at contact) and every fail-safe period: no bias learned
//! in one impact is applied to the next.
use crate::arming::Arming;
use crate::flags::Flags;
use crate::installation::Installation;
use crate::math;
use crate::model::{Branch, BranchSelector};
use crate::table::Table;

/// What to command while the mass moves back out (v ≤ 0, extension branch).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReboundPolicy {
    /// Lowest allowed current: the softest unloading, so the elastomer hands
    /// back the least energy and the rebound is slowest. The default.
    Minimum,
    /// A fixed current (clamped to the output range).
    Fixed { current_a: f32 },
    /// Keep the last compression command.
    Hold,
}

/// Every tunable of the law, in one place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawConfig {
    /// Moving mass that hits the damper (the paper's drop test: 5.5 kg).
    pub mass_kg: f32,
    /// Usable stroke measured from first contact.
    pub stroke_max_mm: f32,
    pub gravity_m_s2: f32,
    /// Output clamp.
    pub current_min_a: f32,
    pub current_max_a: f32,
    /// Largest change of the command per second (coil and driver limit).
    pub slew_a_per_s: f32,
    /// Commanded whenever the inputs cannot be trusted.
    pub failsafe_current_a: f32,
    pub rebound: ReboundPolicy,
    /// Half-width of the velocity hysteresis band of the branch selector.
    pub branch_band_m_s: f32,
    /// Plausible sensor ranges; outside them the law goes fail-safe.
    pub x_valid_min_mm: f32,
    pub x_valid_max_mm: f32,
    pub v_valid_max_m_s: f32,
    /// Control period, for the slew limit.
    pub period_s: f32,
    /// Drive command range (A) with a coil time constant: the driver's
    /// supply voltage over the coil resistance, negative when it can reverse
    /// the voltage (half bridge). Board constants, not uploaded in PIL.
    pub drive_min_a: f32,
    pub drive_max_a: f32,
    /// Coil current held between impacts when the coil lags and no impact
    /// range is set (`impact_v_max_m_s` = 0). Moderate on purpose: at contact the force is zero whatever the field,
    /// and a coil that starts high must then decay (at most at V_s/L) while
    /// the plan asks for less. Measured when it was chosen (drop test,
    /// τ = 5 ms, the look-ahead on): 0–1 A all within 1.13–1.21× of the
    /// issue's 1242 N, 2 A 2.98×.
    pub armed_current_a: f32,
    /// The fastest impact the installation expects (m/s): between impacts a
    /// lagging coil is held at the current the model says stops it within
    /// the stroke (`crate::arming`). 0 = hold `armed_current_a` instead.
    pub impact_v_max_m_s: f32,
    /// Weight of each new observation in the force observer (0 = off, 1 =
    /// the last period's error alone; see the module docs). 0.05 averages
    /// the velocity sensor's noise (one period's Δv at 2 mm/s noise is
    /// ±160 N) over about 20 periods, 2 ms; 0.02–0.2 all met the
    /// `mre bench-control` targets when it was chosen.
    pub observer_gain: f32,
}

/// The end of the stroke (mm) over which the law plans with this much stroke
/// left: about ten times the displacement sensor's noise. A mass arriving
/// there at v overtravels by about `v²/(2a)`; at the 0.1 m/s the plan leaves
/// at most, a few hundredths of a millimetre.
pub const TERMINAL_MM: f32 = 0.1;

/// Displacement (mm) at or below which the damper counts as idle between
/// impacts (the coil is pre-energised there). Above the sensor's noise.
pub const CONTACT_MM: f32 = 0.05;

/// The force observer's largest correction (N), either way: about 80 % of
/// the paper drop's 1242 N force limit. A larger error is a failed model,
/// not a bias to learn: asking the inverse for more would double the plan.
pub const FORCE_ERROR_LIMIT_N: f32 = 1000.0;

impl Default for LawConfig {
    /// The paper's drop test (5.5 kg at 2.24 m/s) on a 2 A coil at 10 kHz.
    /// The usable stroke suits the drop test's 4–14 mm deflections (Table 5
    /// peaks with 13.8 J imply them; see README "Units and the paper").
    fn default() -> Self {
        Self {
            // The installation: one value for the image and the simulation.
            mass_kg: crate::installation::DEFAULT_INSTALLATION.mass_kg,
            stroke_max_mm: crate::installation::DEFAULT_INSTALLATION.usable_stroke_mm,
            gravity_m_s2: 9.81,
            current_min_a: 0.0,
            current_max_a: 2.0,
            slew_a_per_s: 2000.0,
            failsafe_current_a: Self::DEFAULT_FAILSAFE_CURRENT_A,
            rebound: ReboundPolicy::Minimum,
            branch_band_m_s: 0.005,
            x_valid_min_mm: -1.0,
            x_valid_max_mm: 25.0,
            v_valid_max_m_s: 20.0,
            period_s: 1.0e-4,
            // 12 V half bridge into the 4 Ω coil (firmware/README.md).
            drive_min_a: -3.0,
            drive_max_a: 3.0,
            armed_current_a: 0.5,
            impact_v_max_m_s: crate::installation::DEFAULT_INSTALLATION.impact_v_max_m_s,
            observer_gain: 0.05,
        }
    }
}

/// Why a configuration was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfigError {
    NonFinite,
    NonPositive,
    EmptyOutputRange,
    FailsafeOutsideRange,
    EmptySensorRange,
}

impl LawConfig {
    /// The default fail-safe current (A): the default coil's rating.
    pub const DEFAULT_FAILSAFE_CURRENT_A: f32 = 2.0;

    pub fn validate(&self) -> Result<(), ConfigError> {
        let all = [
            self.mass_kg,
            self.stroke_max_mm,
            self.gravity_m_s2,
            self.current_min_a,
            self.current_max_a,
            self.slew_a_per_s,
            self.failsafe_current_a,
            self.branch_band_m_s,
            self.x_valid_min_mm,
            self.x_valid_max_mm,
            self.v_valid_max_m_s,
            self.period_s,
            self.drive_min_a,
            self.drive_max_a,
            self.armed_current_a,
            self.impact_v_max_m_s,
            self.observer_gain,
        ];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(ConfigError::NonFinite);
        }
        if let ReboundPolicy::Fixed { current_a } = self.rebound {
            if !current_a.is_finite() {
                return Err(ConfigError::NonFinite);
            }
        }
        let positive = [
            self.mass_kg,
            self.stroke_max_mm,
            self.slew_a_per_s,
            self.v_valid_max_m_s,
            self.period_s,
        ];
        if positive.iter().any(|&v| v <= 0.0)
            || self.gravity_m_s2 < 0.0
            || self.branch_band_m_s < 0.0
            || self.impact_v_max_m_s < 0.0
        {
            return Err(ConfigError::NonPositive);
        }
        if self.current_min_a > self.current_max_a
            || self.drive_min_a > self.current_min_a
            || self.drive_max_a < self.current_max_a
        {
            return Err(ConfigError::EmptyOutputRange);
        }
        if self.failsafe_current_a < self.current_min_a || self.failsafe_current_a > self.current_max_a {
            return Err(ConfigError::FailsafeOutsideRange);
        }
        if self.armed_current_a < self.current_min_a || self.armed_current_a > self.current_max_a {
            return Err(ConfigError::EmptyOutputRange);
        }
        if !(0.0..=1.0).contains(&self.observer_gain) {
            return Err(ConfigError::NonPositive);
        }
        if self.x_valid_min_mm >= self.x_valid_max_mm {
            return Err(ConfigError::EmptySensorRange);
        }
        Ok(())
    }
}

/// One control decision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Command {
    /// The coil command: always finite; within `[current_min_a,
    /// current_max_a]`, or, when the table has a coil time constant, the
    /// drive within `[drive_min_a, drive_max_a]` (A equivalent: V / R).
    pub current_a: f32,
    /// The force the law asked for (0 when fail-safe or rebounding).
    pub target_force_n: f32,
    pub branch: Branch,
    pub flags: Flags,
}

/// A configuration an installation sets ([`Installation::apply`]): the law's
/// and the velocity sensor's scale. `control::ControlConfig` is one. Here,
/// not in `installation`, so that the installation (which a table carries)
/// uses nothing above it: no import circle table → installation → law →
/// table (issue 40).
pub trait InstallationTarget {
    fn law_mut(&mut self) -> &mut LawConfig;
    fn set_v_sensor_full_scale_m_s(&mut self, full_scale_m_s: f32);
}

impl Installation {
    /// Sets the law and fault configuration this installation determines:
    /// the law's mass and usable stroke, the output clamp at the coil's
    /// rating (the fail-safe and armed currents kept within it), the drive
    /// range of the half bridge (±supply / resistance), the displacement
    /// check's top at the sensor's range, the fastest impact the law arms
    /// for without a prediction (`impact_v_max_m_s`), and the velocity
    /// sensor's scale.
    pub fn apply<C: InstallationTarget + ?Sized>(&self, cfg: &mut C) {
        let law = cfg.law_mut();
        law.mass_kg = self.mass_kg;
        law.stroke_max_mm = self.usable_stroke_mm;
        law.current_max_a = self.coil_rating_a;
        law.failsafe_current_a = law.failsafe_current_a.min(self.coil_rating_a);
        law.armed_current_a = law.armed_current_a.min(self.coil_rating_a);
        law.drive_max_a = self.drive_max_a();
        law.drive_min_a = -self.drive_max_a();
        law.x_valid_max_mm = self.x_sensor_range_mm;
        // Without a predicted impact the coil idles armed for the fastest one.
        law.impact_v_max_m_s = self.impact_v_max_m_s;
        cfg.set_v_sensor_full_scale_m_s(self.v_sensor_full_scale_m_s);
    }
}

/// Stopping force for a mass at `v_m_s` with `remaining_mm` of stroke left:
/// `m·v²/(2r) + m·g`. `None` when no stroke is left.
#[inline]
pub fn stopping_force_n(mass_kg: f32, gravity_m_s2: f32, v_m_s: f32, remaining_mm: f32) -> Option<f32> {
    // Below a micrometre the force is unbounded for any practical purpose.
    const MIN_REMAINING_MM: f32 = 1.0e-3;
    if remaining_mm.is_nan() || remaining_mm < MIN_REMAINING_MM {
        return None;
    }
    Some(stopping_force_within_n(
        mass_kg,
        mass_kg * gravity_m_s2,
        v_m_s,
        remaining_mm,
    ))
}

/// [`stopping_force_n`] with the weight `m·g` given, for a remaining stroke
/// the caller keeps at or above a micrometre (the law: [`TERMINAL_MM`]).
#[inline(always)]
fn stopping_force_within_n(mass_kg: f32, weight_n: f32, v_m_s: f32, remaining_mm: f32) -> f32 {
    let remaining_m = remaining_mm * 1.0e-3;
    mass_kg * v_m_s * v_m_s / (2.0 * remaining_m) + weight_n
}

/// The stateful law: branch hysteresis and the slew limiter's memory.
#[derive(Clone, Copy, Debug)]
pub struct ImpactLaw {
    cfg: LawConfig,
    selector: BranchSelector,
    /// The last wanted coil current (the slew limiter's memory).
    last_current_a: f32,
    last_compression_current_a: f32,
    /// Model of the coil current behind the drive (used when τ > 0).
    coil_a: f32,
    /// The τ `coil_alpha` was computed for, and `1 − e^{−T/τ}`.
    coil_tau_s: f32,
    coil_alpha: f32,
    /// `coil_alpha < 1`: the coil lags (one byte test a period, not a
    /// float comparison; kept by `set_coil_tau`).
    lag: bool,
    /// The model's force at the last compression plan's current (N): what
    /// the sensor-delay prediction decelerates with, one period old.
    model_force_n: f32,
    /// The sampled velocity of the last period (the observer's Δv).
    last_v_m_s: f32,
    /// `m·g` and `m/T`: the measured force is `m·g − (m/T)·Δv`.
    weight_n: f32,
    mass_per_period_kg_s: f32,
    /// The force the model says the last command delivers (N), or 0 when
    /// it does not (saturated, capped, fail-safe, not compressing).
    expected_n: f32,
    /// The observer's estimate of how much less force the plant gives than
    /// the model (N).
    force_error_n: f32,
    /// The look-ahead's memory: the last plan's current (A), and whether
    /// the last period planned one (a compression, not fail-safe).
    last_plan_a: f32,
    planned_last: bool,
    /// The look-ahead `LEAD_TAU·τ` in control periods.
    lead_periods: f32,
    /// The arming currents of the table with CRC `arming_crc` (valid once
    /// `armed` is set).
    arming: Arming,
    arming_crc: u32,
    armed: bool,
}

/// How far ahead the law looks for a lagging coil, in units of τ: the
/// current must be able to decay to what the plan wants there.
pub const LEAD_TAU: f32 = 0.1;
/// `e^{LEAD_TAU}`: how much a decaying coil's distance to the drive floor
/// shrinks over the look-ahead (computed once, by hand: e^0.1).
const LEAD_GROWTH: f32 = 1.105_170_9;

impl ImpactLaw {
    /// Refuses an invalid configuration instead of running with it.
    // Out of line: run once per configuration; since `control` moved into this
    // crate (issue 40) it was inlined into `Controller::new`'s callers, +140 bytes of flash.
    #[inline(never)]
    pub fn new(cfg: LawConfig) -> Result<Self, ConfigError> {
        cfg.validate()?;
        Ok(Self {
            cfg,
            selector: BranchSelector::new(cfg.branch_band_m_s, Branch::Extension),
            last_current_a: cfg.current_min_a,
            last_compression_current_a: cfg.current_min_a,
            // Before its first sample the law has been idle: a lagging coil
            // has settled at the pre-energising current (a coil without lag
            // is overwritten by the first command).
            coil_a: cfg.armed_current_a,
            coil_tau_s: 0.0,
            coil_alpha: 1.0,
            lag: false,
            model_force_n: 0.0,
            last_v_m_s: 0.0,
            weight_n: cfg.mass_kg * cfg.gravity_m_s2,
            mass_per_period_kg_s: cfg.mass_kg / cfg.period_s,
            expected_n: 0.0,
            force_error_n: 0.0,
            last_plan_a: 0.0,
            planned_last: false,
            lead_periods: 0.0,
            arming: Arming::NONE,
            arming_crc: 0,
            armed: false,
        })
    }

    /// The coil current the law holds between impacts with `table`: the
    /// pre-energising current if its coil lags, else the rebound's minimum.
    /// A simulation that starts at contact starts the coil there.
    pub fn idle_current_a(&self, table: &Table) -> f32 {
        if table.terms().coil_tau_s > 0.0 {
            Self::idle_armed_a(&self.cfg, &self.arming_for(table))
        } else {
            self.cfg.current_min_a
        }
    }

    /// The arming currents for `table` with this configuration.
    fn arming_for(&self, table: &Table) -> Arming {
        let cfg = &self.cfg;
        Arming::new(
            table,
            cfg.mass_kg,
            cfg.gravity_m_s2,
            cfg.stroke_max_mm,
            cfg.impact_v_max_m_s,
        )
    }

    /// The current a lagging coil is held at between impacts.
    fn idle_armed_a(cfg: &LawConfig, arming: &Arming) -> f32 {
        if cfg.impact_v_max_m_s > 0.0 {
            math::clamp(arming.robust_current_a(), cfg.current_min_a, cfg.current_max_a)
        } else {
            cfg.armed_current_a
        }
    }

    /// The arming currents in use (for reports and tests).
    pub fn arming(&self) -> &Arming {
        &self.arming
    }

    /// The law's model of the coil current (A).
    pub fn coil_estimate_a(&self) -> f32 {
        self.coil_a
    }

    /// The force observer's estimate of how much less force the plant gives
    /// than the model (N; negative: more).
    pub fn force_error_n(&self) -> f32 {
        self.force_error_n
    }

    pub fn config(&self) -> &LawConfig {
        &self.cfg
    }

    pub fn last_current_a(&self) -> f32 {
        self.last_current_a
    }

    /// The fail-safe command. It bypasses the slew limit: a fault must not
    /// wait for a ramp.
    pub fn fail_safe(&mut self, flags: Flags) -> Command {
        // No learned bias survives a fault: the plant it was learned on
        // (sensors, coil) is in question.
        self.force_error_n = 0.0;
        self.last_current_a = self.cfg.failsafe_current_a;
        self.planned_last = false;
        self.expected_n = 0.0;
        self.coil_a += self.coil_alpha * (self.cfg.failsafe_current_a - self.coil_a);
        Command {
            current_a: self.cfg.failsafe_current_a,
            target_force_n: 0.0,
            branch: self.selector.branch(),
            flags: flags | Flags::FAIL_SAFE,
        }
    }

    /// The drive removed (0 A, 0 % duty): the answer to an over-current,
    /// where the fail-safe current would drive into the failed coil or driver.
    /// Like [`ImpactLaw::fail_safe`] it bypasses the slew limit.
    pub fn drive_off(&mut self, flags: Flags) -> Command {
        self.force_error_n = 0.0;
        self.last_current_a = 0.0;
        self.planned_last = false;
        self.expected_n = 0.0;
        self.coil_a -= self.coil_alpha * self.coil_a;
        Command {
            current_a: 0.0,
            target_force_n: 0.0,
            branch: self.selector.branch(),
            flags: flags | Flags::FAIL_SAFE,
        }
    }

    /// True when both samples are finite and within the plausible ranges,
    /// in one pass of comparisons (each false for NaN).
    #[inline(always)]
    fn inputs_plausible(&self, x_mm: f32, v_m_s: f32) -> bool {
        x_mm >= self.cfg.x_valid_min_mm
            && x_mm <= self.cfg.x_valid_max_mm
            && math::abs(v_m_s) <= self.cfg.v_valid_max_m_s
    }

    /// Which input fault makes the samples implausible (out of line: only
    /// a fault pays for telling them apart).
    #[inline(never)]
    #[cold]
    fn check_inputs(&self, x_mm: f32, v_m_s: f32) -> Flags {
        let mut flags = Flags::NONE;
        if !x_mm.is_finite() || !v_m_s.is_finite() {
            flags |= Flags::NON_FINITE_INPUT;
        } else if x_mm < self.cfg.x_valid_min_mm
            || x_mm > self.cfg.x_valid_max_mm
            || math::abs(v_m_s) > self.cfg.v_valid_max_m_s
        {
            flags |= Flags::SENSOR_RANGE;
        }
        flags
    }

    /// One period: sampled displacement and velocity in, coil command out.
    /// Derives what the law needs from `table` first when it has not yet
    /// ([`ImpactLaw::prepare`]).
    pub fn step(&mut self, table: &Table, x_mm: f32, v_m_s: f32) -> Command {
        self.prepare(table);
        self.step_prepared(table, x_mm, v_m_s)
    }

    /// [`ImpactLaw::step`] for a law already [`ImpactLaw::prepare`]d for
    /// `table` that flies no other (the controller: its table is fixed at
    /// construction): the period without the check that the table is the
    /// prepared one (7 instructions a control step).
    #[inline]
    pub(crate) fn step_prepared(&mut self, table: &Table, x_mm: f32, v_m_s: f32) -> Command {
        if !self.inputs_plausible(x_mm, v_m_s) {
            let input_faults = self.check_inputs(x_mm, v_m_s);
            return self.fail_safe(input_faults);
        }
        // Force observer: over the last period the mass decelerated by
        // Δv/T, so the plant gave m·(g − Δv/T); where the model said the
        // command gives `expected_n`, the difference is the model's error.
        if self.expected_n > 0.0 {
            let measured_n = self.weight_n - self.mass_per_period_kg_s * (v_m_s - self.last_v_m_s);
            let error_n =
                self.force_error_n + self.cfg.observer_gain * (self.expected_n - measured_n - self.force_error_n);
            self.force_error_n = math::clamp(error_n, -FORCE_ERROR_LIMIT_N, FORCE_ERROR_LIMIT_N);
        }
        self.last_v_m_s = v_m_s;
        let delay_s = table.terms().sensor_delay_s;
        let (x_mm, v_m_s) = if delay_s > 0.0 {
            self.predict(table, x_mm, v_m_s, delay_s)
        } else {
            (x_mm, v_m_s)
        };
        let branch = self.selector.update(v_m_s);
        // Re-armed between impacts: what the last impact taught the observer
        // says nothing about the next one.
        if branch == Branch::Extension && x_mm <= CONTACT_MM {
            self.force_error_n = 0.0;
        }
        let mut flags = Flags::NONE;
        let mut target_force_n = 0.0;
        let mut expected_n = 0.0;

        let wanted_a = match branch {
            // Before contact, moving in, with a coil too slow to set the
            // current during the impact: arm for the predicted impact. In
            // contact (the usual period) the first comparison settles it.
            Branch::Compression if x_mm < -CONTACT_MM && self.coil_tau_s > 0.0 => self.approach_current_a(x_mm, v_m_s),
            Branch::Compression => {
                // The last TERMINAL_MM are planned as if that much were left:
                // a slow arrival there (noise, model error) must not ask
                // for the unbounded force of stopping in a micrometre.
                // The command holds for one period while the mass moves on
                // and, at a held current, the force grows with x: plan for
                // where the period ends, so the force peaks at the target
                // instead of past it.
                let x_mm = x_mm + v_m_s * self.cfg.period_s * 1.0e3;
                let remaining_mm = self.cfg.stroke_max_mm - x_mm;
                // Not `f32::max`: that is a libcall on the target; the
                // remaining stroke is finite here (the inputs were checked).
                let planned_mm = if remaining_mm < TERMINAL_MM {
                    flags |= Flags::STROKE_EXHAUSTED;
                    TERMINAL_MM
                } else {
                    remaining_mm
                };
                // Finite and at least TERMINAL_MM: the inputs were checked.
                let force_n = stopping_force_within_n(self.cfg.mass_kg, self.weight_n, v_m_s, planned_mm);
                target_force_n = force_n;
                let ask_n = force_n + self.force_error_n;
                // Finite, |v| ≤ v_valid_max (checked above, far below the viscous
                // clamp) and v > 0 here: the plan's preconditions.
                let r = table.plan_current_v(x_mm, v_m_s, ask_n);
                flags |= r.flags;
                self.model_force_n = r.force_n;
                let (wanted_a, capped) = if self.lag {
                    self.anticipate(r.current_a)
                } else {
                    (r.current_a, false)
                };
                // The observer compares only where the model sets the force:
                // the inverse inside the table, the look-ahead not capping.
                if !capped && !r.flags.intersects(Flags::SATURATED_HIGH.union(Flags::SATURATED_LOW)) {
                    expected_n = ask_n;
                }
                wanted_a
            }
            // Idle between impacts with a lagging coil: pre-energise.
            Branch::Extension if self.coil_tau_s > 0.0 && x_mm <= CONTACT_MM => {
                Self::idle_armed_a(&self.cfg, &self.arming)
            }
            Branch::Extension => {
                flags |= Flags::REBOUND;
                match self.cfg.rebound {
                    ReboundPolicy::Minimum => self.cfg.current_min_a,
                    ReboundPolicy::Fixed { current_a } => current_a,
                    ReboundPolicy::Hold => self.last_compression_current_a,
                }
            }
        };

        let clamped_a = math::clamp(wanted_a, self.cfg.current_min_a, self.cfg.current_max_a);
        // The model's force is delivered only if the coil gets the command:
        // not where the output clamp or the slew limit changes it. A NaN
        // (or infinite) wanted current differs from its clamp too: it
        // would clamp to the softest current, so fail safe instead and
        // flag the table (validation bounds its values, so this is a bug).
        // Tested only here, where the clamp changed something.
        if clamped_a != wanted_a {
            if !wanted_a.is_finite() {
                return self.fail_safe(flags | Flags::TABLE_FAULT);
            }
            flags |= Flags::OUTPUT_CLAMPED;
            expected_n = 0.0;
        }
        // With a coil model the driver's voltage limit is the physical slew
        // limit (in `drive_for`); the configured one stands in for it otherwise.
        // The result stays in the output range: it lies between `clamped_a`
        // and the last command, and every command (fail-safe included) is
        // in that range. One test of the coil model for both.
        let (current_a, drive_a) = if self.lag {
            (clamped_a, self.drive_for(clamped_a))
        } else {
            let max_step_a = self.cfg.slew_a_per_s * self.cfg.period_s;
            let slewed_a = math::clamp(
                clamped_a,
                self.last_current_a - max_step_a,
                self.last_current_a + max_step_a,
            );
            if slewed_a != clamped_a {
                flags |= Flags::SLEW_LIMITED;
                expected_n = 0.0;
            }
            // No lag: the coil current is the command.
            self.coil_a = slewed_a;
            (slewed_a, slewed_a)
        };

        self.last_current_a = current_a;
        if branch == Branch::Compression {
            // (On the approach too: the rebound's `Hold` comes after the stroke.)
            self.last_compression_current_a = current_a;
        } else {
            // No plan this period: the look-ahead's trend starts afresh.
            self.planned_last = false;
        }
        // Every other exit goes through `fail_safe`, which clears it.
        self.expected_n = expected_n;
        Command {
            current_a: drive_a,
            target_force_n,
            branch,
            flags,
        }
    }

    /// The current to arm at on the approach (x < 0, moving in): the one
    /// that stops the predicted impact within the stroke. Out of line: the
    /// control periods in contact do not pay for it.
    #[inline(never)]
    #[cold]
    fn approach_current_a(&mut self, x_mm: f32, v_m_s: f32) -> f32 {
        // Free fall over the gap: v_c² = v² + 2·g·|x|.
        let gap_m = -x_mm * 1.0e-3;
        let impact_m_s = math::sqrt_precise(v_m_s * v_m_s + 2.0 * self.cfg.gravity_m_s2 * gap_m);
        // No plan: the look-ahead's trend starts at contact.
        self.planned_last = false;
        self.arming.stop_current_a(impact_m_s)
    }

    /// Derives what the law needs from `table`'s terms, unless it already
    /// has. [`ImpactLaw::step`] does it when the table changes; the
    /// controller does it when it gets its table, so that no control period
    /// pays for it.
    #[inline]
    pub fn prepare(&mut self, table: &Table) {
        // The CRC covers the entries and the terms: one comparison a period.
        if !self.armed || table.crc32() != self.arming_crc {
            self.prepare_for(table);
        }
    }

    /// Derives the coil model's factors and the arming currents of `table`.
    /// The first table finds the coil settled at its idle current (as
    /// [`ImpactLaw::new`] assumes).
    #[inline(never)]
    fn prepare_for(&mut self, table: &Table) {
        let coil_tau_s = table.terms().coil_tau_s;
        if coil_tau_s != self.coil_tau_s {
            self.set_coil_tau(coil_tau_s);
        }
        self.arming = self.arming_for(table);
        self.arming_crc = table.crc32();
        if !self.armed && self.coil_tau_s > 0.0 {
            self.coil_a = Self::idle_armed_a(&self.cfg, &self.arming);
        }
        self.armed = true;
    }

    #[inline(never)]
    fn set_coil_tau(&mut self, tau_s: f32) {
        self.coil_tau_s = tau_s;
        // Table validation keeps τ finite and ≥ 0; 0 → no lag (α = 1).
        self.coil_alpha = if tau_s > 0.0 {
            1.0 - math::exp_precise(-self.cfg.period_s / tau_s)
        } else {
            1.0
        };
        self.lag = self.coil_alpha < 1.0;
        self.lead_periods = LEAD_TAU * tau_s / self.cfg.period_s;
    }

    /// The wanted current now, so that a coil that can only decay at the
    /// driver's limit (`i(t+Δ) ≥ u_min + (i(t) − u_min)·e^{−Δ/τ}`) is no
    /// higher than what the plan will want `Δ = LEAD_TAU·τ` ahead:
    /// `min(i_now, u_min + (i_Δ − u_min)·e^{Δ/τ})`. `i_Δ` is the plan's
    /// current extrapolated along its change over the last period (`Δ/T`
    /// periods on), clamped to the output range: no model evaluation. The
    /// first period of a compression has no trend and is not capped.
    /// Also says whether it capped (the observer then compares nothing).
    #[inline(always)]
    fn anticipate(&mut self, now_a: f32) -> (f32, bool) {
        let prev_a = self.last_plan_a;
        self.last_plan_a = now_a;
        let has_trend = self.planned_last;
        self.planned_last = true;
        if !has_trend {
            return (now_a, false);
        }
        let cfg = &self.cfg;
        let ahead_a = math::clamp(
            now_a + (now_a - prev_a) * self.lead_periods,
            cfg.current_min_a,
            cfg.current_max_a,
        );
        let bound_a = cfg.drive_min_a + (ahead_a - cfg.drive_min_a) * LEAD_GROWTH;
        if bound_a < now_a {
            (bound_a, true)
        } else {
            (now_a, false)
        }
    }

    /// The drive that takes the modelled coil current to `wanted_a` in one
    /// period (the inverse of the first-order lag, `coil_alpha` < 1),
    /// clamped to the driver.
    #[inline]
    fn drive_for(&mut self, wanted_a: f32) -> f32 {
        let drive = self.coil_a + (wanted_a - self.coil_a) / self.coil_alpha;
        let drive = math::clamp(drive, self.cfg.drive_min_a, self.cfg.drive_max_a);
        self.coil_a += self.coil_alpha * (drive - self.coil_a);
        drive
    }

    /// x (mm) and v `delay_s` ahead of the samples, decelerated by the
    /// force the model gave at the last compression plan's current (on
    /// contact only: before it the mass is free; a rebound, which plans
    /// nothing, keeps the last one). That force is one period old, which a
    /// prediction over a delay of 0.1–1 ms (1–10 periods) tolerates, and it
    /// costs no model evaluation of its own.
    #[inline]
    fn predict(&self, table: &Table, x_mm: f32, v_m_s: f32, delay_s: f32) -> (f32, f32) {
        // Not `f32::max` (a libcall on the target); NaN → 0 as it did.
        let force_n = if x_mm > 0.0 && self.model_force_n > 0.0 {
            self.model_force_n
        } else {
            0.0
        };
        let a_m_s2 = self.cfg.gravity_m_s2 - force_n / self.cfg.mass_kg;
        let [mm_per_m_s, mm_per_m_s2] = table.delay_factors();
        (
            x_mm + v_m_s * mm_per_m_s + a_m_s2 * mm_per_m_s2,
            v_m_s + a_m_s2 * delay_s,
        )
    }
}
