//! What drives each test: a sinusoid, a random band-limited multisine (random
//! phases, flat amplitude spectrum) or a drop impact (a mass falling onto the
//! specimen, integrated against the plant's force, `ẍ = g − F/m`).
use rand::Rng;
use std::f64::consts::PI;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Excitation {
    Sine {
        amplitude_mm: f64,
        frequency_hz: f64,
        cycles: f64,
    },
    Multisine {
        /// (frequency Hz, amplitude mm, phase rad) of each component.
        components: Vec<(f64, f64, f64)>,
        duration_s: f64,
    },
    Drop {
        mass_kg: f64,
        impact_velocity_m_s: f64,
    },
}

impl Excitation {
    /// A multisine of `n` components log-spaced over `[f_lo, f_hi]` with
    /// random phases, scaled to peak near `peak_mm`.
    pub fn multisine(peak_mm: f64, f_lo_hz: f64, f_hi_hz: f64, n: usize, duration_s: f64, rng: &mut impl Rng) -> Self {
        let components: Vec<(f64, f64, f64)> = (0..n)
            .map(|i| {
                let f = f_lo_hz * (f_hi_hz / f_lo_hz).powf(i as f64 / (n.max(2) - 1) as f64);
                // Equal velocity per component keeps the speed range of a sine.
                (f, f_lo_hz / f, rng.random_range(0.0..2.0 * PI))
            })
            .collect();
        let raw_peak: f64 = components.iter().map(|c| c.1).sum();
        Excitation::Multisine {
            components: components
                .iter()
                .map(|&(f, a, p)| (f, a * peak_mm / raw_peak, p))
                .collect(),
            duration_s,
        }
    }

    /// Prescribed displacement (mm) and velocity (mm/s) at `t_s`; `None` for a drop.
    pub fn prescribed(&self, t_s: f64) -> Option<(f64, f64)> {
        match self {
            Excitation::Sine {
                amplitude_mm,
                frequency_hz,
                ..
            } => {
                let w = 2.0 * PI * frequency_hz;
                Some((amplitude_mm * (w * t_s).sin(), amplitude_mm * w * (w * t_s).cos()))
            }
            Excitation::Multisine { components, .. } => {
                Some(components.iter().fold((0.0, 0.0), |(x, v), &(f, a, p)| {
                    let w = 2.0 * PI * f;
                    (x + a * ((w * t_s + p).sin() - p.sin()), v + a * w * (w * t_s + p).cos())
                }))
            }
            Excitation::Drop { .. } => None,
        }
    }

    /// Length of a prescribed test (a drop ends when the mass leaves).
    pub fn duration_s(&self) -> f64 {
        match self {
            Excitation::Sine {
                frequency_hz, cycles, ..
            } => cycles / frequency_hz,
            Excitation::Multisine { duration_s, .. } => *duration_s,
            Excitation::Drop { .. } => 0.2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn a_sine_by_hand() {
        let s = Excitation::Sine {
            amplitude_mm: 2.0,
            frequency_hz: 1.0,
            cycles: 3.0,
        };
        // t = 1/4 s: x = 2 mm, v = 0; duration 3 s.
        let (x, v) = s.prescribed(0.25).unwrap();
        assert!((x - 2.0).abs() < 1e-12 && v.abs() < 1e-9);
        assert_eq!(s.duration_s(), 3.0);
    }

    #[test]
    fn a_multisine_starts_at_rest_position_and_stays_within_its_peak() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let m = Excitation::multisine(5.0, 0.5, 5.0, 6, 4.0, &mut rng);
        assert_eq!(m.prescribed(0.0).unwrap().0, 0.0);
        // |x| ≤ Σ a·(|sin| + |sin p|) ≤ 2·peak.
        assert!((0..4000).all(|k| m.prescribed(k as f64 * 1e-3).unwrap().0.abs() <= 10.0 + 1e-9));
    }
}
