//! Over-current fault from the coil's shunt. The board samples the shunt at
//! mid on-time of the PWM period (a low-side shunt carries the coil current
//! only while the switch is on; mid on-time is the ripple's average), or the
//! PIL plant reports its coil current. A current above [`TRIP_A`] for
//! [`TRIP_SAMPLES`] periods in a row latches `Flags::OVER_CURRENT`, which puts
//! the controller in its fail-safe (the board's control task calls
//! `Controller::latch_fault`). Pure logic: host-tested in
//! `tests/tests/overcurrent.rs`.
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
