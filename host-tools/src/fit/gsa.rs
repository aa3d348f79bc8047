//! The Gravitational Search Algorithm exactly as published (Rashedi,
//! Nezamabadi-pour, Saryazdi, "GSA: A Gravitational Search Algorithm",
//! Information Sciences 179, 2009), minimising. Per iteration t = 1..T:
//!
//! 1. evaluate every agent's fitness fitᵢ (N evaluations per iteration, N·T in all);
//! 2. masses (Eqs. 9–12 of the paper there, 14–15 in Rashedi):
//!    mᵢ = (fitᵢ − worst)/(best − worst), Mᵢ = mᵢ / Σⱼ mⱼ (all equal → Mᵢ = 1/N);
//! 3. G(t) = G0·e^(−α·t/T);
//! 4. Kbest: the K heaviest agents, K falling linearly from N (t = 0) to
//!    `final_kbest_pct` % of N (t = T), rounded, at least 1;
//! 5. force on i from each j ∈ Kbest, j ≠ i: F_ij = G·(M_pi·M_aj)/(R_ij + ε)·(x_j − x_i)
//!    (the *product* of masses: the paper's Eq. 5 prints a sum, a typo; see
//!    `shared/paper/README.md`), R_ij the Euclidean distance, ε = 2⁻⁵²;
//!    total Fᵢ = Σⱼ rand_ij·F_ij with one uniform random weight per force
//!    term; aᵢ = Fᵢ/M_ii. With M_pi = M_ii = Mᵢ, aᵢ = G·Σⱼ rand_ij·Mⱼ·(x_j − x_i)/(R_ij + ε);
//! 6. vᵢ ← randᵢ·vᵢ + aᵢ (one uniform random per agent), xᵢ ← xᵢ + vᵢ;
//! 7. bounds: a coordinate that left [lower, upper] is re-drawn uniformly
//!    inside it (as Rashedi's reference code does); its velocity is kept.
//!
//! Coordinates: the algorithm runs on the search box mapped affinely onto
//! [−100, 100]⁵, the range of Rashedi's benchmark functions for which G0 = 100
//! and α = 20 were tuned; the objective sees the mapped-back coefficients. In
//! raw coefficients (~10⁴ N/mm⁴ next to ~10 N) one G-sized step is negligible
//! along some axes and huge along others, and the published constants stall.
//!
//! Agents start uniform in the box with zero velocity. Fitness that is not
//! finite counts as the worst possible (f64::MAX). The result is the best
//! agent ever evaluated; `convergence[t]` is the best-so-far after iteration t+1.
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
    mut evaluate: impl FnMut(&[Vec<f64>]) -> Vec<f64>,
    params: &GsaParams,
    rng: &mut impl Rng,
    mut on_iteration: impl FnMut(),
) -> GsaResultN {
    let dim = lower.len().min(upper.len());
    let n = params.agents.max(1);
    let t_max = params.iters.max(1);
    let eps = f64::EPSILON;
    // Agent positions live in [−SPAN, SPAN]^dim; `to_box` maps them back.
    const SPAN: f64 = 100.0;
    let to_box = |u: &[f64]| -> Vec<f64> {
        (0..dim)
            .map(|d| lower[d] + (u[d] + SPAN) / (2.0 * SPAN) * (upper[d] - lower[d]))
            .collect()
    };
    let mut x: Vec<Vec<f64>> = (0..n)
        .map(|_| (0..dim).map(|_| -SPAN + rng.random::<f64>() * 2.0 * SPAN).collect())
        .collect();
    let mut v = vec![vec![0.0; dim]; n];
    let mut mass = vec![0.0; n];
    let mut order: Vec<usize> = (0..n).collect();
    let mut best = to_box(&x[0]);
    let mut best_value = f64::INFINITY;
    let mut convergence = Vec::with_capacity(t_max);
    let mut evaluations = 0;
    let mut acc = vec![0.0; dim];

    for t in 1..=t_max {
        let mapped: Vec<Vec<f64>> = x.iter().map(|xi| to_box(xi)).collect();
        let values = evaluate(&mapped);
        let mut fit = Vec::with_capacity(n);
        for (i, coeffs) in mapped.into_iter().enumerate() {
            let value = values.get(i).copied().unwrap_or(f64::NAN);
            evaluations += 1;
            let f = if value.is_finite() { value } else { f64::MAX };
            if f < best_value {
                best_value = f;
                best = coeffs;
            }
            fit.push(f);
        }
        convergence.push(best_value);
        // Masses (minimisation: best = smallest fitness).
        let (lo, hi) = fit
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &f| (l.min(f), h.max(f)));
        if hi > lo {
            for (m, f) in mass.iter_mut().zip(&fit) {
                *m = (f - hi) / (lo - hi);
            }
        } else {
            mass.fill(1.0);
        }
        let total: f64 = mass.iter().sum();
        for m in &mut mass {
            *m /= total;
        }

        let progress = t as f64 / t_max as f64;
        let g = params.g0 * (-params.alpha * progress).exp();
        let kbest_pct = params.final_kbest_pct + (1.0 - progress) * (100.0 - params.final_kbest_pct);
        let kbest = ((n as f64 * kbest_pct / 100.0).round() as usize).clamp(1, n);
        order.sort_unstable_by(|&a, &b| mass[b].total_cmp(&mass[a]));
        let heavy = &order[..kbest];

        for i in 0..n {
            acc.fill(0.0);
            for &j in heavy {
                if j == i {
                    continue;
                }
                let r2: f64 = x[j].iter().zip(&x[i]).map(|(a, b)| (a - b) * (a - b)).sum();
                let w = rng.random::<f64>() * mass[j] / (r2.sqrt() + eps);
                for d in 0..dim {
                    acc[d] += w * (x[j][d] - x[i][d]);
                }
            }
            let keep = rng.random::<f64>();
            for d in 0..dim {
                v[i][d] = keep * v[i][d] + g * acc[d];
            }
        }
        for (xi, vi) in x.iter_mut().zip(&v) {
            for d in 0..dim {
                xi[d] += vi[d];
                if !(-SPAN..=SPAN).contains(&xi[d]) {
                    xi[d] = -SPAN + rng.random::<f64>() * 2.0 * SPAN;
                }
            }
        }
        on_iteration();
    }
    GsaResultN {
        best,
        best_value,
        convergence,
        evaluations,
    }
}
