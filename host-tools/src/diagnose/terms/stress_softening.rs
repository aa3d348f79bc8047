//! `stress_softening`: each recording's force scaled by `1 − Δ·g_r`, with
//! `g_r` from its place in the run order or its temperature.
use super::{Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{crossed_recordings, distinct_sequences, temperature_span_c};
use crate::diagnose::design::{Layout, SofteningLaw, Solution, Terms};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct StressSoftening;

impl Term for StressSoftening {
    fn effect(&self) -> Effect {
        Effect::StressSoftening
    }
    fn deciding_experiment(&self) -> &'static str {
        "the first test repeated at the end of the run, and the run order crossed with amplitude"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.softening.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms { softening: None, ..*t }
    }
    fn identifiable(&self, prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
        if distinct_sequences(prep) < 3 && temperature_span_c(prep) < 2.0 {
            return Err("repeated tests with their run order recorded (`sequence`), or temperature records".into());
        }
        // A drift across the run is told from a difference between test
        // conditions only where one condition is repeated at another place
        // in the run (a crossed effect, [`Term::crossed`]).
        if crossed_recordings(prep) < 2 {
            return Err(
                "a test condition repeated at another place in the run order (each condition here is run once, \
                 so a drift over the run cannot be told from a difference between conditions)"
                    .into(),
            );
        }
        Ok(())
    }
    fn crossed(&self) -> bool {
        true
    }
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let with = |law: SofteningLaw| Terms {
            softening: Some(law),
            ..*base
        };
        if distinct_sequences(prep) >= 3 {
            [2.0, 4.0, 8.0, 16.0, 40.0]
                .iter()
                .map(|&n0| with(SofteningLaw::Sequence { n0 }))
                .collect()
        } else {
            let t: Vec<f64> = prep
                .fit_indices()
                .iter()
                .filter_map(|&i| prep.recs[i].temperature_c)
                .collect();
            let t_ref_c = t.iter().sum::<f64>() / t.len().max(1) as f64;
            vec![with(SofteningLaw::Temperature { t_ref_c })]
        }
    }
    /// Quarter octaves of n0 around the grid's best.
    fn refinements(&self, _prep: &Prepared, best: &Terms) -> Vec<Terms> {
        let Some(SofteningLaw::Sequence { n0 }) = best.softening else {
            return Vec::new();
        };
        [-0.5, -0.25, 0.25, 0.5]
            .iter()
            .map(|e| Terms {
                softening: Some(SofteningLaw::Sequence { n0: n0 * 2f64.powf(*e) }),
                ..*best
            })
            .collect()
    }
    /// Over a run order it scales whole recordings: the per-recording gains
    /// can judge it.
    /// The damper as the latest recording found it: every coefficient at
    /// that recording's softening factor.
    fn table_scale(&self, prep: &Prepared, t: &Terms, sol: &Solution) -> f64 {
        let Some(law) = t.softening else { return 1.0 };
        let g = prep
            .recs
            .iter()
            .map(|r| law.covariate(r))
            .fold(f64::NEG_INFINITY, f64::max);
        1.0 - sol.delta * if g.is_finite() { g } else { 0.0 }
    }
    fn parameters(&self, _prep: &Prepared, _layout: &Layout, t: &Terms, sol: &Solution) -> Vec<Value> {
        match t.softening {
            Some(SofteningLaw::Sequence { n0 }) => vec![
                ("delta".into(), sol.delta, "1".into()),
                ("n0".into(), n0, "tests".into()),
            ],
            Some(SofteningLaw::Temperature { .. }) => vec![("beta_per_c".into(), -sol.delta, "1/°C".into())],
            None => Vec::new(),
        }
    }
    fn searched(&self) -> &'static [&'static str] {
        &["n0"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["sequence", "temperature_c"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.softening.map(|law| match law {
            SofteningLaw::Sequence { n0 } => format!("softening over the run order (n0 = {n0:.2} tests)"),
            SofteningLaw::Temperature { t_ref_c } => format!("softening with temperature (about {t_ref_c:.1} °C)"),
        })
    }
}
