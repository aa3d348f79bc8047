//! Fitting on synthetic data made from known quartics: least squares recovers
//! them up to noise, the moment-form objective equals the sample sum, GSA
//! converges towards the optimum, and the model file is a table file.
use mre_core::model::Branch;
use mre_host::dataset::BranchSamples;
use mre_host::fit::bounds::{data_bounds, paper_bounds, SearchBox};
use mre_host::fit::gsa::{minimize, GsaParams};
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
    // factor of the optimum in the median over seeds.
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
fn gsa_keeps_agents_inside_the_paper_bounds() {
    // Paper Table 3 bounds: the optimum of data made from Table 4's 1 A
    // extension is outside them (a4 = 7180.70 > 800), so GSA must stay at the box.
    let (x, f) = synthetic(&PAPER_1A_E, 200, 0.0, 5);
    let m = BranchMoments::new(&x, &f);
    let b: SearchBox = paper_bounds(Branch::Extension);
    assert!(!b.contains(&PAPER_1A_E));
    let p = GsaParams {
        agents: 30,
        iters: 30,
        ..Default::default()
    };
    let r = minimize(|c| m.rmse(c), &b, &p, &mut branch_rng(1, 0), || {});
    assert!(b.contains(&r.best));
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
