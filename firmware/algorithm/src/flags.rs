//! Status and fault flags shared by the model, the inverse, the law and the
//! control loop. A plain bit set so it fits in a PIL frame and a defmt log.

/// A set of status bits. `Flags::NONE` means a clean, in-range result.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Flags(pub u32);

impl Flags {
    pub const NONE: Flags = Flags(0);
    /// Displacement was outside the fitted stroke and was clamped to it.
    pub const X_CLAMPED: Flags = Flags(1 << 0);
    /// Current was outside the table's range and was clamped to it.
    pub const CURRENT_CLAMPED: Flags = Flags(1 << 1);
    /// The requested force is above every reachable force (nearest returned).
    pub const SATURATED_HIGH: Flags = Flags(1 << 2);
    /// The requested force is below every reachable force (nearest returned).
    pub const SATURATED_LOW: Flags = Flags(1 << 3);
    /// An input was NaN or infinite; a safe value was used instead.
    pub const NON_FINITE_INPUT: Flags = Flags(1 << 4);
    /// A sensor value was outside its plausible range.
    pub const SENSOR_RANGE: Flags = Flags(1 << 5);
    /// The remaining stroke is used up: the law commands its maximum.
    pub const STROKE_EXHAUSTED: Flags = Flags(1 << 6);
    /// The command was limited by the slew-rate limit.
    pub const SLEW_LIMITED: Flags = Flags(1 << 7);
    /// The controller is in its fail-safe state (fail-safe current commanded).
    pub const FAIL_SAFE: Flags = Flags(1 << 8);
    /// The command was limited by the output clamp.
    pub const OUTPUT_CLAMPED: Flags = Flags(1 << 9);
    /// The mass is rebounding (v ≤ 0); the rebound policy set the command.
    pub const REBOUND: Flags = Flags(1 << 10);
    /// A sensor reading has not changed for too long.
    pub const SENSOR_STUCK: Flags = Flags(1 << 11);
    /// Control periods overran their deadline repeatedly.
    pub const OVERRUN: Flags = Flags(1 << 12);
    /// The coefficient table failed validation or its CRC.
    pub const TABLE_FAULT: Flags = Flags(1 << 13);
    /// A PIL frame was corrupt or out of order.
    pub const FRAME_FAULT: Flags = Flags(1 << 14);
    /// The velocity sensor and the displacement-based estimate disagree for
    /// too long: one of the two sensors is lying.
    pub const SENSOR_DISAGREE: Flags = Flags(1 << 15);
    /// The coil current measured by the shunt exceeded the coil's rating
    /// (`mre_algorithm::overcurrent`). Bits 16.. travel in the command frame's
    /// byte 3 (`frame`).
    pub const OVER_CURRENT: Flags = Flags(1 << 16);
    /// The current-sense channel is dead: no new conversion for
    /// `overcurrent::STALE_PERIODS` periods, or a reading stuck near 0 A while
    /// the coil is driven (`mre_algorithm::overcurrent::SenseMonitor`). Over-current
    /// protection is blind, so this is a fault of its own.
    pub const CURRENT_SENSE: Flags = Flags(1 << 17);

    /// Flags that mean the inputs or the system cannot be trusted.
    pub const FAULTS: Flags = Flags(
        Self::NON_FINITE_INPUT.0
            | Self::SENSOR_RANGE.0
            | Self::SENSOR_STUCK.0
            | Self::OVERRUN.0
            | Self::TABLE_FAULT.0
            | Self::FRAME_FAULT.0
            | Self::SENSOR_DISAGREE.0
            | Self::OVER_CURRENT.0
            | Self::CURRENT_SENSE.0,
    );

    #[inline]
    pub const fn contains(self, other: Flags) -> bool {
        self.0 & other.0 == other.0
    }

    #[inline]
    pub const fn intersects(self, other: Flags) -> bool {
        self.0 & other.0 != 0
    }

    #[inline]
    pub const fn union(self, other: Flags) -> Flags {
        Flags(self.0 | other.0)
    }

    #[inline]
    pub const fn is_fault(self) -> bool {
        self.intersects(Self::FAULTS)
    }

    #[inline]
    pub fn insert(&mut self, other: Flags) {
        self.0 |= other.0;
    }
}

impl core::ops::BitOr for Flags {
    type Output = Flags;
    #[inline]
    fn bitor(self, rhs: Flags) -> Flags {
        self.union(rhs)
    }
}

impl core::ops::BitOrAssign for Flags {
    #[inline]
    fn bitor_assign(&mut self, rhs: Flags) {
        self.insert(rhs);
    }
}
