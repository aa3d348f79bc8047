//! `viscous_damping`: a rate-dependent force `c(I)·φ(v)`, `φ(v) = v`,
//! `v0·tanh(v/v0)`, or `v_τ`: v through a first-order lag τ (a Maxwell
//! branch, a spring in series with the dashpot).
use super::{Block, Sample, TableParts, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{
    median_dt_s, rate_dependent, spread_within_currents, tested_speeds_m_s, KNEE_FRACTIONS,
};
use crate::diagnose::cv::score;
use crate::diagnose::design::{Layout, Solution, Terms, Viscous};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct ViscousDamping;

/// The Maxwell relaxation times searched: from this many sample periods …
const MAXWELL_FIRST_SAMPLES: f64 = 2.0;
/// … in √2 steps up to this (s). A longer branch is viscous in the
/// sinusoids and elastic in a drop, the base law's own relaxation (a
/// viscoelastic law's fastest Prony branch, 50 ms on the outside-class
/// plants); searched up to 45 ms the term named itself and a sensor
/// delay on `none` plants (tuning seeds 7261–7265).
const MAXWELL_LONGEST_S: f64 = 0.016;

/// `v_τ` of `dv_τ/dt = (v − v_τ)/τ` at each sample, from `v_τ = 0` at the
/// first (the branch relaxed when the recording starts: a drop's force
/// builds from zero at contact), exact for v linear between samples. A
/// non-positive or non-finite τ is no lag (`v` itself).
pub fn maxwell_velocity_m_s(time_s: &[f64], v_m_s: &[f64], tau_s: f64) -> Vec<f64> {
    if !(tau_s > 0.0 && tau_s.is_finite()) {
        return v_m_s.to_vec();
    }
    let mut out = Vec::with_capacity(v_m_s.len());
    let mut lag = 0.0;
    for t in 0..v_m_s.len().min(time_s.len()) {
        if t > 0 {
            let h = (time_s[t] - time_s[t - 1]).max(0.0);
            let (v0, v1) = (v_m_s[t - 1], v_m_s[t]);
            let a = (-h / tau_s).exp();
            // Over a ramp from v0 to v1: the lag of v0 plus the ramp's share.
            let ramp = if h > 0.0 { 1.0 - tau_s / h * (1.0 - a) } else { 0.0 };
            lag = a * lag + (1.0 - a) * v0 + (v1 - v0) * ramp;
        }
        out.push(lag);
    }
    out
}

/// The Maxwell forms `c(I)·v_τ` on top of `base`, τ from
/// [`MAXWELL_FIRST_SAMPLES`] sample periods to [`MAXWELL_LONGEST_S`] in √2
/// steps, or none when their best fit (the same in-sample choice the
/// library's search makes) sits at the longest τ: the data then want a
/// relaxation slower than any fast branch searched, a viscoelastic law's own
/// slow branch (viscous in the sinusoids, elastic in a drop), not a damper.
/// Chosen there, the lagged column left the contact transient of every
/// drop to `sensor_delay`'s regressor, named on 8 of 12 effect-free plants
/// (tuning seeds 7268–7279; all 9 whose Maxwell choice was the longest τ
/// but one, none of the 3 that chose `c·v`).
fn located_maxwell_forms(prep: &Prepared, base: &Terms) -> Vec<Terms> {
    let dt = median_dt_s(prep);
    if !(dt > 0.0 && dt.is_finite()) {
        return Vec::new();
    }
    let mut forms = Vec::new();
    let mut tau_s = MAXWELL_FIRST_SAMPLES * dt;
    while tau_s <= MAXWELL_LONGEST_S * 1.001 {
        forms.push(Terms {
            viscous: Some(Viscous::Maxwell { tau_s }),
            ..*base
        });
        tau_s *= std::f64::consts::SQRT_2;
    }
    // One τ alone locates nothing either.
    let located = match forms.last() {
        Some(longest) if forms.len() >= 2 => score(prep, &forms).is_ok_and(|s| s.terms != *longest),
        _ => false,
    };
    if located {
        forms
    } else {
        Vec::new()
    }
}

impl Term for ViscousDamping {
    fn effect(&self) -> Effect {
        Effect::ViscousDamping
    }
    fn deciding_experiment(&self) -> &'static str {
        "one amplitude at three or more frequencies (the velocity changes, the stroke does not)"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.viscous.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms { viscous: None, ..*t }
    }
    fn identifiable(&self, prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
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
    /// Only knees under which the term still grows with speed over the
    /// tests: a lower knee is a yield force (`hysteresis_memory`).
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let (lo, vmax) = tested_speeds_m_s(prep);
        let with = |v: Viscous| Terms {
            viscous: Some(v),
            ..*base
        };
        let mut out = vec![with(Viscous::Linear)];
        for f in KNEE_FRACTIONS {
            if rate_dependent(f * vmax, lo, vmax) {
                out.push(with(Viscous::Saturating { v0_m_s: f * vmax }));
            }
        }
        // Listed after the instantaneous forms: a tie keeps the simpler.
        out.extend(located_maxwell_forms(prep, base));
        out
    }
    fn blocks(&self, t: &Terms) -> Vec<Block> {
        t.viscous.map(|_| Block::PerCurrent).into_iter().collect()
    }
    fn shape(&self, t: &Terms, _block: usize, s: &Sample) -> f64 {
        match t.viscous {
            Some(Viscous::Linear) => s.v_m_s,
            Some(Viscous::Saturating { v0_m_s }) => v0_m_s * (s.v_m_s / v0_m_s).tanh(),
            Some(Viscous::Maxwell { .. }) => s.v_lag_m_s,
            None => 0.0,
        }
    }
    /// Each `c(I) ≥ 0`: damping only takes energy out.
    fn nonnegative(&self, _t: &Terms, _block: usize) -> bool {
        true
    }
    /// A dissipative force: `c(I)·φ(v)` with c > 0 (with every c held at
    /// its bound the term is no term). A fit whose coefficients
    /// are negative on average over the tabulated currents is not damping
    /// but the model's misfit anti-correlated with velocity: on simulated
    /// drops after a true sensor delay, a rate-independent base law's
    /// turn-around structure was fitted by c ≈ −1…−16 N·s/m at every
    /// current and accepted (1.10× on the fit folds, 1.025× over all
    /// recordings).
    fn physical(&self, layout: &Layout, _t: &Terms, sol: &Solution) -> bool {
        let Some(at) = layout.at(Effect::ViscousDamping, 0) else {
            return true;
        };
        sol.beta[at..at + layout.n_currents].iter().sum::<f64>() > 0.0
    }
    fn parameters(&self, prep: &Prepared, layout: &Layout, t: &Terms, sol: &Solution) -> Vec<Value> {
        let mut out = Vec::new();
        if let (Some(at), Some(visc)) = (layout.at(Effect::ViscousDamping, 0), t.viscous) {
            for (k, c) in prep.currents_a.iter().enumerate() {
                out.push((format!("c_at_{c}a_n_s_per_m"), sol.beta[at + k], "N·s/m".into()));
            }
            match visc {
                Viscous::Saturating { v0_m_s } => out.push(("v0_m_s".into(), v0_m_s, "m/s".into())),
                Viscous::Maxwell { tau_s } => out.push(("maxwell_tau_s".into(), tau_s, "s".into())),
                Viscous::Linear => {}
            }
        }
        out
    }
    /// `c(I)·v` as the table's viscous coefficient; a saturating
    /// `c·v0·tanh(v/v0)` as its secant slope at the fastest recorded speed;
    /// a Maxwell branch as its `c` (its force once v has held for a few τ;
    /// the table has no lag for it, so the first τ of an impact is over-damped).
    fn write_table(&self, layout: &Layout, t: &Terms, sol: &Solution, parts: &mut TableParts) -> anyhow::Result<()> {
        let (Some(visc), Some(at)) = (t.viscous, layout.at(Effect::ViscousDamping, 0)) else {
            return Ok(());
        };
        let fastest = parts.fastest_m_s;
        for k in 0..layout.n_currents.min(parts.terms.viscous_n_s_per_m.len()) {
            let c = parts.scale * sol.beta[at + k];
            let slope = match visc {
                Viscous::Saturating { v0_m_s } if fastest > 0.0 => c * v0_m_s * (fastest / v0_m_s).tanh() / fastest,
                _ => c,
            };
            parts.terms.viscous_n_s_per_m[k] = slope as f32;
        }
        Ok(())
    }
    fn wrong_sign(&self, name: &str, value: f64) -> Option<&'static str> {
        (name.starts_with("c_at_") && value < 0.0)
            .then_some("a damping coefficient below zero feeds energy in at this current")
    }
    fn searched(&self) -> &'static [&'static str] {
        &["v0_m_s", "maxwell_tau_s"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["velocity"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.viscous.map(|v| match v {
            Viscous::Linear => "linear viscous damping".into(),
            Viscous::Saturating { v0_m_s } => format!("viscous damping saturating at {v0_m_s:.3} m/s"),
            Viscous::Maxwell { tau_s } => format!("viscous damping relaxing over {:.2} ms (Maxwell)", tau_s * 1e3),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::maxwell_velocity_m_s;

    /// Physics: a velocity held at v from t = 0 drives a relaxed Maxwell
    /// branch to v·(1 − e^{−t/τ}); a ramp v = k·t to k·(t − τ(1 − e^{−t/τ})).
    #[test]
    fn maxwell_velocity_follows_the_first_order_lag_from_a_relaxed_start() {
        let tau = 0.004;
        let time: Vec<f64> = (0..400).map(|k| k as f64 * 1e-4).collect();
        // A step at contact: the recording starts at v = 0.5 m/s.
        let step = maxwell_velocity_m_s(&time, &vec![0.5; time.len()], tau);
        for (t, got) in time.iter().zip(&step) {
            let want = 0.5 * (1.0 - (-t / tau).exp());
            assert!((got - want).abs() < 1e-12, "t {t}: {got} vs {want}");
        }
        let ramp_v: Vec<f64> = time.iter().map(|t| 20.0 * t).collect();
        let ramp = maxwell_velocity_m_s(&time, &ramp_v, tau);
        for (t, got) in time.iter().zip(&ramp) {
            let want = 20.0 * (t - tau * (1.0 - (-t / tau).exp()));
            assert!((got - want).abs() < 1e-12, "t {t}: {got} vs {want}");
        }
        // No lag: v itself.
        assert_eq!(maxwell_velocity_m_s(&time, &ramp_v, 0.0), ramp_v);
    }
}
