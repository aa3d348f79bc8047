//! Quartics in the paper's layout (`[a1, …, a5]`, highest power first, x in
//! mm) and their change of variable to u = (x − centre)/scale, which keeps
//! the fits and the moment form well conditioned (x⁴ at 25 mm is 4·10⁵).

/// Horner evaluation of a highest-power-first quartic.
#[inline]
pub fn eval(c: &[f64; 5], x: f64) -> f64 {
    (((c[0] * x + c[1]) * x + c[2]) * x + c[3]) * x + c[4]
}

/// The affine map x = centre + scale·u that sends [x_min, x_max] to [−1, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scaling {
    pub centre_mm: f64,
    pub scale_mm: f64,
}

impl Scaling {
    pub fn for_range(x_min_mm: f64, x_max_mm: f64) -> Scaling {
        let half = 0.5 * (x_max_mm - x_min_mm);
        Scaling {
            centre_mm: 0.5 * (x_max_mm + x_min_mm),
            scale_mm: if half > 0.0 { half } else { 1.0 },
        }
    }

    pub fn for_samples(x_mm: &[f64]) -> Scaling {
        let (lo, hi) = min_max(x_mm);
        Scaling::for_range(lo, hi)
    }

    #[inline]
    pub fn u(&self, x_mm: f64) -> f64 {
        (x_mm - self.centre_mm) / self.scale_mm
    }

    /// Raw coefficients (highest first, in x) → coefficients in u (highest first):
    /// p(centre + scale·u) expanded by the binomial theorem.
    pub fn raw_to_scaled(&self, raw: &[f64; 5]) -> [f64; 5] {
        let (m, s) = (self.centre_mm, self.scale_mm);
        let a = ascending(raw);
        let mut c = [0.0; 5];
        for (k, ck) in c.iter_mut().enumerate() {
            let mut sum = 0.0;
            for (j, aj) in a.iter().enumerate().skip(k) {
                sum += aj * binomial(j, k) * m.powi((j - k) as i32);
            }
            *ck = sum * s.powi(k as i32);
        }
        ascending(&c)
    }

    /// Coefficients in u (highest first) → raw coefficients in x (highest
    /// first): q((x − centre)/scale) expanded by the binomial theorem.
    pub fn scaled_to_raw(&self, scaled: &[f64; 5]) -> [f64; 5] {
        let (m, s) = (self.centre_mm, self.scale_mm);
        let c = ascending(scaled);
        let mut a = [0.0; 5];
        for (k, ck) in c.iter().enumerate() {
            // ck·((x − m)/s)^k = ck/s^k · Σ_j C(k, j) x^j (−m)^(k−j)
            let f = ck / s.powi(k as i32);
            for (j, aj) in a.iter_mut().enumerate().take(k + 1) {
                *aj += f * binomial(k, j) * (-m).powi((k - j) as i32);
            }
        }
        ascending(&a)
    }
}

/// Reverses between highest-first and ascending-power order.
fn ascending(c: &[f64; 5]) -> [f64; 5] {
    [c[4], c[3], c[2], c[1], c[0]]
}

fn binomial(n: usize, k: usize) -> f64 {
    const ROWS: [[f64; 5]; 5] = [
        [1.0, 0.0, 0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0, 0.0, 0.0],
        [1.0, 2.0, 1.0, 0.0, 0.0],
        [1.0, 3.0, 3.0, 1.0, 0.0],
        [1.0, 4.0, 6.0, 4.0, 1.0],
    ];
    ROWS[n][k]
}

/// (min, max) of a non-empty slice; (0, 0) if empty.
pub fn min_max(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
        (lo.min(x), hi.max(x))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn change_of_variable_round_trips_and_preserves_values() {
        let s = Scaling::for_range(-3.0, 7.0); // centre 2, scale 5
        let raw = [1.5, -2.0, 0.25, 3.0, -7.0];
        let scaled = s.raw_to_scaled(&raw);
        for x in [-3.0, 0.0, 1.3, 7.0] {
            assert!((eval(&raw, x) - eval(&scaled, s.u(x))).abs() < 1e-9);
        }
        let back = s.scaled_to_raw(&scaled);
        for (a, b) in raw.iter().zip(&back) {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
        // By hand: p(x) = x with centre 2, scale 5 → q(u) = 2 + 5u.
        assert_eq!(s.raw_to_scaled(&[0.0, 0.0, 0.0, 1.0, 0.0]), [0.0, 0.0, 0.0, 5.0, 2.0]);
    }
}
