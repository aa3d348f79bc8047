//! `magnetic_saturation` outside the model class: the field-dependent force
//! grows with the square of the flux density, and the flux saturates with the
//! coil current as a Fröhlich–Kennelly law `B ∝ I/(I_s + I)`. The estimator's
//! saturation term is a different curve; without this effect the gain is
//! linear in current.

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FieldGain {
    /// Gain per ampere at low current (1/A).
    pub per_a: f64,
    /// Fröhlich–Kennelly knee `I_s` (A); `None` = no saturation.
    pub knee_a: Option<f64>,
}

impl FieldGain {
    /// The factor on the base force at coil current `current_a`.
    pub fn gain(&self, current_a: f64) -> f64 {
        let i = current_a.max(0.0);
        match self.knee_a {
            None => 1.0 + self.per_a * i,
            // b = I/(I_s + I); 2b − b² has slope 2/I_s at 0, so the factor
            // I_s/2 keeps the low-current slope per_a.
            Some(k) => {
                let b = i / (k + i);
                1.0 + self.per_a * 0.5 * k * (2.0 * b - b * b)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saturating_gain_by_hand() {
        let g = FieldGain {
            per_a: 2.0,
            knee_a: Some(1.0),
        };
        // I = 1 A: b = 1/2, 2b − b² = 0.75, gain = 1 + 2·0.5·0.75 = 1.75 (linear: 3).
        assert!((g.gain(1.0) - 1.75).abs() < 1e-12);
        // Small I: slope per_a = 2 (d/dI of 2b − b² at 0 is 2/I_s, × per_a·I_s/2).
        let h = 1e-6;
        assert!(((g.gain(h) - 1.0) / h - 2.0).abs() < 1e-4);
        // Far above the knee the gain tends to 1 + per_a·I_s/2 = 2.
        assert!((g.gain(1e6) - 2.0).abs() < 1e-5);
    }
}
