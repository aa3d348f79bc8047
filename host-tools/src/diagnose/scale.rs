//! Stress softening judged on each recording's scale.
//!
//! Softening over the run order multiplies a whole test's force by
//! `1 − Δ·(1 − e^{−(n−1)/n0})`. When n0 is a few tests, every test after the
//! first few has softened by nearly Δ, so the signal is the scale of the
//! first two or three tests. Scored sample by sample, that is a few per cent
//! of a few recordings, diluted by everything else (and by the 0 A tests'
//! small forces); scored per recording it is the whole signal.
//!
//! So each recording gets a *gain*: the factor that best maps the current
//! model's held-out prediction onto it (fit recordings from their fold's fit,
//! validate ones from the full fit: no recording's own force sets the model
//! its gain is measured against). The softening law is then fitted to the
//! gains against the run order, per current a free level (`a_c·(1 − Δ·g)`,
//! Δ ≥ 0, n0 on a grid), and compared with the level alone (`a_c`) by an F
//! test whose scatter is the law fit's own residual: a first test standing
//! above its level counts by its size, not its rank. Calibration: the same F
//! on simulated gain sets without softening (each level's mean plus
//! Student-t scatter at the gains' RMS, the recorded run order); the p-value
//! is the share that do at least as well. (A permutation of the run order,
//! used before, cannot go below ≈ 1/15 when one recording carries the signal.)
use super::prepared::scored;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StudentT};
use rayon::prelude::*;

/// Onset lengths n0 (tests) searched in each fit of the law.
const N0_GRID: [f64; 9] = [1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0];
/// Degrees of freedom of the Student-t scatter the null simulations draw.
const T_DOF: f64 = 4.0;
/// Softening depth Δ searched in [0, `MAX_DEPTH`].
const MAX_DEPTH: f64 = 0.6;

/// One recording's gain and what the law reads of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gain {
    /// Recording index in the prepared set.
    pub index: usize,
    /// Least-squares factor from the current model's held-out prediction to the force.
    pub gain: f64,
    /// Run order (`sequence`).
    pub sequence: f64,
    /// Which level the recording shares (its current).
    pub level: usize,
}

/// The gains of one comparison, ready to be judged with recordings left out.
#[derive(Clone, Debug, Default)]
pub struct ScaleStats {
    pub gains: Vec<Gain>,
    /// Simulated gain sets without softening that calibrate the test.
    pub simulations: usize,
    pub seed: u64,
    /// The simulations stop once the p-value must exceed this (the decision
    /// is then made).
    pub max_p: f64,
}

/// The scale test's result.
#[derive(Clone, Copy, Debug, Default)]
pub struct ScaleTest {
    /// √(Σ e²_level / Σ e²_law) of the leave-one-out gain predictions
    /// (reported, not a gate: a signal in one recording cannot predict itself).
    pub ratio: f64,
    /// The law's F statistic against the level alone ([`f_statistic`]).
    pub f: f64,
    /// Share of simulated gain sets without softening with an F at least as
    /// large (NaN when none was run, at least `max_p` when they stopped early).
    pub p: f64,
    /// Recordings whose gain was predicted.
    pub n: usize,
    /// The law fitted to every gain: depth Δ and onset n0 (tests).
    pub depth: f64,
    pub n0: f64,
}

/// The gain of each recording in `pool` that has a run order: `Σ y·p / Σ p²`
/// over `mask`, with `pred` the current model's held-out prediction.
pub fn gains<'a>(
    pool: &[usize],
    pred: &[Vec<f64>],
    force_n: &dyn Fn(usize) -> &'a [f64],
    mask: &[Vec<bool>],
    sequence: &dyn Fn(usize) -> Option<f64>,
    level: &dyn Fn(usize) -> usize,
) -> Vec<Gain> {
    pool.iter()
        .filter_map(|&i| {
            let n = sequence(i)?;
            let (mut yp, mut pp) = (0.0, 0.0);
            for (p, y) in scored(pred[i].iter().zip(force_n(i)), &mask[i]) {
                yp += y * p;
                pp += p * p;
            }
            (pp > 0.0).then(|| Gain {
                index: i,
                gain: yp / pp,
                sequence: n,
                level: level(i),
            })
        })
        .collect()
}

