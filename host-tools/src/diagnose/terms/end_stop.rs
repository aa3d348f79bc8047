//! `end_stop`: a stop at `x_e` pushing back `k_e(I)·max(0, x − x_e)²` (or
//! the mirror image at the extension end of a two-sided stroke).
use super::{Block, Sample, TableParts, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{spread_within_currents, stroke_ends_mm, two_sided};
use crate::diagnose::design::{end_stop_shape, Layout, Solution, Terms, QUARTIC_TERMS};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct EndStop;

impl Term for EndStop {
    fn effect(&self) -> Effect {
        Effect::EndStop
    }
    fn deciding_experiment(&self) -> &'static str {
        "amplitudes stepping across the stop at each current, each amplitude repeated"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.end_stop_x_mm.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms {
            end_stop_x_mm: None,
            end_stop_lower: false,
            ..*t
        }
    }
    fn identifiable(&self, prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
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
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let (xmin, xmax) = stroke_ends_mm(prep);
        let fractions = [0.3, 0.4, 0.5, 0.6, 0.7, 0.75, 0.8, 0.85, 0.9, 0.94];
        let at = |x_e: f64, lower: bool| Terms {
            end_stop_x_mm: Some(x_e),
            end_stop_lower: lower,
            ..*base
        };
        let upper = fractions.iter().map(|f| at(f * xmax, false));
        // The extension end only where the stroke is two-sided (a shaker or
        // MTS test), not a drop's few noisy samples below x = 0.
        let lower = fractions
            .iter()
            .filter(|_| two_sided(xmin, xmax))
            .map(|f| at(f * xmin, true));
        upper.chain(lower).collect()
    }
    fn blocks(&self, t: &Terms) -> Vec<Block> {
        t.end_stop_x_mm.map(|_| Block::PerCurrent).into_iter().collect()
    }
    fn shape(&self, t: &Terms, _block: usize, s: &Sample) -> f64 {
        t.end_stop_x_mm
            .map_or(0.0, |x_e| end_stop_shape(s.x_mm, x_e, t.end_stop_lower))
    }
    /// A stop only pushes back (k_e ≥ 0 at every current). Unconstrained,
    /// the 1 A tests of the real MR damper fit k_e < 0 (their own misfit at
    /// the stroke ends), which made a true stop's prediction worse there.
    fn nonnegative(&self, _t: &Terms, _block: usize) -> bool {
        true
    }
    fn parameters(&self, prep: &Prepared, layout: &Layout, t: &Terms, sol: &Solution) -> Vec<Value> {
        let mut out = Vec::new();
        if let (Some(at), Some(xe)) = (layout.at(Effect::EndStop, 0), t.end_stop_x_mm) {
            // Per tabulated current (fitted ≥ 0; 0 where a current's tests
            // give no push-back at the stop).
            for (k, c) in prep.currents_a.iter().enumerate() {
                out.push((format!("k_e_at_{c}a_n_per_mm2"), sol.beta[at + k], "N/mm²".into()));
            }
            out.push(("x_e_mm".into(), xe, "mm".into()));
            // 1: the stop acts at the extension end (x < x_e); 0: the compression end.
            out.push(("lower_end".into(), f64::from(u8::from(t.end_stop_lower)), "1".into()));
        }
        out
    }
    /// `k_e(I)·`[`end_stop_shape`] added to both branch quartics of each
    /// current, projected by least squares on 200 points over its stroke.
    fn write_table(&self, layout: &Layout, t: &Terms, sol: &Solution, parts: &mut TableParts) -> anyhow::Result<()> {
        let (Some(at), Some(x_e)) = (layout.at(Effect::EndStop, 0), t.end_stop_x_mm) else {
            return Ok(());
        };
        const N: usize = 200;
        for (k, (q, &(lo, hi))) in parts.quartics.iter_mut().zip(&parts.stroke_mm).enumerate() {
            let k_e = parts.scale * sol.beta[at + k];
            let x = |r: usize| lo + (hi - lo) * r as f64 / (N - 1) as f64;
            let a = nalgebra::DMatrix::from_fn(N, QUARTIC_TERMS, |r, c| x(r).powi(c as i32));
            for branch in q.iter_mut() {
                let y = nalgebra::DVector::from_fn(N, |r, _| {
                    let xr = x(r);
                    let p: f64 = branch.iter().rev().fold(0.0, |acc, c| acc * xr + c);
                    p + k_e * end_stop_shape(xr, x_e, t.end_stop_lower)
                });
                let fit = crate::linalg::solve(&a, &y)?;
                *branch = std::array::from_fn(|i| fit.coeffs[i]);
            }
        }
        Ok(())
    }
    fn searched(&self) -> &'static [&'static str] {
        &["x_e_mm"]
    }
    fn set_by_design(&self) -> &'static [&'static str] {
        &["lower_end"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["displacement beyond 80 % of the largest stroke"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.end_stop_x_mm.map(|x_e| {
            let end = if t.end_stop_lower { "extension" } else { "compression" };
            format!("an end stop at {x_e:.2} mm ({end} end)")
        })
    }
}
