//! `end_stop` outside the model class: a Hunt–Crossley contact (Hunt &
//! Crossley 1975) with finite stiffness and damping, `F = k·δⁿ·(1 + α·δ̇)`,
//! δ the penetration past the stop. The force never pulls (`F ≥ 0`): the
//! contact separates faster than it relaxes. The estimator's stop is
//! `k_e(I)·max(0, x − x_e)²` per current with no damping; this one is one
//! contact shared across currents with a Hertzian exponent and damping.

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct HuntCrossley {
    /// Where contact starts (mm of compression).
    pub x_stop_mm: f64,
    /// `k` in N/mmⁿ.
    pub k_n_per_mm_n: f64,
    /// Hertzian exponent (1.5 for a sphere on a flat).
    pub exponent: f64,
    /// `α` in s/mm: damping per unit penetration rate.
    pub alpha_s_per_mm: f64,
}

impl HuntCrossley {
    /// Contact force (N, compression positive) at `x_mm` moving at `v_mm_s`.
    pub fn force_n(&self, x_mm: f64, v_mm_s: f64) -> f64 {
        let delta = x_mm - self.x_stop_mm;
        if delta <= 0.0 {
            return 0.0;
        }
        (self.k_n_per_mm_n * delta.powf(self.exponent) * (1.0 + self.alpha_s_per_mm * v_mm_s)).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: HuntCrossley = HuntCrossley {
        x_stop_mm: 4.0,
        k_n_per_mm_n: 100.0,
        exponent: 1.5,
        alpha_s_per_mm: 0.02,
    };

    #[test]
    fn static_force_is_hertzian() {
        // δ = 0.5 mm at rest: 100 · 0.5^1.5 = 100 · 0.353553 = 35.3553 N.
        assert!((C.force_n(4.5, 0.0) - 35.3553).abs() < 1e-3);
        assert_eq!(C.force_n(3.9, 100.0), 0.0);
    }

    #[test]
    fn damping_adds_on_approach_and_never_pulls() {
        // Approaching at 10 mm/s: × (1 + 0.02·10) = 1.2 → 42.4264 N.
        assert!((C.force_n(4.5, 10.0) - 42.4264).abs() < 1e-3);
        // Separating at 100 mm/s: 1 − 2 < 0, clipped to no force.
        assert_eq!(C.force_n(4.5, -100.0), 0.0);
    }
}
