//! The error-against-time plot: one marker per mode (per model, when a run has
//! several), ε over frame time, both averaged over the views; the reference,
//! the ruler the others are measured against, is a vertical line at its time.
//!
//! Drawn with `plotters` into an RGB buffer and encoded with `image`; labels
//! use the bundled font (`crate::font`), so no system font is needed.

use std::path::Path;

use plotters::prelude::*;

use super::report::BenchRow;

/// Width and least height of the plot; it grows to give every legend entry its line.
const SIZE: (u32, u32) = (1300, 600);
/// Height of one legend line.
const LEGEND_LINE: u32 = 24;
/// Width of the chart; the legend takes the rest.
const CHART_WIDTH: u32 = 760;

/// One point of the plot: a mode variant averaged over views.
#[derive(Debug, Clone)]
pub struct ModePoint {
    pub label: String,
    /// Median over views of the frame-time medians.
    pub frame_ms: f64,
    /// Mean ε over views.
    pub eps: f64,
    /// The reference: the ruler, drawn as a line at its time, not as a point at ε 0.
    pub ruler: bool,
}

/// Averages `rows` over views per variant (and per model, when there are several).
pub fn mode_points(rows: &[BenchRow]) -> Vec<ModePoint> {
    let several_models = rows.iter().any(|r| r.model != rows[0].model);
    let label = |r: &BenchRow| {
        if several_models { format!("{}, {}", r.model.trim_end_matches(".ply"), r.variant) } else { r.variant.clone() }
    };
    let mut labels: Vec<String> = Vec::new();
    for r in rows {
        let label = label(r);
        if !labels.contains(&label) {
            labels.push(label);
        }
    }
    labels
        .into_iter()
        .map(|l| {
            let of: Vec<&BenchRow> = rows.iter().filter(|r| label(r) == l).collect();
            let mut ms: Vec<f64> = of.iter().map(|r| r.frame_ms).collect();
            ms.sort_by(f64::total_cmp);
            ModePoint {
                frame_ms: ms[ms.len() / 2],
                eps: of.iter().map(|r| r.eps).sum::<f64>() / of.len() as f64,
                ruler: of.iter().all(|r| r.ruler),
                label: l,
            }
        })
        .collect()
}

