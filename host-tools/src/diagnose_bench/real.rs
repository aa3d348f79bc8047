//! `mre bench-diagnose --real DATASET`: the diagnosis proven on real
//! recordings. Each case injects one effect that can honestly be added to a
//! measured force (a delay in time units, an end stop at either end of the
//! stroke, softening over a random recorded run order, inertia, saturation
//! where validate currents sit between the tabulated ones, or nothing) at a
//! random strength of 3–15 % of the force RMS, diagnoses the result blind,
//! and scores it against what the untouched recordings already give.
//!
//! The injections are written from the physics and call nothing of the
//! estimator (issue 38: an injection through the estimator's own shapes
//! proves only that it finds its own columns): the stop is a Hunt–Crossley
//! contact, softening is Mullins damage carried through the run in its
//! recorded order, saturation follows Fröhlich–Kennelly flux between two
//! least-squares quartics of the product's fit (`fit::lsq`), and the delay
//! interpolates the force in time with its own code. The laws are the
//! outside-class plants' (`plant::outside`), which never call the estimator.
use super::oracle::{oracle, Amplitude, Oracle};
use crate::dataset::{Dataset, Role};
use crate::diagnose::design::Terms;
use crate::diagnose::{diagnose, DiagnoseOptions};
use crate::plant::outside::hunt_crossley::HuntCrossley;
use crate::plant::outside::mullins::{Mullins, MullinsState};
use crate::plant::outside::saturation::FieldGain;
use crate::vocabulary::{names, Effect};
use anyhow::{bail, Result};
use mre_algorithm::model::Branch;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

/// Injected strengths: RMS of the added force over RMS of the force, all samples.
pub const STRENGTH_RANGE: std::ops::Range<f64> = 0.03..0.15;
/// Strength from which the target (≥ 90 % found) applies.
pub const TARGET_STRENGTH: f64 = 0.05;

/// One injection with the parameters that realise its strength.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Injection {
    pub effect: Effect,
    /// Requested strength (fraction of the force RMS).
    pub strength: f64,
    /// Strength actually reached (saturation is bounded by the data).
    pub achieved_strength: f64,
    pub parameters: BTreeMap<String, f64>,
}

/// One real-data case.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RealCase {
    pub case: usize,
    pub injection: Injection,
    /// Every accepted effect, in order of acceptance.
    pub found: Vec<Effect>,
    /// Accepted effects the untouched recordings do not give.
    pub new_found: Vec<Effect>,
    /// First of `new_found`, or `none`.
    pub top1: Effect,
    pub found_at_all: bool,
    /// `new_found` other than the injected effect.
    pub false_positives: Vec<Effect>,
    /// Held-out RMSE ratio of the injected effect's term, the choice between
    /// effects nested (absent when not found or `none`).
    pub heldout_improvement: Option<f64>,
    /// Held-out ratio of the oracle (the reference model given the true
    /// injected force as a column with a free amplitude, [`oracle`]) over
    /// its decision pool; 1 for `none`.
    pub oracle_held_out_ratio: f64,
    /// The oracle in full: its support numbers and the route it passes.
    pub oracle: Oracle,
    /// The same with the amplitude free per tabulated current (not the headline).
    pub oracle_per_current: Oracle,
    /// Every candidate tested, per round: `name ratio [ci lo, ci hi] ΔBIC`.
    pub tested: Vec<Vec<String>>,
    pub seconds: f64,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct RealSummary {
    pub dataset: String,
    /// What the untouched recordings give (not counted as false positives).
    pub untouched: Vec<Effect>,
    pub cases: Vec<RealCase>,
    /// Over injected (non-`none`) cases at strength ≥ [`TARGET_STRENGTH`].
    pub found_rate_at_target: f64,
    pub top1_rate_at_target: f64,
    /// Share of those the oracle can get accepted ([`Oracle::identifiable`]),
    /// and the share found among those it can.
    pub identifiable_rate_at_target: f64,
    pub found_rate_identifiable_at_target: f64,
    /// Over every injected case.
    pub found_rate: f64,
    pub top1_rate: f64,
    /// Share of `none` cases with any effect beyond the untouched data's.
    pub false_positive_rate_none: f64,
    /// Share of injected cases with an effect beyond the truth and the untouched data's.
    pub false_positive_rate_injected: f64,
    pub median_improvement: BTreeMap<String, f64>,
    pub max_seconds: f64,
}

