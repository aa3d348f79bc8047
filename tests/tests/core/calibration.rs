//! Boot calibration: VDDA from VREFINT, and sensor zeros at rest.
use mre_runtime::calibration::{rest_offset, vdda_v, CalError, RestLimits, V_REST, X_REST};

#[test]
fn vdda_follows_the_reference_reading() {
    // VREFINT is 1.212 V typ.; the factory reads it at VDDA = 3.0 V:
    // 1.212/3.0 · 4095 = 1654. At VDDA = 3.3 V the same reference reads
    // 1.212/3.3 · 4095 = 1504.
    let cal = 1654;
    let vdda = vdda_v(1504, cal).unwrap();
    assert!((vdda - 3.0 * 1654.0 / 1504.0).abs() < 1e-6);
    assert!((vdda - 3.3).abs() < 0.01, "{vdda}");
}

#[test]
fn implausible_vdda_and_missing_readings_are_refused() {
    // A reading as if VDDA were 2.5 V: 1.212/2.5 · 4095 = 1985.
    assert!(matches!(vdda_v(1985, 1654), Err(CalError::OutOfRange(v)) if (v - 2.5).abs() < 0.01));
    assert_eq!(vdda_v(0, 1654), Err(CalError::NoData));
    assert_eq!(vdda_v(1504, 0), Err(CalError::NoData));
}

#[test]
fn a_resting_sensor_gives_its_offset() {
    // x reads 0.40 ± 0.05 mm at rest: offset 0.40 mm.
    let samples = [0.35, 0.45, 0.40, 0.40];
    let offset = rest_offset(&samples, 0.0, X_REST).unwrap();
    assert!((offset - 0.40).abs() < 1e-6, "{offset}");
    // Velocity zero against 0 m/s.
    assert!((rest_offset(&[0.1, 0.1], 0.0, V_REST).unwrap() - 0.1).abs() < 1e-6);
}

#[test]
fn moving_offset_or_broken_sensors_are_refused() {
    let limits = RestLimits {
        max_offset: 1.0,
        max_spread: 0.2,
    };
    // Moving: 0 → 0.5 mm during calibration.
    assert!(matches!(
        rest_offset(&[0.0, 0.25, 0.5], 0.0, limits),
        Err(CalError::NotAtRest { spread }) if (spread - 0.5).abs() < 1e-6
    ));
    // Steady but 2 mm off: a mounting error too large to trust.
    assert_eq!(rest_offset(&[2.0, 2.0], 0.0, limits), Err(CalError::OutOfRange(2.0)));
    // A broken wire reads the rail (−2.8 mm): refused.
    assert!(rest_offset(&[-2.8; 8], 0.0, limits).is_err());
    assert_eq!(rest_offset(&[], 0.0, limits), Err(CalError::NoData));
    assert_eq!(rest_offset(&[0.1, f32::NAN], 0.0, limits), Err(CalError::NoData));
}