/// Draws the plot to a PNG at `path` (written atomically).
pub fn write(rows: &[BenchRow], title: &str, path: &Path) -> Result<(), String> {
    crate::font::register();
    let points = mode_points(rows);
    if points.is_empty() {
        return Err("nothing to plot".into());
    }
    let size = (SIZE.0, SIZE.1.max(80 + LEGEND_LINE * points.len() as u32));
    let mut buffer = vec![255u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (plot_area, legend_area) = root.split_horizontally(CHART_WIDTH);
        let max_ms = points.iter().map(|p| p.frame_ms).fold(1e-3, f64::max) * 2.0;
        let min_ms = points.iter().map(|p| p.frame_ms).fold(f64::INFINITY, f64::min).max(1e-3) / 2.0;
        let max_eps = points.iter().map(|p| p.eps).fold(0.0, f64::max).max(0.5) * 1.15;
        let mut chart = ChartBuilder::on(&plot_area)
            .caption(title, ("sans-serif", 22))
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d((min_ms..max_ms).log_scale().base(2.0), 0.0..max_eps)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("frame time, ms (median; log2 scale)")
            .y_desc("ε: mean |ΔR|+|ΔG|+|ΔB| per pixel")
            .label_style(("sans-serif", 15))
            .draw()
            .map_err(|e| e.to_string())?;
        for (i, p) in points.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let y = 60 + (LEGEND_LINE * i as u32) as i32;
            let text = if p.ruler {
                // The ruler has no error of its own: a vertical line at its time.
                let line = [(p.frame_ms, 0.0), (p.frame_ms, max_eps)];
                chart
                    .draw_series(std::iter::once(PathElement::new(line, colour.stroke_width(2))))
                    .map_err(|e| e.to_string())?;
                legend_area
                    .draw(&PathElement::new([(6, y), (18, y)], colour.stroke_width(3)))
                    .map_err(|e| e.to_string())?;
                format!("{}: {:.1} ms, the ruler", p.label, p.frame_ms)
            } else {
                chart
                    .draw_series(std::iter::once(Circle::new((p.frame_ms, p.eps), 7, colour.filled())))
                    .map_err(|e| e.to_string())?;
                legend_area.draw(&Circle::new((12, y), 6, colour.filled())).map_err(|e| e.to_string())?;
                let digits = if p.eps < 0.1 { 3 } else { 2 };
                format!("{}: {:.1} ms, ε {:.*}", p.label, p.frame_ms, digits, p.eps)
            };
            legend_area
                .draw(&Text::new(text, (26, y - 8), ("sans-serif", 14).into_font()))
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    let rgb = image::RgbImage::from_raw(size.0, size.1, buffer).ok_or("plot buffer size")?;
    let rgba = image::DynamicImage::ImageRgb8(rgb).to_rgba8();
    crate::output::save_png(&rgba, path).map_err(|e| format!("{}: {e}", path.display()))
}

/// (frame, frame ms, regroup + upload ms, ε) of one variant.
type FramePoint = (usize, f64, Option<f64>, f64);

/// Per animation frame and variant (means over views): frame time and, for a
/// variant that regroups, regroup + upload (left); ε against that frame's
/// reference (right). Written atomically to `path`.
pub fn write_animation(rows: &[BenchRow], title: &str, path: &Path) -> Result<(), String> {
    crate::font::register();
    let mut variants: Vec<String> = Vec::new();
    for r in rows.iter().filter(|r| r.frame.is_some() && !r.ruler) {
        if !variants.contains(&r.variant) {
            variants.push(r.variant.clone());
        }
    }
    if variants.is_empty() {
        return Err("no animation frames to plot".into());
    }
    let frame_count = rows.iter().filter_map(|r| r.frame).max().unwrap_or(0) + 1;
    let series: Vec<Vec<FramePoint>> = variants
        .iter()
        .map(|v| {
            (0..frame_count)
                .filter_map(|f| {
                    let of: Vec<&BenchRow> = rows.iter().filter(|r| &r.variant == v && r.frame == Some(f)).collect();
                    let n = of.len() as f64;
                    (!of.is_empty()).then(|| {
                        let cost = match (of[0].regroup_ms, of[0].upload_ms) {
                            (Some(g), Some(u)) => Some(g + u),
                            _ => None,
                        };
                        let ms = of.iter().map(|r| r.frame_ms).sum::<f64>() / n;
                        (f, ms, cost, of.iter().map(|r| r.eps).sum::<f64>() / n)
                    })
                })
                .collect()
        })
        .collect();
    let size = (1300u32, 560u32);
    let mut buffer = vec![255u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root.titled(title, ("sans-serif", 22)).map_err(|e| e.to_string())?;
        let (left, right) = root.split_horizontally(size.0 / 2);
        let max_ms = series.iter().flatten().map(|s| s.1.max(s.2.unwrap_or(0.0))).fold(1.0, f64::max) * 1.15;
        let max_eps = series.iter().flatten().map(|s| s.3).fold(0.5, f64::max) * 1.15;
        let frames = -0.5..(frame_count as f64 - 0.5);
        let mut time = frame_chart(&left, frames.clone(), max_ms, "ms: frame (circles), regroup + upload (triangles)")?;
        let mut error = frame_chart(&right, frames, max_eps, "ε against that frame's reference")?;
        for (i, (variant, points)) in variants.iter().zip(&series).enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let frame_ms: Vec<(f64, f64)> = points.iter().map(|p| (p.0 as f64, p.1)).collect();
            time.draw_series(LineSeries::new(frame_ms.clone(), colour.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(variant.clone())
                .legend(move |(x, y)| Circle::new((x + 8, y), 5, colour.filled()));
            time.draw_series(frame_ms.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                .map_err(|e| e.to_string())?;
            let cost: Vec<(f64, f64)> = points.iter().filter_map(|p| p.2.map(|c| (p.0 as f64, c))).collect();
            time.draw_series(cost.iter().map(|&p| TriangleMarker::new(p, 6, colour.filled())))
                .map_err(|e| e.to_string())?;
            let eps: Vec<(f64, f64)> = points.iter().map(|p| (p.0 as f64, p.3)).collect();
            error.draw_series(LineSeries::new(eps.clone(), colour.stroke_width(2))).map_err(|e| e.to_string())?;
            error.draw_series(eps.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(|e| e.to_string())?;
        }
        time.configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    let rgb = image::RgbImage::from_raw(size.0, size.1, buffer).ok_or("plot buffer size")?;
    let rgba = image::DynamicImage::ImageRgb8(rgb).to_rgba8();
    crate::output::save_png(&rgba, path).map_err(|e| format!("{}: {e}", path.display()))
}

/// One panel of the animation plot: a value per animation frame, with the
/// frames along x and `y_desc` up to `max` along y.
type FrameChart<'a> = ChartContext<
    'a,
    BitMapBackend<'a>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

fn frame_chart<'a>(
    area: &DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>,
    frames: std::ops::Range<f64>,
    max: f64,
    y_desc: &str,
) -> Result<FrameChart<'a>, String> {
    let mut chart = ChartBuilder::on(area)
        .margin(20)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(frames, 0.0..max)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("frame")
        // Whole frames only: the axis runs from -0.5, and halves would round to repeated labels.
        .x_label_formatter(&|x| if x.fract() == 0.0 { format!("{x:.0}") } else { String::new() })
        .y_desc(y_desc)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(chart)
}
