//! The candidates stage: which registered effects ([`super::terms`]) this
//! data set can identify, and the variants of each to search; with the facts
//! about the data the terms' identifiability tests and grids read.
use super::acceptance::Thresholds;
use super::design::Terms;
use super::prepared::Prepared;
use super::terms;

pub use super::terms::memory_variants;
pub use crate::vocabulary::Effect;

/// Knees v0 of the saturating rate terms, as fractions of the fastest test's
/// peak speed.
pub const KNEE_FRACTIONS: [f64; 4] = [0.05, 0.15, 0.4, 1.0];

/// The slowest and fastest peak speed of the fit recordings (m/s).
pub fn tested_speeds_m_s(prep: &Prepared) -> (f64, f64) {
    prep.fit_indices()
        .iter()
        .map(|&i| prep.recs[i].max_abs_v_m_s())
        .fold((f64::INFINITY, 0.0), |(l, h), v| (l.min(v), h.max(v)))
}

/// How much `v0·tanh(v/v0)` grows from the slowest to the fastest test's
/// peak speed (a linear term grows by `hi/lo`, a yield force by 1).
pub fn knee_growth(v0_m_s: f64, lo_m_s: f64, hi_m_s: f64) -> f64 {
    let phi = |v: f64| (v / v0_m_s).tanh();
    phi(hi_m_s) / phi(lo_m_s).max(1e-300)
}

/// Is the saturating term `v0·tanh(v/v0)` rate-dependent over the speeds
/// tested? Only if it grows by at least half the linear growth on a log
/// scale, `√(hi/lo)`: a knee well below the slowest test makes a force that
/// is the same at every speed, i.e. a yield or dry-friction force.
pub fn rate_dependent(v0_m_s: f64, lo_m_s: f64, hi_m_s: f64) -> bool {
    lo_m_s > 0.0 && hi_m_s > lo_m_s && knee_growth(v0_m_s, lo_m_s, hi_m_s) >= (hi_m_s / lo_m_s).sqrt()
}

/// Relative spread `(max − min)/max` of a per-recording quantity within each
/// current's fit recordings; the largest over currents.
pub fn spread_within_currents(prep: &Prepared, q: impl Fn(usize) -> f64) -> f64 {
    let mut best: f64 = 0.0;
    for &c in &prep.currents_a {
        let vals: Vec<f64> = prep
            .fit_indices()
            .into_iter()
            .filter(|&i| prep.recs[i].current_a == c)
            .map(&q)
            .collect();
        let (lo, hi) = vals
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
        if vals.len() >= 2 && hi > 0.0 {
            best = best.max((hi - lo) / hi);
        }
    }
    best
}

/// Lowest and highest displacement over the fit recordings (mm).
pub fn stroke_ends_mm(prep: &Prepared) -> (f64, f64) {
    prep.fit_indices()
        .iter()
        .flat_map(|&i| prep.recs[i].x_mm.iter().copied())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)))
}

/// A stroke that reaches well into both signs of x (a sinusoid about the
/// middle), not a drop that starts at contact (x ≥ 0 up to noise).
pub fn two_sided(xmin_mm: f64, xmax_mm: f64) -> bool {
    xmin_mm < -0.3 * xmax_mm.abs() && xmax_mm > 0.0
}

pub fn distinct_sequences(prep: &Prepared) -> usize {
    let mut s: Vec<f64> = prep
        .fit_indices()
        .iter()
        .filter_map(|&i| prep.recs[i].sequence)
        .collect();
    s.sort_by(f64::total_cmp);
    s.dedup();
    s.len()
}

/// Relative agreement of stroke and peak speed within which two recordings
/// at the same current are one test condition, repeated (a definition of
/// "the same test", not a rule fitted to any data).
pub const SAME_CONDITION: f64 = 0.10;

/// Each recording's test condition (an index into the conditions, in the
/// order they first appear): the same held current and current step, the
/// same role, and stroke and peak speed within [`SAME_CONDITION`] of the
/// condition's first recording. Read from the excitation only, never from
/// the force.
pub fn conditions(prep: &Prepared) -> Vec<usize> {
    let near = |a: f64, b: f64| (a - b).abs() <= SAME_CONDITION * a.abs().max(b.abs()).max(1e-12);
    let key = |i: usize| {
        let r = &prep.recs[i];
        (
            r.current_label(),
            r.is_fit(),
            r.max_x_mm() - r.min_x_mm(),
            r.max_abs_v_m_s(),
        )
    };
    let mut firsts: Vec<usize> = Vec::new();
    (0..prep.recs.len())
        .map(|i| {
            let (label, fit, stroke, speed) = key(i);
            match firsts.iter().position(|&f| {
                let (l, ff, s, v) = key(f);
                l == label && ff == fit && near(s, stroke) && near(v, speed)
            }) {
                Some(c) => c,
                None => {
                    firsts.push(i);
                    firsts.len() - 1
                }
            }
        })
        .collect()
}