/// Force RMS over every sample of every recording.
pub fn force_rms_n(ds: &Dataset) -> f64 {
    let (s, n) = ds
        .recordings
        .iter()
        .flat_map(|r| r.samples.force_n.iter())
        .fold((0.0, 0usize), |(s, n), f| (s + f * f, n + 1));
    (s / n.max(1) as f64).sqrt()
}

/// RMS over every sample of a per-recording added force.
fn added_rms_n(added: &[Vec<f64>]) -> f64 {
    let (s, n) = added
        .iter()
        .flatten()
        .fold((0.0, 0usize), |(s, n), f| (s + f * f, n + 1));
    (s / n.max(1) as f64).sqrt()
}

/// Bisection for the parameter `p` in `[lo, hi]` at which the (increasing)
/// strength `f(p)` equals `target`.
fn solve_increasing(f: &dyn Fn(f64) -> f64, target: f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// `F(t − τ)` of each recording, linearly interpolated in time (the first
/// sample held before the start): a delay in seconds, whatever the rate.
pub fn delayed_force(ds: &Dataset, delay_s: f64) -> Vec<Vec<f64>> {
    ds.recordings
        .iter()
        .map(|r| {
            let (t, f) = (&r.samples.time_s, &r.samples.force_n);
            // Samples are in time order: the bracket only moves forward.
            let mut k = 0;
            t.iter()
                .map(|&now| {
                    let at = now - delay_s;
                    if at <= t[0] {
                        return f[0];
                    }
                    while k + 1 < t.len() && t[k + 1] < at {
                        k += 1;
                    }
                    match t.get(k + 1) {
                        Some(&t1) if t1 > t[k] => f[k] + (at - t[k]) / (t1 - t[k]) * (f[k + 1] - f[k]),
                        _ => f[k],
                    }
                })
                .collect()
        })
        .collect()
}

/// Acceleration from the displacement channel (m/s²): a second difference
/// over about `span_s` on each side, so it is not the diagnosis's own
/// regressor (the derivative of the velocity channel).
pub fn acceleration_from_x(time_s: &[f64], x_mm: &[f64], span_s: f64) -> Vec<f64> {
    let n = x_mm.len();
    let dt = {
        let mut d: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).copied().unwrap_or(0.0)
    };
    if dt <= 0.0 || n < 3 {
        return vec![0.0; n];
    }
    let h = ((span_s / dt).round() as usize).clamp(1, (n - 1) / 2);
    (0..n)
        .map(|t| {
            let (a, b) = (t.saturating_sub(h), (t + h).min(n - 1));
            let m = (a + b) / 2;
            let (ta, tm, tb) = (time_s[a], time_s[m], time_s[b]);
            if tb - tm <= 0.0 || tm - ta <= 0.0 {
                return 0.0;
            }
            let slope_hi = (x_mm[b] - x_mm[m]) / (tb - tm);
            let slope_lo = (x_mm[m] - x_mm[a]) / (tm - ta);
            1e-3 * (slope_hi - slope_lo) / (0.5 * (tb - ta))
        })
        .collect()
}

/// The effects that can be injected into this data set under `opts`.
pub fn injectable(ds: &Dataset, opts: &DiagnoseOptions) -> Result<Vec<Effect>> {
    let mut out = vec![
        Effect::SensorDelay,
        Effect::EndStop,
        Effect::StressSoftening,
        Effect::Inertia,
    ];
    if saturation_pairs(ds, opts)?.len() >= 2 {
        out.push(Effect::MagneticSaturation);
    }
    out.push(Effect::None);
    Ok(out)
}

/// Whether a recording is only predicted under `opts` (its role, or its
/// current among the validate currents).
fn is_validate(r: &crate::dataset::Recording, opts: &DiagnoseOptions) -> bool {
    r.role_holding_out(&opts.validate_currents_a) == Role::Validate
}

