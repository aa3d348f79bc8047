//! `magnetic_saturation`: between tabulated currents the law interpolates
//! on `tanh(I/I_s)` instead of I.
use super::{TableParts, Term, Value};
use crate::diagnose::acceptance::Thresholds;
use crate::diagnose::candidates::{intermediate_validate, intermediate_validate_count};
use crate::diagnose::design::{Layout, Solution, Terms};
use crate::diagnose::prepared::Prepared;
use crate::vocabulary::Effect;

pub struct MagneticSaturation;

impl Term for MagneticSaturation {
    fn effect(&self) -> Effect {
        Effect::MagneticSaturation
    }
    fn deciding_experiment(&self) -> &'static str {
        "tests at a current above the highest fitted one, held out as `validate`"
    }
    fn present_in(&self, t: &Terms) -> bool {
        t.saturation_i_a.is_some()
    }
    fn removed_from(&self, t: &Terms) -> Terms {
        Terms {
            saturation_i_a: None,
            ..*t
        }
    }
    fn identifiable(&self, prep: &Prepared, _th: &Thresholds) -> Result<(), String> {
        if prep.currents_a.len() >= 2 && intermediate_validate_count(prep) >= 2 {
            Ok(())
        } else {
            Err("at least two `validate` recordings at currents between the tabulated (fit) currents".into())
        }
    }
    /// A fit recording sits on a tabulated current: only the interpolated
    /// (validate) recordings change.
    fn validate_only(&self) -> bool {
        true
    }
    fn evidence(&self, prep: &Prepared) -> Vec<usize> {
        intermediate_validate(prep)
    }
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms> {
        let imax = prep.currents_a[prep.currents_a.len() - 1].abs().max(1e-3);
        [0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.75, 1.0]
            .iter()
            .map(|f| Terms {
                saturation_i_a: Some(f * imax),
                ..*base
            })
            .collect()
    }
    /// The `tanh(I/I_s)` interpolation variable of the table.
    fn write_table(&self, _layout: &Layout, t: &Terms, _sol: &Solution, parts: &mut TableParts) -> anyhow::Result<()> {
        parts.terms.saturation_current_a = t.saturation_i_a.unwrap_or(0.0) as f32;
        Ok(())
    }
    fn parameters(&self, _prep: &Prepared, _layout: &Layout, t: &Terms, _sol: &Solution) -> Vec<Value> {
        t.saturation_i_a
            .map(|is| ("i_s_a".into(), is, "A".into()))
            .into_iter()
            .collect()
    }
    fn searched(&self) -> &'static [&'static str] {
        &["i_s_a"]
    }
    fn signature(&self) -> &'static [&'static str] {
        &["current_a"]
    }
    fn describe(&self, t: &Terms) -> Option<String> {
        t.saturation_i_a.map(|is| format!("magnetic saturation at {is:.3} A"))
    }
}
