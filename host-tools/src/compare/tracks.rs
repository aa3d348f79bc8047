//! What the families are fitted to and scored on: every recording as a
//! track of measured x(t), v(t), F(t) at its held current, and the metric
//! the comparison reports.
//!
//! A recording's error is the one measure of every report
//! ([`crate::error_measure`]: RMSE / measured force range). A family's score
//! is the mean over recordings, so a 2 mm test counts as much as a 25 mm one.
//! (The fitting objective weights each track by its peak |F| instead,
//! `force_scale_n`: a weight, never reported.)
use crate::dataset::{Dataset, Recording, Role};

/// One recording, in internal units (s, mm, m/s, N, A).
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// File stem (e.g. `10mm1Hz0A`), used for output names.
    pub stem: String,
    pub file: String,
    pub current_a: f64,
    pub role: Role,
    pub time_s: Vec<f64>,
    pub x_mm: Vec<f64>,
    pub v_m_s: Vec<f64>,
    pub force_n: Vec<f64>,
    /// max |F measured| (N), at least 1e-9.
    pub force_scale_n: f64,
}

impl Track {
    pub fn from_recording(r: &Recording) -> Track {
        let s = &r.samples;
        let stem = std::path::Path::new(&r.file)
            .file_stem()
            .map_or_else(|| r.file.clone(), |s| s.to_string_lossy().into_owned());
        Track {
            stem,
            file: r.file.clone(),
            current_a: r.current_a,
            role: r.role,
            time_s: s.time_s.clone(),
            x_mm: s.x_mm.clone(),
            v_m_s: s.v_m_s.clone(),
            force_n: s.force_n.clone(),
            force_scale_n: max_abs(&s.force_n).max(1e-9),
        }
    }

    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Every `stride`-th sample (the first always kept). The fits search on
    /// decimated recordings (GSA coarser than LM); every score and prediction
    /// uses all samples.
    pub fn decimated(&self, stride: usize) -> Track {
        let stride = stride.max(1);
        let pick = |v: &[f64]| v.iter().step_by(stride).copied().collect::<Vec<_>>();
        Track {
            stem: self.stem.clone(),
            file: self.file.clone(),
            current_a: self.current_a,
            role: self.role,
            time_s: pick(&self.time_s),
            x_mm: pick(&self.x_mm),
            v_m_s: pick(&self.v_m_s),
            force_n: pick(&self.force_n),
            force_scale_n: self.force_scale_n,
        }
    }

    /// Decimated to at most about `max_samples` samples.
    pub fn at_most(&self, max_samples: usize) -> Track {
        self.decimated(self.len().div_ceil(max_samples.max(1)))
    }
}

/// Every recording of the data set as a track; recordings at `hold_out_a` become `validate`.
pub fn tracks(ds: &Dataset, hold_out_a: &[f64]) -> Vec<Track> {
    ds.recordings
        .iter()
        .map(|r| {
            let mut t = Track::from_recording(r);
            t.role = r.role_holding_out(hold_out_a);
            t
        })
        .collect()
}

pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
}

/// RMSE (N) between measured and modelled force (the one error measure's numerator).
pub use crate::error_measure::rmse_n;

/// NRMSE of one recording ([`crate::error_measure`]).
pub fn nrmse(track: &Track, model: &[f64]) -> f64 {
    crate::error_measure::nrmse_of(&track.force_n, model)
}

/// Mean NRMSE over the tracks with `role` (NaN if there are none).
pub fn mean_nrmse(tracks: &[Track], predictions: &[Vec<f64>], role: Role) -> f64 {
    let scores: Vec<f64> = tracks
        .iter()
        .zip(predictions)
        .filter(|(t, _)| t.role == role)
        .map(|(t, p)| nrmse(t, p))
        .collect();
    if scores.is_empty() {
        return f64::NAN;
    }
    scores.iter().sum::<f64>() / scores.len() as f64
}

/// AIC and BIC of a Gaussian least-squares fit with `k` parameters over the
/// `fit` tracks: n·ln(SSE/n) + 2k and n·ln(SSE/n) + k·ln n (n = fit samples).
/// Samples of a recording are correlated, so these rank families, they are
/// not likelihoods to read absolutely.
pub fn information_criteria(tracks: &[Track], predictions: &[Vec<f64>], k: usize) -> (f64, f64) {
    let mut sse = 0.0;
    let mut n = 0usize;
    for (t, p) in tracks.iter().zip(predictions).filter(|(t, _)| t.role == Role::Fit) {
        sse += t.force_n.iter().zip(p).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
        n += t.len();
    }
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let nf = n as f64;
    let base = nf * (sse.max(f64::MIN_POSITIVE) / nf).ln();
    (base + 2.0 * k as f64, base + k as f64 * nf.ln())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(force: Vec<f64>) -> Track {
        let n = force.len();
        Track {
            stem: "t".into(),
            file: "t.csv".into(),
            current_a: 0.0,
            role: Role::Fit,
            time_s: (0..n).map(|i| i as f64).collect(),
            x_mm: vec![0.0; n],
            v_m_s: vec![0.0; n],
            force_scale_n: max_abs(&force),
            force_n: force,
        }
    }

    #[test]
    fn nrmse_is_rmse_over_the_measured_force_range() {
        // Errors 3 and 4 on two samples: RMSE = √((9 + 16)/2) = √12.5; range 5 − (−10) = 15.
        let t = track(vec![-10.0, 5.0]);
        let got = nrmse(&t, &[-7.0, 9.0]);
        assert!((got - 12.5f64.sqrt() / 15.0).abs() < 1e-12);
    }

    #[test]
    fn decimation_keeps_first_sample_and_stride() {
        let t = track((0..10).map(f64::from).collect());
        assert_eq!(t.decimated(3).force_n, vec![0.0, 3.0, 6.0, 9.0]);
        assert!(t.at_most(4).len() <= 4);
    }
}