/// Validate recordings strictly between two fit currents, with the bracket.
fn saturation_pairs(ds: &Dataset, opts: &DiagnoseOptions) -> Result<Vec<(usize, f64, f64)>> {
    let fit_currents = crate::dataset::distinct_currents_a(
        ds.recordings
            .iter()
            .filter(|r| !is_validate(r, opts))
            .map(|r| r.current_a),
    );
    Ok(ds
        .recordings
        .iter()
        .enumerate()
        .filter(|(_, r)| is_validate(r, opts))
        .filter_map(|(i, r)| {
            let cur = r.current_a;
            let k = fit_currents.iter().rposition(|&x| x < cur - 1e-9)?;
            let hi = *fit_currents.get(k + 1)?;
            (hi > cur + 1e-9).then_some((i, fit_currents[k], hi))
        })
        .collect())
}

/// The exact least-squares quartic (`fit::lsq`, the paper's model) of one
/// branch at one fit current, highest power first.
fn branch_quartic(ds: &Dataset, opts: &DiagnoseOptions, current_a: f64, compression: bool) -> Result<[f64; 5]> {
    let (mut x, mut f) = (Vec::new(), Vec::new());
    for r in ds
        .recordings
        .iter()
        .filter(|r| !is_validate(r, opts) && (r.current_a - current_a).abs() < 1e-9)
    {
        let s = &r.samples;
        for t in 0..s.len().min(s.v_m_s.len()) {
            if (Branch::from_velocity(s.v_m_s[t] as f32) == Branch::Compression) == compression {
                x.push(s.x_mm[t]);
                f.push(s.force_n[t]);
            }
        }
    }
    Ok(crate::fit::lsq::fit_quartic(&x, &f)?.coeffs)
}

/// A quartic, highest power first, at `x_mm` (Horner).
fn horner(c: &[f64; 5], x_mm: f64) -> f64 {
    c.iter().fold(0.0, |acc, k| acc * x_mm + k)
}

/// The force each recording of `injected` carries beyond `ds`'s (N).
pub fn added_force_n(ds: &Dataset, injected: &Dataset) -> Vec<Vec<f64>> {
    injected
        .recordings
        .iter()
        .zip(&ds.recordings)
        .map(|(a, b)| {
            a.samples
                .force_n
                .iter()
                .zip(&b.samples.force_n)
                .map(|(a, b)| a - b)
                .collect()
        })
        .collect()
}

