//! One control period from sampled values: sample → estimate → law → coil
//! current, with fault latching, overrun accounting and statistics.
//!
//! This is the whole control task minus the I/O and the timing: the board's
//! embassy task (a `Ticker`, through `mre_runtime::io`) and the PIL frame link
//! both call [`Controller::step_sample`] once per period, and the host runs the
//! same calls, so `mre pil` and the tests fly exactly the logic of the board.
//!
//! Faults and the fail-safe (see `firmware/README.md`):
//! - A non-finite or out-of-range sample makes that period fail-safe (the law
//!   does that); `range_fault_samples` of them in a row latch `SENSOR_RANGE`
//!   (or `NON_FINITE_INPUT`).
//! - `SENSOR_STUCK` latches when the velocity sensor reports motion
//!   (|v| ≥ `stuck_min_speed_m_s`) but the displacement reading has not changed
//!   at all for `stuck_samples` periods: one of the two sensors is lying.
//!   Without a velocity sensor a frozen displacement cannot be told from a
//!   resting mass, so only its range (ADC rails) is checked.
//! - `OVERRUN` latches when `overrun_limit` periods of one window of
//!   `overrun_window` periods overran their deadline.
//! - `TABLE_FAULT` latches at construction if the table was rejected.
//!
//! - `OVER_CURRENT` / `CURRENT_SENSE`: the shunt's reading, before the step
//!   ([`Controller::check_coil_current`], `crate::overcurrent`).
//!
//! While any fault is latched every period commands the law's fail-safe
//! current (default 2 A: the stiffest damper, so an impact cannot bottom out),
//! except `OVER_CURRENT`, which removes the drive (0 A): the fail-safe would
//! drive 67 % duty into the failed coil or driver.
//! Latched faults clear only by [`Controller::clear_faults`] (a reset) or,
//! at rest, by B1's [`Controller::clear_faults_if_at_rest`], which keeps
//! `OVER_CURRENT`, `TABLE_FAULT` and a failed self-test's faults.
use crate::estimate::AlphaBeta;
use crate::flags::Flags;
use crate::law::{Command, ConfigError, ImpactLaw, LawConfig};
use crate::math;
use crate::overcurrent::{Sense, SenseMonitor};
use crate::table::{Table, TableError};

/// Control rate limits: below 1 kHz an impact (a few ms) is under-sampled;
/// 40 kHz leaves the M4F at 80 MHz 2000 cycles per period.
pub const RATE_MIN_HZ: u32 = 1_000;
pub const RATE_MAX_HZ: u32 = 40_000;
pub const DEFAULT_RATE_HZ: u32 = 10_000;
/// Displacement (mm) within which the damper counts as at rest for a fault clear.
pub const REST_X_MM: f32 = 0.5;
/// The velocity transducer's rated range, ±5 m/s (firmware/README.md, "Wiring").
pub const V_SENSOR_FULL_SCALE_M_S: f32 = 5.0;
/// Velocity cross-check defaults: the estimator lags an impact's
/// deceleration (hundreds of m/s²) by a few tenths of a m/s, so 5 ms (at
/// 10 kHz) more than 1 m/s apart is a lying sensor.
pub const DISAGREE_M_S: f32 = 1.0;
pub const DISAGREE_SAMPLES: u16 = 50;

/// Everything the control step needs besides the law's own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlConfig {
    /// Control rate; `law.period_s` is derived from it by [`ControlConfig::at_rate`].
    pub rate_hz: u32,
    pub law: LawConfig,
    /// Alpha-beta estimator gain α (β by Benedict–Bordner).
    pub estimator_alpha: f32,
    /// Consecutive bad samples (non-finite or out of range) that latch a fault.
    pub range_fault_samples: u16,
    /// Periods of an unchanged displacement while the velocity sensor reports
    /// motion that latch `SENSOR_STUCK`; 0 disables the check.
    pub stuck_samples: u16,
    pub stuck_min_speed_m_s: f32,
    /// `overrun_limit` overruns within one window of `overrun_window` periods
    /// latch `OVERRUN`.
    pub overrun_limit: u16,
    pub overrun_window: u16,
    /// The velocity sensor's rated full scale: a measured |v| at or beyond it
    /// is a range fault. The ADC rails read ±5.5 m/s (firmware/README.md), so
    /// a broken wire is caught here, not taken as a rebound.
    pub v_sensor_full_scale_m_s: f32,
    /// A measured velocity further than this from the estimator's (derived
    /// from x) for `disagree_samples` periods in a row latches `SENSOR_DISAGREE`;
    /// 0 samples disables the check.
    pub disagree_m_s: f32,
    pub disagree_samples: u16,
}

