//! The over-current fault (`mre_algorithm::overcurrent`), the current-sense zero
//! at boot, and the fault's path into the controller's fail-safe.
use mre_algorithm::control::{ControlConfig, Controller};
use mre_algorithm::law::LawConfig;
use mre_algorithm::overcurrent::{
    OverCurrent, Sense, SenseMonitor, SenseVerdict, COIL_RATING_A, STALE_PERIODS, STUCK_DRIVEN_A, STUCK_PERIODS,
    TRIP_A, TRIP_SAMPLES,
};
use mre_algorithm::table::Table;
use mre_algorithm::Flags;
use mre_protocol::frame::{CommandFrame, SampleFrame};
use mre_runtime::calibration::{rest_offset, CalError, I_SENSE_REST};

// The trip level sits above the coil's rating, within 25 % of it.
const _: () = assert!(TRIP_A > COIL_RATING_A && TRIP_A <= 1.25 * COIL_RATING_A);

#[test]
fn the_trip_level_is_above_the_fail_safe_current() {
    // The fail-safe itself (2 A) must never trip the fault it answers.
    let failsafe_a = LawConfig::default().failsafe_current_a;
    assert!(TRIP_A > failsafe_a, "{failsafe_a}");
}

#[test]
fn three_periods_in_a_row_above_the_trip_level_latch() {
    let mut oc = OverCurrent::default();
    assert_eq!(TRIP_SAMPLES, 3);
    // At the rating and at the trip level itself: never.
    for _ in 0..1000 {
        assert!(!oc.check(2.0));
        assert!(!oc.check(2.4));
    }
    // Two over, one back under: the count restarts (a noisy conversion).
    assert!(!oc.check(3.0));
    assert!(!oc.check(3.0));
    assert!(!oc.check(1.0));
    assert_eq!(oc.above(), 0);
    assert!(!oc.check(2.5));
    assert!(!oc.check(2.5));
    assert!(oc.check(2.5));
}

#[test]
fn a_negative_or_non_finite_reading_counts_as_over() {
    let mut oc = OverCurrent::new(2.4, 2);
    assert!(!oc.check(-3.0));
    assert!(oc.check(-3.0));
    let mut oc = OverCurrent::new(2.4, 2);
    assert!(!oc.check(f32::NAN));
    assert!(oc.check(f32::INFINITY));
}

#[test]
fn the_current_sense_zero_is_taken_with_the_pwm_off_and_range_checked() {
    // 64 readings around 0.03 A of amplifier offset, within 0.01 A.
    let samples: Vec<f32> = (0..64).map(|k| 0.03 + 0.01 * ((k % 5) as f32 / 4.0 - 0.5)).collect();
    let offset = rest_offset(&samples, 0.0, I_SENSE_REST).unwrap();
    assert!((offset - 0.03).abs() < 1.0e-3, "{offset}");
    // 0.2 A at rest: the amplifier or the shunt is wrong.
    assert!(matches!(
        rest_offset(&[0.2; 64], 0.0, I_SENSE_REST),
        Err(CalError::OutOfRange(o)) if (o - 0.2).abs() < 1.0e-5
    ));
    // Current flowing (PWM not off): spread far beyond the ADC noise.
    let ripple: Vec<f32> = (0..64).map(|k| if k % 2 == 0 { 0.0 } else { 0.3 }).collect();
    assert!(matches!(
        rest_offset(&ripple, 0.0, I_SENSE_REST),
        Err(CalError::NotAtRest { .. })
    ));
}

#[test]
fn a_latched_over_current_removes_the_drive_until_cleared_at_rest() {
    let cfg = ControlConfig::at_rate(10_000).unwrap();
    let mut ctl = Controller::new(cfg, Table::paper()).unwrap();
    // At rest: 0 mm, not moving.
    let before = ctl.step_sample(0.0, Some(0.0));
    ctl.end_period(false);
    assert!(!before.flags.contains(Flags::FAIL_SAFE));
    // Three conversions over the trip level, fed before the step as the
    // board does: the third period's step already commands no drive.
    for _ in 0..TRIP_SAMPLES {
        ctl.check_coil_current(Some(Sense::Fresh(3.0)));
    }
    assert!(ctl.latched().contains(Flags::OVER_CURRENT));
    for _ in 0..50 {
        // Mid-impact, and with a sensor fault on top: still no drive. The
        // 2 A fail-safe would be 67 % duty into the shorted coil.
        let cmd = ctl.step_sample(5.0, Some(2.0));
        ctl.end_period(false);
        assert!(
            cmd.flags.contains(Flags::OVER_CURRENT | Flags::FAIL_SAFE),
            "{:?}",
            cmd.flags
        );
        assert_eq!(cmd.current_a, 0.0);
        assert_eq!(ctl.step_sample(f32::NAN, None).current_a, 0.0);
    }
    assert_eq!(ctl.stats().fault_latches, 1);
    // B1 at rest clears the other faults but not this one (issue 39: only a
    // reset clears an over-current, firmware/README.md): still 0 A.
    for _ in 0..200 {
        ctl.step_sample(0.0, Some(0.0));
    }
    assert!(ctl.clear_faults_if_at_rest());
    assert!(ctl.latched().contains(Flags::OVER_CURRENT));
    let after = ctl.step_sample(0.0, Some(0.0));
    assert!(after.flags.contains(Flags::OVER_CURRENT), "{:?}", after.flags);
    assert_eq!(after.current_a, 0.0);
    // A reset (`clear_faults`) does.
    ctl.clear_faults();
    let after = ctl.step_sample(0.0, Some(0.0));
    assert!(!after.flags.intersects(Flags::OVER_CURRENT | Flags::FAIL_SAFE));
}