/// Injects `effect` at `strength` (RMS of the added force over the force RMS).
pub fn inject(
    ds: &Dataset,
    effect: Effect,
    strength: f64,
    rng: &mut ChaCha8Rng,
    opts: &DiagnoseOptions,
) -> Result<(Dataset, Injection)> {
    let target = strength * force_rms_n(ds);
    let mut out = ds.clone();
    let mut params = BTreeMap::new();
    let added: Vec<Vec<f64>> = match effect {
        Effect::None => ds.recordings.iter().map(|r| vec![0.0; r.samples.len()]).collect(),
        Effect::SensorDelay => {
            let diff = |tau: f64| -> Vec<Vec<f64>> {
                delayed_force(ds, tau)
                    .into_iter()
                    .zip(&ds.recordings)
                    .map(|(d, r)| d.iter().zip(&r.samples.force_n).map(|(a, b)| a - b).collect())
                    .collect()
            };
            let tau = solve_increasing(&|tau| added_rms_n(&diff(tau)), target, 0.0, 0.05);
            params.insert("delay_s".into(), tau);
            diff(tau)
        }
        Effect::EndStop => {
            let (lo, hi) = ds
                .recordings
                .iter()
                .flat_map(|r| r.samples.x_mm.iter().copied())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
            let two_sided = lo < -0.3 * hi.abs();
            let lower = two_sided && rng.random_bool(0.5);
            let x_e = rng.random_range(0.6..0.85) * if lower { lo } else { hi };
            // One Hunt–Crossley contact for every current and both
            // directions, at k = 1 N/mmⁿ (scaled below); the lower stop is
            // the mirror image.
            let unit_contact = HuntCrossley {
                x_stop_mm: x_e.abs(),
                k_n_per_mm_n: 1.0,
                exponent: rng.random_range(1.3..1.7),
                alpha_s_per_mm: rng.random_range(0.002..0.01),
            };
            let side = if lower { -1.0 } else { 1.0 };
            let shape: Vec<Vec<f64>> = ds
                .recordings
                .iter()
                .map(|r| {
                    let s = &r.samples;
                    (0..s.len())
                        .map(|t| {
                            let v_mm_s = s.v_m_s.get(t).map_or(0.0, |v| 1e3 * v);
                            side * unit_contact.force_n(side * s.x_mm[t], side * v_mm_s)
                        })
                        .collect()
                })
                .collect();
            let k = target / added_rms_n(&shape).max(1e-300);
            params.insert("x_e_mm".into(), x_e);
            params.insert("k_n_per_mm_n".into(), k);
            params.insert("exponent".into(), unit_contact.exponent);
            params.insert("alpha_s_per_mm".into(), unit_contact.alpha_s_per_mm);
            params.insert("lower_end".into(), f64::from(u8::from(lower)));
            shape
                .into_iter()
                .map(|v| v.into_iter().map(|s| k * s).collect())
                .collect()
        }
        Effect::StressSoftening => {
            // Mullins damage through the recorded run order (assigned here):
            // the force of each sample times the Ogden–Roxburgh factor of the
            // run's strain history and the cumulative per-cycle damage, a
            // cycle per two velocity reversals; its depth scaled to the
            // strength. The whole measured force is softened (a real record
            // does not separate the elastomer's elastic part).
            let order = run_order(ds.recordings.len(), rng);
            for (r, n) in out.recordings.iter_mut().zip(&order) {
                r.sequence = Some(*n);
            }
            let w_top_mm2 = ds
                .recordings
                .iter()
                .flat_map(|r| r.samples.x_mm.iter())
                .fold(0.0f64, |m, x| m.max(0.5 * x * x))
                .max(1e-12);
            let law = Mullins {
                r: rng.random_range(1.5..4.0),
                m_mm2: rng.random_range(0.05..0.3) * w_top_mm2,
                d_inf: rng.random_range(0.05..0.2),
                n0_cycles: rng.random_range(10.0..30.0),
            };
            let mut in_run_order: Vec<usize> = (0..ds.recordings.len()).collect();
            in_run_order.sort_by_key(|&i| order[i]);
            let mut state = MullinsState::default();
            let mut unit: Vec<Vec<f64>> = vec![Vec::new(); ds.recordings.len()];
            for i in in_run_order {
                let s = &ds.recordings[i].samples;
                let mut last_sign = 0.0;
                unit[i] = (0..s.len())
                    .map(|t| {
                        let sign = s.v_m_s.get(t).map_or(0.0, |v| v.signum());
                        if sign != 0.0 {
                            if last_sign != 0.0 && sign != last_sign {
                                state.cycles += 0.5;
                            }
                            last_sign = sign;
                        }
                        (law.factor(&mut state, s.x_mm[t]) - 1.0) * s.force_n[t]
                    })
                    .collect();
            }
            // The softened force keeps at least 40 % of the measured one.
            let deepest = ds
                .recordings
                .iter()
                .zip(&unit)
                .flat_map(|(r, u)| r.samples.force_n.iter().zip(u))
                .filter(|(f, _)| f.abs() > 0.0)
                .fold(0.0f64, |m, (f, u)| m.max(-u / f));
            let depth = (target / added_rms_n(&unit).max(1e-300)).min(0.6 / deepest.max(1e-12));
            params.insert("depth".into(), depth);
            params.insert("ogden_roxburgh_r".into(), law.r);
            params.insert("ogden_roxburgh_m_mm2".into(), law.m_mm2);
            params.insert("damage_d_inf".into(), law.d_inf);
            params.insert("damage_n0_cycles".into(), law.n0_cycles);
            unit.into_iter()
                .map(|v| v.into_iter().map(|s| depth * s).collect())
                .collect()
        }
        Effect::Inertia => {
            let acc: Vec<Vec<f64>> = ds
                .recordings
                .iter()
                .map(|r| acceleration_from_x(&r.samples.time_s, &r.samples.x_mm, 5e-3))
                .collect();
            let m = target / added_rms_n(&acc).max(1e-300);
            params.insert("m_s_kg".into(), m);
            acc.into_iter()
                .map(|v| v.into_iter().map(|a| m * a).collect())
                .collect()
        }
        Effect::MagneticSaturation => {
            // Per affected recording: the force difference between the
            // bracketing currents at each sample, from the product's exact
            // least-squares quartic per current and branch on the fit
            // recordings (the paper's model, not the estimator).
            let pairs = saturation_pairs(ds, opts)?;
            let mut quartics: BTreeMap<(u64, bool), [f64; 5]> = BTreeMap::new();
            for &(_, lo, hi) in &pairs {
                for current_a in [lo, hi] {
                    for compression in [true, false] {
                        if let std::collections::btree_map::Entry::Vacant(slot) =
                            quartics.entry((current_a.to_bits(), compression))
                        {
                            slot.insert(branch_quartic(ds, opts, current_a, compression)?);
                        }
                    }
                }
            }
            let spans: Vec<(usize, f64, f64, f64, Vec<f64>)> = pairs
                .iter()
                .map(|&(i, lo, hi)| {
                    let r = &ds.recordings[i];
                    let s = &r.samples;
                    let span: Vec<f64> = (0..s.len())
                        .map(|t| {
                            let compression = Branch::from_velocity(s.v_m_s[t] as f32) == Branch::Compression;
                            let f = |c: f64| horner(&quartics[&(c.to_bits(), compression)], s.x_mm[t]);
                            f(hi) - f(lo)
                        })
                        .collect();
                    (i, r.current_a, lo, hi, span)
                })
                .collect();
            // Fröhlich–Kennelly flux, force ∝ B²: the share of the step
            // between the bracketing currents reached at `cur`, less the
            // linear interpolation's share.
            let build = |knee_a: f64| -> Vec<Vec<f64>> {
                let g = |c: f64| {
                    FieldGain {
                        per_a: 1.0,
                        knee_a: Some(knee_a),
                    }
                    .gain(c)
                };
                let mut added: Vec<Vec<f64>> = ds.recordings.iter().map(|r| vec![0.0; r.samples.len()]).collect();
                for (i, cur, lo, hi, span) in &spans {
                    let w = (g(*cur) - g(*lo)) / (g(*hi) - g(*lo)) - (cur - lo) / (hi - lo);
                    added[*i] = span.iter().map(|d| w * d).collect();
                }
                added
            };
            // A smaller knee saturates harder: strength falls as it grows.
            let imax = ds
                .recordings
                .iter()
                .map(|r| r.current_a.abs())
                .fold(0.0, f64::max)
                .max(1e-3);
            let knee_a = imax / solve_increasing(&|p| added_rms_n(&build(imax / p)), target, 0.2, 200.0);
            params.insert("frohlich_kennelly_knee_a".into(), knee_a);
            build(knee_a)
        }
        other => bail!("cannot inject `{other}` into real recordings"),
    };
    for (r, a) in out.recordings.iter_mut().zip(&added) {
        for (f, d) in r.samples.force_n.iter_mut().zip(a) {
            *f += d;
        }
    }
    if effect != Effect::StressSoftening {
        // Every case records a run order, so softening is always testable
        // and a `none` case checks that a random order invents nothing.
        let order = run_order(ds.recordings.len(), rng);
        for (r, n) in out.recordings.iter_mut().zip(order) {
            r.sequence = Some(n);
        }
    }
    let achieved_strength = added_rms_n(&added) / force_rms_n(ds).max(1e-300);
    Ok((
        out,
        Injection {
            effect,
            strength,
            achieved_strength,
            parameters: params,
        },
    ))
}

