//! The control step against mock I/O: fault handling, fail-safe, overrun
//! accounting, rate config, stats and the coil duty.
use mre_algorithm::control::{ControlConfig, ControlConfigError, Controller, DEFAULT_RATE_HZ};
use mre_algorithm::estimate::AlphaBeta;
use mre_algorithm::law::ImpactLaw;
use mre_algorithm::table::{Table, TableError, TableImage, PAPER_TABLE4, PAPER_TABLE4_ENTRIES};
use mre_algorithm::{Branch, Flags};
use mre_runtime::io::{open_loop_duty, Coil, ControllerIo, DisplacementSensor, NoVelocitySensor, VelocitySensor};

/// Plays back a script of displacements, then repeats the last one.
struct ScriptX {
    xs: Vec<f32>,
    at: usize,
}
impl DisplacementSensor for ScriptX {
    fn read_x_mm(&mut self) -> f32 {
        let x = self.xs.get(self.at).or(self.xs.last()).copied().unwrap_or(0.0);
        self.at += 1;
        x
    }
}

struct ConstV(Option<f32>);
impl VelocitySensor for ConstV {
    fn read_v_m_s(&mut self) -> Option<f32> {
        self.0
    }
}

#[derive(Default)]
struct RecordingCoil(Vec<f32>);
impl Coil for RecordingCoil {
    fn set_current_a(&mut self, current_a: f32) {
        self.0.push(current_a);
    }
}

fn controller(rate_hz: u32) -> Controller {
    let cfg = ControlConfig::at_rate(rate_hz).unwrap();
    Controller::new(cfg, Table::paper()).unwrap()
}

/// The documented fail-safe: 2 A, the stiffest damper.
const FAILSAFE_A: f32 = 2.0;

#[test]
fn rate_config_sets_period_and_refuses_out_of_range_rates() {
    assert_eq!(ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap().period_s(), 1.0e-4);
    assert_eq!(ControlConfig::at_rate(20_000).unwrap().period_s(), 5.0e-5);
    assert_eq!(
        ControlConfig::at_rate(500),
        Err(ControlConfigError::Rate { rate_hz: 500 })
    );
    assert_eq!(
        ControlConfig::at_rate(50_000),
        Err(ControlConfigError::Rate { rate_hz: 50_000 })
    );
    // A law period that disagrees with the rate is refused.
    let mut cfg = ControlConfig::at_rate(10_000).unwrap();
    cfg.rate_hz = 20_000;
    assert_eq!(cfg.validate(), Err(ControlConfigError::PeriodMismatch));
}

#[test]
fn slew_limit_per_period_follows_the_rate() {
    // The law plans for where the period ends: at 3 m/s, 0.3 mm on at
    // 10 kHz and 0.15 mm at 20 kHz. From x = 0.2 mm that leaves 11.5 and
    // 11.65 mm of the 12 mm stroke: 5.5·9/(2·0.0115) + 5.5·9.81 = 2206.129 N
    // and 5.5·9/(2·0.01165) + 53.955 = 2178.419 N. Table 4 needs more than the
    // first slew step for either, so the command ramps at 2000 A/s from 0 A.
    for (rate_hz, first_step_a, target_n) in [(10_000, 0.2f32, 2206.129f32), (20_000, 0.1, 2178.419)] {
        let mut c = controller(rate_hz);
        let cmd = c.step_sample(0.2, Some(3.0));
        assert_eq!(cmd.branch, Branch::Compression);
        assert!((cmd.target_force_n - target_n).abs() < 0.05, "{}", cmd.target_force_n);
        assert!(cmd.flags.contains(Flags::SLEW_LIMITED));
        assert!(
            (cmd.current_a - first_step_a).abs() < 1e-6,
            "{rate_hz} Hz: {}",
            cmd.current_a
        );
        let cmd = c.step_sample(0.21, Some(3.0));
        assert!((cmd.current_a - 2.0 * first_step_a).abs() < 1e-6);
    }
}

