//! `viscous_damping`: a rate-dependent force `c(I)·φ(v)`, `φ(v) = v` or
//! `v0·tanh(v/v0)`.
use super::{Block, Sample, TableParts, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{rate_dependent, spread_within_currents, tested_speeds_m_s, KNEE_FRACTIONS};
use crate::diagnose::design::{Layout, Solution, Terms, Viscous};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct ViscousDamping;

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
        out
    }
    fn blocks(&self, t: &Terms) -> Vec<Block> {
        t.viscous.map(|_| Block::PerCurrent).into_iter().collect()
    }
    fn shape(&self, t: &Terms, _block: usize, s: &Sample) -> f64 {
        match t.viscous {
            Some(Viscous::Linear) => s.v_m_s,
            Some(Viscous::Saturating { v0_m_s }) => v0_m_s * (s.v_m_s / v0_m_s).tanh(),
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
            if let Viscous::Saturating { v0_m_s } = visc {
                out.push(("v0_m_s".into(), v0_m_s, "m/s".into()));
            }
        }
        out
    }
    /// `c(I)·v` as the table's viscous coefficient; a saturating
    /// `c·v0·tanh(v/v0)` as its secant slope at the fastest recorded speed.
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
        &["v0_m_s"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["velocity"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.viscous.map(|v| match v {
            Viscous::Linear => "linear viscous damping".into(),
            Viscous::Saturating { v0_m_s } => format!("viscous damping saturating at {v0_m_s:.3} m/s"),
        })
    }
}
