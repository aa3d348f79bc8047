//! The law with a version 2 table: coil-lag inversion, look-ahead, pre-energising
//! and sensor-delay prediction, always within the coil's and the driver's limits.
use mre_algorithm::law::{stopping_force_n, ImpactLaw, LawConfig, CONTACT_MM};
use mre_algorithm::table::ModelTerms;
use mre_algorithm::Table;
use proptest::prelude::*;

fn with_terms(terms: ModelTerms) -> Table {
    Table::with_terms(&mre_algorithm::generated_table::GENERATED_ENTRIES, terms).unwrap()
}

/// No impact range: idle at the fixed `armed_current_a` (arming from the
/// range is `law_arming.rs`'s).
fn fast() -> LawConfig {
    LawConfig {
        slew_a_per_s: 1.0e9,
        impact_v_max_m_s: 0.0,
        ..LawConfig::default()
    }
}

fn lag(tau_s: f32) -> ModelTerms {
    ModelTerms {
        coil_tau_s: tau_s,
        ..ModelTerms::NONE
    }
}

#[test]
fn the_drive_brings_a_first_order_coil_to_the_wanted_current_in_one_period() {
    // τ = 0.2 ms at T = 100 µs: α = 1 − e^{−0.5} = 0.393469. From 0 A, the
    // idle law wants the armed 0.5 A: drive 0.5/α = 1.270747 A (inside the
    // ±3 A supply), and the coil, i += α·(u − i), lands on 0.5 A.
    let alpha = 1.0 - (-0.5f64).exp();
    let table = with_terms(lag(2.0e-4));
    // A law that has not been idle yet: its coil model starts at 0 A.
    let mut law = ImpactLaw::new(LawConfig {
        armed_current_a: 0.0,
        ..fast()
    })
    .unwrap();
    for _ in 0..3 {
        law.step(&table, 5.0, -1.0); // rebounding: 0 A wanted
    }
    assert!(law.coil_estimate_a().abs() < 1e-6);
    let mut law = ImpactLaw::new(fast()).unwrap();
    law.step(&table, 5.0, -1.0);
    let drive = law.step(&table, 0.0, 0.0).current_a as f64;
    assert!((drive - 1.270747).abs() < 1e-3, "{drive}");
    let coil = alpha * drive;
    assert!((coil - 0.5).abs() < 1e-4, "{coil}");
    assert!((law.coil_estimate_a() as f64 - 0.5).abs() < 1e-4);
    // On the way out (rebound: minimum current wanted) the drive reverses:
    // 0.5 − 0.5/α = −0.770747 A takes the coil to 0 A in one period.
    let drive = law.step(&table, 1.0, -0.5).current_a as f64;
    assert!((drive + 0.770747).abs() < 1e-3, "{drive}");
    assert!((0.5 + alpha * (drive - 0.5)).abs() < 1e-4);
    // A bigger jump than the supply allows saturates at −3 A (−12 V / 4 Ω).
    let mut slow = ImpactLaw::new(fast()).unwrap();
    let cmd = slow.step(&with_terms(lag(5.0e-3)), 1.0, -0.5);
    assert_eq!(cmd.current_a, -3.0);
}

fn lagged_free() -> Table {
    with_terms(ModelTerms::NONE)
}

#[test]
fn idle_with_a_lagging_coil_pre_energises_and_without_one_rests_at_the_minimum() {
    let mut lagging = ImpactLaw::new(fast()).unwrap();
    let lagged = with_terms(lag(1.0e-3));
    // Resting at contact: extension branch, x at contact.
    for _ in 0..200 {
        lagging.step(&lagged, 0.0, 0.0);
    }
    assert!((lagging.coil_estimate_a() - fast().armed_current_a).abs() < 1e-3);
    let mut plain = ImpactLaw::new(fast()).unwrap();
    assert_eq!(plain.step(&lagged_free(), 0.0, 0.0).current_a, 0.0);
    // Past contact on the way out the rebound policy applies (0 A wanted).
    let mut out = ImpactLaw::new(fast()).unwrap();
    let cmd = out.step(&lagged, CONTACT_MM + 1.0, -0.5);
    assert!(cmd.current_a < 0.0, "drives the current down: {}", cmd.current_a);
}

