//! The Gravitational Search Algorithm exactly as published (Rashedi,
//! Nezamabadi-pour, Saryazdi, "GSA: A Gravitational Search Algorithm",
//! Information Sciences 179, 2009), minimising. Per iteration t = 1..T:
//!
//! 1. evaluate every agent's fitness fitᵢ (N evaluations per iteration, N·T in all);
//! 2. masses (the paper's Eqs. 8–12, Rashedi's 14–17), see [`masses`]:
//!    mᵢ = (fitᵢ − worst)/(best − worst), Mᵢ = mᵢ / Σⱼ mⱼ (all equal → Mᵢ = 1/N);
//!    best and worst are the smallest and largest *finite* fitness, and an
//!    agent whose fitness is not finite (an inadmissible point) gets mass 0;
//! 3. G(t) = G0·e^(−α·t/T) (Eq. 7), see [`gravitational_constant`];
//! 4. Kbest: the K heaviest agents, K falling linearly from N (t = 0) to
//!    `final_kbest_pct` % of N (t = T), rounded, at least 1, see [`kbest`];
//! 5. force on i from each j ∈ Kbest, j ≠ i: F_ij = G·(M_pi·M_aj)/(R_ij + ε)·(x_j − x_i)
//!    (the *product* of masses: the paper's Eq. 5 prints a sum, a typo; see
//!    `shared/paper/README.md`), R_ij the Euclidean distance, ε = 2⁻⁵²;
//!    total Fᵢ = Σⱼ rand_ij·F_ij; aᵢ = Fᵢ/M_ii. With M_pi = M_ii = Mᵢ (Eq. 8),
//!    aᵢ = G·Σⱼ rand_ij·Mⱼ·(x_j − x_i)/(R_ij + ε), which is how it is computed
//!    (so an agent of mass 0 is still pulled towards the heavy ones);
//! 6. vᵢ ← randᵢ·vᵢ + aᵢ, xᵢ ← xᵢ + vᵢ;
//! 7. bounds: a coordinate that left [lower, upper] is re-drawn uniformly
//!    inside it (as Rashedi's reference code does); its velocity is kept.
//!
//! Random weights ([`RandomWeights`]): Rashedi's paper draws one rand_j per
//! force term (Eq. 7 there) and one randᵢ per agent for the velocity (Eq. 11);
//! his reference MATLAB code draws them per dimension (`rand` inside the loop
//! over dimensions, `rand(N,dim).*V`). The default is the paper's form
//! ([`RandomWeights::PerAgent`]): the paper we implement cites the published
//! equations, and a per-agent weight keeps each pull along the line joining
//! two agents. The code's form is [`RandomWeights::PerDimension`]. On
//! `data/drop-none`, both boxes, 10 seeds × 10 branches, neither form ends
//! lower significantly more often (sign tests p = 0.76 and 0.14; BENCHMARKS.md,
//! "Two boxes"), so `mre fit` has no flag for it.
//!
//! Coordinates: the algorithm runs on the search box mapped affinely onto
//! [−100, 100]ⁿ, the range of Rashedi's benchmark functions for which G0 = 100
//! and α = 20 were tuned; the objective sees the mapped-back coefficients. In
//! raw coefficients (~10⁴ N/mm⁴ next to ~10 N) one G-sized step is negligible
//! along some axes and huge along others, and the published constants stall.
//!
//! Agents start uniform in the box with zero velocity. The result is the best
//! agent ever evaluated with a finite fitness (`best_value` stays ∞ if none
//! was); `convergence[t]` is the best-so-far after iteration t+1. Every random
//! draw goes through one `draw` closure ([`minimize_with_draws`]), the seam
//! through which tests inject fixed draws.
use super::bounds::SearchBox;
use rand::Rng;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GsaParams {
    /// N, the number of agents.
    pub agents: usize,
    /// T, the number of iterations.
    pub iters: usize,
    pub g0: f64,
    pub alpha: f64,
    /// Kbest at t = T, in % of N.
    pub final_kbest_pct: f64,
    pub seed: u64,
    /// Where the random weights of the force sum and the velocity are drawn.
    pub weights: RandomWeights,
}

/// How the random weights of steps 5 and 6 are drawn (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RandomWeights {
    /// One weight per force term (i, j) and one per agent's velocity:
    /// Rashedi et al. 2009, Eqs. 7 and 11.
    #[default]
    PerAgent,
    /// One weight per force term and dimension, and one per agent's velocity
    /// and dimension: Rashedi's reference code.
    PerDimension,
}