#[test]
fn over_current_overrides_every_other_fault_with_zero_drive() {
    let cfg = ControlConfig::at_rate(10_000).unwrap();
    let mut ctl = Controller::new(cfg, Table::paper()).unwrap();
    // A dead sense channel first (fail-safe 2 A), then an over-current.
    for _ in 0..STALE_PERIODS {
        ctl.check_coil_current(Some(Sense::Stale));
    }
    let cmd = ctl.step_sample(0.0, Some(0.0));
    assert!(cmd.flags.contains(Flags::CURRENT_SENSE | Flags::FAIL_SAFE));
    assert_eq!(cmd.current_a, cfg.law.failsafe_current_a);
    ctl.latch_fault(Flags::OVER_CURRENT);
    let cmd = ctl.step_sample(0.0, Some(0.0));
    assert_eq!(cmd.current_a, 0.0, "{:?}", cmd.flags);
}

/// The coil held at 1.5 A between impacts (rebound policy `Fixed`): the
/// coil is driven without an impact or a fault, so a sense channel that reads
/// nothing is plainly wrong. Returns the commands; `sense(k, coil_a)` gives
/// period k's reading (`coil_a`: the last command, what a healthy shunt reads).
const HELD_A: f32 = 1.5;
fn hold_the_coil(
    periods: usize,
    mut sense: impl FnMut(usize, f32) -> Option<Sense>,
) -> (ControlConfig, Vec<mre_algorithm::law::Command>) {
    let mut cfg = ControlConfig::at_rate(10_000).unwrap();
    cfg.law.rebound = mre_algorithm::law::ReboundPolicy::Fixed { current_a: HELD_A };
    let mut ctl = Controller::new(cfg, Table::paper()).unwrap();
    let mut coil_a = 0.0f32;
    let mut cmds = Vec::new();
    for k in 0..periods {
        ctl.check_coil_current(sense(k, coil_a));
        let cmd = ctl.step_sample(0.0, Some(0.0));
        ctl.end_period(false);
        coil_a = cmd.current_a;
        cmds.push(cmd);
    }
    (cfg, cmds)
}

#[test]
fn a_sense_channel_that_goes_stale_while_the_coil_is_driven_latches_current_sense() {
    // The shunt reads the coil for 30 periods, then no conversion arrives
    // (the trigger chain died) while the coil is driven.
    let dead_from = 30;
    let (cfg, cmds) = hold_the_coil(60, |k, coil_a| {
        Some(if k < dead_from {
            Sense::Fresh(coil_a)
        } else {
            Sense::Stale
        })
    });
    assert!(cmds[..dead_from].iter().all(|c| !c.flags.is_fault()));
    assert_eq!(
        cmds[dead_from - 1].current_a,
        HELD_A,
        "the coil is driven when the channel dies"
    );
    // Latched on the third stale period (dead_from, +1, +2), before its step.
    let latch_at = dead_from + usize::from(STALE_PERIODS) - 1;
    assert!(!cmds[latch_at - 1].flags.contains(Flags::CURRENT_SENSE));
    for c in &cmds[latch_at..] {
        assert!(
            c.flags.contains(Flags::CURRENT_SENSE | Flags::FAIL_SAFE),
            "{:?}",
            c.flags
        );
        // The damper keeps its stiff fail-safe: only over-current removes the drive.
        assert_eq!(c.current_a, cfg.law.failsafe_current_a);
    }
}

