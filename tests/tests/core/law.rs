//! The impact-mitigation law: physics of the stopping force, and its limits.
use mre_algorithm::law::{stopping_force_n, ConfigError, ImpactLaw, LawConfig, ReboundPolicy};
use mre_algorithm::model::Branch;
use mre_algorithm::{Flags, Table};

fn paper() -> Table {
    Table::paper().expect("built-in table is valid")
}

fn fast_config() -> LawConfig {
    // No slew limit in the way, so one step reaches the wanted current.
    LawConfig {
        slew_a_per_s: 1.0e9,
        ..LawConfig::default()
    }
}

#[test]
fn stopping_force_is_the_energy_balance() {
    // 5.5 kg at 2.24 m/s with 10 mm left: ½mv²/r + mg
    // = 0.5·5.5·5.0176/0.010 + 5.5·9.81 = 1379.84 + 53.955 N.
    let f = stopping_force_n(5.5, 9.81, 2.24, 10.0).expect("stroke remains");
    assert!((f - 1433.795).abs() < 0.01, "{f}");
    assert_eq!(stopping_force_n(5.5, 9.81, 2.24, 0.0), None);
    assert_eq!(stopping_force_n(5.5, 9.81, 2.24, -3.0), None);
    assert_eq!(stopping_force_n(5.5, 9.81, 2.24, f32::NAN), None);
}

#[test]
fn compression_command_produces_the_stopping_force() {
    let t = paper();
    let cfg = LawConfig {
        stroke_max_mm: 1.2,
        ..fast_config()
    };
    let mut law = ImpactLaw::new(cfg).expect("valid config");
    // Sampled at x = 0.4 mm, v = 1.0 m/s, the law plans for the end of the
    // 100 µs period, x = 0.5 mm: F* = 0.5·5.5·1.0/0.0007 + 53.955 = 3982.5 N,
    // which the paper's table reaches between 0.5 A (2532.6 N) and 1 A
    // (4826.2 N) at x = 0.5 mm.
    let cmd = law.step(&t, 0.4, 1.0);
    let expected_force = 0.5 * 5.5 * 1.0 / 0.0007 + 5.5 * 9.81;
    assert!(
        (cmd.target_force_n - expected_force).abs() < 0.5,
        "{}",
        cmd.target_force_n
    );
    assert_eq!(cmd.branch, Branch::Compression);
    assert!(!cmd.flags.is_fault());
    let achieved = t.force_on_branch(0.5, Branch::Compression, cmd.current_a).force_n;
    assert!(
        (achieved - cmd.target_force_n).abs() < 1.0,
        "{achieved} vs {}",
        cmd.target_force_n
    );
    assert!(cmd.current_a > 0.5 && cmd.current_a < 1.0, "{}", cmd.current_a);
}

#[test]
fn slew_rate_limits_each_step() {
    let t = paper();
    let cfg = LawConfig {
        stroke_max_mm: 1.2,
        slew_a_per_s: 1000.0,
        period_s: 1.0e-4,
        ..LawConfig::default()
    };
    let mut law = ImpactLaw::new(cfg).expect("valid config");
    // The wanted current is far above 0 A; each step may move 1000 A/s · 100 µs = 0.1 A.
    let first = law.step(&t, 0.9, 2.0);
    assert!((first.current_a - 0.1).abs() < 1e-6, "{}", first.current_a);
    assert!(first.flags.contains(Flags::SLEW_LIMITED));
    let second = law.step(&t, 0.9, 2.0);
    assert!((second.current_a - 0.2).abs() < 1e-6);
}

#[test]
fn rebound_policies() {
    let t = paper();
    for (policy, expected_a) in [
        (ReboundPolicy::Minimum, 0.0),
        (ReboundPolicy::Fixed { current_a: 0.7 }, 0.7),
        (ReboundPolicy::Fixed { current_a: 9.0 }, 2.0), // clamped to the output range
    ] {
        let mut law = ImpactLaw::new(LawConfig {
            rebound: policy,
            ..fast_config()
        })
        .expect("valid config");
        let cmd = law.step(&t, 0.5, -1.0);
        assert_eq!(cmd.current_a, expected_a, "{policy:?}");
        assert!(cmd.flags.contains(Flags::REBOUND));
    }
    let mut law = ImpactLaw::new(LawConfig {
        rebound: ReboundPolicy::Hold,
        stroke_max_mm: 1.2,
        ..fast_config()
    })
    .expect("valid config");
    let pressing = law.step(&t, 0.5, 1.2);
    let rebounding = law.step(&t, 0.6, -0.5);
    assert_eq!(rebounding.current_a, pressing.current_a);
}

