//! What the final model leaves: the residual located again, and the places
//! where it is concentrated reported as `unexplained` (`docs/effects.md`).
//!
//! Every vocabulary term was tested on top of the final model and none
//! passed, so structure still in the residual is structure no term explains.
//! "Structure" means two things here: the residual is well above the force
//! channel's own noise (else there is nothing to explain), and its energy
//! sits in one part of the data — a branch, a stretch of stroke or of time,
//! one excitation frequency or one current — far more than that part's
//! share of the samples.
use super::prepared::{Prepared, BRANCH_AMBIGUITY_SIGMAS};

/// The residual counts as structure only above this multiple of the force noise.
pub const NOISE_FACTOR: f64 = 2.0;
/// A cell is reported when it holds at least this share of the residual energy…
pub const MIN_ENERGY_SHARE: f64 = 0.15;
/// …and at least this multiple of its share of the samples.
pub const MIN_CONCENTRATION: f64 = 1.5;
/// Stroke bins over the data set's displacement range.
const STROKE_BINS: usize = 5;
/// Time bins over each recording's duration.
const TIME_BINS: usize = 5;

/// One place where the final residual is concentrated.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Unexplained {
    /// `branch`, `stroke`, `time`, `frequency` or `current`.
    pub dimension: String,
    /// The cell, e.g. `compression`, `x 15.0 … 25.0 mm`, `5 Hz`, `1 A`.
    pub cell: String,
    /// Share of the final residual's energy in this cell.
    pub energy_share: f64,
    /// Share of the scored samples in this cell.
    pub sample_share: f64,
    /// Final residual RMS in this cell (N).
    pub rmse_n: f64,
    /// The same over every scored sample, and the force channel's noise (N).
    pub overall_rmse_n: f64,
    pub noise_rmse_n: f64,
}

/// Force-channel noise (N): the median over the fit recordings of the
/// robust white-noise estimate [`crate::signal::white_noise_sd`] (second
/// differences, MAD, √6). Fit recordings only: the noise gates of selection
/// read it, and no decision reads a validate recording.
pub fn force_noise_n(prep: &Prepared) -> f64 {
    let mut per: Vec<f64> = prep
        .recs
        .iter()
        .filter(|r| r.is_fit())
        .map(|r| crate::signal::white_noise_sd(&r.force_n))
        .filter(|v| v.is_finite())
        .collect();
    per.sort_by(f64::total_cmp);
    per.get(per.len() / 2).copied().unwrap_or(0.0)
}

/// Excitation frequency of a recording from its velocity sign changes (Hz),
/// `None` with less than a full cycle between the first and last sign change.
fn frequency_hz(time_s: &[f64], v: &[f64], band_m_s: f64) -> Option<f64> {
    // Sign changes with a dead band, so velocity noise chattering around a
    // turn-around counts once.
    let mut crossings = Vec::new();
    let mut sign: Option<bool> = None;
    for (t, &vt) in time_s.iter().zip(v) {
        let s = if vt > band_m_s {
            true
        } else if vt < -band_m_s {
            false
        } else {
            continue;
        };
        if sign.is_some_and(|p| p != s) {
            crossings.push(*t);
        }
        sign = Some(s);
    }
    if crossings.len() < 3 {
        return None;
    }
    let span = crossings[crossings.len() - 1] - crossings[0];
    if span <= 0.0 {
        return None;
    }
    Some((crossings.len() - 1) as f64 / (2.0 * span))
}

/// Cell labels for per-recording frequencies: estimates within 10 % of each
/// other share a cell (sampling makes the same excitation read slightly
/// differently), labelled by their mean to two significant digits.
fn frequency_labels(freqs: &[Option<f64>]) -> Vec<Option<String>> {
    let mut sorted: Vec<f64> = freqs.iter().flatten().copied().collect();
    sorted.sort_by(f64::total_cmp);
    let mut clusters: Vec<Vec<f64>> = Vec::new();
    for f in sorted {
        match clusters.last_mut() {
            Some(c) if f <= 1.1 * c[0] => c.push(f),
            _ => clusters.push(vec![f]),
        }
    }
    let label = |c: &[f64]| {
        let m = c.iter().sum::<f64>() / c.len() as f64;
        let decimals = (1.0 - m.log10().floor()).max(0.0) as usize;
        format!("{m:.decimals$} Hz")
    };
    freqs
        .iter()
        .map(|f| {
            let f = (*f)?;
            clusters
                .iter()
                .find(|c| f >= c[0] && f <= c[c.len() - 1])
                .map(|c| label(c))
        })
        .collect()
}

/// Accumulates energy and counts per cell label.
#[derive(Default)]
struct Cells(Vec<(String, f64, usize)>);

impl Cells {
    fn add(&mut self, label: String, e: f64) {
        match self.0.iter_mut().find(|c| c.0 == label) {
            Some(c) => {
                c.1 += e;
                c.2 += 1;
            }
            None => self.0.push((label, e, 1)),
        }
    }
}

