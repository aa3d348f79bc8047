//! Velocity estimated from displacement, as a rig without a velocity channel
//! records it: the displacement quantised to the transducer's resolution, then
//! a central difference. The estimator otherwise reads an exact velocity.

/// Central-difference velocity (m/s) of `x_mm` sampled every `dt_s`, after
/// quantising x to `resolution_mm` (0 = none); one-sided at the ends.
pub fn from_displacement(x_mm: &[f64], dt_s: f64, resolution_mm: f64) -> Vec<f64> {
    let q: Vec<f64> = x_mm
        .iter()
        .map(|&x| {
            if resolution_mm > 0.0 {
                (x / resolution_mm).round() * resolution_mm
            } else {
                x
            }
        })
        .collect();
    let n = q.len();
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n.saturating_sub(1)));
            if b == a {
                0.0
            } else {
                (q[b] - q[a]) / ((b - a) as f64 * dt_s) / 1000.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn central_difference_is_exact_on_a_parabola() {
        // x = 1000·t² mm, so v = 2t m/s; a central difference is exact on t².
        let dt = 1e-3;
        let x: Vec<f64> = (0..50).map(|k| 1000.0 * (k as f64 * dt).powi(2)).collect();
        let v = from_displacement(&x, dt, 0.0);
        assert!((v[20] - 2.0 * 20.0 * dt).abs() < 1e-9);
    }

    #[test]
    fn quantisation_shows_as_steps() {
        // 0.01 mm resolution, x = 0.004 k mm: the quantised x is 0,0,0.01,0.01,0.02 …
        let x: Vec<f64> = (0..6).map(|k| 0.004 * k as f64).collect();
        let v = from_displacement(&x, 1e-3, 0.01);
        // k = 1: (x₂ − x₀)/2 ms = 0.01 mm / 2 ms = 5 mm/s = 0.005 m/s.
        assert!((v[1] - 0.005).abs() < 1e-12);
    }
}
