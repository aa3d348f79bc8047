//! `coil_lag`: the material sees the recorded current through a first-order
//! lag L/R ([`crate::diagnose::design::effective_current_a`]).
use super::{TableParts, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{median_dt_s, stepped_validate, stepped_validate_count};
use crate::diagnose::design::{Layout, Solution, Terms};
use crate::diagnose::locate::CURRENT_NOT_FOLLOWED;
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct CoilLag;

impl Term for CoilLag {
    fn effect(&self) -> Effect {
        Effect::CoilLag
    }
    fn deciding_experiment(&self) -> &'static str {
        "current steps commanded mid-stroke (controlled impacts), so the force follows the coil's lag"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.coil_lag_s.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms { coil_lag_s: None, ..*t }
    }
    fn identifiable(&self, prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
        let n = stepped_validate_count(prep);
        if n >= 2 {
            Ok(())
        } else {
            Err(format!(
                "at least two `validate` recordings in which the coil current changes during the test \
                 (controlled impacts), with the command recorded per sample (`current_a` column); this \
                 data set has {n}"
            ))
        }
    }
    /// The fit recordings hold their current: only the controlled
    /// (validate) impacts change.
    fn validate_only(&self) -> bool {
        true
    }
    fn evidence(&self, prep: &Prepared) -> Vec<usize> {
        stepped_validate(prep)
    }
    /// From one sample period to about 720 (√2 steps; 36 ms at the drop
    /// tests' 50 µs): an L/R from well under the sampling time to the 20 ms
    /// of real MR coils (#29) and beyond. Stopping at 90 periods (4.5 ms)
    /// diagnosed every 10–20 ms coil as 5.4 ms.
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let dt = median_dt_s(prep);
        (0..20)
            .map(|k| dt * 2f64.powf(0.5 * k as f64))
            .map(|tau| Terms {
                coil_lag_s: Some(tau),
                ..*base
            })
            .collect()
    }
    /// The √2 grid refined to 2^(1/16) steps: within 2.2 % of any τ between
    /// the grid's points.
    fn refinements(&self, _prep: &Prepared, best: &Terms) -> Vec<Terms> {
        let Some(tau) = best.coil_lag_s else {
            return Vec::new();
        };
        [-0.25, -0.1875, -0.125, -0.0625, 0.0625, 0.125, 0.1875, 0.25]
            .iter()
            .map(|e| Terms {
                coil_lag_s: Some(tau * 2f64.powf(*e)),
                ..*best
            })
            .collect()
    }
    /// The coil time constant, which the table's law inverts.
    fn write_table(&self, _layout: &Layout, t: &Terms, _sol: &Solution, parts: &mut TableParts) -> anyhow::Result<()> {
        parts.terms.coil_tau_s = t.coil_lag_s.unwrap_or(0.0) as f32;
        Ok(())
    }
    fn parameters(&self, _prep: &Prepared, _layout: &Layout, t: &Terms, _sol: &Solution) -> Vec<Value> {
        t.coil_lag_s
            .map(|tau| ("time_constant_s".into(), tau, "s".into()))
            .into_iter()
            .collect()
    }
    fn searched(&self) -> &'static [&'static str] {
        &["time_constant_s"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &[CURRENT_NOT_FOLLOWED]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.coil_lag_s.map(|tau| format!("a coil lag of {:.3} ms", tau * 1e3))
    }
}
