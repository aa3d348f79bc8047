//! Unit-carrying column names (`docs/dataset-format.md`) and their
//! conversion factors to the internal units.
use super::error::DatasetError;

/// What a column measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    Time,
    Displacement,
    Velocity,
    Acceleration,
    Force,
    Current,
    Temperature,
}

impl Quantity {
    /// The physically plausible range in the internal unit (min, max, unit).
    /// A value outside is a unit mix-up or a broken channel, rejected at load:
    /// 1e6 s of recording, 1 m of displacement, 100 m/s, 10⁶ m/s² (10⁵ g),
    /// 10 MN, 100 A, absolute zero to 1000 °C.
    pub fn plausible_range(self) -> (f64, f64, &'static str) {
        match self {
            Quantity::Time => (-1e6, 1e6, "s"),
            Quantity::Displacement => (-1e3, 1e3, "mm"),
            Quantity::Velocity => (-100.0, 100.0, "m/s"),
            Quantity::Acceleration => (-1e6, 1e6, "m/s²"),
            Quantity::Force => (-1e7, 1e7, "N"),
            Quantity::Current => (-100.0, 100.0, "A"),
            Quantity::Temperature => (-273.15, 1000.0, "°C"),
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            Quantity::Time => "time",
            Quantity::Displacement => "displacement",
            Quantity::Velocity => "velocity",
            Quantity::Acceleration => "acceleration",
            Quantity::Force => "force",
            Quantity::Current => "current",
            Quantity::Temperature => "temperature",
        }
    }
}

/// Accepted names, their quantity and the factor to the internal unit.
const NAMES: &[(&str, Quantity, f64)] = &[
    ("time_s", Quantity::Time, 1.0),
    ("time_ms", Quantity::Time, 1e-3),
    ("displacement_mm", Quantity::Displacement, 1.0),
    ("displacement_m", Quantity::Displacement, 1e3),
    // 1 in = 25.4 mm exactly (international inch, 1959).
    ("displacement_in", Quantity::Displacement, 25.4),
    ("velocity_m_s", Quantity::Velocity, 1.0),
    ("velocity_mm_s", Quantity::Velocity, 1e-3),
    ("acceleration_m_s2", Quantity::Acceleration, 1.0),
    // Standard gravity, 9.806 65 m/s² exactly (3rd CGPM, 1901).
    ("acceleration_g", Quantity::Acceleration, 9.806_65),
    ("force_n", Quantity::Force, 1.0),
    ("force_kn", Quantity::Force, 1e3),
    // 1 lbf = 0.453 592 37 kg × 9.806 65 m/s², exactly.
    ("force_lbf", Quantity::Force, 4.448_221_615_260_5),
    ("current_a", Quantity::Current, 1.0),
    ("temperature_c", Quantity::Temperature, 1.0),
];

/// A column: `None` for `ignore`, else its quantity and unit factor.
pub type Column = Option<(Quantity, f64)>;

fn accepted_for(q: Option<Quantity>) -> String {
    let mut names: Vec<&str> = NAMES
        .iter()
        .filter(|(_, qq, _)| q.is_none_or(|q| q == *qq))
        .map(|(n, _, _)| *n)
        .collect();
    if q.is_none() {
        names.push("ignore");
    }
    names.join(", ")
}

/// Maps header names to columns. `path`/`line` locate the names (the data
/// file's header row, or `columns` in dataset.toml).
pub fn parse_header(names: &[String], path: &str, line: usize) -> Result<Vec<Column>, DatasetError> {
    let mut layout: Vec<Column> = Vec::with_capacity(names.len());
    for (i, name) in names.iter().enumerate() {
        if name == "ignore" {
            layout.push(None);
            continue;
        }
        let Some(&(_, quantity, factor)) = NAMES.iter().find(|(n, _, _)| n == name) else {
            return Err(DatasetError::UnknownColumn {
                path: path.to_string(),
                line,
                column: i + 1,
                name: name.clone(),
                accepted: accepted_for(None),
            });
        };
        if layout.iter().any(|c| matches!(c, Some((q, _)) if *q == quantity)) {
            return Err(DatasetError::DuplicateColumn {
                path: path.to_string(),
                line,
                column: i + 1,
                name: name.clone(),
                quantity: quantity.describe().to_string(),
            });
        }
        layout.push(Some((quantity, factor)));
    }
    Ok(layout)
}

