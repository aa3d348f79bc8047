//! `inertia`: a mass `m_s` moving with the measured end, `m_s·a`.
use super::{Block, Sample, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::acceleration_misfit_over_noise;
use crate::diagnose::design::{Layout, Solution, Terms};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct Inertia;

/// The setting that marks the term present (it has no searched value).
const PRESENT: f64 = 1.0;

impl Term for Inertia {
    fn effect(&self) -> Effect {
        Effect::Inertia
    }
    fn deciding_experiment(&self) -> &'static str {
        "an accelerometer on the moving mass, or drops of two different masses"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.settings.get(Effect::Inertia).is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms {
            settings: t.settings.with(Effect::Inertia, None),
            ..*t
        }
    }
    /// A test on the data, not on a column's presence: an acceleration that
    /// is only the force again (a one-mass drop's striker accelerometer,
    /// a = g − F/M) would feed the measured force back into the prediction.
    fn identifiable(&self, prep: &Prepared, th: &Thresholds) -> Result<(), String> {
        if prep.free_drop {
            return Err(
                "a test whose acceleration is not proportional to the measured force (shaker or MTS \
                 test, or a measured acceleration channel): in a free drop a = g − F/M, a pure scale the \
                 fit absorbs"
                    .into(),
            );
        }
        let misfit = acceleration_misfit_over_noise(prep);
        if misfit >= th.inertia_min_accel_misfit_over_noise {
            Ok(())
        } else {
            Err(format!(
                "an acceleration that is not proportional to the measured force (a shaker or MTS test, or \
                 drops of two masses): here a = α + β·F fits the acceleration to {misfit:.1}× its noise \
                 (below {:.1}×), so an `m·a` term would only feed the measured force back",
                th.inertia_min_accel_misfit_over_noise
            ))
        }
    }
    fn variants(&self, _prep: &Prepared, base: &Terms) -> Vec<Terms> {
        // Nothing is searched: the setting only marks the term present.
        vec![Terms {
            settings: base.settings.with(Effect::Inertia, Some(PRESENT)),
            ..*base
        }]
    }
    fn blocks(&self, t: &Terms) -> Vec<Block> {
        self.present_in(t).then_some(Block::Global).into_iter().collect()
    }
    fn shape(&self, _t: &Terms, _block: usize, s: &Sample) -> f64 {
        s.a_m_s2
    }
    /// A mass is ≥ 0.
    fn nonnegative(&self, _t: &Terms, _block: usize) -> bool {
        true
    }
    fn parameters(&self, _prep: &Prepared, layout: &Layout, _t: &Terms, sol: &Solution) -> Vec<Value> {
        layout
            .at(Effect::Inertia, 0)
            .map(|at| ("m_s_kg".into(), sol.beta[at], "kg".into()))
            .into_iter()
            .collect()
    }
    fn wrong_sign(&self, name: &str, value: f64) -> Option<&'static str> {
        (name == "m_s_kg" && value < 0.0).then_some("a mass below zero")
    }
    fn signature(&self) -> &'static [&'static str] {
        &["acceleration"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        self.present_in(t).then(|| "inertia".into())
    }
}
