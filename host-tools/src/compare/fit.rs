//! Fitting a nonlinear family: GSA (the project's published algorithm,
//! [`crate::fit::gsa::minimize_batch`], agents evaluated in parallel) on
//! decimated recordings, then Levenberg–Marquardt (the `levenberg-marquardt`
//! crate) from GSA's best on denser recordings.
//!
//! Objective: J = √(mean over recordings of NRMSE²), NRMSE = RMSE / max |F|,
//! so every recording weighs the same. Both stages search only a family's
//! nonlinear parameters q; for each q the linear ones θ are the exact
//! weighted least-squares optimum ([`project`], variable projection). Both
//! run in the box normalised to [0, 1] per parameter; LM's steps are
//! projected back into it.
use super::families::{interpolate_sets, Basis, CurrentLaw, Family, Scales};
use super::tracks::Track;
use crate::dataset::Role;
use crate::fit::gsa::{minimize_batch, GsaParams, GsaResultN};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{storage::Owned, DMatrix, DVector, Dyn};
use rayon::prelude::*;

/// How much work a nonlinear fit gets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    pub gsa: GsaParams,
    /// Each recording is decimated to about this many samples for GSA.
    pub gsa_samples_per_track: usize,
    /// … and to this many for LM (`usize::MAX`: every sample).
    pub lm_samples_per_track: usize,
    /// LM stops after this many evaluations per parameter (+1).
    pub lm_patience: usize,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            gsa: GsaParams {
                agents: 40,
                iters: 150,
                ..GsaParams::default()
            },
            gsa_samples_per_track: 600,
            lm_samples_per_track: 3000,
            lm_patience: 30,
        }
    }
}

/// A fitted family: one parameter set per fitted current (PerCurrent) or one
/// set for all (Joint, stored with current NaN).
#[derive(Clone, Debug, PartialEq)]
pub struct FittedFamily {
    pub sets: Vec<(f64, Vec<f64>)>,
    pub law: CurrentLaw,
    /// Objective after GSA and after LM, per set (on their own sample grids).
    pub gsa_objective: Vec<f64>,
    pub lm_objective: Vec<f64>,
    pub evaluations: usize,
}

impl FittedFamily {
    /// The parameters the model uses at `current_a`.
    pub fn params_at(&self, current_a: f64) -> Vec<f64> {
        match self.law {
            CurrentLaw::Joint => self.sets.first().map(|s| s.1.clone()).unwrap_or_default(),
            CurrentLaw::PerCurrent => interpolate_sets(&self.sets, current_a),
        }
    }

    pub fn n_parameters(&self) -> usize {
        self.sets.iter().map(|s| s.1.len()).sum()
    }
}

/// The model force along a track (NaN everywhere if the parameters are not admissible).
pub fn predict(family: &dyn Family, fitted: &FittedFamily, track: &Track) -> Vec<f64> {
    let mut out = Vec::with_capacity(track.len());
    if !family.simulate(&fitted.params_at(track.current_a), track, &mut out) {
        out = vec![f64::NAN; track.len()];
    }
    out
}

/// The linear parameters solved for fixed nonlinear ones, and J there.
#[derive(Clone, Debug, PartialEq)]
pub struct Projected {
    pub objective: f64,
    pub theta: Vec<f64>,
    /// Weighted residuals (model − measured)·w, w = 1/(max|F|·√(n·R)), so Σr² = J².
    pub residuals: Vec<f64>,
}

