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

/// Minimises `objective` over `bounds`. `on_iteration` is called after each
/// iteration (for progress display).
pub fn minimize(
    objective: impl Fn(&[f64; 5]) -> f64,
    bounds: &SearchBox,
    params: &GsaParams,
    rng: &mut impl Rng,
    mut on_iteration: impl FnMut(),
) -> GsaResult {
    const D: usize = 5;
    let n = params.agents.max(1);
    let t_max = params.iters.max(1);
    let eps = f64::EPSILON;
    let mut x: Vec<[f64; D]> = (0..n)
        .map(|_| std::array::from_fn(|d| bounds.lower[d] + rng.random::<f64>() * (bounds.upper[d] - bounds.lower[d])))
        .collect();
    let mut v = vec![[0.0; D]; n];
    let mut fit = vec![0.0; n];
    let mut mass = vec![0.0; n];
    let mut order: Vec<usize> = (0..n).collect();
    let mut best = x[0];
    let mut best_value = f64::INFINITY;
    let mut convergence = Vec::with_capacity(t_max);
    let mut evaluations = 0;

    for t in 1..=t_max {
        for (f, xi) in fit.iter_mut().zip(&x) {
            let value = objective(xi);
            evaluations += 1;
            *f = if value.is_finite() { value } else { f64::MAX };
            if *f < best_value {
                best_value = *f;
                best = *xi;
            }
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
            let mut acc = [0.0; D];
            for &j in heavy {
                if j == i {
                    continue;
                }
                let r2: f64 = x[j].iter().zip(&x[i]).map(|(a, b)| (a - b) * (a - b)).sum();
                let w = rng.random::<f64>() * mass[j] / (r2.sqrt() + eps);
                for d in 0..D {
                    acc[d] += w * (x[j][d] - x[i][d]);
                }
            }
            let keep = rng.random::<f64>();
            for d in 0..D {
                v[i][d] = keep * v[i][d] + g * acc[d];
            }
        }
        for (xi, vi) in x.iter_mut().zip(&v) {
            for d in 0..D {
                xi[d] += vi[d];
                if !(xi[d] >= bounds.lower[d] && xi[d] <= bounds.upper[d]) {
                    xi[d] = bounds.lower[d] + rng.random::<f64>() * (bounds.upper[d] - bounds.lower[d]);
                }
            }
        }
        on_iteration();
    }
    GsaResult {
        best,
        best_value,
        convergence,
        evaluations,
    }
}