fn law(sequence: f64, n0: f64) -> f64 {
    1.0 - (-(sequence - 1.0) / n0).exp()
}

/// Per level, the moments of the gains `k` and the law's covariate `g` over
/// the gains in use: (Σk, Σk·g, n, Σg, Σg²). With `s = 1 − Δ·g` the level is
/// `a_c = Σk·s / Σs²` and the level's SSE is `Σk² − (Σk·s)²/Σs²`.
fn moments(gains: &[Gain], g: &[f64], use_: &[bool], n_levels: usize) -> Vec<[f64; 5]> {
    let mut m = vec![[0.0; 5]; n_levels];
    for (j, gn) in gains.iter().enumerate() {
        if use_[j] {
            let r = &mut m[gn.level];
            r[0] += gn.gain;
            r[1] += gn.gain * g[j];
            r[2] += 1.0;
            r[3] += g[j];
            r[4] += g[j] * g[j];
        }
    }
    m
}

/// `(Σk·s, Σs²)` of one level at depth `d`.
fn level_sums(m: &[f64; 5], d: f64) -> (f64, f64) {
    (m[0] - d * m[1], m[2] - 2.0 * d * m[3] + d * d * m[4])
}

/// What the law explains at depth `d`: Σ over levels of (Σk·s)²/Σs² (the
/// SSE is Σk² minus this, and Σk² does not depend on the law).
fn explained(m: &[[f64; 5]], d: f64) -> f64 {
    m.iter()
        .map(|r| {
            let (ks, ss) = level_sums(r, d);
            if ss > 0.0 {
                ks * ks / ss
            } else {
                0.0
            }
        })
        .sum()
}

/// The law's covariate `g(n; n0)` of every gain, for each n0 of [`N0_GRID`].
fn covariates(seq: &[f64]) -> Vec<Vec<f64>> {
    N0_GRID
        .iter()
        .map(|&n0| seq.iter().map(|&n| law(n, n0)).collect())
        .collect()
}

/// The law `a_c·(1 − Δ·g(n; n0))` fitted to the gains `use_`: (Δ, index of n0).
fn fit_law(gains: &[Gain], g: &[Vec<f64>], use_: &[bool], n_levels: usize) -> (f64, usize) {
    let mut best = (f64::NEG_INFINITY, 0.0, 0);
    for (k, gk) in g.iter().enumerate() {
        let m = moments(gains, gk, use_, n_levels);
        let gain_of = |d: f64| explained(&m, d);
        // Golden-section search on Δ (maximising what is explained).
        let phi = 0.5 * (5f64.sqrt() - 1.0);
        let (mut lo, mut hi) = (0.0, MAX_DEPTH);
        let (mut a, mut b) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
        let (mut fa, mut fb) = (gain_of(a), gain_of(b));
        for _ in 0..30 {
            if fa > fb {
                hi = b;
                b = a;
                fb = fa;
                a = hi - phi * (hi - lo);
                fa = gain_of(a);
            } else {
                lo = a;
                a = b;
                fa = fb;
                b = lo + phi * (hi - lo);
                fb = gain_of(b);
            }
        }
        let (d, f) = if fa > fb { (a, fa) } else { (b, fb) };
        // The edge Δ = 0 (no softening) is a candidate too.
        let (d, f) = if gain_of(0.0) >= f { (0.0, gain_of(0.0)) } else { (d, f) };
        if f > best.0 {
            best = (f, d, k);
        }
    }
    (best.1, best.2)
}

