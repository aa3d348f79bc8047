//! The held-out numbers reported for an accepted effect: the round winner's
//! ratio with the choice between candidates nested ([`nested_ratio`]; the
//! plain ratio of the best of several candidates carries its selection bias),
//! and a ratio with its bootstrap interval over the same recordings
//! ([`HeldOutRatio`]).
use super::acceptance::{accepts, bootstrap_ratio_ci95, judge, scoring_units, Comparison, Thresholds};
use super::prepared::Prepared;
use super::scale::ScaleTest;

/// The winner's held-out ratio from units that played no part in choosing
/// it. For each of the winner's scoring units the round is decided again
/// without that unit (every candidate judged on its other units, the
/// consistency route then needing one unit fewer), and the unit is scored
/// with what that choice gives: the chosen candidate's held-out errors, or
/// the current model's when nothing passes. Recordings selection never reads
/// (validate ones, for a term fitted on fit recordings) keep the winner's.
/// Each unit's own held-out errors come from fits without it, but the other
/// units' do not exclude it: one level of nesting, not a full refit.
pub fn nested_ratio(prep: &Prepared, tested: &[Comparison], winner: usize, th: &Thresholds) -> HeldOutRatio {
    let w = &tested[winner];
    // Every held-out unit: each fit fold, and each validate recording.
    let units: Vec<Vec<usize>> = scoring_units(prep, false)
        .into_iter()
        .chain(scoring_units(prep, true))
        .collect();
    let (mut b, mut a) = (w.sse_before.clone(), w.sse_after.clone());
    for u in &units {
        let chosen = tested
            .iter()
            .enumerate()
            .filter_map(|(k, c)| {
                let on_validate = c.scored.insample_on_validate;
                let own = scoring_units(prep, on_validate).contains(u);
                let min_units = th.min_consistent_units.saturating_sub(usize::from(own));
                // The scale test without this unit's gains, run only if
                // no other route passes.
                let scale_test = c.scale.as_ref().map(|s| move || s.test(u));
                let j = judge(
                    prep,
                    &c.sse_before,
                    &c.sse_after,
                    on_validate,
                    u,
                    th,
                    min_units,
                    c.local_open.then_some(&c.local_stats),
                    scale_test.as_ref().map(|f| f as &dyn Fn() -> ScaleTest),
                );
                accepts(prep, &j, c.delta_bic, &c.scored, c.effect, th).then_some((k, j.ratio))
            })
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .map(|(k, _)| k);
        for &i in u {
            match chosen {
                Some(k) => {
                    b[i] = tested[k].sse_before[i];
                    a[i] = tested[k].sse_after[i];
                }
                None => a[i] = b[i],
            }
        }
    }
    HeldOutRatio::over_every_recording(b, a, th)
}

/// A held-out RMSE ratio and its 95 % bootstrap interval, both computed over
/// the same recordings (every recording, each scored held out), so the
/// interval printed beside the ratio is the doubt about that ratio.
#[derive(Clone, Debug)]
pub struct HeldOutRatio {
    /// `sqrt(Σ sse_before / Σ sse_after)` over every recording.
    pub ratio: f64,
    /// Percentile bootstrap interval of the same ratio, resampling the same
    /// recordings ([`bootstrap_ratio_ci95`]).
    pub ci95: [f64; 2],
    /// Per recording: held-out SSE before and after.
    pub sse_before: Vec<f64>,
    pub sse_after: Vec<f64>,
}

impl HeldOutRatio {
    pub fn over_every_recording(sse_before: Vec<f64>, sse_after: Vec<f64>, th: &Thresholds) -> Self {
        let all: Vec<usize> = (0..sse_before.len()).collect();
        HeldOutRatio {
            ratio: (sse_before.iter().sum::<f64>() / sse_after.iter().sum::<f64>().max(1e-300)).sqrt(),
            ci95: bootstrap_ratio_ci95(&sse_before, &sse_after, &all, th),
            sse_before,
            sse_after,
        }
    }
}
