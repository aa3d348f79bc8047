//! The board's hard limits: what its hardware takes, whatever a configuration
//! asks. `frame::decode_config` refuses an upload (or a stored page) that
//! crosses one, naming it ([`Limit`]); `mre upload` checks the same limits
//! before it sends. firmware/README.md ("Hard limits") says why each is there.
//!
//! Both STM32L4 boards (and the PIL image, which stands in for them) share one
//! wiring (firmware/README.md, "Wiring"): a 2 A coil, 4 Ω, on a 12 V driver,
//! a 0–25 mm displacement sensor on 0.3–3.0 V, a ±5 m/s velocity sensor. A
//! board with other hardware gets its own [`BoardLimits`] constant.
use crate::control::ControlConfig;
use crate::installation::{Installation, FIELD_COUNT};
use crate::law::ReboundPolicy;

/// A closed range `min..=max` (NaN is outside every range).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    pub min: f32,
    pub max: f32,
}

impl Range {
    pub fn contains(&self, value: f32) -> bool {
        value >= self.min && value <= self.max
    }
}

/// The hardware's limits on a configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoardLimits {
    /// Output clamp and any fixed rebound current: the coil's continuous rating.
    pub current_a: Range,
    /// The current held when the inputs cannot be trusted: stiff, within rating.
    pub failsafe_current_a: Range,
    /// Usable stroke: inside the displacement sensor's range.
    pub stroke_mm: Range,
    /// Lowest valid displacement: between the sensor's low rail reading and 0.
    pub x_valid_min_mm: Range,
    /// Highest valid displacement: below the sensor's high rail reading.
    pub x_valid_max_mm: Range,
    pub v_valid_max_m_s: Range,
    pub mass_kg: Range,
    pub gravity_m_s2: Range,
    /// Fault counts (periods): a fault must latch within one impact.
    pub range_fault_samples: Range,
    pub stuck_samples: Range,
    pub overrun_limit: Range,
    pub overrun_window: Range,
    /// A format 3 table's installation, value by value (`installation_min`
    /// ≤ value ≤ `installation_max`). The board's ADC and PWM scaling are
    /// compiled for its wiring, so the driver supply, the coil resistance
    /// and the sensors' ranges are pinned to it.
    pub installation_min: Installation,
    pub installation_max: Installation,
}

/// The coil's continuous rating (A): `overcurrent::COIL_RATING_A`.
pub const COIL_RATING_A: f32 = crate::overcurrent::COIL_RATING_A;
/// The displacement sensor: 0.3 V = 0 mm … 3.0 V = 25 mm; the ADC's rails
/// (0 V, 3.3 V: a broken or shorted wire) read these.
pub const X_SENSOR_MAX_MM: f32 = crate::installation::DEFAULT_INSTALLATION.x_sensor_range_mm;
pub const X_RAIL_LOW_MM: f32 = -2.8;
pub const X_RAIL_HIGH_MM: f32 = 27.8;
/// Margin kept inside each rail reading (about 40 ADC codes), so a rail is
/// always outside the valid range.
pub const X_RAIL_MARGIN_MM: f32 = 0.3;
/// The coil drive the board's open-loop duty (I / 3 A) is compiled for:
/// a 12 V half bridge into a 4 Ω coil.
pub const DRIVER_SUPPLY_V: f32 = 12.0;
pub const COIL_RESISTANCE_OHM: f32 = 4.0;
/// The velocity sensor's full scale the board's ADC scaling assumes.
pub const V_SENSOR_FULL_SCALE_M_S: f32 = crate::control::V_SENSOR_FULL_SCALE_M_S;

/// The STM32L4 boards' wiring (B-L475E-IOT01A, NUCLEO-L476RG, PIL).
pub const STM32L4_BOARD: BoardLimits = BoardLimits {
    current_a: Range {
        min: 0.0,
        max: COIL_RATING_A,
    },
    failsafe_current_a: Range {
        min: 0.5 * COIL_RATING_A,
        max: COIL_RATING_A,
    },
    stroke_mm: Range {
        min: 1.0,
        max: X_SENSOR_MAX_MM,
    },
    x_valid_min_mm: Range {
        min: X_RAIL_LOW_MM + X_RAIL_MARGIN_MM,
        max: 0.0,
    },
    x_valid_max_mm: Range {
        min: 1.0,
        max: X_RAIL_HIGH_MM - X_RAIL_MARGIN_MM,
    },
    v_valid_max_m_s: Range { min: 0.1, max: 20.0 },
    mass_kg: Range { min: 0.1, max: 100.0 },
    gravity_m_s2: Range { min: 9.7, max: 9.9 },
    range_fault_samples: Range { min: 1.0, max: 100.0 },
    stuck_samples: Range { min: 1.0, max: 500.0 },
    overrun_limit: Range { min: 1.0, max: 100.0 },
    overrun_window: Range {
        min: 1.0,
        max: 10_000.0,
    },
    installation_min: Installation {
        mass_kg: 0.1,
        usable_stroke_mm: 1.0,
        coil_rating_a: 0.5 * COIL_RATING_A,
        coil_resistance_ohm: COIL_RESISTANCE_OHM,
        supply_v: DRIVER_SUPPLY_V,
        x_sensor_range_mm: X_SENSOR_MAX_MM,
        v_sensor_full_scale_m_s: V_SENSOR_FULL_SCALE_M_S,
        impact_v_min_m_s: 0.1,
        impact_v_max_m_s: 0.1,
    },
    installation_max: Installation {
        mass_kg: 100.0,
        usable_stroke_mm: X_SENSOR_MAX_MM,
        coil_rating_a: COIL_RATING_A,
        coil_resistance_ohm: COIL_RESISTANCE_OHM,
        supply_v: DRIVER_SUPPLY_V,
        x_sensor_range_mm: X_SENSOR_MAX_MM,
        v_sensor_full_scale_m_s: V_SENSOR_FULL_SCALE_M_S,
        impact_v_min_m_s: 20.0,
        impact_v_max_m_s: 20.0,
    },
};