/// Fit recordings that share their test condition with another fit
/// recording at a different place in the run order (`sequence`) or at a
/// different temperature: the recordings that cross the run order with the
/// test condition.
pub fn crossed_recordings(prep: &Prepared) -> usize {
    let cond = conditions(prep);
    let fit = prep.fit_indices();
    fit.iter()
        .filter(|&&i| {
            fit.iter().any(|&j| {
                j != i
                    && cond[j] == cond[i]
                    && (prep.recs[i]
                        .sequence
                        .zip(prep.recs[j].sequence)
                        .is_some_and(|(a, b)| a != b)
                        || prep.recs[i]
                            .temperature_c
                            .zip(prep.recs[j].temperature_c)
                            .is_some_and(|(a, b)| (a - b).abs() >= 0.5))
            })
        })
        .count()
}

/// Fit recordings that repeat one prescribed motion (the same x(t), sample
/// by sample, within [`SAME_CONDITION`] of the stroke over their common
/// length, the lengths within it too), whatever their current: the group of
/// each recording (in the order groups first appear), `None` for one that
/// shares its motion with no other. Read from the excitation only.
pub fn same_motion(prep: &Prepared) -> Vec<Option<usize>> {
    let fit = prep.fit_indices();
    let same = |i: usize, j: usize| {
        let (a, b) = (&prep.recs[i].x_mm, &prep.recs[j].x_mm);
        let n = a.len().min(b.len());
        let stroke = prep.recs[i].max_x_mm() - prep.recs[i].min_x_mm();
        n >= 8
            && (a.len().max(b.len()) - n) as f64 <= SAME_CONDITION * n as f64
            && stroke > 0.0
            && a[..n]
                .iter()
                .zip(&b[..n])
                .all(|(p, q)| (p - q).abs() <= SAME_CONDITION * stroke)
    };
    let mut group: Vec<Option<usize>> = vec![None; prep.recs.len()];
    let mut n_groups = 0;
    for (k, &i) in fit.iter().enumerate() {
        if group[i].is_some() {
            continue;
        }
        let partners: Vec<usize> = fit[k + 1..]
            .iter()
            .copied()
            .filter(|&j| group[j].is_none() && same(i, j))
            .collect();
        if !partners.is_empty() {
            group[i] = Some(n_groups);
            partners.iter().for_each(|&j| group[j] = Some(n_groups));
            n_groups += 1;
        }
    }
    group
}

/// The share of a test's own squared peak by which the run's largest
/// displacement before it must differ between two runs of one motion for
/// the strain history to differ between them (a definition, not tuned).
pub const HISTORY_CONTRAST: f64 = 0.2;

/// Groups of [`same_motion`] whose runs met different strain histories:
/// the run's largest |x| up to the end of each (before it, or its own
/// peak) differs by [`HISTORY_CONTRAST`] of the motion's squared peak, so
/// one ran after a larger test and another did not.
pub fn history_contrasts(prep: &Prepared) -> usize {
    let groups = same_motion(prep);
    let n_groups = groups.iter().flatten().max().map_or(0, |g| g + 1);
    (0..n_groups)
        .filter(|&g| {
            let members: Vec<&super::prepared::Rec> = (0..prep.recs.len())
                .filter(|&i| groups[i] == Some(g))
                .map(|i| &prep.recs[i])
                .collect();
            let peak = |r: &super::prepared::Rec| r.max_x_mm().abs().max(r.min_x_mm().abs());
            let run_peak2: Option<Vec<f64>> = members
                .iter()
                .map(|r| r.run_peak_before_mm.map(|b| b.max(peak(r)).powi(2)))
                .collect();
            let own2 = members.iter().map(|r| peak(r).powi(2)).fold(0.0, f64::max);
            run_peak2.is_some_and(|x2| {
                let (lo, hi) = x2
                    .iter()
                    .fold((f64::INFINITY, 0.0f64), |(l, h), v| (l.min(*v), h.max(*v)));
                hi - lo >= HISTORY_CONTRAST * own2
            })
        })
        .count()
}

pub fn temperature_span_c(prep: &Prepared) -> f64 {
    let t: Vec<f64> = prep
        .fit_indices()
        .iter()
        .filter_map(|&i| prep.recs[i].temperature_c)
        .collect();
    t.iter().copied().fold(f64::NEG_INFINITY, f64::max) - t.iter().copied().fold(f64::INFINITY, f64::min)
}

pub fn intermediate_validate_count(prep: &Prepared) -> usize {
    intermediate_validate(prep).len()
}