/// The flown entries with a sensor delay `d` only, and a fresh fast law.
fn delayed(d: f32) -> (Table, LawConfig, ImpactLaw) {
    let table = with_terms(ModelTerms {
        sensor_delay_s: d,
        ..ModelTerms::NONE
    });
    (table, fast(), ImpactLaw::new(fast()).unwrap())
}

#[test]
fn sensor_delay_is_predicted_with_the_free_fall_before_contact() {
    // Before contact (x < 0) no force acts: across d = 0.5 ms the mass moves
    // v·d + ½·g·d² and speeds up by g·d. The law targets the stopping force
    // of that predicted state, one period on.
    let d = 5.0e-4f32;
    let (table, cfg, mut law) = delayed(d);
    let (x_mm, v) = (-0.5f32, 2.0f32);
    let cmd = law.step(&table, x_mm, v);
    let x_p = -0.5 + (2.0 * 5.0e-4 + 0.5 * 9.81 * 2.5e-7) * 1.0e3;
    let v_p = 2.0 + 9.81 * 5.0e-4;
    // ... and then plans for the end of the 100 µs period it holds the command.
    let x_p = x_p + v_p * 1.0e-4 * 1.0e3;
    let expected = stopping_force_n(5.5, 9.81, v_p, cfg.stroke_max_mm - x_p).unwrap();
    assert!(
        (cmd.target_force_n - expected).abs() < 1e-2 * expected,
        "{} vs {expected}",
        cmd.target_force_n
    );
    // Without the delay the target is that of the sample itself (lower).
    let plain = ImpactLaw::new(cfg).unwrap().step(&lagged_free(), x_mm, v);
    assert!(plain.target_force_n < cmd.target_force_n);
}

#[test]
fn in_contact_the_delay_is_predicted_with_the_last_plans_force() {
    // On contact the prediction decelerates with the force the model gave at
    // the previous compression plan's current: there the target (met, not
    // saturated), F1. Across d the mass moves v·d + ½·a·d² with
    // a = g − F1/m and slows by a·d; the law then plans for the end of its
    // period and targets m·v²/(2r) + m·g for that state.
    let d = 5.0e-4f32;
    let (table, cfg, mut law) = delayed(d);
    let first = law.step(&table, 2.0, 2.0);
    assert!(
        !first
            .flags
            .intersects(mre_algorithm::Flags::SATURATED_HIGH | mre_algorithm::Flags::SATURATED_LOW),
        "{first:?}"
    );
    let f1 = f64::from(first.target_force_n);
    let (x2, v2) = (2.2f64, 1.95f64);
    let cmd = law.step(&table, x2 as f32, v2 as f32);
    let (m, g, dd, t) = (5.5f64, 9.81f64, f64::from(d), 1.0e-4f64);
    let a = g - f1 / m;
    let x_p = x2 + (v2 * dd + 0.5 * a * dd * dd) * 1.0e3;
    let v_p = v2 + a * dd;
    let x_end = x_p + v_p * t * 1.0e3;
    let expected = m * v_p * v_p / (2.0 * (f64::from(cfg.stroke_max_mm) - x_end) * 1.0e-3) + m * g;
    let got = f64::from(cmd.target_force_n);
    assert!((got - expected).abs() < 1e-4 * expected, "{got} vs {expected}");
    // The first step had no plan yet: the mass counted as free (a = g).
    let v_free = 2.0 + g * dd;
    let x_free = 2.0 + (2.0 * dd + 0.5 * g * dd * dd) * 1.0e3 + v_free * t * 1.0e3;
    let free = m * v_free * v_free / (2.0 * (f64::from(cfg.stroke_max_mm) - x_free) * 1.0e-3) + m * g;
    assert!((f1 - free).abs() < 1e-4 * free, "{f1} vs {free}");
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(256))]
    /// Whatever the samples, the drive stays within the supply's range and
    /// the law's coil model within the coil's current limits.
    #[test]
    fn drive_and_coil_stay_within_their_limits(
        tau_ms in 0.05f32..8.0,
        delay_ms in 0.0f32..1.0,
        samples in prop::collection::vec((-2.0f32..30.0, -6.0f32..6.0), 1..80),
    ) {
        let table = with_terms(ModelTerms {
            coil_tau_s: tau_ms * 1e-3,
            sensor_delay_s: delay_ms * 1e-3,
            ..ModelTerms::NONE
        });
        let cfg = LawConfig::default();
        let mut law = ImpactLaw::new(cfg).unwrap();
        for (x, v) in samples {
            let cmd = law.step(&table, x, v);
            prop_assert!(cmd.current_a.is_finite());
            prop_assert!(cmd.current_a >= cfg.drive_min_a && cmd.current_a <= cfg.drive_max_a, "{cmd:?}");
            let i = law.coil_estimate_a();
            prop_assert!(i >= cfg.current_min_a - 1e-4 && i <= cfg.current_max_a + 1e-4, "coil {i}");
        }
    }
}

