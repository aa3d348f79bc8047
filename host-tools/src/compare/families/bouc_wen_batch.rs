//! Bouc–Wen's J for a whole GSA iteration at once: the same objective as
//! projecting each q ([`crate::compare::fit::objective`] on [`BoucWen`]'s
//! basis), organised for speed.
//!
//! - Everything that does not depend on q is summed once per track set: the
//!   Gram entries of the v, x, 1 columns and the target. An evaluation only
//!   integrates z and accumulates its five sums (z·v, z·x, z, z², z·F).
//! - Agents are integrated in lock-step, [`LANES`] at a time (samples outer,
//!   agents inner, struct-of-arrays), so the step is vectorised. Each lane
//!   carries a phase ψ that grows by u = |dx|/x_y between reversals: loading
//!   (ψ ≥ 0) z = s·tanh ψ, computed as (1 − e)/(1 + e) with e = e^(−2ψ) by
//!   [`fastmath::exp`]; just after a reversal (ψ < 0, the tan/atan branch
//!   of [`super::bouc_wen::unloading_phase`]) z = s·tan(√r·ψ)/√r by the
//!   vectorised [`fastmath::tan`]. ψ is recomputed from z only at reversals
//!   (~4 % of the samples on the MTS data), by [`fastmath::atan`]. Lanes with
//!   r ≤ 0 (and w > 0 at a reversal) take libm's functions there, one lane at a time.
//! - Work items are (agent block, track) pairs for rayon; tracks are
//!   independent (z starts at 0 on each).
//!
//! This is the exact step of [`super::bouc_wen::Loop`] rearranged, so J differs
//! from the per-q projection by rounding only (fastmath's exp, atan and tan are
//! within 1e-15 relative of libm): ~1e-15 relative, at most ~1e-9 at the r = −1
//! edge (tested below).
use super::bouc_wen::{unloading_phase, unloading_w, FLAT, MAX_R};
use super::BatchObjective;
use crate::compare::fastmath;
use crate::compare::fit::{solve_normal, weight, MAX_LINEAR};
use crate::compare::tracks::Track;
use rayon::prelude::*;

/// Agents integrated together (8 f64: one AVX-512 or two AVX2 registers).
pub const LANES: usize = 8;

/// One sample, q-independent: direction of the step, |dx| and the regressors.
#[derive(Clone, Copy, Debug)]
struct Sample {
    sign: f64,
    abs_dx_mm: f64,
    v_m_s: f64,
    x_mm: f64,
    force_n: f64,
}

struct TrackData {
    samples: Vec<Sample>,
    /// Squared residual weight of the track (as in the projection).
    w2: f64,
}

/// The nonlinear parameters of one block of agents.
#[derive(Clone, Copy, Debug)]
struct Lanes {
    inv_x_y: [f64; LANES],
    r: [f64; LANES],
    /// √r and 1/√r where r > FLAT (1 elsewhere: those lanes take the scalar path).
    sqrt_r: [f64; LANES],
    inv_sqrt_r: [f64; LANES],
}

impl Lanes {
    fn new(x_y_mm: [f64; LANES], r: [f64; LANES]) -> Lanes {
        let sqrt_r = r.map(|r| if r > FLAT { r.sqrt() } else { 1.0 });
        Lanes {
            inv_x_y: x_y_mm.map(|x| 1.0 / x),
            r,
            sqrt_r,
            inv_sqrt_r: sqrt_r.map(|q| 1.0 / q),
        }
    }
}

/// Per lane: Σz·v, Σz·x, Σz, Σz², Σz·F over one track.
type ZSums = [[f64; LANES]; 5];

pub struct BoucWenBatch {
    tracks: Vec<TrackData>,
    /// Weighted q-independent Gram entries (columns v, x, z, 1; z rows left 0),
    /// right-hand side entries and yᵀy.
    gram: [[f64; MAX_LINEAR]; MAX_LINEAR],
    rhs: [f64; MAX_LINEAR],
    yy: f64,
}

