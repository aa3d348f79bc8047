//! The inputs' declared ranges: the `min`, `max` and `nominal` the model
//! description carries, and what a set value is checked against (a value
//! outside, or NaN or infinite, gives `fmi3Warning` and a log line).
//!
//! The damper's are the table's: the displacement over the union of the
//! entries' fitted strokes, the current over the tabulated currents (both
//! widened to include 0, the inputs' start value: first contact, coil off);
//! the velocity over ± the installation's fastest impact (`impact_v_max_m_s`,
//! the speed the drops it was fitted on reach; the table stores no velocity
//! range). The controller's are its sensors': 0 to the displacement sensor's
//! range, ± the velocity sensor's full scale.
//!
//! A value outside is still handled, as the board's core handles it: the
//! damper clamps x to each entry's stroke and the current to the table
//! (NaN: x → each entry's x_min, current → the lowest, v → the extension
//! branch without viscous force), so the force stays finite; the controller
//! feeds it to its sensor checks, which latch the fail-safe current.
use crate::describe::Kind;
use mre_algorithm::Table;

/// One input's declared range (SI units, as the variable's name says).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InputRange {
    pub name: &'static str,
    pub min: f64,
    pub max: f64,
    pub nominal: f64,
}

impl InputRange {
    /// Whether `value` lies in the range (false for NaN).
    pub fn contains(&self, value: f64) -> bool {
        value >= self.min && value <= self.max
    }
}

/// The ranges of `kind`'s inputs for `table` (with its installation).
pub fn input_ranges(kind: Kind, table: &Table) -> Vec<InputRange> {
    let inst = table.installation();
    match kind {
        Kind::Damper => {
            let entries = table.entries();
            let x_min_mm = entries.iter().map(|e| e.x_min_mm).fold(0.0f32, f32::min);
            let x_max_mm = entries.iter().map(|e| e.x_max_mm).fold(0.0f32, f32::max);
            let (lo_a, hi_a) = table.current_range_a();
            let (i_min, i_max) = (f64::from(lo_a.min(0.0)), f64::from(hi_a.max(0.0)));
            let v_max = f64::from(inst.impact_v_max_m_s);
            let (x_min, x_max) = (f64::from(x_min_mm) * 1.0e-3, f64::from(x_max_mm) * 1.0e-3);
            vec![
                InputRange {
                    name: "displacement_m",
                    min: x_min,
                    max: x_max,
                    nominal: nominal(x_min, x_max),
                },
                InputRange {
                    name: "velocity_m_s",
                    min: -v_max,
                    max: v_max,
                    nominal: nominal(-v_max, v_max),
                },
                InputRange {
                    name: "current_a",
                    min: i_min,
                    max: i_max,
                    nominal: nominal(i_min, i_max),
                },
            ]
        }
        Kind::Controller => {
            let x_max = f64::from(inst.x_sensor_range_mm) * 1.0e-3;
            let v_max = f64::from(inst.v_sensor_full_scale_m_s);
            vec![
                InputRange {
                    name: "displacement_m",
                    min: 0.0,
                    max: x_max,
                    nominal: nominal(0.0, x_max),
                },
                InputRange {
                    name: "velocity_m_s",
                    min: -v_max,
                    max: v_max,
                    nominal: nominal(-v_max, v_max),
                },
            ]
        }
    }
}

/// The magnitude a value of the range is typically of (FMI: nominal > 0).
fn nominal(min: f64, max: f64) -> f64 {
    let m = min.abs().max(max.abs());
    if m > 0.0 {
        m
    } else {
        1.0
    }
}

/// Why `value` of `range` gives a warning, or `None` when it lies in it.
pub fn complaint(range: &InputRange, value: f64) -> Option<String> {
    if !value.is_finite() {
        Some(format!(
            "{} = {value} is not a number: handled as the board's core handles a failed sensor \
             (damper: x at each entry's x_min, current at the lowest, velocity on the extension branch; \
             controller: its sensor checks)",
            range.name
        ))
    } else if !range.contains(value) {
        Some(format!(
            "{} = {value} is outside its declared range [{}, {}] (where the model has data): \
             the damper clamps it to the table, the controller's sensor checks judge it",
            range.name, range.min, range.max
        ))
    } else {
        None
    }
}
