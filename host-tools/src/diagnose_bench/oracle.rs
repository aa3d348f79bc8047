//! The real-data benchmark's oracle: how much the true injected force would
//! gain held out if the model were told its exact shape.
//!
//! The reference model as `diagnose` fits it (the paper's quartics plus the
//! turn-around memory it accepted, same folds, same validate current) gets
//! the injected added force, normalised to unit RMS, as one extra design
//! column with a free amplitude, and is judged by the held-out gain gate
//! every named term must pass ([`Thresholds::min_nested_gain`]). An injection
//! whose oracle does not pass it is not identifiable in these recordings with
//! this model class, whatever a candidate's search does: a miss there is no
//! fault of the candidate.
//!
//! A column no fit recording touches (an injection that only changes the
//! validate recordings, e.g. saturation at interpolated currents) cannot be
//! fitted on them; its amplitude is then chosen leave-one-validate-recording-
//! out on the reference's residual, as a validate-only candidate's value is,
//! and the decision reads the validate recordings.
//!
//! Softening (Mullins damage, [`super::real`]) scales the measured force by a
//! factor of the strain history, so its column carries the untouched
//! recording's own force times that factor's departure from 1: an oracle
//! told the history exactly, which no candidate is.
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::cv::{self, Scored};
use crate::diagnose::design::{Designs, Terms};
use crate::diagnose::prepared::{scored, Prepared};
use crate::diagnose::signals::current_weights;
use anyhow::Result;
use nalgebra::{DMatrix, DVector};

/// The oracle's verdict on one injected case.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Oracle {
    /// Held-out RMSE ratio, reference over reference + true column, on the
    /// decision pool (the fit recordings, each held out by its fold; the
    /// validate recordings for a validate-only column).
    pub held_out_ratio: f64,
    /// The same ratio over every recording.
    pub held_out_ratio_all: f64,
    /// The held-out ratio passes the gain gate ([`Thresholds::min_nested_gain`]).
    pub passes_gain: bool,
    /// In-sample RMSE ratio over the fit recordings (full fits): whether
    /// the shape gains anything even where nothing is held out.
    pub in_sample_ratio: f64,
    /// RMS over every sample of the fitted column(s) (N, full fit):
    /// the injected RMS when the column is recovered exactly.
    pub amplitude_rms_n: f64,
}

impl Oracle {
    pub fn identifiable(&self) -> bool {
        self.passes_gain
    }
}

/// RMS over every sample of a per-recording force.
fn rms(v: &[Vec<f64>]) -> f64 {
    let (s, n) = v.iter().flatten().fold((0.0, 0usize), |(s, n), f| (s + f * f, n + 1));
    (s / n.max(1) as f64).sqrt()
}

/// How the oracle's amplitude is fitted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Amplitude {
    /// One amplitude for every recording: the injection's (the headline).
    Shared,
    /// One per tabulated current (validate recordings interpolated between
    /// them as the quartics are): for an injection whose size the data may
    /// read differently at each current. A column only validate recordings
    /// carry is judged as `Shared`.
    PerCurrent,
}

/// The oracle for `added` (per recording and sample, N) on top of the
/// `reference` terms, judged by the gain gate.
pub fn oracle(
    prep: &Prepared,
    reference: &Terms,
    added: &[Vec<f64>],
    th: &Thresholds,
    amplitude: Amplitude,
) -> Result<Oracle> {
    let per_current = amplitude == Amplitude::PerCurrent;
    let scale = rms(added);
    let column: Vec<Vec<f64>> = added
        .iter()
        .map(|v| v.iter().map(|a| if scale > 0.0 { a / scale } else { 0.0 }).collect())
        .collect();
    let before = cv::score(prep, &[*reference])?;
    let touches_fit = prep.fit_indices().iter().any(|&i| column[i].iter().any(|c| *c != 0.0));
    let (after, amplitude) = if touches_fit {
        let columns = if per_current {
            split_by_current(prep, &column)
        } else {
            vec![column]
        };
        let base = Designs::build(prep, reference);
        let first = base.layout.n_cols;
        let d = columns.iter().fold(base, |d, c| with_column(&d, prep, c));
        let after = cv::score_designs(prep, &d)?;
        // The fitted added force (N) at every sample, for its RMS.
        let fitted: Vec<Vec<f64>> = (0..prep.recs.len())
            .map(|i| {
                (0..prep.recs[i].len())
                    .map(|t| {
                        (0..columns.len())
                            .map(|k| after.solution.beta[first + k] * columns[k][i][t])
                            .sum()
                    })
                    .collect()
            })
            .collect();
        (after, rms(&fitted))
    } else {
        validate_only(prep, &before, &column)
    };
    Ok(verdict(prep, &before, after, th, amplitude.abs()))
}

