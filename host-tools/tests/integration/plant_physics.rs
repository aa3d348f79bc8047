//! Physics checks of the drop-impact plant, with expected values from
//! physics and from the paper (never from the simulator's own output).
use mre_host::plant::synth::step_command;
use mre_host::plant::{
    simulate, ConcealedEffect, CurrentSource, ImpactConfig, LawParams, MeasurementModel, Plant, Trajectory,
};

/// The paper's Table 5 measured peak forces (`shared/paper/table4.toml`).
const TABLE5: [(f64, f64); 5] = [
    (0.0, 2079.22),
    (0.5, 5458.78),
    (1.0, 6603.41),
    (1.5, 7231.52),
    (2.0, 6421.51),
];

fn passive(plant: &Plant, cfg: &ImpactConfig, current_a: f64) -> Trajectory {
    simulate(plant, cfg, CurrentSource::Constant(current_a)).expect("simulation runs")
}

#[test]
fn calibration_matches_table5_peaks_within_10_percent() {
    let plant = Plant::nominal();
    let cfg = ImpactConfig::default();
    assert_eq!(
        (cfg.mass_kg, cfg.impact_velocity_m_s),
        (5.5, 2.24),
        "the paper's drop test"
    );
    for (current_a, measured_n) in TABLE5 {
        let s = passive(&plant, &cfg, current_a).summary;
        let peak = s.peak_force_n;
        let err = (peak - measured_n) / measured_n;
        eprintln!(
            "| {current_a} | {measured_n} | {peak:.0} | {:+.1} | {:.2} | {:.2} |",
            err * 100.0,
            s.max_stroke_mm,
            s.rebound_velocity_m_s.unwrap_or(f64::NAN)
        );
        assert!(
            err.abs() < 0.10,
            "{current_a} A: simulated {peak:.0} N vs Table 5 {measured_n} N ({:.1} %)",
            err * 100.0
        );
    }
}

#[test]
fn elastic_law_returns_the_impact_speed() {
    // No loss: gravity and the backbone are conservative, so the mass leaves
    // x = 0 at the speed it arrived with.
    let plant = Plant {
        law: LawParams::nominal().elastic(),
        ..Plant::nominal()
    };
    for (current_a, v0) in [(0.0, 2.24), (2.0, 2.24), (1.0, 1.2)] {
        let cfg = ImpactConfig {
            impact_velocity_m_s: v0,
            ..ImpactConfig::default()
        };
        let s = passive(&plant, &cfg, current_a).summary;
        let v_out = s.rebound_velocity_m_s.expect("the mass leaves the damper");
        assert!(
            (v_out - v0).abs() < 1e-6 * v0,
            "{current_a} A: out {v_out} m/s vs in {v0} m/s"
        );
    }
}

#[test]
fn elastic_peak_matches_energy_balance() {
    // Linear spring only (k3 = 0), no gravity: ½·m·v² = ½·k·x², F = k·x.
    let law = LawParams {
        k3_n_per_mm3: 0.0,
        ..LawParams::nominal().elastic()
    };
    let plant = Plant {
        law,
        ..Plant::nominal()
    };
    let cfg = ImpactConfig {
        gravity_m_s2: 0.0,
        ..ImpactConfig::default()
    };
    let k_n_per_m = 66.0e3;
    let expected_x_m = cfg.impact_velocity_m_s * (cfg.mass_kg / k_n_per_m).sqrt();
    let s = passive(&plant, &cfg, 0.0).summary;
    assert!(
        (s.max_stroke_mm - expected_x_m * 1e3).abs() < 1e-3,
        "{} mm vs {} mm",
        s.max_stroke_mm,
        expected_x_m * 1e3
    );
    assert!((s.peak_force_n - k_n_per_m * expected_x_m).abs() < 0.1);
    // Half a period of the mass-spring oscillator.
    let expected_t = std::f64::consts::PI * (cfg.mass_kg / k_n_per_m).sqrt();
    assert!((s.contact_time_s - expected_t).abs() < 2e-6);
}

#[test]
fn loss_makes_the_rebound_slower_and_current_stiffens() {
    let plant = Plant::nominal();
    let cfg = ImpactConfig::default();
    let soft = passive(&plant, &cfg, 0.0).summary;
    let stiff = passive(&plant, &cfg, 2.0).summary;
    assert!(soft.rebound_velocity_m_s.unwrap() < 0.9 * cfg.impact_velocity_m_s);
    assert!(stiff.max_stroke_mm < 0.5 * soft.max_stroke_mm);
    assert!(stiff.peak_force_n > 2.0 * soft.peak_force_n);
}

