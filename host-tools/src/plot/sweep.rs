//! Figs. 13 and 14: the performance index against iterations and agents.
use super::chart::{render, Chart, Series, Style, PALETTE};
use crate::fit::sweep::{Sweep, SweepPoint};
use crate::fit::FitOptions;
use anyhow::Result;
use std::path::Path;

fn series(points: &[SweepPoint], x: impl Fn(&SweepPoint) -> usize) -> Vec<Series> {
    vec![
        Series {
            label: "GSA".into(),
            points: points.iter().map(|p| (x(p) as f64, p.mean_gsa_over_lsq)).collect(),
            color: PALETTE[0],
            style: Style::Line { width: 3 },
        },
        Series {
            label: "least-squares optimum".into(),
            points: points.iter().map(|p| (x(p) as f64, 1.0)).collect(),
            color: PALETTE[6],
            style: Style::Dashed { width: 2 },
        },
    ]
}

pub fn render_sweep(s: &Sweep, base: &FitOptions, dir: &Path) -> Result<()> {
    let y = "performance index: mean RMSE / least-squares RMSE (–)".to_string();
    render(
        &Chart {
            title: format!("Performance index vs iterations (N = {} agents)", base.gsa.agents),
            x_label: "iterations T".into(),
            y_label: y.clone(),
            series: series(&s.vs_iters, |p| p.iters),
        },
        &dir.join("fig13_index_vs_iterations"),
    )?;
    render(
        &Chart {
            title: format!("Performance index vs agents (T = {} iterations)", base.gsa.iters),
            x_label: "agents N".into(),
            y_label: y,
            series: series(&s.vs_agents, |p| p.agents),
        },
        &dir.join("fig14_index_vs_agents"),
    )?;
    Ok(())
}
