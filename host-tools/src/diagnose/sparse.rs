//! Grouped sparse selection over one library of columns (issue 38): group
//! sequentially thresholded least squares (group STLSQ, the grouped form of
//! PySINDy's STLSQ) and an ensemble of complementary half-samples of the
//! recordings that gives each group an inclusion probability.
//!
//! Why group STLSQ rather than group lasso or SR3: every iterate is an
//! ordinary least-squares fit of the kept columns, so the coefficients a kept
//! term reports are unshrunk physical values (a lasso biases them toward 0),
//! and the one threshold has a physical reading — the share of what the
//! baseline leaves unexplained that a group accounts for — instead of a
//! penalty weight whose meaning changes with the data's scale. SR3 adds a
//! relaxation parameter on top. The price is that STLSQ is greedy within one
//! fit; the ensemble is what makes the choice stable.
//!
//! Rows may be compressed: a recording's rows can be the R factor of the QR
//! of its `[A | y]`, since `‖A·β − y‖ = ‖R_A·β − r_y‖` for every β. Fits,
//! contributions and held-out errors are then exact at a fraction of the cost.
use nalgebra::{DMatrix, DVector};
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// A group of library columns that enter or leave together.
#[derive(Clone, Debug)]
pub struct Group {
    pub name: String,
    pub cols: Vec<usize>,
    /// Baseline groups (the branch quartics) are never thresholded.
    pub always: bool,
    /// A sign-constrained term (every column ≥ 0 in its real form): a fit
    /// whose coefficients sum below 0 drops it, as the real form would hold it at 0.
    pub nonnegative: bool,
}

/// The library over a set of rows, each row tagged by its recording.
#[derive(Clone, Debug)]
pub struct Library {
    pub a: DMatrix<f64>,
    pub y: DVector<f64>,
    pub recording_of_row: Vec<usize>,
    pub groups: Vec<Group>,
}

impl Library {
    /// The distinct recordings, in row order.
    pub fn recordings(&self) -> Vec<usize> {
        let mut out: Vec<usize> = Vec::new();
        for &r in &self.recording_of_row {
            if !out.contains(&r) {
                out.push(r);
            }
        }
        out
    }

    /// Rows of the recordings `recs` (a recording listed twice counts twice).
    pub fn rows_of(&self, recs: &[usize]) -> Vec<usize> {
        recs.iter()
            .flat_map(|&r| (0..self.recording_of_row.len()).filter(move |&i| self.recording_of_row[i] == r))
            .collect()
    }

    /// Columns of the groups flagged in `kept`.
    fn cols_of(&self, kept: &[bool]) -> Vec<usize> {
        self.groups
            .iter()
            .zip(kept)
            .filter(|(_, k)| **k)
            .flat_map(|(g, _)| g.cols.iter().copied())
            .collect()
    }

    /// Squared error of `beta` on each recording's rows, by recording.
    pub fn sse_by_recording(&self, beta: &DVector<f64>) -> Vec<(usize, f64)> {
        let r = &self.y - &self.a * beta;
        let mut out: Vec<(usize, f64)> = self.recordings().into_iter().map(|k| (k, 0.0)).collect();
        for (i, e) in r.iter().enumerate() {
            if let Some(slot) = out.iter_mut().find(|(k, _)| *k == self.recording_of_row[i]) {
                slot.1 += e * e;
            }
        }
        out
    }
}

/// The rows of a [`Library`] reduced to the R factor of the QR of their
/// `[A | y]` (at most columns + 1 rows). For every subset of the columns the
/// fit and its residual norm are the same as on the rows themselves (module
/// docs), so a set of rows fitted many times (STLSQ's iterations, a fold's
/// with/without fits) is factored once.
pub struct Reduced<'a> {
    lib: &'a Library,
    a: DMatrix<f64>,
    y: DVector<f64>,
}

impl Library {
    /// `rows` reduced for repeated fits (see [`Reduced`]).
    pub fn reduce(&self, rows: &[usize]) -> Reduced<'_> {
        let c = self.a.ncols();
        let mut ay = DMatrix::<f64>::zeros(rows.len(), c + 1);
        for (k, &r) in rows.iter().enumerate() {
            ay.view_mut((k, 0), (1, c)).copy_from(&self.a.row(r));
            ay[(k, c)] = self.y[r];
        }
        let ay = if rows.len() > c + 1 { ay.qr().r() } else { ay };
        Reduced {
            lib: self,
            a: ay.columns(0, c).into_owned(),
            y: ay.column(c).into_owned(),
        }
    }
}