/// The limits this build enforces.
pub const BOARD: BoardLimits = STM32L4_BOARD;

/// One limited value of a configuration. The discriminant is the index in
/// [`Limit::ALL`], [`BoardLimits::ranges`] and the answer code
/// (`upload::CommitAnswer`): keep the three in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    CurrentMin,
    CurrentMax,
    ReboundCurrent,
    FailsafeCurrent,
    Stroke,
    XValidMin,
    XValidMax,
    VValidMax,
    Mass,
    Gravity,
    RangeFaultSamples,
    StuckSamples,
    OverrunLimit,
    OverrunWindow,
}

impl Limit {
    pub const ALL: [Limit; 14] = [
        Limit::CurrentMin,
        Limit::CurrentMax,
        Limit::ReboundCurrent,
        Limit::FailsafeCurrent,
        Limit::Stroke,
        Limit::XValidMin,
        Limit::XValidMax,
        Limit::VValidMax,
        Limit::Mass,
        Limit::Gravity,
        Limit::RangeFaultSamples,
        Limit::StuckSamples,
        Limit::OverrunLimit,
        Limit::OverrunWindow,
    ];

    /// The configuration field's name.
    pub fn name(&self) -> &'static str {
        match self {
            Limit::CurrentMin => "current_min_a",
            Limit::CurrentMax => "current_max_a",
            Limit::ReboundCurrent => "rebound current_a",
            Limit::FailsafeCurrent => "failsafe_current_a",
            Limit::Stroke => "stroke_max_mm",
            Limit::XValidMin => "x_valid_min_mm",
            Limit::XValidMax => "x_valid_max_mm",
            Limit::VValidMax => "v_valid_max_m_s",
            Limit::Mass => "mass_kg",
            Limit::Gravity => "gravity_m_s2",
            Limit::RangeFaultSamples => "range_fault_samples",
            Limit::StuckSamples => "stuck_samples",
            Limit::OverrunLimit => "overrun_limit",
            Limit::OverrunWindow => "overrun_window",
        }
    }

    /// Why the board holds this limit (one clause, for logs and the host).
    pub fn why(&self) -> &'static str {
        match self {
            Limit::CurrentMin | Limit::CurrentMax | Limit::ReboundCurrent => {
                "the coil's continuous rating (the over-current fault trips above it)"
            }
            Limit::FailsafeCurrent => {
                "the fail-safe must keep the damper stiff (0 A lets the drop test bottom out) and within the coil's rating"
            }
            Limit::Stroke => "the law cannot plan beyond the displacement sensor's 25 mm range",
            Limit::XValidMin | Limit::XValidMax => {
                "a broken or shorted displacement wire reads -2.8 or 27.8 mm and must stay outside the valid range"
            }
            Limit::VValidMax => "a velocity beyond 20 m/s (a 20 m fall) is a sensor fault, not an impact",
            Limit::Mass => "the law's plan needs a plausible moving mass",
            Limit::Gravity => "gravity on Earth",
            Limit::RangeFaultSamples | Limit::StuckSamples => {
                "a sensor fault must latch within one impact (0 would disable the check)"
            }
            Limit::OverrunLimit | Limit::OverrunWindow => {
                "overruns must latch within a second at 10 kHz (0 would disable the check)"
            }
        }
    }

    pub fn range(&self, limits: &BoardLimits) -> Range {
        let nothing = Range {
            min: f32::NAN,
            max: f32::NAN,
        };
        limits.ranges().get(*self as usize).copied().unwrap_or(nothing)
    }

    /// The configuration's value (counts as f32: exact below 2^24).
    pub fn value(&self, cfg: &ControlConfig) -> f32 {
        values(cfg).get(*self as usize).copied().unwrap_or(f32::NAN)
    }
}

