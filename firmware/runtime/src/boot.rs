//! Boot facts decoded from raw register values, so the decoding is tested on
//! the host: why the chip reset (STM32L4 `RCC_CSR`, RM0351's "Control/status
//! register (RCC_CSR)" in the RCC chapter; flag bits 24..31 as in ST's CMSIS
//! `stm32l475xx.h`), and what the board does first about it ([`BootPlan`],
//! firmware/README.md "Reset paths").

/// The reset cause, most specific first (NRST pulses on every reset, so
/// `PINRSTF` accompanies the others and only counts alone).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResetCause {
    /// The independent watchdog fired: the control loop stalled.
    IndependentWatchdog,
    WindowWatchdog,
    LowPower,
    /// `SYSRESETREQ` (a debugger's reset, or the firmware's own).
    Software,
    /// Brown-out or power-on.
    BrownOutOrPowerOn,
    OptionByteLoader,
    Firewall,
    /// The reset button or the probe's NRST.
    Pin,
    Unknown,
}

impl ResetCause {
    /// Decodes `RCC_CSR` (bits 31..24: LPWR, WWDG, IWDG, SFT, BOR, PIN, OBL, FW).
    pub fn from_rcc_csr(csr: u32) -> Self {
        let bit = |n: u32| csr & (1 << n) != 0;
        if bit(29) {
            Self::IndependentWatchdog
        } else if bit(30) {
            Self::WindowWatchdog
        } else if bit(31) {
            Self::LowPower
        } else if bit(28) {
            Self::Software
        } else if bit(27) {
            Self::BrownOutOrPowerOn
        } else if bit(25) {
            Self::OptionByteLoader
        } else if bit(24) {
            Self::Firewall
        } else if bit(26) {
            Self::Pin
        } else {
            Self::Unknown
        }
    }

    /// A reset the firmware should warn about: the loop or the supply failed.
    pub fn is_fault(self) -> bool {
        matches!(
            self,
            Self::IndependentWatchdog | Self::WindowWatchdog | Self::BrownOutOrPowerOn | Self::Firewall
        )
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::IndependentWatchdog => "independent watchdog",
            Self::WindowWatchdog => "window watchdog",
            Self::LowPower => "low-power",
            Self::Software => "software",
            Self::BrownOutOrPowerOn => "brown-out / power-on",
            Self::OptionByteLoader => "option byte loader",
            Self::Firewall => "firewall",
            Self::Pin => "NRST pin",
            Self::Unknown => "unknown",
        }
    }
}

/// The first coil command after the pin's safe level in `pre_init`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FirstCommand {
    /// The fail-safe duty as soon as TIM3 runs (before any calibration).
    FailSafeAtOnce,
    /// The coil stays off (0 % duty) through VDDA and current-sense
    /// calibration (~3.5 ms), then the fail-safe duty.
    FailSafeAfterCalibration,
}

/// When VDDA and the current-sense zero are measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CalibrationTime {
    /// At boot, with the coil off.
    AtBoot,
    /// In the control loop, once the damper is at rest with the coil
    /// commanded off ([`crate::calibration::DeferredSenseZero`]); nominal
    /// VDDA and a zero offset until then.
    DeferredUntilAtRest,
}

/// What the board does first after a reset of a given cause.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BootPlan {
    pub first: FirstCommand,
    pub calibration: CalibrationTime,
}

impl ResetCause {
    /// The decision table (firmware/README.md, "Reset paths"). Only a reset
    /// by the NRST pin alone (the button or the probe: a person at the bench)
    /// may calibrate before the fail-safe. Every other cause may strike
    /// mid-impact: watchdog (the loop hung), software, window watchdog,
    /// firewall, low-power, option bytes, unknown, and brown-out. A cold
    /// power-on also sets `BORRSTF` (RCC_CSR reads 0x0C00_0600 after it) and
    /// cannot be told from a brown-out, so it takes the safe path too.
    pub fn boot_plan(self) -> BootPlan {
        match self {
            Self::Pin => BootPlan {
                first: FirstCommand::FailSafeAfterCalibration,
                calibration: CalibrationTime::AtBoot,
            },
            _ => BootPlan {
                first: FirstCommand::FailSafeAtOnce,
                calibration: CalibrationTime::DeferredUntilAtRest,
            },
        }
    }
}

