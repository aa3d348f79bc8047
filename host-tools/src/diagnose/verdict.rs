//! The verdict: `found`, `none` or `inconclusive`, with the reasons and the
//! experiment that would decide.
//!
//! "None" is a claim: the data could have shown a vocabulary effect and did
//! not. It is only made when the final held-out residual is near the noise,
//! or when the data were able to test: enough folds for the sign test, held-
//! out recordings inside the stroke the baseline was fitted on, no candidate
//! that passed one of the two gates but not the other, and no candidate whose
//! columns the baseline can already bend to. Otherwise the verdict is
//! `inconclusive` and names why.
use super::acceptance::Thresholds;
use super::prepared::Prepared;
use super::select::Selection;
use super::unexplained::force_noise_n;

/// A candidate whose column keeps less than this share of its norm outside
/// the baseline's span is collinear with the baseline: the quartics absorb it,
/// and no held-out test on these data can separate the two. Structural, not
/// tuned: 10 % of the norm is 1 % of the energy.
pub const COLLINEAR_SHARE: f64 = 0.10;
/// Held-out recordings with more than this share of their samples outside
/// the stroke of the recordings they are predicted from test extrapolation,
/// not the model.
pub const OUTSIDE_STROKE_SHARE: f64 = 0.5;

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Found,
    None,
    Inconclusive,
}

impl Verdict {
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Found => "found",
            Verdict::None => "none",
            Verdict::Inconclusive => "inconclusive",
        }
    }
}

/// Why the data cannot decide, and what would.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Reason {
    /// `too_few_folds`, `outside_stroke`, `collinear` or `rejected_gain`.
    pub code: &'static str,
    pub detail: String,
    /// The experiment that would decide.
    pub experiment: String,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct VerdictReport {
    pub verdict: Verdict,
    /// Final held-out RMSE over the fit recordings, in units of the force noise.
    pub residual_over_noise: f64,
    pub reasons: Vec<Reason>,
}

/// Decides the verdict from the selection (nothing here changes the model).
pub fn decide(prep: &Prepared, selection: &Selection, n_findings: usize, th: &Thresholds) -> VerdictReport {
    let residual_over_noise = fit_rmse_n(prep, selection) / force_noise_n(prep).max(f64::MIN_POSITIVE);
    if n_findings > 0 {
        return VerdictReport {
            verdict: Verdict::Found,
            residual_over_noise,
            reasons: Vec::new(),
        };
    }
    // Near the noise there is nothing left to find, however little data.
    if residual_over_noise < th.none_max_residual_over_noise {
        return VerdictReport {
            verdict: Verdict::None,
            residual_over_noise,
            reasons: Vec::new(),
        };
    }
    let mut reasons = Vec::new();
    reasons.extend(too_few_folds(prep, th));
    reasons.extend(outside_stroke(prep));
    reasons.extend(rejected_gains(selection, th));
    reasons.extend(collinear(selection));
    VerdictReport {
        verdict: if reasons.is_empty() {
            Verdict::None
        } else {
            Verdict::Inconclusive
        },
        residual_over_noise,
        reasons,
    }
}

/// Held-out RMSE of the final model over the fit recordings.
fn fit_rmse_n(prep: &Prepared, selection: &Selection) -> f64 {
    let m = &selection.final_model;
    let (mut sse, mut n) = (0.0, 0usize);
    for i in prep.fit_indices() {
        sse += m.heldout_sse[i];
        n += m.n[i];
    }
    (sse / n.max(1) as f64).sqrt()
}

/// With few folds each is a large share of the data: the rest of the model
/// is chosen on too little to stand for what it would be on all of it, and
/// the held-out gain rests on a handful of recordings.
fn too_few_folds(prep: &Prepared, th: &Thresholds) -> Option<Reason> {
    let n_fit = prep.fit_indices().len();
    (prep.n_folds < th.min_folds).then(|| Reason {
        code: "too_few_folds",
        detail: format!(
            "{n_fit} fit recordings in {} cross-validation folds, fewer than the {} a nested held-out gain \
             needs",
            prep.n_folds, th.min_folds
        ),
        experiment: format!(
            "record at least {} tests (more amplitudes and frequencies at each current), so that {} folds \
             can be held out",
            th.min_folds.max(n_fit),
            th.min_folds
        ),
    })
}

/// Share of the fit samples that lie outside the stroke of the other folds'
/// recordings at the same current (the baseline each fold is predicted by).
pub fn outside_stroke_share(prep: &Prepared) -> f64 {
    let (mut outside, mut total) = (0usize, 0usize);
    for i in prep.fit_indices() {
        let r = &prep.recs[i];
        let (lo, hi) = prep
            .training_for(r.fold.unwrap_or(usize::MAX))
            .iter()
            .filter(|&&j| prep.recs[j].current_a == r.current_a)
            .flat_map(|&j| prep.recs[j].x_mm.iter().copied())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
        for (&x, &scored) in r.x_mm.iter().zip(&r.in_domain) {
            if scored {
                total += 1;
                outside += usize::from(x < lo || x > hi);
            }
        }
    }
    outside as f64 / total.max(1) as f64
}

fn outside_stroke(prep: &Prepared) -> Option<Reason> {
    let share = outside_stroke_share(prep);
    (share > OUTSIDE_STROKE_SHARE).then(|| Reason {
        code: "outside_stroke",
        detail: format!(
            "{:.0} % of the held-out samples lie outside the stroke of the recordings at the same current they \
             are predicted from: the held-out error measures the baseline's extrapolation",
            100.0 * share
        ),
        experiment: "amplitudes stepping across the stroke at each current (each amplitude repeated, so a held-out \
                     test has a neighbour on either side)"
            .into(),
    })
}

/// A candidate that passed one gate and not the other: a large held-out
/// gain without a stable inclusion, or a stable inclusion without the gain.
fn rejected_gains(selection: &Selection, th: &Thresholds) -> Vec<Reason> {
    selection
        .candidates
        .iter()
        .filter(|c| !c.named && (c.gain.ratio >= th.min_nested_gain || c.inclusion >= th.min_inclusion))
        .filter_map(|c| {
            let term = super::terms::of(c.effect)?;
            Some(Reason {
                code: "rejected_gain",
                detail: format!(
                    "{} gained {:.2}× held out (nested, 95 % {:.2}–{:.2}×; gate {:.2}×) with inclusion \
                     probability {:.2} (gate {:.2})",
                    c.effect.name(),
                    c.gain.ratio,
                    c.gain.ci95[0],
                    c.gain.ci95[1],
                    th.min_nested_gain,
                    c.inclusion,
                    th.min_inclusion
                ),
                experiment: term.deciding_experiment().into(),
            })
        })
        .collect()
}

/// Candidates whose columns lie mostly in the baseline's span.
fn collinear(selection: &Selection) -> Vec<Reason> {
    selection
        .candidates
        .iter()
        .filter(|c| !c.named && c.outside_baseline < COLLINEAR_SHARE)
        .filter_map(|c| {
            let term = super::terms::of(c.effect)?;
            Some(Reason {
                code: "collinear",
                detail: format!(
                    "{}: only {:.1} % of its column's norm lies outside the span of the per-current branch \
                     quartics (the baseline can bend to absorb it)",
                    c.effect.name(),
                    100.0 * c.outside_baseline
                ),
                experiment: term.deciding_experiment().into(),
            })
        })
        .collect()
}