impl BoardLimits {
    /// The ranges in [`Limit::ALL`]'s order.
    pub const fn ranges(&self) -> [Range; 14] {
        [
            self.current_a,
            self.current_a,
            self.current_a,
            self.failsafe_current_a,
            self.stroke_mm,
            self.x_valid_min_mm,
            self.x_valid_max_mm,
            self.v_valid_max_m_s,
            self.mass_kg,
            self.gravity_m_s2,
            self.range_fault_samples,
            self.stuck_samples,
            self.overrun_limit,
            self.overrun_window,
        ]
    }
}

/// The limited values of `cfg` in [`Limit::ALL`]'s order (one straight
/// pass: the board checks every upload with it).
fn values(cfg: &ControlConfig) -> [f32; 14] {
    let law = &cfg.law;
    let rebound_a = match law.rebound {
        ReboundPolicy::Fixed { current_a } => current_a,
        // No current of its own: the output clamp's.
        ReboundPolicy::Minimum | ReboundPolicy::Hold => law.current_min_a,
    };
    [
        law.current_min_a,
        law.current_max_a,
        rebound_a,
        law.failsafe_current_a,
        law.stroke_max_mm,
        law.x_valid_min_mm,
        law.x_valid_max_mm,
        law.v_valid_max_m_s,
        law.mass_kg,
        law.gravity_m_s2,
        f32::from(cfg.range_fault_samples),
        f32::from(cfg.stuck_samples),
        f32::from(cfg.overrun_limit),
        f32::from(cfg.overrun_window),
    ]
}

/// [`BOARD`]'s ranges, laid out once in flash.
static BOARD_RANGES: [Range; 14] = BOARD.ranges();

/// The first value of `cfg` outside `limits`, if any.
pub fn check(cfg: &ControlConfig, limits: &BoardLimits) -> Result<(), Limit> {
    check_ranges(cfg, &limits.ranges())
}

/// [`check`] against this build's [`BOARD`] (what the decoder runs).
pub fn check_board(cfg: &ControlConfig) -> Result<(), Limit> {
    check_ranges(cfg, &BOARD_RANGES)
}

fn check_ranges(cfg: &ControlConfig, ranges: &[Range; 14]) -> Result<(), Limit> {
    let outside = values(cfg).iter().zip(ranges).position(|(v, r)| !r.contains(*v));
    match outside.and_then(|k| Limit::ALL.get(k)) {
        Some(l) => Err(*l),
        None => Ok(()),
    }
}

/// A format 3 table's installation value outside the board's limits: its
/// index in `Installation::FIELD_NAMES`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InstallationLimit(pub u8);

impl InstallationLimit {
    pub fn name(&self) -> &'static str {
        Installation::FIELD_NAMES
            .get(usize::from(self.0))
            .copied()
            .unwrap_or("?")
    }

    pub fn range(&self, limits: &BoardLimits) -> Range {
        let at = |i: &Installation| i.to_array().get(usize::from(self.0)).copied().unwrap_or(f32::NAN);
        Range {
            min: at(&limits.installation_min),
            max: at(&limits.installation_max),
        }
    }

    pub fn value(&self, installation: &Installation) -> f32 {
        installation
            .to_array()
            .get(usize::from(self.0))
            .copied()
            .unwrap_or(f32::NAN)
    }

    /// Why the board holds this limit (one clause, for the host).
    pub fn why(&self) -> &'static str {
        match self.name() {
            "mass_kg" => "the law's plan needs a plausible moving mass",
            "usable_stroke_mm" => "the law cannot plan beyond the displacement sensor's 25 mm range",
            "coil_rating_a" => {
                "the over-current fault is compiled for the board's 2 A coil, and the fail-safe needs at least 1 A"
            }
            "impact_v_min_m_s" | "impact_v_max_m_s" => "an impact beyond 20 m/s (a 20 m fall) is a sensor fault",
            _ => "the board's ADC and PWM scaling are compiled for its wiring (12 V, 4 Ω, 0–25 mm, ±5 m/s)",
        }
    }
}

/// The first value of `installation` outside `limits`, if any.
pub fn check_installation(installation: &Installation, limits: &BoardLimits) -> Result<(), InstallationLimit> {
    let (lo, hi) = (limits.installation_min.to_array(), limits.installation_max.to_array());
    let values = installation.to_array();
    let outside = (0..FIELD_COUNT).position(|k| match (values.get(k), lo.get(k), hi.get(k)) {
        (Some(v), Some(min), Some(max)) => !(v >= min && v <= max),
        _ => true,
    });
    match outside {
        Some(k) => Err(InstallationLimit(u8::try_from(k).unwrap_or(u8::MAX))),
        None => Ok(()),
    }
}

/// [`check_installation`] against this build's [`BOARD`].
pub fn check_installation_board(installation: &Installation) -> Result<(), InstallationLimit> {
    check_installation(installation, &BOARD)
}