fn run_order(n: usize, rng: &mut ChaCha8Rng) -> Vec<u32> {
    let mut order: Vec<u32> = (1..=n as u32).collect();
    order.shuffle(rng);
    order
}

/// Runs `n_cases` cases on `ds`, the effects taken in turn, strengths drawn
/// from `seed`; `progress` is told about each case as it finishes.
pub fn run_real_bench(
    ds: &Dataset,
    n_cases: usize,
    seed: u64,
    only: &[String],
    opts: &DiagnoseOptions,
    mut progress: impl FnMut(&RealCase),
) -> Result<RealSummary> {
    let effects = injectable(ds, opts)?;
    if let Some(unknown) = only
        .iter()
        .find(|name| !Effect::from_name(name).is_some_and(|e| effects.contains(&e)))
    {
        bail!(
            "--only {unknown}: not an effect this data set can be injected with ({:?})",
            names(&effects)
        );
    }
    let untouched: Vec<Effect> = diagnose(ds, opts)?.findings.iter().map(|f| f.effect).collect();
    let mut cases = Vec::with_capacity(n_cases);
    for k in 0..n_cases {
        let mut rng = ChaCha8Rng::seed_from_u64(super::simulated::case_seed(seed, k));
        let effect = effects[k % effects.len()];
        if !only.is_empty() && !only.iter().any(|name| name == effect.name()) {
            continue;
        }
        let strength = rng.random_range(STRENGTH_RANGE);
        let (injected, injection) = inject(ds, effect, strength, &mut rng, opts)?;
        let start = Instant::now();
        let d = diagnose(&injected, opts)?;
        let seconds = start.elapsed().as_secs_f64();
        let added = added_force_n(ds, &injected);
        let reference = &reference_terms(&d.selection);
        let shared = oracle(&d.prep, reference, &added, &opts.thresholds, Amplitude::Shared)?;
        let per_current = oracle(&d.prep, reference, &added, &opts.thresholds, Amplitude::PerCurrent)?;
        let found: Vec<Effect> = d.findings.iter().map(|f| f.effect).collect();
        let new_found: Vec<Effect> = found.iter().filter(|e| !untouched.contains(e)).copied().collect();
        let truth = effect;
        let c = RealCase {
            case: k,
            top1: new_found.first().copied().unwrap_or(Effect::None),
            found_at_all: truth == Effect::None || found.contains(&truth),
            false_positives: new_found.iter().filter(|e| **e != truth).copied().collect(),
            heldout_improvement: d
                .findings
                .iter()
                .find(|f| f.effect == truth)
                .map(|f| f.heldout_improvement_nested),
            tested: vec![d
                .selection
                .candidates
                .iter()
                .map(|c| {
                    format!(
                        "{} inclusion {:.2}; nested {:.3} [{:.3}, {:.3}]; plain {:.3}{}",
                        c.effect.name(),
                        c.inclusion,
                        c.gain.ratio,
                        c.gain.ci95[0],
                        c.gain.ci95[1],
                        c.gain_plain,
                        if c.named { " named" } else { "" }
                    )
                })
                .collect()],
            injection,
            found,
            new_found,
            oracle_held_out_ratio: shared.held_out_ratio,
            oracle: shared,
            oracle_per_current: per_current,
            seconds,
        };
        progress(&c);
        cases.push(c);
    }
    Ok(summarize(&ds.name, untouched, cases))
}

