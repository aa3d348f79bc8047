//! Reset-cause decoding of STM32L4 RCC_CSR values (RM0351 §6.4.29).
use mre_core::boot::ResetCause;

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