/// Time and force must be present; an accelerometer drop record's
/// acceleration stands for force (`super::accelerometer`). Without
/// displacement the motion is derived from force or acceleration (`super::motion`).
pub fn required_columns(layout: &[Column], path: &str, line: usize) -> Result<(), DatasetError> {
    let has = |q: Quantity| layout.iter().any(|c| matches!(c, Some((qq, _)) if *qq == q));
    for q in [Quantity::Time, Quantity::Force] {
        let stands_in = q == Quantity::Force && has(Quantity::Acceleration);
        if !has(q) && !stands_in {
            return Err(DatasetError::MissingColumn {
                path: path.to_string(),
                line,
                quantity: q.describe().to_string(),
                accepted: if q == Quantity::Force {
                    format!(
                        "{}; or, for an accelerometer drop record with mass_kg, {}",
                        accepted_for(Some(q)),
                        accepted_for(Some(Quantity::Acceleration))
                    )
                } else {
                    accepted_for(Some(q))
                },
            });
        }
    }
    Ok(())
}

/// Words naming what a machine was told to do, not what it measured.
const COMMAND_WORDS: &[&str] = &[
    "command", "cmd", "setpoint", "set", "target", "demand", "sollwert", "soll", "consigne", "consigna",
];

/// The quantity a channel's name (lower case, without its unit) names.
fn quantity_word(word: &str) -> Option<&'static str> {
    Some(match word {
        // English, German, Spanish, French and Polish, as MTS and Instron
        // exports name them (Bluehill's German `Traversenweg` and `Last`,
        // its Polish `Godzina`, `Przemieszczenie`, `Obciążenie`).
        "time" | "t" | "running time" | "zeit" | "laufzeit" | "prüfzeit" | "tiempo" | "temps" | "czas" | "godzina" => {
            "time"
        }
        "displacement" | "disp" | "position" | "stroke" | "x" | "deflection" | "extension" | "weg" | "verschiebung"
        | "traversenweg" | "standardweg" | "desplazamiento" | "déplacement" | "deplacement" | "przemieszczenie" => {
            "displacement"
        }
        "velocity" | "vel" | "speed" | "v" => "velocity",
        "force" | "load" | "f" | "kraft" | "prüfkraft" | "pruefkraft" | "standardkraft" | "last" | "fuerza"
        | "carga" | "charge" | "obciążenie" | "siła" => "force",
        "acceleration" | "accel" | "acc" | "a" => "acceleration",
        "current" | "i" | "coil current" => "current",
        "temperature" | "temp" => "temperature",
        _ => return None,
    })
}