/// The reference the oracle is compared against: the paper's model plus
/// `hysteresis_memory` when it was named (as `diagnose` found it).
fn reference_terms(sel: &crate::diagnose::select::Selection) -> Terms {
    sel.candidate(Effect::HysteresisMemory)
        .filter(|c| c.named)
        .map_or_else(Terms::default, |c| c.own)
}

fn rate(cases: &[&RealCase], ok: impl Fn(&RealCase) -> bool) -> f64 {
    if cases.is_empty() {
        return f64::NAN;
    }
    cases.iter().filter(|c| ok(c)).count() as f64 / cases.len() as f64
}

pub fn summarize(dataset: &str, untouched: Vec<Effect>, cases: Vec<RealCase>) -> RealSummary {
    let injected: Vec<&RealCase> = cases.iter().filter(|c| c.injection.effect != Effect::None).collect();
    let at_target: Vec<&RealCase> = injected
        .iter()
        .copied()
        .filter(|c| c.injection.achieved_strength >= TARGET_STRENGTH)
        .collect();
    let none: Vec<&RealCase> = cases.iter().filter(|c| c.injection.effect == Effect::None).collect();
    let mut median_improvement = BTreeMap::new();
    for c in &injected {
        median_improvement
            .entry(c.injection.effect.name().to_string())
            .or_insert_with(Vec::new)
            .push(c.heldout_improvement.unwrap_or(1.0));
    }
    let median_improvement = median_improvement
        .into_iter()
        .map(|(k, mut v)| {
            v.sort_by(f64::total_cmp);
            (k, v[v.len() / 2])
        })
        .collect();
    RealSummary {
        dataset: dataset.to_string(),
        found_rate_at_target: rate(&at_target, |c| c.found_at_all),
        top1_rate_at_target: rate(&at_target, |c| c.top1 == c.injection.effect),
        identifiable_rate_at_target: rate(&at_target, |c| c.oracle.identifiable()),
        found_rate_identifiable_at_target: rate(
            &at_target
                .iter()
                .copied()
                .filter(|c| c.oracle.identifiable())
                .collect::<Vec<_>>(),
            |c| c.found_at_all,
        ),
        found_rate: rate(&injected, |c| c.found_at_all),
        top1_rate: rate(&injected, |c| c.top1 == c.injection.effect),
        false_positive_rate_none: rate(&none, |c| !c.false_positives.is_empty()),
        false_positive_rate_injected: rate(&injected, |c| !c.false_positives.is_empty()),
        median_improvement,
        max_seconds: cases.iter().map(|c| c.seconds).fold(0.0, f64::max),
        untouched,
        cases,
    }
}