/// Locates the residual `measured − final` on the scored samples.
pub fn locate_unexplained(prep: &Prepared, final_pred: &[Vec<f64>], scored: &[Vec<bool>]) -> Vec<Unexplained> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for r in &prep.recs {
        for &x in &r.x_mm {
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    let width = ((hi - lo) / STROKE_BINS as f64).max(1e-12);
    let dims = ["branch", "stroke", "time", "frequency", "current"];
    let mut cells: Vec<Cells> = dims.iter().map(|_| Cells::default()).collect();
    let (mut total_e, mut total_n) = (0.0, 0usize);
    let freqs: Vec<Option<f64>> = prep
        .recs
        .iter()
        .map(|r| {
            let band = BRANCH_AMBIGUITY_SIGMAS * r.velocity_noise_m_s;
            (!prep.free_drop)
                .then(|| frequency_hz(&r.time_s, &r.v_m_s, band))
                .flatten()
        })
        .collect();
    let freq_labels = frequency_labels(&freqs);
    for (i, r) in prep.recs.iter().enumerate() {
        let n = r.len();
        let (t0, t1) = (r.time_s[0], r.time_s[n - 1]);
        for t in (0..n).filter(|&t| scored[i][t]) {
            let e = (r.force_n[t] - final_pred[i][t]).powi(2);
            total_e += e;
            total_n += 1;
            let branch = if r.v_m_s[t] > 0.0 { "compression" } else { "extension" };
            cells[0].add(branch.into(), e);
            let sb = (((r.x_mm[t] - lo) / width).floor() as usize).min(STROKE_BINS - 1);
            let (a, b) = (lo + sb as f64 * width, lo + (sb + 1) as f64 * width);
            cells[1].add(format!("x {a:.1} … {b:.1} mm"), e);
            let tb =
                ((((r.time_s[t] - t0) / (t1 - t0).max(1e-300)) * TIME_BINS as f64).floor() as usize).min(TIME_BINS - 1);
            cells[2].add(format!("{}–{} % of each recording", tb * 20, tb * 20 + 20), e);
            if let Some(f) = &freq_labels[i] {
                cells[3].add(f.clone(), e);
            }
            cells[4].add(format!("{} A", r.current_label()), e);
        }
    }
    if total_n == 0 || total_e <= 0.0 {
        return Vec::new();
    }
    let overall = (total_e / total_n as f64).sqrt();
    let noise = force_noise_n(prep);
    if overall <= NOISE_FACTOR * noise {
        return Vec::new();
    }
    let mut out = Vec::new();
    for (dim, c) in dims.iter().zip(cells) {
        // A dimension with one cell (one current, one frequency) locates nothing.
        if c.0.len() < 2 {
            continue;
        }
        let n_dim: usize = c.0.iter().map(|x| x.2).sum();
        for (label, e, n) in c.0 {
            let energy_share = e / total_e;
            let sample_share = n as f64 / n_dim.max(1) as f64;
            if energy_share >= MIN_ENERGY_SHARE && energy_share >= MIN_CONCENTRATION * sample_share {
                out.push(Unexplained {
                    dimension: dim.to_string(),
                    cell: label,
                    energy_share,
                    sample_share,
                    rmse_n: (e / n.max(1) as f64).sqrt(),
                    overall_rmse_n: overall,
                    noise_rmse_n: noise,
                });
            }
        }
    }
    out.sort_by(|a, b| {
        (b.energy_share / b.sample_share.max(1e-12)).total_cmp(&(a.energy_share / a.sample_share.max(1e-12)))
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frequency_from_sign_changes() {
        // 3 Hz sine over 2 s sampled at 1 kHz: 12 sign changes → 3 Hz.
        let t: Vec<f64> = (0..2000).map(|k| k as f64 * 1e-3 + 1e-4).collect();
        let v: Vec<f64> = t.iter().map(|t| (2.0 * std::f64::consts::PI * 3.0 * t).sin()).collect();
        assert!((frequency_hz(&t, &v, 0.0).unwrap() - 3.0).abs() < 0.01);
        // Half a cycle is not a frequency.
        let v1: Vec<f64> = t.iter().map(|t| (std::f64::consts::PI * 0.25 * t).sin()).collect();
        assert_eq!(frequency_hz(&t, &v1, 0.0), None);
    }

    #[test]
    fn nearby_frequency_estimates_share_a_cell() {
        let labels = frequency_labels(&[Some(0.098), Some(0.1), Some(0.25), None, Some(0.102)]);
        assert_eq!(labels[0].as_deref(), Some("0.10 Hz"));
        assert_eq!(labels[0], labels[1]);
        assert_eq!(labels[0], labels[4]);
        assert_eq!(labels[2].as_deref(), Some("0.25 Hz"));
        assert_eq!(labels[3], None);
    }
}
