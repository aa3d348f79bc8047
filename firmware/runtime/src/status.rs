//! What the status LED shows, as a pure function of the latched faults and
//! a 50 ms slot counter, so the pattern is tested on the host:
//! - no fault: a 50 ms heartbeat flash once a second;
//! - a latched fault: its blink code (1–9 flashes of 100 ms, 100 ms apart)
//!   at the start of every 2 s cycle. The most serious fault is shown.
use mre_algorithm::flags::Flags;

/// The board updates the LED every slot.
pub const SLOT_MS: u32 = 50;
/// 2 s: room for 9 flashes (1.8 s) and a pause that separates the codes.
const CYCLE_SLOTS: u32 = 40;
const HEARTBEAT_SLOTS: u32 = 1000 / SLOT_MS;

/// Blink codes, most serious first (firmware/README.md, "Bench").
const CODES: [(Flags, u32); 9] = [
    // Shown first: the coil or its driver may be damaged.
    (Flags::OVER_CURRENT, 8),
    // Next: over-current protection is blind.
    (Flags::CURRENT_SENSE, 9),
    (Flags::TABLE_FAULT, 1),
    (Flags::SENSOR_RANGE, 2),
    (Flags::NON_FINITE_INPUT, 3),
    (Flags::SENSOR_STUCK, 4),
    (Flags::SENSOR_DISAGREE, 5),
    (Flags::OVERRUN, 6),
    (Flags::FRAME_FAULT, 7),
];

/// The number of flashes for `latched` (0: no fault, heartbeat).
pub fn blink_code(latched: Flags) -> u32 {
    CODES
        .iter()
        .find(|(flag, _)| latched.intersects(*flag))
        .map_or(0, |&(_, code)| code)
}

/// LED state in slot `slot` (counts up every `SLOT_MS`).
pub fn led_on(latched: Flags, slot: u32) -> bool {
    match blink_code(latched) {
        0 => slot.is_multiple_of(HEARTBEAT_SLOTS),
        code => {
            let k = slot % CYCLE_SLOTS;
            k < code.saturating_mul(4) && k % 4 < 2
        }
    }
}
