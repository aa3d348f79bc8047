//! The select stage: group STLSQ over the joint library ([`super::library`],
//! [`super::sparse`]), each term's inclusion probability over an ensemble
//! of complementary half-samples of the recordings, and its nested held-out
//! gain. A term is named when both pass ([`Thresholds::min_inclusion`],
//! [`Thresholds::min_nested_gain`]); the named terms are then refitted as
//! one model and scored out of sample ([`super::cv`]).
use super::acceptance::Thresholds;
use super::candidates::Effect;
use super::cv::{score, Scored};
use super::design::{Layout, Terms};
use super::heldout::HeldOutRatio;
use super::library::{self, Built};
use super::prepared::Prepared;
use super::sparse::{self, group_stlsq, Library};
use super::validate_terms;
use anyhow::Result;
use rayon::prelude::*;

/// One term's evidence.
#[derive(Clone, Debug)]
pub struct Candidate {
    pub effect: Effect,
    /// The term alone at its chosen value.
    pub own: Terms,
    /// It entered the library as one linearised regressor.
    pub linearised: bool,
    /// Share of the ensemble's fits that kept it.
    pub inclusion: f64,
    /// Its contribution in the full-data fit, over what the quartics alone
    /// leave unexplained.
    pub share: f64,
    /// Held-out SSE per library recording without → with the term, the rest
    /// of the model chosen without that recording's fold (nested).
    pub gain: HeldOutRatio,
    /// The same ratio with the rest of the model chosen on all data.
    pub gain_plain: f64,
    /// Held-out RMSE ratio over the library's recordings of the refitted
    /// final model without → with the term, in its real form (NaN unless named).
    pub refit_gain: f64,
    /// `‖(I − P_Q) c‖ / ‖c‖` of its most separable column `c`, `P_Q` the
    /// projection on the quartics: below [`super::verdict::COLLINEAR_SHARE`]
    /// the baseline can bend to absorb it.
    pub outside_baseline: f64,
    pub named: bool,
    /// For a term decided in the validate stage ([`super::validate_terms`]):
    /// the validate recordings that decided it, and those of its evidence
    /// kept as the check (both empty for a library term).
    pub decided_by: Vec<usize>,
    pub checked_by: Vec<usize>,
}

/// The result of the selection.
#[derive(Clone, Debug)]
pub struct Selection {
    /// The paper's model, scored out of sample.
    pub baseline: Scored,
    /// The paper's model with every named term, scored out of sample.
    pub final_model: Scored,
    pub candidates: Vec<Candidate>,
    pub not_identifiable: Vec<(Effect, String)>,
    /// Fits in the inclusion ensemble.
    pub ensemble_fits: usize,
    /// The stability bound on the expected number of wrongly included
    /// terms ([`sparse::stability_bound`]) at [`Thresholds::min_inclusion`].
    pub false_inclusion_bound: f64,
    /// Library recordings and columns.
    pub n_recordings: usize,
    pub n_columns: usize,
    /// Validate recordings some decision read (every one under
    /// `validate_evidence`); the rest are the independent check.
    pub validate_read: Vec<usize>,
}

impl Selection {
    /// The candidate of `effect`, if it was in the library.
    pub fn candidate(&self, effect: Effect) -> Option<&Candidate> {
        self.candidates.iter().find(|c| c.effect == effect)
    }
}

