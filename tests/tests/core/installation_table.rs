//! Format 3 tables carry the installation under their CRC, and the board
//! derives its law and fault configuration from it within its hard limits.
//! Older formats still load, with `DEFAULT_INSTALLATION`.
use mre_algorithm::control::{ControlConfig, DEFAULT_RATE_HZ};
use mre_algorithm::installation::{Installation, DEFAULT_INSTALLATION, FIELD_COUNT};
use mre_algorithm::table::{
    CurrentEntry, ModelTerms, Quartic, Table, TableError, TableImage, FORMAT_VERSION_1, FORMAT_VERSION_2,
    FORMAT_VERSION_3,
};
use mre_protocol::flash_table::RamPage;
use mre_protocol::frame::{decode_config, encode_config, ConfigBlobError, CONFIG_MAX_WORDS};
use mre_protocol::upload::{choose_boot_table, installed_config, TableSource};

/// A lab's rig within the board's limits: a 3 kg striker, 9 mm of stroke,
/// a 1.5 A coil, impacts of 1–3 m/s.
const LAB: Installation = Installation {
    mass_kg: 3.0,
    usable_stroke_mm: 9.0,
    coil_rating_a: 1.5,
    coil_resistance_ohm: 4.0,
    supply_v: 12.0,
    x_sensor_range_mm: 25.0,
    v_sensor_full_scale_m_s: 5.0,
    impact_v_min_m_s: 1.0,
    impact_v_max_m_s: 3.0,
};

fn entries() -> [CurrentEntry; 2] {
    let entry = |current_a: f32, k: f32| CurrentEntry {
        current_a,
        compression: Quartic::new([0.0, 0.0, 0.0, k, 0.0]),
        extension: Quartic::new([0.0, 0.0, 0.0, 0.5 * k, 0.0]),
        x_min_mm: 0.0,
        x_max_mm: 15.0,
    };
    [entry(0.0, 100.0), entry(2.0, 900.0)]
}

fn blob(table: &Table, cfg: &ControlConfig) -> Vec<u32> {
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(table, cfg, &mut words);
    words[..n].to_vec()
}

fn lab_config() -> ControlConfig {
    let mut cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    LAB.apply(&mut cfg);
    cfg
}

#[test]
fn a_format_3_image_round_trips_with_every_installation_value() {
    let table = Table::with_installation(&entries(), ModelTerms::EVERY_TERM, LAB).unwrap();
    assert_eq!(table.version(), FORMAT_VERSION_3);
    let back = Table::from_image(&table.image()).unwrap();
    assert_eq!(back, table);
    assert_eq!(back.installation().to_array(), LAB.to_array());
    // Through the upload blob too.
    let (decoded, cfg) = decode_config(&blob(&table, &lab_config())).unwrap();
    assert_eq!(decoded, table);
    assert_eq!(cfg, lab_config());
}

#[test]
fn every_installation_value_is_under_the_crc() {
    let table = Table::with_installation(&entries(), ModelTerms::NONE, LAB).unwrap();
    for k in 0..FIELD_COUNT {
        let mut values = LAB.to_array();
        values[k] = f32::from_bits(values[k].to_bits() ^ 1);
        let image = TableImage {
            installation: Installation::from_array(values),
            ..table.image()
        };
        assert!(
            matches!(Table::from_image(&image), Err(TableError::CrcMismatch { .. })),
            "{} changed but the CRC still matched",
            Installation::FIELD_NAMES[k]
        );
    }
    // A corrupted installation word in an upload fails the table's CRC as well.
    let mut words = blob(&table, &lab_config());
    let installation_at = 2 + 13 * 2 + 3 + 2; // header, entries, terms (format 2 on)
    assert_eq!(words[installation_at], 3.0f32.to_bits(), "mass_kg is the first value");
    words[installation_at] = 3.5f32.to_bits();
    assert!(matches!(
        decode_config(&words),
        Err(ConfigBlobError::Table(TableError::CrcMismatch { .. }))
    ));
}

#[test]
fn older_formats_load_with_the_default_installation_and_may_not_claim_another() {
    let v1 = Table::new(&entries()).unwrap();
    let v2 = Table::with_terms(&entries(), ModelTerms::EVERY_TERM).unwrap();
    for (old, version) in [(v1, FORMAT_VERSION_1), (v2, FORMAT_VERSION_2)] {
        assert_eq!(old.version(), version);
        assert_eq!(old.installation(), &DEFAULT_INSTALLATION);
        assert_eq!(Table::from_image(&old.image()).unwrap(), old);
        let claiming = TableImage {
            installation: LAB,
            ..old.image()
        };
        assert!(matches!(
            Table::from_image(&claiming),
            Err(TableError::BadInstallation { .. })
        ));
        // Boot from an older built-in image: today's defaults, unchanged.
        let boot = choose_boot_table(&mut RamPage::erased(), &old.image(), DEFAULT_RATE_HZ);
        assert_eq!(boot.config.unwrap(), ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap());
    }
}

