//! The missing-physics vocabulary (`docs/effects.md`): one name per
//! effect, shared by the synthesiser (which conceals an effect,
//! [`crate::plant::effects`]) and `mre diagnose` (which names what it finds).
//! The names are a contract: reports, keys and scripts rely on them.
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// One word of the vocabulary, without parameters: its name. A word, not an
/// enum, so that a diagnosis term declares its own (`diagnose::terms`, one
/// file and one registry line) without editing this file; the words below
/// are those the synthesiser can conceal too.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Effect(&'static str);

#[allow(non_upper_case_globals)]
impl Effect {
    pub const ViscousDamping: Effect = Effect("viscous_damping");
    pub const SensorDelay: Effect = Effect("sensor_delay");
    pub const StressSoftening: Effect = Effect("stress_softening");
    pub const EndStop: Effect = Effect("end_stop");
    pub const MagneticSaturation: Effect = Effect("magnetic_saturation");
    pub const Inertia: Effect = Effect("inertia");
    pub const CoilLag: Effect = Effect("coil_lag");
    /// Rate-independent hysteresis with memory (turn-around memory, with dry
    /// friction / yield as its limiting case).
    pub const HysteresisMemory: Effect = Effect("hysteresis_memory");
    /// No missing physics: what a synthesised plant without an effect
    /// conceals.
    pub const None: Effect = Effect("none");

    /// The synthesiser's words, in the order findings and candidates sort
    /// in. (Not every word: diagnose's candidates are the terms registered
    /// in `diagnose::terms::REGISTRY`, which may add their own.)
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

    /// A word of a diagnosis term's own (snake_case, as a report key).
    pub const fn new(name: &'static str) -> Effect {
        Effect(name)
    }

    pub fn name(self) -> &'static str {
        self.0
    }

    /// The word named `name`: the synthesiser's, or a registered term's.
    pub fn from_name(name: &str) -> Option<Effect> {
        Effect::VOCABULARY
            .into_iter()
            .chain(crate::diagnose::terms::REGISTRY.iter().map(|t| t.effect()))
            .find(|e| e.name() == name)
    }

    /// Position in [`Effect::VOCABULARY`] (a term's own word after them).
    fn rank(self) -> usize {
        Effect::VOCABULARY
            .iter()
            .position(|e| *e == self)
            .unwrap_or(Effect::VOCABULARY.len())
    }
}

impl PartialOrd for Effect {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Effect {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        (self.rank(), self.0).cmp(&(other.rank(), other.0))
    }
}

impl Serialize for Effect {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.0)
    }
}

impl<'de> Deserialize<'de> for Effect {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Effect::from_name(&name).ok_or_else(|| serde::de::Error::custom(format!("unknown effect `{name}`")))
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