#[test]
fn step_reads_sensors_and_commands_the_coil_with_the_returned_current() {
    let mut c = controller(10_000);
    // At 4 m/s the law plans 0.4 mm ahead (one period), at 0.2–0.23 mm,
    // where the stopping force (about 3 kN) needs 1.9–2 A.
    let mut x = ScriptX {
        xs: vec![-0.2, -0.19, -0.18, -0.17],
        at: 0,
    };
    let mut v = ConstV(Some(4.0));
    let mut coil = RecordingCoil::default();
    let cmds: Vec<_> = (0..4).map(|_| c.step(&mut x, &mut v, &mut coil)).collect();
    assert_eq!(coil.0, cmds.iter().map(|c| c.current_a).collect::<Vec<_>>());
    // Ramping up at the slew limit: 0.2, 0.4, 0.6, 0.8 A.
    for (k, a) in coil.0.iter().enumerate() {
        assert!((a - 0.2 * (k as f32 + 1.0)).abs() < 1e-5, "{k}: {a}");
    }
    assert_eq!(c.stats().periods, 4);
}

#[test]
fn corrupt_table_latches_table_fault_and_stays_fail_safe() {
    let corrupt = TableImage {
        crc32: PAPER_TABLE4.crc32 ^ 1,
        ..PAPER_TABLE4
    };
    let table = Table::from_image(&corrupt);
    assert!(matches!(table, Err(TableError::CrcMismatch { .. })));
    let mut c = Controller::new(ControlConfig::at_rate(10_000).unwrap(), table).unwrap();
    assert!(c.table().is_none());
    for _ in 0..3 {
        let cmd = c.step_sample(5.0, Some(1.0));
        assert_eq!(cmd.current_a, FAILSAFE_A);
        assert!(cmd.flags.contains(Flags::TABLE_FAULT | Flags::FAIL_SAFE));
    }
    // A table does not heal.
    c.clear_faults();
    assert!(c.step_sample(5.0, Some(1.0)).flags.contains(Flags::TABLE_FAULT));
    assert_eq!(c.stats().fault_latches, 1);
    assert_eq!(c.stats().failsafe_periods, 4);
}

#[test]
fn a_short_range_glitch_is_fail_safe_only_while_it_lasts() {
    let mut c = controller(10_000);
    for _ in 0..9 {
        let cmd = c.step_sample(30.0, Some(1.0)); // valid range is -1..25 mm
        assert_eq!(cmd.current_a, FAILSAFE_A);
        assert!(cmd.flags.contains(Flags::SENSOR_RANGE | Flags::FAIL_SAFE));
    }
    assert_eq!(c.latched(), Flags::NONE);
    let cmd = c.step_sample(5.0, Some(-1.0));
    assert!(!cmd.flags.contains(Flags::FAIL_SAFE), "{:?}", cmd.flags);
    assert!(cmd.flags.contains(Flags::REBOUND));
}

#[test]
fn persistent_out_of_range_latches_until_cleared() {
    let mut c = controller(10_000);
    for _ in 0..10 {
        c.step_sample(-5.0, Some(1.0));
    }
    assert_eq!(c.latched(), Flags::SENSOR_RANGE);
    // Good samples do not unlatch it.
    let cmd = c.step_sample(5.0, Some(-1.0));
    assert_eq!(cmd.current_a, FAILSAFE_A);
    assert!(cmd.flags.contains(Flags::SENSOR_RANGE | Flags::FAIL_SAFE));
    c.clear_faults();
    let cmd = c.step_sample(5.0, Some(-1.0));
    assert!(!cmd.flags.is_fault(), "{:?}", cmd.flags);
}

#[test]
fn non_finite_samples_give_finite_fail_safe_and_latch() {
    let mut c = controller(10_000);
    for (k, x) in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY]
        .into_iter()
        .cycle()
        .take(10)
        .enumerate()
    {
        let cmd = c.step_sample(x, None);
        assert_eq!(cmd.current_a, FAILSAFE_A, "sample {k}");
        assert!(cmd.flags.contains(Flags::NON_FINITE_INPUT));
    }
    assert_eq!(c.latched(), Flags::NON_FINITE_INPUT);
    // A NaN velocity from the sensor is caught as well.
    let mut c = controller(10_000);
    assert!(c.step_sample(5.0, Some(f32::NAN)).flags.contains(Flags::FAIL_SAFE));
}

