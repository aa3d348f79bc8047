//! The library stage: one joint design holding the paper's per-current
//! branch quartics and every identifiable term's candidate columns, over the
//! recordings the decision may read, compressed per recording (the R factor
//! of the QR of `[A | y]`, see [`super::sparse`]).
//!
//! A term's nonlinear parameter (a knee, a stop position, a delay) is chosen
//! first, the term alone on top of the reference term (`hysteresis_memory`),
//! by grouped cross-validation ([`super::cv::score_refined`]). A term with
//! linear columns ([`Term::blocks`]) brings them as its group. A term that
//! transforms the inputs or scales the force (a delay, a coil lag, current
//! saturation, softening) enters linearised, as one regressor: what it
//! changes in the prediction of the joint fit without it (a lagged or
//! filtered copy of that prediction, NARX-style). Its coefficient is 1 when
//! the term is there at the chosen value. A crossed term (softening) keeps
//! only the part of its regressor a gain per test condition cannot explain
//! ([`Term::crossed`]); one crossed by recording (a decline within each
//! test) keeps only what a gain per recording cannot explain.
use super::acceptance::Thresholds;
use super::candidates::{self, Effect};
use super::cv::score_refined;
use super::design::{Designs, Terms, QUARTIC_TERMS};
use super::prepared::Prepared;
use super::sparse::{Group, Library};
use super::terms::{Crossing, Term, REGISTRY};
use anyhow::Result;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// One term in the library.
#[derive(Clone, Copy)]
pub struct Candidate {
    pub term: &'static dyn Term,
    /// The term alone at its chosen value (on the paper's model).
    pub own: Terms,
    /// Index of its group in [`Library::groups`].
    pub group: usize,
    /// It enters as one linearised regressor, not its own columns.
    pub linearised: bool,
}

impl std::fmt::Debug for Candidate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (group {})", self.term.effect().name(), self.group)
    }
}

/// The library and what it was built from.
#[derive(Clone, Debug)]
pub struct Built {
    pub lib: Library,
    pub candidates: Vec<Candidate>,
    /// Effects the data cannot separate from the baseline, with what would.
    pub not_identifiable: Vec<(Effect, String)>,
    /// Per recording of `prep`: its cross-validation fold in the library
    /// (`None` when it is not in the library).
    pub fold_of: Vec<Option<usize>>,
}

/// A linearised regressor per library recording and sample, and the
/// samples its model scores.
type Linearised = (Vec<Vec<f64>>, Vec<Vec<bool>>);

/// `t` with every registered term but `term` removed.
pub fn only(term: &dyn Term, t: Terms) -> Terms {
    REGISTRY
        .iter()
        .filter(|o| o.effect() != term.effect())
        .fold(t, |acc, o| o.removed_from(&acc))
}

/// Chooses `term`'s value on top of `on` by grouped cross-validation.
fn choose(prep: &Prepared, term: &'static dyn Term, on: &Terms) -> Option<Terms> {
    let variants = term.variants(prep, on);
    match score_refined(prep, variants, &|best| term.refinements(prep, best)) {
        Ok(s) => Some(only(term, s.terms)),
        Err(why) => {
            eprintln!("note: {} was not tested: {why:#}", term.effect().name());
            None
        }
    }
}

/// Keeps only the part of a crossed term's regressor ([`Term::crossed`])
/// that a gain per test condition ([`candidates::conditions`]), or per
/// recording, on the prediction without the term cannot explain: within
/// each condition (recording), `c_r − k_c·b_r` with `k_c` the least-squares
/// gain of its fit recordings. A condition run once, or a per-test gain,
/// leaves nothing; a library recording whose condition has no fit recording
/// (a validate one read as evidence) gets a zero regressor.
fn cross(
    prep: &Prepared,
    by: Crossing,
    recs: &[usize],
    cols: &mut [Vec<f64>],
    bases: &[Vec<f64>],
    masks: &[Vec<bool>],
) {
    let cond = match by {
        Crossing::No => return,
        Crossing::ByMotion => return cross_by_motion(prep, recs, cols, bases, masks),
        Crossing::ByCondition => candidates::conditions(prep),
        Crossing::ByRecording => (0..prep.recs.len()).collect(),
    };
    let mut sums: std::collections::BTreeMap<usize, (f64, f64)> = std::collections::BTreeMap::new();
    for (j, &i) in recs.iter().enumerate().filter(|(_, &i)| prep.recs[i].is_fit()) {
        let e = sums.entry(cond[i]).or_insert((0.0, 0.0));
        for t in (0..masks[j].len()).filter(|&t| masks[j][t]) {
            e.0 += cols[j][t] * bases[j][t];
            e.1 += bases[j][t] * bases[j][t];
        }
    }
    for (j, &i) in recs.iter().enumerate() {
        match sums.get(&cond[i]) {
            Some(&(cb, bb)) if bb > 0.0 => {
                let k = cb / bb;
                for (c, b) in cols[j].iter_mut().zip(&bases[j]) {
                    *c -= k * b;
                }
            }
            _ => cols[j].iter_mut().for_each(|c| *c = 0.0),
        }
    }
}

