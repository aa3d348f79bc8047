//! The impact-mitigation law: the controller's job in one function.
//!
//! A mass `m` moving into the damper at `v` (m/s) at stroke `x`, with usable
//! stroke `s_max`, is stopped within the remaining stroke `r = s_max − x` by
//! the constant force `F* = m·v²/(2r) + m·g` (energy balance with gravity
//! still pushing). The law asks the inverse model for the current that gives
//! `F*`, then applies the rebound policy, an output clamp and a slew-rate
//! limit. Untrusted inputs (NaN, ±inf, out of range) command the fail-safe
//! current instead.
use crate::flags::Flags;
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
}

impl Default for LawConfig {
    /// The paper's drop test (5.5 kg at 2.24 m/s) on a 2 A coil at 10 kHz.
    /// The usable stroke suits the drop test's 4–14 mm deflections (Table 5
    /// peaks with 13.8 J imply them; see README "Units and the paper").
    fn default() -> Self {
        Self {
            mass_kg: 5.5,
            stroke_max_mm: 15.0,
            gravity_m_s2: 9.81,
            current_min_a: 0.0,
            current_max_a: 2.0,
            slew_a_per_s: 2000.0,
            failsafe_current_a: 2.0,
            rebound: ReboundPolicy::Minimum,
            branch_band_m_s: 0.005,
            x_valid_min_mm: -1.0,
            x_valid_max_mm: 25.0,
            v_valid_max_m_s: 20.0,
            period_s: 1.0e-4,
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
        if positive.iter().any(|&v| v <= 0.0) || self.gravity_m_s2 < 0.0 || self.branch_band_m_s < 0.0 {
            return Err(ConfigError::NonPositive);
        }
        if self.current_min_a > self.current_max_a {
            return Err(ConfigError::EmptyOutputRange);
        }
        if self.failsafe_current_a < self.current_min_a || self.failsafe_current_a > self.current_max_a {
            return Err(ConfigError::FailsafeOutsideRange);
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
    /// Always finite and within `[current_min_a, current_max_a]`.
    pub current_a: f32,
    /// The force the law asked for (0 when fail-safe or rebounding).
    pub target_force_n: f32,
    pub branch: Branch,
    pub flags: Flags,
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
    let remaining_m = remaining_mm * 1.0e-3;
    Some(mass_kg * v_m_s * v_m_s / (2.0 * remaining_m) + mass_kg * gravity_m_s2)
}

/// The stateful law: branch hysteresis and the slew limiter's memory.
#[derive(Clone, Copy, Debug)]
pub struct ImpactLaw {
    cfg: LawConfig,
    selector: BranchSelector,
    last_current_a: f32,
    last_compression_current_a: f32,
}

impl ImpactLaw {
    /// Refuses an invalid configuration instead of running with it.
    pub fn new(cfg: LawConfig) -> Result<Self, ConfigError> {
        cfg.validate()?;
        Ok(Self {
            cfg,
            selector: BranchSelector::new(cfg.branch_band_m_s, Branch::Extension),
            last_current_a: cfg.current_min_a,
            last_compression_current_a: cfg.current_min_a,
        })
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
        self.last_current_a = self.cfg.failsafe_current_a;
        Command {
            current_a: self.cfg.failsafe_current_a,
            target_force_n: 0.0,
            branch: self.selector.branch(),
            flags: flags | Flags::FAIL_SAFE,
        }
    }

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
    pub fn step(&mut self, table: &Table, x_mm: f32, v_m_s: f32) -> Command {
        let input_faults = self.check_inputs(x_mm, v_m_s);
        if input_faults != Flags::NONE {
            return self.fail_safe(input_faults);
        }
        let cfg = self.cfg;
        let branch = self.selector.update(v_m_s);
        let mut flags = Flags::NONE;
        let mut target_force_n = 0.0;

        let wanted_a = match branch {
            Branch::Compression => {
                match stopping_force_n(cfg.mass_kg, cfg.gravity_m_s2, v_m_s, cfg.stroke_max_mm - x_mm) {
                    Some(force_n) => {
                        target_force_n = force_n;
                        let r = table.current_for_branch(x_mm, Branch::Compression, force_n);
                        flags |= r.flags;
                        r.current_a
                    }
                    None => {
                        flags |= Flags::STROKE_EXHAUSTED;
                        cfg.current_max_a
                    }
                }
            }
            Branch::Extension => {
                flags |= Flags::REBOUND;
                match cfg.rebound {
                    ReboundPolicy::Minimum => cfg.current_min_a,
                    ReboundPolicy::Fixed { current_a } => current_a,
                    ReboundPolicy::Hold => self.last_compression_current_a,
                }
            }
        };

        let clamped_a = math::clamp(wanted_a, cfg.current_min_a, cfg.current_max_a);
        if clamped_a != wanted_a {
            flags |= Flags::OUTPUT_CLAMPED;
        }
        let max_step_a = cfg.slew_a_per_s * cfg.period_s;
        let current_a = math::clamp(
            clamped_a,
            self.last_current_a - max_step_a,
            self.last_current_a + max_step_a,
        );
        if current_a != clamped_a {
            flags |= Flags::SLEW_LIMITED;
        }
        // Stay inside the output range even if the previous command was not.
        let current_a = math::clamp(current_a, cfg.current_min_a, cfg.current_max_a);

        self.last_current_a = current_a;
        if branch == Branch::Compression {
            self.last_compression_current_a = current_a;
        }
        Command {
            current_a,
            target_force_n,
            branch,
            flags,
        }
    }
}
