//! The installation: what the damper is mounted in and wired to. One value
//! for the board's defaults (`LawConfig::default`) and the host's simulation
//! (`mre sim`, `mre pil`, `mre bench-control`, the demo), so the image and the
//! simulation cannot drift apart (`host-tools/tests/installation.rs`).
//! A model file's `[installation]` section overrides it for `mre upload`.

/// One installation's physical values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Installation {
    /// The drop or striker mass that hits the damper.
    pub mass_kg: f32,
    /// Stroke the damper may use from first contact: the elastomer's rated
    /// compression. The bundled full-stroke data cover 0–15 mm so that this
    /// stroke lies inside every entry's fitted range (firmware/README.md).
    pub usable_stroke_mm: f32,
    /// The coil's continuous current rating.
    pub coil_rating_a: f32,
    pub coil_resistance_ohm: f32,
    /// The coil driver's supply.
    pub supply_v: f32,
    /// The displacement sensor's range (0 to this).
    pub x_sensor_range_mm: f32,
    /// The velocity sensor's rated full scale (±).
    pub v_sensor_full_scale_m_s: f32,
    /// The slowest and fastest impact the installation expects. Without a
    /// predicted impact velocity the law arms for this whole range (#29).
    pub impact_v_min_m_s: f32,
    pub impact_v_max_m_s: f32,
}

/// The paper's drop test on the bundled wiring: 5.5 kg, 12 mm usable stroke,
/// a 2 A, 4 Ω coil on a 12 V driver, a 0–25 mm and a ±5 m/s sensor, and
/// impacts from 1.5 to 2.5 m/s around the paper's 2.24 m/s (115–320 mm drops).
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
}