/// [`Crossing::ByMotion`]: at each sample t of the runs of one motion,
/// `c_r(t) − k(t)·b_r(t)` with `k(t)` the least-squares gain of the fit
/// runs' `c` on `b` at that sample. Whatever is a common function of the
/// motion times the force (an effect of the test's own amplitude, the same
/// at every current) leaves nothing; a difference between runs (one after a
/// larger test, one before) is left.
fn cross_by_motion(prep: &Prepared, recs: &[usize], cols: &mut [Vec<f64>], bases: &[Vec<f64>], masks: &[Vec<bool>]) {
    let group = candidates::same_motion(prep);
    let n_groups = group.iter().flatten().max().map_or(0, |g| g + 1);
    let mut left = vec![false; recs.len()];
    for g in 0..n_groups {
        let members: Vec<usize> = (0..recs.len()).filter(|&j| group[recs[j]] == Some(g)).collect();
        let n = members.iter().map(|&j| cols[j].len()).min().unwrap_or(0);
        for t in 0..n {
            let (cb, bb) = members
                .iter()
                .filter(|&&j| masks[j][t] && prep.recs[recs[j]].is_fit())
                .fold((0.0, 0.0), |(cb, bb), &j| {
                    (cb + cols[j][t] * bases[j][t], bb + bases[j][t] * bases[j][t])
                });
            for &j in &members {
                cols[j][t] = if bb > 0.0 {
                    cols[j][t] - cb / bb * bases[j][t]
                } else {
                    0.0
                };
            }
        }
        for &j in &members {
            cols[j][n..].iter_mut().for_each(|c| *c = 0.0);
            left[j] = true;
        }
    }
    for (j, col) in cols.iter_mut().enumerate() {
        if !left[j] {
            col.iter_mut().for_each(|c| *c = 0.0);
        }
    }
}