impl Default for GsaParams {
    /// The paper's N = T = 100; G0 = 100, α = 20, Kbest → 2 % (Rashedi's values).
    fn default() -> Self {
        GsaParams {
            agents: 100,
            iters: 100,
            g0: 100.0,
            alpha: 20.0,
            final_kbest_pct: 2.0,
            seed: 1,
            weights: RandomWeights::PerAgent,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct GsaResult {
    pub best: [f64; 5],
    pub best_value: f64,
    /// Best-so-far objective after each iteration (length T).
    pub convergence: Vec<f64>,
    pub evaluations: usize,
}

/// The result of [`minimize_batch`] in any dimension.
#[derive(Clone, Debug, PartialEq)]
pub struct GsaResultN {
    pub best: Vec<f64>,
    pub best_value: f64,
    /// Best-so-far objective after each iteration (length T).
    pub convergence: Vec<f64>,
    pub evaluations: usize,
}

/// Minimises `objective` over `bounds`. `on_iteration` is called after each
/// iteration (for progress display).
pub fn minimize(
    objective: impl Fn(&[f64; 5]) -> f64,
    bounds: &SearchBox,
    params: &GsaParams,
    rng: &mut impl Rng,
    on_iteration: impl FnMut(),
) -> GsaResult {
    let r = minimize_batch(
        &bounds.lower,
        &bounds.upper,
        |batch| {
            batch
                .iter()
                .map(|c| objective(&std::array::from_fn(|d| c[d])))
                .collect()
        },
        params,
        rng,
        on_iteration,
    );
    GsaResult {
        best: std::array::from_fn(|d| r.best[d]),
        best_value: r.best_value,
        convergence: r.convergence,
        evaluations: r.evaluations,
    }
}

/// The same algorithm in `lower.len()` dimensions. `evaluate` gets every
/// agent's mapped-back position of one iteration at once and returns their
/// objective values in order, so a caller may evaluate them in parallel; the
/// random stream does not depend on how they are evaluated.
pub fn minimize_batch(
    lower: &[f64],
    upper: &[f64],
    evaluate: impl FnMut(&[Vec<f64>]) -> Vec<f64>,
    params: &GsaParams,
    rng: &mut impl Rng,
    on_iteration: impl FnMut(),
) -> GsaResultN {
    minimize_with_draws(
        lower,
        upper,
        evaluate,
        params,
        &mut || rng.random::<f64>(),
        on_iteration,
    )
}

/// Agent positions live in [−SPAN, SPAN]ⁿ (module doc, "Coordinates").
pub const SPAN: f64 = 100.0;

/// [`minimize_batch`] with every uniform [0, 1) draw taken from `draw`, in
/// this order: the initial positions (agent by agent, dimension by
/// dimension), then per iteration the draws of [`step`].
pub fn minimize_with_draws(
    lower: &[f64],
    upper: &[f64],
    mut evaluate: impl FnMut(&[Vec<f64>]) -> Vec<f64>,
    params: &GsaParams,
    draw: &mut dyn FnMut() -> f64,
    mut on_iteration: impl FnMut(),
) -> GsaResultN {
    let dim = lower.len().min(upper.len());
    let n = params.agents.max(1);
    let t_max = params.iters.max(1);
    let to_box = |u: &[f64]| -> Vec<f64> {
        (0..dim)
            .map(|d| lower[d] + (u[d] + SPAN) / (2.0 * SPAN) * (upper[d] - lower[d]))
            .collect()
    };
    let mut x: Vec<Vec<f64>> = (0..n)
        .map(|_| (0..dim).map(|_| -SPAN + draw() * 2.0 * SPAN).collect())
        .collect();
    let mut v = vec![vec![0.0; dim]; n];
    let mut best = to_box(&x[0]);
    let mut best_value = f64::INFINITY;
    let mut convergence = Vec::with_capacity(t_max);
    let mut evaluations = 0;

    for t in 1..=t_max {
        let mapped: Vec<Vec<f64>> = x.iter().map(|xi| to_box(xi)).collect();
        let values = evaluate(&mapped);
        let mut fit = Vec::with_capacity(n);
        for (i, coeffs) in mapped.into_iter().enumerate() {
            let value = values.get(i).copied().unwrap_or(f64::NAN);
            evaluations += 1;
            if value.is_finite() && value < best_value {
                best_value = value;
                best = coeffs;
            }
            fit.push(value);
        }
        convergence.push(best_value);
        step(&mut x, &mut v, &fit, t, params, draw);
        on_iteration();
    }
    GsaResultN {
        best,
        best_value,
        convergence,
        evaluations,
    }
}

/// Normalised masses Mᵢ of one iteration (Eqs. 9–12) from the agents'
/// fitness: best and worst over the finite values only; a non-finite fitness
/// gets mass 0. All finite values equal → equal masses among them; no finite
/// value at all → 1/N each (nothing to rank by: Rashedi's best = worst case).
pub fn masses(fit: &[f64]) -> Vec<f64> {
    let finite = || fit.iter().copied().filter(|f| f.is_finite());
    let best = finite().fold(f64::INFINITY, f64::min);
    let worst = finite().fold(f64::NEG_INFINITY, f64::max);
    if !best.is_finite() {
        return vec![1.0 / fit.len().max(1) as f64; fit.len()];
    }
    let m: Vec<f64> = fit
        .iter()
        .map(|&f| match f.is_finite() {
            false => 0.0,
            true if worst > best => (f - worst) / (best - worst),
            true => 1.0,
        })
        .collect();
    let total: f64 = m.iter().sum();
    m.iter().map(|mi| mi / total).collect()
}

/// G(t) = G0·e^(−α·t/T) (Eq. 7).
pub fn gravitational_constant(params: &GsaParams, t: usize) -> f64 {
    let progress = t as f64 / params.iters.max(1) as f64;
    params.g0 * (-params.alpha * progress).exp()
}

/// K of Kbest at iteration t: from N at t = 0 linearly down to
/// `final_kbest_pct` % of N at t = T, rounded, within 1..=N.
pub fn kbest(params: &GsaParams, n: usize, t: usize) -> usize {
    let progress = t as f64 / params.iters.max(1) as f64;
    let pct = params.final_kbest_pct + (1.0 - progress) * (100.0 - params.final_kbest_pct);
    ((n as f64 * pct / 100.0).round() as usize).clamp(1, n.max(1))
}

/// What one iteration computed besides the new positions and velocities.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    pub masses: Vec<f64>,
    pub g: f64,
    /// The agents of Kbest, heaviest first (ties by index).
    pub kbest: Vec<usize>,
    /// aᵢ per agent.
    pub acceleration: Vec<Vec<f64>>,
}

/// One iteration's update (steps 2–7 of the module doc) of positions `x`
/// (in [−SPAN, SPAN]ⁿ) and velocities `v` from the agents' fitness at
/// iteration t. Draws, in order: for each agent i, one weight per j ∈ Kbest
/// (j ≠ i, heaviest first) and then one for its velocity (per dimension
/// for [`RandomWeights::PerDimension`]: d varies fastest); then, agent by
/// agent and dimension by dimension, one for each coordinate that left the box.
pub fn step(
    x: &mut [Vec<f64>],
    v: &mut [Vec<f64>],
    fit: &[f64],
    t: usize,
    params: &GsaParams,
    draw: &mut dyn FnMut() -> f64,
) -> Step {
    let n = x.len();
    let dim = x.first().map_or(0, Vec::len);
    let eps = f64::EPSILON;
    let mass = masses(fit);
    let g = gravitational_constant(params, t);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| mass[b].total_cmp(&mass[a]));
    order.truncate(kbest(params, n, t));
    let per_dimension = params.weights == RandomWeights::PerDimension;
    let mut acceleration = vec![vec![0.0; dim]; n];
    for i in 0..n {
        let acc = &mut acceleration[i];
        for &j in &order {
            if j == i {
                continue;
            }
            let r = x[j]
                .iter()
                .zip(&x[i])
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            if per_dimension {
                for d in 0..dim {
                    acc[d] += draw() * mass[j] / (r + eps) * (x[j][d] - x[i][d]);
                }
            } else {
                let w = draw() * mass[j] / (r + eps);
                for d in 0..dim {
                    acc[d] += w * (x[j][d] - x[i][d]);
                }
            }
        }
        // aᵢ = G·acc; kept in this order so `mre fit`'s results do not move.
        for a in acc.iter_mut() {
            *a *= g;
        }
        if per_dimension {
            for d in 0..dim {
                v[i][d] = draw() * v[i][d] + acc[d];
            }
        } else {
            let keep = draw();
            for d in 0..dim {
                v[i][d] = keep * v[i][d] + acc[d];
            }
        }
    }
    for (xi, vi) in x.iter_mut().zip(v.iter()) {
        for d in 0..dim {
            xi[d] += vi[d];
            if !(-SPAN..=SPAN).contains(&xi[d]) {
                xi[d] = -SPAN + draw() * 2.0 * SPAN;
            }
        }
    }
    Step {
        masses: mass,
        g,
        kbest: order,
        acceleration,
    }
}