/// The fail-safe current (A) from reset until the installed configuration
/// is known: the default fail-safe, but never above the weakest coil the
/// board's limits let an upload install (`limits::STM32L4_BOARD`,
/// `installation_min.coil_rating_a`): an installed 1 A coil is not driven
/// at the default's 2 A while the table page is still unread.
pub const BOOT_FAILSAFE_CURRENT_A: f32 = {
    let default = mre_algorithm::law::LawConfig::DEFAULT_FAILSAFE_CURRENT_A;
    let weakest = mre_algorithm::limits::STM32L4_BOARD.installation_min.coil_rating_a;
    if default < weakest {
        default
    } else {
        weakest
    }
};

/// The coil command a panic or HardFault handler sets before it halts
/// (firmware/README.md, "Panic and HardFault"). One decision for every board;
/// the register writes are the board's (`board::coil_safe_from_a_fault`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CoilAfterFault {
    /// The fail-safe current (stiffest damper) through the running drive.
    FailSafe { current_a: f32 },
    /// Drive removed: the pin at its reset-safe low level (0 A).
    Off,
}

/// The safe coil command after a fault. `drive_running`: the coil drive (TIM3
/// PWM on the pin) had been started by `init`; before that only the pin's low
/// level exists. `latched`: the faults the control task had latched. A
/// latched over-current keeps the drive removed, as in the loop
/// (`mre_algorithm::overcurrent`); otherwise a running drive holds the fail-safe.
pub fn coil_after_fault(drive_running: bool, latched: mre_algorithm::Flags, failsafe_current_a: f32) -> CoilAfterFault {
    if drive_running && !latched.contains(mre_algorithm::Flags::OVER_CURRENT) {
        CoilAfterFault::FailSafe {
            current_a: failsafe_current_a,
        }
    } else {
        CoilAfterFault::Off
    }
}

/// The power-on self-test before the controller arms (class-B practice):
/// the board's current sense converts, its PWM duty reads back, and the
/// flown table's CRC holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SelfTest {
    /// An injected conversion of the shunt ended (ADC3 JEOC) at boot.
    pub sense_converts: bool,
    /// TIM3 runs with CH1 on the pin and CCR1 holds the commanded duty.
    pub pwm_reads_back: bool,
    /// The flown table (uploaded or built-in) passed its CRC and validation.
    pub table_crc_holds: bool,
}

impl SelfTest {
    pub fn passed(&self) -> bool {
        self.sense_converts && self.pwm_reads_back && self.table_crc_holds
    }

    /// The faults latched before the first period when a check fails, so
    /// the controller never arms and holds the fail-safe current: a sense
    /// that does not convert or a drive that does not read back is
    /// `CURRENT_SENSE` (the coil current cannot be trusted), a table that
    /// fails its CRC `TABLE_FAULT`. Neither clears with B1
    /// (`Controller::latch_boot_faults`).
    pub fn faults(&self) -> mre_algorithm::Flags {
        let mut f = mre_algorithm::Flags::NONE;
        if !self.sense_converts || !self.pwm_reads_back {
            f |= mre_algorithm::Flags::CURRENT_SENSE;
        }
        if !self.table_crc_holds {
            f |= mre_algorithm::Flags::TABLE_FAULT;
        }
        f
    }

    /// The first failed check, for the one boot-failure log line.
    pub fn first_failure(&self) -> Option<&'static str> {
        if !self.sense_converts {
            Some("current sense does not convert")
        } else if !self.pwm_reads_back {
            Some("PWM duty does not read back")
        } else if !self.table_crc_holds {
            Some("table CRC does not hold")
        } else {
            None
        }
    }
}
