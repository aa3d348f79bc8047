//! Fitting on synthetic data made from known quartics: least squares recovers
//! them up to noise, the moment-form objective equals the sample sum, one GSA
//! iteration equals a step worked by hand from the published equations, GSA
//! converges towards the optimum (also with infeasible agents) and keeps every
//! agent in its box, and the model file is a table file.
use mre_algorithm::model::Branch;
use mre_host::dataset::BranchSamples;
use mre_host::fit::bounds::{data_bounds, paper_bounds, SearchBox};
use mre_host::fit::gsa::{masses, minimize, minimize_batch, minimize_with_draws, step, GsaParams, RandomWeights};
use mre_host::fit::lsq::fit_quartic;
use mre_host::fit::objective::{rmse_by_samples, BranchMoments};
use mre_host::fit::poly::eval;
use mre_host::fit::problems::BranchProblem;
use mre_host::fit::{branch_rng, fit_branches, FitOptions, Method};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

/// The paper's Table 4, 1 A compression quartic (x in mm, F in N).
const PAPER_1A_C: [f64; 5] = [3422.00, -8986.60, 2936.20, 9330.20, 336.52];
const PAPER_1A_E: [f64; 5] = [-2193.60, 8677.00, -7363.90, 7180.70, -22.37];

/// n samples over 0..1.1 mm of `c` plus Gaussian noise σ (N).
fn synthetic(c: &[f64; 5], n: usize, sigma: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let noise = Normal::new(0.0, sigma.max(1e-300)).unwrap();
    let x: Vec<f64> = (0..n).map(|i| 1.1 * i as f64 / (n - 1) as f64).collect();
    let f = x
        .iter()
        .map(|&x| eval(c, x) + if sigma > 0.0 { noise.sample(&mut rng) } else { 0.0 })
        .collect();
    (x, f)
}

#[test]
fn lsq_recovers_exact_coefficients_without_noise() {
    let (x, f) = synthetic(&PAPER_1A_C, 200, 0.0, 1);
    let fit = fit_quartic(&x, &f).unwrap();
    for (got, want) in fit.coeffs.iter().zip(&PAPER_1A_C) {
        assert!((got - want).abs() <= 1e-7 * want.abs(), "{got} vs {want}");
    }
    assert!(fit.rmse_n < 1e-8);
}

#[test]
fn lsq_recovers_coefficients_up_to_noise_on_a_wide_offset_stroke() {
    // x over 20..45 mm: raw x⁴ columns would be badly conditioned.
    let c = [0.002, -0.3, 15.0, -250.0, 1500.0];
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let noise = Normal::new(0.0, 1.0).unwrap();
    let x: Vec<f64> = (0..5000).map(|i| 20.0 + 25.0 * i as f64 / 4999.0).collect();
    let f: Vec<f64> = x.iter().map(|&x| eval(&c, x) + noise.sample(&mut rng)).collect();
    let fit = fit_quartic(&x, &f).unwrap();
    // The residual RMSE of the optimum is the noise σ = 1 N (to ~2 %), and the
    // fitted curve stays within a few σ/√n·√5 of the truth everywhere.
    assert!((fit.rmse_n - 1.0).abs() < 0.03, "{}", fit.rmse_n);
    for &xx in &[20.0, 27.0, 33.0, 45.0] {
        assert!((eval(&fit.coeffs, xx) - eval(&c, xx)).abs() < 0.2, "at {xx}");
    }
}

#[test]
fn moment_form_equals_the_sample_sum() {
    let (x, f) = synthetic(&PAPER_1A_E, 1000, 50.0, 2);
    let m = BranchMoments::new(&x, &f);
    for trial in [PAPER_1A_E, PAPER_1A_C, [0.0; 5], [1.0, -2.0, 3.0, -4.0, 5.0]] {
        let a = m.rmse(&trial);
        let b = rmse_by_samples(&x, &f, &trial);
        assert!((a - b).abs() <= 1e-9 * b.max(1.0), "{a} vs {b}");
    }
}

