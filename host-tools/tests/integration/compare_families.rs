//! Each family of `mre compare` against a closed form or an independent
//! computation (never against its own earlier output).
use mre_host::compare::families::{
    bouc_wen::{step, BoucWen, MAX_R},
    dahl::Dahl,
    exponential::Exponential,
    kwok_tanh::KwokTanh,
    spencer::Spencer,
    Family, Scales,
};
use mre_host::compare::fit::{fit_family, objective, project, refine, Budget};
use mre_host::compare::tracks::Track;
use mre_host::dataset::Role;
use mre_host::fit::gsa::GsaParams;

/// A track along given x(t) (mm), with v from the exact derivative (m/s) and zero force.
fn track(time_s: Vec<f64>, x_mm: Vec<f64>, v_m_s: Vec<f64>) -> Track {
    let n = time_s.len();
    Track {
        stem: "synthetic".into(),
        file: "synthetic.csv".into(),
        current_a: 0.0,
        role: Role::Fit,
        time_s,
        x_mm,
        v_m_s,
        force_n: vec![1.0; n],
        force_scale_n: 1.0,
    }
}

/// A triangle wave between ±amp_mm, `cycles` periods of 1 s, `per_cycle` samples each.
fn triangle(amp_mm: f64, cycles: usize, per_cycle: usize) -> Track {
    let n = cycles * per_cycle + 1;
    let dt = 1.0 / per_cycle as f64;
    let (mut t, mut x, mut v) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        let time = i as f64 * dt;
        let phase = time.fract();
        // −amp at phase 0, +amp at 0.5, slope ±4·amp per s.
        let (xi, vi) = if phase < 0.5 {
            (-amp_mm + 4.0 * amp_mm * phase, 4.0 * amp_mm * 1e-3)
        } else {
            (amp_mm - 4.0 * amp_mm * (phase - 0.5), -4.0 * amp_mm * 1e-3)
        };
        t.push(time);
        x.push(xi);
        v.push(vi);
    }
    track(t, x, v)
}

fn sinusoid(amp_mm: f64, freq_hz: f64, cycles: usize, per_cycle: usize) -> Track {
    let n = cycles * per_cycle + 1;
    let w = 2.0 * std::f64::consts::PI * freq_hz;
    let t: Vec<f64> = (0..n).map(|i| i as f64 / (freq_hz * per_cycle as f64)).collect();
    let x = t.iter().map(|t| amp_mm * (w * t).sin()).collect();
    let v = t.iter().map(|t| amp_mm * 1e-3 * w * (w * t).cos()).collect();
    track(t, x, v)
}

fn simulate(f: &dyn Family, p: &[f64], t: &Track) -> Vec<f64> {
    let mut out = Vec::new();
    assert!(f.simulate(p, t, &mut out), "{} rejected {p:?}", f.name());
    out
}

#[test]
fn bouc_wen_steady_loop_matches_its_closed_form() {
    // r = 0 (β = γ = ½): loading from z = −z_top, dz/dx = 1/x_y while z < 0 and
    // (1 − z²)/x_y after, so z reaches 0 at x0 = −X + z_top·x_y and then
    // z = tanh((x − x0)/x_y); symmetry closes the loop at
    // z_top = tanh(2X/x_y − z_top), solved here by bisection.
    let (amp, x_y) = (2.0, 0.8);
    let g = |z: f64| z - (2.0 * amp / x_y - z).tanh();
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let z_top = 0.5 * (lo + hi);
    let t = triangle(amp, 6, 4000);
    // α = 1 and nothing else: F = z.
    let z = simulate(&BoucWen, &[f64::log10(x_y), 0.0, 0.0, 0.0, 1.0, 0.0], &t);
    let x0 = -amp + z_top * x_y;
    let last_loading = 5 * 4000..5 * 4000 + 2000;
    for i in last_loading {
        let x = t.x_mm[i];
        let want = if x < x0 {
            -z_top + (x + amp) / x_y
        } else {
            ((x - x0) / x_y).tanh()
        };
        assert!((z[i] - want).abs() < 2e-4, "x = {x}: z = {} vs {want}", z[i]);
    }
}