/// Variable projection at `q` over `tracks` (None if `q` is not admissible
/// or the columns are rank-deficient). The k ≤ 6 columns are equilibrated
/// and solved through their k×k Gram matrix by Cholesky; with `residuals`
/// false only J is computed (the GSA path), from the Gram form.
pub fn project(
    family: &dyn Family,
    q: &[f64],
    tracks: &[Track],
    bases: &mut Vec<Basis>,
    residuals: bool,
) -> Option<Projected> {
    let k = family.linear_names().len();
    if k > MAX_LINEAR {
        return None;
    }
    bases.resize_with(tracks.len(), Basis::default);
    // Fixed-size accumulators on the stack: this loop is the GSA's hot path
    // (no allocation, no dynamic indexing per sample).
    let mut gram = [[0.0f64; MAX_LINEAR]; MAX_LINEAR];
    let mut rhs = [0.0f64; MAX_LINEAR];
    let mut yy = 0.0;
    let r = tracks.len().max(1) as f64;
    for (t, b) in tracks.iter().zip(bases.iter_mut()) {
        if !family.basis(q, t, b) || b.columns.len() != k || b.columns.iter().any(|c| c.len() != t.len()) {
            return None;
        }
        // k known at compile time, so the loops unroll (k ≤ MAX_LINEAR checked above).
        let (g, h, s) = match k {
            0 => normal_sums::<0>(t, b),
            1 => normal_sums::<1>(t, b),
            2 => normal_sums::<2>(t, b),
            3 => normal_sums::<3>(t, b),
            4 => normal_sums::<4>(t, b),
            5 => normal_sums::<5>(t, b),
            _ => normal_sums::<MAX_LINEAR>(t, b),
        };
        let w2 = weight(t, r).powi(2);
        for a in 0..k {
            rhs[a] += w2 * h[a];
            for c in a..k {
                gram[a][c] += w2 * g[a][c];
            }
        }
        yy += w2 * s;
    }
    let (theta, sse) = solve_normal(&gram, &rhs, yy, k)?;
    let theta = theta[..k].to_vec();
    let residuals = if residuals {
        let mut out = Vec::with_capacity(tracks.iter().map(Track::len).sum());
        let mut force = Vec::new();
        for (t, b) in tracks.iter().zip(bases.iter()) {
            let w = weight(t, r);
            b.force(&theta, &mut force);
            out.extend(force.iter().zip(&t.force_n).map(|(m, f)| (m - f) * w));
        }
        out
    } else {
        Vec::new()
    };
    // With residuals at hand, J from them (no cancellation near a perfect fit).
    let objective = if residuals.is_empty() {
        sse.sqrt()
    } else {
        residuals.iter().map(|e| e * e).sum::<f64>().sqrt()
    };
    (objective.is_finite() && theta.iter().all(|t| t.is_finite())).then_some(Projected {
        objective,
        theta,
        residuals,
    })
}

/// The normal equations G·θ = b (G's upper triangle in `gram`, k ≤ MAX_LINEAR)
/// solved by Cholesky after equilibration (G scaled to a unit diagonal): θ
/// and SSE = yᵀy − θᵀb. None if G is not positive definite or not finite.
/// Shared by [`project`] and the batch objectives of the families.
pub(crate) fn solve_normal(
    gram: &[[f64; MAX_LINEAR]; MAX_LINEAR],
    rhs: &[f64; MAX_LINEAR],
    yy: f64,
    k: usize,
) -> Option<([f64; MAX_LINEAR], f64)> {
    let k = k.min(MAX_LINEAR);
    let mut scale = [0.0; MAX_LINEAR];
    for a in 0..k {
        scale[a] = gram[a][a].sqrt();
        if !scale[a].is_finite() || scale[a] <= 0.0 {
            return None;
        }
    }
    // Lower Cholesky factor of the scaled G, then forward and back substitution.
    let mut l = [[0.0; MAX_LINEAR]; MAX_LINEAR];
    for a in 0..k {
        for c in 0..=a {
            let dot: f64 = l[a][..c].iter().zip(&l[c][..c]).map(|(p, q)| p * q).sum();
            let sum = gram[c][a] / (scale[a] * scale[c]) - dot;
            if a == c {
                if sum.is_nan() || sum <= 0.0 {
                    return None;
                }
                l[a][a] = sum.sqrt();
            } else {
                l[a][c] = sum / l[c][c];
            }
        }
    }
    let mut y = [0.0; MAX_LINEAR];
    for a in 0..k {
        let dot: f64 = l[a][..a].iter().zip(&y[..a]).map(|(p, q)| p * q).sum();
        y[a] = (rhs[a] / scale[a] - dot) / l[a][a];
    }
    let mut theta = [0.0; MAX_LINEAR];
    for a in (0..k).rev() {
        let dot: f64 = (a + 1..k).map(|m| l[m][a] * theta[m]).sum();
        theta[a] = (y[a] - dot) / l[a][a];
    }
    for a in 0..k {
        theta[a] /= scale[a];
    }
    // SSE = yᵀy − 2θᵀb + θᵀGθ = yᵀy − θᵀb at the optimum.
    let sse = (yy - (0..k).map(|a| theta[a] * rhs[a]).sum::<f64>()).max(0.0);
    Some((theta, sse))
}

/// Gram matrix (upper triangle), Xᵀy and yᵀy of one track's basis (unweighted).
type NormalSums = ([[f64; MAX_LINEAR]; MAX_LINEAR], [f64; MAX_LINEAR], f64);

