//! `stress_softening` outside the model class: Mullins-type damage. Within a
//! test, the Ogden–Roxburgh pseudo-elastic factor (Ogden & Roxburgh 1999, with
//! tanh in place of erf as Dorfmann & Ogden use): below the largest strain
//! energy reached so far, the elastic force is softened by
//! `η = 1 − tanh((W_max − W)/m)/r`. Across the run, each completed cycle adds
//! damage that saturates, `d(N) = d_∞·(1 − e^{−N/N₀})`, N counted over every
//! test in run order. The estimator fits a per-test gain law in run order; this
//! one softens within each cycle as well, and by strain history.

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Mullins {
    /// Ogden–Roxburgh `r` (> 1; larger = less softening).
    pub r: f64,
    /// Ogden–Roxburgh `m`, in the units of W (mm²).
    pub m_mm2: f64,
    /// Saturated cumulative damage `d_∞` (share of the elastic force).
    pub d_inf: f64,
    /// Cycles over which the cumulative damage grows, `N₀`.
    pub n0_cycles: f64,
}

/// The damage state carried through the run.
#[derive(Clone, Copy, Debug, Default)]
pub struct MullinsState {
    /// Largest `W = x²/2` (mm²) reached so far in the run.
    pub w_max_mm2: f64,
    /// Completed cycles so far in the run.
    pub cycles: f64,
}

impl Mullins {
    /// The factor on the elastic force at displacement `x_mm`, updating the state.
    pub fn factor(&self, state: &mut MullinsState, x_mm: f64) -> f64 {
        let w = 0.5 * x_mm * x_mm;
        state.w_max_mm2 = state.w_max_mm2.max(w);
        let eta = 1.0 - ((state.w_max_mm2 - w) / self.m_mm2).tanh() / self.r;
        eta * (1.0 - self.cumulative_damage(state.cycles))
    }

    /// `d(N) = d_∞·(1 − e^{−N/N₀})`.
    pub fn cumulative_damage(&self, cycles: f64) -> f64 {
        self.d_inf * (1.0 - (-cycles / self.n0_cycles).exp())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const M: Mullins = Mullins {
        r: 2.0,
        m_mm2: 1.0,
        d_inf: 0.2,
        n0_cycles: 10.0,
    };

    #[test]
    fn at_the_largest_strain_so_far_there_is_no_within_cycle_softening() {
        let mut s = MullinsState::default();
        assert_eq!(M.factor(&mut s, 2.0), 1.0);
        // Back at x = 1: W_max − W = 2 − 0.5 = 1.5; η = 1 − tanh(1.5)/2 = 1 − 0.905148/2 = 0.547426.
        assert!((M.factor(&mut s, 1.0) - 0.547426).abs() < 1e-6);
    }

    #[test]
    fn cumulative_damage_saturates() {
        // N = N₀: 0.2·(1 − 1/e) = 0.126424.
        assert!((M.cumulative_damage(10.0) - 0.126424).abs() < 1e-6);
        assert!((M.cumulative_damage(1e6) - 0.2).abs() < 1e-12);
    }
}
