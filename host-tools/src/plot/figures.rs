//! Builds the figures from a data set and a model file.
use super::chart::{render, Chart, Series, Style, PALETTE};
use super::current_tag;
use crate::dataset::{Dataset, Role};
use crate::fit::model_file::ModelFile;
use crate::loops::model_loop;
use anyhow::Result;
use mre_algorithm::model::Branch;
use mre_algorithm::table::Table;
use std::path::{Path, PathBuf};

/// Most measured dots per chart (evenly thinned), so loops stay readable.
const MAX_DOTS: usize = 6000;

#[derive(Clone, Debug, PartialEq)]
pub struct PlotOptions {
    /// Extra currents to draw interpolated loops at (Fig. 11). Empty: midpoints
    /// between adjacent table entries plus every validate-recording current.
    pub interpolated_a: Vec<f64>,
}

/// A force–displacement chart (Figs. 8, 9, 11, 12) to `{base}.png/.svg`.
fn render_loops(title: String, series: Vec<Series>, base: &Path) -> Result<()> {
    render(
        &Chart {
            title,
            x_label: "displacement x (mm)".into(),
            y_label: "force F (N)".into(),
            series,
        },
        base,
    )
}

/// The model loop at `current_a` as one closed path (compression out, extension back).
fn model_path(table: &Table, current_a: f64) -> Result<Vec<(f64, f64)>> {
    let pts = model_loop(table, current_a as f32, 201)?;
    let mut path: Vec<(f64, f64)> = pts.iter().map(|p| (p.x_mm, p.compression_n)).collect();
    path.extend(pts.iter().rev().map(|p| (p.x_mm, p.extension_n)));
    Ok(path)
}

fn measured_dots(ds: &Dataset, current_a: f64) -> Vec<(f64, f64)> {
    let all: Vec<(f64, f64)> = ds
        .recordings
        .iter()
        .filter(|r| r.current_a == current_a)
        .flat_map(|r| r.samples.x_mm.iter().copied().zip(r.samples.force_n.iter().copied()))
        .collect();
    let step = all.len().div_ceil(MAX_DOTS).max(1);
    all.into_iter().step_by(step).collect()
}

fn line(label: String, points: Vec<(f64, f64)>, i: usize) -> Series {
    Series {
        label,
        points,
        color: PALETTE[i % PALETTE.len()],
        style: Style::Line { width: 3 },
    }
}

/// Fig. 8: measured (dots) against modelled (line) per table current.
pub fn fig08(ds: &Dataset, table: &Table, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for e in table.entries() {
        let c = e.current_a as f64;
        let dots = measured_dots(ds, c);
        let mut series = Vec::new();
        if !dots.is_empty() {
            series.push(Series {
                label: format!("measured, {c} A"),
                points: dots,
                color: PALETTE[0],
                style: Style::Dots,
            });
        }
        series.push(line(format!("model, {c} A"), model_path(table, c)?, 1));
        let base = dir.join(format!("fig08_loop_{}", current_tag(c)));
        render_loops(
            format!("Measured vs modelled force–displacement loop at {c} A"),
            series,
            &base,
        )?;
        out.push(base);
    }
    Ok(out)
}

/// Fig. 9: every table current's model loop superimposed.
pub fn fig09(table: &Table, dir: &Path) -> Result<PathBuf> {
    let series = table
        .entries()
        .iter()
        .enumerate()
        .map(|(i, e)| {
            Ok(line(
                format!("{} A", e.current_a),
                model_path(table, e.current_a as f64)?,
                i,
            ))
        })
        .collect::<Result<Vec<_>>>()?;
    let base = dir.join("fig09_all_currents");
    render_loops("Modelled loops at every tabulated current".into(), series, &base)?;
    Ok(base)
}

/// The currents drawn by interpolation (Fig. 11).
pub fn interpolated_currents(ds: &Dataset, table: &Table, options: &PlotOptions) -> Vec<f64> {
    let mut cs: Vec<f64> = if options.interpolated_a.is_empty() {
        let e = table.entries();
        let mut v: Vec<f64> = e
            .windows(2)
            .map(|w| 0.5 * (w[0].current_a + w[1].current_a) as f64)
            .collect();
        v.extend(
            ds.recordings
                .iter()
                .filter(|r| r.role == Role::Validate)
                .map(|r| r.current_a),
        );
        v
    } else {
        options.interpolated_a.clone()
    };
    cs.retain(|&c| crate::validate::neighbours(table, c).is_some());
    cs.sort_by(f64::total_cmp);
    cs.dedup();
    cs
}