/// `after` judged against `before` as `effect`'s candidate would be.
fn verdict(prep: &Prepared, before: &Scored, after: Scored, th: &Thresholds, amplitude: f64) -> Oracle {
    let in_sample_ratio = (before.fit_sse / after.fit_sse.max(1e-300)).sqrt();
    let ratio_over = |idx: &[usize]| {
        let b: f64 = idx.iter().map(|&i| before.heldout_sse[i]).sum();
        let a: f64 = idx.iter().map(|&i| after.heldout_sse[i]).sum();
        (b / a.max(1e-300)).sqrt()
    };
    // The decision pool: fit recordings, or the validate ones for a column
    // only they carry.
    let pool = if after.insample_on_validate {
        prep.validate_indices()
    } else {
        prep.fit_indices()
    };
    let all: Vec<usize> = (0..prep.recs.len()).collect();
    let held_out_ratio = ratio_over(&pool);
    Oracle {
        held_out_ratio,
        held_out_ratio_all: ratio_over(&all),
        passes_gain: held_out_ratio >= th.min_nested_gain,
        in_sample_ratio,
        amplitude_rms_n: amplitude,
    }
}

/// One column per tabulated current: each recording's column times its
/// current's interpolation weight on that current.
fn split_by_current(prep: &Prepared, column: &[Vec<f64>]) -> Vec<Vec<Vec<f64>>> {
    (0..prep.currents_a.len())
        .map(|k| {
            prep.recs
                .iter()
                .zip(column)
                .map(|(r, c)| {
                    let w: f64 = current_weights(&prep.currents_a, r.current_a, None)
                        .iter()
                        .filter(|(j, _)| *j == k)
                        .map(|(_, w)| w)
                        .sum();
                    c.iter().map(|v| w * v).collect()
                })
                .collect()
        })
        .collect()
}

/// `before` with the column added to each validate recording's prediction,
/// its amplitude fitted by least squares on the other validate recordings'
/// residuals (their scored samples); the amplitude over all of them.
fn validate_only(prep: &Prepared, before: &Scored, column: &[Vec<f64>]) -> (Scored, f64) {
    let validate = prep.validate_indices();
    // Per validate recording: Σ c·r and Σ c² over its scored samples.
    let sums: Vec<(f64, f64)> = validate
        .iter()
        .map(|&i| {
            let r = prep.recs[i]
                .force_n
                .iter()
                .zip(&before.heldout_pred[i])
                .map(|(f, p)| f - p);
            let c = column[i].iter();
            let both: Vec<(f64, f64)> = scored(c.zip(r), &before.mask[i]).map(|(c, r)| (*c, r)).collect();
            (
                both.iter().map(|(c, r)| c * r).sum(),
                both.iter().map(|(c, _)| c * c).sum(),
            )
        })
        .collect();
    let amplitude = |skip: Option<usize>| {
        let (cr, cc) = sums
            .iter()
            .enumerate()
            .filter(|(k, _)| Some(*k) != skip)
            .fold((0.0, 0.0), |(a, b), (_, (cr, cc))| (a + cr, b + cc));
        if cc > 0.0 {
            cr / cc
        } else {
            0.0
        }
    };
    let mut after = before.clone();
    for (k, &i) in validate.iter().enumerate() {
        let a = if validate.len() >= 2 { amplitude(Some(k)) } else { 0.0 };
        let pred: Vec<f64> = before.heldout_pred[i]
            .iter()
            .zip(&column[i])
            .map(|(p, c)| p + a * c)
            .collect();
        let se: Vec<f64> = pred
            .iter()
            .zip(&prep.recs[i].force_n)
            .map(|(p, f)| (p - f) * (p - f))
            .collect();
        after.heldout_sse[i] = scored(se.iter(), &after.mask[i]).sum();
        after.heldout_se[i] = se;
        after.heldout_pred[i] = pred;
    }
    after.insample_on_validate = true;
    after.insample_sse = validate.iter().map(|&i| after.heldout_sse[i]).sum();
    after.insample_n = validate.iter().map(|&i| after.n[i]).sum();
    after.n_params += 1;
    (after, amplitude(None))
}

/// The same model with one more column, `column[i][t]` at sample t of
/// recording i, and a free coefficient (the last): the real-data
/// benchmark's oracle gives the true injected force this way. A
/// recording whose column is all zero keeps its design.
pub fn with_column(designs: &Designs, prep: &Prepared, column: &[Vec<f64>]) -> Designs {
    let mut out = designs.clone();
    let at = out.layout.n_cols;
    out.layout.n_cols += 1;
    for ((d, rec), col) in out.recs.iter_mut().zip(&prep.recs).zip(column) {
        if col.iter().all(|v| *v == 0.0) || col.len() != d.a.nrows() {
            continue;
        }
        let n = d.cols.len();
        d.a = std::mem::replace(&mut d.a, DMatrix::zeros(0, 0)).insert_column(n, 0.0);
        d.a.set_column(n, &DVector::from_column_slice(col));
        d.cols.push(at);
        (d.r_a, d.r_y) = crate::diagnose::design::compress(rec, &d.a, &d.mask);
    }
    out
}