/// Validate recordings held at a current strictly between the lowest and
/// highest tabulated ones (predicted by interpolation).
pub fn intermediate_validate(prep: &Prepared) -> Vec<usize> {
    let (lo, hi) = (prep.currents_a[0], prep.currents_a[prep.currents_a.len() - 1]);
    prep.validate_indices()
        .into_iter()
        .filter(|&i| prep.recs[i].current_a > lo + 1e-9 && prep.recs[i].current_a < hi - 1e-9)
        .collect()
}

/// `Err(needs)` when this data set cannot separate the effect from the
/// baseline, with the test that would.
///
/// A term that changes only how validate currents are predicted
/// ([`terms::Term::validate_only`]) is identifiable when enough of its
/// evidence recordings exist; by default it is then decided on a part of
/// them ([`super::validate_terms`]), not in the library.
pub fn identifiable(prep: &Prepared, effect: Effect, th: &Thresholds) -> Result<(), String> {
    // No term: nothing to separate from the baseline.
    let Some(term) = terms::of(effect) else {
        return Ok(());
    };
    term.identifiable(prep, th)
}

/// How far the acceleration departs from an affine function of the measured
/// force, in units of what the two channels' noise alone would leave: the
/// RMS residual of `a = α + β·F` fitted over every fit recording, over
/// `√(σ_a² + β²·σ_F²)` (median white-noise estimates of the channels). A
/// one-mass drop's striker accelerometer records `a = g − F/M` and gives ≈ 1:
/// the force again, no evidence of inertia. A shaker, an MTS or two drop
/// masses give far more.
pub fn acceleration_misfit_over_noise(prep: &Prepared) -> f64 {
    let fit = prep.fit_indices();
    let (mut n, mut sf, mut sa, mut sff, mut sfa) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &i in &fit {
        let r = &prep.recs[i];
        for (f, a) in r.force_n.iter().zip(&r.a_m_s2) {
            n += 1.0;
            sf += f;
            sa += a;
            sff += f * f;
            sfa += f * a;
        }
    }
    if n < 3.0 {
        return 0.0;
    }
    let (mf, ma) = (sf / n, sa / n);
    let var_f = sff / n - mf * mf;
    let beta = if var_f > 0.0 { (sfa / n - mf * ma) / var_f } else { 0.0 };
    let alpha = ma - beta * mf;
    let mut sse = 0.0;
    for &i in &fit {
        let r = &prep.recs[i];
        for (f, a) in r.force_n.iter().zip(&r.a_m_s2) {
            let e = a - alpha - beta * f;
            sse += e * e;
        }
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    };
    let sigma_a = median(
        fit.iter()
            .map(|&i| crate::signal::white_noise_sd(&prep.recs[i].a_m_s2))
            .collect(),
    );
    let sigma_f = median(
        fit.iter()
            .map(|&i| crate::signal::white_noise_sd(&prep.recs[i].force_n))
            .collect(),
    );
    let noise = (sigma_a * sigma_a + beta * beta * sigma_f * sigma_f).sqrt();
    (sse / n).sqrt() / noise.max(1e-300)
}

/// Validate recordings whose recorded current moves by at least a tenth of
/// the table's current span during the test.
pub fn stepped_validate_count(prep: &Prepared) -> usize {
    stepped_validate(prep).len()
}

/// The validate recordings [`stepped_validate_count`] counts.
pub fn stepped_validate(prep: &Prepared) -> Vec<usize> {
    let span = prep.currents_a[prep.currents_a.len() - 1] - prep.currents_a[0];
    prep.validate_indices()
        .into_iter()
        .filter(|&i| span > 0.0 && prep.recs[i].current_change_a() >= 0.1 * span)
        .collect()
}

/// Extra variants around the grid's best, `best`, where the effect's grid is
/// too coarse ([`terms::Term::refinements`]).
pub fn refinements(prep: &Prepared, best: &Terms, effect: Effect) -> Vec<Terms> {
    terms::of(effect).map_or_else(Vec::new, |t| t.refinements(prep, best))
}

/// The median sampling interval of the fit recordings (s).
pub fn median_dt_s(prep: &Prepared) -> f64 {
    let mut dts: Vec<f64> = prep.fit_indices().iter().map(|&i| prep.recs[i].dt_s()).collect();
    dts.sort_by(f64::total_cmp);
    dts.get(dts.len() / 2).copied().unwrap_or(0.0)
}

/// The model `base + effect` at every searched value of the effect's
/// nonlinear parameter (one variant when it has none).
pub fn variants(prep: &Prepared, base: &Terms, effect: Effect) -> Vec<Terms> {
    terms::of(effect).map_or_else(Vec::new, |t| t.variants(prep, base))
}
