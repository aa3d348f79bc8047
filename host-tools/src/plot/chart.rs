//! One line/scatter chart, rendered to PNG and SVG in memory and written
//! atomically. Text uses the bundled DejaVu Sans (registered once).
use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};
use std::path::Path;

const FONT: &str = "sans-serif";
const SIZE: (u32, u32) = (1200, 800);

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Style {
    Line {
        width: u32,
    },
    Dashed {
        width: u32,
    },
    /// Small translucent dots (measured samples).
    Dots,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    pub style: Style,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// A qualitative palette (Okabe–Ito, readable by colour-blind viewers).
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

fn register_font() -> Result<()> {
    static ONCE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *ONCE.get_or_init(|| {
        plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            include_bytes!("../../assets/fonts/DejaVuSans.ttf"),
        )
        .is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(anyhow!("the bundled font could not be loaded"))
    }
}

fn ranges(chart: &Chart) -> Result<((f64, f64), (f64, f64))> {
    let pts = chart
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0.partial_cmp(&x1) != Some(std::cmp::Ordering::Less) || !y0.is_finite() {
        return Err(anyhow!("chart `{}` has no data to plot", chart.title));
    }
    let pad = |a: f64, b: f64| {
        let d = if b > a { 0.05 * (b - a) } else { 1.0 };
        (a - d, b + d)
    };
    Ok(((x0, x1), pad(y0, y1)))
}

/// The top of a y-range that leaves the upper band of the plot to a legend of
/// `rows` entries in a `font_px` font, over a plot area `plot_px` tall: data up
/// to `hi` stays below the legend, which then never hides it.
pub fn with_legend_room(lo: f64, hi: f64, rows: usize, font_px: u32, plot_px: u32) -> f64 {
    // A row is the text height plus plotters' spacing; the box adds a margin.
    let legend_px = rows as f64 * (1.5 * f64::from(font_px) + 4.0) + 30.0;
    let share = (legend_px / f64::from(plot_px)).min(0.6);
    lo + (hi - lo) / (1.0 - share)
}

/// Plot area height of [`SIZE`] after the caption, margins and x labels.
const PLOT_PX: u32 = SIZE.1 - 45 - 40 - 60;

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &Chart) -> Result<()> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plotting failed: {e:?}");
    let ((x0, x1), (y0, y1)) = ranges(chart)?;
    let y1 = with_legend_room(y0, y1, chart.series.len(), 20, PLOT_PX);
    root.fill(&WHITE).map_err(e)?;
    let mut c = ChartBuilder::on(&root)
        .caption(&chart.title, (FONT, 30))
        .margin(20)
        .margin_right(50)
        .x_label_area_size(60)
        .y_label_area_size(100)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    c.configure_mesh()
        .x_desc(&chart.x_label)
        .y_desc(&chart.y_label)
        .label_style((FONT, 20))
        .axis_desc_style((FONT, 22))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(e)?;
    for s in &chart.series {
        let color = s.color;
        // The legend's sample is drawn as the series is: a line, a dashed line, or dots.
        let style = s.style;
        let anno = match s.style {
            Style::Line { width } => c
                .draw_series(LineSeries::new(s.points.iter().copied(), color.stroke_width(width)))
                .map_err(e)?,
            Style::Dashed { width } => c
                .draw_series(DashedLineSeries::new(
                    s.points.iter().copied(),
                    DASH_PX.0 as u32,
                    DASH_PX.1 as u32,
                    color.stroke_width(width),
                ))
                .map_err(e)?,
            Style::Dots => c
                .draw_series(s.points.iter().map(|&p| Circle::new(p, 2, color.mix(0.25).filled())))
                .map_err(e)?,
        };
        anno.label(s.label.clone())
            .legend(move |at| LegendSample::of(style, color, at));
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 20))
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

/// A legend entry's sample, drawn as its series is (24 px wide): a plotters
/// element of its own, so it carries no backend type (composed elements do,
/// and a legend closure cannot return them).
#[derive(Clone, Copy, Debug)]
pub struct LegendSample {
    at: (i32, i32),
    look: SampleLook,
    color: RGBColor,
}

/// How a [`LegendSample`] is drawn.
#[derive(Clone, Copy, Debug)]
pub enum SampleLook {
    Line {
        width: u32,
    },
    /// Dashes `dash` px long with `gap` px between, as `DashedLineSeries` draws them.
    Dashes {
        width: u32,
        dash: i32,
        gap: i32,
    },
    Dots,
}