/// Held-out SSE per library recording, without and with each optional group
/// (rows: groups), the rest of the model chosen by `kept_for(fold)` on the
/// fold's training recordings.
fn heldout_sse(
    lib: &Library,
    folds: &[(usize, Vec<usize>)],
    recs: &[usize],
    kept_for: &(dyn Fn(&[usize]) -> Vec<bool> + Sync),
) -> Vec<(Vec<f64>, Vec<f64>)> {
    let n_groups = lib.groups.len();
    let per_fold: Vec<Vec<(Vec<f64>, Vec<f64>)>> = folds
        .par_iter()
        .map(|(_, test)| {
            let train: Vec<usize> = recs.iter().copied().filter(|r| !test.contains(r)).collect();
            let rows = lib.rows_of(&train);
            let kept = kept_for(&rows);
            let reduced = lib.reduce(&rows);
            let mut out = vec![(vec![0.0; recs.len()], vec![0.0; recs.len()]); n_groups];
            for (g, slot) in out.iter_mut().enumerate().filter(|(g, _)| !lib.groups[*g].always) {
                for (with, sse) in [(false, &mut slot.0), (true, &mut slot.1)] {
                    let mut k = kept.clone();
                    k[g] = with;
                    let beta = reduced.least_squares(&k);
                    for (rec, e) in lib.sse_by_recording(&beta) {
                        if test.contains(&rec) {
                            if let Some(j) = recs.iter().position(|&r| r == rec) {
                                sse[j] += e;
                            }
                        }
                    }
                }
            }
            out
        })
        .collect();
    (0..n_groups)
        .map(|g| {
            let mut without = vec![0.0; recs.len()];
            let mut with = vec![0.0; recs.len()];
            for f in &per_fold {
                for j in 0..recs.len() {
                    without[j] += f[g].0[j];
                    with[j] += f[g].1[j];
                }
            }
            (without, with)
        })
        .collect()
}

/// Selects the terms (see the module docs).
pub fn select(prep: &Prepared, th: &Thresholds) -> Result<Selection> {
    let baseline = score(prep, &[Terms::default()])?;
    let Built {
        lib,
        candidates: built,
        not_identifiable,
        fold_of,
    } = library::build(prep, th)?;
    let recs = lib.recordings();
    let mut folds: Vec<(usize, Vec<usize>)> = Vec::new();
    for &r in &recs {
        let f = fold_of[r].unwrap_or(usize::MAX);
        match folds.iter_mut().find(|(k, _)| *k == f) {
            Some((_, members)) => members.push(r),
            None => folds.push((f, vec![r])),
        }
    }
    let all_rows: Vec<usize> = (0..lib.y.len()).collect();
    let full = group_stlsq(&lib, &all_rows, th.sparsity);
    let ensemble = sparse::ensemble(&lib, th.sparsity, th.ensemble_pairs, th.seed);
    let nested = heldout_sse(&lib, &folds, &recs, &|rows| group_stlsq(&lib, rows, th.sparsity).kept);
    let plain = heldout_sse(&lib, &folds, &recs, &|_| full.kept.clone());
    let quartics: Vec<usize> = (0..lib.groups.len()).filter(|&g| lib.groups[g].always).collect();
    let candidates: Vec<Candidate> = built
        .iter()
        .map(|c| {
            let (without, with) = nested[c.group].clone();
            let gain = HeldOutRatio::over_every_recording(without, with, th);
            let (pw, pi) = &plain[c.group];
            let gain_plain = (pw.iter().sum::<f64>() / pi.iter().sum::<f64>().max(1e-300)).sqrt();
            let inclusion = ensemble.inclusion[c.group];
            Candidate {
                effect: c.term.effect(),
                own: c.own,
                linearised: c.linearised,
                inclusion,
                share: full.share[c.group],
                named: inclusion >= th.min_inclusion && gain.ratio >= th.min_nested_gain,
                gain,
                gain_plain,
                refit_gain: f64::NAN,
                outside_baseline: sparse::share_outside(&lib, c.group, &quartics),
                decided_by: Vec::new(),
                checked_by: Vec::new(),
            }
        })
        .collect();
    let mut selection = Selection {
        final_model: baseline.clone(),
        baseline,
        candidates,
        not_identifiable,
        ensemble_fits: ensemble.fits,
        false_inclusion_bound: sparse::stability_bound(
            ensemble.mean_kept,
            lib.groups.iter().filter(|g| !g.always).count(),
            th.min_inclusion,
        ),
        n_recordings: recs.len(),
        n_columns: lib.a.ncols(),
        validate_read: if prep.validate_evidence {
            prep.validate_indices()
        } else {
            Vec::new()
        },
    };
    // The named terms as one model; a term whose refit is not physical
    // (a net negative damping, a stop pulling) is not named.
    loop {
        let terms = selection
            .candidates
            .iter()
            .filter(|c| c.named)
            .fold(Terms::default(), |acc, c| acc.merged(c.own));
        if terms == Terms::default() {
            selection.final_model = selection.baseline.clone();
            break;
        }
        let model = score(prep, &[terms])?;
        let layout = Layout::new(prep.currents_a.len(), &model.terms);
        let mut dropped = false;
        for c in selection.candidates.iter_mut().filter(|c| c.named) {
            if let Some(t) = super::terms::of(c.effect) {
                if !t.physical(&layout, &model.terms, &model.solution) {
                    c.named = false;
                    dropped = true;
                }
            }
        }
        if dropped {
            continue;
        }
        // Validated on the refitted model: a linearised regressor has a free
        // coefficient and can stand for more than its term, so each named
        // term must also gain by the gate with its real form in the refit
        // (held out); the weakest that does not is
        // dropped and the rest refitted.
        // Over the library's recordings: the validate ones too when they are
        // evidence (a coil lag changes nothing else).
        let mut pool = prep.fit_indices();
        if prep.validate_evidence {
            pool.extend(prep.validate_indices());
        }
        let heldout = |m: &Scored| pool.iter().map(|&i| m.heldout_sse[i]).sum::<f64>();
        let with = heldout(&model);
        let mut weakest: Option<(usize, f64)> = None;
        for (k, c) in selection.candidates.iter_mut().enumerate().filter(|(_, c)| c.named) {
            let Some(t) = super::terms::of(c.effect) else { continue };
            let without = score(prep, &[t.removed_from(&model.terms)])?;
            c.refit_gain = (heldout(&without) / with.max(1e-300)).sqrt();
            if c.refit_gain < th.min_nested_gain && weakest.is_none_or(|(_, g)| c.refit_gain < g) {
                weakest = Some((k, c.refit_gain));
            }
        }
        if let Some((k, _)) = weakest {
            selection.candidates[k].named = false;
            continue;
        }
        selection.final_model = model;
        break;
    }
    validate_stage(prep, th, &mut selection)?;
    Ok(selection)
}