#[test]
fn frozen_displacement_while_velocity_sensor_reports_motion_is_stuck() {
    let mut c = controller(10_000);
    // First sample sets the reference; 50 more unchanged ones latch.
    for k in 0..50 {
        let cmd = c.step_sample(3.0, Some(1.0));
        assert!(!cmd.flags.contains(Flags::SENSOR_STUCK), "latched early at {k}");
    }
    let cmd = c.step_sample(3.0, Some(1.0));
    assert!(cmd.flags.contains(Flags::SENSOR_STUCK | Flags::FAIL_SAFE));
    assert_eq!(cmd.current_a, FAILSAFE_A);
}

#[test]
fn resting_mass_or_moving_reading_is_not_stuck() {
    // At rest (|v| below 0.05 m/s) a constant reading is expected.
    let mut c = controller(10_000);
    for _ in 0..200 {
        c.step_sample(3.0, Some(0.01));
    }
    // Without a velocity sensor a constant reading cannot be judged.
    let mut d = controller(10_000);
    for _ in 0..200 {
        d.step_sample(3.0, None);
    }
    // A reading that changes every period while moving.
    let mut e = controller(10_000);
    for k in 0..200 {
        e.step_sample(1.0 + 0.01 * k as f32, Some(0.1));
    }
    // The count restarts when the reading moves: 49 frozen, 1 moved, 49 frozen.
    let mut f = controller(10_000);
    for x in std::iter::repeat_n(3.0, 50).chain(std::iter::repeat_n(3.1, 50)) {
        f.step_sample(x, Some(1.0));
    }
    for ctl in [c, d, e, f] {
        assert_eq!(ctl.latched(), Flags::NONE);
    }
}

#[test]
fn overruns_are_counted_and_repeated_ones_latch() {
    let mut c = controller(10_000);
    for _ in 0..9 {
        c.step_sample(5.0, Some(-1.0));
        c.end_period(true);
    }
    assert_eq!(c.stats().overruns, 9);
    assert_eq!(c.latched(), Flags::NONE);
    c.end_period(true);
    assert_eq!(c.latched(), Flags::OVERRUN);
    let cmd = c.step_sample(5.0, Some(-1.0));
    assert!(cmd.flags.contains(Flags::OVERRUN | Flags::FAIL_SAFE));
    assert_eq!(cmd.current_a, FAILSAFE_A);
}

#[test]
fn sparse_overruns_in_separate_windows_do_not_latch() {
    let mut c = controller(10_000);
    // 9 overruns per 1000-period window, for three windows.
    for period in 0..3000 {
        c.end_period(period % 1000 < 9);
    }
    assert_eq!(c.stats().overruns, 27);
    assert_eq!(c.latched(), Flags::NONE);
    // Skipped ticks count as overruns too.
    c.record_missed_periods(25);
    assert_eq!(c.stats().overruns, 52);
    assert_eq!(c.latched(), Flags::OVERRUN);
}

#[test]
fn cycle_stats_report_min_mean_max() {
    let mut c = controller(10_000);
    for cycles in [300, 100, 200] {
        c.record_step_cycles(cycles);
    }
    let s = c.stats();
    assert_eq!(
        (s.step_cycles_min, s.step_cycles_mean(), s.step_cycles_max),
        (100, 200, 300)
    );
    c.reset_cycle_stats();
    assert_eq!(c.stats().step_cycles_count, 0);
}