#[test]
fn recordings_hold_measured_samples_on_the_instrument_grid() {
    let plant = Plant::nominal();
    let cfg = ImpactConfig::default();
    let t = passive(&plant, &cfg, 1.0);
    let dt = plant.measurement.sample_period_s;
    for (i, s) in t.samples.iter().enumerate() {
        assert!((s.time_s - i as f64 * dt).abs() < 1e-12);
    }
    // Quantisation: forces are whole ADC counts.
    let lsb = MeasurementModel::default().force_lsb_n;
    assert!(t
        .samples
        .iter()
        .all(|s| ((s.force_n / lsb) - (s.force_n / lsb).round()).abs() < 1e-6));
    // Noise: the recording differs from a perfect instrument's by about σ.
    let ideal = Plant {
        measurement: plant.measurement.ideal(),
        ..Plant::nominal()
    };
    let clean = passive(&ideal, &cfg, 1.0);
    let mean_abs_diff: f64 = t
        .samples
        .iter()
        .zip(&clean.samples)
        .map(|(a, b)| (a.force_n - b.force_n).abs())
        .sum::<f64>()
        / t.samples.len() as f64;
    let sigma = plant.measurement.force_noise_n;
    assert!(
        mean_abs_diff > 0.5 * sigma && mean_abs_diff < 1.5 * sigma,
        "mean |noise| {mean_abs_diff} N"
    );
    assert_eq!(ConcealedEffect::None.name(), "none");
}

#[test]
fn coil_lag_is_first_order_and_commands_are_held() {
    let plant = Plant::nominal();
    let cfg = ImpactConfig {
        coil_lag_s: Some(1.0e-3),
        ..ImpactConfig::default()
    };
    let t = simulate(&plant, &cfg, CurrentSource::Function(Box::new(|_| 2.0))).unwrap();
    // I(t) = 2·(1 − e^{−t/τ}) from 0 A at contact.
    for s in t.samples.iter().filter(|s| s.time_s > 0.0).take(60) {
        let expected = 2.0 * (1.0 - (-s.time_s / 1.0e-3).exp());
        assert!(
            (s.current_a - expected).abs() < 2e-3,
            "t = {}: {} vs {expected}",
            s.time_s,
            s.current_a
        );
        assert_eq!(s.command_a, 2.0);
    }
    // A time-varying command reaches the coil at once without lag.
    let step = |t: f64| if t < 1.0e-3 { 0.0 } else { 1.0 };
    let t = simulate(
        &plant,
        &ImpactConfig::default(),
        CurrentSource::Function(Box::new(step)),
    )
    .unwrap();
    assert!(t
        .samples
        .iter()
        .all(|s| s.current_a == if s.time_s <= 1.0e-3 { 0.0 } else { 1.0 }));
}

/// The nominal law by hand (README): G(I)·(k1·x + k3·x³)·(1 + η·tanh(v/v_t)),
/// G linear between the knots 1, 10.15, 15.13, 16.33, 16.83 at 0…2 A.
fn nominal_force_by_hand(x_mm: f64, v_m_s: f64, current_a: f64) -> f64 {
    let knots = [1.0, 10.15, 15.13, 16.33, 16.83];
    let pos = (current_a.clamp(0.0, 2.0) / 0.5).min(3.999_999);
    let k = pos.floor() as usize;
    let gain = knots[k] + (pos - k as f64) * (knots[k + 1] - knots[k]);
    gain * (66.0 * x_mm + 0.080 * x_mm.powi(3)) * (1.0 + 0.5 * (v_m_s / 0.003).tanh())
}

/// A perfect instrument: the samples are the true state and force.
fn ideal_nominal() -> Plant {
    Plant {
        measurement: MeasurementModel::default().ideal(),
        ..Plant::nominal()
    }
}