fn normal_sums<const K: usize>(t: &Track, b: &Basis) -> NormalSums {
    let cols: [&[f64]; K] = std::array::from_fn(|a| &b.columns[a][..t.len()]);
    let (mut g, mut h, mut s) = ([[0.0; K]; K], [0.0; K], 0.0);
    for (i, f) in t.force_n.iter().take(t.len()).enumerate() {
        let y = f - b.offset.get(i).copied().unwrap_or(0.0);
        let phi: [f64; K] = std::array::from_fn(|a| cols[a][i]);
        for a in 0..K {
            h[a] += phi[a] * y;
            for c in a..K {
                g[a][c] += phi[a] * phi[c];
            }
        }
        s += y * y;
    }
    let mut out = ([[0.0; MAX_LINEAR]; MAX_LINEAR], [0.0; MAX_LINEAR], s);
    for a in 0..K {
        out.1[a] = h[a];
        out.0[a][..K].copy_from_slice(&g[a]);
    }
    out
}

/// Most linear parameters a family may have (the exponential family's six).
pub(crate) const MAX_LINEAR: usize = 6;

/// A track's residual weight 1/(max|F|·√(n·R)), R = number of tracks, so Σr² = J².
pub(crate) fn weight(t: &Track, tracks: f64) -> f64 {
    1.0 / (t.force_scale_n * (t.len().max(1) as f64 * tracks).sqrt())
}

/// J at `q` (∞ if not admissible).
pub fn objective(family: &dyn Family, q: &[f64], tracks: &[Track], bases: &mut Vec<Basis>) -> f64 {
    project(family, q, tracks, bases, false).map_or(f64::INFINITY, |p| p.objective)
}

/// Fits `family` to the `fit` tracks (validate tracks are never passed on).
pub fn fit_family(family: &dyn Family, tracks: &[Track], budget: &Budget, seed: u64) -> FittedFamily {
    let fit: Vec<&Track> = tracks.iter().filter(|t| t.role == Role::Fit).collect();
    let scales = Scales::of(fit.iter().copied());
    let groups: Vec<(f64, Vec<Track>)> = match family.law() {
        CurrentLaw::Joint => vec![(f64::NAN, fit.iter().map(|t| (*t).clone()).collect())],
        CurrentLaw::PerCurrent => {
            let mut currents: Vec<f64> = fit.iter().map(|t| t.current_a).collect();
            currents.sort_by(f64::total_cmp);
            currents.dedup();
            currents
                .into_iter()
                .map(|c| {
                    (
                        c,
                        fit.iter().filter(|t| t.current_a == c).map(|t| (*t).clone()).collect(),
                    )
                })
                .collect()
        }
    };
    let (lower, upper) = family.bounds(&scales);
    let fits: Vec<(f64, Vec<f64>, f64, f64, usize)> = groups
        .par_iter()
        .enumerate()
        .map(|(g, (current, group))| {
            let coarse: Vec<Track> = group.iter().map(|t| t.at_most(budget.gsa_samples_per_track)).collect();
            let r = search(family, &coarse, &lower, &upper, &budget.gsa, seed, g as u64);
            let dense: Vec<Track> = group.iter().map(|t| t.at_most(budget.lm_samples_per_track)).collect();
            let (q, lm_value, lm_evals) = refine(family, &r.best, &lower, &upper, &dense, budget.lm_patience);
            // θ from the dense samples at the refined q (an admissible q: GSA's best was).
            let theta = project(family, &q, &dense, &mut Vec::new(), false)
                .map(|p| p.theta)
                .unwrap_or_default();
            let full = q.into_iter().chain(theta).collect();
            (*current, full, r.best_value, lm_value, r.evaluations + lm_evals)
        })
        .collect();
    FittedFamily {
        sets: fits.iter().map(|f| (f.0, f.1.clone())).collect(),
        law: family.law(),
        gsa_objective: fits.iter().map(|f| f.2).collect(),
        lm_objective: fits.iter().map(|f| f.3).collect(),
        evaluations: fits.iter().map(|f| f.4).sum(),
    }
}

/// GSA over the box, agents evaluated in parallel; seeded by (seed, stream).
pub fn search(
    family: &dyn Family,
    tracks: &[Track],
    lower: &[f64],
    upper: &[f64],
    gsa: &GsaParams,
    seed: u64,
    stream: u64,
) -> GsaResultN {
    let mut rng = crate::fit::branch_rng(seed, stream);
    let batch = family.batch_objective(tracks);
    minimize_batch(
        lower,
        upper,
        |agents| match &batch {
            Some(b) => b.evaluate(agents),
            None => agents
                .par_iter()
                .map_init(Vec::new, |bases, q| objective(family, q, tracks, bases))
                .collect(),
        },
        gsa,
        &mut rng,
        || {},
    )
}

