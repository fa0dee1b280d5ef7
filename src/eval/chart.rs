//! Charts of the sweep, as PNG and SVG: shadow cost against error for every configuration with
//! the Pareto front drawn and labelled, and error against view distance.

use crate::render::Image;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

/// Errors below this share are drawn at it: a log scale has no zero.
pub const FLOOR: f64 = 1e-5;

/// The error axis: from a third of the smallest error above [`FLOOR`] (or the floor) to three
/// times the largest, at most 100%.
fn error_range(errors: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, FLOOR * 10.0);
    for e in errors.filter(|e| e.is_finite()) {
        hi = hi.max(e);
        if e > FLOOR {
            lo = lo.min(e);
        }
    }
    let lo = if lo.is_finite() { (lo / 3.0).max(FLOOR) } else { FLOOR };
    (lo, (hi * 3.0).min(1.0).max(lo * 10.0))
}

/// One configuration on a cost-against-error chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Shadow cost in milliseconds.
    pub cost: f64,
    /// Error share, 0..1.
    pub error: f64,
    /// The configuration's name.
    pub label: String,
    /// Drawn as the default configuration.
    pub default: bool,
    /// Its family: each has its own colour and marker, named in the legend.
    pub family: &'static str,
}

/// The families in legend order, each with its colour (the marker goes by the position).
const FAMILIES: [(&str, RGBColor); 10] = [
    ("hard", RGBColor(110, 110, 110)),
    ("grid PCF", RGBColor(0, 140, 200)),
    ("Gaussian PCF", RGBColor(0, 160, 80)),
    ("Poisson PCF", RGBColor(200, 120, 0)),
    ("PCSS", RGBColor(170, 0, 170)),
    ("moment maps", RGBColor(200, 30, 30)),
    ("depth in colour", RGBColor(120, 80, 20)),
    ("planar", RGBColor(0, 150, 150)),
    ("Bevy-like", RGBColor(0, 0, 0)),
    (super::config::VIRTUAL_FAMILY, RGBColor(230, 150, 0)),
];

/// A family's marker: its shape (circle, triangle or cross), size in pixels and whether it is
/// filled.
#[derive(Clone, Copy)]
enum Shape {
    Circle,
    Triangle,
    Cross,
}

const MARKERS: [(Shape, i32, bool); 10] = [
    (Shape::Circle, 4, true),
    (Shape::Triangle, 6, true),
    (Shape::Cross, 5, false),
    (Shape::Circle, 5, false),
    (Shape::Triangle, 7, false),
    (Shape::Cross, 7, false),
    (Shape::Triangle, 5, true),
    (Shape::Cross, 6, false),
    (Shape::Circle, 6, true),
    (Shape::Triangle, 8, true),
];

/// Why a chart could not be written.
#[derive(Debug, thiserror::Error)]
#[error("could not draw {path}: {why}")]
pub struct ChartError {
    /// The file.
    pub path: String,
    /// What went wrong.
    pub why: String,
}

const SIZE: (u32, u32) = (1100, 640);

fn font_ready() {
    static FONT: std::sync::Once = std::sync::Once::new();
    FONT.call_once(|| {
        // Built into the program, so charts look the same on every machine and need no fonts
        // installed (if it cannot be read, text is simply left out).
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
    });
}

/// Draws a chart into `stem`.svg with `svg` and into `stem`.png with `png` (the same drawing for
/// both backends).
fn both(
    stem: &Path,
    svg_draw: impl FnOnce(&DrawingArea<SVGBackend, Shift>) -> Result<(), String>,
    png_draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<(), String>,
) -> Result<(), ChartError> {
    font_ready();
    let fail = |path: &Path, why: String| ChartError { path: path.display().to_string(), why };
    let svg_path = stem.with_extension("svg");
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        svg_draw(&area).map_err(|e| fail(&svg_path, e))?;
        area.present().map_err(|e| fail(&svg_path, e.to_string()))?;
    }
    std::fs::write(&svg_path, svg).map_err(|e| fail(&svg_path, e.to_string()))?;
    let png_path = stem.with_extension("png");
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let area = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        png_draw(&area).map_err(|e| fail(&png_path, e))?;
        area.present().map_err(|e| fail(&png_path, e.to_string()))?;
    }
    let pixels = rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    Image { width: SIZE.0, height: SIZE.1, pixels }.save_png(&png_path).map_err(|e| fail(&png_path, e.to_string()))
}

