//! Motion of a drop record that has no displacement column
//! (docs/dataset-format.md, "Force–time drop records").
//!
//! An instrumented drop tower records force (and maybe the striker's
//! acceleration) against time. Velocity and displacement follow from the
//! impulse–momentum method of ISO 6603-2 / ASTM D7136, positive compressing:
//!
//! v(t) = v0 + g·(t − t_c) − (1/m)·∫F dt,   x(t) = ∫v dt,   x(t_c) = 0,
//!
//! or v(t) = v0 + ∫a dt from a striker accelerometer (it reads ẍ, so gravity
//! is in it already). Integration is trapezoidal on the samples as recorded.
//! The contact t_c is where the force rises from zero towards the first
//! sample above [`CONTACT_FRACTION`] of its peak; the record is trimmed to
//! [`PRE_TRIGGER_SAMPLES`] samples before the contact and after the last
//! sample above that threshold.
//!
//! Errors grow with time from contact: a load-cell offset δF gives
//! Δx = δF·t²/(2m), an impact-velocity error Δv0 gives Δx = Δv0·t
//! (the drift study in host-tools/tests/integration/dataset_motion.rs measures both).

/// Standard gravity (m/s²), as the drop simulator uses.
pub const G_M_S2: f64 = 9.81;
/// Force threshold for contact, as a share of the record's peak force.
pub const CONTACT_FRACTION: f64 = 0.02;
/// Samples kept before the contact and after the last sample above the threshold.
pub const PRE_TRIGGER_SAMPLES: usize = 10;

/// What the motion of a recording was derived from.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionSource {
    /// v = v0 + g·t − (1/m)∫F dt.
    Force { mass_kg: f64, impact_velocity_m_s: f64 },
    /// v = v0 + ∫a dt.
    Acceleration { impact_velocity_m_s: f64 },
    /// No force column: F = m·(g − a) and v = v0 + ∫a dt, the accelerometer's
    /// offset removed (`super::accelerometer`).
    Accelerometer {
        mass_kg: f64,
        impact_velocity_m_s: f64,
        uncertainty: super::accelerometer::IntegrationUncertainty,
    },
}

impl MotionSource {
    /// One sentence for reports.
    pub fn describe(&self) -> String {
        match self {
            MotionSource::Force {
                mass_kg,
                impact_velocity_m_s,
            } => format!(
                "velocity and displacement integrated from force (ISO 6603-2: m = {mass_kg} kg, \
                 v0 = {impact_velocity_m_s} m/s, g = {G_M_S2} m/s²)"
            ),
            MotionSource::Acceleration { impact_velocity_m_s } => format!(
                "velocity and displacement integrated from the striker acceleration (v0 = {impact_velocity_m_s} m/s)"
            ),
            MotionSource::Accelerometer {
                mass_kg,
                impact_velocity_m_s,
                uncertainty,
            } => format!(
                "force F = m·(g − a) and velocity and displacement integrated from the striker accelerometer \
                 (ISO 6603-2 read backwards: m = {mass_kg} kg, v0 = {impact_velocity_m_s} m/s, g = {G_M_S2} m/s²); {}",
                uncertainty.describe()
            ),
        }
    }
}

/// The samples of a record kept around its contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactWindow {
    /// First sample kept.
    pub start: usize,
    /// The contact sample (x = 0, v = v0).
    pub contact: usize,
    /// One past the last sample kept.
    pub end: usize,
}

/// Finds the contact in a force record; `None` when no force is positive.
pub fn contact_window(force_n: &[f64]) -> Option<ContactWindow> {
    let peak = force_n.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if peak <= 0.0 {
        return None;
    }
    let threshold = CONTACT_FRACTION * peak;
    let first = force_n.iter().position(|&f| f >= threshold)?;
    let last = force_n.iter().rposition(|&f| f >= threshold)?;
    // Back down the rising edge to where the force left zero.
    let mut contact = first;
    while contact > 0 && force_n[contact - 1] > 0.0 && force_n[contact - 1] < force_n[contact] {
        contact -= 1;
    }
    if contact > 0 && force_n[contact] > 0.0 {
        contact -= 1;
    }
    Some(ContactWindow {
        start: contact.saturating_sub(PRE_TRIGGER_SAMPLES),
        contact,
        end: (last + 1 + PRE_TRIGGER_SAMPLES).min(force_n.len()),
    })
}