/// Why a control configuration was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ControlConfigError {
    Rate {
        rate_hz: u32,
    },
    Law(ConfigError),
    /// Period of the law does not match the rate.
    PeriodMismatch,
    Estimator,
    Counts,
}

impl ControlConfig {
    /// Defaults (the paper's drop test, see [`LawConfig::default`]) at `rate_hz`.
    pub fn at_rate(rate_hz: u32) -> Result<Self, ControlConfigError> {
        if !(RATE_MIN_HZ..=RATE_MAX_HZ).contains(&rate_hz) {
            return Err(ControlConfigError::Rate { rate_hz });
        }
        let law = LawConfig {
            period_s: 1.0 / rate_hz as f32,
            ..LawConfig::default()
        };
        let cfg = Self {
            rate_hz,
            law,
            estimator_alpha: 0.3,
            // 1 ms of bad samples at 10 kHz: a glitch is ridden out in
            // fail-safe, a broken wire latches.
            range_fault_samples: 10,
            // 5 ms at ≥ 50 mm/s is ≥ 0.25 mm of motion: tens of ADC LSBs.
            stuck_samples: 50,
            stuck_min_speed_m_s: 0.05,
            overrun_limit: 10,
            overrun_window: 1000,
            v_sensor_full_scale_m_s: V_SENSOR_FULL_SCALE_M_S,
            disagree_m_s: DISAGREE_M_S,
            disagree_samples: DISAGREE_SAMPLES,
        };
        cfg.validate()?;
        Ok(cfg)
    }

    pub fn period_s(&self) -> f32 {
        self.law.period_s
    }

    pub fn validate(&self) -> Result<(), ControlConfigError> {
        if !(RATE_MIN_HZ..=RATE_MAX_HZ).contains(&self.rate_hz) {
            return Err(ControlConfigError::Rate { rate_hz: self.rate_hz });
        }
        self.law.validate().map_err(ControlConfigError::Law)?;
        let period_s = 1.0 / self.rate_hz as f32;
        if math::abs(self.law.period_s - period_s) > period_s * 1.0e-4 {
            return Err(ControlConfigError::PeriodMismatch);
        }
        let a = self.estimator_alpha;
        if !(a > 0.0 && a <= 1.0) {
            return Err(ControlConfigError::Estimator);
        }
        if self.range_fault_samples == 0
            || self.overrun_limit == 0
            || self.overrun_window < self.overrun_limit
            || !self.stuck_min_speed_m_s.is_finite()
            || self.stuck_min_speed_m_s < 0.0
            || self.v_sensor_full_scale_m_s.is_nan()
            || self.v_sensor_full_scale_m_s <= 0.0
            || self.disagree_m_s.is_nan()
            || self.disagree_m_s <= 0.0
        {
            return Err(ControlConfigError::Counts);
        }
        Ok(())
    }
}

impl crate::law::InstallationTarget for ControlConfig {
    fn law_mut(&mut self) -> &mut LawConfig {
        &mut self.law
    }

    fn set_v_sensor_full_scale_m_s(&mut self, full_scale_m_s: f32) {
        self.v_sensor_full_scale_m_s = full_scale_m_s;
    }
}

/// Counters for the periodic defmt statistics. Cycle figures are fed by the
/// board ([`Controller::record_step_cycles`]); they stay 0 where no cycle
/// counter exists (QEMU).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    pub periods: u32,
    pub overruns: u32,
    /// Periods that commanded the fail-safe current.
    pub failsafe_periods: u32,
    /// Times a fault got latched.
    pub fault_latches: u32,
    pub latched: Flags,
    pub step_cycles_min: u32,
    pub step_cycles_max: u32,
    pub step_cycles_sum: u64,
    pub step_cycles_count: u32,
}