/// The dash pattern [`draw`] gives [`Style::Dashed`] series.
const DASH_PX: (i32, i32) = (10, 6);

impl LegendSample {
    pub fn new(at: (i32, i32), look: SampleLook, color: RGBColor) -> Self {
        Self { at, look, color }
    }

    fn of(style: Style, color: RGBColor, at: (i32, i32)) -> Self {
        let look = match style {
            Style::Line { width } => SampleLook::Line { width },
            Style::Dashed { width } => SampleLook::Dashes {
                width,
                dash: DASH_PX.0,
                gap: DASH_PX.1,
            },
            Style::Dots => SampleLook::Dots,
        };
        Self::new(at, look, color)
    }
}

impl<'a> PointCollection<'a, (i32, i32)> for &'a LegendSample {
    type Point = &'a (i32, i32);
    type IntoIter = std::iter::Once<&'a (i32, i32)>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<DB: DrawingBackend> Drawable<DB> for LegendSample {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        const WIDE: i32 = 24;
        let Some((x, y)) = pos.next() else {
            return Ok(());
        };
        match self.look {
            SampleLook::Line { width } => backend.draw_line((x, y), (x + WIDE, y), &self.color.stroke_width(width)),
            SampleLook::Dashes { width, dash, gap } => {
                let mut from = 0;
                while from < WIDE {
                    let to = (from + dash).min(WIDE);
                    backend.draw_line((x + from, y), (x + to, y), &self.color.stroke_width(width))?;
                    from = to + gap.max(1);
                }
                Ok(())
            }
            SampleLook::Dots => {
                for dx in [4, 12, 20] {
                    backend.draw_circle((x + dx, y), 3, &self.color.mix(0.6).filled(), true)?;
                }
                Ok(())
            }
        }
    }
}

/// Renders `chart` to `{base}.png` and `{base}.svg` (both in memory first).
pub fn render(chart: &Chart, base: &Path) -> Result<()> {
    register_font()?;
    let mut svg = String::new();
    draw(SVGBackend::with_string(&mut svg, SIZE).into_drawing_area(), chart)?;
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(), chart)?;
    crate::atomic_write::write_atomic(&with_suffix(base, "png"), &encode_png(&rgb, SIZE)?)?;
    crate::atomic_write::write_atomic(&with_suffix(base, "svg"), svg.as_bytes())?;
    Ok(())
}

/// For figures that don't fit [`Chart`]: `draw` paints a white bitmap of
/// `size`, which is written to `path` as PNG atomically. Text uses the
/// bundled font, as in [`render`].
pub fn render_png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> Result<()>,
) -> Result<()> {
    register_font()?;
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        draw(&root)?;
        root.present()
            .map_err(|e| anyhow!("cannot render {}: {e}", path.display()))?;
    }
    crate::atomic_write::write_atomic(path, &encode_png(&rgb, size)?)
}

fn encode_png(rgb: &[u8], size: (u32, u32)) -> Result<Vec<u8>> {
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, size.0, size.1);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        // Plots are flat colour with thin lines: the best deflate level and a
        // per-row filter choice make them several times smaller than the
        // encoder's fast default (the demo's out/ must stay small).
        enc.set_compression(png::Compression::Best);
        enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        let mut w = enc.write_header()?;
        w.write_image_data(rgb)?;
    }
    Ok(png_bytes)
}

/// `base` + `.ext` (not `with_extension`, which would eat "0.5" in a name).
fn with_suffix(base: &Path, ext: &str) -> std::path::PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    s.into()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_stays_below_the_legend_band() {
        // A legend of 4 rows in a 20 px font: 4 × (1.5·20 + 4) + 30 = 166 px
        // at the top of a 655 px plot. The data's top (hi) must sit at least
        // that far below the axis top.
        let (lo, hi) = (-800.0, 6938.0);
        let top = with_legend_room(lo, hi, 4, 20, 655);
        let gap_px = 655.0 * (top - hi) / (top - lo);
        assert!((gap_px - 166.0).abs() < 1e-9, "{gap_px}");
        // No legend rows still leave the box's margin; the share is capped.
        assert!(with_legend_room(0.0, 1.0, 0, 20, 655) > 1.0);
        assert!(with_legend_room(0.0, 1.0, 100, 20, 655) <= 1.0 / 0.4 + 1e-12);
    }
}