#[test]
fn branch_hysteresis_ignores_noise_around_zero_velocity() {
    let t = paper();
    let mut law = ImpactLaw::new(LawConfig {
        branch_band_m_s: 0.01,
        ..fast_config()
    })
    .expect("valid config");
    assert_eq!(law.step(&t, 0.5, 0.5).branch, Branch::Compression);
    // Inside the ±10 mm/s band the branch holds.
    assert_eq!(law.step(&t, 0.5, -0.004).branch, Branch::Compression);
    assert_eq!(law.step(&t, 0.5, 0.003).branch, Branch::Compression);
    assert_eq!(law.step(&t, 0.5, -0.02).branch, Branch::Extension);
    assert_eq!(law.step(&t, 0.5, 0.009).branch, Branch::Extension);
}

#[test]
fn the_last_tenth_of_a_millimetre_is_planned_as_a_tenth_left() {
    let t = paper();
    let cfg = LawConfig {
        stroke_max_mm: 5.0,
        ..fast_config()
    };
    let mut law = ImpactLaw::new(cfg).expect("valid config");
    // At the end at 0.5 m/s: ½·5.5·0.25/0.1e-3 + 5.5·9.81 = 6875 + 53.955 N,
    // not the unbounded force of stopping in no stroke.
    let cmd = law.step(&t, 5.0, 0.5);
    assert!((cmd.target_force_n - 6928.955).abs() < 0.5, "{}", cmd.target_force_n);
    assert!(cmd.flags.contains(Flags::STROKE_EXHAUSTED));
    // Beyond the end, the same; a fast arrival still gets the maximum.
    let mut law = ImpactLaw::new(cfg).expect("valid config");
    let cmd = law.step(&t, 5.3, 3.0);
    assert_eq!(cmd.current_a, 2.0);
    assert!(cmd.flags.contains(Flags::STROKE_EXHAUSTED | Flags::SATURATED_HIGH));
    // Before the terminal zone the plan uses the real remaining stroke.
    let mut law = ImpactLaw::new(cfg).expect("valid config");
    assert!(!law.step(&t, 4.8, 0.5).flags.contains(Flags::STROKE_EXHAUSTED));
}

#[test]
fn untrusted_inputs_command_the_fail_safe_current() {
    let t = paper();
    let cfg = LawConfig {
        failsafe_current_a: 1.25,
        ..fast_config()
    };
    let mut law = ImpactLaw::new(cfg).expect("valid config");
    for (x, v, flag) in [
        (f32::NAN, 1.0, Flags::NON_FINITE_INPUT),
        (0.5, f32::INFINITY, Flags::NON_FINITE_INPUT),
        (cfg.x_valid_max_mm + 1.0, 1.0, Flags::SENSOR_RANGE),
        (0.5, -cfg.v_valid_max_m_s * 2.0, Flags::SENSOR_RANGE),
    ] {
        let cmd = law.step(&t, x, v);
        assert_eq!(cmd.current_a, 1.25, "x={x} v={v}");
        assert!(cmd.flags.contains(flag | Flags::FAIL_SAFE));
    }
}

#[test]
fn invalid_configurations_are_refused() {
    let base = LawConfig::default();
    assert_eq!(
        ImpactLaw::new(LawConfig {
            mass_kg: f32::NAN,
            ..base
        })
        .err(),
        Some(ConfigError::NonFinite)
    );
    assert_eq!(
        ImpactLaw::new(LawConfig { mass_kg: 0.0, ..base }).err(),
        Some(ConfigError::NonPositive)
    );
    assert_eq!(
        ImpactLaw::new(LawConfig {
            current_min_a: 2.0,
            current_max_a: 1.0,
            ..base
        })
        .err(),
        Some(ConfigError::EmptyOutputRange)
    );
    assert_eq!(
        ImpactLaw::new(LawConfig {
            failsafe_current_a: 3.0,
            ..base
        })
        .err(),
        Some(ConfigError::FailsafeOutsideRange)
    );
    assert_eq!(
        ImpactLaw::new(LawConfig {
            rebound: ReboundPolicy::Fixed { current_a: f32::NAN },
            ..base
        })
        .err(),
        Some(ConfigError::NonFinite)
    );
}

/// The law of `compression_command_produces_the_stopping_force` (paper
/// table, 1.2 mm stroke), with the given observer gain.
fn observed_law(observer_gain: f32) -> ImpactLaw {
    ImpactLaw::new(LawConfig {
        stroke_max_mm: 1.2,
        observer_gain,
        ..fast_config()
    })
    .expect("valid config")
}

#[test]
fn the_force_observer_sees_the_model_error_in_the_measured_deceleration() {
    // At x = 0.4 mm, v = 1.0 m/s the inverse is inside the table (between
    // 0.5 and 1 A, see above). A plant that gives 80 % of the model's force
    // F decelerates the mass by 0.8·F/m − g over the 100 µs period; with
    // the observer taking each observation whole (gain 1), the error it
    // reports is F − m·(g − Δv/T) = F − 0.8·F = 0.2·F.
    let t = paper();
    let (m, g, period) = (5.5f32, 9.81f32, 1.0e-4f32);
    let mut law = observed_law(1.0);
    let first = law.step(&t, 0.4, 1.0);
    assert!(!first
        .flags
        .intersects(Flags::SATURATED_HIGH.union(Flags::SATURATED_LOW)));
    let asked_n = first.target_force_n;
    let v_next = 1.0 + (g - 0.8 * asked_n / m) * period;
    let second = law.step(&t, 0.5, v_next);
    let error_n = law.force_error_n();
    assert!((error_n - 0.2 * asked_n).abs() < 0.5, "{error_n} vs {}", 0.2 * asked_n);
    // The plan is the same with the observer off; the command is higher,
    // since it asks the model for the plan plus the error.
    let mut plain = observed_law(0.0);
    plain.step(&t, 0.4, 1.0);
    let unobserved = plain.step(&t, 0.5, v_next);
    assert_eq!(plain.force_error_n(), 0.0);
    assert_eq!(second.target_force_n, unobserved.target_force_n);
    assert!(second.current_a > unobserved.current_a);
}

