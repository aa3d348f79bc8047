//! `hysteresis_memory` outside the model class: a Prandtl–Ishlinskii
//! operator, a weighted sum of play (backlash) operators of radii r_i — rate
//! independent, with the turn-around memory of every reversal, and not the
//! Dahl or Bouc–Wen equations the other calibration laws use.

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PrandtlIshlinskii {
    /// (radius mm, weight N/mm) of each play operator.
    pub plays: Vec<(f64, f64)>,
}

impl PrandtlIshlinskii {
    /// Advances the play outputs `y` (mm) to `x_mm` and returns the force (N).
    pub fn step_n(&self, y: &mut [f64], x_mm: f64) -> f64 {
        self.plays
            .iter()
            .zip(y.iter_mut())
            .map(|(&(r, w), yi)| {
                *yi = play(*yi, x_mm, r);
                w * *yi
            })
            .sum()
    }
}

/// One play operator: the output follows x at distance r, and holds inside.
pub fn play(y_prev: f64, x: f64, r: f64) -> f64 {
    (x - r).max((x + r).min(y_prev))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_play_follows_by_hand() {
        // r = 1 from y = 0: x = 3 → 2; back to x = 1 → holds 2; x = −1 → 0.
        let mut y = 0.0;
        for (x, want) in [(3.0, 2.0), (1.0, 2.0), (-1.0, 0.0)] {
            y = play(y, x, 1.0);
            assert_eq!(y, want);
        }
    }

    #[test]
    fn the_force_is_the_weighted_sum() {
        let pi = PrandtlIshlinskii {
            plays: vec![(0.0, 10.0), (1.0, 5.0)],
        };
        let mut y = [0.0, 0.0];
        // x = 3: 10·3 + 5·2 = 40 N.
        assert_eq!(pi.step_n(&mut y, 3.0), 40.0);
    }
}
