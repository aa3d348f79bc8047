//! GSA search boxes.
//!
//! - `paper`: the paper's Table 3 (`shared/paper/table4.toml`, `[gsa_bounds]`),
//!   one box per branch for every current. The paper's own Table 4 results lie
//!   outside it in places, so it is offered for faithfulness, not as default.
//! - `data` (default): a box around a cheap estimate. The estimate is the
//!   least-squares quartic on every 8th sample of the branch, â. Each
//!   coefficient gets `â_k ± (|â_k| + δ_k)`, where `δ_k = RMS(F) / RMS(x^p_k)`
//!   is the size of a coefficient that alone would produce the branch's force
//!   level (p_k = the power of term k). So the box scales with the data and its
//!   units, is never degenerate, and contains sign changes of small terms.
use super::lsq::fit_quartic;
use anyhow::{bail, Result};
use mre_algorithm::model::Branch;

/// Per-coefficient [lower, upper], highest power first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchBox {
    pub lower: [f64; 5],
    pub upper: [f64; 5],
}

impl SearchBox {
    pub fn contains(&self, c: &[f64; 5]) -> bool {
        (0..5).all(|k| c[k] >= self.lower[k] && c[k] <= self.upper[k])
    }
}

/// Where GSA's bounds come from.
#[derive(Clone, Debug, PartialEq)]
pub enum BoundsChoice {
    Data,
    Paper,
}

impl std::str::FromStr for BoundsChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "data" => Ok(BoundsChoice::Data),
            "paper" => Ok(BoundsChoice::Paper),
            other => Err(format!("unknown bounds `{other}`: use `data` or `paper`")),
        }
    }
}

impl BoundsChoice {
    pub fn label(&self) -> &'static str {
        match self {
            BoundsChoice::Data => "data",
            BoundsChoice::Paper => "paper",
        }
    }

    pub fn search_box(&self, branch: Branch, x_mm: &[f64], force_n: &[f64]) -> Result<SearchBox> {
        match self {
            BoundsChoice::Paper => Ok(paper_bounds(branch)),
            BoundsChoice::Data => data_bounds(x_mm, force_n),
        }
    }
}

/// The paper's Table 3 (a_y1-1..5 for compression, a_y2-1..5 for extension).
pub fn paper_bounds(branch: Branch) -> SearchBox {
    match branch {
        Branch::Compression => SearchBox {
            lower: [-1100.0, -9000.0, -25000.0, 4000.0, -300.0],
            upper: [4000.0, 20000.0, 3000.0, 20000.0, 400.0],
        },
        Branch::Extension => SearchBox {
            lower: [-9000.0, -62000.0, -8000.0, 500.0, -70.0],
            upper: [33000.0, 21000.0, 35000.0, 800.0, 3.0],
        },
    }
}

/// The default data-derived box (see the module docs).
pub fn data_bounds(x_mm: &[f64], force_n: &[f64]) -> Result<SearchBox> {
    let stride = 8;
    let xs: Vec<f64> = x_mm.iter().step_by(stride).copied().collect();
    let fs: Vec<f64> = force_n.iter().step_by(stride).copied().collect();
    // Too few for the subsample: use every sample.
    let estimate = if xs.len() >= 10 {
        fit_quartic(&xs, &fs)
    } else {
        fit_quartic(x_mm, force_n)
    }?;
    let n = x_mm.len().max(1) as f64;
    let rms_f = (force_n.iter().map(|f| f * f).sum::<f64>() / n).sqrt().max(1e-9);
    let mut lower = [0.0; 5];
    let mut upper = [0.0; 5];
    for k in 0..5 {
        let power = 4 - k as i32;
        let rms_xp = (x_mm.iter().map(|x| x.powi(power).powi(2)).sum::<f64>() / n).sqrt();
        let delta = if rms_xp > 0.0 { rms_f / rms_xp } else { rms_f };
        let half = estimate.coeffs[k].abs() + delta;
        if !half.is_finite() {
            bail!("cannot derive search bounds: the data give a non-finite estimate");
        }
        lower[k] = estimate.coeffs[k] - half;
        upper[k] = estimate.coeffs[k] + half;
    }
    Ok(SearchBox { lower, upper })
}
