//! The over-current fault (`mre_core::overcurrent`), the current-sense zero
//! at boot, and the fault's path into the controller's fail-safe.
use mre_core::calibration::{rest_offset, CalError, I_SENSE_REST};
use mre_core::control::{ControlConfig, Controller};
use mre_core::frame::{CommandFrame, SampleFrame};
use mre_core::law::LawConfig;
use mre_core::overcurrent::{OverCurrent, COIL_RATING_A, TRIP_A, TRIP_SAMPLES};
use mre_core::table::Table;
use mre_core::Flags;

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
fn a_latched_over_current_commands_the_fail_safe_until_cleared_at_rest() {
    let cfg = ControlConfig::at_rate(10_000).unwrap();
    let mut ctl = Controller::new(cfg, Table::paper()).unwrap();
    // At rest: 0 mm, not moving.
    let before = ctl.step_sample(0.0, Some(0.0));
    ctl.end_period(false);
    assert!(!before.flags.contains(Flags::FAIL_SAFE));
    ctl.latch_fault(Flags::OVER_CURRENT);
    let cmd = ctl.step_sample(0.0, Some(0.0));
    ctl.end_period(false);
    assert!(
        cmd.flags.contains(Flags::OVER_CURRENT | Flags::FAIL_SAFE),
        "{:?}",
        cmd.flags
    );
    assert_eq!(cmd.current_a, cfg.law.failsafe_current_a);
    assert_eq!(ctl.stats().fault_latches, 1);
    // B1 at rest clears it.
    assert!(ctl.clear_faults_if_at_rest());
    let after = ctl.step_sample(0.0, Some(0.0));
    assert!(!after.flags.intersects(Flags::OVER_CURRENT | Flags::FAIL_SAFE));
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