#[test]
fn a_sense_channel_stuck_near_zero_while_the_coil_is_driven_latches_current_sense() {
    // Fresh conversions that always read 0 A (an open amplifier input).
    let (cfg, cmds) = hold_the_coil(100, |_, _| Some(Sense::Fresh(0.0)));
    let latch_at = cmds
        .iter()
        .position(|c| c.flags.contains(Flags::CURRENT_SENSE))
        .expect("a stuck channel latches");
    // The first period checked with the coil driven ≥ 1 A follows the first
    // command ≥ 1 A (the slew limit ramps 0.2 A per period); STUCK_PERIODS
    // such periods in a row latch, before that period's step.
    let first_driven = cmds.iter().position(|c| c.current_a >= STUCK_DRIVEN_A).unwrap();
    assert_eq!(latch_at, first_driven + usize::from(STUCK_PERIODS));
    assert!(cmds[latch_at..]
        .iter()
        .all(|c| c.current_a == cfg.law.failsafe_current_a));
    // The same with a channel that reads the coil: no fault at all.
    let (_, cmds) = hold_the_coil(100, |_, coil_a| Some(Sense::Fresh(coil_a)));
    assert!(cmds.iter().all(|c| !c.flags.is_fault()));
    assert_eq!(cmds.last().unwrap().current_a, HELD_A);
    // And without a channel (None): nothing is checked.
    let (_, cmds) = hold_the_coil(100, |_, _| None);
    assert!(cmds.iter().all(|c| !c.flags.is_fault()));
}

#[test]
fn the_sense_monitor_counts_stale_and_stuck_periods_in_a_row() {
    let mut m = SenseMonitor::default();
    // Two stale periods, then a fresh one: the count restarts.
    for _ in 0..STALE_PERIODS - 1 {
        assert!(!m.check(Sense::Stale, 0.0).sense_dead);
    }
    assert!(!m.check(Sense::Fresh(0.0), 0.0).sense_dead);
    for _ in 0..STALE_PERIODS - 1 {
        assert!(!m.check(Sense::Stale, 0.0).sense_dead);
    }
    assert!(m.check(Sense::Stale, 0.0).sense_dead);
    // Stuck: needs the coil driven. At 0.5 A driven, a 0 A reading is fine
    // (half the 1 A threshold) for ever.
    let mut m = SenseMonitor::default();
    for _ in 0..1000 {
        assert_eq!(m.check(Sense::Fresh(0.0), 0.5), SenseVerdict::default());
    }
    // Driven at 2 A, read 0.1 A: latched on the 20th period, not the 19th.
    for _ in 0..STUCK_PERIODS - 1 {
        assert!(!m.check(Sense::Fresh(0.1), 2.0).sense_dead);
    }
    assert!(m.check(Sense::Fresh(0.1), 2.0).sense_dead);
    // A reading of 0.3 A (above 0.25 A) restarts it.
    let mut m = SenseMonitor::default();
    for _ in 0..STUCK_PERIODS - 1 {
        m.check(Sense::Fresh(0.1), 2.0);
    }
    assert!(!m.check(Sense::Fresh(0.3), 2.0).sense_dead);
    assert!(!m.check(Sense::Fresh(0.1), 2.0).sense_dead);
    // The over-current verdict is the same debounced monitor as before.
    let mut m = SenseMonitor::default();
    assert!(!m.check(Sense::Fresh(3.0), 2.0).over_current);
    assert!(!m.check(Sense::Fresh(3.0), 2.0).over_current);
    assert!(m.check(Sense::Fresh(3.0), 2.0).over_current);
}

#[test]
fn frames_carry_the_coil_current_and_the_over_current_flag() {
    let s = SampleFrame {
        seq: 7,
        x_mm: 1.0,
        v_m_s: Some(0.5),
        force_n: None,
        coil_current_a: Some(2.75),
    };
    assert_eq!(SampleFrame::decode(&s.encode()).unwrap(), s);
    // The byte layout: present bits 0 and 2, the current in bytes 16..20.
    let b = s.encode();
    assert_eq!(b[3], 0b101);
    assert_eq!(f32::from_le_bytes([b[16], b[17], b[18], b[19]]), 2.75);
    // A frame from before the coil current: bit 2 clear, force in its slot.
    let old = SampleFrame {
        coil_current_a: None,
        force_n: Some(900.0),
        ..s
    };
    assert_eq!(SampleFrame::decode(&old.encode()).unwrap(), old);
    assert_eq!(old.encode()[3], 0b011);

    let c = CommandFrame {
        seq: 7,
        current_a: 2.0,
        target_force_n: 0.0,
        flags: Flags::OVER_CURRENT | Flags::FAIL_SAFE,
        rejected: 0,
    };
    let cb = c.encode();
    assert_eq!(CommandFrame::decode(&cb).unwrap(), c);
    // Bit 16 in byte 3; bits 0..16 where they always were (bit 8 = FAIL_SAFE).
    assert_eq!(cb[3], 0x01);
    assert_eq!(u16::from_le_bytes([cb[16], cb[17]]), 1 << 8);
}
