//! Boot calibration arithmetic, range-checked so that a bad reading is
//! refused (and logged by the board) instead of silently applied:
//! - VDDA from the internal reference (VREFINT) and its factory value;
//! - the zero of a sensor read at rest (displacement offset, velocity zero,
//!   and the current sense with the PWM off).
//!
//! The board samples; this module decides. A refused calibration leaves the
//! nominal scaling in place.

/// VDDA at which the factory measured `VREFINT_CAL` (RM0351: 3.0 V).
pub const VREFINT_CAL_VDDA_V: f32 = 3.0;
/// The boards run VDDA from their 3.3 V regulator: accept ±10 %.
pub const VDDA_MIN_V: f32 = 2.97;
pub const VDDA_MAX_V: f32 = 3.63;

/// Why a calibration was refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CalError {
    /// No samples, a zero reference reading, or a non-finite sample.
    NoData,
    /// The result lies outside its plausible range (value attached).
    OutOfRange(f32),
    /// The samples spread more than allowed: the sensor was not at rest.
    NotAtRest { spread: f32 },
}

impl CalError {
    /// A short reason for logs (no `core::fmt` on the board).
    pub fn as_str(&self) -> &'static str {
        match self {
            CalError::NoData => "no data",
            CalError::OutOfRange(_) => "out of range",
            CalError::NotAtRest { .. } => "not at rest",
        }
    }
}

/// VDDA (V) from a VREFINT conversion and the factory calibration value,
/// both 12-bit: VDDA = 3.0 V · cal / raw.
pub fn vdda_v(vrefint_raw: u16, vrefint_cal: u16) -> Result<f32, CalError> {
    if vrefint_raw == 0 || vrefint_cal == 0 {
        return Err(CalError::NoData);
    }
    let vdda = VREFINT_CAL_VDDA_V * f32::from(vrefint_cal) / f32::from(vrefint_raw);
    if (VDDA_MIN_V..=VDDA_MAX_V).contains(&vdda) {
        Ok(vdda)
    } else {
        Err(CalError::OutOfRange(vdda))
    }
}

/// Limits for a zero taken at rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestLimits {
    /// Largest accepted |mean − expected|.
    pub max_offset: f32,
    /// Largest accepted max − min of the samples.
    pub max_spread: f32,
}

/// Displacement at rest: the sensor should read 0 mm. 1 mm is ~0.1 V of
/// mounting error; 0.2 mm of spread is ~20 LSB, far above ADC noise.
pub const X_REST: RestLimits = RestLimits {
    max_offset: 1.0,
    max_spread: 0.2,
};
/// Velocity at rest: 0 m/s; 0.3 m/s is 90 mV of conditioning offset.
pub const V_REST: RestLimits = RestLimits {
    max_offset: 0.3,
    max_spread: 0.3,
};

/// Current sense with the PWM off (the coil carries nothing): 0 A. 0.1 A is
/// 10 mV of amplifier offset at 0.1 V/A; 0.05 A of spread is ~6 LSB.
pub const I_SENSE_REST: RestLimits = RestLimits {
    max_offset: 0.1,
    max_spread: 0.05,
};

/// The offset (mean − `expected`) of `samples` taken at rest, to subtract
/// from later readings.
pub fn rest_offset(samples: &[f32], expected: f32, limits: RestLimits) -> Result<f32, CalError> {
    if samples.is_empty() || samples.iter().any(|s| !s.is_finite()) {
        return Err(CalError::NoData);
    }
    let (mut lo, mut hi, mut sum) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
    for &s in samples {
        lo = lo.min(s);
        hi = hi.max(s);
        sum += s;
    }
    let spread = hi - lo;
    if spread > limits.max_spread {
        return Err(CalError::NotAtRest { spread });
    }
    let offset = sum / samples.len() as f32 - expected;
    if mre_algorithm::math::abs(offset) > limits.max_offset {
        return Err(CalError::OutOfRange(offset));
    }
    Ok(offset)
}

/// Samples in a deferred current-sense zero (one per control period).
pub const DEFERRED_SAMPLES: usize = 64;
/// Periods the coil must have been commanded off before a sample counts:
/// 5 ms, over 2 coil time constants of the 2 ms coil and far past the
/// shunt filter.
pub const DEFERRED_SETTLE_PERIODS: u16 = 50;

/// The current-sense zero taken in the control loop after a reset that
/// deferred it ([`crate::boot::CalibrationTime::DeferredUntilAtRest`]): one
/// conversion per period, counted only while the damper is at rest and the
/// coil has been commanded 0 A for [`DEFERRED_SETTLE_PERIODS`]; any other
/// period starts the collection again. Then the same range check as at boot.
#[derive(Clone, Copy, Debug)]
pub struct DeferredSenseZero {
    samples: [f32; DEFERRED_SAMPLES],
    taken: usize,
    off_periods: u16,
}

impl Default for DeferredSenseZero {
    fn default() -> Self {
        Self {
            samples: [0.0; DEFERRED_SAMPLES],
            taken: 0,
            off_periods: 0,
        }
    }
}

impl DeferredSenseZero {
    /// One period: whether the damper is at rest, the coil current the last
    /// period commanded, and this period's raw reading (A, no offset). The
    /// result once [`DEFERRED_SAMPLES`] samples were taken, else `None`.
    pub fn push(&mut self, at_rest: bool, commanded_a: f32, raw_a: f32) -> Option<Result<f32, CalError>> {
        if !at_rest || commanded_a != 0.0 {
            self.off_periods = 0;
            self.taken = 0;
            return None;
        }
        if self.off_periods < DEFERRED_SETTLE_PERIODS {
            self.off_periods = self.off_periods.saturating_add(1);
            return None;
        }
        let slot = self.samples.get_mut(self.taken)?;
        *slot = raw_a;
        self.taken = self.taken.saturating_add(1);
        if self.taken < DEFERRED_SAMPLES {
            return None;
        }
        self.taken = 0;
        Some(rest_offset(&self.samples, 0.0, I_SENSE_REST))
    }
}
