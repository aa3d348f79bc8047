//! The vocabulary's effects as plug-ins (`docs/effects.md`): one file per
//! effect, each a [`Term`], listed once in [`REGISTRY`]. The stages read
//! effects only through the trait: [`super::candidates`] asks each term what
//! the data must contain and which variants to search, [`super::design`]
//! builds its columns, [`super::acceptance`] checks its physical constraint and
//! [`super::parameters`] reads its parameters.
//!
//! Adding an effect: a new file here implementing [`Term`] (its searched
//! value lives in [`Terms::settings`], under its word), its line in
//! [`REGISTRY`], and its word in [`crate::vocabulary::Effect`], the contract
//! the data-set format and the plant share (DIAGNOSE.md, "Adding an effect").
use super::acceptance::Thresholds;
use super::design::{Layout, Solution, Terms};
use super::prepared::Prepared;
use crate::vocabulary::Effect;

mod coil_lag;
mod coulomb_friction;
mod end_stop;
mod hysteresis_memory;
mod inertia;
mod magnetic_saturation;
mod sensor_delay;
mod stress_softening;
mod viscous_damping;

pub use hysteresis_memory::memory_variants;
pub use viscous_damping::maxwell_velocity_m_s;

/// Every effect diagnose can add, in column order (the layout places each
/// term's [`Block`]s in this order).
pub static REGISTRY: &[&dyn Term] = &[
    &viscous_damping::ViscousDamping,
    &sensor_delay::SensorDelay,
    &stress_softening::StressSoftening,
    &end_stop::EndStop,
    &magnetic_saturation::MagneticSaturation,
    &inertia::Inertia,
    &coil_lag::CoilLag,
    &hysteresis_memory::HysteresisMemory,
    &coulomb_friction::CoulombFriction,
];

/// The term of a vocabulary effect (`None` for `none`).
pub fn of(effect: Effect) -> Option<&'static dyn Term> {
    REGISTRY.iter().copied().find(|t| t.effect() == effect)
}

/// What a crossed term's regressor is crossed with ([`Term::crossed`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossing {
    No,
    /// Less its gain within each test condition.
    ByCondition,
    /// Less its gain within each recording.
    ByRecording,
    /// Less, at each sample, its gain on the prediction over the runs of one
    /// prescribed motion ([`super::candidates::same_motion`]): only what
    /// differs between those runs beyond a common ratio to the force is
    /// left. A recording that repeats no other's motion keeps nothing.
    ByMotion,
}

/// A block of linear design columns a term adds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Block {
    /// One column per tabulated current, weighted between currents like the
    /// quartics: `w_k(I) · shape(sample)`.
    PerCurrent,
    /// One column for every current: `shape(sample)`.
    Global,
    /// The turn-around memory basis (per current, direction and basis
    /// function), built by [`super::design`] from the memory feature.
    MemoryBasis,
}

/// One sample's inputs to a column shape, after any sensor delay.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub x_mm: f64,
    pub v_m_s: f64,
    pub a_m_s2: f64,
    /// v through the viscous term's Maxwell lag (v itself without one):
    /// the one column input that needs the recording's history.
    pub v_lag_m_s: f64,
}

/// `(name, value, unit)` of one parameter.
pub type Value = (String, f64, String);

/// The final model as the v2 table holds it (`--model-out`), for each term
/// to write itself into ([`Term::write_table`]).
#[derive(Clone, Debug)]
pub struct TableParts {
    /// Per current: compression and extension powers x⁰..x⁴.
    pub quartics: Vec<[[f64; super::design::QUARTIC_TERMS]; 2]>,
    /// Per current: the stroke its fit recordings cover (mm).
    pub stroke_mm: Vec<(f64, f64)>,
    /// The factor every fitted coefficient is written at ([`Term::table_scale`]).
    pub scale: f64,
    /// The fastest recorded speed (m/s).
    pub fastest_m_s: f64,
    pub terms: mre_algorithm::table::ModelTerms,
    /// `[diagnose]` metadata: `(key, value)`.
    pub metadata: Vec<(String, f64)>,
}

