//! Status LED patterns and the button's fault clear at rest.
use mre_algorithm::control::{ControlConfig, Controller};
use mre_algorithm::table::Table;
use mre_algorithm::Flags;
use mre_runtime::status::{blink_code, led_on, SLOT_MS};

/// Rising edges of the LED over `slots` slots from 0.
fn flashes(latched: Flags, slots: u32) -> u32 {
    (0..slots)
        .filter(|&k| led_on(latched, k) && (k == 0 || !led_on(latched, k - 1)))
        .count() as u32
}

#[test]
fn no_fault_is_a_one_hertz_heartbeat() {
    let ten_s = 10_000 / SLOT_MS;
    assert_eq!(flashes(Flags::NONE, ten_s), 10);
    // Each flash is one 50 ms slot: on 10 of 200 slots.
    assert_eq!((0..ten_s).filter(|&k| led_on(Flags::NONE, k)).count(), 10);
    // Status bits that are not faults do not change it.
    assert_eq!(flashes(Flags::REBOUND | Flags::SLEW_LIMITED, ten_s), 10);
}

#[test]
fn a_fault_blinks_its_code_every_two_seconds() {
    let two_s = 2_000 / SLOT_MS;
    for (flag, code) in [
        (Flags::TABLE_FAULT, 1),
        (Flags::SENSOR_RANGE, 2),
        (Flags::NON_FINITE_INPUT, 3),
        (Flags::SENSOR_STUCK, 4),
        (Flags::SENSOR_DISAGREE, 5),
        (Flags::OVERRUN, 6),
        (Flags::FRAME_FAULT, 7),
        (Flags::OVER_CURRENT, 8),
        (Flags::CURRENT_SENSE, 9),
    ] {
        assert_eq!(blink_code(flag), code);
        assert_eq!(flashes(flag, two_s), code, "{flag:?}");
        // The same count in every cycle.
        assert_eq!(flashes(flag, 5 * two_s), 5 * code, "{flag:?}");
        // The cycle ends dark, so codes are told apart.
        assert!(!led_on(flag, two_s - 1));
    }
    // The most serious fault wins.
    assert_eq!(blink_code(Flags::OVERRUN | Flags::SENSOR_RANGE), 2);
    // Over-current is shown before everything (the hardware may be damaged).
    assert_eq!(blink_code(Flags::OVER_CURRENT | Flags::TABLE_FAULT), 8);
    // Then a dead sense channel (over-current protection is blind).
    assert_eq!(blink_code(Flags::CURRENT_SENSE | Flags::TABLE_FAULT), 9);
    assert_eq!(blink_code(Flags::CURRENT_SENSE | Flags::OVER_CURRENT), 8);
}

fn controller() -> Controller {
    Controller::new(ControlConfig::at_rate(10_000).unwrap(), Table::paper()).unwrap()
}

#[test]
fn the_button_clears_a_fault_only_at_rest() {
    // Latch SENSOR_RANGE with x beyond the valid range.
    let mut c = controller();
    for _ in 0..10 {
        c.step_sample(30.0, None);
    }
    assert_eq!(c.latched(), Flags::SENSOR_RANGE);
    // Mid-stroke and moving (x falls 0.1 mm per period: 1 m/s): refused.
    for k in 0..20 {
        c.step_sample(10.0 - 0.1 * k as f32, None);
    }
    assert!(!c.clear_faults_if_at_rest());
    assert_eq!(c.latched(), Flags::SENSOR_RANGE);
    // Back at rest at 0 mm: cleared.
    for _ in 0..200 {
        c.step_sample(0.0, None);
    }
    assert!(c.clear_faults_if_at_rest());
    assert_eq!(c.latched(), Flags::NONE);
    // A table fault is not the button's to clear.
    let mut bad = mre_algorithm::table::PAPER_TABLE4;
    bad.crc32 ^= 1;
    let mut c = Controller::new(ControlConfig::at_rate(10_000).unwrap(), Table::from_image(&bad)).unwrap();
    c.step_sample(0.0, None);
    c.step_sample(0.0, None);
    c.clear_faults_if_at_rest();
    assert!(c.latched().contains(Flags::TABLE_FAULT));
}