/// Leave-one-recording-out ratio of the level-only to the law's gain
/// prediction errors, with the law's covariates `g` (per n0, one per gain).
fn loo_ratio(gains: &[Gain], g: &[Vec<f64>], n_levels: usize) -> (f64, usize) {
    let (mut e_level, mut e_law, mut n) = (0.0, 0.0, 0usize);
    let mut use_: Vec<bool> = vec![true; gains.len()];
    for j in 0..gains.len() {
        use_[j] = false;
        let (d, k) = fit_law(gains, g, &use_, n_levels);
        let m = moments(gains, &g[k], &use_, n_levels)[gains[j].level];
        use_[j] = true;
        // No other gain on this level: nothing predicts it.
        if m[2] == 0.0 {
            continue;
        }
        let (ks, ss) = level_sums(&m, d);
        let s_j = 1.0 - d * g[k][j];
        e_level += (gains[j].gain - m[0] / m[2]).powi(2);
        e_law += (gains[j].gain - ks / ss.max(1e-300) * s_j).powi(2);
        n += 1;
    }
    ((e_level / e_law.max(1e-300)).sqrt(), n)
}

/// The law against the level alone over all the gains in use: the F
/// statistic `((SSE_level − SSE_law)/2) / (SSE_law/(N − L − 2))` (the law
/// adds Δ and n0; L levels), the law's Δ and the index of its n0.
///
/// The scatter is the law fit's own residual, so a first test that stands
/// above its level is judged by its size against the other gains' scatter,
/// not by its rank (a rank test over 15 recordings cannot go below ≈ 1/15
/// when one recording carries the signal, however large).
fn f_statistic(gains: &[Gain], g: &[Vec<f64>], n_levels: usize) -> (f64, f64, usize) {
    let all = vec![true; gains.len()];
    let (d, k) = fit_law(gains, g, &all, n_levels);
    let m = moments(gains, &g[k], &all, n_levels);
    let sum_k2: f64 = gains.iter().map(|x| x.gain * x.gain).sum();
    let sse_level = sum_k2 - m.iter().filter(|r| r[2] > 0.0).map(|r| r[0] * r[0] / r[2]).sum::<f64>();
    let sse_law = (sum_k2 - explained(&m, d)).max(0.0);
    let levels = m.iter().filter(|r| r[2] > 0.0).count();
    let df = gains.len().saturating_sub(levels + 2).max(1) as f64;
    let f = ((sse_level - sse_law).max(0.0) / 2.0) / (sse_law / df).max(1e-300);
    (f, d, k)
}

/// Each level's mean gain, and the RMS scatter about those means (with the
/// levels' degrees of freedom taken off).
fn level_fit(gains: &[Gain], n_levels: usize) -> (Vec<f64>, f64) {
    let m = moments(gains, &vec![0.0; gains.len()], &vec![true; gains.len()], n_levels);
    let mean: Vec<f64> = m.iter().map(|r| if r[2] > 0.0 { r[0] / r[2] } else { 0.0 }).collect();
    let sse: f64 = gains.iter().map(|x| (x.gain - mean[x.level]).powi(2)).sum();
    let levels = m.iter().filter(|r| r[2] > 0.0).count();
    (mean, (sse / gains.len().saturating_sub(levels).max(1) as f64).sqrt())
}

