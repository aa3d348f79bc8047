//! `sensor_delay`: the force channel lags (or leads) the motion by τ; the
//! design reads x, v, a and the current at t − τ.
use super::{TableParts, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::median_dt_s;
use crate::diagnose::design::{Layout, Solution, Terms};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct SensorDelay;

impl Term for SensorDelay {
    fn effect(&self) -> Effect {
        Effect::SensorDelay
    }
    fn deciding_experiment(&self) -> &'static str {
        "one amplitude at three or more frequencies, so the phase lag grows with frequency"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.delay_s.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms { delay_s: None, ..*t }
    }
    /// Any recording with motion can show a time shift.
    fn identifiable(&self, _prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
        Ok(())
    }
    /// Finer where delays are common (a few samples of filter group delay),
    /// and both signs: a DAQ offset can lead as well as lag.
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let dt = median_dt_s(prep);
        let lags = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 12.0];
        let leads = [1.0, 2.0, 4.0, 8.0];
        lags.iter()
            .map(|s| s * dt)
            .chain(leads.iter().map(|s| -s * dt))
            .map(|tau| Terms {
                delay_s: Some(tau),
                ..*base
            })
            .collect()
    }
    /// A filter's group delay is rarely a whole number of samples, and the
    /// residual of a half-sample error follows stiffness × velocity, which a
    /// rate term would then pick up as spurious damping: quarter samples
    /// around the grid's best.
    fn refinements(&self, prep: &Prepared, best: &Terms) -> Vec<Terms> {
        let Some(tau) = best.delay_s else {
            return Vec::new();
        };
        let dt = median_dt_s(prep);
        [-0.5, -0.25, 0.25, 0.5]
            .iter()
            .map(|f| Terms {
                delay_s: Some(tau + f * dt),
                ..*best
            })
            .collect()
    }
    /// Compensated in the quartics (fitted at `x(t − τ)`) and written as
    /// metadata only: the controller does not read the force channel.
    fn write_table(&self, _layout: &Layout, t: &Terms, _sol: &Solution, parts: &mut TableParts) -> anyhow::Result<()> {
        parts
            .metadata
            .push(("force_channel_delay_s".into(), t.delay_s.unwrap_or(0.0)));
        Ok(())
    }
    fn parameters(&self, _prep: &Prepared, _layout: &Layout, t: &Terms, _sol: &Solution) -> Vec<Value> {
        t.delay_s
            .map(|tau| ("tau_s".into(), tau, "s".into()))
            .into_iter()
            .collect()
    }
    fn searched(&self) -> &'static [&'static str] {
        &["tau_s"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["model force rate dF/dt (time shift)"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.delay_s.map(|tau| format!("a sensor delay of {:.3} ms", tau * 1e3))
    }
}
