//! One candidate model term per vocabulary effect (`docs/effects.md`):
//! whether this data set can identify it, and the variants to search.
use super::design::{SofteningLaw, Terms, Viscous};
use super::prepared::Prepared;
use super::select::Thresholds;

pub use crate::vocabulary::Effect;

impl Effect {
    /// The candidates forward selection adds to the reference model
    /// ([`Effect::HysteresisMemory`], tested first, is not among them).
    pub const CANDIDATES: [Effect; 7] = [
        Effect::ViscousDamping,
        Effect::SensorDelay,
        Effect::StressSoftening,
        Effect::EndStop,
        Effect::MagneticSaturation,
        Effect::Inertia,
        Effect::CoilLag,
    ];

    /// Is the term already in the model?
    pub fn present_in(self, t: &Terms) -> bool {
        match self {
            Effect::ViscousDamping => t.viscous.is_some(),
            Effect::SensorDelay => t.delay_s.is_some(),
            Effect::StressSoftening => t.softening.is_some(),
            Effect::EndStop => t.end_stop_x_mm.is_some(),
            Effect::MagneticSaturation => t.saturation_i_a.is_some(),
            Effect::Inertia => t.inertia,
            Effect::CoilLag => t.coil_lag_s.is_some(),
            Effect::HysteresisMemory => t.memory_mm.is_some() || t.friction_v0_m_s.is_some(),
            Effect::None => false,
        }
    }
}

/// `hysteresis_memory`, tested first as the reference model: the
/// turn-around memory (length δ a fraction of the largest stroke), a yield /
/// dry-friction force `f(I)·tanh(v/v0)` at each knee v0 that is
/// rate-independent over the speeds tested ([`rate_dependent`] false), and
/// each knee with the memory.
pub fn memory_variants(prep: &Prepared) -> Vec<Terms> {
    let fit = prep.fit_indices();
    let span = fit
        .iter()
        .flat_map(|&i| prep.recs[i].x_mm.iter().copied())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
    let memory = |f: f64| Terms {
        memory_mm: Some(f * (span.1 - span.0).max(1e-9)),
        ..Terms::default()
    };
    // δ from 1.25 % to 5 % of the stroke span: the basis' lengths 0.4–2.5 δ
    // then cover a switching length from 0.5 % to 12 % of it.
    let lengths = [0.0125, 0.025, 0.05];
    let mut out: Vec<Terms> = lengths.iter().map(|&f| memory(f)).collect();
    let (lo, hi) = tested_speeds_m_s(prep);
    for f in KNEE_FRACTIONS {
        let v0 = f * hi;
        if v0 > 0.0 && !rate_dependent(v0, lo, hi) {
            out.push(Terms {
                friction_v0_m_s: Some(v0),
                ..Terms::default()
            });
            out.extend(lengths.iter().map(|&f| Terms {
                friction_v0_m_s: Some(v0),
                ..memory(f)
            }));
        }
    }
    out
}

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
fn spread_within_currents(prep: &Prepared, q: impl Fn(usize) -> f64) -> f64 {
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
fn stroke_ends_mm(prep: &Prepared) -> (f64, f64) {
    prep.fit_indices()
        .iter()
        .flat_map(|&i| prep.recs[i].x_mm.iter().copied())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)))
}

/// A stroke that reaches well into both signs of x (a sinusoid about the
/// middle), not a drop that starts at contact (x ≥ 0 up to noise).
fn two_sided(xmin_mm: f64, xmax_mm: f64) -> bool {
    xmin_mm < -0.3 * xmax_mm.abs() && xmax_mm > 0.0
}

fn distinct_sequences(prep: &Prepared) -> usize {
    let mut s: Vec<f64> = prep
        .fit_indices()
        .iter()
        .filter_map(|&i| prep.recs[i].sequence)
        .collect();
    s.sort_by(f64::total_cmp);
    s.dedup();
    s.len()
}

fn temperature_span_c(prep: &Prepared) -> f64 {
    let t: Vec<f64> = prep
        .fit_indices()
        .iter()
        .filter_map(|&i| prep.recs[i].temperature_c)
        .collect();
    t.iter().copied().fold(f64::NEG_INFINITY, f64::max) - t.iter().copied().fold(f64::INFINITY, f64::min)
}

fn intermediate_validate_count(prep: &Prepared) -> usize {
    let (lo, hi) = (prep.currents_a[0], prep.currents_a[prep.currents_a.len() - 1]);
    prep.validate_indices()
        .iter()
        .filter(|&&i| prep.recs[i].current_a > lo + 1e-9 && prep.recs[i].current_a < hi - 1e-9)
        .count()
}

