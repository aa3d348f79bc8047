//! Fig. 15-style overlays: for every recording, the measured force against
//! displacement with every family's prediction on top, grouped by current in
//! the file names (`<current>_<recording>.png|svg`).
use super::Comparison;
use crate::dataset::Role;
use crate::plot::{current_tag, render, Chart, Series, Style, PALETTE};
use anyhow::Result;
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

/// Points per drawn series (the SVGs stay small; the loops are smooth at this density).
const MAX_POINTS: usize = 1500;

/// Colours beyond the shared palette (the comparison draws up to 8 families).
const EXTRA: [RGBColor; 3] = [RGBColor(120, 120, 120), RGBColor(140, 86, 75), RGBColor(188, 189, 34)];

fn colour(i: usize) -> RGBColor {
    // The palette's black is kept for the measured samples.
    let own: Vec<RGBColor> = PALETTE[..PALETTE.len() - 1].iter().chain(&EXTRA).copied().collect();
    own[i % own.len()]
}

/// Writes one overlay per recording under `dir`; returns the base paths.
pub fn overlays(c: &Comparison, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (k, t) in c.tracks.iter().enumerate() {
        let stride = t.len().div_ceil(MAX_POINTS).max(1);
        let pick = |ys: &[f64]| -> Vec<(f64, f64)> {
            t.x_mm
                .iter()
                .zip(ys)
                .step_by(stride)
                .filter(|(_, y)| y.is_finite())
                .map(|(&x, &y)| (x, y))
                .collect()
        };
        let mut series = vec![Series {
            label: "measured".into(),
            points: pick(&t.force_n),
            color: PALETTE[PALETTE.len() - 1],
            style: Style::Dots,
        }];
        for (i, o) in c.outcomes.iter().enumerate() {
            series.push(Series {
                label: o.name.clone(),
                points: pick(&o.predictions[k]),
                color: colour(i),
                style: if o.kind == "polynomial" {
                    Style::Dashed { width: 2 }
                } else {
                    Style::Line { width: 2 }
                },
            });
        }
        let role = match t.role {
            Role::Fit => "fitted",
            Role::Validate => "held out, predicted",
        };
        let chart = Chart {
            title: format!("{} — {} A ({role}): measured vs every family", t.stem, t.current_a),
            x_label: "displacement x (mm)".into(),
            y_label: "force F (N)".into(),
            series,
        };
        let base = dir.join(format!("{}_{}", current_tag(t.current_a), t.stem));
        render(&chart, &base)?;
        written.push(base);
    }
    Ok(written)
}