#[test]
fn the_force_observer_learns_nothing_where_the_model_does_not_set_the_force() {
    let t = paper();
    let (m, g, period) = (5.5f32, 9.81f32, 1.0e-4f32);
    // Out of stroke: the plan asks for far more than 2 A gives (saturated).
    // The plant then gives less than asked, but that is the coil's limit,
    // not a model error.
    let mut law = observed_law(1.0);
    let cmd = law.step(&t, 1.15, 2.0);
    assert!(cmd.flags.contains(Flags::SATURATED_HIGH), "{:?}", cmd.flags);
    law.step(&t, 1.17, 2.0 + (g - 1000.0 / m) * period);
    assert_eq!(law.force_error_n(), 0.0);
    // Moving out (rebound): no plan, nothing to compare.
    let mut law = observed_law(1.0);
    law.step(&t, 0.5, -0.5);
    law.step(&t, 0.45, -0.5 + (g - 500.0 / m) * period);
    assert_eq!(law.force_error_n(), 0.0);
}

/// A law that learned a model error of 0.2·F (≈ 800 N) over one period, as
/// in `the_force_observer_sees_the_model_error_in_the_measured_deceleration`.
fn law_with_a_learned_error() -> (ImpactLaw, Table) {
    let t = paper();
    let (m, g, period) = (5.5f32, 9.81f32, 1.0e-4f32);
    let mut law = observed_law(1.0);
    let asked_n = law.step(&t, 0.4, 1.0).target_force_n;
    law.step(&t, 0.5, 1.0 + (g - 0.8 * asked_n / m) * period);
    assert!(law.force_error_n() > 500.0, "{}", law.force_error_n());
    (law, t)
}

#[test]
fn the_force_observer_starts_from_zero_after_a_fail_safe_period() {
    let (mut law, t) = law_with_a_learned_error();
    law.fail_safe(Flags::SENSOR_RANGE);
    assert_eq!(law.force_error_n(), 0.0);
    // The next compression period asks the model for the plan alone: the
    // same command as a law that never learned anything (after one
    // fail-safe period of its own, for the same slew and coil state).
    let mut fresh = observed_law(1.0);
    fresh.step(&t, 0.4, 1.0);
    fresh.fail_safe(Flags::SENSOR_RANGE);
    assert_eq!(law.step(&t, 0.45, 1.0), fresh.step(&t, 0.45, 1.0));
    // The over-current's drive-off too.
    let (mut law, _) = law_with_a_learned_error();
    law.drive_off(Flags::OVER_CURRENT);
    assert_eq!(law.force_error_n(), 0.0);
}

#[test]
fn the_force_observer_starts_from_zero_when_the_law_re_arms_between_impacts() {
    let (mut law, t) = law_with_a_learned_error();
    // Rebound mid-stroke: not reset (the impact is not over; the rebound
    // sample itself updates the estimate, which is then non-zero).
    law.step(&t, 0.3, -0.5);
    assert_ne!(law.force_error_n(), 0.0);
    // Back at contact, moving out: re-armed, nothing carried to the next impact.
    law.step(&t, 0.0, -0.5);
    assert_eq!(law.force_error_n(), 0.0);
}

#[test]
fn the_force_observers_correction_is_clamped() {
    // A plant that gives no force at all: the whole asked force F ≈ 3980 N
    // is "model error" with gain 1; the correction stops at the limit.
    let t = paper();
    let (g, period) = (9.81f32, 1.0e-4f32);
    let mut law = observed_law(1.0);
    let asked_n = law.step(&t, 0.4, 1.0).target_force_n;
    assert!(asked_n > 2.0 * mre_algorithm::law::FORCE_ERROR_LIMIT_N, "{asked_n}");
    law.step(&t, 0.5, 1.0 + g * period);
    assert_eq!(law.force_error_n(), mre_algorithm::law::FORCE_ERROR_LIMIT_N);
    // And the other way: a plant far stiffer than the model.
    let mut law = observed_law(1.0);
    law.step(&t, 0.4, 1.0);
    law.step(&t, 0.5, 1.0 - 2.0);
    assert_eq!(law.force_error_n(), -mre_algorithm::law::FORCE_ERROR_LIMIT_N);
}
