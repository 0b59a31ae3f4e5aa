//! Measurement labels burnt into a saved screenshot: the measured polyline,
//! a dot on each point and each segment's length at its middle, as the view
//! draws them over the frame (`inspect.rs`), placed by the screenshot's own
//! projection and scaled with its size. Drawn with `plotters` in the
//! bundled font (`crate::font`).

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
}

impl Annotation {
    pub fn is_empty(&self) -> bool {
        self.points.len() < 2
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
        root.present().map_err(|e| e.to_string())?;
    }
    let rgb = image::RgbImage::from_raw(size.0, size.1, buffer).ok_or("the annotated image has the wrong size")?;
    Ok(image::DynamicImage::ImageRgb8(rgb).into_rgba8())
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
}