impl Stats {
    pub fn step_cycles_mean(&self) -> u32 {
        if self.step_cycles_count == 0 {
            0
        } else {
            self.step_cycles_sum
                .checked_div(u64::from(self.step_cycles_count))
                .unwrap_or(0) as u32
        }
    }
}

/// The control loop's state: law, estimator, fault latches and statistics.
#[derive(Clone, Copy, Debug)]
pub struct Controller {
    cfg: ControlConfig,
    table: Option<Table>,
    law: ImpactLaw,
    estimator: AlphaBeta,
    latched: Flags,
    bad_samples: u16,
    last_x_mm: f32,
    unchanged_moving: u16,
    disagreeing: u16,
    /// The latest displacement sample (for the at-rest test of a fault clear).
    sample_x_mm: f32,
    window_periods: u16,
    window_overruns: u16,
    sense: SenseMonitor,
    /// Faults of a failed power-on self-test: kept through B1's clear.
    boot_faults: Flags,
    stats: Stats,
}

impl Controller {
    /// A rejected table does not stop construction: the controller then
    /// latches `TABLE_FAULT` and runs fail-safe, which is what the board must do.
    pub fn new(cfg: ControlConfig, table: Result<Table, TableError>) -> Result<Self, ControlConfigError> {
        cfg.validate()?;
        let law = ImpactLaw::new(cfg.law).map_err(ControlConfigError::Law)?;
        let mut c = Self {
            cfg,
            table: None,
            law,
            estimator: AlphaBeta::benedict_bordner(cfg.period_s(), cfg.estimator_alpha),
            latched: Flags::NONE,
            bad_samples: 0,
            last_x_mm: f32::NAN,
            unchanged_moving: 0,
            disagreeing: 0,
            sample_x_mm: f32::NAN,
            window_periods: 0,
            window_overruns: 0,
            sense: SenseMonitor::default(),
            boot_faults: Flags::NONE,
            stats: Stats::default(),
        };
        match table {
            Ok(t) => {
                c.law.prepare(&t);
                c.table = Some(t);
            }
            Err(_) => c.latch(Flags::TABLE_FAULT),
        }
        Ok(c)
    }

    pub fn config(&self) -> &ControlConfig {
        &self.cfg
    }

    pub fn table(&self) -> Option<&Table> {
        self.table.as_ref()
    }

    pub fn latched(&self) -> Flags {
        self.latched
    }

    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Restarts the cycle statistics (min/max/mean per logging interval).
    pub fn reset_cycle_stats(&mut self) {
        self.stats.step_cycles_min = 0;
        self.stats.step_cycles_max = 0;
        self.stats.step_cycles_sum = 0;
        self.stats.step_cycles_count = 0;
    }

    /// Clears latched sensor and overrun faults (not a table fault: the table
    /// does not heal). Counters keep running.
    pub fn clear_faults(&mut self) {
        self.latched = Flags(self.latched.0 & Flags::TABLE_FAULT.0);
        self.bad_samples = 0;
        self.unchanged_moving = 0;
        self.disagreeing = 0;
        self.window_periods = 0;
        self.window_overruns = 0;
        self.sense = SenseMonitor::default();
    }

    /// The button's fault clear: only with the damper at rest (the latest
    /// displacement within `REST_X_MM` of 0 and the estimated speed below
    /// `stuck_min_speed_m_s`), never mid-impact. True if it cleared. A fault
    /// whose cause persists latches again.
    /// `OVER_CURRENT` stays latched (a short does not heal at rest; only a
    /// reset clears it, firmware/README.md "Faults"), as `TABLE_FAULT` does.
    pub fn clear_faults_if_at_rest(&mut self) -> bool {
        let at_rest = self.is_at_rest();
        if at_rest {
            let kept = Flags(self.latched.0 & (Flags::OVER_CURRENT.0 | self.boot_faults.0));
            self.clear_faults();
            self.latched |= kept;
        }
        at_rest
    }

    /// The latest displacement within `REST_X_MM` of 0 and the estimated
    /// speed below `stuck_min_speed_m_s` (a fault clear, a table upload).
    pub fn is_at_rest(&self) -> bool {
        math::abs(self.sample_x_mm) <= REST_X_MM
            && math::abs(self.estimator.velocity_m_s()) < self.cfg.stuck_min_speed_m_s
    }

