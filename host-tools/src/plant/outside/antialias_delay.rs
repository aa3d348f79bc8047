//! `sensor_delay` outside the model class: the force channel passes an
//! anti-aliasing filter (second-order Butterworth, bilinear transform with
//! pre-warping on the fine simulation grid) and then a transport delay that is
//! a fraction of a sample of the recording (linear interpolation on the fine
//! grid). The estimator shifts the recording by a whole searched delay; here
//! the delay is fractional and the filter adds frequency-dependent lag.
use std::f64::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AntiAliasDelay {
    /// Butterworth cut-off (Hz).
    pub cutoff_hz: f64,
    /// Transport delay after the filter (s), any real value ≥ 0.
    pub delay_s: f64,
}

impl AntiAliasDelay {
    /// The channel sampled every `dt_s` after the filter and the delay. The
    /// filter starts in steady state at the first value; before the delay
    /// has elapsed the output holds that value.
    pub fn apply(&self, y: &[f64], dt_s: f64) -> Vec<f64> {
        let filtered = butterworth2(y, self.cutoff_hz, dt_s);
        let shift = self.delay_s / dt_s;
        (0..filtered.len())
            .map(|k| {
                let pos = k as f64 - shift;
                if pos <= 0.0 {
                    return filtered[0];
                }
                let i = pos.floor() as usize;
                let frac = pos - i as f64;
                let next = filtered.get(i + 1).copied().unwrap_or(filtered[i]);
                filtered[i] + frac * (next - filtered[i])
            })
            .collect()
    }

    /// Low-frequency lag of filter and delay together: the Butterworth's
    /// group delay at DC is `√2/ω_c`.
    pub fn dc_lag_s(&self) -> f64 {
        std::f64::consts::SQRT_2 / (2.0 * PI * self.cutoff_hz) + self.delay_s
    }
}

/// Second-order Butterworth low-pass, bilinear with pre-warping.
pub fn butterworth2(y: &[f64], cutoff_hz: f64, dt_s: f64) -> Vec<f64> {
    let Some(&first) = y.first() else {
        return Vec::new();
    };
    let k = (PI * cutoff_hz * dt_s).tan();
    let q = std::f64::consts::FRAC_1_SQRT_2;
    let norm = 1.0 / (1.0 + k / q + k * k);
    let b0 = k * k * norm;
    let (b1, b2) = (2.0 * b0, b0);
    let a1 = 2.0 * (k * k - 1.0) * norm;
    let a2 = (1.0 - k / q + k * k) * norm;
    let (mut x1, mut x2, mut y1, mut y2) = (first, first, first, first);
    y.iter()
        .map(|&x0| {
            let y0 = b0 * x0 + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
            (x2, x1, y2, y1) = (x1, x0, y1, y0);
            y0
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ramp_comes_out_late_by_the_group_delay_plus_the_delay() {
        // A slow ramp through a 2nd-order Butterworth lags by √2/ω_c at DC
        // (the s¹ coefficient of 1/(1 + √2 s/ω + s²/ω²)); the delay adds τ.
        let f = AntiAliasDelay {
            cutoff_hz: 50.0,
            delay_s: 0.00237,
        };
        let dt = 1e-4;
        let ramp: Vec<f64> = (0..20_000).map(|k| k as f64 * dt).collect();
        let out = f.apply(&ramp, dt);
        let lag = ramp[19_999] - out[19_999];
        let by_hand = 2f64.sqrt() / (2.0 * PI * 50.0) + 0.00237; // 0.0045016 + 0.00237
        assert!((lag - by_hand).abs() < 2e-6, "lag {lag} s, by hand {by_hand} s");
        assert!((f.dc_lag_s() - by_hand).abs() < 1e-12);
    }

    #[test]
    fn a_constant_passes_unchanged() {
        let out = butterworth2(&[3.0; 100], 10.0, 1e-3);
        assert!(out.iter().all(|v| (v - 3.0).abs() < 1e-12));
    }
}
