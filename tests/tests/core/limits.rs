//! The board's hard limits (`mre_algorithm::limits`): no configuration the decoder
//! accepts lies outside what the hardware takes. The expected bounds here are
//! written from the wiring (firmware/README.md, "Wiring" and "Hard limits"),
//! not read from the code: a 2 A coil, a 0–25 mm displacement sensor whose ADC
//! rails read −2.8 and 27.8 mm (0.3 mm kept inside each), fault counts that latch within an impact.
use mre_algorithm::control::{ControlConfig, DEFAULT_RATE_HZ};
use mre_algorithm::law::ReboundPolicy;
use mre_algorithm::limits::Limit;
use mre_algorithm::table::Table;
use mre_protocol::frame::{decode_config, encode_config, ConfigBlobError, CONFIG_MAX_WORDS};
use proptest::prelude::*;

fn blob(cfg: &ControlConfig) -> Vec<u32> {
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(&Table::paper().unwrap(), cfg, &mut words);
    words[..n].to_vec()
}

fn default_cfg() -> ControlConfig {
    ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap()
}

/// The hardware's bounds, by hand (see the module docs).
fn within_hardware(cfg: &ControlConfig) -> bool {
    let law = &cfg.law;
    let rebound_ok = match law.rebound {
        ReboundPolicy::Fixed { current_a } => (0.0..=2.0).contains(&current_a),
        _ => true,
    };
    (0.0..=2.0).contains(&law.current_min_a)
        && (0.0..=2.0).contains(&law.current_max_a)
        && rebound_ok
        && (1.0..=2.0).contains(&law.failsafe_current_a)
        && (1.0..=25.0).contains(&law.stroke_max_mm)
        // The rails' readings with 0.3 mm (about 40 ADC codes) kept inside them.
        && (-2.5..=0.0).contains(&law.x_valid_min_mm)
        && (1.0..=27.5).contains(&law.x_valid_max_mm)
        && (0.1..=20.0).contains(&law.v_valid_max_m_s)
        && (0.1..=100.0).contains(&law.mass_kg)
        && (9.7..=9.9).contains(&law.gravity_m_s2)
        && (1..=100).contains(&cfg.range_fault_samples)
        && (1..=500).contains(&cfg.stuck_samples)
        && (1..=100).contains(&cfg.overrun_limit)
        && (1..=10_000).contains(&cfg.overrun_window)
}

#[test]
fn the_defaults_lie_within_the_limits_at_every_supported_rate() {
    for rate_hz in [1_000, DEFAULT_RATE_HZ, 20_000, 40_000] {
        let cfg = ControlConfig::at_rate(rate_hz).unwrap();
        assert!(within_hardware(&cfg), "{rate_hz} Hz");
        assert_eq!(decode_config(&blob(&cfg)).map(|(_, c)| c), Ok(cfg));
    }
}

/// The examples, each consistent with the rest of the configuration
/// (`ControlConfig::validate` takes them) but refused by the board, by name.
#[test]
fn each_out_of_limit_value_is_refused_by_name() {
    type Case = (&'static str, fn(&mut ControlConfig), Limit);
    let cases: [Case; 8] = [
        (
            "fail-safe 0 A",
            |c| c.law.failsafe_current_a = 0.0,
            Limit::FailsafeCurrent,
        ),
        (
            "3 A output on a 2 A coil",
            |c| {
                c.law.current_max_a = 3.0;
                c.law.failsafe_current_a = 2.0;
            },
            Limit::CurrentMax,
        ),
        (
            "broken-wire detection off",
            |c| c.law.x_valid_max_mm = 1.0e30,
            Limit::XValidMax,
        ),
        (
            "x valid below the low rail",
            |c| c.law.x_valid_min_mm = -3.0,
            Limit::XValidMin,
        ),
        (
            "range faults never latch",
            |c| c.range_fault_samples = 65_535,
            Limit::RangeFaultSamples,
        ),
        ("stuck check off", |c| c.stuck_samples = 0, Limit::StuckSamples),
        (
            "a fixed rebound current above rating",
            |c| c.law.rebound = ReboundPolicy::Fixed { current_a: 2.5 },
            Limit::ReboundCurrent,
        ),
        (
            "a stroke past the sensor",
            |c| c.law.stroke_max_mm = 30.0,
            Limit::Stroke,
        ),
    ];
    for (what, edit, limit) in cases {
        let mut cfg = default_cfg();
        edit(&mut cfg);
        assert_eq!(cfg.validate(), Ok(()), "{what}: the case must be consistent");
        assert!(!within_hardware(&cfg), "{what}");
        assert_eq!(
            decode_config(&blob(&cfg)),
            Err(ConfigBlobError::OutOfLimits(limit)),
            "{what}"
        );
    }
}

/// Mostly a plausible value, sometimes anything in a wide range around it.
fn mostly(inside: std::ops::Range<f32>, wide: std::ops::Range<f32>) -> BoxedStrategy<f32> {
    prop_oneof![12 => inside, 1 => wide].boxed()
}

fn mostly_count(inside: std::ops::Range<u16>, wide: std::ops::Range<u16>) -> BoxedStrategy<u16> {
    prop_oneof![12 => inside, 1 => wide].boxed()
}

fn any_config() -> impl Strategy<Value = ControlConfig> {
    (
        (
            mostly(0.0..0.5, -1.0..4.0),
            mostly(1.5..2.0, -1.0..4.0),
            mostly(1.0..1.5, -1.0..4.0),
            prop::option::of(mostly(0.0..2.0, -1.0..4.0)),
        ),
        (
            mostly(5.0..20.0, 0.0..40.0),
            mostly(-2.0..0.0, -5.0..2.0),
            mostly(20.0..27.0, -1.0..1.0e6),
            mostly(1.0..20.0, 0.0..40.0),
        ),
        (mostly(1.0..50.0, 0.0..200.0), mostly(9.78..9.83, 9.0..10.5)),
        (
            mostly_count(1..100, 0..2000),
            mostly_count(1..500, 0..2000),
            mostly_count(1..50, 0..200),
            mostly_count(100..10_000, 0..u16::MAX),
        ),
    )
        .prop_map(|(currents, ranges, plant, counts)| {
            let mut c = default_cfg();
            (c.law.current_min_a, c.law.current_max_a, c.law.failsafe_current_a) = (currents.0, currents.1, currents.2);
            c.law.rebound = match currents.3 {
                Some(current_a) => ReboundPolicy::Fixed { current_a },
                None => ReboundPolicy::Minimum,
            };
            (
                c.law.stroke_max_mm,
                c.law.x_valid_min_mm,
                c.law.x_valid_max_mm,
                c.law.v_valid_max_m_s,
            ) = ranges;
            (c.law.mass_kg, c.law.gravity_m_s2) = plant;
            (
                c.range_fault_samples,
                c.stuck_samples,
                c.overrun_limit,
                c.overrun_window,
            ) = counts;
            c
        })
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(2000))]

    /// Accepted ⇔ consistent and within the hardware's bounds: nothing
    /// outside them gets through, and nothing inside them is refused.
    #[test]
    fn the_decoder_accepts_exactly_the_consistent_configurations_within_the_limits(cfg in any_config()) {
        let accepted = decode_config(&blob(&cfg));
        if let Ok((_, got)) = &accepted {
            prop_assert!(within_hardware(got), "accepted outside the limits: {:?}", got);
        }
        prop_assert_eq!(accepted.is_ok(), cfg.validate().is_ok() && within_hardware(&cfg), "{:?}", accepted);
    }
}