/// Velocity (m/s) and displacement (mm) from the acceleration `a` (m/s²)
/// at each sample, with v = v0 and x = 0 at sample `contact` (trapezoidal,
/// forwards and backwards from the contact).
pub fn integrate(time_s: &[f64], accel_m_s2: &[f64], contact: usize, v0_m_s: f64) -> (Vec<f64>, Vec<f64>) {
    let n = time_s.len();
    let mut v = vec![0.0; n];
    let mut x_mm = vec![0.0; n];
    if contact >= n {
        return (v, x_mm);
    }
    v[contact] = v0_m_s;
    for i in contact + 1..n {
        let dt = time_s[i] - time_s[i - 1];
        v[i] = v[i - 1] + dt * 0.5 * (accel_m_s2[i] + accel_m_s2[i - 1]);
        x_mm[i] = x_mm[i - 1] + dt * 0.5 * (v[i] + v[i - 1]) * 1e3;
    }
    for i in (0..contact).rev() {
        let dt = time_s[i + 1] - time_s[i];
        v[i] = v[i + 1] - dt * 0.5 * (accel_m_s2[i] + accel_m_s2[i + 1]);
        x_mm[i] = x_mm[i + 1] - dt * 0.5 * (v[i] + v[i + 1]) * 1e3;
    }
    (v, x_mm)
}

/// The striker's acceleration from the force on it: a = g − F/m.
pub fn accel_from_force(force_n: &[f64], mass_kg: f64) -> Vec<f64> {
    force_n.iter().map(|f| G_M_S2 - f / mass_kg).collect()
}

/// Trims `samples` to the contact window of its force and fills in
/// velocity and displacement from `source`. `None` when the force is never
/// positive (no contact to find).
pub fn derive_motion(samples: &mut super::Samples, source: MotionSource) -> Option<ContactWindow> {
    let w = contact_window(&samples.force_n)?;
    let cut = |c: &mut Vec<f64>| {
        c.truncate(w.end);
        c.drain(..w.start);
    };
    cut(&mut samples.time_s);
    cut(&mut samples.force_n);
    for c in [
        &mut samples.accel_m_s2,
        &mut samples.current_a,
        &mut samples.temperature_c,
    ]
    .into_iter()
    .flatten()
    {
        cut(c);
    }
    let contact = w.contact - w.start;
    let (accel, v0) = match source {
        MotionSource::Force {
            mass_kg,
            impact_velocity_m_s,
        } => (accel_from_force(&samples.force_n, mass_kg), impact_velocity_m_s),
        MotionSource::Acceleration { impact_velocity_m_s }
        | MotionSource::Accelerometer {
            impact_velocity_m_s, ..
        } => (samples.accel_m_s2.clone().unwrap_or_default(), impact_velocity_m_s),
    };
    let (v, x) = integrate(&samples.time_s, &accel, contact, v0);
    samples.v_m_s = v;
    samples.x_mm = x;
    Some(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Constant force F on mass m from v0: closed form v = v0 + (g − F/m)t,
    /// x = v0 t + (g − F/m)t²/2, which the trapezoidal rule integrates exactly.
    #[test]
    fn constant_force_integrates_to_the_closed_form() {
        let t: Vec<f64> = (0..101).map(|k| k as f64 * 1e-4).collect();
        let a = accel_from_force(&vec![1000.0; 101], 5.5);
        let (v, x) = integrate(&t, &a, 0, 2.24);
        let a0 = 9.81 - 1000.0 / 5.5;
        let tn = t[100];
        assert!((v[100] - (2.24 + a0 * tn)).abs() < 1e-12);
        assert!((x[100] - (2.24 * tn + 0.5 * a0 * tn * tn) * 1e3).abs() < 1e-9);
    }

    #[test]
    fn contact_keeps_pre_trigger_samples_and_trims_the_tail() {
        // 30 zeros, a half-sine of 50 samples, 40 zeros.
        let mut f = vec![0.0; 30];
        f.extend((1..50).map(|k| 1000.0 * (std::f64::consts::PI * k as f64 / 50.0).sin()));
        f.extend(vec![0.0; 41]);
        let w = contact_window(&f).unwrap();
        assert_eq!(w.contact, 29, "the last zero before the rise");
        assert_eq!(w.start, 19);
        // The last sample above 2 % of the peak is 78 (k = 49: sin(π·49/50) = 0.063).
        assert_eq!(w.end, 78 + 1 + PRE_TRIGGER_SAMPLES);
        assert_eq!(contact_window(&[0.0, -1.0, -3.0]), None);
    }
}