#[test]
fn without_velocity_sensor_the_estimator_feeds_the_law() {
    // Composition by hand: the same alpha-beta filter and law, fed the same
    // samples, must give the same commands bit for bit.
    let cfg = ControlConfig::at_rate(10_000).unwrap();
    let table = Table::new(&PAPER_TABLE4_ENTRIES).unwrap();
    let mut c = Controller::new(cfg, Ok(table)).unwrap();
    let mut est = AlphaBeta::benedict_bordner(cfg.period_s(), cfg.estimator_alpha);
    let mut law = ImpactLaw::new(cfg.law).unwrap();
    let mut x = ScriptX {
        xs: (0..300).map(|k| 0.15 * k as f32).collect(),
        at: 0,
    };
    let mut coil = RecordingCoil::default();
    let mut saw_compression = false;
    for _ in 0..300 {
        let cmd = c.step(&mut x, &mut NoVelocitySensor, &mut coil);
        let (v, _) = est.update(x.xs[x.at - 1]);
        let expected = law.step(&table, x.xs[x.at - 1], v);
        assert_eq!(cmd, expected);
        saw_compression |= cmd.branch == Branch::Compression;
    }
    // 0.15 mm per 100 µs is 1.5 m/s: the estimator must have found compression.
    assert!(saw_compression);
    assert!((est.velocity_m_s() - 1.5).abs() < 0.01, "{}", est.velocity_m_s());
}

#[test]
fn open_loop_duty_scales_and_clamps() {
    assert!((open_loop_duty(1.0, 3.0) - 1.0 / 3.0).abs() < 1e-7);
    assert_eq!(open_loop_duty(5.0, 3.0), 1.0);
    assert_eq!(open_loop_duty(-1.0, 3.0), 0.0);
    assert_eq!(open_loop_duty(f32::NAN, 3.0), 0.0);
    assert_eq!(open_loop_duty(1.0, 0.0), 0.0);
}

#[test]
fn a_velocity_sensor_at_its_rail_is_a_range_fault_not_a_rebound() {
    // The sensor's ADC spans 0..3.3 V = 1.65 V ± 1.65 V at 3.33 m/s per V:
    // a broken wire reads the rail, (0 − 1.65) · 5/1.5 = −5.5 m/s. Taken at
    // face value that is a rebound, which commands the *minimum* current
    // mid-impact; it must command the fail-safe instead and latch.
    let rail_m_s = (0.0 - 1.65) * (5.0 / 1.5);
    let mut c = controller(10_000);
    for k in 0..10 {
        let cmd = c.step_sample(5.0, Some(rail_m_s));
        assert_eq!(cmd.current_a, FAILSAFE_A, "period {k}");
        assert!(
            cmd.flags.contains(Flags::SENSOR_RANGE | Flags::FAIL_SAFE),
            "{:?}",
            cmd.flags
        );
        assert!(!cmd.flags.contains(Flags::REBOUND));
    }
    assert_eq!(c.latched(), Flags::SENSOR_RANGE);
    // Just inside the rated ±5 m/s is a plausible (fast) rebound.
    let mut c = controller(10_000);
    let cmd = c.step_sample(5.0, Some(-4.9));
    assert!(cmd.flags.contains(Flags::REBOUND) && !cmd.flags.contains(Flags::FAIL_SAFE));
}

#[test]
fn a_velocity_sensor_that_contradicts_the_displacement_latches_disagree() {
    // x rises 0.15 mm per 100 µs period: 1.5 m/s (22.5 mm after 150
    // periods, inside the stroke), while a sensor stuck at its zero (an open
    // input biased to 1.65 V) reports 0 m/s.
    let ramp = |k: usize| 0.15 * k as f32;
    let mut c = controller(10_000);
    let mut first_latch = None;
    for k in 0..150 {
        let cmd = c.step_sample(ramp(k), Some(0.0));
        if cmd.flags.contains(Flags::SENSOR_DISAGREE) && first_latch.is_none() {
            first_latch = Some(k);
            assert_eq!(cmd.current_a, FAILSAFE_A);
        }
    }
    // The estimator needs a few periods to see the 1 m/s, then 50 periods
    // more than 1 m/s apart latch: well inside 150 periods, not before 50.
    let k = first_latch.expect("SENSOR_DISAGREE never latched");
    assert!((50..150).contains(&k), "latched at period {k}");

    // An honest sensor on the same ramp: no fault.
    let mut c = controller(10_000);
    for k in 0..150 {
        let cmd = c.step_sample(ramp(k), Some(1.5));
        assert!(!cmd.flags.is_fault(), "period {k}: {:?}", cmd.flags);
    }
}
