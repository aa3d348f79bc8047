//! The alpha-beta velocity estimator against its textbook properties.
use mre_algorithm::estimate::AlphaBeta;
use mre_algorithm::Flags;

const PERIOD_S: f32 = 1.0e-4;

#[test]
fn tracks_a_constant_velocity_without_lag() {
    let mut f = AlphaBeta::benedict_bordner(PERIOD_S, 0.3);
    let v_true = 2.24f32;
    let mut v = 0.0;
    for k in 0..2000 {
        let x_mm = v_true * (k as f32 * PERIOD_S) * 1.0e3;
        v = f.update(x_mm).0;
    }
    assert!((v - v_true).abs() < 1e-3, "{v}");
}

#[test]
fn constant_acceleration_lag_matches_theory() {
    // Velocity bias under acceleration a: a·T·(α/β − ½) (Kalata 1984).
    let (alpha, beta) = (0.4f32, 0.1f32);
    let mut f = AlphaBeta::new(PERIOD_S, alpha, beta);
    let a = -200.0f64; // m/s²: 1.1 kN on the paper's 5.5 kg
    let v0 = 2.0f64;
    let mut v_est = 0.0f64;
    let mut v_true = 0.0f64;
    for k in 0..500 {
        let t = k as f64 * PERIOD_S as f64;
        v_true = v0 + a * t;
        let x_mm = (v0 * t + 0.5 * a * t * t) * 1.0e3;
        v_est = f.update(x_mm as f32).0 as f64;
    }
    let expected_bias = a * PERIOD_S as f64 * (alpha as f64 / beta as f64 - 0.5);
    // The estimate trails the truth by the bias.
    assert!(
        ((v_true - v_est) - expected_bias).abs() < 0.02 * expected_bias.abs(),
        "{} vs {expected_bias}",
        v_true - v_est
    );
    assert!((f.velocity_lag_m_s(a as f32) as f64 - expected_bias).abs() < 1e-6);
}

/// Standard normal samples from a seeded xorshift generator (Box–Muller).
struct Gaussian(u64);

impl Gaussian {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn next(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

#[test]
fn velocity_noise_matches_the_steady_state_variance_formula() {
    // σ_v/σ = sqrt(2β²/(α(4 − 2α − β)))/T for white position noise σ.
    let mut f = AlphaBeta::benedict_bordner(PERIOD_S, 0.2);
    let (alpha, beta) = (f.alpha() as f64, f.beta() as f64);
    let expected_gain = (2.0 * beta * beta / (alpha * (4.0 - 2.0 * alpha - beta))).sqrt() / PERIOD_S as f64;
    assert!((f.velocity_noise_gain_per_s() as f64 - expected_gain).abs() < 1e-3 * expected_gain);

    let sigma_mm = 0.01;
    let mut noise = Gaussian(0x9E37_79B9_7F4A_7C15);
    let (mut sum, mut sum_sq, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..200_000 {
        let v = f.update((sigma_mm * noise.next()) as f32).0 as f64;
        if k > 1000 {
            sum += v;
            sum_sq += v * v;
            n += 1.0;
        }
    }
    let std_v = (sum_sq / n - (sum / n).powi(2)).sqrt();
    let expected = expected_gain * sigma_mm * 1.0e-3;
    assert!(
        (std_v - expected).abs() < 0.05 * expected,
        "measured {std_v} m/s, theory {expected} m/s"
    );
}

#[test]
fn bad_samples_are_skipped_and_flagged() {
    let mut f = AlphaBeta::benedict_bordner(PERIOD_S, 0.3);
    for k in 0..100 {
        f.update(k as f32 * 0.1);
    }
    let before = f.velocity_m_s();
    let (v, flags) = f.update(f32::NAN);
    assert_eq!(flags, Flags::NON_FINITE_INPUT);
    assert_eq!(v, before);
    let (_, flags) = f.update(1.0e9);
    assert_eq!(flags, Flags::SENSOR_RANGE);
    assert!(f.position_mm().is_finite());
}

#[test]
fn unstable_gains_fall_back_to_a_stable_filter() {
    let f = AlphaBeta::new(PERIOD_S, 1.5, 3.0);
    assert!(f.alpha() > 0.0 && f.alpha() <= 1.0);
    assert!(f.beta() > 0.0 && f.beta() < 4.0 - 2.0 * f.alpha());
}
