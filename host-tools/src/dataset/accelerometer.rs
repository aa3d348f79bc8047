//! Accelerometer drop records (docs/dataset-format.md, "Accelerometer drop
//! records"): time and the striker's acceleration, no force column, with
//! the drop mass and the impact velocity (a light gate's) in the manifest.
//!
//! ISO 6603-2 and ASTM D7136 integrate the striker's equation of motion,
//! positive downwards (compressing): m·ẍ = m·g − F, so
//! v(t) = v0 + g·t − (1/m)∫F dt. Read backwards, an accelerometer on the
//! striker gives the force on the damper: F = m·(g − ẍ), and the motion is
//! the same integral, v(t) = v0 + ∫ẍ dt, x(t) = ∫v dt (`super::motion`).
//!
//! An accelerometer reads ẍ plus an offset: a piezoelectric or MEMS sensor
//! reads 0 in free fall (it measures ẍ − g), a bias drifts, rail friction
//! slows the fall. The samples before contact, in free fall, read what the
//! sensor gives for ẍ = g, so their mean minus g is the offset, removed
//! before integration. What is left is reported as the integration's
//! uncertainty at the end of the impact (time T after contact):
//! Δv = Δv0 + δa·T, Δx = Δv0·T + δa·T²/2 + v0·Δt, with δa twice the
//! standard error of the free-fall mean (95 %), Δv0 the light gate's stated
//! uncertainty, and v0·Δt the contact located to one sample interval Δt
//! (x = 0 there), added linearly (a bound, not a root-sum-square). The
//! trapezoidal rule's own error is not in it: it is negligible at the
//! sampling rates drop towers record at (≥ 50 samples per contact).
use super::motion::{contact_window, G_M_S2};

/// Free-fall samples needed before the contact to find the offset.
pub const MIN_FREE_FALL_SAMPLES: usize = 5;
/// Samples at the start of the record that set the baseline the contact is
/// found against (before the offset is known).
const BASELINE_SAMPLES: usize = 5;

/// What the integration of an accelerometer record leaves uncertain, at
/// the end of the impact (the last sample above the contact threshold).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct IntegrationUncertainty {
    /// Time from contact to the end of the impact, T (s).
    pub contact_s: f64,
    /// The accelerometer's offset found from the free fall and removed (m/s²).
    pub offset_m_s2: f64,
    /// Free-fall samples the offset was found from.
    pub free_fall_samples: usize,
    /// Uncertainty of the removed offset, δa (m/s², 95 %).
    pub offset_uncertainty_m_s2: f64,
    /// The light gate's stated uncertainty, Δv0 (m/s); `None` when not given.
    pub impact_velocity_uncertainty_m_s: Option<f64>,
    /// Δv at the end of the impact (m/s).
    pub velocity_m_s: f64,
    /// Δx at the end of the impact (mm).
    pub displacement_mm: f64,
    /// Of Δx, the contact located to one sample interval: v0·Δt (mm).
    pub contact_timing_mm: f64,
}

impl IntegrationUncertainty {
    /// One clause for reports.
    pub fn describe(&self) -> String {
        let gate = match self.impact_velocity_uncertainty_m_s {
            Some(dv) => format!("light gate ±{dv} m/s"),
            None => "light-gate uncertainty not given (impact_velocity_uncertainty_m_s), counted as 0".to_string(),
        };
        format!(
            "accelerometer offset {:.4} m/s² removed (from {} samples of free fall before contact, ±{:.4} m/s²); \
             {gate}; contact located to one sample (±{:.4} mm); at the end of the impact ({:.2} ms after \
             contact) velocity ±{:.4} m/s, displacement ±{:.4} mm",
            self.offset_m_s2,
            self.free_fall_samples,
            self.offset_uncertainty_m_s2,
            self.contact_timing_mm,
            self.contact_s * 1e3,
            self.velocity_m_s,
            self.displacement_mm
        )
    }
}

/// Why an accelerometer record cannot be integrated.
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// The acceleration's largest excursion from its start is a rise: no
    /// deceleration, so no contact (or the sensor reads deceleration positive).
    NoDeceleration,
    /// Fewer free-fall samples before the contact than the offset needs.
    TooLittleFreeFall { samples: usize },
}

impl Refusal {
    pub fn sentence(&self, column: &str) -> String {
        match self {
            Refusal::NoDeceleration => format!(
                "the acceleration rises rather than falls from its value at the start of the record, so no impact is found; \
                 compression is positive, so the striker's acceleration falls during the impact: if the \
                 accelerometer reads deceleration positive, declare sign = {{ {column} = -1 }}"
            ),
            Refusal::TooLittleFreeFall { samples } => format!(
                "{samples} samples before the contact; the accelerometer's offset is found from the free fall \
                 before it, which needs {MIN_FREE_FALL_SAMPLES} (record with a pre-trigger)"
            ),
        }
    }
}