#[test]
fn gsa_lands_within_ten_percent_of_the_optimum_at_damper_scale() {
    // A quartic like the MTS damper's 0 A fit (x ±20 mm, F ~ ±200 N), σ = 40 N.
    let c = [-2.6e-4, -5e-4, 0.025, 1.77, 139.8];
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let noise = Normal::new(0.0, 40.0).unwrap();
    let x: Vec<f64> = (0..2000).map(|i| -20.0 + 40.0 * i as f64 / 1999.0).collect();
    let f: Vec<f64> = x.iter().map(|&x| eval(&c, x) + noise.sample(&mut rng)).collect();
    let optimum = fit_quartic(&x, &f).unwrap();
    // The optimum's RMSE is the noise level.
    assert!((optimum.rmse_n - 40.0).abs() < 2.0);
    let m = BranchMoments::new(&x, &f);
    let bounds = data_bounds(&x, &f).unwrap();
    for seed in 1..=3 {
        let params = GsaParams {
            seed,
            ..Default::default()
        };
        let r = minimize(|c| m.rmse(c), &bounds, &params, &mut branch_rng(seed, 0), || {});
        assert_eq!(r.evaluations, 100 * 100);
        assert_eq!(r.convergence.len(), 100);
        assert!(
            r.convergence.windows(2).all(|w| w[1] <= w[0]),
            "best-so-far never worsens"
        );
        assert!(
            r.best_value < 0.8 * r.convergence[0],
            "GSA improves on its initial agents"
        );
        assert!(
            r.best_value >= optimum.rmse_n * (1.0 - 1e-9),
            "GSA cannot beat the exact optimum"
        );
        // Stated tolerance: within 10 % of the optimal RMSE.
        assert!(
            r.best_value < 1.10 * optimum.rmse_n,
            "{} vs {}",
            r.best_value,
            optimum.rmse_n
        );
        assert!(bounds.contains(&r.best));
    }
}

#[test]
fn gsa_at_paper_scale_comes_near_the_optimum() {
    // The paper's coefficients are ~10⁴ wide boxes next to ~10² ones. GSA runs
    // on the box mapped to [−100, 100]⁵ (the scale its constants were tuned
    // for), so it must improve on its initial agents, never beat the exact
    // optimum, beat a random search with the same number of evaluations on
    // every seed (a yardstick independent of GSA), and land within the stated
    // factor of the optimum in the median over seeds. It catches a swarm that
    // does not search: attraction flipped to repulsion (seed 1 ends worse than
    // random search) or positions never moved (no improvement on the initial
    // agents). It cannot notice subtler wrong equations (G(t − 1) for G(t),
    // or Kbest taking the lightest agents, both pass it): the tests
    // `one_gsa_iteration_…_worked_by_hand` and `the_gsa_loop_runs_the_hand_step…`
    // pin each equation to a step computed by hand.
    let (x, f) = synthetic(&PAPER_1A_C, 500, 20.0, 3);
    let optimum = fit_quartic(&x, &f).unwrap();
    let m = BranchMoments::new(&x, &f);
    let bounds = data_bounds(&x, &f).unwrap();
    let params = GsaParams::default();
    let mut ratios = Vec::new();
    for seed in 1..=5 {
        let r = minimize(|c| m.rmse(c), &bounds, &params, &mut branch_rng(seed, 0), || {});
        assert!(r.best_value < r.convergence[0]);
        assert!(r.best_value >= optimum.rmse_n * (1.0 - 1e-9));
        let random = random_search(|c| m.rmse(c), &bounds, params.agents * params.iters, seed);
        assert!(
            r.best_value < random,
            "seed {seed}: GSA {} vs random search {random}",
            r.best_value
        );
        ratios.push(r.best_value / optimum.rmse_n);
    }
    ratios.sort_by(f64::total_cmp);
    assert!(
        ratios[2] < GSA_PAPER_SCALE_MEDIAN_FACTOR,
        "median GSA/optimum {} over seeds 1..=5: {ratios:?}",
        ratios[2]
    );
}

/// Stated tolerance of GSA (N = T = 100) against the exact optimum at the
/// paper's scale, in the median over seeds 1..=5. Single seeds range from
/// 1.7× to 12× (GSA is a poor optimiser here; `mre fit` puts the exact
/// least-squares optimum into the table and reports GSA's gap).
const GSA_PAPER_SCALE_MEDIAN_FACTOR: f64 = 5.0;

