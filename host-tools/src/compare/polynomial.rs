//! The polynomial families: the paper's per-current, per-branch quartics
//! fitted by least squares and by GSA (`mre fit`'s code), predicted with the
//! core's table (the board's f32 arithmetic, interpolated in current), and
//! the quartics plus the terms `mre diagnose` selects (its own fit and
//! prediction, called through its public entry point).
use super::tracks::Track;
use crate::dataset::Dataset;
use crate::diagnose::{diagnose, DiagnoseOptions};
use crate::fit::{fit_dataset, gsa::GsaParams, model_file, FitOptions, Method};
use anyhow::{anyhow, Result};
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

/// The quartics plus what `mre diagnose` selects, with the held-out currents
/// as its validate currents (so it never fits them).
pub fn with_diagnosis(ds: &Dataset, hold_out_a: &[f64], tracks: &[Track]) -> Result<PolyOutcome> {
    let d = diagnose(
        ds,
        &DiagnoseOptions {
            validate_currents_a: hold_out_a.to_vec(),
            ..DiagnoseOptions::default()
        },
    )?;
    let predictions = tracks
        .iter()
        .map(|t| {
            d.prep
                .recs
                .iter()
                .position(|r| r.file == t.file)
                .and_then(|i| d.final_pred.get(i).cloned())
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