impl BoucWenBatch {
    pub fn new(tracks: &[Track]) -> BoucWenBatch {
        let r = tracks.len().max(1) as f64;
        let mut gram = [[0.0; MAX_LINEAR]; MAX_LINEAR];
        let mut rhs = [0.0; MAX_LINEAR];
        let mut yy = 0.0;
        let data = tracks
            .iter()
            .map(|t| {
                let w2 = weight(t, r).powi(2);
                let n = t.len();
                let mut x_prev = t.x_mm.first().copied().unwrap_or(0.0);
                let samples: Vec<Sample> = (0..n)
                    .map(|i| {
                        let dx = t.x_mm[i] - x_prev;
                        x_prev = t.x_mm[i];
                        Sample {
                            sign: super::sign(dx),
                            abs_dx_mm: dx.abs(),
                            v_m_s: t.v_m_s[i],
                            x_mm: t.x_mm[i],
                            force_n: t.force_n[i],
                        }
                    })
                    .collect();
                // The v, x, 1 columns and the target: q-independent.
                let (mut g, mut h, mut s) = ([[0.0; 4]; 4], [0.0; 4], 0.0);
                for p in &samples {
                    let phi = [p.v_m_s, p.x_mm, 0.0, 1.0];
                    for a in [0, 1, 3] {
                        h[a] += phi[a] * p.force_n;
                        for c in [0, 1, 3] {
                            if c >= a {
                                g[a][c] += phi[a] * phi[c];
                            }
                        }
                    }
                    s += p.force_n * p.force_n;
                }
                for a in 0..4 {
                    rhs[a] += w2 * h[a];
                    for c in a..4 {
                        gram[a][c] += w2 * g[a][c];
                    }
                }
                yy += w2 * s;
                TrackData { samples, w2 }
            })
            .collect();
        BoucWenBatch {
            tracks: data,
            gram,
            rhs,
            yy,
        }
    }
}

/// (x_y, r) of an admissible q (the same test as [`BoucWen`]'s basis).
fn admissible(q: &[f64]) -> Option<(f64, f64)> {
    let &[log_x_y, r] = q else { return None };
    let x_y = 10f64.powf(log_x_y);
    (!x_y.is_nan() && x_y > 0.0 && (-1.0..=MAX_R).contains(&r)).then_some((x_y, r))
}

impl BatchObjective for BoucWenBatch {
    fn evaluate(&self, qs: &[Vec<f64>]) -> Vec<f64> {
        let params: Vec<Option<(f64, f64)>> = qs.iter().map(|q| admissible(q)).collect();
        // Inadmissible agents and the padding of the last block run a harmless dummy.
        let blocks: Vec<Lanes> = params
            .chunks(LANES)
            .map(|chunk| {
                let at = |l: usize| chunk.get(l).copied().flatten().unwrap_or((1.0, 0.0));
                Lanes::new(std::array::from_fn(|l| at(l).0), std::array::from_fn(|l| at(l).1))
            })
            .collect();
        let nt = self.tracks.len();
        let sums: Vec<ZSums> = (0..blocks.len() * nt)
            .into_par_iter()
            .map(|item| integrate(&self.tracks[item % nt].samples, &blocks[item / nt]))
            .collect();
        params
            .iter()
            .enumerate()
            .map(|(agent, p)| {
                p.and_then(|_| {
                    let (b, l) = (agent / LANES, agent % LANES);
                    let (mut gram, mut rhs) = (self.gram, self.rhs);
                    for (t, s) in self.tracks.iter().zip(&sums[b * nt..(b + 1) * nt]) {
                        gram[0][2] += t.w2 * s[0][l];
                        gram[1][2] += t.w2 * s[1][l];
                        gram[2][3] += t.w2 * s[2][l];
                        gram[2][2] += t.w2 * s[3][l];
                        rhs[2] += t.w2 * s[4][l];
                    }
                    let (theta, sse) = solve_normal(&gram, &rhs, self.yy, 4)?;
                    let j = sse.sqrt();
                    (j.is_finite() && theta.iter().all(|t| t.is_finite())).then_some(j)
                })
                .unwrap_or(f64::INFINITY)
            })
            .collect()
    }
}

