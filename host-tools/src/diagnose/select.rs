//! Forward selection: effects join the model one at a time, each round
//! scoring every candidate on the current model out of sample
//! ([`super::cv`]) and adding the best of those accepted
//! ([`super::acceptance`]).
use super::acceptance::{accepts, bootstrap_ratio_ci95, compare, judge, scoring_units, Comparison, Thresholds};
use super::candidates::{self, Effect};
use super::cv::{score, score_refined, Scored};
use super::design::Terms;
use super::prepared::Prepared;
use super::scale::ScaleTest;
use anyhow::Result;

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