impl ScaleStats {
    /// The test over the gains whose recordings are not in `excluded`.
    ///
    /// p is the share of simulated gain sets without softening (each level's
    /// mean plus Student-t scatter with [`T_DOF`] degrees of freedom, at the
    /// level fit's RMS) whose F is at least the recorded one, over the same
    /// run order. Heavy-tailed scatter on purpose: a real set's gains carry
    /// each recording's own misfit, and a Gaussian null would count one
    /// deviant recording that happens to be test 1 as softening too readily.
    pub fn test(&self, excluded: &[usize]) -> ScaleTest {
        let gains: Vec<Gain> = self
            .gains
            .iter()
            .copied()
            .filter(|g| !excluded.contains(&g.index))
            .collect();
        let n_levels = gains.iter().map(|g| g.level + 1).max().unwrap_or(0);
        let seq: Vec<f64> = gains.iter().map(|g| g.sequence).collect();
        let mut levels: Vec<usize> = gains.iter().map(|g| g.level).collect();
        levels.sort_unstable();
        levels.dedup();
        // At least two degrees of freedom left for the law's scatter.
        if gains.len() < levels.len() + 4 {
            return ScaleTest {
                ratio: 1.0,
                p: 1.0,
                ..ScaleTest::default()
            };
        }
        let g = covariates(&seq);
        let (ratio, n) = loo_ratio(&gains, &g, n_levels);
        let (f, depth, k) = f_statistic(&gains, &g, n_levels);
        let (mean, sigma) = level_fit(&gains, n_levels);
        let t = StudentT::new(T_DOF).expect("T_DOF > 0");
        let unit = ((T_DOF - 2.0) / T_DOF).sqrt();
        // In blocks, each simulation seeded by its index (the same result
        // whatever the thread count); stop once p ≤ max_p is out of reach.
        let (mut as_good, mut done) = (0usize, 0usize);
        let enough = (self.max_p * (1 + self.simulations) as f64).floor() as usize;
        while done < self.simulations && as_good < enough {
            let block = (done..(done + 64).min(self.simulations)).into_par_iter();
            as_good += block
                .filter(|&j| {
                    let mut rng = ChaCha8Rng::seed_from_u64(self.seed.wrapping_add(j as u64));
                    let sim: Vec<Gain> = gains
                        .iter()
                        .map(|x| Gain {
                            gain: mean[x.level] + sigma * unit * t.sample(&mut rng),
                            ..*x
                        })
                        .collect();
                    f_statistic(&sim, &g, n_levels).0 >= f
                })
                .count();
            done = (done + 64).min(self.simulations);
        }
        ScaleTest {
            ratio,
            f,
            p: if done == 0 {
                f64::NAN
            } else {
                (1 + as_good) as f64 / (1 + done) as f64
            },
            n,
            depth,
            n0: N0_GRID[k],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gain(index: usize, gain: f64, sequence: f64, level: usize) -> Gain {
        Gain {
            index,
            gain,
            sequence,
            level,
        }
    }

    #[test]
    fn the_gain_is_the_least_squares_factor_on_the_scored_samples() {
        // y = 1.1·p on the scored samples; the unscored one is far off and ignored.
        let pred = vec![vec![1.0, 2.0, -3.0, 5.0]];
        let y = [1.1, 2.2, -3.3, 100.0];
        let mask = vec![vec![true, true, true, false]];
        let g = gains(&[0], &pred, &|_| &y, &mask, &|_| Some(4.0), &|_| 0);
        assert_eq!(g.len(), 1);
        assert!((g[0].gain - 1.1).abs() < 1e-12);
        // No run order: no gain.
        assert!(gains(&[0], &pred, &|_| &y, &mask, &|_| None, &|_| 0).is_empty());
    }

    /// Twelve recordings on two levels (1.0 and 0.9), with the first tests
    /// in run order at full scale and the rest softened by 10 % with n0 = 2.
    fn softened(noise: &[f64]) -> Vec<Gain> {
        (0..12)
            .map(|k| {
                let n = (k + 1) as f64;
                let level = k % 2;
                let a = [1.0, 0.9][level];
                gain(k, a * (1.0 - 0.1 * law(n, 2.0)) + noise[k], n, level)
            })
            .collect()
    }

    const NOISE: [f64; 12] = [
        0.002, -0.003, 0.001, 0.004, -0.002, 0.0, -0.004, 0.003, -0.001, 0.002, 0.001, -0.003,
    ];

    /// The same levels and noise without softening.
    fn flat() -> Vec<Gain> {
        (0..12)
            .map(|k| gain(k, [1.0, 0.9][k % 2] + NOISE[k], (k + 1) as f64, k % 2))
            .collect()
    }

    /// Every simulation run (no early stop).
    fn stats(gains: Vec<Gain>, simulations: usize) -> ScaleStats {
        ScaleStats {
            gains,
            simulations,
            seed: 1,
            max_p: 1.0,
        }
    }

    #[test]
    fn softening_over_the_run_order_is_found_and_its_law_recovered() {
        let t = stats(softened(&NOISE), 1999).test(&[]);
        assert_eq!(t.n, 12);
        // The law explains the first tests' scale; the level alone cannot.
        assert!(t.ratio > 3.0 && t.f > 50.0, "{t:?}");
        // No simulated set without softening comes near: p is its floor.
        assert!(t.p <= 1.0 / 2000.0 + 1e-12, "{t:?}");
        assert!((t.depth - 0.1).abs() < 0.02 && (1.0..=3.0).contains(&t.n0), "{t:?}");
    }

    #[test]
    fn gains_that_ignore_the_run_order_give_no_evidence() {
        // The same noise, no softening: the law cannot predict better.
        let t = stats(flat(), 1999).test(&[]);
        assert!(t.ratio < 1.1 && t.p > 0.05, "{t:?}");
    }

    /// Fifteen gains on three levels (1.0, 0.8, 0.9) with a seeded Gaussian
    /// scatter of `sigma`, in a seeded random run order; the test run first
    /// stands `first` above its level.
    fn fifteen(seed: u64, sigma: f64, first: f64) -> Vec<Gain> {
        use rand::seq::SliceRandom;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut order: Vec<usize> = (1..=15).collect();
        order.shuffle(&mut rng);
        let normal = rand_distr::Normal::new(0.0, sigma).unwrap();
        (0..15)
            .map(|k| {
                let level = k / 5;
                let n = order[k] as f64;
                let lift = if order[k] == 1 { first } else { 0.0 };
                gain(k, [1.0, 0.8, 0.9][level] + lift + normal.sample(&mut rng), n, level)
            })
            .collect()
    }

    #[test]
    fn one_deviant_first_test_is_judged_by_its_size_not_its_rank() {
        // Only test 1 softened-free (n0 → 0): a run-order permutation can
        // do no better than 1/15 here. Eight scatters above its level is
        // softening; one and a half is not.
        let big = stats(fifteen(7, 0.01, 0.08), 1999).test(&[]);
        assert!(big.p <= 0.002, "{big:?}");
        let small = stats(fifteen(7, 0.01, 0.015), 1999).test(&[]);
        assert!(small.p > 0.01, "{small:?}");
    }

    #[test]
    fn without_softening_p_is_calibrated() {
        // Gaussian scatter, no softening, 300 seeds: p ≤ 0.05 in about 5 %
        // of them or fewer (the Student-t null is heavier-tailed than the
        // data here, so conservative), and p not stuck near 1.
        let p: Vec<f64> = (0..300u64)
            .map(|seed| stats(fifteen(100 + seed, 0.02, 0.0), 199).test(&[]).p)
            .collect();
        let share = |x: f64| p.iter().filter(|&&v| v <= x).count() as f64 / p.len() as f64;
        assert!(share(0.05) <= 0.08, "{}", share(0.05));
        assert!(share(0.5) >= 0.25, "{}", share(0.5));
    }

    #[test]
    fn the_simulations_stop_once_the_decision_is_made() {
        let st = ScaleStats {
            max_p: 0.002,
            ..stats(flat(), 9999)
        };
        // Without softening p ≤ 0.002 is soon out of reach: p stays above it.
        let t = st.test(&[]);
        assert!(t.p > 0.002, "{t:?}");
    }

    #[test]
    fn leaving_recordings_out_removes_their_gains() {
        let st = stats(softened(&NOISE), 19);
        // Without the first three tests: nine gains predicted, and the
        // remaining trend (22 % of Δ left at test 4, 3 % at test 8)
        // carries less evidence than the whole run order.
        let t = st.test(&[0, 1, 2]);
        assert_eq!(t.n, 9);
        assert!(t.ratio < st.test(&[]).ratio, "{t:?}");
        // Too few gains: no test.
        let t = st.test(&(0..9).collect::<Vec<_>>());
        assert_eq!((t.ratio, t.p), (1.0, 1.0));
    }
}
