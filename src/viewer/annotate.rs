//! What the view draws over the frame, burnt into a saved screenshot: the
//! measured polyline, a dot on each point and each segment's length at its
//! middle (`inspect.rs`), placed by the screenshot's own projection, and the
//! legend of the colours in the lower left corner (`legend.rs`), all scaled
//! with the screenshot's size. Drawn with `plotters` in the bundled font
//! (`crate::font`).

use plotters::prelude::*;

/// The measurement's colour, as the view draws it.
pub const MEASURE_RGB: [u8; 3] = [255, 110, 90];
const MEASURE_COLOUR: RGBColor = RGBColor(MEASURE_RGB[0], MEASURE_RGB[1], MEASURE_RGB[2]);

/// What is drawn over a screenshot, in its pixels.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Annotation {
    /// The measured points, `None` where one is behind the camera.
    pub points: Vec<Option<(f32, f32)>>,
    /// The label of segment k (points k and k + 1).
    pub segment_labels: Vec<String>,
    /// Line widths and font sizes are multiplied by this (the screenshot's size over the view's).
    pub scale: f32,
    /// The legend of the colours, when they show an attribute.
    pub legend: Option<super::legend::Legend>,
}

impl Annotation {
    pub fn is_empty(&self) -> bool {
        self.points.len() < 2 && self.legend.is_none()
    }
}

