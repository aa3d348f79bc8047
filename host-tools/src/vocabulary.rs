//! The missing-physics vocabulary (`docs/effects.md`): one name per
//! effect, shared by the synthesiser (which conceals an effect,
//! [`crate::plant::effects`]) and `mre diagnose` (which names what it finds).
//! The names are a contract: reports, keys and scripts rely on them.
use serde::{Deserialize, Serialize};

/// One word of the vocabulary, without parameters. The declaration order is
/// the order findings and candidates sort in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Effect {
    ViscousDamping,
    SensorDelay,
    StressSoftening,
    EndStop,
    MagneticSaturation,
    Inertia,
    CoilLag,
    /// Rate-independent hysteresis with memory (turn-around memory, with dry
    /// friction / yield as its limiting case).
    HysteresisMemory,
    /// No missing physics: what a synthesised plant without an effect
    /// conceals.
    None,
}

impl Effect {
    /// Every word, in declaration order. (Not `ALL`: diagnose's candidates
    /// are the terms registered in `diagnose::terms::REGISTRY`.)
    pub const VOCABULARY: [Effect; 9] = [
        Effect::ViscousDamping,
        Effect::SensorDelay,
        Effect::StressSoftening,
        Effect::EndStop,
        Effect::MagneticSaturation,
        Effect::Inertia,
        Effect::CoilLag,
        Effect::HysteresisMemory,
        Effect::None,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Effect::ViscousDamping => "viscous_damping",
            Effect::SensorDelay => "sensor_delay",
            Effect::StressSoftening => "stress_softening",
            Effect::EndStop => "end_stop",
            Effect::MagneticSaturation => "magnetic_saturation",
            Effect::Inertia => "inertia",
            Effect::CoilLag => "coil_lag",
            Effect::HysteresisMemory => "hysteresis_memory",
            Effect::None => "none",
        }
    }

    pub fn from_name(name: &str) -> Option<Effect> {
        Effect::VOCABULARY.into_iter().find(|e| e.name() == name)
    }
}

impl std::fmt::Display for Effect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // `pad`, so widths and precisions in format strings apply.
        f.pad(self.name())
    }
}

/// The names of `effects`, in order (what a list of them prints as).
pub fn names(effects: &[Effect]) -> Vec<&'static str> {
    effects.iter().map(|e| e.name()).collect()
}

/// The names of `effects` joined by ", " (for messages listing what is accepted).
pub fn join_names(effects: &[Effect]) -> String {
    names(effects).join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names as written in `docs/effects.md`'s table, plus `none`.
    #[test]
    fn names_are_the_spec_words_and_round_trip() {
        let spec = [
            "viscous_damping",
            "sensor_delay",
            "stress_softening",
            "end_stop",
            "magnetic_saturation",
            "inertia",
            "coil_lag",
            "hysteresis_memory",
            "none",
        ];
        for (e, name) in Effect::VOCABULARY.into_iter().zip(spec) {
            assert_eq!(e.name(), name);
            assert_eq!(Effect::from_name(name), Some(e));
            assert_eq!(serde_json::to_value(e).unwrap(), serde_json::json!(name));
            assert_eq!(serde_json::from_value::<Effect>(serde_json::json!(name)).unwrap(), e);
        }
        assert_eq!(Effect::from_name("random"), None);
    }
}