#[test]
fn dahl_response_to_a_monotone_ramp_is_exponential() {
    // From z = 0 at x = 0 on a ramp: z = 1 − e^(−σx), so
    // F = k0·x + c0·v + Fd·(1 − e^(−σx)) + f0.
    let n = 501;
    let v = 0.01;
    let t = track(
        (0..n).map(|i| i as f64 * 0.01).collect(),
        (0..n).map(|i| i as f64 * 0.01 * v * 1e3).collect(),
        vec![v; n],
    );
    let (sigma, k0, c0, fd, f0) = (1.7f64, 3.0, 200.0, 50.0, -4.0);
    let f = simulate(&Dahl, &[sigma.log10(), k0, c0, fd, f0], &t);
    for (x, got) in t.x_mm.iter().zip(&f) {
        let want = k0 * x + c0 * v + fd * (1.0 - (-sigma * x).exp()) + f0;
        assert!((got - want).abs() < 1e-9, "x = {x}: {got} vs {want}");
    }
}

#[test]
fn exponential_layers_at_one_rate_are_one_dahl_element() {
    // Three hysterons with the same σ move together: the sum is Dahl with Fd = a1 + a2 + a3.
    let t = sinusoid(3.0, 2.0, 3, 500);
    let ls = 0.4f64;
    let (k0, c0, f0, a) = (2.0, 150.0, 1.5, [10.0, 20.0, 30.0]);
    let e = simulate(&Exponential, &[ls, ls, ls, k0, c0, f0, a[0], a[1], a[2]], &t);
    let d = simulate(&Dahl, &[ls, k0, c0, a.iter().sum(), f0], &t);
    for (x, y) in e.iter().zip(&d) {
        assert!((x - y).abs() < 1e-9);
    }
}

#[test]
fn kwok_tanh_limits() {
    let (c, k, alpha, beta, delta, f0) = (100.0, 5.0, 40.0, 50.0, 0.3, 2.0);
    let p = [f64::log10(beta), delta, c, k, alpha, f0];
    let t = track(
        vec![0.0, 1.0, 2.0, 3.0],
        vec![1.0, 1.0, -1.0, 0.5],
        vec![10.0, -10.0, 0.0, 0.0],
    );
    let f = simulate(&KwokTanh, &p, &t);
    // |βv| = 500: tanh saturates at ±1.
    assert!((f[0] - (c * 10.0 + k + alpha + f0)).abs() < 1e-9);
    assert!((f[1] - (-c * 10.0 + k - alpha + f0)).abs() < 1e-9);
    // v = 0: only the sign of x drives the tanh, F = k·x ± α·tanh(δ) + f0.
    assert!((f[2] - (-k - alpha * delta.tanh() + f0)).abs() < 1e-12);
    assert!((f[3] - (0.5 * k + alpha * delta.tanh() + f0)).abs() < 1e-12);
}

#[test]
fn spencer_without_spring_and_bouc_wen_is_two_dampers_in_series() {
    // α = 0, k0 = 0: ẏ = c0·ẋ/(c0 + c1), F = c1·ẏ + k1·x + f0 = c0c1/(c0 + c1)·ẋ + k1·x + f0.
    let t = sinusoid(5.0, 1.0, 2, 400);
    let (c0, c1, k1, f0) = (300.0, 900.0, 4.0, -3.0);
    let q = [0.0, 0.0, c0, c0, f64::log10(c1), f64::log10(c1), 0.0, 0.5, 0.0];
    let f = simulate(&Spencer, &[&q[..], &[k1, f0]].concat(), &t);
    let series = c0 * c1 / (c0 + c1);
    for ((x, v), got) in t.x_mm.iter().zip(&t.v_m_s).zip(&f) {
        let want = series * v + k1 * x + f0;
        assert!((got - want).abs() < 1e-9 * want.abs().max(1.0));
    }
}

#[test]
fn spencer_with_a_stiff_low_velocity_damper_is_bouc_wen() {
    // c1 → ∞: ẏ → 0, y stays at x(0), and F = αz + c0ẋ + k0(x − x(0)) + k1·x with
    // z the Bouc–Wen variable of x: the Bouc–Wen family with k = k0 + k1,
    // f0 = −k0·x(0). Different integrators (time, implicit vs displacement, midpoint).
    let t = sinusoid(4.0, 1.0, 3, 2000);
    let (alpha, c0, k0, k1, x_y, r) = (60.0, 200.0, 3.0, 1.0, 0.6, 0.4);
    let q = [alpha, alpha, c0, c0, 12.0, 12.0, k0, x_y, r];
    let s = simulate(&Spencer, &[&q[..], &[k1, 0.0]].concat(), &t);
    let b = simulate(&BoucWen, &[f64::log10(x_y), r, c0, k0 + k1, alpha, -k0 * t.x_mm[0]], &t);
    let scale = b.iter().fold(0.0f64, |m, f| m.max(f.abs()));
    for (i, (x, y)) in s.iter().zip(&b).enumerate() {
        assert!((x - y).abs() < 5e-3 * scale, "sample {i}: spencer {x} vs bouc-wen {y}");
    }
}