/// A header name to a unit-carrying column name, if it can be told:
/// `Time (ms)` → `time_ms`, `Load [kN]` → `force_kn`, `Axial Force (kN)`
/// → `force_kn`, `Load (Newtons)` → `force_n`.
pub fn map_name(raw: &str) -> Option<String> {
    let lower = raw.trim().to_ascii_lowercase();
    if parse_header(std::slice::from_ref(&lower), "", 1).is_ok() {
        return Some(lower);
    }
    // Split "Force (kN)", "force[kN]", "Force_kN", "force kn" into word and unit.
    let cleaned: String = lower
        .chars()
        .map(|c| if "()[]{}_,;:".contains(c) { ' ' } else { c })
        .collect();
    // "Axial Force", "Universal Force", "Ch 1 Kraft" (MTS channel names): the
    // axis, frame and channel number say nothing about the quantity.
    let mut words: Vec<&str> = cleaned
        .split_whitespace()
        .skip_while(|w| matches!(*w, "axial" | "universal" | "ch") || w.chars().all(|c| c.is_ascii_digit()))
        .collect();
    let unit = if words.len() > 1 { words.pop() } else { None };
    let word = words.join(" ");
    let quantity = match quantity_word(&word) {
        Some(q) => q,
        // A name of several words with one quantity word among them, as
        // Bluehill names channels (`Compressive extension`, `Primary load
        // measurement`, `Time measurement`); one-letter words say nothing
        // here, and two quantity words (`Load cell temperature`) are no name,
        // nor is a command (MTS's `Ch 1 Kraft Sollwert`, a `Load command`).
        None if words.iter().any(|w| COMMAND_WORDS.contains(w)) => return None,
        None => {
            let mut found = words
                .iter()
                .filter(|w| w.chars().count() > 1)
                .filter_map(|w| quantity_word(w));
            let first = found.next()?;
            if words.len() < 2 || found.any(|q| q != first) {
                return None;
            }
            first
        }
    };
    // Spelled-out units (LabVIEW's `Newtons`, MTS's `Sec`) to their symbols.
    let unit = unit.map(|u| {
        let u = u.replace(['/', ' '], "_");
        match u.as_str() {
            "sec" | "secs" | "second" | "seconds" => "s".to_string(),
            "newton" | "newtons" => "n".to_string(),
            "kilonewton" | "kilonewtons" => "kn".to_string(),
            "meter" | "meters" | "metre" | "metres" => "m".to_string(),
            "millimeter" | "millimeters" | "millimetre" | "millimetres" => "mm".to_string(),
            "ampere" | "amperes" | "amps" => "a".to_string(),
            _ => u,
        }
    });
    let name = match (quantity, unit.as_deref()) {
        ("time", None | Some("s")) => "time_s",
        ("time", Some("ms")) => "time_ms",
        ("displacement", None | Some("mm")) => "displacement_mm",
        ("displacement", Some("m")) => "displacement_m",
        ("displacement", Some("in")) => "displacement_in",
        ("velocity", None | Some("m_s")) => "velocity_m_s",
        ("velocity", Some("mm_s")) => "velocity_mm_s",
        ("acceleration", None | Some("m_s2") | Some("m_s^2")) => "acceleration_m_s2",
        ("acceleration", Some("g")) => "acceleration_g",
        ("force", None | Some("n")) => "force_n",
        ("force", Some("kn")) => "force_kn",
        ("force", Some("lbf")) => "force_lbf",
        ("current", None | Some("a")) => "current_a",
        ("temperature", None | Some("c") | Some("degc") | Some("°c")) => "temperature_c",
        _ => return None,
    };
    Some(name.to_string())
}

#[cfg(test)]
mod tests {
    use super::map_name;

    /// Hand-written: channel names as the real exports in the vendor
    /// README's tally write them (Bluehill in German and Polish, a custom
    /// Bluehill method, MTS TestSuite), with their units joined.
    #[test]
    fn instrument_channel_names_map_to_their_quantity_and_commands_do_not() {
        let cases = [
            ("Zeit (sec)", Some("time_s")),
            ("Traversenweg (mm)", Some("displacement_mm")),
            ("Last (kN)", Some("force_kn")),
            ("Godzina (s)", Some("time_s")),
            ("Przemieszczenie (mm)", Some("displacement_mm")),
            ("Obciążenie (N)", Some("force_n")),
            ("Time measurement (s)", Some("time_s")),
            ("Primary load measurement (N)", Some("force_n")),
            ("Compressive extension (mm)", Some("displacement_mm")),
            ("Ch 1 Kraft (kN)", Some("force_kn")),
            // A command is not a measurement; strain, stress and a name with two quantities say nothing.
            ("Ch 1 Kraft Sollwert (kN)", None),
            ("Load command (N)", None),
            ("Tensile strain (Strain 1) (%)", None),
            ("Zugspannung (MPa)", None),
            ("Load cell temperature (C)", None),
            // A known quantity in a unit mre has no factor for.
            ("Extension (%)", None),
        ];
        for (raw, want) in cases {
            assert_eq!(map_name(raw).as_deref(), want, "{raw}");
        }
    }
}