/// One vocabulary effect as a model term.
pub trait Term: Sync {
    /// Its vocabulary word.
    fn effect(&self) -> Effect;
    /// The reference term: its value is chosen first, and every other
    /// term's on top of it ([`super::library`]).
    fn is_reference(&self) -> bool {
        false
    }
    /// Is the term in the model `t`?
    fn present_in(&self, t: &Terms) -> bool;
    /// `t` without this term.
    fn removed_from(&self, t: &Terms) -> Terms;
    /// `Ok` when these data can separate the term from the rest of the
    /// model; otherwise what the data must contain.
    fn identifiable(&self, prep: &Prepared, th: &Thresholds) -> Result<(), String>;
    /// The term changes only how the `validate` recordings are predicted
    /// (its only evidence is them).
    fn validate_only(&self) -> bool {
        false
    }
    /// For a [`Term::validate_only`] term: the validate recordings whose
    /// prediction it changes (its evidence), in data-set order.
    fn evidence(&self, _prep: &Prepared) -> Vec<usize> {
        Vec::new()
    }
    /// `base` plus this term at every searched value of its nonlinear
    /// parameter (one variant when it has none).
    fn variants(&self, prep: &Prepared, base: &Terms) -> Vec<Terms>;
    /// Extra variants around the grid's best, where the grid is too coarse.
    fn refinements(&self, _prep: &Prepared, _best: &Terms) -> Vec<Terms> {
        Vec::new()
    }
    /// The linear columns it adds to the model `t` (none for a term that
    /// transforms the inputs, such as a delay).
    fn blocks(&self, _t: &Terms) -> Vec<Block> {
        Vec::new()
    }
    /// The shape of column block `block` at one sample.
    fn shape(&self, _t: &Terms, _block: usize, _s: &Sample) -> f64 {
        0.0
    }
    /// Its physical sign constraint: the coefficients of its block `block`
    /// in the model `t` are ≥ 0. The fit holds a coefficient whose least-
    /// squares value is negative at 0 (sign-constrained least squares,
    /// [`super::design::Designs::solve`]), and the report says which.
    fn nonnegative(&self, _t: &Terms, _block: usize) -> bool {
        false
    }
    /// The fitted term is physical (checked before it is accepted).
    fn physical(&self, _layout: &Layout, _t: &Terms, _sol: &Solution) -> bool {
        true
    }
    /// The factor the table writes every fitted coefficient at (softening:
    /// the damper as the latest recording found it).
    fn table_scale(&self, _prep: &Prepared, _t: &Terms, _sol: &Solution) -> f64 {
        1.0
    }
    /// Writes the fitted term into the table (`--model-out`); a term the
    /// table cannot carry writes nothing (DIAGNOSE.md says which).
    fn write_table(
        &self,
        _layout: &Layout,
        _t: &Terms,
        _sol: &Solution,
        _parts: &mut TableParts,
    ) -> anyhow::Result<()> {
        Ok(())
    }
    /// Its parameters in a fitted model.
    fn parameters(&self, prep: &Prepared, layout: &Layout, t: &Terms, sol: &Solution) -> Vec<Value>;
    /// Why a fitted value of parameter `name` is unphysical (a wrong sign),
    /// or `None` when it is not; reported with the parameter.
    fn wrong_sign(&self, _name: &str, _value: f64) -> Option<&'static str> {
        None
    }
    /// Parameters chosen by the variant search (their intervals re-choose
    /// among the variants); the rest are solved.
    fn searched(&self) -> &'static [&'static str] {
        &[]
    }
    /// Parameters set by the search design, not estimated (no interval).
    fn set_by_design(&self) -> &'static [&'static str] {
        &[]
    }
    /// A crossed effect in the model `t`: its linearised regressor keeps
    /// only what a gain per test condition, or per recording, cannot explain
    /// ([`super::library`]), so the term can only explain a change between
    /// repeats of one condition, or within one test (softening: the run
    /// order crossed with the test condition, or the cycles of one test;
    /// never a difference between conditions or tests, which the baseline's
    /// misfit also makes).
    fn crossed(&self, _t: &Terms) -> Crossing {
        Crossing::No
    }
    /// The experiment that would separate the term from the baseline when
    /// these data cannot (reported with an `inconclusive` verdict).
    fn deciding_experiment(&self) -> &'static str {
        "more tests at the conditions where the term acts, each repeated"
    }
    /// The covariates its residual signature follows, as [`super::locate`]
    /// names them.
    fn signature(&self) -> &'static [&'static str];
    /// The term's searched values in words (`None` when absent from `t`).
    fn describe(&self, t: &Terms) -> Option<String>;
}

