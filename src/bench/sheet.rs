//! The contact sheet of the main job (`out/modes.png`): for each model, its
//! exact reference and then every mode's image side by side, each under a
//! label with the mode's name, what it measured (ε against that reference,
//! frame time) and, where it applies, that it ran two-pass on an opaque scene.
//!
//! The tiles are scaled with `image` and the labels drawn with `plotters` in
//! the bundled font (`crate::font`), like the error-against-time plot.

use std::path::{Path, PathBuf};

use plotters::prelude::*;

/// One image of the sheet and its two label lines.
#[derive(Debug, Clone)]
pub struct Tile {
    pub image: PathBuf,
    pub title: String,
    pub figures: String,
}

/// One model: a heading and its tiles, the reference first.
#[derive(Debug, Clone)]
pub struct SheetRow {
    pub heading: String,
    pub tiles: Vec<Tile>,
}

const HEADING: u32 = 30;
const LABEL: u32 = 44;
const BACKGROUND: RGBColor = RGBColor(16, 17, 20);

/// Draws `rows` with tiles `tile` pixels square to a PNG at `path` (written atomically).
pub fn write(rows: &[SheetRow], tile: u32, path: &Path) -> Result<(), String> {
    crate::font::register();
    let columns = rows.iter().map(|r| r.tiles.len()).max().unwrap_or(0).max(1) as u32;
    let size = (columns * tile, rows.len().max(1) as u32 * (HEADING + LABEL + tile));
    let mut canvas =
        image::RgbImage::from_pixel(size.0, size.1, image::Rgb([BACKGROUND.0, BACKGROUND.1, BACKGROUND.2]));
    for (r, row) in rows.iter().enumerate() {
        let top = r as u32 * (HEADING + LABEL + tile) + HEADING + LABEL;
        for (c, t) in row.tiles.iter().enumerate() {
            let picture = image::open(&t.image).map_err(|e| format!("{}: {e}", t.image.display()))?;
            let scaled = picture.resize_exact(tile, tile, image::imageops::FilterType::Triangle).to_rgb8();
            image::imageops::replace(&mut canvas, &scaled, (c as u32 * tile) as i64, top as i64);
        }
    }
    let mut buffer = canvas.into_raw();
    {
        let root = BitMapBackend::with_buffer(&mut buffer, size).into_drawing_area();
        let heading = ("sans-serif", 19).into_font().color(&WHITE);
        let title = ("sans-serif", 16).into_font().color(&WHITE);
        let figures = ("sans-serif", 14).into_font().color(&RGBColor(190, 195, 205));
        for (r, row) in rows.iter().enumerate() {
            let y = (r as u32 * (HEADING + LABEL + tile)) as i32;
            root.draw(&Text::new(row.heading.clone(), (8, y + 6), heading.clone())).map_err(|e| e.to_string())?;
            for (c, t) in row.tiles.iter().enumerate() {
                let x = (c as u32 * tile) as i32 + 6;
                let y = y + HEADING as i32;
                root.draw(&Text::new(t.title.clone(), (x, y + 2), title.clone())).map_err(|e| e.to_string())?;
                root.draw(&Text::new(t.figures.clone(), (x, y + 22), figures.clone())).map_err(|e| e.to_string())?;
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    let rgb = image::RgbImage::from_raw(size.0, size.1, buffer).ok_or("sheet buffer size")?;
    let rgba = image::DynamicImage::ImageRgb8(rgb).to_rgba8();
    crate::output::save_png(&rgba, path).map_err(|e| format!("{}: {e}", path.display()))
}