/// The printed summary: one row per effect, then the target figures.
pub fn format_real_summary(s: &RealSummary) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "real recordings: {}", s.dataset);
    let _ = writeln!(
        out,
        "untouched data give: {:?} (not counted as false positives)",
        names(&s.untouched)
    );
    let _ = writeln!(
        out,
        "{:<20} {:>5} {:>14} {:>14} {:>10} {:>16} {:>16} {:>14}",
        "injected",
        "cases",
        "found (≥5 %)",
        "top-1 (≥5 %)",
        "found all",
        "median held-out",
        "oracle (≥5 %)",
        "found|oracle"
    );
    // Rows in the order of the names, as the JSON's maps are.
    let mut injected: Vec<Effect> = s.cases.iter().map(|c| c.injection.effect).collect();
    injected.sort_by_key(|e| e.name());
    injected.dedup();
    for effect in injected {
        let name = effect.name();
        let all: Vec<&RealCase> = s.cases.iter().filter(|c| c.injection.effect == effect).collect();
        // `none` has no strength: its row counts cases with nothing invented.
        let strong: Vec<&RealCase> = all
            .iter()
            .copied()
            .filter(|c| effect == Effect::None || c.injection.achieved_strength >= TARGET_STRENGTH)
            .collect();
        let ok = |c: &RealCase| {
            if effect == Effect::None {
                c.false_positives.is_empty()
            } else {
                c.found_at_all
            }
        };
        let count = |v: &[&RealCase], ok: &dyn Fn(&RealCase) -> bool| {
            format!("{}/{}", v.iter().filter(|c| ok(c)).count(), v.len())
        };
        // Cases the oracle can get accepted, and how many of those were found.
        let identifiable: Vec<&RealCase> = strong.iter().copied().filter(|c| c.oracle.identifiable()).collect();
        let _ = writeln!(
            out,
            "{:<20} {:>5} {:>14} {:>14} {:>10} {:>15.2}× {:>16} {:>14}",
            name,
            all.len(),
            count(&strong, &ok),
            count(&strong, &|c| c.top1 == effect),
            count(&all, &ok),
            s.median_improvement.get(name).copied().unwrap_or(1.0),
            count(&strong, &|c| c.oracle.identifiable()),
            count(&identifiable, &ok)
        );
    }
    let _ = writeln!(
        out,
        "found at strength ≥ 5 %: {}; top-1: {}; all strengths: found {}, top-1 {}",
        percent(s.found_rate_at_target),
        percent(s.top1_rate_at_target),
        percent(s.found_rate),
        percent(s.top1_rate)
    );
    let _ = writeln!(
        out,
        "identifiable (the oracle passes a route) at strength ≥ 5 %: {}; found among those: {}",
        percent(s.identifiable_rate_at_target),
        percent(s.found_rate_identifiable_at_target)
    );
    let _ = writeln!(
        out,
        "false positives: {} of none cases, {} of injected cases; slowest diagnosis {:.2} s",
        percent(s.false_positive_rate_none),
        percent(s.false_positive_rate_injected),
        s.max_seconds
    );
    out
}

/// A rate as a percentage; "n/a" where no case of its kind was run (`--only`).
fn percent(rate: f64) -> String {
    if rate.is_nan() {
        "n/a".into()
    } else {
        format!("{:.1} %", 100.0 * rate)
    }
}
