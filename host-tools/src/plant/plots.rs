//! PNG plots of simulated impacts (force–time and force–displacement).
//! Text uses the bundled DejaVu Sans, so no system fonts are needed.
use super::closed_loop::Comparison;
use anyhow::{anyhow, Context, Result};
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

/// Registers the bundled font as "sans-serif" (once per process).
fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
        // The font is bundled and known good; if registration failed anyway,
        // plotters reports the missing font when text is drawn.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

const SIZE: (u32, u32) = (1000, 640);
const COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// Renders into a temporary `.png` beside `path`, then renames it into place.
fn png_atomic(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<()>,
) -> Result<()> {
    register_font();
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let tmp = tempfile::Builder::new()
        .prefix(".mre-")
        .suffix(".png")
        .tempfile_in(dir)?;
    {
        let root = BitMapBackend::new(tmp.path(), SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        draw(&root)?;
        root.present()
            .map_err(|e| anyhow!("cannot render {}: {e}", path.display()))?;
    }
    tmp.persist(path)
        .map_err(|e| e.error)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
}

/// Measured force against time since contact, one line per run.
pub fn force_time_png(cmp: &Comparison, path: &Path) -> Result<()> {
    let all = || cmp.runs.iter().flat_map(|r| r.trajectory.samples.iter());
    let (_, t_max) = bounds(all().map(|s| s.time_s * 1e3));
    let (_, f_max) = bounds(all().map(|s| s.force_n));
    png_atomic(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption("Drop impact: force against time", ("sans-serif", 26))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..t_max * 1.02, 0.0..f_max * 1.08)
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("time since contact (ms)")
            .y_desc("force on the damper (N)")
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (i, run) in cmp.runs.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let points = run.trajectory.samples.iter().map(|s| (s.time_s * 1e3, s.force_n));
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?
                .label(format!("{} (peak {:.0} N)", run.label, run.summary.peak_force_n))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        Ok(())
    })
}

/// Measured force against measured displacement, with the usable stroke.
pub fn force_displacement_png(cmp: &Comparison, path: &Path) -> Result<()> {
    let all = || cmp.runs.iter().flat_map(|r| r.trajectory.samples.iter());
    let (_, x_max) = bounds(all().map(|s| s.x_mm));
    let (_, f_max) = bounds(all().map(|s| s.force_n));
    let stroke = cmp.runs.first().map_or(x_max, |r| r.usable_stroke_mm);
    let x_hi = x_max.max(stroke) * 1.05;
    png_atomic(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption("Drop impact: force against displacement", ("sans-serif", 26))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..x_hi, 0.0..f_max * 1.08)
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("displacement (mm, compression positive)")
            .y_desc("force on the damper (N)")
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
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
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(2)));
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        Ok(())
    })
}