/// The model `t` in words: "the paper's model" plus each term's values.
pub fn describe(t: &Terms) -> String {
    let parts: Vec<String> = REGISTRY.iter().filter_map(|term| term.describe(t)).collect();
    if parts.is_empty() {
        "the paper's model".into()
    } else {
        format!("the paper's model with {}", parts.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_hold_one_value_per_word_whatever_the_order_they_were_set_in() {
        use crate::diagnose::design::Settings;
        let a = Settings::default()
            .with(Effect::Inertia, Some(1.0))
            .with(Effect::EndStop, Some(8.0));
        let b = Settings::default()
            .with(Effect::EndStop, Some(3.0))
            .with(Effect::Inertia, Some(1.0))
            .with(Effect::EndStop, Some(8.0));
        assert_eq!(a, b);
        assert_eq!(a.get(Effect::EndStop), Some(8.0));
        assert_eq!(a.get(Effect::ViscousDamping), None);
        let c = a.with(Effect::Inertia, None);
        assert_eq!(c.get(Effect::Inertia), None);
        assert_eq!(c, Settings::default().with(Effect::EndStop, Some(8.0)));
        // Every word at once fits.
        let all = Effect::VOCABULARY
            .iter()
            .fold(Settings::default(), |s, &e| s.with(e, Some(2.0)));
        assert!(Effect::VOCABULARY.iter().all(|&e| all.get(e) == Some(2.0)));
    }

    #[test]
    fn every_vocabulary_effect_but_none_has_exactly_one_term() {
        for e in Effect::VOCABULARY {
            let n = REGISTRY.iter().filter(|t| t.effect() == e).count();
            assert_eq!(n, usize::from(e != Effect::None), "{}", e.name());
        }
        // One reference term, tested before the candidates.
        assert_eq!(REGISTRY.iter().filter(|t| t.is_reference()).count(), 1);
        // Every term's word is its own, and a model holding every term fits
        // the settings.
        for (k, t) in REGISTRY.iter().enumerate() {
            assert!(
                REGISTRY[..k].iter().all(|o| o.effect() != t.effect()),
                "{}",
                t.effect().name()
            );
        }
        assert!(REGISTRY.len() <= crate::diagnose::design::SETTINGS_CAPACITY);
    }

    #[test]
    fn a_model_is_described_in_words_not_as_a_struct() {
        assert_eq!(describe(&Terms::default()), "the paper's model");
        let t = Terms {
            delay_s: Some(2.5e-3),
            settings: crate::diagnose::design::Settings::default().with(Effect::Inertia, Some(1.0)),
            ..Terms::default()
        };
        assert_eq!(
            describe(&t),
            "the paper's model with a sensor delay of 2.500 ms, inertia"
        );
    }

    #[test]
    fn wrong_signs_are_named_for_damping_yield_and_mass_only() {
        let viscous = of(Effect::ViscousDamping).unwrap();
        assert!(viscous.wrong_sign("c_at_0a_n_s_per_m", -1.0).is_some());
        assert!(viscous.wrong_sign("c_at_0a_n_s_per_m", 1.0).is_none());
        assert!(viscous.wrong_sign("v0_m_s", -1.0).is_none());
        let memory = of(Effect::HysteresisMemory).unwrap();
        assert!(memory.wrong_sign("f_yield_at_1a_n", -120.0).is_some());
        assert!(of(Effect::Inertia).unwrap().wrong_sign("m_s_kg", -0.1).is_some());
        // A lead is a legitimate delay sign.
        assert!(of(Effect::SensorDelay).unwrap().wrong_sign("tau_s", -1e-3).is_none());
    }
}
