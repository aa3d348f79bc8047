//! Fig. 15-style overlays: for every recording, one panel per family with
//! the measured loop (grey) under the family's prediction (colour), all
//! panels on the same axes, so eight families stay readable. Files are
//! `plots/<current>_<recording>.png|svg`, grouped by current by their names.
use super::tracks::nrmse;
use super::Comparison;
use crate::dataset::Role;
use crate::plot::{current_tag, PALETTE};
use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Points per drawn line (the SVGs stay small; the loops are smooth at this density).
const MAX_POINTS: usize = 1500;
const SIZE: (u32, u32) = (1800, 1000);
/// The font `crate::plot` registers (bundled DejaVu Sans).
const FONT: &str = "sans-serif";
const MEASURED: RGBColor = RGBColor(170, 170, 170);

/// Colours beyond the shared palette (the comparison draws up to 8 families).
const EXTRA: [RGBColor; 2] = [RGBColor(140, 86, 75), RGBColor(188, 189, 34)];

fn colour(i: usize) -> RGBColor {
    let own: Vec<RGBColor> = PALETTE.iter().chain(&EXTRA).copied().collect();
    own[i % own.len()]
}

fn err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("plotting failed: {e:?}")
}

/// Every `stride`-th (x, y) pair with a finite y.
fn thin(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    let stride = x.len().div_ceil(MAX_POINTS).max(1);
    x.iter()
        .zip(y)
        .step_by(stride)
        .filter(|(_, y)| y.is_finite())
        .map(|(&x, &y)| (x, y))
        .collect()
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &Comparison, k: usize) -> Result<()> {
    let t = &c.tracks[k];
    root.fill(&WHITE).map_err(err)?;
    let role = match t.role {
        Role::Fit => "fitted",
        Role::Validate => "held out: predicted, never fitted",
    };
    let (head, body) = root.split_vertically(60);
    head.draw_text(
        &format!(
            "{} at {} A ({role}) — measured (grey) vs each family",
            t.stem, t.current_a
        ),
        &(FONT, 30).into_text_style(&head),
        (20, 15),
    )
    .map_err(err)?;
    let (x0, x1) = crate::fit::poly::min_max(&t.x_mm);
    let (f0, f1) = crate::fit::poly::min_max(&t.force_n);
    let pad = 0.15 * (f1 - f0).max(1e-9);
    let measured = thin(&t.x_mm, &t.force_n);
    let cols = c.outcomes.len().div_ceil(2).max(1);
    for (i, (panel, o)) in body.split_evenly((2, cols)).iter().zip(&c.outcomes).enumerate() {
        let mut ch = ChartBuilder::on(panel)
            .caption(
                format!("{} — NRMSE {:.1} %", o.name, 100.0 * nrmse(t, &o.predictions[k])),
                (FONT, 22),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1.max(x0 + 1e-9), (f0 - pad)..(f1 + pad))
            .map_err(err)?;
        ch.configure_mesh()
            .x_desc("x (mm)")
            .y_desc("F (N)")
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 16))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(err)?;
        ch.draw_series(LineSeries::new(measured.iter().copied(), MEASURED.stroke_width(4)))
            .map_err(err)?;
        ch.draw_series(LineSeries::new(
            thin(&t.x_mm, &o.predictions[k]),
            colour(i).stroke_width(2),
        ))
        .map_err(err)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

/// Writes one figure per recording under `dir`; returns the base paths.
pub fn overlays(c: &Comparison, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (k, t) in c.tracks.iter().enumerate() {
        let base = format!("{}_{}", current_tag(t.current_a), t.stem);
        // The PNG first: `render_png` registers the bundled font the SVG uses too.
        crate::plot::chart::render_png(&dir.join(format!("{base}.png")), SIZE, |root| draw(root, c, k))?;
        let mut svg = String::new();
        draw(&SVGBackend::with_string(&mut svg, SIZE).into_drawing_area(), c, k)?;
        crate::atomic_write::write_atomic(&dir.join(format!("{base}.svg")), svg.as_bytes())?;
        written.push(dir.join(base));
    }
    Ok(written)
}