/// The chart both kinds share: white, titled, x from 0 to `x_max`, errors (shares `lo` to `hi`)
/// in percent on a log scale.
fn log_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    title: &str,
    x_max: f64,
    (lo, hi): (f64, f64),
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, LogCoord<f64>>>, String>
where
    DB::ErrorType: 'static,
{
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..x_max, (100.0 * lo..100.0 * hi).log_scale())
        .map_err(|e| e.to_string())
}

/// The cost axis's name: where the cost was measured matters as much as its number (a software
/// rasterizer and a GPU rank the methods differently).
#[must_use]
pub fn cost_axis(adapter: &str) -> String {
    format!("shadow cost per frame (ms on {adapter}): drawing every map + looking it up")
}

/// Cost against error, one marker per configuration, the Pareto front drawn and labelled;
/// `axes` name the cost (see [`cost_axis`]) and the error.
pub fn cost_chart(
    stem: &Path,
    title: &str,
    axes: (&str, &str),
    points: &[Point],
    front: &[usize],
) -> Result<(), ChartError> {
    both(stem, |a| draw_cost(a, title, axes, points, front), |a| draw_cost(a, title, axes, points, front))
}

fn draw_cost<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    (x_desc, y_desc): (&str, &str),
    points: &[Point],
    front: &[usize],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let max_cost = points.iter().map(|p| p.cost).filter(|c| c.is_finite()).fold(0.0, f64::max).max(1e-3) * 1.15;
    let (lo, hi) = error_range(points.iter().map(|p| p.error));
    let y = |e: f64| 100.0 * e.max(lo);
    let mut chart = log_chart(area, title, max_cost, (lo, hi))?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .y_label_formatter(&|v| format!("{v}%"))
        .draw()
        .map_err(|e| e.to_string())?;
    for ((family, colour), (shape, size, filled)) in FAMILIES.into_iter().zip(MARKERS) {
        let at: Vec<(f64, f64)> = points.iter().filter(|p| p.family == family).map(|p| (p.cost, y(p.error))).collect();
        if at.is_empty() {
            continue;
        }
        let style = if filled { colour.filled() } else { colour.stroke_width(2) };
        // Each shape is its own element type, so each draws (and keys its legend) on its own.
        let series = match shape {
            Shape::Circle => chart
                .draw_series(at.iter().map(|&a| Circle::new(a, size, style)))
                .map_err(|e| e.to_string())?
                .legend(move |(x, y)| Circle::new((x + 8, y), size, style)),
            Shape::Triangle => chart
                .draw_series(at.iter().map(|&a| TriangleMarker::new(a, size, style)))
                .map_err(|e| e.to_string())?
                .legend(move |(x, y)| TriangleMarker::new((x + 8, y), size, style)),
            Shape::Cross => chart
                .draw_series(at.iter().map(|&a| Cross::new(a, size, style)))
                .map_err(|e| e.to_string())?
                .legend(move |(x, y)| Cross::new((x + 8, y), size, style)),
        };
        series.label(family);
    }
    let line: Vec<(f64, f64)> = front.iter().map(|&i| (points[i].cost, y(points[i].error))).collect();
    chart.draw_series(LineSeries::new(line.clone(), RED.stroke_width(2))).map_err(|e| e.to_string())?;
    chart.draw_series(line.iter().map(|&p| Circle::new(p, 5, RED.filled()))).map_err(|e| e.to_string())?;
    let font = ("sans-serif", 13).into_font();
    let labelled = |at: (f64, f64), text: String, offset: (i32, i32), colour: RGBColor| {
        EmptyElement::at(at) + Text::new(text, offset, font.clone().color(&colour))
    };
    // Front points are labelled where a label fits: one too close to a label already placed
    // (in pixels) is left out, so crowded corners stay readable.
    let mut placed: Vec<(i32, i32)> = Vec::new();
    for &i in front {
        let at = (points[i].cost, y(points[i].error));
        let (px, py) = chart.backend_coord(&at);
        if placed.iter().any(|&(x, y)| (py - y).abs() < 15 && (px - x).abs() < 110) {
            continue;
        }
        placed.push((px, py));
        chart.draw_series([labelled(at, points[i].label.clone(), (8, -16), RED)]).map_err(|e| e.to_string())?;
    }
    for p in points.iter().filter(|p| p.default) {
        let at = (p.cost, y(p.error));
        chart.draw_series([Circle::new(at, 9, BLUE.stroke_width(2))]).map_err(|e| e.to_string())?;
        chart.draw_series([labelled(at, "default".into(), (-20, 12), BLUE)]).map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// Error against view distance: one line per configuration, bands on the x axis.
pub fn distance_chart(stem: &Path, title: &str, bands: &[f32], lines: &[(String, Vec<f64>)]) -> Result<(), ChartError> {
    both(stem, |a| draw_distance(a, title, bands, lines), |a| draw_distance(a, title, bands, lines))
}

fn draw_distance<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    bands: &[f32],
    lines: &[(String, Vec<f64>)],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let (lo, hi) = error_range(lines.iter().flat_map(|(_, v)| v.iter().copied()));
    let palette = [RED, BLUE, RGBColor(0, 150, 0), MAGENTA, RGBColor(230, 140, 0), CYAN, BLACK];
    let y = |e: f64| 100.0 * e.max(lo);
    let mut chart = log_chart(area, title, bands.len() as f64, (lo, hi))?;
    let name = |i: usize| {
        let start = if i == 0 { 0.0 } else { bands[i - 1] };
        if bands[i].is_finite() { format!("{start}-{} m", bands[i]) } else { format!("{start} m+") }
    };
    chart
        .configure_mesh()
        .x_labels(2 * bands.len() + 1)
        .x_label_formatter(&|x| {
            let i = x.floor() as usize;
            if (x - x.floor() - 0.5).abs() < 0.01 && i < bands.len() { name(i) } else { String::new() }
        })
        .x_desc("distance from the camera")
        .y_desc("misclassified %")
        .y_label_formatter(&|v| format!("{v}%"))
        .draw()
        .map_err(|e| e.to_string())?;
    for (k, (label, values)) in lines.iter().enumerate() {
        let colour = palette[k % palette.len()];
        let at: Vec<(f64, f64)> = values.iter().enumerate().map(|(i, v)| (i as f64 + 0.5, y(*v))).collect();
        chart
            .draw_series(LineSeries::new(at.clone(), colour.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(label.clone())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
        chart.draw_series(at.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// Lines of (x, y) points on linear axes named `axes` (x, then y), each point of every line
/// labelled with `labels` (by index), as `stem`.png and .svg.
pub fn line_chart(
    stem: &Path,
    title: &str,
    axes: (&str, &str),
    lines: &[(String, Vec<(f64, f64)>)],
    labels: &[String],
) -> Result<(), ChartError> {
    both(stem, |a| draw_lines(a, title, axes, lines, labels), |a| draw_lines(a, title, axes, lines, labels))
}

fn draw_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    (x_desc, y_desc): (&str, &str),
    lines: &[(String, Vec<(f64, f64)>)],
    labels: &[String],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let points = || lines.iter().flat_map(|(_, p)| p.iter().copied()).filter(|(x, y)| x.is_finite() && y.is_finite());
    let x_max = points().map(|p| p.0).fold(1e-3, f64::max) * 1.08;
    let y_max = points().map(|p| p.1).fold(1e-3, f64::max) * 1.15;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..x_max, 0.0..y_max)
        .map_err(|e| e.to_string())?;
    chart.configure_mesh().x_desc(x_desc).y_desc(y_desc).draw().map_err(|e| e.to_string())?;
    let palette = [RED, BLUE, RGBColor(0, 150, 0), MAGENTA];
    for (k, (name, at)) in lines.iter().enumerate() {
        let colour = palette[k % palette.len()];
        chart
            .draw_series(LineSeries::new(at.clone(), colour.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(name.clone())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
        chart.draw_series(at.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(|e| e.to_string())?;
    }
    if let Some((_, first)) = lines.first() {
        let style = ("sans-serif", 13).into_font().color(&BLACK);
        let marks =
            first.iter().zip(labels).map(|(&p, l)| EmptyElement::at(p) + Text::new(l.clone(), (6, -16), style.clone()));
        chart.draw_series(marks).map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_the_sweep_measures_has_a_colour_and_a_marker_in_the_charts() {
        for config in super::super::config::configs(false) {
            let family = config.family();
            assert!(FAMILIES.iter().any(|(f, _)| *f == family), "no colour for the family {family}");
        }
    }
}