/// LM from `start`; returns the best of the start and LM's end points, its
/// objective and the evaluations spent (each Jacobian counts n + 1, n the
/// parameters LM moves). LM's steps are clipped to the box, which stalls it
/// along a bound; so when it ends with some parameters on a bound, a second
/// LM moves only the others from there.
pub fn refine(
    family: &dyn Family,
    start: &[f64],
    lower: &[f64],
    upper: &[f64],
    tracks: &[Track],
    patience: usize,
) -> (Vec<f64>, f64, usize) {
    let mut bases = Vec::new();
    let start_value = objective(family, start, tracks, &mut bases);
    let mut best = (start.to_vec(), start_value);
    let mut evals = 0;
    let mut u = DVector::from_iterator(
        start.len(),
        start
            .iter()
            .zip(lower.iter().zip(upper))
            .map(|(p, (lo, hi))| if hi > lo { (p - lo) / (hi - lo) } else { 0.0 }),
    );
    let mut active: Vec<usize> = (0..start.len()).collect();
    for _round in 0..2 {
        let problem = LmProblem {
            family,
            tracks,
            lower,
            upper,
            u: u.clone(),
            active: active.clone(),
            last: std::sync::Mutex::new(None),
        };
        let (solved, report) = LevenbergMarquardt::new().with_patience(patience).minimize(problem);
        evals += report.number_of_evaluations * (active.len() + 1);
        let q = solved.raw(&solved.u);
        let value = objective(family, &q, tracks, &mut bases);
        if value <= best.1 {
            best = (q, value);
        }
        u = solved.u;
        let free: Vec<usize> = active.iter().copied().filter(|&j| u[j] > 0.0 && u[j] < 1.0).collect();
        if free.is_empty() || free.len() == active.len() {
            break;
        }
        active = free;
    }
    (best.0, best.1, evals)
}

struct LmProblem<'a> {
    family: &'a dyn Family,
    tracks: &'a [Track],
    lower: &'a [f64],
    upper: &'a [f64],
    /// Normalised nonlinear parameters (0 = lower bound, 1 = upper bound).
    u: DVector<f64>,
    /// The entries of `u` LM moves (the others stay fixed).
    active: Vec<usize>,
    /// The residuals LM last asked for, and where: its Jacobian at the same
    /// point reuses them instead of integrating the model again.
    last: std::sync::Mutex<Option<(DVector<f64>, Vec<f64>)>>,
}

/// Forward-difference step in normalised coordinates.
const JACOBIAN_STEP: f64 = 1e-6;
/// Residual scale for inadmissible parameters (as if the model were ten
/// times the measured force off): LM rejects such a step and shrinks.
const PENALTY: f64 = 10.0;

impl LmProblem<'_> {
    fn raw(&self, u: &DVector<f64>) -> Vec<f64> {
        u.iter()
            .zip(self.lower.iter().zip(self.upper))
            .map(|(u, (lo, hi))| lo + u.clamp(0.0, 1.0) * (hi - lo))
            .collect()
    }

    /// The projected residuals at `u` (a penalty if not admissible).
    fn residuals_at(&self, u: &DVector<f64>) -> Vec<f64> {
        match project(self.family, &self.raw(u), self.tracks, &mut Vec::new(), true) {
            Some(p) => p.residuals,
            None => {
                let r = self.tracks.len().max(1) as f64;
                self.tracks
                    .iter()
                    .flat_map(|t| {
                        let w = weight(t, r);
                        t.force_n.iter().map(move |f| -PENALTY * f * w)
                    })
                    .collect()
            }
        }
    }
}
impl LeastSquaresProblem<f64, Dyn, Dyn> for LmProblem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, u: &DVector<f64>) {
        for (&j, v) in self.active.iter().zip(u.iter()) {
            self.u[j] = v.clamp(0.0, 1.0);
        }
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_iterator(self.active.len(), self.active.iter().map(|&j| self.u[j]))
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.residuals_at(&self.u);
        if let Ok(mut last) = self.last.lock() {
            *last = Some((self.u.clone(), r.clone()));
        }
        Some(DVector::from_vec(r))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let cached = self
            .last
            .lock()
            .ok()
            .and_then(|last| last.as_ref().filter(|(u, _)| *u == self.u).map(|(_, r)| r.clone()));
        let base = cached.unwrap_or_else(|| self.residuals_at(&self.u));
        let n = self.active.len();
        let columns: Vec<Vec<f64>> = self
            .active
            .par_iter()
            .map(|&j| {
                let mut u = self.u.clone();
                // Step inwards at the upper bound so the difference sees the model.
                let h = if u[j] + JACOBIAN_STEP > 1.0 {
                    -JACOBIAN_STEP
                } else {
                    JACOBIAN_STEP
                };
                u[j] += h;
                let shifted = self.residuals_at(&u);
                shifted.iter().zip(&base).map(|(a, b)| (a - b) / h).collect()
            })
            .collect();
        Some(DMatrix::from_fn(base.len(), n, |i, j| columns[j][i]))
    }
}
