//! The polynomial families: the paper's per-current, per-branch quartics
//! fitted by least squares and by GSA (`mre fit`'s code), predicted with the
//! core's table (the board's f32 arithmetic, interpolated in current), and
//! the quartics plus the terms `mre diagnose` selects (its own fit and
//! prediction, called through its public entry point).
use super::tracks::Track;
use crate::dataset::{Dataset, Role};
use crate::diagnose::{diagnose, DiagnoseOptions};
use crate::fit::{fit_dataset, gsa::GsaParams, model_file, FitOptions, Method};
use anyhow::{anyhow, bail, Result};
use serde_json::json;

/// A polynomial family's parameters, size and predictions (one per track, in order).
pub struct PolyOutcome {
    pub parameters: serde_json::Value,
    pub n_parameters: usize,
    pub predictions: Vec<Vec<f64>>,
    pub note: String,
}

/// The paper's model fitted with `method` (`Lsq` or `Gsa`) on the fit recordings of `ds`.
pub fn quartics(ds: &Dataset, method: Method, gsa: GsaParams) -> Result<PolyOutcome> {
    let options = FitOptions {
        method,
        gsa,
        ..FitOptions::default()
    };
    let run = fit_dataset(ds, &options)?;
    let table = crate::table_file::parse_table_toml(&model_file::to_toml(&run.model)?)?;
    let predictions = ds
        .recordings
        .iter()
        .map(|r| crate::validate::model_forces(&table, r).0)
        .collect();
    let parameters = json!(run
        .model
        .current
        .iter()
        .map(|c| json!({
            "current_a": c.current_a,
            "compression": c.compression,
            "extension": c.extension,
        }))
        .collect::<Vec<_>>());
    Ok(PolyOutcome {
        parameters,
        n_parameters: 10 * run.model.current.len(),
        predictions,
        note: match method {
            Method::Gsa => format!("GSA N = {}, T = {}, seed {}", gsa.agents, gsa.iters, gsa.seed),
            _ => "least squares (QR), the exact optimum".into(),
        },
    })
}

/// The quartics plus what `mre diagnose` selects. The diagnosis runs on the
/// fit recordings alone: its candidate scoring also reads `validate`
/// recordings (a term that only changes how they are predicted is scored on
/// them), so running it on the whole data set would let the held-out data
/// choose the model. The selected model is then applied to every recording.
pub fn with_diagnosis(ds: &Dataset, hold_out_a: &[f64], tracks: &[Track]) -> Result<PolyOutcome> {
    let mut fit_only = ds.clone();
    crate::fit::problems::hold_out(&mut fit_only, hold_out_a);
    fit_only.recordings.retain(|r| r.role == Role::Fit);
    let options = DiagnoseOptions::default();
    let d = diagnose(&fit_only, &options)?;
    let every = crate::diagnose::prepared::prepare(ds, &options.folds, hold_out_a)?;
    let all_pred = crate::diagnose::predictions(&every, &d.selection.final_model);
    // The same model on the same fit recordings must give the diagnosis's own predictions.
    for (r, p) in d.prep.recs.iter().zip(&d.final_pred) {
        let i = every.recs.iter().position(|e| e.file == r.file);
        let same = i.is_some_and(|i| {
            all_pred[i].len() == p.len()
                && all_pred[i]
                    .iter()
                    .zip(p)
                    .all(|(a, b)| (a - b).abs() <= 1e-6 * (1.0 + b.abs()))
        });
        if !same {
            bail!("diagnose's model does not reproduce its own prediction of {}", r.file);
        }
    }
    let predictions = tracks
        .iter()
        .map(|t| {
            every
                .recs
                .iter()
                .position(|r| r.file == t.file)
                .and_then(|i| all_pred.get(i).cloned())
                .filter(|p| p.len() == t.len())
                .ok_or_else(|| anyhow!("diagnose returned no prediction for {}", t.file))
        })
        .collect::<Result<Vec<_>>>()?;
    let effects: Vec<&str> = d.findings.iter().map(|f| f.effect.name()).collect();
    let terms: serde_json::Map<String, serde_json::Value> = d
        .findings
        .iter()
        .map(|f| {
            let values: serde_json::Map<String, serde_json::Value> =
                f.parameters.iter().map(|(k, p)| (k.clone(), json!(p.value))).collect();
            (f.effect.name().to_string(), serde_json::Value::Object(values))
        })
        .collect();
    Ok(PolyOutcome {
        parameters: json!({ "effects": effects, "terms": terms }),
        n_parameters: d.selection.final_model.n_params,
        predictions,
        note: if effects.is_empty() {
            "diagnose selected no term: the plain quartics".into()
        } else {
            format!("quartics + {}", effects.join(" + "))
        },
    })
}