    /// The current-sense channel's reading for this period, before the step
    /// (`None`: no channel wired, nothing checked). Latches `OVER_CURRENT`
    /// (this period's step then removes the drive) or `CURRENT_SENSE`
    /// (stale or stuck channel: the fail-safe current).
    pub fn check_coil_current(&mut self, reading: Option<Sense>) {
        let Some(reading) = reading else { return };
        let verdict = self.sense.check(reading, self.law.coil_estimate_a());
        if verdict.over_current {
            self.latch(Flags::OVER_CURRENT);
        }
        if verdict.sense_dead {
            self.latch(Flags::CURRENT_SENSE);
        }
    }

    /// Latches a fault detected outside the step.
    pub fn latch_fault(&mut self, fault: Flags) {
        self.latch(fault);
    }

    /// Faults a failed power-on self-test latches before the first period
    /// (`boot::SelfTest::faults`): the controller holds the fail-safe and
    /// never arms; B1 does not clear them (only a reset).
    pub fn latch_boot_faults(&mut self, faults: Flags) {
        self.boot_faults |= faults;
        self.latch(faults);
    }

    fn latch(&mut self, fault: Flags) {
        if !self.latched.contains(fault) {
            self.stats.fault_latches = self.stats.fault_latches.saturating_add(1);
        }
        self.latched |= fault;
        self.stats.latched = self.latched;
    }

    /// One period from sampled values (`v_measured_m_s = None`: no velocity
    /// sensor, use the estimator). The returned current is always finite and
    /// inside the law's output range.
    // `#[inline]`: emitted into the board's crate with `step_io`
    // (`mre_runtime::io`), optimized there with the board's I/O before LTO. Compiled alone in this crate and
    // inlined only by LTO, the control task took 396 bytes more of flash and
    // 1 more instruction per step (issue 40: `cargo fw` 86 340 -> 85 972 B).
    #[inline]
    pub fn step_sample(&mut self, x_mm: f32, v_measured_m_s: Option<f32>) -> Command {
        self.stats.periods = self.stats.periods.wrapping_add(1);
        self.sample_x_mm = x_mm;
        // The estimator runs every period so it is settled if the velocity
        // sensor is ever dropped; a non-finite x only predicts.
        let (v_est_m_s, _) = self.estimator.update(x_mm);
        let v_m_s = v_measured_m_s.unwrap_or(v_est_m_s);
        self.check_stuck(x_mm, v_measured_m_s);
        self.check_disagree(x_mm, v_measured_m_s, v_est_m_s);
        // A reading at the sensor's full scale is a rail (broken wire), not
        // a speed: the law's own plausibility limit is far wider.
        let at_full_scale = v_measured_m_s.is_some_and(|v| math::abs(v) >= self.cfg.v_sensor_full_scale_m_s);

        let mut cmd = match &self.table {
            Some(_) if at_full_scale && !self.latched.is_fault() => self.law.fail_safe(Flags::SENSOR_RANGE),
            Some(table) if !self.latched.is_fault() => self.law.step_prepared(table, x_mm, v_m_s),
            _ if self.latched.contains(Flags::OVER_CURRENT) => self.law.drive_off(self.latched),
            _ => self.law.fail_safe(self.latched),
        };
        // A fail-safe period (or a table fault) has bookkeeping to do; the
        // usual period only clears the bad-sample run (no fault is latched:
        // it would have failed safe).
        if cmd.flags.intersects(Flags::FAIL_SAFE.union(Flags::TABLE_FAULT)) {
            self.account_fail_safe(cmd.flags);
        } else {
            self.bad_samples = 0;
        }
        cmd.flags |= self.latched;
        cmd
    }