/// `image` with `annotation` drawn over it.
pub fn draw(image: &image::RgbaImage, annotation: &Annotation) -> Result<image::RgbaImage, String> {
    crate::font::register();
    let size = image.dimensions();
    let mut buffer = image::DynamicImage::ImageRgba8(image.clone()).into_rgb8().into_raw();
    {
        let root = BitMapBackend::with_buffer(&mut buffer, size).into_drawing_area();
        let scale = annotation.scale.max(1.0);
        let width = (2.0 * scale).round() as u32;
        let line = ShapeStyle { color: MEASURE_COLOUR.to_rgba(), filled: false, stroke_width: width };
        let at = |p: (f32, f32)| (p.0.round() as i32, p.1.round() as i32);
        for (k, pair) in annotation.points.windows(2).enumerate() {
            if let [Some(a), Some(b)] = pair {
                root.draw(&PathElement::new(vec![at(*a), at(*b)], line)).map_err(|e| e.to_string())?;
                if let Some(label) = annotation.segment_labels.get(k) {
                    let font = ("sans-serif", 14.0 * scale as f64).into_font().color(&WHITE);
                    let style = font.pos(plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Center,
                        plotters::style::text_anchor::VPos::Bottom,
                    ));
                    let middle = ((a.0 + b.0) * 0.5, (a.1 + b.1) * 0.5);
                    root.draw(&Text::new(label.clone(), at(middle), style)).map_err(|e| e.to_string())?;
                }
            }
        }
        for p in annotation.points.iter().flatten() {
            let dot = Circle::new(at(*p), (4.0 * scale) as i32, MEASURE_COLOUR.filled());
            root.draw(&dot).map_err(|e| e.to_string())?;
        }
        if let Some(legend) = &annotation.legend {
            draw_legend(&root, size, legend, scale).map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    let rgb = image::RgbImage::from_raw(size.0, size.1, buffer).ok_or("the annotated image has the wrong size")?;
    Ok(image::DynamicImage::ImageRgb8(rgb).into_rgba8())
}

/// The legend in the lower left corner, laid out as the view lays it out, times `scale`.
fn draw_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    (_, height): (u32, u32),
    legend: &super::legend::Legend,
    scale: f32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    use super::legend::{Legend, MARGIN, ROW};
    let px = |v: f32| (v * scale).round() as i32;
    let (h, w) = legend.size();
    let (left, top) = (px(MARGIN), height as i32 - px(MARGIN) - px(h));
    root.draw(&Rectangle::new(
        [(left - px(4.0), top - px(4.0)), (left + px(w + 4.0), top + px(h + 4.0))],
        BLACK.mix(0.59).filled(),
    ))?;
    let text = RGBColor(230, 230, 230);
    let font = |anchor: plotters::style::text_anchor::HPos| {
        ("sans-serif", 12.0 * scale as f64)
            .into_font()
            .color(&text)
            .pos(plotters::style::text_anchor::Pos::new(anchor, plotters::style::text_anchor::VPos::Top))
    };
    use plotters::style::text_anchor::HPos;
    match legend {
        Legend::Classes { title, rows } => {
            root.draw(&Text::new(title.clone(), (left, top), font(HPos::Left)))?;
            for (row, ([r, g, b], label)) in rows.iter().enumerate() {
                let y = top + px(ROW * (row + 1) as f32);
                let swatch = [(left, y + px(3.0)), (left + px(10.0), y + px(13.0))];
                root.draw(&Rectangle::new(swatch, RGBColor(*r, *g, *b).filled()))?;
                root.draw(&Text::new(label.clone(), (left + px(16.0), y + px(2.0)), font(HPos::Left)))?;
            }
        }
        Legend::Scale { title, colormap, range } => {
            root.draw(&Text::new(title.clone(), (left, top), font(HPos::Left)))?;
            let (bar_top, bar_width) = (top + px(ROW), px(w));
            let steps = 64;
            for i in 0..steps {
                let [r, g, b] = colormap.colour((i as f64 + 0.5) / steps as f64);
                let (x0, x1) = (left + bar_width * i / steps, left + bar_width * (i + 1) / steps);
                root.draw(&Rectangle::new([(x0, bar_top), (x1, bar_top + px(10.0))], RGBColor(r, g, b).filled()))?;
            }
            let (lo, hi) = Legend::range_labels(*range);
            let below = bar_top + px(12.0);
            root.draw(&Text::new(lo, (left, below), font(HPos::Left)))?;
            root.draw(&Text::new(hi, (left + bar_width, below), font(HPos::Right)))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_the_segment_its_dots_and_its_label_and_nothing_far_from_them() {
        let image = image::RgbaImage::from_pixel(200, 100, image::Rgba([20, 20, 30, 255]));
        let annotation = Annotation {
            points: vec![Some((20.0, 70.0)), Some((180.0, 70.0))],
            segment_labels: vec!["1.234".into()],
            scale: 1.0,
            legend: None,
        };
        let drawn = draw(&image, &annotation).unwrap();
        let changed = |x0: u32, y0: u32, x1: u32, y1: u32| {
            (y0..y1)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .filter(|&(x, y)| drawn.get_pixel(x, y) != image.get_pixel(x, y))
                .count()
        };
        assert!(changed(20, 68, 180, 73) > 150, "the segment");
        assert!(changed(15, 65, 25, 75) > 20 && changed(175, 65, 185, 75) > 20, "the dots");
        assert!(changed(80, 45, 120, 68) > 20, "the label above the middle");
        assert_eq!(changed(0, 0, 200, 30), 0, "far above the segment");
        assert_eq!(changed(0, 80, 200, 100), 0, "below the segment");
    }

    #[test]
    fn a_legend_is_burnt_into_the_lower_left_corner_with_its_colours_and_nothing_else_changes() {
        use super::super::legend::Legend;
        let image = image::RgbaImage::from_pixel(300, 200, image::Rgba([20, 20, 30, 255]));
        let classes = Legend::Classes { title: "classification".into(), rows: vec![([255, 0, 0], "2 Ground".into())] };
        let scale = Legend::Scale { title: "elevation".into(), colormap: Default::default(), range: (10.0, 20.0) };
        for (legend, colour) in [(classes, [255u8, 0, 0]), (scale, Default::default())] {
            let annotation = Annotation { legend: Some(legend.clone()), scale: 1.0, ..Default::default() };
            assert!(!annotation.is_empty());
            let drawn = draw(&image, &annotation).unwrap();
            let (height, width) = legend.size();
            let corner = |x: u32, y: u32| x < width as u32 + 20 && y + height as u32 + 20 > 200;
            let changed: Vec<(u32, u32)> = drawn
                .enumerate_pixels()
                .filter(|(x, y, p)| *p != image.get_pixel(*x, *y))
                .map(|(x, y, _)| (x, y))
                .collect();
            assert!(changed.len() > 500, "{legend:?}: {} pixels drawn", changed.len());
            assert!(changed.iter().all(|&(x, y)| corner(x, y)), "{legend:?} drew outside its corner");
            if let Legend::Classes { .. } = legend {
                assert!(drawn.pixels().filter(|p| p.0[..3] == colour).count() >= 64, "the class swatch");
            } else {
                let [r, g, b] = crate::style::Colormap::default().colour(0.99);
                let near = |p: &image::Rgba<u8>| (0..3).all(|c| p.0[c].abs_diff([r, g, b][c]) <= 8);
                assert!(drawn.pixels().filter(|p| near(p)).count() >= 10, "the colormap's top end");
            }
        }
    }
}
