//! The physical limit of a drop: the lowest peak force any coil-current
//! profile can achieve while stopping the mass within the usable stroke.
//!
//! The damper's force at (x, v) can be anything between its force at the
//! lowest and at the highest current (the coil's limits, here 0–2 A, the
//! current taken as instant). To stop within the stroke with the lowest
//! peak, the force is held at a level P wherever the envelope allows:
//! `F = clamp(P, F(x, v, I_min), F(x, v, I_max))`. Below P only at small
//! strokes (where even I_max gives less) and above it only where even
//! I_min gives more (the elastomer's own stiffness late in the stroke). The
//! limit is the lowest peak of such a drop over P among those that stop
//! within the stroke. [`Limit::ceiling_only_n`] is the same without the
//! I_min floor: the constant force capped at small strokes by the I_max
//! envelope (the definition issue 11 quotes, 1242 N on the nominal plant).
use crate::plant::{ImpactConfig, Plant};
use anyhow::{bail, Result};
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Limit {
    /// Lowest achievable peak force with the current anywhere in its range (N).
    pub envelope_n: f64,
    /// The constant force capped by the I_max envelope that just uses the stroke (N).
    pub ceiling_only_n: f64,
}

/// One drop under `F = clamp(level, floor, ceiling)` (floor 0 when
/// `with_floor` is false): (stroke used in mm, peak force in N). RK4 at the
/// impact's step until the mass stops.
fn capped_drop(
    plant: &Plant,
    impact: &ImpactConfig,
    range_a: (f64, f64),
    level_n: f64,
    with_floor: bool,
) -> (f64, f64) {
    let (m, g, h) = (impact.mass_kg, impact.gravity_m_s2, impact.step_s);
    let force = |x_m: f64, v: f64| {
        let x_mm = x_m * 1e3;
        let ceiling = plant.force_n(x_mm, v, range_a.1, impact.sequence);
        let floor = if with_floor {
            plant.force_n(x_mm, v, range_a.0, impact.sequence)
        } else {
            0.0
        };
        level_n.min(ceiling).max(floor)
    };
    let accel = |x: f64, v: f64| g - force(x, v) / m;
    let (mut x, mut v, mut peak) = (0.0f64, impact.impact_velocity_m_s, 0.0f64);
    let max_steps = (impact.max_duration_s / h) as usize;
    for _ in 0..max_steps {
        let k1 = (v, accel(x, v));
        let k2 = (v + 0.5 * h * k1.1, accel(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1));
        let k3 = (v + 0.5 * h * k2.1, accel(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1));
        let k4 = (v + h * k3.1, accel(x + h * k3.0, v + h * k3.1));
        x += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        peak = peak.max(force(x, v));
        if v <= 0.0 {
            break;
        }
    }
    (x * 1e3, peak)
}

/// The lowest level whose drop stops within `stroke_mm` (stroke falls as the
/// level rises), by bisection.
fn lowest_level(stroke_at: impl Fn(f64) -> f64, stroke_mm: f64) -> Result<f64> {
    let (mut lo, mut hi) = (1.0f64, 1.0e6f64);
    if stroke_at(hi) > stroke_mm {
        bail!("no force level stops the drop within {stroke_mm} mm");
    }
    for _ in 0..60 {
        let mid = (lo * hi).sqrt();
        if stroke_at(mid) > stroke_mm {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(hi)
}

/// The limit for `plant` and `impact` with the coil current in `range_a`.
pub fn physical_limit(plant: &Plant, impact: &ImpactConfig, range_a: (f64, f64), stroke_mm: f64) -> Result<Limit> {
    let ceiling_level = lowest_level(|p| capped_drop(plant, impact, range_a, p, false).0, stroke_mm)?;
    let ceiling_only_n = capped_drop(plant, impact, range_a, ceiling_level, false).1;
    // With the floor, a higher level can lower the peak (the mass stops
    // earlier, where the floor is lower): scan levels above the lowest.
    let first = lowest_level(|p| capped_drop(plant, impact, range_a, p, true).0, stroke_mm)?;
    let envelope_n = (0..=80)
        .map(|k| first * (1.0 + 0.005 * k as f64))
        .map(|p| capped_drop(plant, impact, range_a, p, true))
        .filter(|(stroke, _)| *stroke <= stroke_mm)
        .map(|(_, peak)| peak)
        .fold(f64::INFINITY, f64::min);
    Ok(Limit {
        envelope_n,
        ceiling_only_n,
    })
}
