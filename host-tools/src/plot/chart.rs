//! One line/scatter chart, rendered to PNG and SVG in memory and written
//! atomically. Text uses the bundled DejaVu Sans (registered once).
use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
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

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &Chart) -> Result<()> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plotting failed: {e:?}");
    let ((x0, x1), (y0, y1)) = ranges(chart)?;
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
        let legend_style = match s.style {
            Style::Dots => color.mix(0.6).stroke_width(6),
            Style::Line { width } | Style::Dashed { width } => color.stroke_width(width + 1),
        };
        let anno = match s.style {
            Style::Line { width } => c
                .draw_series(LineSeries::new(s.points.iter().copied(), color.stroke_width(width)))
                .map_err(e)?,
            Style::Dashed { width } => c
                .draw_series(DashedLineSeries::new(
                    s.points.iter().copied(),
                    10,
                    6,
                    color.stroke_width(width),
                ))
                .map_err(e)?,
            Style::Dots => c
                .draw_series(s.points.iter().map(|&p| Circle::new(p, 2, color.mix(0.25).filled())))
                .map_err(e)?,
        };
        anno.label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], legend_style));
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

/// Renders `chart` to `{base}.png` and `{base}.svg` (both in memory first).
pub fn render(chart: &Chart, base: &Path) -> Result<()> {
    register_font()?;
    let mut svg = String::new();
    draw(SVGBackend::with_string(&mut svg, SIZE).into_drawing_area(), chart)?;
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(), chart)?;
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, SIZE.0, SIZE.1);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header()?;
        w.write_image_data(&rgb)?;
    }
    crate::atomic_write::write_atomic(&with_suffix(base, "png"), &png_bytes)?;
    crate::atomic_write::write_atomic(&with_suffix(base, "svg"), svg.as_bytes())?;
    Ok(())
}

/// `base` + `.ext` (not `with_extension`, which would eat "0.5" in a name).
fn with_suffix(base: &Path, ext: &str) -> std::path::PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    s.into()
}