/// The terms whose only evidence is the validate recordings, judged on
/// their deciding half on top of the model the fit recordings chose
/// ([`super::validate_terms`]); the named ones join the final model. Their
/// real form has no free coefficient (the searched value only), so there is
/// no linearised stand-in to refit.
fn validate_stage(prep: &Prepared, th: &Thresholds, selection: &mut Selection) -> Result<()> {
    if prep.validate_evidence {
        return Ok(());
    }
    let on = selection.final_model.terms;
    let mut added = Terms::default();
    for &t in super::terms::REGISTRY.iter().filter(|t| t.validate_only()) {
        if super::candidates::identifiable(prep, t.effect(), th).is_err() {
            continue;
        }
        let Some(j) = validate_terms::judge(prep, t, &on, th)? else {
            continue;
        };
        let named = j.improved_share >= th.min_inclusion && j.gain.ratio >= th.min_nested_gain;
        if named {
            added = added.merged(j.own);
        }
        selection.validate_read.extend(&j.split.deciding);
        selection.candidates.push(Candidate {
            effect: t.effect(),
            own: j.own,
            linearised: false,
            inclusion: j.improved_share,
            share: f64::NAN,
            refit_gain: if named { j.gain.ratio } else { f64::NAN },
            gain: j.gain,
            gain_plain: j.gain_plain,
            // Not in the quartics' span: it changes nothing they are fitted to.
            outside_baseline: 1.0,
            named,
            decided_by: j.split.deciding,
            checked_by: j.split.checking,
        });
    }
    selection.validate_read.sort_unstable();
    selection.validate_read.dedup();
    if added != Terms::default() {
        selection.final_model = score(prep, &[on.merged(added)])?;
    }
    Ok(())
}