    /// The bookkeeping of a period whose command carries `flags` with
    /// `FAIL_SAFE` or `TABLE_FAULT` (out of line: the usual period has none).
    #[inline(never)]
    #[cold]
    fn account_fail_safe(&mut self, flags: Flags) {
        // The law flags a non-finite result of the table (it cannot happen
        // with a validated table): the table is not to be trusted again.
        if flags.contains(Flags::TABLE_FAULT) {
            self.latch(Flags::TABLE_FAULT);
        }
        let input_fault = Flags(flags.0 & (Flags::SENSOR_RANGE.0 | Flags::NON_FINITE_INPUT.0));
        if input_fault != Flags::NONE && flags.contains(Flags::FAIL_SAFE) {
            self.bad_samples = self.bad_samples.saturating_add(1);
            if self.bad_samples >= self.cfg.range_fault_samples {
                self.latch(input_fault);
            }
        } else if !self.latched.is_fault() {
            self.bad_samples = 0;
        }
        if flags.contains(Flags::FAIL_SAFE) {
            self.stats.failsafe_periods = self.stats.failsafe_periods.saturating_add(1);
        }
    }

    fn check_stuck(&mut self, x_mm: f32, v_measured_m_s: Option<f32>) {
        if self.cfg.stuck_samples == 0 {
            return;
        }
        // Bit-identical: a real moving sensor changes by at least one LSB.
        // A changed reading (the usual case) settles it without the speed.
        let unchanged = x_mm.to_bits() == self.last_x_mm.to_bits();
        self.last_x_mm = x_mm;
        if !unchanged {
            self.unchanged_moving = 0;
            return;
        }
        let moving = match v_measured_m_s {
            Some(v) => v.is_finite() && math::abs(v) >= self.cfg.stuck_min_speed_m_s,
            None => false,
        };
        if moving {
            self.unchanged_moving = self.unchanged_moving.saturating_add(1);
            if self.unchanged_moving >= self.cfg.stuck_samples {
                self.latch(Flags::SENSOR_STUCK);
            }
        } else {
            self.unchanged_moving = 0;
        }
    }

    fn check_disagree(&mut self, x_mm: f32, v_measured_m_s: Option<f32>, v_est_m_s: f32) {
        let Some(v_m_s) = v_measured_m_s else { return };
        // Agreement first: one comparison on the usual path (false for NaN).
        if math::abs(v_m_s - v_est_m_s) <= self.cfg.disagree_m_s {
            self.disagreeing = 0;
            return;
        }
        // Both finite, in one comparison (false for NaN and ±inf; a sum
        // beyond f32::MAX is far out of range: the range check's too).
        let finite = math::abs(x_mm) + math::abs(v_m_s) <= f32::MAX;
        if self.cfg.disagree_samples == 0 || !finite {
            // Non-finite samples are the range check's business.
            self.disagreeing = 0;
            return;
        }
        self.disagreeing = self.disagreeing.saturating_add(1);
        if self.disagreeing >= self.cfg.disagree_samples {
            self.latch(Flags::SENSOR_DISAGREE);
        }
    }

    /// Call once per period after the step, with whether the period's work
    /// finished after the next tick was due.
    pub fn end_period(&mut self, overran: bool) {
        if overran {
            self.stats.overruns = self.stats.overruns.saturating_add(1);
            self.window_overruns = self.window_overruns.saturating_add(1);
            if self.window_overruns >= self.cfg.overrun_limit {
                self.latch(Flags::OVERRUN);
            }
        }
        self.window_periods = self.window_periods.saturating_add(1);
        if self.window_periods >= self.cfg.overrun_window {
            self.window_periods = 0;
            self.window_overruns = 0;
        }
    }

    /// Adds ticks that were missed entirely (the ticker skipped them).
    pub fn record_missed_periods(&mut self, missed: u32) {
        for _ in 0..missed.min(u32::from(self.cfg.overrun_limit)) {
            self.end_period(true);
        }
        let extra = missed.saturating_sub(u32::from(self.cfg.overrun_limit));
        self.stats.overruns = self.stats.overruns.saturating_add(extra);
    }

    /// Cycle count of one step (DWT CYCCNT on the board).
    pub fn record_step_cycles(&mut self, cycles: u32) {
        let s = &mut self.stats;
        if s.step_cycles_count == 0 || cycles < s.step_cycles_min {
            s.step_cycles_min = cycles;
        }
        s.step_cycles_max = s.step_cycles_max.max(cycles);
        s.step_cycles_sum = s.step_cycles_sum.saturating_add(u64::from(cycles));
        s.step_cycles_count = s.step_cycles_count.saturating_add(1);
    }
}