#[test]
fn the_look_ahead_caps_the_wanted_current_from_the_plans_trend() {
    // τ = 0.5 ms at T = 100 µs: the look-ahead Δ = 0.1·τ is 0.5 periods,
    // α = 1 − e^{−0.2}. Period 1 at contact plans above every entry's force
    // (saturated high: I1, the strongest entry there); period 2 plans I2 on
    // a segment. The plan's current Δ ahead, extrapolated along its change,
    // is clamp(I2 + 0.5·(I2 − I1), 0, 2), and a coil decaying at the −3 A
    // drive reaches at best u_min + (i − u_min)·e^{−0.1} in Δ: the law wants
    // min(I2, −3 + (ahead + 3)·e^{0.1}).
    let table = with_terms(lag(5.0e-4));
    let cfg = fast();
    let mut law = ImpactLaw::new(cfg).unwrap();
    let plan = |x_mm: f32, v_m_s: f32| {
        let x_plan = x_mm + v_m_s * cfg.period_s * 1.0e3;
        let f = stopping_force_n(cfg.mass_kg, cfg.gravity_m_s2, v_m_s, cfg.stroke_max_mm - x_plan).unwrap();
        table.current_for_branch_v(x_plan, v_m_s, mre_algorithm::Branch::Compression, f)
    };
    let p1 = plan(0.0, 2.24);
    assert!(
        p1.flags.contains(mre_algorithm::Flags::SATURATED_HIGH),
        "contact asks more than any entry gives"
    );
    let i1 = p1.current_a as f64;
    law.step(&table, 0.0, 2.24);
    let i2 = plan(1.0, 2.0).current_a as f64;
    assert!(i2 > 0.2 && i2 < 1.0, "{i2}");
    let ahead = (i2 + 0.5 * (i2 - i1)).clamp(0.0, 2.0);
    let expected = i2.min(-3.0 + (ahead + 3.0) * 0.1f64.exp());
    assert!(expected < i2 - 1e-3, "the cap binds here: {expected} < {i2}");
    let cmd = law.step(&table, 1.0, 2.0);
    assert!(cmd.current_a.abs() < 3.0, "drive inside the supply: {}", cmd.current_a);
    // An unclamped drive takes the modelled coil to the wanted current.
    let coil = law.coil_estimate_a() as f64;
    assert!((coil - expected).abs() < 1e-4, "{coil} vs {expected}");
}

/// The law's non-finite test now sits behind the output clamp's (a NaN
/// wanted current differs from its clamp): it must still fail safe. A
/// configuration that lets a velocity of 1e38 m/s through (finite, so
/// valid) makes the stopping force infinite; the plan, outside its
/// preconditions, gives a NaN current, and the law commands the fail-safe
/// current with `TABLE_FAULT` instead of the softest one.
#[test]
fn a_nan_plan_fails_safe_behind_the_output_clamp() {
    let cfg = LawConfig {
        v_valid_max_m_s: f32::MAX,
        ..LawConfig::default()
    };
    let mut law = ImpactLaw::new(cfg).unwrap();
    let table = Table::with_terms(
        &mre_algorithm::generated_table::GENERATED_ENTRIES,
        ModelTerms::EVERY_TERM,
    )
    .unwrap();
    let cmd = law.step(&table, 1.0, 1.0e38);
    assert!(
        cmd.flags
            .contains(mre_algorithm::Flags::FAIL_SAFE | mre_algorithm::Flags::TABLE_FAULT),
        "{cmd:?}"
    );
    assert_eq!(cmd.current_a, cfg.failsafe_current_a);
}