/// The best of `evaluations` uniform samples of the box.
fn random_search(f: impl Fn(&[f64; 5]) -> f64, b: &SearchBox, evaluations: usize, seed: u64) -> f64 {
    use rand::Rng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..evaluations)
        .map(|_| f(&std::array::from_fn(|k| rng.random_range(b.lower[k]..=b.upper[k]))))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn gsa_is_reproducible_for_a_seed() {
    let (x, f) = synthetic(&PAPER_1A_C, 100, 5.0, 4);
    let m = BranchMoments::new(&x, &f);
    let b = data_bounds(&x, &f).unwrap();
    let p = GsaParams {
        agents: 20,
        iters: 20,
        ..Default::default()
    };
    let r1 = minimize(|c| m.rmse(c), &b, &p, &mut branch_rng(9, 3), || {});
    let r2 = minimize(|c| m.rmse(c), &b, &p, &mut branch_rng(9, 3), || {});
    assert_eq!(r1, r2);
}

#[test]
fn gsa_keeps_every_agent_inside_the_paper_bounds_at_every_iteration() {
    // Paper Table 3 bounds: the optimum of data made from Table 4's 1 A
    // extension is outside them (a4 = 7180.70 > 800), so the swarm is pulled
    // against the box. `best` is inside by construction; what can fail is an
    // agent evaluated outside, so every position the objective is handed is
    // checked, every iteration. With the published G0 = 100 no agent is thrown
    // past a face on this problem (the pulls point at other agents); G0 = 1000
    // throws 9–114 out per run (seeds 1–3), which the re-draw must bring back.
    let (x, f) = synthetic(&PAPER_1A_E, 200, 0.0, 5);
    let m = BranchMoments::new(&x, &f);
    let b: SearchBox = paper_bounds(Branch::Extension);
    assert!(!b.contains(&PAPER_1A_E));
    for (g0, seed) in [(100.0, 1), (1000.0, 1), (1000.0, 2)] {
        let p = GsaParams {
            agents: 30,
            iters: 30,
            g0,
            ..Default::default()
        };
        let mut checked = 0;
        minimize_batch(
            &b.lower,
            &b.upper,
            |agents| {
                agents
                    .iter()
                    .map(|c| {
                        let c: [f64; 5] = std::array::from_fn(|k| c[k]);
                        assert!(
                            b.contains(&c),
                            "G0 {g0}, seed {seed}: agent evaluated outside the box: {c:?}"
                        );
                        checked += 1;
                        m.rmse(&c)
                    })
                    .collect()
            },
            &p,
            &mut branch_rng(seed, 0),
            || {},
        );
        assert_eq!(checked, 30 * 30);
    }
}

#[test]
fn gsa_masses_rank_only_the_finite_agents() {
    // Eqs. 9–12 over the finite values: best 1, worst 3, so m = 1, 0.5, 0 and
    // M = m/Σm = 2/3, 1/3, 0; the infeasible agents (∞, NaN) get mass 0.
    let m = masses(&[1.0, 2.0, 3.0, f64::INFINITY, f64::NAN, f64::INFINITY]);
    let want = [2.0 / 3.0, 1.0 / 3.0, 0.0, 0.0, 0.0, 0.0];
    for (got, want) in m.iter().zip(want) {
        assert!((got - want).abs() < 1e-15, "{m:?}");
    }
    // Equal finite values share the mass; with none finite there is nothing to
    // rank by, and every agent gets 1/N (Rashedi's best = worst case).
    assert_eq!(masses(&[5.0, f64::NAN, 5.0]), vec![0.5, 0.0, 0.5]);
    assert_eq!(masses(&[f64::NAN; 4]), vec![0.25; 4]);
}

#[test]
fn gsa_finds_the_optimum_when_half_the_box_is_infeasible() {
    // f = |x − (−60, 40)|² on the half x₀ ≤ 0 of [−100, 100]², ∞ on the other
    // half, as `mre compare` returns for inadmissible parameters: about half
    // the agents start infeasible, and re-drawn ones land there all run long.
    // When ∞ became f64::MAX, (f − MAX)/(best − MAX) rounded to 1 for every
    // finite agent: equal masses, no fitness information. That code ended at
    // 1.5, 2.6, 9.3, 15 and 71 on seeds 1–5 (median 9.3); with the finite
    // worst, three seeds reach 1e-19 and the median is below 1e-18.
    let f = |c: &[f64]| {
        if c[0] > 0.0 {
            f64::INFINITY
        } else {
            (c[0] + 60.0).powi(2) + (c[1] - 40.0).powi(2)
        }
    };
    let mut best: Vec<f64> = (1..=5)
        .map(|seed| {
            minimize_batch(
                &[-100.0, -100.0],
                &[100.0, 100.0],
                |agents| agents.iter().map(|c| f(c)).collect(),
                &GsaParams::default(),
                &mut branch_rng(seed, 0),
                || {},
            )
            .best_value
        })
        .collect();
    best.sort_by(f64::total_cmp);
    assert!(best[2] < 1e-6, "median best over seeds 1–5: {best:?}");
}

