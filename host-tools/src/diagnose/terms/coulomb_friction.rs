//! `coulomb_friction`: a dry-friction force `f_c(I)·tanh(v/v_c)` per
//! current, resisting the motion, `v_c` a knee well below the slowest test's
//! peak speed. A sharp `sign(v)` would be a constant per branch, which the
//! branch quartics already hold: the term is told apart from them only by its
//! transition near rest, seen when one current is tested at several speeds.
use super::{Block, Sample, TableParts, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{spread_within_currents, tested_speeds_m_s};
use crate::diagnose::design::{Layout, Solution, Terms};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct CoulombFriction;

const WORD: Effect = Effect::new("coulomb_friction");

/// Knees `v_c` searched, as fractions of the slowest test's peak speed.
const KNEE_FRACTIONS: [f64; 3] = [0.05, 0.1, 0.2];

impl Term for CoulombFriction {
    fn effect(&self) -> Effect {
        WORD
    }
    fn deciding_experiment(&self) -> &'static str {
        "each current tested at several speeds, slow ones included, so the friction's transition near rest \
         is seen apart from the branch"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.settings.get(WORD).is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms {
            settings: t.settings.with(WORD, None),
            ..*t
        }
    }
    fn identifiable(&self, prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
        if spread_within_currents(prep, |i| prep.recs[i].max_abs_v_m_s()) >= 0.15 {
            Ok(())
        } else {
            Err(
                "recordings at one current with different speeds: at one speed the friction's transition \
                 is a function of x along the branch, and f_c·sign(v) alone is a constant per branch, \
                 which the quartics hold"
                    .into(),
            )
        }
    }
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let (slowest_m_s, _) = tested_speeds_m_s(prep);
        KNEE_FRACTIONS
            .iter()
            .map(|f| f * slowest_m_s)
            .filter(|v_c| *v_c > 0.0)
            .map(|v_c| Terms {
                settings: base.settings.with(WORD, Some(v_c)),
                ..*base
            })
            .collect()
    }
    fn blocks(&self, t: &Terms) -> Vec<Block> {
        self.present_in(t).then_some(Block::PerCurrent).into_iter().collect()
    }
    fn shape(&self, t: &Terms, _block: usize, s: &Sample) -> f64 {
        t.settings.get(WORD).map_or(0.0, |v_c| (s.v_m_s / v_c).tanh())
    }
    /// Friction resists the motion: `f_c(I) ≥ 0`.
    fn nonnegative(&self, _t: &Terms, _block: usize) -> bool {
        true
    }
    fn parameters(&self, prep: &Prepared, layout: &Layout, t: &Terms, sol: &Solution) -> Vec<Value> {
        let mut out = Vec::new();
        if let (Some(at), Some(v_c)) = (layout.at(WORD, 0), t.settings.get(WORD)) {
            for (k, c) in prep.currents_a.iter().enumerate() {
                out.push((format!("f_c_at_{c}a_n"), sol.beta[at + k], "N".into()));
            }
            out.push(("v_c_m_s".into(), v_c, "m/s".into()));
        }
        out
    }
    /// Carried in its sliding limit: `+f_c(I)` on the compression quartic's
    /// constant, `−f_c(I)` on the extension one's (the table has one quartic
    /// per branch; the transition near rest is left out).
    fn write_table(&self, layout: &Layout, _t: &Terms, sol: &Solution, parts: &mut TableParts) -> anyhow::Result<()> {
        if let Some(at) = layout.at(WORD, 0) {
            let scale = parts.scale;
            for (k, q) in parts.quartics.iter_mut().enumerate() {
                let f_c = scale * sol.beta[at + k];
                q[0][0] += f_c;
                q[1][0] -= f_c;
            }
        }
        Ok(())
    }
    fn wrong_sign(&self, name: &str, value: f64) -> Option<&'static str> {
        (name.starts_with("f_c_at_") && value < 0.0).then_some("a friction force below zero pushes along the motion")
    }
    fn searched(&self) -> &'static [&'static str] {
        &["v_c_m_s"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["velocity"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.settings
            .get(WORD)
            .map(|v_c| format!("Coulomb friction with its transition at {v_c:.4} m/s"))
    }
}
