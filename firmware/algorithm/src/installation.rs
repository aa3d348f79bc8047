//! The installation: what the damper is mounted in and wired to. One value
//! for the board's defaults (`LawConfig::default`) and the host's simulation
//! (`mre sim`, `mre pil`, `mre bench-control`, the demo), so the image and the
//! simulation cannot drift apart (`host-tools/tests/integration/installation.rs`).
//!
//! A model file's `[installation]` section overrides it; `mre tables` and
//! `mre upload` carry it in the flash table (format 3, under the table's
//! CRC), and the board derives its law and fault configuration from it
//! ([`Installation::apply`]) within its hard limits (`limits`).

/// Declares [`Installation`] once: each field is one line here, and the
/// table's CRC, the upload blob, the limits check and the host's TOML reader
/// and writers walk [`Installation::FIELD_NAMES`] and
/// [`Installation::to_array`] instead of naming fields.
macro_rules! installation {
    ($($(#[$doc:meta])* $field:ident,)+) => {
        /// One installation's physical values.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct Installation {
            $($(#[$doc])* pub $field: f32,)+
        }

        impl Installation {
            /// The fields' names, in [`Self::to_array`]'s order (the order
            /// the flash table and the upload blob store them in).
            pub const FIELD_NAMES: [&'static str; FIELD_COUNT] = [$(stringify!($field)),+];

            pub const fn to_array(&self) -> [f32; FIELD_COUNT] {
                [$(self.$field),+]
            }

            #[allow(clippy::indexing_slicing)] // the macro counts the fields: every index exists
            pub const fn from_array(values: [f32; FIELD_COUNT]) -> Self {
                let mut _k = 0usize;
                $(
                    let $field = values[_k];
                    _k = _k.wrapping_add(1);
                )+
                Self { $($field),+ }
            }
        }

        /// How many values an installation holds.
        pub const FIELD_COUNT: usize = [$(stringify!($field)),+].len();
    };
}

installation! {
    /// The drop or striker mass that hits the damper.
    mass_kg,
    /// Stroke the damper may use from first contact: the elastomer's rated
    /// compression. The bundled full-stroke data cover 0–15 mm so that this
    /// stroke lies inside every entry's fitted range (firmware/README.md).
    usable_stroke_mm,
    /// The coil's continuous current rating.
    coil_rating_a,
    coil_resistance_ohm,
    /// The coil driver's supply.
    supply_v,
    /// The displacement sensor's range (0 to this).
    x_sensor_range_mm,
    /// The velocity sensor's rated full scale (±).
    v_sensor_full_scale_m_s,
    /// The slowest and fastest impact the installation expects. Without a
    /// predicted impact velocity the law arms for this whole range (#29).
    impact_v_min_m_s,
    impact_v_max_m_s,
}

/// The paper's drop test on the bundled wiring: 5.5 kg, 12 mm usable stroke,
/// a 2 A, 4 Ω coil on a 12 V driver, a 0–25 mm and a ±5 m/s sensor, and
/// impacts from 1.5 to 2.5 m/s around the paper's 2.24 m/s (115–320 mm drops).
/// Tables of format 1 and 2 (which carry no installation) load with it.
pub const DEFAULT_INSTALLATION: Installation = Installation {
    mass_kg: 5.5,
    usable_stroke_mm: 12.0,
    coil_rating_a: 2.0,
    coil_resistance_ohm: 4.0,
    supply_v: 12.0,
    x_sensor_range_mm: 25.0,
    v_sensor_full_scale_m_s: 5.0,
    impact_v_min_m_s: 1.5,
    impact_v_max_m_s: 2.5,
};

impl Installation {
    /// The largest drive (A equivalent, V / R) the supply gives.
    pub fn drive_max_a(&self) -> f32 {
        self.supply_v / self.coil_resistance_ohm
    }

    /// The first field that is not a finite positive value, or an impact
    /// range with its minimum above its maximum: a value no installation
    /// has, whatever the board (`limits` then bounds it by the board's).
    pub fn invalid_field(&self) -> Option<&'static str> {
        let bad = self.to_array().iter().position(|v| !(v.is_finite() && *v > 0.0));
        match bad {
            Some(k) => Self::FIELD_NAMES.get(k).copied(),
            None if self.impact_v_min_m_s > self.impact_v_max_m_s => Some("impact_v_min_m_s"),
            None => None,
        }
    }
}
