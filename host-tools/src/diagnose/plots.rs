//! The diagnosis's plots: residual maps, residual against covariates, and
//! before/after loops of the worst recordings. Rendered through
//! `plot::chart::render_png` (bundled font, atomic write).
use super::locate;
use super::Diagnosis;
use crate::plot::chart::render_png;
use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

fn range(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = vals
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9);
    (lo - pad, hi + pad)
}

fn current_color(d: &Diagnosis, current_a: f64) -> RGBColor {
    // Ten distinct colours (tab10), so nine currents never share one.
    const PALETTE: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    let k = distinct_currents(d).iter().position(|&c| c == current_a).unwrap_or(0);
    PALETTE[k % PALETTE.len()]
}

fn distinct_currents(d: &Diagnosis) -> Vec<f64> {
    let mut cs: Vec<f64> = d.prep.recs.iter().map(|r| r.current_a).collect();
    cs.sort_by(f64::total_cmp);
    cs.dedup();
    cs
}

/// Keeps at most ~`max` points per series (stride sampling).
fn stride(n_total: usize, max: usize) -> usize {
    n_total.div_ceil(max).max(1)
}

/// A scatter of `(x, y)` per current, in one chart.
fn scatter_by_current(
    area: &Area,
    d: &Diagnosis,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    pts: &[(f64, f64, f64)],
    radius: u32,
) -> Result<()> {
    let (x0, x1) = range(pts.iter().map(|p| p.0));
    let (y0, y1) = range(pts.iter().map(|p| p.1));
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    for c in distinct_currents(d) {
        let color = current_color(d, c);
        let series: Vec<(f64, f64)> = pts.iter().filter(|p| p.2 == c).map(|p| (p.0, p.1)).collect();
        if series.is_empty() {
            continue;
        }
        chart
            .draw_series(
                series
                    .iter()
                    .map(|&(x, y)| Circle::new((x, y), radius, color.mix(0.6).filled())),
            )
            .map_err(|e| anyhow!("{e}"))?
            .label(format!("{c} A"))
            .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// Residual of the baseline against displacement, per branch.
pub fn residual_map(d: &Diagnosis, path: &Path) -> Result<()> {
    let total: usize = d.prep.recs.iter().map(|r| r.len()).sum();
    let k = stride(total, 30_000);
    let mut comp = Vec::new();
    let mut ext = Vec::new();
    for (i, r) in d.prep.recs.iter().enumerate() {
        for t in (0..r.len()).step_by(k) {
            let p = (r.x_mm[t], r.force_n[t] - d.baseline_pred[i][t], r.current_a);
            if r.v_m_s[t] > 0.0 {
                comp.push(p);
            } else {
                ext.push(p);
            }
        }
    }
    render_png(path, (1400, 600), |root| {
        let panels = root.split_evenly((1, 2));
        scatter_by_current(
            &panels[0],
            d,
            "Baseline residual, compression (v > 0)",
            "displacement x (mm)",
            "measured − model force (N)",
            &comp,
            1,
        )?;
        scatter_by_current(
            &panels[1],
            d,
            "Baseline residual, extension (v ≤ 0)",
            "displacement x (mm)",
            "measured − model force (N)",
            &ext,
            1,
        )
    })
}

/// Residual against velocity and acceleration (per sample) and the
/// per-recording residual scale against run order and peak velocity.
pub fn residual_covariates(d: &Diagnosis, path: &Path) -> Result<()> {
    let total: usize = d.prep.recs.iter().map(|r| r.len()).sum();
    let k = stride(total, 30_000);
    let (mut vel, mut acc, mut seq, mut peak) = (vec![], vec![], vec![], vec![]);
    for (i, r) in d.prep.recs.iter().enumerate() {
        let p = &d.baseline_pred[i];
        for t in (0..r.len()).step_by(k) {
            let res = r.force_n[t] - p[t];
            vel.push((r.v_m_s[t], res, r.current_a));
            acc.push((r.a_m_s2[t], res, r.current_a));
        }
        let scale = locate::residual_scale(&r.force_n, p) * 100.0;
        seq.push((r.sequence.unwrap_or((i + 1) as f64), scale, r.current_a));
        peak.push((r.max_abs_v_m_s(), scale, r.current_a));
    }
    let seq_label = if d.prep.recs.iter().any(|r| r.sequence.is_some()) {
        "run order (sequence)"
    } else {
        "recording index (no sequence recorded)"
    };
    render_png(path, (1400, 1000), |root| {
        let p = root.split_evenly((2, 2));
        let y = "measured − model force (N)";
        scatter_by_current(&p[0], d, "Residual vs velocity", "velocity v (m/s)", y, &vel, 1)?;
        scatter_by_current(
            &p[1],
            d,
            "Residual vs acceleration",
            "acceleration a (m/s²)",
            y,
            &acc,
            1,
        )?;
        let ys = "residual scale Σr·F̂/ΣF̂² (%)";
        scatter_by_current(
            &p[2],
            d,
            "Per recording: residual scale vs run order",
            seq_label,
            ys,
            &seq,
            4,
        )?;
        scatter_by_current(
            &p[3],
            d,
            "Per recording: residual scale vs peak velocity",
            "peak |v| (m/s)",
            ys,
            &peak,
            4,
        )
    })
}

/// Force–displacement loops of the three worst recordings (by baseline RMSE),
/// drawn over the scored samples only: a branch-ambiguous sample, or a stretch
/// outside the fitted stroke, breaks the lines instead of drawing a spike.
pub fn loops_worst(d: &Diagnosis, path: &Path) -> Result<()> {
    let mut order: Vec<(usize, f64)> = d
        .prep
        .recs
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let (se, n) = (0..r.len())
                .filter(|&t| d.scored_mask[i][t])
                .map(|t| (r.force_n[t] - d.baseline_pred[i][t]).powi(2))
                .fold((0.0, 0usize), |(s, n), e| (s + e, n + 1));
            (i, se / n.max(1) as f64)
        })
        .collect();
    order.sort_by(|a, b| b.1.total_cmp(&a.1));
    let worst: Vec<usize> = order.iter().take(3).map(|o| o.0).collect();
    render_png(path, (600 * worst.len().max(1) as u32, 550), |root| {
        let panels = root.split_evenly((1, worst.len().max(1)));
        for (panel, &i) in panels.iter().zip(&worst) {
            let r = &d.prep.recs[i];
            let k = stride(r.len(), 4000);
            let idx: Vec<usize> = (0..r.len()).step_by(k).filter(|&t| d.scored_mask[i][t]).collect();
            // Runs of consecutive drawn samples, also split where x turns
            // around: a thick polyline that doubles back on itself gets a
            // miter join that shoots off the chart.
            let mut runs: Vec<Vec<usize>> = Vec::new();
            for &t in &idx {
                match runs.last_mut() {
                    Some(run) if run.last().is_some_and(|&p| t - p <= k) => {
                        let turns = match run[..] {
                            [.., a, b] => (r.x_mm[b] - r.x_mm[a]) * (r.x_mm[t] - r.x_mm[b]) < 0.0,
                            _ => false,
                        };
                        if turns {
                            let b = run[run.len() - 1];
                            runs.push(vec![b, t]);
                        } else {
                            run.push(t);
                        }
                    }
                    _ => runs.push(vec![t]),
                }
            }
            let (x0, x1) = range(idx.iter().map(|&t| r.x_mm[t]));
            let (y0, y1) = range(
                idx.iter()
                    .flat_map(|&t| [r.force_n[t], d.baseline_pred[i][t], d.final_pred[i][t]]),
            );
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{} ({} A)", r.file, r.current_label()), ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .configure_mesh()
                .x_desc("displacement x (mm)")
                .y_desc("force F (N)")
                .label_style(("sans-serif", 14))
                .axis_desc_style(("sans-serif", 16))
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
            let series: [(&str, &[f64], RGBColor); 3] = [
                ("measured", &r.force_n, RGBColor(90, 90, 90)),
                ("baseline model", &d.baseline_pred[i], RGBColor(214, 39, 40)),
                ("after diagnosis", &d.final_pred[i], RGBColor(31, 119, 180)),
            ];
            for (name, y, color) in series {
                chart
                    .draw_series(runs.iter().map(|run| {
                        PathElement::new(
                            run.iter().map(|&t| (r.x_mm[t], y[t])).collect::<Vec<_>>(),
                            color.stroke_width(2),
                        )
                    }))
                    .map_err(|e| anyhow!("{e}"))?
                    .label(name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3)));
            }
            chart
                .configure_series_labels()
                .label_font(("sans-serif", 14))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
        }
        Ok(())
    })
}