/// Removes the accelerometer's offset from `accel_m_s2` (so it reads ẍ,
/// g in free fall) and returns the force on the damper, F = m·(g − ẍ),
/// and the uncertainty of integrating it from `v0_m_s` with the light
/// gate's `dv0_m_s`.
pub fn force_from_acceleration(
    time_s: &[f64],
    accel_m_s2: &mut [f64],
    mass_kg: f64,
    v0_m_s: f64,
    dv0_m_s: Option<f64>,
) -> Result<(Vec<f64>, IntegrationUncertainty), Refusal> {
    let n = accel_m_s2.len().min(time_s.len());
    if n == 0 {
        return Err(Refusal::NoDeceleration);
    }
    // The contact is found on the deceleration from the record's start,
    // which needs no offset: whatever the sensor reads in free fall, the
    // impact is where it falls below that.
    let k0 = BASELINE_SAMPLES.min(n);
    let baseline = accel_m_s2[..k0].iter().sum::<f64>() / k0 as f64;
    let deceleration: Vec<f64> = accel_m_s2[..n].iter().map(|a| baseline - a).collect();
    // The impact is the largest excursion; when the largest goes the other
    // way, the sensor reads deceleration positive (or there is no impact).
    let (lo, hi) = deceleration
        .iter()
        .fold((0.0f64, 0.0f64), |(l, h), &d| (l.min(d), h.max(d)));
    if hi <= lo.abs() {
        return Err(Refusal::NoDeceleration);
    }
    let w = contact_window(&deceleration).ok_or(Refusal::NoDeceleration)?;
    let free = &accel_m_s2[..w.contact];
    let free_fall_samples = free.len();
    if free_fall_samples < MIN_FREE_FALL_SAMPLES {
        return Err(Refusal::TooLittleFreeFall {
            samples: free_fall_samples,
        });
    }
    let k = free_fall_samples as f64;
    let mean = free.iter().sum::<f64>() / k;
    let var = free.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / (k - 1.0);
    let offset = mean - G_M_S2;
    let da = 2.0 * (var / k).sqrt();
    accel_m_s2.iter_mut().for_each(|a| *a -= offset);
    let force_n: Vec<f64> = accel_m_s2.iter().map(|a| mass_kg * (G_M_S2 - a)).collect();
    // The end of the impact: the last sample above the contact threshold.
    let last = last_above(&deceleration).max(w.contact);
    let t = time_s[last] - time_s[w.contact];
    let dv0 = dv0_m_s.unwrap_or(0.0);
    let dt = time_s[w.contact + 1] - time_s[w.contact];
    let contact_timing_mm = v0_m_s.abs() * dt * 1e3;
    Ok((
        force_n,
        IntegrationUncertainty {
            contact_s: t,
            offset_m_s2: offset,
            free_fall_samples,
            offset_uncertainty_m_s2: da,
            impact_velocity_uncertainty_m_s: dv0_m_s,
            velocity_m_s: dv0 + da * t,
            displacement_mm: (dv0 * t + 0.5 * da * t * t) * 1e3 + contact_timing_mm,
            contact_timing_mm,
        },
    ))
}

/// The last sample above the contact threshold (`motion::contact_window`'s).
fn last_above(signal: &[f64]) -> usize {
    let peak = signal.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let threshold = super::motion::CONTACT_FRACTION * peak;
    signal.iter().rposition(|&s| s >= threshold).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Free fall reading 0 (a sensor that measures ẍ − g), then a constant
    /// deceleration: the offset found is −g, and F = m·(g − ẍ) is the
    /// constant force that gives that deceleration.
    #[test]
    fn a_sensor_reading_zero_in_free_fall_is_referenced_to_g() {
        let t: Vec<f64> = (0..40).map(|k| k as f64 * 1e-4).collect();
        // 20 samples at 0, then −100 m/s² (ẍ = g − 100 − … read as ẍ − g).
        let mut a: Vec<f64> = (0..40).map(|k| if k < 20 { 0.0 } else { -100.0 }).collect();
        let (f, u) = force_from_acceleration(&t, &mut a, 2.0, 2.0, Some(0.01)).unwrap();
        assert!((u.offset_m_s2 + G_M_S2).abs() < 1e-12, "offset {}", u.offset_m_s2);
        assert_eq!(u.offset_uncertainty_m_s2, 0.0);
        // F = m·(g − ẍ) = 2 kg × 100 m/s² during the impact, 0 in free fall.
        assert!((f[30] - 200.0).abs() < 1e-9 && f[5].abs() < 1e-9, "{} {}", f[30], f[5]);
        // No noise: Δx = Δv0·T + v0·Δt, T from the contact (sample 19) to
        // the last sample (39), Δt = 0.1 ms: 0.01 × 2 ms + 2 × 0.1 ms = 0.22 mm.
        assert!((u.displacement_mm - 0.22).abs() < 1e-12, "{}", u.displacement_mm);
    }

    #[test]
    fn a_record_without_free_fall_or_deceleration_is_refused() {
        let t: Vec<f64> = (0..40).map(|k| k as f64 * 1e-4).collect();
        let mut rising: Vec<f64> = (0..40).map(|k| k as f64).collect();
        assert_eq!(
            force_from_acceleration(&t, &mut rising, 1.0, 2.0, None).unwrap_err(),
            Refusal::NoDeceleration
        );
        let mut early: Vec<f64> = (0..40).map(|k| if k < 3 { 0.0 } else { -50.0 }).collect();
        assert_eq!(
            force_from_acceleration(&t, &mut early, 1.0, 2.0, None).unwrap_err(),
            Refusal::TooLittleFreeFall { samples: 2 }
        );
    }
}
