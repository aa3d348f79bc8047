//! Forward selection: effects join the model one at a time, each round
//! scoring every candidate on the current model out of sample
//! ([`super::cv`]) and adding the best of those accepted
//! ([`super::acceptance`]), with its held-out ratio nested
//! ([`super::heldout`]).
use super::acceptance::{compare, Comparison, Thresholds};
use super::candidates::{self, Effect};
use super::cv::{score, score_refined, Scored};
use super::design::Terms;
use super::heldout::{nested_ratio, HeldOutRatio};
use super::prepared::Prepared;
use anyhow::Result;

/// One round of forward selection: every candidate tested on the current model.
#[derive(Clone, Debug)]
pub struct Round {
    pub tested: Vec<Comparison>,
    /// Index into `tested` of the accepted candidate, if any.
    pub accepted: Option<usize>,
    /// The accepted candidate's held-out ratio with the choice between
    /// candidates nested (see [`nested_ratio`]), and its interval.
    pub nested_ratio: Option<HeldOutRatio>,
}

/// The result of forward selection.
#[derive(Clone, Debug)]
pub struct Selection {
    pub baseline: Scored,
    /// The turn-around memory test (reference = baseline + memory if accepted).
    pub memory: Option<Comparison>,
    pub reference: Scored,
    pub rounds: Vec<Round>,
    /// `hysteresis_memory` tested again on top of every other accepted
    /// effect (the final model without it → with it): its own share of the
    /// held-out improvement. When it no longer passes, it was standing in for
    /// an effect found later (a delay shifts every turn-around) and is
    /// dropped from the final model.
    pub memory_share: Option<Comparison>,
    pub final_model: Scored,
    /// Effects the data cannot identify, with what would.
    pub not_identifiable: Vec<(Effect, String)>,
}

/// Adds effects one at a time, the best-scoring significant one first, until
/// no candidate passes the test.
pub fn forward_select(prep: &Prepared, th: &Thresholds) -> Result<Selection> {
    let baseline = score(prep, &[Terms::default()])?;
    // The reference: the paper's model, plus turn-around memory if the data
    // show it (a structural limit of one quartic per branch, not missing
    // physics from the vocabulary). Candidates are tested against it.
    let memory = score(prep, &candidates::memory_variants(prep))
        .map_err(|e| {
            eprintln!(
                "note: turn-around memory was not tested, so candidates are tested against the paper's model alone: {e:#}"
            )
        })
        .ok()
        .map(|after| compare(prep, &baseline, after, Some(Effect::HysteresisMemory), th));
    let reference = match &memory {
        Some(c) if c.accepted => c.scored.clone(),
        _ => baseline.clone(),
    };
    let mut current = reference.clone();
    let mut rounds = Vec::new();
    let mut not_identifiable = Vec::new();
    let mut testable = Vec::new();
    let mut untested: Vec<Effect> = Vec::new();
    for e in super::terms::candidates().map(|t| t.effect()) {
        match candidates::identifiable(prep, e, th) {
            Ok(()) => testable.push(e),
            Err(needs) => not_identifiable.push((e, needs)),
        }
    }
    loop {
        let todo: Vec<Effect> = testable
            .iter()
            .copied()
            .filter(|e| !super::terms::of(*e).is_some_and(|t| t.present_in(&current.terms)))
            .collect();
        if todo.is_empty() {
            break;
        }
        let mut tested = Vec::new();
        // Candidates carry the current terms at their full-data values in
        // every fold, while `current`'s own held-out errors came from each
        // fold's choice: compared with that, every candidate would gain the
        // same few per cent. So they are compared with the current terms
        // fixed the same way.
        let before = if rounds.is_empty() && memory.as_ref().is_none_or(|m| !m.accepted) {
            current.clone()
        } else {
            score(prep, &[current.terms])?
        };
        for e in todo {
            let variants = candidates::variants(prep, &current.terms, e);
            let refine = |best: &Terms| candidates::refinements(prep, best, e);
            match score_refined(prep, variants, &refine) {
                Ok(after) => tested.push(compare(prep, &before, after, Some(e), th)),
                // Once per effect and run, as a sentence.
                Err(why) if !untested.contains(&e) => {
                    eprintln!("note: {} was not tested: {why:#}", e.name());
                    untested.push(e);
                }
                Err(_) => {}
            }
        }
        let accepted = (0..tested.len())
            .filter(|&i| tested[i].accepted)
            .max_by(|&a, &b| tested[a].ratio_pool.total_cmp(&tested[b].ratio_pool));
        let next = accepted.map(|i| tested[i].scored.clone());
        let nested_ratio = accepted.map(|w| nested_ratio(prep, &tested, w, th));
        rounds.push(Round {
            tested,
            accepted,
            nested_ratio,
        });
        match next {
            Some(s) => current = s,
            None => break,
        }
    }
    let mut memory_share = None;
    let others_accepted = rounds.iter().any(|r| r.accepted.is_some());
    if memory.as_ref().is_some_and(|m| m.accepted) && others_accepted {
        let without =
            super::terms::of(Effect::HysteresisMemory).map_or(current.terms, |t| t.removed_from(&current.terms));
        let share = compare(
            prep,
            &score(prep, &[without])?,
            current.clone(),
            Some(Effect::HysteresisMemory),
            th,
        );
        if !share.accepted {
            current = score(prep, &[without])?;
        }
        memory_share = Some(share);
    }
    Ok(Selection {
        baseline,
        memory,
        reference,
        rounds,
        memory_share,
        final_model: current,
        not_identifiable,
    })
}