#[test]
fn coil_lag_after_a_command_step_is_first_order_and_drives_the_force() {
    // Coil energised at 0 A before contact, command 0 → 2 A at 0.8 ms:
    // I(t) = 2·(1 − e^{−(t − 0.8 ms)/τ}) after the step, and the force is
    // the law at that lagging current.
    let plant = ideal_nominal();
    let (tau, step_at) = (0.5e-3, 0.8e-3);
    let cfg = ImpactConfig {
        coil_lag_s: Some(tau),
        initial_current_a: 0.0,
        ..ImpactConfig::default()
    };
    let command = step_command(0.0, 2.0, step_at, cfg.step_s);
    let t = simulate(&plant, &cfg, CurrentSource::Function(Box::new(command))).unwrap();
    let after = |dt: f64| {
        t.samples
            .iter()
            .find(|s| (s.time_s - step_at - dt).abs() < 1e-9)
            .unwrap()
    };
    // At τ, 2τ, 3τ: 63.2 %, 86.5 %, 95.0 % of the way.
    for (dt, fraction) in [(tau, 0.632_120_6), (2.0 * tau, 0.864_664_7), (3.0 * tau, 0.950_212_9)] {
        let s = after(dt);
        assert!(
            (s.current_a - 2.0 * fraction).abs() < 1e-6,
            "{} s: {} A",
            s.time_s,
            s.current_a
        );
    }
    for s in &t.samples {
        if s.time_s <= step_at + 1e-9 {
            assert_eq!((s.command_a, s.current_a), (0.0, 0.0), "no transient before the step");
        } else {
            let expected = 2.0 * (1.0 - (-(s.time_s - step_at) / tau).exp());
            assert_eq!(s.command_a, 2.0);
            assert!((s.current_a - expected).abs() < 1e-9, "{} s", s.time_s);
        }
        if s.x_mm > 0.0 && s.v_m_s > 0.05 {
            let law = nominal_force_by_hand(s.x_mm, s.v_m_s, s.current_a);
            assert!((s.force_n - law).abs() < 1e-6 * law.max(1.0), "{} s", s.time_s);
        }
    }
    // Right after the step the force is still far below the 2 A law.
    let s = after(0.05e-3);
    assert!(s.force_n < 0.3 * nominal_force_by_hand(s.x_mm, s.v_m_s, 2.0));
}

#[test]
fn without_lag_the_force_after_a_step_is_the_law_at_the_new_current() {
    let plant = ideal_nominal();
    let step_at = 0.8e-3;
    for (from, to) in [(0.0, 2.0), (2.0, 0.0), (0.5, 1.5), (2.0, 1.0)] {
        let cfg = ImpactConfig {
            initial_current_a: from,
            ..ImpactConfig::default()
        };
        let command = step_command(from, to, step_at, cfg.step_s);
        let t = simulate(&plant, &cfg, CurrentSource::Function(Box::new(command))).unwrap();
        let k = t.samples.iter().position(|s| s.time_s > step_at + 1e-9).unwrap();
        assert!((t.samples[k].time_s - step_at - 0.05e-3).abs() < 1e-9);
        for s in &t.samples[k - 3..k + 3] {
            let i = if s.time_s <= step_at + 1e-9 { from } else { to };
            assert_eq!((s.command_a, s.current_a), (i, i));
            let law = nominal_force_by_hand(s.x_mm, s.v_m_s, i);
            assert!((s.force_n - law).abs() < 1e-6 * law, "{from}→{to} at {} s", s.time_s);
        }
    }
}

#[test]
fn a_coil_energised_before_contact_hides_its_lag_at_constant_current() {
    for current_a in [0.0, 0.7, 2.0] {
        let cfg = ImpactConfig {
            initial_current_a: current_a,
            ..ImpactConfig::default()
        };
        let lagging = ImpactConfig {
            coil_lag_s: Some(0.8e-3),
            ..cfg.clone()
        };
        let plant = Plant::nominal();
        assert_eq!(
            passive(&plant, &cfg, current_a),
            passive(&plant, &lagging, current_a),
            "{current_a} A"
        );
    }
}

#[test]
fn bad_settings_are_refused_with_a_clear_error() {
    let plant = Plant::nominal();
    // Each bad setting with the words its error must contain.
    let bad = [
        ImpactConfig {
            impact_velocity_m_s: f64::NAN,
            ..ImpactConfig::default()
        },
        ImpactConfig {
            step_s: 1.0e-5,
            ..ImpactConfig::default()
        },
        ImpactConfig {
            control_period_s: 1.25e-4,
            ..ImpactConfig::default()
        },
        ImpactConfig {
            mass_kg: -1.0,
            ..ImpactConfig::default()
        },
    ];
    let expected = [
        "impact settings must be finite",
        "RK4 step must be in (0, 1 µs]",
        "control period must be a whole number of sample periods",
        "mass must be positive",
    ];
    for (cfg, want) in bad.into_iter().zip(expected) {
        let err = simulate(&plant, &cfg, CurrentSource::Constant(1.0)).unwrap_err();
        assert!(format!("{err:#}").contains(want), "expected `{want}` in: {err:#}");
    }
    let mut broken = Plant::nominal();
    broken.law.loss_eta = 1.5;
    assert!(simulate(&broken, &ImpactConfig::default(), CurrentSource::Constant(1.0)).is_err());
    // A controller that returns NaN gets 0 A (documented safe state), never a panic.
    let t = simulate(
        &plant,
        &ImpactConfig::default(),
        CurrentSource::Controller(Box::new(|_, _| f32::NAN)),
    )
    .unwrap();
    assert!(t.samples.iter().all(|s| s.command_a == 0.0));
}
