//! Plots (PNG + SVG) of the paper's figures: measured vs modelled loops per
//! current (Fig. 8), all currents (Fig. 9), interpolated currents (Fig. 11),
//! interpolated vs neighbours (Fig. 12), GSA convergence, and the sweep
//! (Figs. 13/14).
pub mod chart;
pub mod figures;
pub mod sweep;

pub use chart::{render, Chart, Series, Style, PALETTE};
pub use figures::{run_plot, PlotOptions};

/// "0p5A" for 0.5 A: a file-name-safe current tag.
pub fn current_tag(current_a: f64) -> String {
    format!("{current_a}A").replace('.', "p").replace('-', "m")
}