/// The parameters of the hand-worked iteration: N = 3, T = 2, t = 1, so
/// G(1) = G0·e^(−α·1/2) = 2·e^(−ln 4 / 2) = 2·(1/2) = 1 (Eq. 7), and
/// Kbest = round(3·(2 + (1 − 1/2)·98)/100) = round(1.53) = 2.
fn hand_params(weights: RandomWeights) -> GsaParams {
    GsaParams {
        agents: 3,
        iters: 2,
        g0: 2.0,
        alpha: 4f64.ln(),
        final_kbest_pct: 2.0,
        seed: 0,
        weights,
    }
}

/// Fixed draws in order, then 0.5 for ever.
fn fixed_draws(values: &[f64]) -> impl FnMut() -> f64 + '_ {
    let mut next = values.iter();
    move || next.next().copied().unwrap_or(0.5)
}

fn assert_close(got: &[Vec<f64>], want: &[[f64; 2]], what: &str) {
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        for d in 0..2 {
            assert!(
                (g[d] - w[d]).abs() < 1e-12,
                "{what} of agent {}: {g:?}, want {w:?}",
                i + 1
            );
        }
    }
}

#[test]
fn one_gsa_iteration_matches_the_step_worked_by_hand() {
    // Agents 1, 2, 3 at x = (0, 0), (3, 4), (0, 4): R₁₂ = 5, R₁₃ = 4, R₂₃ = 3.
    // Fitness 2, 8, 4 → best 2, worst 8 (Eqs. 11, 12);
    // m = (fit − 8)/(2 − 8) = 1, 0, 2/3 (Eq. 9); M = m/(5/3) = 0.6, 0, 0.4 (Eq. 10).
    // Kbest = 2: agents 1 and 3 (the heaviest).
    // aᵢ = G·Σ_{j∈Kbest, j≠i} rand_j·M_j·(x_j − x_i)/R_ij   (Eq. 5 with the
    // product M_pi·M_aj, divided by M_ii = M_i; Rashedi's Eqs. 7–10):
    //   a₁ = 1·0.5·0.4·(0, 4)/4                          = (0, 0.2)
    //   a₂ = 0.5·0.6·(−3, −4)/5 + 0.75·0.4·(−3, 0)/3      = (−0.18, −0.24) + (−0.3, 0) = (−0.48, −0.24)
    //   a₃ = 0.125·0.6·(0, −4)/4                         = (0, −0.075)
    // Agent 2 has mass 0 but is still pulled: the acceleration does not depend
    // on its own mass. vᵢ ← randᵢ·vᵢ + aᵢ (Rashedi's Eq. 11), xᵢ ← xᵢ + vᵢ:
    //   v₁ = 0.25·(1, 0) + a₁      = (0.25, 0.2),     x₁ = (0.25, 0.2)
    //   v₂ = 0.5·(0, −2) + a₂      = (−0.48, −1.24),  x₂ = (2.52, 2.76)
    //   v₃ = 0.875·(0.5, 0.5) + a₃ = (0.4375, 0.3625), x₃ = (0.4375, 4.3625)
    // Draw order: per agent, its Kbest weights heaviest first, then its velocity's.
    let draws = [
        0.5, 0.25, /* agent 2 */ 0.5, 0.75, 0.5, /* agent 3 */ 0.125, 0.875,
    ];
    let mut draw = fixed_draws(&draws);
    let mut x = vec![vec![0.0, 0.0], vec![3.0, 4.0], vec![0.0, 4.0]];
    let mut v = vec![vec![1.0, 0.0], vec![0.0, -2.0], vec![0.5, 0.5]];
    let s = step(
        &mut x,
        &mut v,
        &[2.0, 8.0, 4.0],
        1,
        &hand_params(RandomWeights::PerAgent),
        &mut draw,
    );
    assert!((s.g - 1.0).abs() < 1e-15, "G = {}", s.g);
    for (got, want) in s.masses.iter().zip([0.6, 0.0, 0.4]) {
        assert!((got - want).abs() < 1e-15, "masses {:?}", s.masses);
    }
    assert_eq!(s.kbest, vec![0, 2]);
    assert_close(
        &s.acceleration,
        &[[0.0, 0.2], [-0.48, -0.24], [0.0, -0.075]],
        "acceleration",
    );
    assert_close(&v, &[[0.25, 0.2], [-0.48, -1.24], [0.4375, 0.3625]], "velocity");
    assert_close(&x, &[[0.25, 0.2], [2.52, 2.76], [0.4375, 4.3625]], "position");
    assert_eq!(draw(), 0.5, "the step used more draws than worked by hand");
}