#[test]
fn an_impossible_installation_is_refused_by_name() {
    let cases = [
        ("mass_kg", Installation { mass_kg: 0.0, ..LAB }),
        (
            "usable_stroke_mm",
            Installation {
                usable_stroke_mm: f32::NAN,
                ..LAB
            },
        ),
        ("supply_v", Installation { supply_v: -12.0, ..LAB }),
        (
            "impact_v_max_m_s",
            Installation {
                impact_v_max_m_s: f32::INFINITY,
                ..LAB
            },
        ),
        // Slowest above fastest.
        (
            "impact_v_min_m_s",
            Installation {
                impact_v_min_m_s: 3.5,
                ..LAB
            },
        ),
    ];
    for (field, bad) in cases {
        assert_eq!(
            Table::with_installation(&entries(), ModelTerms::NONE, bad),
            Err(TableError::BadInstallation { field }),
        );
    }
}

#[test]
fn the_built_in_installation_sets_the_board_s_law_and_fault_configuration() {
    let table = Table::with_installation(&entries(), ModelTerms::NONE, LAB).unwrap();
    let boot = choose_boot_table(&mut RamPage::erased(), &table.image(), DEFAULT_RATE_HZ);
    assert!(matches!(boot.source, TableSource::BuiltIn(_)));
    let cfg = boot.config.unwrap();
    // Values written from LAB above, not read back from the code.
    assert_eq!(cfg.law.mass_kg, 3.0);
    assert_eq!(cfg.law.stroke_max_mm, 9.0);
    assert_eq!(cfg.law.current_max_a, 1.5);
    // The fail-safe (2 A by default) is held within the 1.5 A rating.
    assert_eq!(cfg.law.failsafe_current_a, 1.5);
    // 12 V over 4 Ω, either way (half bridge).
    assert_eq!((cfg.law.drive_min_a, cfg.law.drive_max_a), (-3.0, 3.0));
    assert_eq!(cfg.law.x_valid_max_mm, 25.0);
    assert_eq!(cfg.v_sensor_full_scale_m_s, 5.0);
    // The coil idles armed for LAB's fastest impact, 3 m/s.
    assert_eq!(cfg.law.impact_v_max_m_s, 3.0);
    // The defaults' installation changes nothing: the default image is today's.
    let default = Table::with_installation(&entries(), ModelTerms::NONE, DEFAULT_INSTALLATION).unwrap();
    assert_eq!(
        installed_config(&default, DEFAULT_RATE_HZ).unwrap(),
        ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap()
    );
}

#[test]
fn an_installation_outside_the_board_s_limits_is_refused_by_name() {
    use mre_algorithm::limits::{check_installation, InstallationLimit, BOARD};
    // A 3 A coil on a board whose over-current fault is compiled for 2 A; a
    // 24 V supply the PWM scaling was not compiled for; a 30 mm stroke past
    // the 25 mm sensor; a 0.05 kg mass.
    let cases = [
        (
            "coil_rating_a",
            Installation {
                coil_rating_a: 3.0,
                ..LAB
            },
        ),
        ("supply_v", Installation { supply_v: 24.0, ..LAB }),
        (
            "usable_stroke_mm",
            Installation {
                usable_stroke_mm: 30.0,
                ..LAB
            },
        ),
        ("mass_kg", Installation { mass_kg: 0.05, ..LAB }),
    ];
    assert_eq!(check_installation(&LAB, &BOARD), Ok(()));
    for (field, bad) in cases {
        let limit = check_installation(&bad, &BOARD).unwrap_err();
        assert_eq!(limit.name(), field);
        let expected = InstallationLimit(Installation::FIELD_NAMES.iter().position(|n| *n == field).unwrap() as u8);
        assert_eq!(limit, expected);

        // The decoder refuses the upload by name...
        let table = Table::with_installation(&entries(), ModelTerms::NONE, bad).unwrap();
        let mut cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
        bad.apply(&mut cfg);
        assert_eq!(
            decode_config(&blob(&table, &cfg)),
            Err(ConfigBlobError::InstallationOutOfLimits(expected)),
            "{field}"
        );
        // ...and boot refuses such a built-in table (TABLE_FAULT, fail-safe).
        let boot = choose_boot_table(&mut RamPage::erased(), &table.image(), DEFAULT_RATE_HZ);
        assert_eq!(boot.table, Err(TableError::BadInstallation { field }));
    }
}

#[test]
fn a_configuration_that_disagrees_with_the_table_s_installation_is_refused() {
    let table = Table::with_installation(&entries(), ModelTerms::NONE, LAB).unwrap();
    // The image's defaults (5.5 kg, 12 mm, 2 A) with a table for the lab's rig.
    let defaults = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    assert_eq!(
        decode_config(&blob(&table, &defaults)),
        Err(ConfigBlobError::InstallationMismatch)
    );
    let mut heavier = lab_config();
    heavier.law.mass_kg = 3.1;
    assert_eq!(
        decode_config(&blob(&table, &heavier)),
        Err(ConfigBlobError::InstallationMismatch)
    );
    assert!(decode_config(&blob(&table, &lab_config())).is_ok());
}
