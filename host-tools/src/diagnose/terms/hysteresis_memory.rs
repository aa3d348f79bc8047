//! `hysteresis_memory`, the reference model's term, tested before the
//! candidates: the turn-around memory (length δ a fraction of the largest
//! stroke), a yield / dry-friction force `f(I)·tanh(v/v0)` at each knee v0
//! that is rate-independent over the speeds tested, and each knee with the
//! memory.
use super::{Block, Sample, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{rate_dependent, tested_speeds_m_s, KNEE_FRACTIONS};
use crate::diagnose::design::{Layout, Solution, Terms};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct HysteresisMemory;

/// The memory and yield variants on their own (added to the paper's model).
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

impl Term for HysteresisMemory {
    fn effect(&self) -> Effect {
        Effect::HysteresisMemory
    }
    fn deciding_experiment(&self) -> &'static str {
        "partial loops: reversals at several amplitudes inside the stroke at each current"
    }
    fn is_reference(&self) -> bool {
        true
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.memory_mm.is_some() || t.friction_v0_m_s.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms {
            memory_mm: None,
            friction_v0_m_s: None,
            ..*t
        }
    }
    /// One quartic per branch cannot follow a turn-around in any data.
    fn identifiable(&self, _prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
        Ok(())
    }
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        memory_variants(prep)
            .into_iter()
            .map(|m| Terms {
                memory_mm: m.memory_mm,
                friction_v0_m_s: m.friction_v0_m_s,
                ..*base
            })
            .collect()
    }
    /// The memory basis (built by the design from the memory feature), then
    /// the yield force per current.
    fn blocks(&self, t: &Terms) -> Vec<Block> {
        let memory = t.memory_mm.map(|_| Block::MemoryBasis);
        let friction = t.friction_v0_m_s.map(|_| Block::PerCurrent);
        memory.into_iter().chain(friction).collect()
    }
    fn shape(&self, t: &Terms, _block: usize, s: &Sample) -> f64 {
        t.friction_v0_m_s.map_or(0.0, |v0| (s.v_m_s / v0).tanh())
    }
    /// The yield force `f(I) ≥ 0` resists the motion; the memory basis is
    /// free (it moves the force either way after a turn-around).
    fn nonnegative(&self, t: &Terms, block: usize) -> bool {
        self.blocks(t).get(block) == Some(&Block::PerCurrent)
    }
    fn parameters(&self, prep: &Prepared, layout: &Layout, t: &Terms, sol: &Solution) -> Vec<Value> {
        let mut out = Vec::new();
        if let Some(delta) = t.memory_mm {
            out.push(("delta_mm".into(), delta, "mm".into()));
        }
        let friction_block = usize::from(t.memory_mm.is_some());
        if let (Some(at), Some(v0)) = (layout.at(Effect::HysteresisMemory, friction_block), t.friction_v0_m_s) {
            // The yield / dry-friction force reached beyond the knee.
            for (k, c) in prep.currents_a.iter().enumerate() {
                out.push((format!("f_yield_at_{c}a_n"), sol.beta[at + k], "N".into()));
            }
            out.push(("v0_m_s".into(), v0, "m/s".into()));
        }
        out
    }
    fn wrong_sign(&self, name: &str, value: f64) -> Option<&'static str> {
        (name.starts_with("f_yield_at_") && value < 0.0).then_some("a yield force below zero pushes along the motion")
    }
    fn searched(&self) -> &'static [&'static str] {
        &["v0_m_s", "delta_mm"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["peak stroke"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        match (t.memory_mm, t.friction_v0_m_s) {
            (None, None) => None,
            (Some(d), None) => Some(format!("turn-around memory over {d:.2} mm")),
            (None, Some(v0)) => Some(format!("a yield force with its knee at {v0:.3} m/s")),
            (Some(d), Some(v0)) => Some(format!(
                "turn-around memory over {d:.2} mm and a yield force with its knee at {v0:.3} m/s"
            )),
        }
    }
}
