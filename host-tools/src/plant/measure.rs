//! The instrument: what a recording holds is what the sensors report (noise,
//! quantisation, the sampling grid), never the simulator's internal state.
use rand::Rng;
use rand_distr::{Distribution, Normal};
use serde::Serialize;

/// Noise (1 σ) and resolution of each channel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasurementModel {
    /// Time between recorded samples (s).
    pub sample_period_s: f64,
    pub force_noise_n: f64,
    pub x_noise_mm: f64,
    pub v_noise_m_s: f64,
    /// Quantisation steps (one ADC count).
    pub force_lsb_n: f64,
    pub x_lsb_mm: f64,
    pub v_lsb_m_s: f64,
}

impl Default for MeasurementModel {
    /// 20 kHz; a 16-bit load cell channel over ±25 kN, a 16-bit displacement
    /// transducer over 50 mm and a velocity channel over ±10 m/s.
    fn default() -> Self {
        Self {
            sample_period_s: 50.0e-6,
            force_noise_n: 8.0,
            x_noise_mm: 0.008,
            v_noise_m_s: 0.002,
            force_lsb_n: 50_000.0 / 65_536.0,
            x_lsb_mm: 50.0 / 65_536.0,
            v_lsb_m_s: 20.0 / 65_536.0,
        }
    }
}

impl MeasurementModel {
    /// A perfect instrument (same sampling grid, no noise, no quantisation).
    pub fn ideal(&self) -> Self {
        Self {
            sample_period_s: self.sample_period_s,
            force_noise_n: 0.0,
            x_noise_mm: 0.0,
            v_noise_m_s: 0.0,
            force_lsb_n: 0.0,
            x_lsb_mm: 0.0,
            v_lsb_m_s: 0.0,
        }
    }

    pub fn validate(&self) -> anyhow::Result<()> {
        let all = [
            self.force_noise_n,
            self.x_noise_mm,
            self.v_noise_m_s,
            self.force_lsb_n,
            self.x_lsb_mm,
            self.v_lsb_m_s,
        ];
        anyhow::ensure!(
            all.iter().all(|v| v.is_finite() && *v >= 0.0),
            "noise and quantisation must be finite and ≥ 0"
        );
        anyhow::ensure!(
            self.sample_period_s.is_finite() && self.sample_period_s > 0.0,
            "sample period must be positive"
        );
        Ok(())
    }

    /// One reading: true value + Gaussian noise, rounded to the ADC step.
    pub fn read(value: f64, noise: f64, lsb: f64, rng: &mut impl Rng) -> f64 {
        let noisy = if noise > 0.0 {
            // σ > 0 and finite was validated, so Normal::new cannot fail.
            Normal::new(value, noise).map_or(value, |d| d.sample(rng))
        } else {
            value
        };
        if lsb > 0.0 {
            (noisy / lsb).round() * lsb
        } else {
            noisy
        }
    }
}