impl Reduced<'_> {
    /// Least squares with the columns of the groups flagged in `kept`; the
    /// others are 0. Columns are scaled to unit norm first (powers of x in
    /// mm span orders of magnitude), and directions below round-off are
    /// dropped (a current no row touches leaves zero columns).
    pub fn least_squares(&self, kept: &[bool]) -> DVector<f64> {
        let mut beta = DVector::zeros(self.a.ncols());
        let cols = self.lib.cols_of(kept);
        if cols.is_empty() || self.a.nrows() == 0 {
            return beta;
        }
        let mut sub = self.a.select_columns(&cols);
        let norms: Vec<f64> = (0..sub.ncols()).map(|c| sub.column(c).norm()).collect();
        for (c, n) in norms.iter().enumerate() {
            if *n > 0.0 {
                sub.column_mut(c).scale_mut(1.0 / n);
            }
        }
        let svd = sub.svd(true, true);
        let eps = 1e-10 * svd.singular_values.max();
        if let Ok(b) = svd.solve(&self.y, eps) {
            for (k, &c) in cols.iter().enumerate() {
                if norms[k] > 0.0 {
                    beta[c] = b[k] / norms[k];
                }
            }
        }
        beta
    }

    /// `‖A·β − y‖` over the reduced rows.
    fn residual_norm(&self, beta: &DVector<f64>) -> f64 {
        (&self.y - &self.a * beta).norm()
    }
}

/// The result of one group STLSQ fit.
#[derive(Clone, Debug)]
pub struct Sparse {
    pub beta: DVector<f64>,
    /// Per group: kept or not.
    pub kept: Vec<bool>,
    /// Per group: norm of its contribution over the norm of what the
    /// always-kept groups alone leave unexplained.
    pub share: Vec<f64>,
}

const MAX_ITERATIONS: usize = 20;

/// Group STLSQ: fit the kept groups by least squares, drop every optional
/// group whose contribution `‖A_g β_g‖` is below `threshold` times the
/// residual norm of the always-kept groups alone, refit, until nothing changes.
pub fn group_stlsq(lib: &Library, rows: &[usize], threshold: f64) -> Sparse {
    let n_groups = lib.groups.len();
    let always: Vec<bool> = lib.groups.iter().map(|g| g.always).collect();
    let reduced = lib.reduce(rows);
    let base = reduced.least_squares(&always);
    let unexplained = reduced.residual_norm(&base).max(f64::MIN_POSITIVE);
    let mut kept = vec![true; n_groups];
    let mut beta = DVector::zeros(lib.a.ncols());
    let mut share = vec![0.0; n_groups];
    for _ in 0..MAX_ITERATIONS {
        beta = reduced.least_squares(&kept);
        for (g, group) in lib.groups.iter().enumerate() {
            // ‖A_g·β_g‖ is the same on the reduced rows (Q is orthonormal).
            let part = reduced.a.select_columns(&group.cols)
                * DVector::from_iterator(group.cols.len(), group.cols.iter().map(|&c| beta[c]));
            share[g] = part.norm() / unexplained;
        }
        // A sign-constrained group fitted net negative stands in for
        // something else (a lagged elastic force is −τ·k·v: negative
        // damping), which its real form cannot carry.
        let negative =
            |g: usize| lib.groups[g].nonnegative && lib.groups[g].cols.iter().map(|&c| beta[c]).sum::<f64>() < 0.0;
        let next: Vec<bool> = (0..n_groups)
            .map(|g| kept[g] && (lib.groups[g].always || (share[g] >= threshold && !negative(g))))
            .collect();
        if next == kept {
            break;
        }
        kept = next;
    }
    Sparse { beta, kept, share }
}

/// What the ensemble says about each group.
#[derive(Clone, Debug)]
pub struct Ensemble {
    /// Per group: share of the ensemble's fits that kept it.
    pub inclusion: Vec<f64>,
    /// Mean number of optional groups a fit kept (q of the stability bound).
    pub mean_kept: f64,
    pub fits: usize,
}

/// Inclusion probability of each group over `pairs` random splits of the
/// recordings into two halves, each half fitted (complementary pairs, Shah &
/// Samworth 2013); rows travel with their recording, so autocorrelated
/// samples are not counted as independent. In parallel.
pub fn ensemble(lib: &Library, threshold: f64, pairs: usize, seed: u64) -> Ensemble {
    let recs = lib.recordings();
    let kept: Vec<Vec<bool>> = (0..pairs)
        .into_par_iter()
        .flat_map_iter(|b| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (b as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15));
            let mut order = recs.clone();
            order.shuffle(&mut rng);
            let (h1, h2) = order.split_at(order.len() / 2);
            [h1.to_vec(), h2.to_vec()]
                .into_iter()
                .filter(|h| !h.is_empty())
                .map(|h| group_stlsq(lib, &lib.rows_of(&h), threshold).kept)
                .collect::<Vec<_>>()
        })
        .collect();
    let fits = kept.len().max(1);
    let inclusion = (0..lib.groups.len())
        .map(|g| kept.iter().filter(|k| k[g]).count() as f64 / fits as f64)
        .collect();
    let optional = |k: &Vec<bool>| k.iter().zip(&lib.groups).filter(|(k, g)| **k && !g.always).count();
    let mean_kept = kept.iter().map(optional).sum::<usize>() as f64 / fits as f64;
    Ensemble {
        inclusion,
        mean_kept,
        fits: kept.len(),
    }
}

