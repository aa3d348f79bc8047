//! The validate stage: terms whose only evidence is the `validate`
//! recordings ([`Term::validate_only`]: a fit recording sits at a tabulated
//! current and holds it, so such a term changes none of its predictions).
//!
//! Each such term's evidence recordings ([`Term::evidence`]) are split in
//! two, in data-set order: every other one **decides** (at least two), the
//! rest are **kept as the check** ([`split`]). On the deciding recordings
//! the term is judged leave-one-recording-out on top of the model the fit
//! recordings chose: for each deciding recording its searched value is
//! chosen on the other deciding recordings, and the recording is predicted
//! with and without the term. The same two gates as the library's decide:
//! the share of deciding recordings on which it gains at least the gain
//! gate held out (each a fit of the ensemble, against
//! [`Thresholds::min_inclusion`]) and the nested gain
//! (against [`Thresholds::min_nested_gain`]). No checking recording, and no
//! validate recording outside every term's evidence, is read by a decision:
//! the report's independent validate RMSE is over those only.
use super::acceptance::Thresholds;
use super::cv::{first_best, score};
use super::design::Terms;
use super::heldout::HeldOutRatio;
use super::prepared::Prepared;
use super::terms::Term;
use anyhow::Result;

/// The two halves of a term's evidence recordings.
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    pub deciding: Vec<usize>,
    pub checking: Vec<usize>,
}

/// Every other recording of `evidence` is kept as the check, as long as at
/// least two decide (leave-one-out needs one to choose on and one to
/// score): 2 → 2 + 0, 3 → 2 + 1, 4 → 2 + 2, 6 → 3 + 3.
pub fn split(evidence: &[usize]) -> Split {
    let n_check = (evidence.len() / 2).min(evidence.len().saturating_sub(2));
    let (mut deciding, mut checking) = (Vec::new(), Vec::new());
    for (k, &i) in evidence.iter().enumerate() {
        if k % 2 == 1 && checking.len() < n_check {
            checking.push(i);
        } else {
            deciding.push(i);
        }
    }
    Split { deciding, checking }
}

/// The validate recordings a decision on `term` reads: its deciding half,
/// or every validate recording under `validate_evidence` (the library
/// route, where they are folds of the joint fit).
pub fn deciding(prep: &Prepared, term: &dyn Term) -> Vec<usize> {
    if prep.validate_evidence {
        prep.validate_indices()
    } else {
        split(&term.evidence(prep)).deciding
    }
}

/// One validate-only term, judged.
#[derive(Clone, Debug)]
pub struct Judged {
    /// The term alone at the value chosen on every deciding recording.
    pub own: Terms,
    /// Held-out SSE per deciding recording without → with the term, its
    /// value chosen without that recording.
    pub gain: HeldOutRatio,
    /// The same ratio with the value chosen on every deciding recording.
    pub gain_plain: f64,
    /// Share of the deciding recordings on which it gains at least
    /// [`Thresholds::min_nested_gain`] held out.
    pub improved_share: f64,
    pub split: Split,
}

/// Judges `term` on top of `on` (the model the fit recordings chose); `None`
/// when it has fewer than two evidence recordings.
pub fn judge(prep: &Prepared, term: &dyn Term, on: &Terms, th: &Thresholds) -> Result<Option<Judged>> {
    let split = split(&term.evidence(prep));
    let d = &split.deciding;
    if d.len() < 2 {
        return Ok(None);
    }
    // The linear coefficients are fitted on the fit recordings alone, where
    // the term changes nothing: each variant differs only in its searched
    // value, read here per recording from its full fit.
    let without = score(prep, &[term.removed_from(on)])?.variant_sse[0].1.clone();
    let mut table: Vec<(Terms, Vec<f64>)> = score(prep, &term.variants(prep, on))?.variant_sse;
    let n_grid = table.len();
    let sum_over = |t: &[(Terms, Vec<f64>)], v: usize, out: Option<usize>| {
        d.iter().filter(|&&i| Some(i) != out).map(|&i| t[v].1[i]).sum::<f64>()
    };
    let grid: Vec<usize> = (0..n_grid).collect();
    // Centres: the full choice, then each left-out recording's; each may
    // choose among the grid and refinements around its own centre only.
    let outs: Vec<Option<usize>> = std::iter::once(None).chain(d.iter().map(|&j| Some(j))).collect();
    let mut allowed: Vec<Vec<usize>> = Vec::new();
    let mut refined: Vec<(usize, Vec<usize>)> = Vec::new();
    for out in &outs {
        let mut a = grid.clone();
        if let Some(c) = first_best(&grid, |v| sum_over(&table, v, *out)) {
            if let Some((_, at)) = refined.iter().find(|(k, _)| *k == c) {
                a.extend(at);
            } else {
                let extra = term.refinements(prep, &table[c].0);
                let mut at = Vec::new();
                if !extra.is_empty() {
                    for (t, sse) in score(prep, &extra)?.variant_sse {
                        at.push(table.len());
                        table.push((t, sse));
                    }
                }
                a.extend(&at);
                refined.push((c, at));
            }
        }
        allowed.push(a);
    }
    let (mut before, mut after) = (Vec::new(), Vec::new());
    for (k, &j) in d.iter().enumerate() {
        let v = first_best(&allowed[1 + k], |v| sum_over(&table, v, Some(j))).unwrap_or(0);
        before.push(without[j]);
        after.push(table[v].1[j]);
    }
    // A left-out recording supports the term when the term gains at least
    // the gain gate on it alone: lowering its error a little is what any
    // re-weighting between currents does to a large misfit of another kind
    // (a fast Maxwell branch, seed 7224: 1.14×, 1.11× and 1.01×).
    let gate2 = th.min_nested_gain * th.min_nested_gain;
    let improved = before.iter().zip(&after).filter(|(b, a)| **b >= gate2 * **a).count();
    let full = first_best(&allowed[0], |v| sum_over(&table, v, None)).unwrap_or(0);
    let base: f64 = d.iter().map(|&i| without[i]).sum();
    let gain_plain = (base / sum_over(&table, full, None).max(1e-300)).sqrt();
    Ok(Some(Judged {
        own: super::library::only(term, table[full].0),
        gain: HeldOutRatio::over_every_recording(before, after, th),
        gain_plain,
        improved_share: improved as f64 / d.len() as f64,
        split,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-written: the halves alternate and at least two recordings decide.
    #[test]
    fn evidence_is_split_alternately_keeping_two_to_decide() {
        let s = |e: &[usize]| {
            let s = split(e);
            (s.deciding, s.checking)
        };
        assert_eq!(s(&[4, 9]), (vec![4, 9], vec![]));
        assert_eq!(s(&[1, 2, 3]), (vec![1, 3], vec![2]));
        assert_eq!(s(&[1, 2, 3, 4]), (vec![1, 3], vec![2, 4]));
        assert_eq!(s(&[0, 1, 2, 3, 4, 5]), (vec![0, 2, 4], vec![1, 3, 5]));
        assert_eq!(s(&[7]), (vec![7], vec![]));
        assert_eq!(s(&[]), (vec![], vec![]));
    }
}