#[test]
fn one_gsa_iteration_with_per_dimension_weights_matches_the_hand_step() {
    // The same swarm as above, with Rashedi's reference code's draws: one per
    // force term and dimension, one per velocity component (d fastest).
    //   a₁ = (0.5·0.4·0/4, 0.25·0.4·4/4)                 = (0, 0.1)
    //   a₂ = 0.5·0.6·(−3, −4)/5 + 0.5·0.4·(−3, 0)/3       = (−0.18, −0.24) + (−0.2, 0) = (−0.38, −0.24)
    //   a₃ = 0.5·0.6·(0, −4)/4                           = (0, −0.3)
    //   v₁ = (0.5·1, 0.75·0) + a₁   = (0.5, 0.1)
    //   v₂ = (0.5·0, 0.5·(−2)) + a₂ = (−0.38, −1.24)
    //   v₃ = (0.5·0.5, 0.5·0.5) + a₃ = (0.25, −0.05)
    let draws = [0.5, 0.25, 0.5, 0.75];
    let mut draw = fixed_draws(&draws);
    let mut x = vec![vec![0.0, 0.0], vec![3.0, 4.0], vec![0.0, 4.0]];
    let mut v = vec![vec![1.0, 0.0], vec![0.0, -2.0], vec![0.5, 0.5]];
    let s = step(
        &mut x,
        &mut v,
        &[2.0, 8.0, 4.0],
        1,
        &hand_params(RandomWeights::PerDimension),
        &mut draw,
    );
    assert_close(
        &s.acceleration,
        &[[0.0, 0.1], [-0.38, -0.24], [0.0, -0.3]],
        "acceleration",
    );
    assert_close(&v, &[[0.5, 0.1], [-0.38, -1.24], [0.25, -0.05]], "velocity");
    assert_close(&x, &[[0.5, 0.1], [2.62, 2.76], [0.25, 3.95]], "position");
}

#[test]
fn a_coordinate_leaving_the_box_is_redrawn_and_keeps_its_velocity() {
    // One agent: no force; v = 0.5·(4, 0) = (2, 0) carries x₀ from 99 to 101,
    // outside [−100, 100], so x₀ is re-drawn: −100 + 0.75·200 = 50.
    let mut draw = fixed_draws(&[0.5, 0.75]);
    let mut x = vec![vec![99.0, 0.0]];
    let mut v = vec![vec![4.0, 0.0]];
    step(
        &mut x,
        &mut v,
        &[1.0],
        1,
        &hand_params(RandomWeights::PerAgent),
        &mut draw,
    );
    assert_eq!(x, vec![vec![50.0, 0.0]]);
    assert_eq!(v, vec![vec![2.0, 0.0]]);
}

#[test]
fn the_gsa_loop_runs_the_hand_step_between_evaluations() {
    // The whole loop with injected draws, on the box [−100, 100]² (mapped
    // onto itself). Initial draws u give x = −100 + 200·u: the three agents of
    // the hand-worked step, starting at rest. Iteration 1 sees fitness 2, 8, 4,
    // so the positions evaluated at iteration 2 are x + a (v = 0 + a):
    // (0, 0.2), (2.52, 3.76), (0, 3.925).
    let draws = [
        0.5, 0.5, 0.515, 0.52, 0.5, 0.52, /* iteration 1 */ 0.5, 0.25, 0.5, 0.75, 0.5, 0.125, 0.875,
    ];
    let mut draw = fixed_draws(&draws);
    let mut seen = Vec::new();
    let r = minimize_with_draws(
        &[-100.0, -100.0],
        &[100.0, 100.0],
        |agents| {
            seen.push(agents.to_vec());
            if seen.len() == 1 {
                vec![2.0, 8.0, 4.0]
            } else {
                vec![1.0, 1.0, 1.0]
            }
        },
        &hand_params(RandomWeights::PerAgent),
        &mut draw,
        || {},
    );
    assert_eq!(seen.len(), 2);
    assert_close(&seen[0], &[[0.0, 0.0], [3.0, 4.0], [0.0, 4.0]], "initial position");
    assert_close(
        &seen[1],
        &[[0.0, 0.2], [2.52, 3.76], [0.0, 3.925]],
        "position at iteration 2",
    );
    assert_eq!(r.convergence, vec![2.0, 1.0]);
    assert_close(&[r.best], &[[0.0, 0.2]], "best");
    assert_eq!(r.evaluations, 6);
}