/// Bound on the expected number of optional groups named with inclusion
/// probability ≥ `pi` that do not belong (Meinshausen & Bühlmann 2010,
/// Theorem 1; for complementary pairs Shah & Samworth 2013): `q²/((2π − 1)·p)`,
/// `q` the mean number kept per fit, `p` the number of optional groups.
/// Assumes the selection does better than random guessing and exchangeable
/// false groups; it is a bound on the inclusion rule alone (the held-out gain
/// gate can only lower it). Infinite for `pi` ≤ 0.5.
pub fn stability_bound(mean_kept: f64, n_optional: usize, pi: f64) -> f64 {
    if pi <= 0.5 || n_optional == 0 {
        return f64::INFINITY;
    }
    mean_kept * mean_kept / ((2.0 * pi - 1.0) * n_optional as f64)
}
/// `‖(I − P)·c‖ / ‖c‖` for the most separable column `c` of group `g`,
/// `P` the projection on the columns of `of` (1 when `g` has no non-zero
/// column to compare).
pub fn share_outside(lib: &Library, g: usize, of: &[usize]) -> f64 {
    let cols: Vec<usize> = of.iter().flat_map(|&o| lib.groups[o].cols.iter().copied()).collect();
    let base = lib.a.select_columns(&cols);
    let svd = base.svd(true, false);
    let Some(u) = svd.u else { return 1.0 };
    let s_max = svd.singular_values.max();
    let keep: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&k| svd.singular_values[k] > 1e-10 * s_max)
        .collect();
    let q = u.select_columns(&keep);
    lib.groups[g]
        .cols
        .iter()
        .filter_map(|&c| {
            let col = lib.a.column(c).into_owned();
            let norm = col.norm();
            (norm > 0.0).then(|| (&col - &q * (q.transpose() * &col)).norm() / norm)
        })
        .fold(None, |best: Option<f64>, s| Some(best.map_or(s, |b| b.max(s))))
        .unwrap_or(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_distr::{Distribution, Normal};

    /// y = 3·x + 0.5·x² + 2·z + noise over 8 recordings; the library holds a
    /// baseline group {x, x²}, the true term z and an absent term w.
    fn library(seed: u64) -> Library {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let noise = Normal::new(0.0, 0.1).expect("finite");
        let (mut rows, mut y, mut rec) = (Vec::new(), Vec::new(), Vec::new());
        for r in 0..8 {
            for k in 0..50 {
                let x = (k as f64 / 10.0) - 2.5;
                let z = ((k + r) as f64 * 0.7).sin();
                let w = ((k * 3 + r) as f64 * 0.31).cos();
                rows.push([x, x * x, z, w]);
                y.push(3.0 * x + 0.5 * x * x + 2.0 * z + noise.sample(&mut rng));
                rec.push(r);
            }
        }
        Library {
            a: DMatrix::from_fn(rows.len(), 4, |i, j| rows[i][j]),
            y: DVector::from_vec(y),
            recording_of_row: rec,
            groups: vec![
                Group {
                    name: "baseline".into(),
                    cols: vec![0, 1],
                    always: true,
                    nonnegative: false,
                },
                Group {
                    name: "z".into(),
                    cols: vec![2],
                    always: false,
                    nonnegative: false,
                },
                Group {
                    name: "w".into(),
                    cols: vec![3],
                    always: false,
                    nonnegative: false,
                },
            ],
        }
    }

    #[test]
    fn keeps_the_true_term_drops_the_absent_one_and_reports_unshrunk_values() {
        let lib = library(1);
        let all: Vec<usize> = (0..lib.y.len()).collect();
        let s = group_stlsq(&lib, &all, 0.05);
        assert_eq!(s.kept, vec![true, true, false]);
        // Least squares on the kept columns: z's coefficient is 2 to within
        // the noise (0.1 over 400 rows: SE ≈ 0.1/√(400·0.5) ≈ 0.007).
        assert!((s.beta[2] - 2.0).abs() < 0.03, "{}", s.beta[2]);
        assert_eq!(s.beta[3], 0.0);
    }

    #[test]
    fn the_ensemble_includes_the_true_term_always_and_the_absent_one_never() {
        let e = ensemble(&library(2), 0.05, 25, 9);
        assert_eq!(e.inclusion, vec![1.0, 1.0, 0.0]);
        assert_eq!(e.fits, 50);
        // Only z is kept by every fit: q = 1 of p = 2 optional groups.
        assert_eq!(e.mean_kept, 1.0);
    }

    #[test]
    fn compressed_rows_give_the_same_fit_as_the_raw_rows() {
        // ‖Aβ − y‖ = ‖R_A β − r_y‖ for the R factor of [A | y]: replacing
        // each recording's 50 rows by its 5×5 R factor leaves β unchanged.
        let raw = library(3);
        let mut a_rows: Vec<Vec<f64>> = Vec::new();
        let mut rec = Vec::new();
        for r in raw.recordings() {
            let rows = raw.rows_of(&[r]);
            let mut ay = DMatrix::<f64>::zeros(rows.len(), 5);
            for (k, &i) in rows.iter().enumerate() {
                for c in 0..4 {
                    ay[(k, c)] = raw.a[(i, c)];
                }
                ay[(k, 4)] = raw.y[i];
            }
            let rf = ay.qr().r();
            for k in 0..rf.nrows() {
                a_rows.push(rf.row(k).iter().copied().collect());
                rec.push(r);
            }
        }
        let packed = Library {
            a: DMatrix::from_fn(a_rows.len(), 4, |i, j| a_rows[i][j]),
            y: DVector::from_iterator(a_rows.len(), a_rows.iter().map(|r| r[4])),
            recording_of_row: rec,
            groups: raw.groups.clone(),
        };
        let all_raw: Vec<usize> = (0..raw.y.len()).collect();
        let all_packed: Vec<usize> = (0..packed.y.len()).collect();
        let (b1, b2) = (
            group_stlsq(&raw, &all_raw, 0.05),
            group_stlsq(&packed, &all_packed, 0.05),
        );
        assert_eq!(b1.kept, b2.kept);
        assert!((&b1.beta - &b2.beta).norm() < 1e-9, "{} vs {}", b1.beta, b2.beta);
        let (s1, s2) = (raw.sse_by_recording(&b1.beta), packed.sse_by_recording(&b1.beta));
        for ((_, x), (_, y)) in s1.iter().zip(&s2) {
            assert!((x - y).abs() < 1e-9 * x.max(1.0), "{x} vs {y}");
        }
    }

    /// Evidence: hand-written. A spring read through a lagged force channel,
    /// `y = sin(ω(t − τ)) ≈ sin ωt − ωτ·cos ωt`, on a library of the spring
    /// and a damping group `cos ωt` that must be ≥ 0: least squares fits the
    /// damping at −ωτ (negative damping standing in for the lag), which its
    /// real form would hold at 0, so the fit does not keep it.
    #[test]
    fn a_sign_constrained_group_fitted_net_negative_is_not_kept() {
        let (w, tau) = (2.0 * std::f64::consts::PI, 0.05);
        let t: Vec<f64> = (0..400).map(|k| k as f64 * 0.005).collect();
        let lib = Library {
            a: DMatrix::from_fn(
                t.len(),
                2,
                |i, j| if j == 0 { (w * t[i]).sin() } else { (w * t[i]).cos() },
            ),
            y: DVector::from_iterator(t.len(), t.iter().map(|t| (w * (t - tau)).sin())),
            recording_of_row: (0..t.len()).map(|i| i / 100).collect(),
            groups: vec![
                Group {
                    name: "spring".into(),
                    cols: vec![0],
                    always: true,
                    nonnegative: false,
                },
                Group {
                    name: "damping".into(),
                    cols: vec![1],
                    always: false,
                    nonnegative: true,
                },
            ],
        };
        let all: Vec<usize> = (0..lib.y.len()).collect();
        // Unconstrained it would be kept: sin(ωτ) ≈ 0.31 of the force, far
        // above the 5 % share.
        let mut free = lib.clone();
        free.groups[1].nonnegative = false;
        let s = group_stlsq(&free, &all, 0.05);
        assert_eq!(s.kept, vec![true, true]);
        assert!((s.beta[1] + (w * tau).sin()).abs() < 1e-6, "{}", s.beta[1]);
        assert_eq!(group_stlsq(&lib, &all, 0.05).kept, vec![true, false]);
    }

    #[test]
    fn the_stability_bound_is_q_squared_over_2pi_minus_1_times_p() {
        // q = 2 kept of p = 8 at π = 0.9: 4 / (0.8 · 8) = 0.625.
        assert!((stability_bound(2.0, 8, 0.9) - 0.625).abs() < 1e-12);
        assert!(stability_bound(2.0, 8, 0.5).is_infinite());
    }
}
