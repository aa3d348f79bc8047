//! The decision rules: every number a decision of `mre diagnose` reads, in
//! one place ([`Thresholds`]). Two decide whether an effect is named — its
//! inclusion probability over the ensemble and its nested held-out gain
//! ([`super::select`]); the rest set the estimator (the sparsity threshold,
//! the ensemble's size) or the verdict when nothing is named
//! ([`super::verdict`]).
use anyhow::bail;

/// The decision rules. Each is an option of the command (`--set
/// NAME=VALUE`, [`Thresholds::with_overrides`]); the defaults are frozen
/// (DIAGNOSE.md, "Calibration").
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Thresholds {
    /// Decision 1: an effect is named only when at least this share of the
    /// ensemble's fits keep it. With 0.9, the stability bound on wrongly
    /// included terms is q²/(0.8·p) ([`super::sparse::stability_bound`]).
    pub min_inclusion: f64,
    /// Decision 2: …and its nested held-out RMSE ratio, without → with the
    /// term, is at least this.
    pub min_nested_gain: f64,
    /// Group STLSQ keeps a term whose contribution is at least this share of
    /// what the baseline quartics alone leave unexplained (a property of
    /// the estimator, not a decision: the two gates above decide).
    pub sparsity: f64,
    /// Complementary pairs of half-samples of the recordings in the
    /// inclusion ensemble (twice as many fits).
    pub ensemble_pairs: usize,
    /// Resamples of the bootstrap interval of a held-out ratio.
    pub bootstrap_resamples: usize,
    /// The verdict is `none` outright when the final held-out RMSE is below
    /// this multiple of the force noise (nothing left to find).
    pub none_max_residual_over_noise: f64,
    /// Fewer cross-validation folds than this make a `none` `inconclusive`:
    /// a fold's training set is then too small a share of the data to
    /// choose the rest of the model without it.
    pub min_folds: usize,
    /// Let the terms that change nothing but how validate currents are
    /// predicted be judged in the library on every validate recording (each
    /// its own fold). Off by default: then such a term is decided on half of
    /// its validate recordings, leave-one-out, and the other half is read by
    /// no decision ([`super::validate_terms`]).
    pub validate_evidence: bool,
    /// `inertia` (an `m·a` term on a measured or derived acceleration) is
    /// tested only when the acceleration departs from an affine function of
    /// the measured force by at least this multiple of the channels' noise
    /// ([`candidates::acceleration_misfit_over_noise`](super::candidates::acceleration_misfit_over_noise)).
    pub inertia_min_accel_misfit_over_noise: f64,
    pub seed: u64,
}

impl Default for Thresholds {
    fn default() -> Self {
        Thresholds {
            min_inclusion: 0.9,
            min_nested_gain: 1.05,
            sparsity: 0.05,
            ensemble_pairs: 50,
            bootstrap_resamples: 1000,
            none_max_residual_over_noise: 5.0,
            min_folds: 5,
            validate_evidence: false,
            inertia_min_accel_misfit_over_noise: 3.0,
            seed: 1,
        }
    }
}

impl Thresholds {
    /// These rules with `NAME=VALUE` overrides (e.g. `min_ratio=1.2`,
    /// `validate_evidence=true`), each checked against the field's name and type.
    pub fn with_overrides(self, overrides: &[String]) -> anyhow::Result<Thresholds> {
        let mut table = toml::Table::try_from(self).map_err(|e| anyhow::anyhow!("the rules as a table: {e}"))?;
        for o in overrides {
            let Some((name, value)) = o.split_once('=') else {
                bail!("`--set {o}`: expected NAME=VALUE, e.g. `--set min_ratio=1.2`");
            };
            let name = name.trim();
            let Some(old) = table.get(name) else {
                let known: Vec<&str> = table.keys().map(|k| k.as_str()).collect();
                bail!(
                    "`--set {o}`: no rule named `{name}`; the rules are {}",
                    known.join(", ")
                );
            };
            let parsed: toml::Table = toml::from_str(&format!("v = {}", value.trim()))
                .map_err(|_| anyhow::anyhow!("`--set {o}`: `{}` is not a number or true/false", value.trim()))?;
            let mut v = parsed["v"].clone();
            // An integer given for a real-valued rule.
            if let (toml::Value::Float(_), toml::Value::Integer(i)) = (old, &v) {
                v = toml::Value::Float(*i as f64);
            }
            if std::mem::discriminant(old) != std::mem::discriminant(&v) {
                bail!("`--set {o}`: `{name}` takes a value like `{old}`");
            }
            table.insert(name.to_string(), v);
        }
        table
            .try_into()
            .map_err(|e| anyhow::anyhow!("the rules after `--set`: {e}"))
    }
}
