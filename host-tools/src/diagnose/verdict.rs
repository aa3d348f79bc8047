//! The verdict: `found`, `none` or `inconclusive`, with the reasons and the
//! experiment that would decide.
//!
//! "None" is a claim: the data could have shown a vocabulary effect and did
//! not. It is only made when the final held-out residual is near the noise,
//! or when the data were able to test: enough folds for the sign test, held-
//! out recordings inside the stroke the baseline was fitted on, no candidate
//! with a large held-out gain that failed a rule, and no candidate whose
//! columns the baseline can already bend to. Otherwise the verdict is
//! `inconclusive` and names why.
use super::acceptance::Thresholds;
use super::design::Designs;
use super::prepared::Prepared;
use super::select::Selection;
use super::unexplained::force_noise_n;
use nalgebra::DMatrix;

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
    if residual_over_noise < th.consistent_min_residual_over_noise {
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
    reasons.extend(collinear(prep, selection));
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

/// The sign test over folds cannot reach its level with fewer folds than
/// `min_consistent_units`, and a fold's training set shrinks with each one.
fn too_few_folds(prep: &Prepared, th: &Thresholds) -> Option<Reason> {
    let n_fit = prep.fit_indices().len();
    (prep.n_folds < th.min_consistent_units).then(|| Reason {
        code: "too_few_folds",
        detail: format!(
            "{n_fit} fit recordings in {} cross-validation folds: the every-fold sign test needs at least {} \
             (p ≤ 2^−{}), so a real effect could not pass it",
            prep.n_folds, th.min_consistent_units, th.min_consistent_units
        ),
        experiment: format!(
            "record at least {} tests (more amplitudes and frequencies at each current), so that {} folds \
             can be held out",
            th.min_consistent_units.saturating_sub(n_fit) + n_fit,
            th.min_consistent_units
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

/// A first-round candidate that gained as much as the large route asks but
/// failed a rule (its interval, its support, its physical check).
fn rejected_gains(selection: &Selection, th: &Thresholds) -> Vec<Reason> {
    let Some(round) = selection.rounds.first() else {
        return Vec::new();
    };
    round
        .tested
        .iter()
        .filter(|c| !c.accepted && c.ratio >= th.min_ratio)
        .filter_map(|c| {
            let term = super::terms::of(c.effect?)?;
            Some(Reason {
                code: "rejected_gain",
                detail: format!(
                    "{} gained {:.2}× held out ({:.2}× over the decision pool, 95 % {:.2}–{:.2}×) but failed the \
                     acceptance rules",
                    term.effect().name(),
                    c.ratio,
                    c.ratio_pool,
                    c.ratio_ci95[0],
                    c.ratio_ci95[1]
                ),
                experiment: term.deciding_experiment().into(),
            })
        })
        .collect()
}

/// First-round candidates whose columns lie mostly in the baseline's span.
fn collinear(prep: &Prepared, selection: &Selection) -> Vec<Reason> {
    let Some(round) = selection.rounds.first() else {
        return Vec::new();
    };
    round
        .tested
        .iter()
        .filter_map(|c| {
            let term = super::terms::of(c.effect?)?;
            let share = share_outside_baseline_span(prep, &Designs::build(prep, &c.scored.terms), term)?;
            (share < COLLINEAR_SHARE).then(|| Reason {
                code: "collinear",
                detail: format!(
                    "{}: only {:.1} % of its column's norm lies outside the span of the per-current branch \
                     quartics (the baseline can bend to absorb it)",
                    term.effect().name(),
                    100.0 * share
                ),
                experiment: term.deciding_experiment().into(),
            })
        })
        .collect()
}

/// `‖(I − P_Q) c‖ / ‖c‖` for the term's own columns `c` stacked over the fit
/// recordings' fitted samples, `P_Q` the projection on the quartic columns;
/// the largest over the term's columns (its most separable one). `None` when
/// the term adds no linear column (it transforms the inputs).
pub fn share_outside_baseline_span(prep: &Prepared, d: &Designs, term: &dyn super::terms::Term) -> Option<f64> {
    let n_quartic = d.layout.n_cols - d.layout.extra_cols();
    let own: Vec<usize> = d
        .layout
        .blocks
        .iter()
        .filter(|p| p.term.effect() == term.effect())
        .flat_map(|p| {
            let width = d
                .layout
                .blocks
                .iter()
                .map(|q| q.at)
                .filter(|&a| a > p.at)
                .min()
                .unwrap_or(d.layout.n_cols)
                - p.at;
            p.at..p.at + width
        })
        .collect();
    if own.is_empty() {
        return None;
    }
    let rows: Vec<(usize, usize)> = prep
        .fit_indices()
        .into_iter()
        .flat_map(|i| {
            let mask = &d.recs[i].mask;
            (0..mask.len()).filter(move |&t| mask[t]).map(move |t| (i, t))
        })
        .collect();
    let cols: Vec<usize> = (0..n_quartic).chain(own.iter().copied()).collect();
    let mut a = DMatrix::<f64>::zeros(rows.len(), cols.len());
    for (row, &(i, t)) in rows.iter().enumerate() {
        let rd = &d.recs[i];
        for (local, &g) in rd.cols.iter().enumerate() {
            if let Some(k) = cols.iter().position(|&c| c == g) {
                a[(row, k)] = rd.a[(t, local)];
            }
        }
    }
    // An orthonormal basis of the quartics' span by SVD, dropping directions
    // below round-off (currents without data leave zero columns).
    let svd = a.columns(0, n_quartic).into_owned().svd(true, false);
    let u = svd.u?;
    let s_max = svd.singular_values.max();
    let keep: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&k| svd.singular_values[k] > 1e-10 * s_max)
        .collect();
    let q = u.select_columns(&keep);
    let mut best: Option<f64> = None;
    for k in n_quartic..cols.len() {
        let c = a.column(k).into_owned();
        let norm = c.norm();
        if norm <= 0.0 {
            continue;
        }
        let resid = &c - &q * (q.transpose() * &c);
        let share = resid.norm() / norm;
        best = Some(best.map_or(share, |b: f64| b.max(share)));
    }
    best
}