#[test]
fn projection_recovers_the_linear_parameters_exactly() {
    // Force made by Dahl with known parameters: at the true σ the least
    // squares give back k0, c0, Fd, f0 and a zero objective.
    let mut t = sinusoid(3.0, 1.0, 2, 500);
    let truth = [0.2, 7.0, 300.0, 80.0, -5.0];
    t.force_n = simulate(&Dahl, &truth, &t);
    t.force_scale_n = t.force_n.iter().fold(0.0, |m: f64, f| m.max(f.abs()));
    let p = project(&Dahl, &truth[..1], std::slice::from_ref(&t), &mut Vec::new(), true).expect("admissible");
    let direct: f64 = p.residuals.iter().map(|r| r * r).sum::<f64>().sqrt();
    assert!((direct - p.objective).abs() < 1e-9);
    assert!(p.objective < 1e-9, "objective {}", p.objective);
    for (got, want) in p.theta.iter().zip(&truth[1..]) {
        assert!((got - want).abs() < 1e-6 * want.abs().max(1.0), "{got} vs {want}");
    }
}

#[test]
fn gsa_and_lm_find_a_planted_bouc_wen_loop() {
    // Data made by Bouc–Wen itself: the fit must get back to (almost) zero error.
    let mut t = sinusoid(5.0, 1.0, 3, 400);
    let truth = [f64::log10(0.7), 0.3, 250.0, 4.0, 120.0, 3.0];
    t.force_n = simulate(&BoucWen, &truth, &t);
    t.force_scale_n = t.force_n.iter().fold(0.0, |m: f64, f| m.max(f.abs()));
    let budget = Budget {
        gsa: GsaParams {
            agents: 15,
            iters: 30,
            ..GsaParams::default()
        },
        gsa_samples_per_track: 400,
        lm_samples_per_track: usize::MAX,
        lm_patience: 20,
    };
    let fitted = fit_family(&BoucWen, std::slice::from_ref(&t), &budget, 3);
    assert!(fitted.lm_objective[0] < 1e-3, "objective {:?}", fitted.lm_objective);
    let p = &fitted.sets[0].1;
    assert!((p[0] - truth[0]).abs() < 0.01 && (p[4] - truth[4]).abs() < 2.0, "{p:?}");
}

#[test]
fn lm_follows_a_bound_to_the_best_point_on_it() {
    // Data made with r = 5, beyond the box (r ≤ MAX_R): the best admissible fit
    // lies on r = MAX_R. LM's clipped steps stall along that bound (without the
    // second round J ends 0.3–7 % above the line's minimum here); `refine` must
    // reach the minimum along the line, found independently on a dense grid.
    let mut t = sinusoid(5.0, 1.0, 3, 400);
    let (mut z, mut prev) = (0.0, t.x_mm[0]);
    t.force_n = (0..t.len())
        .map(|i| {
            z = step(z, t.x_mm[i] - prev, 0.4, 5.0);
            prev = t.x_mm[i];
            250.0 * t.v_m_s[i] + 4.0 * t.x_mm[i] + 120.0 * z + 3.0
        })
        .collect();
    t.force_scale_n = t.force_n.iter().fold(0.0, |m: f64, f| m.max(f.abs()));
    let tracks = std::slice::from_ref(&t);
    let (lower, upper) = BoucWen.bounds(&Scales::of(tracks));
    let grid_best = (0..=4000)
        .map(|k| {
            let log_x_y = lower[0] + (upper[0] - lower[0]) * k as f64 / 4000.0;
            objective(&BoucWen, &[log_x_y, MAX_R], tracks, &mut Vec::new())
        })
        .fold(f64::INFINITY, f64::min);
    for start in [[0.1f64.log10(), 1.0], [0.6f64.log10(), 2.0], [2f64.log10(), 2.8]] {
        let (q, j, _) = refine(&BoucWen, &start, &lower, &upper, tracks, 30);
        assert_eq!(q[1], MAX_R, "from {start:?}: {q:?}");
        assert!(j <= grid_best + 1e-7, "from {start:?}: J {j} vs the line's {grid_best}");
    }
}
