//! Over-current fault from the coil's shunt. The board samples the shunt at
//! mid on-time of the PWM period (a low-side shunt carries the coil current
//! only while the switch is on; mid on-time is the ripple's average), or the
//! PIL plant reports its coil current. A current above [`TRIP_A`] for
//! [`TRIP_SAMPLES`] periods in a row latches `Flags::OVER_CURRENT`, which
//! removes the drive: zero, not the 2 A fail-safe, because the fail-safe
//! drives 67 % duty into the very coil or driver that failed
//! (`Controller::check_coil_current`). Pure logic: host-tested in
//! `tests/tests/core/overcurrent.rs`.
//!
//! The monitor is only as good as its input, so [`SenseMonitor`] also checks
//! the channel itself and latches `Flags::CURRENT_SENSE`:
//! - **stale**: every reading carries proof that it is new (the board's
//!   end-of-conversion flag, [`Sense::Stale`] when none arrived since the last
//!   period); [`STALE_PERIODS`] periods in a row without one latch;
//! - **stuck**: the coil model says ≥ [`STUCK_DRIVEN_A`] flows but the reading
//!   stays below [`STUCK_READ_A`] for [`STUCK_PERIODS`] periods in a row (an
//!   open amplifier, a broken sense wire, a trigger that converts nothing new
//!   but an old value).
//!
//! The open-loop drive cannot exceed the coil's 2 A rating on a healthy coil
//! (the law clamps its command; 100 % duty is 3 A only on a 4 Ω coil), so a
//! trip means a shorted turn, a wrong coil or supply, or a driver fault.

/// The coil's continuous rating (firmware/README.md, "Wiring").
pub const COIL_RATING_A: f32 = 2.0;
/// Trip level: 20 % above the rating, for the current ripple left at mid
/// on-time and the shunt amplifier's gain tolerance.
pub const TRIP_A: f32 = 2.4;
/// Periods in a row above the trip level: one noisy conversion does not
/// latch; 3 periods (0.3 ms at 10 kHz) is far inside the coil's thermal time.
pub const TRIP_SAMPLES: u16 = 3;

/// Debounced over-current detector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverCurrent {
    trip_a: f32,
    samples: u16,
    above: u16,
}

impl Default for OverCurrent {
    fn default() -> Self {
        Self::new(TRIP_A, TRIP_SAMPLES)
    }
}

impl OverCurrent {
    pub const fn new(trip_a: f32, samples: u16) -> Self {
        Self {
            trip_a,
            samples,
            above: 0,
        }
    }

    /// One measured coil current (A). True when the fault must latch: the
    /// magnitude was above the trip level for `samples` periods in a row. A
    /// non-finite reading counts as above (it cannot be shown safe).
    pub fn check(&mut self, measured_a: f32) -> bool {
        let over = measured_a.is_nan() || crate::math::abs(measured_a) > self.trip_a;
        self.above = if over { self.above.saturating_add(1) } else { 0 };
        self.above >= self.samples
    }

    /// Periods in a row above the trip level so far.
    pub fn above(&self) -> u16 {
        self.above
    }
}

/// One period's reading of the current-sense channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sense {
    /// A conversion completed since the last period (A, offset removed).
    Fresh(f32),
    /// No conversion completed since the last period.
    Stale,
}

/// Periods in a row without a new conversion that latch `CURRENT_SENSE`.
/// The shunt converts once per PWM period (20 kHz), so a 10 kHz period sees
/// two and a 20 kHz period one; 3 leaves room for one period of phase jitter
/// at 20 kHz and still latches within 0.3 ms at 10 kHz.
pub const STALE_PERIODS: u16 = 3;
/// The stuck check: the coil is driven (the law's coil model at or above
/// this), yet the reading stays below [`STUCK_READ_A`]. 1 A is half the
/// rating; 0.25 A is 10 % of it, far above the amplifier offset (0.1 A max).
pub const STUCK_DRIVEN_A: f32 = 1.0;
pub const STUCK_READ_A: f32 = 0.25;
/// 2 ms at 10 kHz: longer than the ripple, the current-sense filter and the
/// coil model's error over a period; short against a 10 ms impact.
pub const STUCK_PERIODS: u16 = 20;

/// What the current-sense channel says this period.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SenseVerdict {
    /// Latch `OVER_CURRENT` (remove the drive).
    pub over_current: bool,
    /// Latch `CURRENT_SENSE` (the channel is dead).
    pub sense_dead: bool,
}

/// Over-current plus the channel's own health (stale, stuck).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SenseMonitor {
    over: OverCurrent,
    stale: u16,
    stuck: u16,
}

impl SenseMonitor {
    /// One period: `reading` from the board, `driven_a` the coil current the
    /// law's model says flows now (its last command through the coil lag).
    pub fn check(&mut self, reading: Sense, driven_a: f32) -> SenseVerdict {
        let measured_a = match reading {
            Sense::Stale => {
                self.stale = self.stale.saturating_add(1);
                return SenseVerdict {
                    over_current: false,
                    sense_dead: self.stale >= STALE_PERIODS,
                };
            }
            Sense::Fresh(a) => a,
        };
        self.stale = 0;
        let over_current = self.over.check(measured_a);
        // NaN readings are the over-current check's; a NaN model current is
        // not "driven".
        let stuck = driven_a >= STUCK_DRIVEN_A && crate::math::abs(measured_a) < STUCK_READ_A;
        self.stuck = if stuck { self.stuck.saturating_add(1) } else { 0 };
        SenseVerdict {
            over_current,
            sense_dead: self.stuck >= STUCK_PERIODS,
        }
    }
}
