//! Reset-cause decoding of STM32L4 RCC_CSR values (RM0351's "Control/status register (RCC_CSR)").
use mre_runtime::boot::ResetCause;

/// RCC_CSR flag bits, from the reference manual.
const LPWRRSTF: u32 = 1 << 31;
const IWDGRSTF: u32 = 1 << 29;
const SFTRSTF: u32 = 1 << 28;
const BORRSTF: u32 = 1 << 27;
const PINRSTF: u32 = 1 << 26;
/// MSIRANGE after reset (bits 11:8 = 6), present in every real read.
const MSI_BITS: u32 = 6 << 8;

#[test]
fn watchdog_resets_are_told_apart_from_the_pin_that_accompanies_them() {
    assert_eq!(
        ResetCause::from_rcc_csr(IWDGRSTF | PINRSTF | MSI_BITS),
        ResetCause::IndependentWatchdog
    );
    assert!(ResetCause::IndependentWatchdog.is_fault());
}

#[test]
fn power_on_software_pin_and_low_power_resets() {
    // The documented reset value of RCC_CSR after power-on: 0x0C00_0600.
    assert_eq!(0x0C00_0600, BORRSTF | PINRSTF | MSI_BITS);
    assert_eq!(ResetCause::from_rcc_csr(0x0C00_0600), ResetCause::BrownOutOrPowerOn);
    assert_eq!(
        ResetCause::from_rcc_csr(SFTRSTF | PINRSTF | MSI_BITS),
        ResetCause::Software
    );
    assert_eq!(ResetCause::from_rcc_csr(PINRSTF | MSI_BITS), ResetCause::Pin);
    assert_eq!(ResetCause::from_rcc_csr(LPWRRSTF | PINRSTF), ResetCause::LowPower);
    assert_eq!(ResetCause::from_rcc_csr(MSI_BITS), ResetCause::Unknown);
    assert!(!ResetCause::Pin.is_fault());
}

mod boot_plan {
    use super::*;
    use mre_runtime::boot::{BootPlan, CalibrationTime, FirstCommand};

    const SAFE_AT_ONCE: BootPlan = BootPlan {
        first: FirstCommand::FailSafeAtOnce,
        calibration: CalibrationTime::DeferredUntilAtRest,
    };

    #[test]
    fn every_reset_that_can_strike_mid_impact_commands_the_fail_safe_at_once() {
        // The list: watchdog, fault, brown-out, software; and the
        // power-on value, which carries BORRSTF and cannot be told apart.
        for csr in [
            IWDGRSTF | PINRSTF | MSI_BITS,
            1 << 30 | PINRSTF, // WWDG
            SFTRSTF | PINRSTF | MSI_BITS,
            BORRSTF | PINRSTF | MSI_BITS, // brown-out, and power-on (0x0C00_0600)
            LPWRRSTF | PINRSTF,
            1 << 25 | PINRSTF, // option byte loader
            1 << 24 | PINRSTF, // firewall
            0,                 // no flag at all: unknown
        ] {
            let cause = ResetCause::from_rcc_csr(csr);
            assert_eq!(cause.boot_plan(), SAFE_AT_ONCE, "RCC_CSR {csr:#010x}: {cause:?}");
        }
    }

    #[test]
    fn only_the_reset_pin_alone_calibrates_before_the_fail_safe() {
        let plan = ResetCause::from_rcc_csr(PINRSTF | MSI_BITS).boot_plan();
        assert_eq!(plan.first, FirstCommand::FailSafeAfterCalibration);
        assert_eq!(plan.calibration, CalibrationTime::AtBoot);
    }
}

mod deferred_sense_zero {
    use mre_runtime::calibration::{CalError, DeferredSenseZero, DEFERRED_SAMPLES, DEFERRED_SETTLE_PERIODS};

    #[test]
    fn the_zero_is_taken_only_after_the_coil_settled_off_at_rest() {
        let mut z = DeferredSenseZero::default();
        // 5 ms of the coil off at rest first: nothing is sampled.
        for _ in 0..DEFERRED_SETTLE_PERIODS {
            assert_eq!(z.push(true, 0.0, 0.04), None);
        }
        // Then 64 conversions around 0.04 A of amplifier offset.
        for k in 0..DEFERRED_SAMPLES - 1 {
            assert_eq!(z.push(true, 0.0, 0.04 + 0.001 * (k % 3) as f32), None);
        }
        let offset = z.push(true, 0.0, 0.041).unwrap().unwrap();
        assert!((offset - 0.041).abs() < 1.0e-3, "{offset}");
    }

    #[test]
    fn an_impact_or_a_driven_coil_restarts_the_collection() {
        let mut z = DeferredSenseZero::default();
        let settle_and_take = |z: &mut DeferredSenseZero, n: usize| {
            for _ in 0..DEFERRED_SETTLE_PERIODS as usize + n {
                assert_eq!(z.push(true, 0.0, 0.0), None);
            }
        };
        settle_and_take(&mut z, DEFERRED_SAMPLES - 1);
        // The coil is driven for one period (0.5 A): start again.
        assert_eq!(z.push(true, 0.5, 0.5), None);
        settle_and_take(&mut z, DEFERRED_SAMPLES - 1);
        // An impact (not at rest): start again.
        assert_eq!(z.push(false, 0.0, 0.0), None);
        settle_and_take(&mut z, DEFERRED_SAMPLES - 1);
        assert_eq!(z.push(true, 0.0, 0.0), Some(Ok(0.0)));
        // A zero at 0.2 A is refused (the amplifier is wrong), as at boot.
        let mut z = DeferredSenseZero::default();
        for _ in 0..DEFERRED_SETTLE_PERIODS as usize + DEFERRED_SAMPLES - 1 {
            z.push(true, 0.0, 0.2);
        }
        assert!(matches!(z.push(true, 0.0, 0.2), Some(Err(CalError::OutOfRange(_)))));
    }
}

/// The panic/HardFault decision (firmware/README.md, "Panic and HardFault"):
/// a running drive holds the 2 A fail-safe (the stiffest damper, the paper's
/// highest table current), a drive not yet started stays off (the pin low
/// is all a bare GPIO holds), and a latched over-current keeps the drive
/// removed whatever else is latched.
mod coil_after_a_fault {
    use mre_algorithm::Flags;
    use mre_runtime::boot::{coil_after_fault, CoilAfterFault};

    const FAILSAFE_A: f32 = 2.0;

    #[test]
    fn a_running_drive_holds_the_failsafe_current() {
        for latched in [
            Flags::NONE,
            Flags::SENSOR_STUCK,
            Flags::CURRENT_SENSE,
            Flags::TABLE_FAULT,
        ] {
            assert_eq!(
                coil_after_fault(true, latched, FAILSAFE_A),
                CoilAfterFault::FailSafe { current_a: 2.0 },
                "{latched:?}"
            );
        }
    }

    #[test]
    fn before_the_drive_runs_the_coil_stays_off() {
        assert_eq!(coil_after_fault(false, Flags::NONE, FAILSAFE_A), CoilAfterFault::Off);
    }

    #[test]
    fn a_latched_over_current_keeps_the_drive_removed() {
        for latched in [Flags::OVER_CURRENT, Flags::OVER_CURRENT | Flags::SENSOR_STUCK] {
            assert_eq!(coil_after_fault(true, latched, FAILSAFE_A), CoilAfterFault::Off);
            assert_eq!(coil_after_fault(false, latched, FAILSAFE_A), CoilAfterFault::Off);
        }
    }
}
