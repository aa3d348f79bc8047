//! PNG plots of simulated impacts (force–time and force–displacement).
//! Rendered through `plot::chart::render_png` (bundled font, atomic write).
use super::closed_loop::Comparison;
use crate::plot::chart::{LegendSample, SampleLook};
use anyhow::{anyhow, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

const SIZE: (u32, u32) = (1000, 640);
/// Plot area height of [`SIZE`] after the caption, margins and x labels.
const PLOT_PX: u32 = SIZE.1 - 40 - 32 - 50;
/// The legend's font size (px).
const LEGEND_FONT_PX: u32 = 16;
/// The figures' one palette (Okabe–Ito).
const COLOURS: [RGBColor; 7] = crate::plot::chart::PALETTE;

fn png_atomic(path: &Path, draw: impl FnOnce(&Area) -> Result<()>) -> Result<()> {
    crate::plot::chart::render_png(path, SIZE, draw)
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type ForceChart<'a, 'b> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Captioned axes from 0 with force (N) upwards, shared by both plots.
fn force_axes<'a, 'b>(
    root: &'a Area<'b>,
    caption: &str,
    x_desc: &str,
    x_hi: f64,
    f_hi: f64,
) -> Result<ForceChart<'a, 'b>> {
    let mut chart = ChartBuilder::on(root)
        .caption(caption, ("sans-serif", 26))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..x_hi, 0.0..f_hi)
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc("force on the damper (N)")
        .y_label_formatter(&|v| format!("{v:.0}"))
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    Ok(chart)
}

fn legend<'a, 'b: 'a>(chart: &mut ForceChart<'a, 'b>, position: SeriesLabelPosition) -> Result<()> {
    chart
        .configure_series_labels()
        .label_font(("sans-serif", LEGEND_FONT_PX))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .position(position)
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// A legend sample dashed as its line is (`dash` px on, `gap` px off, 2 px wide).
fn dashed_sample(at: (i32, i32), colour: RGBColor, dash: i32, gap: i32) -> LegendSample {
    LegendSample::new(at, SampleLook::Dashes { width: 2, dash, gap }, colour)
}

/// Measured force against time since contact, one line per run.
pub fn force_time_png(cmp: &Comparison, path: &Path) -> Result<()> {
    let all = || cmp.runs.iter().flat_map(|r| r.trajectory.samples.iter());
    let (_, t_max) = bounds(all().map(|s| s.time_s * 1e3));
    let (_, f_max) = bounds(all().map(|s| s.force_n));
    png_atomic(path, |root| {
        let mut chart = force_axes(
            root,
            "Drop impact: force against time",
            "time since contact (ms)",
            t_max * 1.02,
            crate::plot::chart::with_legend_room(0.0, f_max * 1.02, cmp.runs.len(), LEGEND_FONT_PX, PLOT_PX),
        )?;
        for (i, run) in cmp.runs.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let points = run.trajectory.samples.iter().map(|s| (s.time_s * 1e3, s.force_n));
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?
                .label(format!("{} (peak {:.0} N)", run.label, run.summary.peak_force_n))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    })
}

/// Measured force against measured displacement, with the usable stroke.
pub fn force_displacement_png(cmp: &Comparison, path: &Path) -> Result<()> {
    force_displacement_with_limit_png(cmp, None, path)
}

/// [`force_displacement_png`] with a horizontal line at `limit_n` (the
/// physical limit of `mre bench-control`), if given.
pub fn force_displacement_with_limit_png(cmp: &Comparison, limit_n: Option<f64>, path: &Path) -> Result<()> {
    let all = || cmp.runs.iter().flat_map(|r| r.trajectory.samples.iter());
    let (_, x_max) = bounds(all().map(|s| s.x_mm));
    let (_, f_max) = bounds(all().map(|s| s.force_n));
    let stroke = cmp.runs.first().map_or(x_max, |r| r.usable_stroke_mm);
    let x_hi = x_max.max(stroke) * 1.05;
    png_atomic(path, |root| {
        let mut chart = force_axes(
            root,
            "Drop impact: force against displacement",
            "displacement (mm, compression positive)",
            x_hi,
            // One legend row per run, plus the stroke and the limit lines.
            crate::plot::chart::with_legend_room(
                0.0,
                f_max.max(limit_n.unwrap_or(0.0)) * 1.02,
                cmp.runs.len() + 2,
                LEGEND_FONT_PX,
                PLOT_PX,
            ),
        )?;
        for (i, run) in cmp.runs.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let points = run.trajectory.samples.iter().map(|s| (s.x_mm, s.force_n));
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?
                .label(format!("{} (stroke {:.1} mm)", run.label, run.summary.max_stroke_mm))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
        }
        let grey = RGBColor(90, 90, 90);
        chart
            .draw_series(DashedLineSeries::new(
                vec![(stroke, 0.0), (stroke, f_max * 1.08)],
                8,
                6,
                grey.stroke_width(2),
            ))
            .map_err(|e| anyhow!("{e}"))?
            .label(format!("usable stroke {stroke:.0} mm"))
            .legend(move |at| dashed_sample(at, grey, 8, 6));
        if let Some(limit) = limit_n {
            let black = RGBColor(0, 0, 0);
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(0.0, limit), (x_hi, limit)],
                    4,
                    4,
                    black.stroke_width(2),
                ))
                .map_err(|e| anyhow!("{e}"))?
                .label(format!("physical limit {limit:.0} N"))
                .legend(move |at| dashed_sample(at, black, 4, 4));
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    })
}
