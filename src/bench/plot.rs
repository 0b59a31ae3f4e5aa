//! The error-against-time plot: one marker per mode (per model, when a run has
//! several), ε over frame time, both averaged over the views; the reference,
//! the ruler the others are measured against, is a vertical line at its time.
//!
//! Drawn with `plotters` into an RGB buffer and encoded with `image`; labels
//! use the DejaVu Sans font bundled in `assets/fonts`, so no system font is needed.

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

use super::report::BenchRow;

const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
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

/// Makes the bundled font the "sans-serif" of `plotters` (once per process).
pub fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        if plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_err() {
            log::warn!("the bundled plot font could not be read; labels may be missing");
        }
    });
}

/// Draws the plot to a PNG at `path` (written atomically).
pub fn write(rows: &[BenchRow], title: &str, path: &Path) -> Result<(), String> {
    register_font();
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