/// z along one track for a block of agents, and its sums; the widest vector
/// instructions the CPU has, with fused multiply–adds where it has them
/// (checked at run time; the paths differ by rounding only).
fn integrate(samples: &[Sample], lanes: &Lanes) -> ZSums {
    #[cfg(target_arch = "x86_64")]
    {
        if is_x86_feature_detected!("fma") {
            if is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU supports AVX-512F and FMA (checked just above).
                return unsafe { integrate_avx512(samples, lanes) };
            }
            if is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU supports AVX2 and FMA (checked just above).
                return unsafe { integrate_avx2(samples, lanes) };
            }
        }
    }
    integrate_lanes::<false>(samples, lanes)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,fma")]
unsafe fn integrate_avx512(samples: &[Sample], lanes: &Lanes) -> ZSums {
    integrate_lanes::<true>(samples, lanes)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn integrate_avx2(samples: &[Sample], lanes: &Lanes) -> ZSums {
    integrate_lanes::<true>(samples, lanes)
}

/// a·b + c, fused when `FMA` (only on CPUs that have the instruction).
#[inline(always)]
fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

#[inline(always)]
fn integrate_lanes<const FMA: bool>(samples: &[Sample], lanes: &Lanes) -> ZSums {
    let mut z = [0.0f64; LANES];
    // Each lane's phase ψ: it grows by u = |dx|/x_y along a monotone stretch;
    // ψ ≥ 0 loading (z = s·tanh ψ), ψ < 0 unloading (z = s·unloading_w(ψ)).
    let mut psi = [0.0f64; LANES];
    let mut dir = 0.0;
    let mut sums: ZSums = [[0.0; LANES]; 5];
    for p in samples {
        if p.sign != 0.0 {
            if p.sign != dir {
                // A reversal (or the first motion): each lane's phase from its z.
                dir = p.sign;
                // Vectorised for the usual case, w ≤ 0 and r > 0 (ψ = atan(√r·w)/√r);
                // the other lanes exactly, one at a time.
                let mut other = false;
                for l in 0..LANES {
                    let w = dir * z[l];
                    psi[l] = fastmath::atan(lanes.sqrt_r[l] * w) * lanes.inv_sqrt_r[l];
                    other |= !(w <= 0.0 && lanes.r[l] > FLAT);
                }
                if other {
                    for l in 0..LANES {
                        let w = dir * z[l];
                        if !(w <= 0.0 && lanes.r[l] > FLAT) {
                            psi[l] = if w >= 0.0 {
                                w.atanh()
                            } else {
                                unloading_phase(w, lanes.r[l])
                            };
                        }
                    }
                }
            }
            let mut back = false;
            for l in 0..LANES {
                psi[l] = madd::<FMA>(p.abs_dx_mm, lanes.inv_x_y[l], psi[l]);
                // tanh ψ = (1 − e)/(1 + e), e = e^(−2ψ).
                let e = if FMA {
                    fastmath::exp_fma(-2.0 * psi[l])
                } else {
                    fastmath::exp(-2.0 * psi[l])
                };
                z[l] = dir * ((1.0 - e) / (1.0 + e));
                back |= psi[l] < 0.0;
            }
            if back {
                // Unloading lanes: w = tan(√r·ψ)/√r vectorised for r > 0, the others exactly.
                let mut other = false;
                for l in 0..LANES {
                    let w = fastmath::tan(lanes.sqrt_r[l] * psi[l]) * lanes.inv_sqrt_r[l];
                    if psi[l] < 0.0 {
                        z[l] = dir * w;
                        other |= lanes.r[l] <= FLAT;
                    }
                }
                if other {
                    for l in 0..LANES {
                        if psi[l] < 0.0 && lanes.r[l] <= FLAT {
                            z[l] = dir * unloading_w(psi[l], lanes.r[l]);
                        }
                    }
                }
            }
        }
        for l in 0..LANES {
            sums[0][l] = madd::<FMA>(z[l], p.v_m_s, sums[0][l]);
            sums[1][l] = madd::<FMA>(z[l], p.x_mm, sums[1][l]);
            sums[2][l] += z[l];
            sums[3][l] = madd::<FMA>(z[l], z[l], sums[3][l]);
            sums[4][l] = madd::<FMA>(z[l], p.force_n, sums[4][l]);
        }
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compare::families::bouc_wen::BoucWen;
    use crate::compare::fit::objective;
    use crate::dataset::Role;

    fn track(x_mm: Vec<f64>, force_n: Vec<f64>) -> Track {
        let n = x_mm.len();
        let v_m_s: Vec<f64> = (0..n)
            .map(|i| {
                if i == 0 {
                    0.0
                } else {
                    (x_mm[i] - x_mm[i - 1]) * 1e-3 / 0.01
                }
            })
            .collect();
        Track {
            stem: "t".into(),
            file: "t.csv".into(),
            current_a: 1.0,
            role: Role::Fit,
            time_s: (0..n).map(|i| i as f64 * 0.01).collect(),
            x_mm,
            v_m_s,
            force_scale_n: force_n.iter().fold(1e-9, |m, f: &f64| m.max(f.abs())),
            force_n,
        }
    }

    #[test]
    fn agrees_with_projecting_each_q_including_reversals_pauses_and_bad_q() {
        // Noisy sinusoids (many reversals), a pause (dx = 0) and a force with its own hysteresis.
        let tracks: Vec<Track> = (0..3)
            .map(|k| {
                let x: Vec<f64> = (0..500)
                    .map(|i| {
                        let t = i as f64 * 0.01;
                        let pause = if (200..220).contains(&i) { 0.0 } else { 1.0 };
                        pause * (3.0 + k as f64) * (2.0 * t).sin() + 0.05 * ((i * 7919 % 13) as f64 - 6.0) / 6.0
                    })
                    .collect();
                let f: Vec<f64> = x
                    .iter()
                    .enumerate()
                    .map(|(i, x)| 50.0 * x + 300.0 * ((i as f64 * 0.02).cos()))
                    .collect();
                track(x, f)
            })
            .collect();
        let batch = BoucWenBatch::new(&tracks);
        let mut qs: Vec<Vec<f64>> = Vec::new();
        for log_x_y in [-2.5, -1.0, -0.3, 0.4, 1.2] {
            for r in [-1.0, -0.4, 0.0, 0.7, 3.0] {
                qs.push(vec![log_x_y, r]);
            }
        }
        qs.push(vec![0.0, 3.5]); // r out of its range
        qs.push(vec![f64::NAN, 0.0]);
        qs.push(vec![0.0]); // wrong length
        let got = batch.evaluate(&qs);
        assert_eq!(got.len(), qs.len());
        let mut bases = Vec::new();
        for (q, g) in qs.iter().zip(&got) {
            let want = objective(&BoucWen, q, &tracks, &mut bases);
            if want.is_finite() {
                // Rounding only: ~1e-15 typically; 3e-10 at r = −1, where z can stick at
                // ±1 (dz/dx = 0 there) depending on the last bit of a saturated z.
                assert!(
                    (g - want).abs() <= 1e-9 * want,
                    "q {q:?}: batch {g} vs projection {want}"
                );
            } else {
                assert!(g.is_infinite(), "q {q:?}: batch {g}, projection not admissible");
            }
        }
        assert!(got[..25].iter().all(|j| j.is_finite()));
    }

    #[test]
    fn every_instruction_path_integrates_alike() {
        // The portable path (no FMA) against the one this CPU dispatches to.
        let x: Vec<f64> = (0..400)
            .map(|i| 5.0 * (i as f64 * 0.05).sin() + 0.03 * ((i % 7) as f64 - 3.0))
            .collect();
        let t = track(x, vec![1.0; 400]);
        let data = BoucWenBatch::new(std::slice::from_ref(&t));
        let lanes = Lanes::new(
            std::array::from_fn(|l| 0.05 + 0.3 * l as f64),
            std::array::from_fn(|l| -1.0 + 0.5 * l as f64),
        );
        let (portable, dispatched) = (
            integrate_lanes::<false>(&data.tracks[0].samples, &lanes),
            integrate(&data.tracks[0].samples, &lanes),
        );
        for (a, b) in portable.iter().flatten().zip(dispatched.iter().flatten()) {
            assert!((a - b).abs() <= 1e-9 * (1.0 + a.abs()), "{a} vs {b}");
        }
    }

    #[test]
    fn no_tracks_is_not_admissible() {
        let batch = BoucWenBatch::new(&[]);
        assert_eq!(batch.evaluate(&[vec![0.0, 0.5]]), vec![f64::INFINITY]);
    }
}
