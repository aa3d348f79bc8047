//! Velocity from displacement samples, for boards without a velocity sensor.
//!
//! An alpha-beta filter at a fixed period `T`:
//! predict `x̂ ← x̂ + v̂·T`, then correct with the residual `r = z − x̂`:
//! `x̂ ← x̂ + α·r`, `v̂ ← v̂ + (β/T)·r`.
//!
//! Properties (Kalata 1984; Benedict & Bordner 1962), for white position
//! noise of standard deviation σ:
//! - velocity noise: `σ_v = σ/T · sqrt(2β² / (α(4 − 2α − β)))`;
//! - lag: a constant velocity is tracked with zero steady-state error; a
//!   constant acceleration `a` leaves a velocity error of `a·T·(α/β − 1/2)`
//!   and a position lag of `a·T²·(1 − α)/β`.
//!
//! [`AlphaBeta::benedict_bordner`] picks `β = α²/(2 − α)`, the optimal pair
//! for a ramp with noise.
use crate::flags::Flags;
use micromath::F32Ext;

/// Samples beyond ±10 m cannot come from a damper; they are rejected.
pub const MAX_ABS_X_MM: f32 = 1.0e4;

fn clamp_finite(x_mm: f32) -> f32 {
    crate::math::clamp(x_mm, -MAX_ABS_X_MM, MAX_ABS_X_MM)
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaBeta {
    alpha: f32,
    beta: f32,
    period_s: f32,
    /// Precomputed per-period factors (no divide on the hot path): mm moved
    /// per m/s in one period, and the velocity gain `β/T` per mm of residual.
    period_mm_per_m_s: f32,
    v_gain_per_mm_s: f32,
    x_mm: f32,
    v_m_s: f32,
    primed: bool,
}

impl AlphaBeta {
    /// Gains outside the stable region (0 < α ≤ 1, 0 < β < 4 − 2α) or a
    /// non-positive period fall back to `benedict_bordner(1e-4, 0.2)`.
    pub fn new(period_s: f32, alpha: f32, beta: f32) -> Self {
        let stable = alpha > 0.0 && alpha <= 1.0 && beta > 0.0 && beta < 4.0 - 2.0 * alpha;
        let (period_s, alpha, beta) = if stable && period_s.is_finite() && period_s > 0.0 {
            (period_s, alpha, beta)
        } else {
            (1.0e-4, 0.2, 0.2 * 0.2 / 1.8)
        };
        Self {
            alpha,
            beta,
            period_s,
            period_mm_per_m_s: period_s * 1.0e3,
            v_gain_per_mm_s: beta * 1.0e-3 / period_s,
            x_mm: 0.0,
            v_m_s: 0.0,
            primed: false,
        }
    }

    /// `β = α²/(2 − α)`.
    pub fn benedict_bordner(period_s: f32, alpha: f32) -> Self {
        Self::new(period_s, alpha, alpha * alpha / (2.0 - alpha))
    }

    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    pub fn beta(&self) -> f32 {
        self.beta
    }

    /// Ratio σ_v / σ_x in 1/s (multiply by the position noise in m).
    pub fn velocity_noise_gain_per_s(&self) -> f32 {
        let (a, b) = (self.alpha, self.beta);
        crate::math::sqrt_precise(2.0 * b * b / (a * (4.0 - 2.0 * a - b))) / self.period_s
    }

    /// Velocity error (m/s) under a constant acceleration `a_m_s2`.
    pub fn velocity_lag_m_s(&self, a_m_s2: f32) -> f32 {
        a_m_s2 * self.period_s * (self.alpha / self.beta - 0.5)
    }

    /// Restarts from a known state (e.g. at first contact).
    /// Non-finite values restart from zero.
    pub fn reset(&mut self, x_mm: f32, v_m_s: f32) {
        self.x_mm = if x_mm.is_finite() { clamp_finite(x_mm) } else { 0.0 };
        self.v_m_s = if v_m_s.is_finite() { v_m_s } else { 0.0 };
        self.primed = true;
    }

    /// Feeds one displacement sample; returns the velocity estimate (m/s).
    /// A non-finite sample, or one beyond ±`MAX_ABS_X_MM`, is skipped
    /// (prediction only) and flagged, so the estimate stays finite.
    #[inline]
    pub fn update(&mut self, z_mm: f32) -> (f32, Flags) {
        // One comparison on the hot path (false for NaN and ±inf); which
        // fault it is only matters when there is one.
        let plausible = F32Ext::abs(z_mm) <= MAX_ABS_X_MM;
        if !plausible {
            let flags = if z_mm.is_finite() {
                Flags::SENSOR_RANGE
            } else {
                Flags::NON_FINITE_INPUT
            };
            if self.primed {
                self.x_mm = clamp_finite(self.x_mm + self.v_m_s * self.period_mm_per_m_s);
            }
            return (self.v_m_s, flags);
        }
        if !self.primed {
            // `reset(z_mm, 0.0)` without its checks: z is finite and within
            // ±MAX_ABS_X_MM here (the first period of every impact runs this).
            self.x_mm = z_mm;
            self.v_m_s = 0.0;
            self.primed = true;
            return (0.0, Flags::NONE);
        }
        let predicted_mm = self.x_mm + self.v_m_s * self.period_mm_per_m_s;
        let residual_mm = z_mm - predicted_mm;
        self.x_mm = predicted_mm + self.alpha * residual_mm;
        self.v_m_s += self.v_gain_per_mm_s * residual_mm;
        (self.v_m_s, Flags::NONE)
    }

    pub fn position_mm(&self) -> f32 {
        self.x_mm
    }

    #[inline]
    pub fn velocity_m_s(&self) -> f32 {
        self.v_m_s
    }
}
