//! `mre model`: the model's compression and extension curves at one current.
use anyhow::{bail, Result};
use mre_algorithm::model::Branch;
use mre_algorithm::table::Table;
use std::io::Write;

/// One point of a force-displacement loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopPoint {
    pub x_mm: f64,
    pub compression_n: f64,
    pub extension_n: f64,
}

/// The stroke both bracketing entries were fitted on (their overlap), so no
/// point of an interpolated loop is a clamped extrapolation.
pub fn fitted_stroke_mm(table: &Table, current_a: f32) -> (f32, f32) {
    let seg = table.segment(current_a);
    let entries = table.entries();
    let mut lo = f32::NEG_INFINITY;
    let mut hi = f32::INFINITY;
    let upper = if seg.t > 0.0 { seg.lower + 1 } else { seg.lower };
    for e in entries.iter().take(upper + 1).skip(seg.lower) {
        lo = lo.max(e.x_min_mm);
        hi = hi.min(e.x_max_mm);
    }
    (lo, hi)
}

/// `points` evenly spaced samples of both branches over the fitted stroke.
pub fn model_loop(table: &Table, current_a: f32, points: usize) -> Result<Vec<LoopPoint>> {
    if !current_a.is_finite() {
        bail!("--current must be a finite number of amperes, got {current_a}");
    }
    let (lo_a, hi_a) = table.current_range_a();
    if current_a < lo_a || current_a > hi_a {
        bail!("--current {current_a} A is outside the table's range {lo_a}..{hi_a} A");
    }
    if points < 2 {
        bail!("--points must be at least 2");
    }
    let (x0, x1) = fitted_stroke_mm(table, current_a);
    if x0 >= x1 {
        bail!("the entries around {current_a} A share no fitted stroke");
    }
    Ok((0..points)
        .map(|i| {
            let x = x0 + (x1 - x0) * i as f32 / (points - 1) as f32;
            LoopPoint {
                x_mm: x as f64,
                compression_n: table.force_on_branch(x, Branch::Compression, current_a).force_n as f64,
                extension_n: table.force_on_branch(x, Branch::Extension, current_a).force_n as f64,
            }
        })
        .collect())
}

/// CSV with header `x_mm,compression_force_n,extension_force_n`.
pub fn write_loop_csv(out: &mut impl Write, points: &[LoopPoint]) -> Result<()> {
    let mut w = csv::Writer::from_writer(out);
    w.write_record(["x_mm", "compression_force_n", "extension_force_n"])?;
    for p in points {
        w.write_record([
            p.x_mm.to_string(),
            p.compression_n.to_string(),
            p.extension_n.to_string(),
        ])?;
    }
    w.flush()?;
    Ok(())
}
