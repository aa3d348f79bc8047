//! `stress_softening`: the force scaled by `1 − Δ·g`, with `g` from the
//! recording's place in the run order or its temperature (between repeats
//! of a test condition), or from the cycle within the test (a decline over
//! the cycles of one test, [`SofteningLaw::Cycle`]), or from the strain
//! history of the run (softer below the run's largest displacement so far,
//! [`SofteningLaw::History`]), judged between runs of one motion that met
//! different histories.
use super::{Crossing, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{crossed_recordings, distinct_sequences, history_contrasts, temperature_span_c};
use crate::diagnose::design::{cycle_index, Layout, SofteningLaw, Solution, Terms};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct StressSoftening;

/// Complete cycles a recording needs for its within-test decline to be
/// judged: Δ and k0 are two parameters of the decline, and the crossing
/// spends the recording's own gain, so the cycles' levels must give at
/// least two contrasts beyond the gain: three cycles. (With two, the one
/// contrast is the first cycle against the second, which a start from rest
/// also makes.)
pub const MIN_CYCLES: f64 = 3.0;

/// Fit recordings with at least [`MIN_CYCLES`] cycles.
fn cycled_recordings(prep: &Prepared) -> usize {
    prep.fit_indices()
        .iter()
        .filter(|&&i| cycle_index(&prep.recs[i].x_mm).last().is_some_and(|&k| k > MIN_CYCLES))
        .count()
}

/// Between-repeats evidence: `Ok`, or what the data lack.
fn between_repeats(prep: &Prepared) -> Result<(), String> {
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

/// Within-test evidence: two fit recordings of [`MIN_CYCLES`] cycles or
/// more (one to train a fold on while the other is held out).
fn within_test(prep: &Prepared) -> bool {
    cycled_recordings(prep) >= 2
}

/// Strain-history evidence: a run order, and two motions each run once
/// after a larger test and once not ([`history_contrasts`]): one to train
/// a fold on while the other is held out.
fn strain_history(prep: &Prepared) -> bool {
    distinct_sequences(prep) >= 3 && history_contrasts(prep) >= 2
}

impl Term for StressSoftening {
    fn effect(&self) -> Effect {
        Effect::StressSoftening
    }
    fn deciding_experiment(&self) -> &'static str {
        "the first test repeated at the end of the run, and a small-amplitude test run both before and after the largest-amplitude one"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.softening.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms { softening: None, ..*t }
    }
    fn identifiable(&self, prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
        match between_repeats(prep) {
            Ok(()) => Ok(()),
            Err(_) if within_test(prep) || strain_history(prep) => Ok(()),
            Err(why) => Err(format!(
                "{why}; or tests of {MIN_CYCLES} cycles or more, for a decline within each test; or one motion run \
                 both before and after a larger test (twice), for a softening by strain history"
            )),
        }
    }
    fn crossed(&self, t: &Terms) -> Crossing {
        match t.softening {
            Some(SofteningLaw::History { .. } | SofteningLaw::Run { .. }) => Crossing::ByMotion,
            Some(law) if law.within_test() => Crossing::ByRecording,
            Some(_) => Crossing::ByCondition,
            None => Crossing::No,
        }
    }
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let with = |law: SofteningLaw| Terms {
            softening: Some(law),
            ..*base
        };
        let mut out = Vec::new();
        if between_repeats(prep).is_ok() {
            out.extend(self.between_variants(prep, base));
        }
        if within_test(prep) {
            // k0 in cycles: a step after the first cycle (the Mullins first
            // loading) to a decline still going at the test's end.
            out.extend(CYCLE_K0.iter().map(|&k0| with(SofteningLaw::Cycle { k0 })));
        }
        if strain_history(prep) {
            // u0 from a knee close under the run's largest displacement to a
            // softening spread over the whole stroke.
            let peak_mm = prep
                .recs
                .iter()
                .flat_map(|r| r.x_mm.iter())
                .fold(0.0f64, |m, x| m.max(x.abs()));
            out.extend(RUN_N0.iter().map(|&n0| with(SofteningLaw::Run { n0 })));
            out.extend(HISTORY_U0_SHARE.iter().map(|&s| {
                with(SofteningLaw::History {
                    u0_mm2: s * peak_mm * peak_mm,
                })
            }));
        }
        out
    }
    /// Quarter octaves of n0 (k0) around the grid's best.
    fn refinements(&self, _prep: &Prepared, best: &Terms) -> Vec<Terms> {
        let law = |f: f64| match best.softening {
            Some(SofteningLaw::Sequence { n0 }) => Some(SofteningLaw::Sequence { n0: n0 * f }),
            Some(SofteningLaw::Cycle { k0 }) => Some(SofteningLaw::Cycle { k0: k0 * f }),
            Some(SofteningLaw::Run { n0 }) => Some(SofteningLaw::Run { n0: n0 * f }),
            Some(SofteningLaw::History { u0_mm2 }) => Some(SofteningLaw::History { u0_mm2: u0_mm2 * f }),
            _ => None,
        };
        [-0.5, -0.25, 0.25, 0.5]
            .iter()
            .filter_map(|e| law(2f64.powf(*e)))
            .map(|l| Terms {
                softening: Some(l),
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
            Some(SofteningLaw::Sequence { n0 } | SofteningLaw::Run { n0 }) => vec![
                ("delta".into(), sol.delta, "1".into()),
                ("n0".into(), n0, "tests".into()),
            ],
            Some(SofteningLaw::Cycle { k0 }) => vec![
                ("delta".into(), sol.delta, "1".into()),
                ("k0".into(), k0, "cycles".into()),
            ],
            Some(SofteningLaw::History { u0_mm2 }) => vec![
                ("delta".into(), sol.delta, "1".into()),
                ("u0_mm2".into(), u0_mm2, "mm²".into()),
            ],
            Some(SofteningLaw::Temperature { .. }) => vec![("beta_per_c".into(), -sol.delta, "1/°C".into())],
            None => Vec::new(),
        }
    }
    fn searched(&self) -> &'static [&'static str] {
        &["n0", "k0", "u0_mm2"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["sequence", "temperature_c"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.softening.map(|law| match law {
            SofteningLaw::Sequence { n0 } => format!("softening over the run order (n0 = {n0:.2} tests)"),
            SofteningLaw::Run { n0 } => {
                format!("softening over the run order, between runs of one motion (n0 = {n0:.2} tests)")
            }
            SofteningLaw::Cycle { k0 } => format!("softening over the cycles of each test (k0 = {k0:.2} cycles)"),
            SofteningLaw::History { u0_mm2 } => {
                format!("softening by strain history (u0 = {u0_mm2:.2} mm² below the run's largest x²)")
            }
            SofteningLaw::Temperature { t_ref_c } => format!("softening with temperature (about {t_ref_c:.1} °C)"),
        })
    }
}

/// The searched k0 of the within-test law (cycles).
const CYCLE_K0: [f64; 4] = [0.3, 1.0, 3.0, 10.0];

/// The searched u0 of the strain-history law, as shares of the run's
/// largest squared displacement.
const HISTORY_U0_SHARE: [f64; 4] = [0.03, 0.1, 0.3, 1.0];

/// The searched n0 of the run-order law judged between runs of one motion.
const RUN_N0: [f64; 4] = [2.0, 4.0, 8.0, 16.0];

impl StressSoftening {
    fn between_variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
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
}