/// Builds the library for `prep` (see the module docs).
pub fn build(prep: &Prepared, th: &Thresholds) -> Result<Built> {
    let mut testable: Vec<&'static dyn Term> = Vec::new();
    let mut not_identifiable = Vec::new();
    for &t in REGISTRY {
        match candidates::identifiable(prep, t.effect(), th) {
            // Decided after the joint fit, on part of its validate recordings
            // ([`super::validate_terms`]).
            Ok(()) if t.validate_only() && !th.validate_evidence => {}
            Ok(()) => testable.push(t),
            Err(needs) => not_identifiable.push((t.effect(), needs)),
        }
    }
    // The reference term first: the others' values are chosen on top of it,
    // since a delay or a knee chosen against the bare quartics mimics the
    // turn-around the quartics cannot follow.
    let reference: Vec<(&'static dyn Term, Terms)> = testable
        .iter()
        .filter(|t| t.is_reference())
        .filter_map(|&t| choose(prep, t, &Terms::default()).map(|own| (t, own)))
        .collect();
    let on = reference
        .iter()
        .fold(Terms::default(), |acc, (_, own)| acc.merged(*own));
    let others: Vec<(&'static dyn Term, Terms)> = testable
        .par_iter()
        .filter(|t| !t.is_reference())
        .filter_map(|&t| choose(prep, t, &on).map(|own| (t, own)))
        .collect();
    let mut chosen = reference;
    chosen.extend(others);
    let joint = chosen.iter().fold(Terms::default(), |acc, (_, own)| acc.merged(*own));
    let linearised: Vec<bool> = chosen.iter().map(|(t, _)| t.blocks(&joint).is_empty()).collect();
    let base = chosen
        .iter()
        .zip(&linearised)
        .filter(|(_, l)| **l)
        .fold(joint, |acc, ((t, _), _)| t.removed_from(&acc));
    let d = Designs::build(prep, &base);
    let fit = prep.fit_indices();
    let mut recs = fit.clone();
    if prep.validate_evidence {
        recs.extend(prep.validate_indices());
    }
    let mut fold_of = vec![None; prep.recs.len()];
    for (j, &i) in recs.iter().enumerate() {
        // Each validate recording read as evidence is a fold of its own.
        fold_of[i] = Some(prep.recs[i].fold.unwrap_or(prep.n_folds + j));
    }
    // The linearised regressors, each about the fit of the reference model
    // (quartics and `hysteresis_memory`) *with* the term: `A_t·β_t − A_r·β_t`,
    // what the term changes in that fit's prediction. When the term is
    // there, `y ≈ A_r·β_t + 1·column`, so no other group needs to stand in
    // for it. (About the joint fit without it, the column came from groups
    // already bent towards a delay, and they kept their share; about the
    // quartics alone, a delay on a hysteretic law left most of the lag to
    // the memory basis and was missed on every MTS campaign tried.)
    let lin_terms: Vec<(&'static dyn Term, Terms)> = chosen
        .iter()
        .zip(&linearised)
        .filter(|(_, l)| **l)
        .map(|((t, own), _)| (*t, *own))
        .collect();
    let reference = if lin_terms.is_empty() {
        None
    } else {
        Some(Designs::build(prep, &on))
    };
    // Each with the samples its own model scores (a delay moves the
    // branch-ambiguous samples at each turn-around).
    let lin_cols: Vec<Linearised> = lin_terms
        .par_iter()
        .map(|(term, own)| -> Result<Linearised> {
            let dq = reference
                .as_ref()
                .ok_or_else(|| anyhow::anyhow!("no reference design"))?;
            let dt = Designs::build(prep, &on.merged(*own));
            let sol = dt.solve(prep, &fit)?;
            let mut without = sol.clone();
            without.delta = 0.0;
            let (mut cols, bases): (Vec<Vec<f64>>, Vec<Vec<f64>>) = recs
                .iter()
                .map(|&i| {
                    let a = dt.predict(prep, i, &sol);
                    let b = dq.predict(prep, i, &without);
                    (a.iter().zip(&b).map(|(a, b)| a - b).collect(), b)
                })
                .unzip();
            let masks: Vec<Vec<bool>> = recs.iter().map(|&i| dt.recs[i].mask.clone()).collect();
            cross(prep, term.crossed(own), &recs, &mut cols, &bases, &masks);
            Ok((cols, masks))
        })
        .collect::<Result<_>>()?;
    let p0 = d.layout.n_cols;
    let p = p0 + lin_terms.len();
    // Groups: the quartics, then each candidate's.
    let n_quartic = d.layout.n_currents * 2 * QUARTIC_TERMS;
    let mut groups = vec![Group {
        name: "baseline quartics".into(),
        cols: (0..n_quartic).collect(),
        always: true,
        nonnegative: false,
    }];
    let mut candidates_out = Vec::new();
    let mut next_lin = p0;
    for ((t, own), &lin) in chosen.iter().zip(&linearised) {
        let cols: Vec<usize> = if lin {
            next_lin += 1;
            vec![next_lin - 1]
        } else {
            d.layout
                .blocks
                .iter()
                .filter(|b| b.term.effect() == t.effect())
                .flat_map(|b| {
                    let end = d
                        .layout
                        .blocks
                        .iter()
                        .map(|q| q.at)
                        .filter(|&a| a > b.at)
                        .min()
                        .unwrap_or(p0);
                    b.at..end
                })
                .collect()
        };
        candidates_out.push(Candidate {
            term: *t,
            own: *own,
            group: groups.len(),
            linearised: lin,
        });
        let blocks = t.blocks(&joint);
        groups.push(Group {
            name: t.effect().name().into(),
            cols,
            always: false,
            nonnegative: !lin && !blocks.is_empty() && (0..blocks.len()).all(|b| t.nonnegative(&joint, b)),
        });
    }
    // Compress each recording's rows to the R factor of its [A | y].
    let packed: Vec<(usize, DMatrix<f64>, Vec<usize>)> = recs
        .par_iter()
        .enumerate()
        .map(|(j, &i)| {
            let rd = &d.recs[i];
            // The samples every model of the library scores.
            let rows: Vec<usize> = (0..rd.mask.len())
                .filter(|&t| rd.mask[t] && lin_cols.iter().all(|(_, m)| m[j][t]))
                .collect();
            let mut cols = rd.cols.clone();
            cols.extend(p0..p);
            let c = cols.len();
            let mut m = DMatrix::<f64>::zeros(rows.len(), c + 1);
            for (k, &t) in rows.iter().enumerate() {
                for l in 0..rd.cols.len() {
                    m[(k, l)] = rd.a[(t, l)];
                }
                for (q, (col, _)) in lin_cols.iter().enumerate() {
                    m[(k, rd.cols.len() + q)] = col[j][t];
                }
                m[(k, c)] = prep.recs[i].force_n[t];
            }
            (i, m.qr().r(), cols)
        })
        .collect();
    let n_rows: usize = packed.iter().map(|(_, r, _)| r.nrows()).sum();
    let mut a = DMatrix::<f64>::zeros(n_rows, p);
    let mut y = DVector::<f64>::zeros(n_rows);
    let mut recording_of_row = Vec::with_capacity(n_rows);
    let mut at = 0;
    for (i, r, cols) in &packed {
        for row in 0..r.nrows() {
            for (l, &g) in cols.iter().enumerate() {
                a[(at + row, g)] = r[(row, l)];
            }
            y[at + row] = r[(row, cols.len())];
            recording_of_row.push(*i);
        }
        at += r.nrows();
    }
    Ok(Built {
        lib: Library {
            a,
            y,
            recording_of_row,
            groups,
        },
        candidates: candidates_out,
        not_identifiable,
        fold_of,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::{Dataset, Recording, Role, Samples};
    use crate::diagnose::design::SofteningLaw;
    use crate::diagnose::prepared::{prepare, FoldPlan};

    /// Evidence: hand-written. Three recordings of one condition, 4 cycles
    /// each; the reference fit's prediction b is the displacement times 100.
    /// A regressor that is a constant gain per recording times b, (γ_r − 1)·b
    /// with γ = 0.9, 1.0, 1.1, is left with nothing when crossed by
    /// recording, and kept whole uncrossed; a decline within each test,
    /// −g(k)·b, keeps what a per-recording gain cannot explain.
    #[test]
    fn crossing_by_recording_leaves_nothing_of_a_constant_gain_per_test() {
        let n = 400;
        let x: Vec<f64> = (0..n)
            .map(|t| 5.0 * (2.0 * std::f64::consts::PI * t as f64 / 100.0).sin())
            .collect();
        let rec = |k: usize| Recording {
            file: format!("r{k}.csv"),
            current_a: 0.0,
            role: Role::Fit,
            mass_kg: None,
            impact_velocity_m_s: None,
            sequence: None,
            temperature_c: None,
            tags: Default::default(),
            samples: Samples {
                time_s: (0..n).map(|t| t as f64 * 0.01).collect(),
                x_mm: x.clone(),
                v_m_s: (0..n)
                    .map(|t| 0.5 * 2.0 * std::f64::consts::PI * (2.0 * std::f64::consts::PI * t as f64 / 100.0).cos())
                    .collect(),
                force_n: x.iter().map(|x| 100.0 * x).collect(),
                ..Samples::default()
            },
            velocity_estimated: false,
            motion_from: None,
            notes: Vec::new(),
        };
        let ds = Dataset {
            name: "crossing".into(),
            root: Default::default(),
            recordings: (0..3).map(rec).collect(),
        };
        let prep = prepare(&ds, &FoldPlan::Stratified { k: 3 }, &[]).expect("prepared");
        let recs: Vec<usize> = (0..3).collect();
        let bases: Vec<Vec<f64>> = recs.iter().map(|_| x.iter().map(|x| 100.0 * x).collect()).collect();
        let masks = vec![vec![true; n]; 3];
        let gains = [0.9, 1.0, 1.1];
        let gain_cols = || -> Vec<Vec<f64>> {
            (0..3)
                .map(|r| bases[r].iter().map(|b| (gains[r] - 1.0) * b).collect())
                .collect()
        };
        let size = |cols: &[Vec<f64>]| cols.iter().flatten().map(|c| c * c).sum::<f64>().sqrt();
        let mut crossed = gain_cols();
        cross(&prep, Crossing::ByRecording, &recs, &mut crossed, &bases, &masks);
        assert!(size(&crossed) < 1e-9 * size(&gain_cols()), "{}", size(&crossed));
        let mut plain = gain_cols();
        cross(&prep, Crossing::No, &recs, &mut plain, &bases, &masks);
        assert_eq!(plain, gain_cols());
        // The per-cycle decline: g(k) at k0 = 1 cycle.
        let g = SofteningLaw::Cycle { k0: 1.0 }.per_sample(&prep.recs[0]);
        let decline: Vec<Vec<f64>> = (0..3)
            .map(|r| bases[r].iter().zip(&g).map(|(b, g)| -g * b).collect())
            .collect();
        let mut kept = decline.clone();
        cross(&prep, Crossing::ByRecording, &recs, &mut kept, &bases, &masks);
        assert!(
            size(&kept) > 0.2 * size(&decline),
            "{} of {}",
            size(&kept),
            size(&decline)
        );
    }

    /// Evidence: hand-written. One motion (5 mm, 4 cycles) run at 0, 0.5
    /// and 1 A, and a 3 mm motion run once; the prediction b_r is x times
    /// 100, 200, 300 N/mm. A regressor that is a common function of the
    /// motion times b, κ(t)·b_r with κ = 0.1·(1 − x²/25) (softer below the
    /// test's own peak, the same at every current), is left with nothing
    /// crossed by motion; a softening of the runs made after a larger test
    /// only, −g_r·b_r with g = 0, 0.3, 0.3, keeps the difference between
    /// runs; the motion run once keeps nothing.
    #[test]
    fn crossing_by_motion_leaves_only_the_difference_between_runs() {
        let n = 400;
        let w = 2.0 * std::f64::consts::PI / 100.0;
        let rec = |k: usize, amp_mm: f64, current_a: f64| Recording {
            file: format!("r{k}.csv"),
            current_a,
            role: Role::Fit,
            mass_kg: None,
            impact_velocity_m_s: None,
            sequence: Some(k as u32 + 1),
            temperature_c: None,
            tags: Default::default(),
            samples: Samples {
                time_s: (0..n).map(|t| t as f64 * 0.01).collect(),
                x_mm: (0..n).map(|t| amp_mm * (w * t as f64).sin()).collect(),
                v_m_s: (0..n).map(|t| amp_mm * 0.1 * w * (w * t as f64).cos()).collect(),
                force_n: (0..n).map(|t| 100.0 * amp_mm * (w * t as f64).sin()).collect(),
                ..Samples::default()
            },
            velocity_estimated: false,
            motion_from: None,
            notes: Vec::new(),
        };
        let ds = Dataset {
            name: "crossing by motion".into(),
            root: Default::default(),
            recordings: vec![rec(0, 5.0, 0.0), rec(1, 5.0, 0.5), rec(2, 5.0, 1.0), rec(3, 3.0, 0.0)],
        };
        let prep = prepare(&ds, &FoldPlan::Stratified { k: 2 }, &[]).expect("prepared");
        let recs: Vec<usize> = (0..4).collect();
        let stiffness = [100.0, 200.0, 300.0, 100.0];
        let bases: Vec<Vec<f64>> = (0..4)
            .map(|r| prep.recs[r].x_mm.iter().map(|x| stiffness[r] * x).collect())
            .collect();
        let masks = vec![vec![true; n]; 4];
        let size = |cols: &[Vec<f64>]| cols.iter().flatten().map(|c| c * c).sum::<f64>().sqrt();
        let own: Vec<Vec<f64>> = (0..4)
            .map(|r| {
                prep.recs[r]
                    .x_mm
                    .iter()
                    .zip(&bases[r])
                    .map(|(x, b)| 0.1 * (1.0 - x * x / 25.0) * b)
                    .collect()
            })
            .collect();
        let mut crossed = own.clone();
        cross(&prep, Crossing::ByMotion, &recs, &mut crossed, &bases, &masks);
        assert!(size(&crossed) < 1e-9 * size(&own), "{}", size(&crossed));
        let g = [0.0, 0.3, 0.3, 0.3];
        let history: Vec<Vec<f64>> = (0..4).map(|r| bases[r].iter().map(|b| -g[r] * b).collect()).collect();
        let mut kept = history.clone();
        cross(&prep, Crossing::ByMotion, &recs, &mut kept, &bases, &masks);
        // At each sample k = −0.3·(200² + 300²)/(100² + 200² + 300²) = −0.279:
        // the first run keeps 0.279·b, the others −0.021·b.
        let k = -0.3 * (4.0 + 9.0) / 14.0;
        for t in [25, 130] {
            assert!((kept[0][t] - (-k) * bases[0][t]).abs() < 1e-9 * bases[0][t].abs().max(1.0));
            assert!((kept[2][t] - (-0.3 - k) * bases[2][t]).abs() < 1e-9 * bases[2][t].abs().max(1.0));
        }
        assert!(kept[3].iter().all(|c| *c == 0.0));
    }
}