/// `Err(needs)` when this data set cannot separate the effect from the
/// baseline, with the test that would.
///
/// `magnetic_saturation` and `coil_lag` change only how validate currents
/// are predicted, so their only evidence is the validate recordings: unless
/// `validate_evidence` lets those be read, they are not identifiable.
pub fn identifiable(prep: &Prepared, effect: Effect, th: &Thresholds) -> Result<(), String> {
    if !th.validate_evidence && matches!(effect, Effect::MagneticSaturation | Effect::CoilLag) {
        return Err(
            "its only evidence is the `validate` recordings, which no decision reads by default;              `--set validate_evidence=true` judges it on them (they then stop being an independent check)"
                .into(),
        );
    }
    match effect {
        Effect::ViscousDamping => {
            if spread_within_currents(prep, |i| prep.recs[i].max_abs_v_m_s()) >= 0.15 {
                Ok(())
            } else {
                Err(
                    "recordings at one current with different velocities (impact velocities, or sinusoid \
                     amplitude × frequency): along one trajectory v is a function of x and the branch \
                     quartics absorb it"
                        .into(),
                )
            }
        }
        Effect::SensorDelay => Ok(()),
        Effect::StressSoftening => {
            if distinct_sequences(prep) >= 3 || temperature_span_c(prep) >= 2.0 {
                Ok(())
            } else {
                Err("repeated tests with their run order recorded (`sequence`), or temperature records".into())
            }
        }
        Effect::EndStop => {
            let (xmin, xmax) = stroke_ends_mm(prep);
            let upper = spread_within_currents(prep, |i| prep.recs[i].max_x_mm());
            let lower = if two_sided(xmin, xmax) {
                spread_within_currents(prep, |i| -prep.recs[i].min_x_mm())
            } else {
                0.0
            };
            if upper.max(lower) >= 0.1 {
                Ok(())
            } else {
                Err("recordings at one current that reach different maximum strokes".into())
            }
        }
        Effect::MagneticSaturation => {
            if prep.currents_a.len() >= 2 && intermediate_validate_count(prep) >= 2 {
                Ok(())
            } else {
                Err("at least two `validate` recordings at currents between the tabulated (fit) currents".into())
            }
        }
        Effect::Inertia => {
            if prep.free_drop {
                return Err(
                    "a test whose acceleration is not proportional to the measured force (shaker or MTS \
                     test, or a measured acceleration channel): in a free drop a = g − F/M, a pure scale the \
                     fit absorbs"
                        .into(),
                );
            }
            let misfit = acceleration_misfit_over_noise(prep);
            if misfit >= th.inertia_min_accel_misfit_over_noise {
                Ok(())
            } else {
                Err(format!(
                    "an acceleration that is not proportional to the measured force (a shaker or MTS test, or \
                     drops of two masses): here a = α + β·F fits the acceleration to {misfit:.1}× its noise \
                     (below {:.1}×), so an `m·a` term would only feed the measured force back",
                    th.inertia_min_accel_misfit_over_noise
                ))
            }
        }
        Effect::HysteresisMemory => Ok(()),
        // No term: nothing to separate from the baseline.
        Effect::None => Ok(()),
        Effect::CoilLag => {
            let n = stepped_validate_count(prep);
            if n >= 2 {
                Ok(())
            } else {
                Err(format!(
                    "at least two `validate` recordings in which the coil current changes during the test \
                     (controlled impacts), with the command recorded per sample (`current_a` column); this \
                     data set has {n}"
                ))
            }
        }
    }
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
fn stepped_validate_count(prep: &Prepared) -> usize {
    let span = prep.currents_a[prep.currents_a.len() - 1] - prep.currents_a[0];
    prep.validate_indices()
        .iter()
        .filter(|&&i| span > 0.0 && prep.recs[i].current_change_a() >= 0.1 * span)
        .count()
}

/// Extra variants around the grid's best, `best`, where the grid is too
/// coarse for the effect: a filter's group delay is rarely a whole number of
/// samples, and the residual of a half-sample error follows stiffness ×
/// velocity, which a rate term would then pick up as spurious damping; the
/// coil time constant's √2 grid is refined to 2^(1/16) steps.
pub fn refinements(prep: &Prepared, best: &Terms, effect: Effect) -> Vec<Terms> {
    match effect {
        Effect::SensorDelay => match best.delay_s {
            Some(tau) => {
                let dt = median_dt_s(prep);
                [-0.5, -0.25, 0.25, 0.5]
                    .iter()
                    .map(|f| Terms {
                        delay_s: Some(tau + f * dt),
                        ..*best
                    })
                    .collect()
            }
            None => Vec::new(),
        },
        Effect::StressSoftening => match best.softening {
            Some(SofteningLaw::Sequence { n0 }) => [-0.5, -0.25, 0.25, 0.5]
                .iter()
                .map(|e| Terms {
                    softening: Some(SofteningLaw::Sequence { n0: n0 * 2f64.powf(*e) }),
                    ..*best
                })
                .collect(),
            _ => Vec::new(),
        },
        // 2^(1/16) steps: within 2.2 % of any τ between the grid's points.
        Effect::CoilLag => match best.coil_lag_s {
            Some(tau) => [-0.25, -0.1875, -0.125, -0.0625, 0.0625, 0.125, 0.1875, 0.25]
                .iter()
                .map(|e| Terms {
                    coil_lag_s: Some(tau * 2f64.powf(*e)),
                    ..*best
                })
                .collect(),
            None => Vec::new(),
        },
        _ => Vec::new(),
    }
}

fn median_dt_s(prep: &Prepared) -> f64 {
    let mut dts: Vec<f64> = prep.fit_indices().iter().map(|&i| prep.recs[i].dt_s()).collect();
    dts.sort_by(f64::total_cmp);
    dts.get(dts.len() / 2).copied().unwrap_or(0.0)
}

/// The model `base + effect` at every searched value of the effect's
/// nonlinear parameter (one variant when it has none).
pub fn variants(prep: &Prepared, base: &Terms, effect: Effect) -> Vec<Terms> {
    let fit = prep.fit_indices();
    let with = |f: &dyn Fn(&mut Terms)| {
        let mut t = *base;
        f(&mut t);
        t
    };
    match effect {
        // Only knees under which the term still grows with speed over the
        // tests: a lower knee is a yield force (`hysteresis_memory`).
        Effect::ViscousDamping => {
            let (lo, vmax) = tested_speeds_m_s(prep);
            let mut out = vec![with(&|t| t.viscous = Some(Viscous::Linear))];
            for f in KNEE_FRACTIONS {
                if rate_dependent(f * vmax, lo, vmax) {
                    out.push(with(&|t| t.viscous = Some(Viscous::Saturating { v0_m_s: f * vmax })));
                }
            }
            out
        }
        Effect::SensorDelay => {
            let dt = median_dt_s(prep);
            // Finer where delays are common (a few samples of filter group
            // delay), and both signs: a DAQ offset can lead as well as lag.
            let lags = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 12.0];
            let leads = [1.0, 2.0, 4.0, 8.0];
            lags.iter()
                .map(|s| s * dt)
                .chain(leads.iter().map(|s| -s * dt))
                .map(|tau| with(&|t| t.delay_s = Some(tau)))
                .collect()
        }
        Effect::StressSoftening => {
            if distinct_sequences(prep) >= 3 {
                [2.0, 4.0, 8.0, 16.0, 40.0]
                    .iter()
                    .map(|&n0| with(&|t| t.softening = Some(SofteningLaw::Sequence { n0 })))
                    .collect()
            } else {
                let t: Vec<f64> = fit.iter().filter_map(|&i| prep.recs[i].temperature_c).collect();
                let t_ref_c = t.iter().sum::<f64>() / t.len().max(1) as f64;
                vec![with(&|t| t.softening = Some(SofteningLaw::Temperature { t_ref_c }))]
            }
        }
        Effect::EndStop => {
            let (xmin, xmax) = stroke_ends_mm(prep);
            let fractions = [0.3, 0.4, 0.5, 0.6, 0.7, 0.75, 0.8, 0.85, 0.9, 0.94];
            let upper = fractions.iter().map(|f| {
                with(&|t| {
                    t.end_stop_x_mm = Some(f * xmax);
                    t.end_stop_lower = false;
                })
            });
            // The extension end only where the stroke is two-sided (a shaker
            // or MTS test), not a drop's few noisy samples below x = 0.
            let lower = fractions.iter().filter(|_| two_sided(xmin, xmax)).map(|f| {
                with(&|t| {
                    t.end_stop_x_mm = Some(f * xmin);
                    t.end_stop_lower = true;
                })
            });
            upper.chain(lower).collect()
        }
        Effect::MagneticSaturation => {
            let imax = prep.currents_a[prep.currents_a.len() - 1].abs().max(1e-3);
            [0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.75, 1.0]
                .iter()
                .map(|f| with(&|t| t.saturation_i_a = Some(f * imax)))
                .collect()
        }
        Effect::Inertia => vec![with(&|t| t.inertia = true)],
        Effect::None => Vec::new(),
        Effect::HysteresisMemory => memory_variants(prep)
            .into_iter()
            .map(|m| {
                with(&|t| {
                    t.memory_mm = m.memory_mm;
                    t.friction_v0_m_s = m.friction_v0_m_s;
                })
            })
            .collect(),
        // From one sample period to about 90 (√2 steps): an L/R from well
        // under the sampling time to longer than an impact.
        Effect::CoilLag => {
            let dt = median_dt_s(prep);
            (0..14)
                .map(|k| dt * 2f64.powf(0.5 * k as f64))
                .map(|tau| with(&|t| t.coil_lag_s = Some(tau)))
                .collect()
        }
    }
}