/// Fig. 11: loops at interpolated currents (dashed) with the table's (solid).
pub fn fig11(table: &Table, currents: &[f64], dir: &Path) -> Result<Option<PathBuf>> {
    if currents.is_empty() {
        return Ok(None);
    }
    let mut series = Vec::new();
    for (i, e) in table.entries().iter().enumerate() {
        series.push(line(
            format!("{} A (table)", e.current_a),
            model_path(table, e.current_a as f64)?,
            i,
        ));
    }
    for (i, &c) in currents.iter().enumerate() {
        series.push(Series {
            label: format!("{c} A (interpolated)"),
            points: model_path(table, c)?,
            color: PALETTE[(table.entries().len() + i) % PALETTE.len()],
            style: Style::Dashed { width: 3 },
        });
    }
    let base = dir.join("fig11_interpolated");
    render_loops("Interpolated loops between tabulated currents".into(), series, &base)?;
    Ok(Some(base))
}

/// Fig. 12: each interpolated loop against its two neighbours (and the
/// measured samples at that current, if any).
pub fn fig12(ds: &Dataset, table: &Table, currents: &[f64], dir: &Path) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for &c in currents {
        let Some((lo, hi)) = crate::validate::neighbours(table, c) else {
            continue;
        };
        let mut series = Vec::new();
        let dots = measured_dots(ds, c);
        if !dots.is_empty() {
            series.push(Series {
                label: format!("measured, {c} A (not fitted)"),
                points: dots,
                color: PALETTE[5],
                style: Style::Dots,
            });
        }
        series.push(line(format!("{lo} A (table)"), model_path(table, lo as f64)?, 0));
        series.push(line(format!("{hi} A (table)"), model_path(table, hi as f64)?, 2));
        series.push(Series {
            label: format!("{c} A (interpolated)"),
            points: model_path(table, c)?,
            color: PALETTE[1],
            style: Style::Dashed { width: 3 },
        });
        let base = dir.join(format!("fig12_bracket_{}", current_tag(c)));
        render_loops(
            format!("Interpolated loop at {c} A between its neighbours"),
            series,
            &base,
        )?;
        out.push(base);
    }
    Ok(out)
}

/// GSA convergence: best-so-far RMSE per iteration, relative to the lsq
/// optimum when the model has it (1 = optimal), else in N.
pub fn convergence(model: &ModelFile, dir: &Path) -> Result<Option<PathBuf>> {
    let mut series = Vec::new();
    let mut relative = true;
    for c in &model.current {
        for b in [Branch::Compression, Branch::Extension] {
            let meta = c.fit.branch(b);
            if meta.lsq_rmse_n.is_none() {
                relative = false;
            }
        }
    }
    let mut i = 0;
    for c in &model.current {
        for b in [Branch::Compression, Branch::Extension] {
            let meta = c.fit.branch(b);
            let Some(curve) = &meta.gsa_convergence_rmse_n else {
                continue;
            };
            let norm = if relative { meta.lsq_rmse_n.unwrap_or(1.0) } else { 1.0 };
            let pts = curve
                .iter()
                .enumerate()
                .map(|(t, v)| ((t + 1) as f64, v / norm))
                .collect();
            series.push(line(
                format!("{} A {}", c.current_a, crate::fit::branch_name(b)),
                pts,
                i,
            ));
            i += 1;
        }
    }
    if series.is_empty() {
        return Ok(None);
    }
    let base = dir.join("gsa_convergence");
    render(
        &Chart {
            title: format!(
                "GSA convergence (N = {}, T = {}, G0 = {}, α = {})",
                model.model.agents, model.model.iters, model.model.g0, model.model.alpha
            ),
            x_label: "iteration".into(),
            y_label: if relative {
                "best RMSE / least-squares RMSE (–)".into()
            } else {
                "best RMSE (N)".into()
            },
            series,
        },
        &base,
    )?;
    Ok(Some(base))
}

/// `mre plot DATASET --model MODEL --out DIR`: every figure the inputs allow.
pub fn run_plot(
    dataset_dir: &Path,
    model_path: &Path,
    hold_out_a: &[f64],
    options: &PlotOptions,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let mut ds = Dataset::load(dataset_dir)?;
    crate::fit::problems::hold_out(&mut ds, hold_out_a);
    let table = crate::table_file::read_table_file(model_path)?;
    let mut out = fig08(&ds, &table, dir)?;
    out.push(fig09(&table, dir)?);
    let currents = interpolated_currents(&ds, &table, options);
    out.extend(fig11(&table, &currents, dir)?);
    out.extend(fig12(&ds, &table, &currents, dir)?);
    // Convergence needs `mre fit` metadata; a plain table file has none.
    if let Ok(model) = crate::fit::model_file::read(model_path) {
        out.extend(convergence(&model, dir)?);
    }
    Ok(out)
}