#[test]
fn both_reports_gap_and_model_file_is_a_table() {
    let problems: Vec<BranchProblem> = [(0.0, 1.0), (1.0, 2.0)]
        .iter()
        .flat_map(|&(current_a, gain)| {
            [(Branch::Compression, PAPER_1A_C), (Branch::Extension, PAPER_1A_E)].map(|(branch, c)| {
                let c = c.map(|v| v * gain);
                let (x_mm, force_n) = synthetic(&c, 300, 10.0, 6);
                BranchProblem {
                    current_a,
                    branch,
                    samples: BranchSamples { x_mm, force_n },
                }
            })
        })
        .collect();
    let options = FitOptions {
        method: Method::Both,
        gsa: GsaParams {
            agents: 30,
            iters: 30,
            ..Default::default()
        },
        ..Default::default()
    };
    let fits = fit_branches(&problems, &options).unwrap();
    for b in &fits {
        let ratio = b.gap_ratio().unwrap();
        assert!(ratio >= 1.0 - 1e-9, "{ratio}");
        // The table coefficients are the least-squares optimum.
        assert_eq!(b.chosen, *b.lsq.as_ref().unwrap());
    }
    let model = mre_host::fit::model_file::build("synthetic", "00", false, &fits, &options).unwrap();
    let text = mre_host::fit::model_file::to_toml(&model).unwrap();
    let table = mre_host::table_file::parse_table_toml(&text).unwrap();
    assert_eq!(table.entries().len(), 2);
    assert_eq!(table.entries()[1].current_a, 1.0);
    assert_eq!(table.entries()[1].x_max_mm, 1.1);
    let back: mre_host::fit::model_file::ModelFile = toml::from_str(&text).unwrap();
    assert_eq!(back, model);
}

#[test]
fn sweep_reports_an_index_at_or_above_the_optimum() {
    let (x_mm, force_n) = synthetic(&PAPER_1A_C, 200, 10.0, 8);
    let problems = vec![BranchProblem {
        current_a: 0.0,
        branch: Branch::Compression,
        samples: BranchSamples { x_mm, force_n },
    }];
    let s = mre_host::fit::sweep::sweep(&problems, &FitOptions::default(), &[2, 8], &[4, 12]).unwrap();
    assert_eq!(
        s.vs_iters.iter().map(|p| (p.agents, p.iters)).collect::<Vec<_>>(),
        [(100, 2), (100, 8)]
    );
    assert_eq!(
        s.vs_agents.iter().map(|p| (p.agents, p.iters)).collect::<Vec<_>>(),
        [(4, 100), (12, 100)]
    );
    for p in s.vs_iters.iter().chain(&s.vs_agents) {
        assert!(p.mean_gsa_over_lsq >= 1.0 - 1e-9);
    }
    assert_eq!(mre_host::fit::sweep::to_csv(&s).lines().count(), 5);
}

#[test]
fn a_failed_fit_leaves_an_existing_model_file_untouched() {
    let data = tempfile::tempdir().unwrap();
    std::fs::write(
        data.path().join("dataset.toml"),
        "[[recording]]\nfile = \"a.csv\"\ncurrent_a = 0\n",
    )
    .unwrap();
    std::fs::write(
        data.path().join("a.csv"),
        "time_s,displacement_mm,force_n\n0,0,1\n1,0,x\n",
    )
    .unwrap();
    let out = tempfile::tempdir().unwrap();
    let model = out.path().join("model.toml");
    std::fs::write(&model, "previous contents").unwrap();
    let err = mre_host::fit::run_fit(data.path(), &FitOptions::default(), &[], &model).unwrap_err();
    assert!(
        err.to_string()
            .ends_with("line 3, column 3 (force_n): `x` is not a number"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&model).unwrap(), "previous contents");
    assert_eq!(
        std::fs::read_dir(out.path()).unwrap().count(),
        1,
        "no temporary file left behind"
    );
}
