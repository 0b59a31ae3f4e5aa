//! The legend of a scan coloured by attribute: what the colours show (its
//! title), then the classes shown with their colours, names and opacity, or
//! the colormap as a bar with the values at its ends. [`Legend::of`] works it
//! out once; the view draws it over its lower left corner ([`draw`]) and a
//! saved screenshot burns it in at the same place (`annotate.rs`).

use egui::{Align2, Color32, FontId, Painter, Rect, pos2, vec2};

use crate::style::summary::Summary;
use crate::style::{ColorBy, Colormap, Style, classes};

/// Margin to the view's corner, and one row's height, in points at scale 1.
pub const MARGIN: f32 = 10.0;
pub const ROW: f32 = 16.0;

/// What a legend shows.
#[derive(Debug, Clone, PartialEq)]
pub enum Legend {
    /// One row per class shown: its colour and its label.
    Classes { title: String, rows: Vec<([u8; 3], String)> },
    /// A colormap over a range of values.
    Scale { title: String, colormap: Colormap, range: (f64, f64) },
}

impl Legend {
    /// The legend of `style` over a model summed up by `summary` (none for
    /// the file's own colours); a scale spans `used`, the range the colours
    /// were made with ([`crate::scene::Scene::colour_range`]), else the style's.
    pub fn of(style: &Style, summary: &Summary, used: Option<(f64, f64)>) -> Option<Legend> {
        match style.color_by.as_ref()? {
            ColorBy::Rgb => None,
            ColorBy::Classification => {
                let shown = summary
                    .classes
                    .iter()
                    .map(|c| c.0)
                    .filter(|c| style.classes.as_ref().is_none_or(|l| l.contains(c)));
                let rows = shown
                    .map(|class| {
                        let opacity =
                            style.class_opacity.iter().find(|p| p.0 == class).map(|p| format!(" · {:.2}", p.1));
                        (
                            classes::colour(class),
                            format!("{class} {}{}", classes::name(class), opacity.unwrap_or_default()),
                        )
                    })
                    .collect();
                Some(Legend::Classes { title: "classification".into(), rows })
            }
            by => {
                let column = summary.scalar_column(style)?;
                let range = used.or(style.range).unwrap_or(column.percentiles);
                Some(Legend::Scale { title: by.text(), colormap: style.colormap, range })
            }
        }
    }

    /// Its height and width, in points at scale 1.
    pub fn size(&self) -> (f32, f32) {
        match self {
            Legend::Classes { rows, .. } => (ROW * (rows.len() + 1) as f32, 190.0),
            Legend::Scale { .. } => (ROW * 2.0 + 10.0, 200.0),
        }
    }

    /// The end values of a scale, as they are written.
    pub fn range_labels((lo, hi): (f64, f64)) -> (String, String) {
        (format!("{lo:.4}"), format!("{hi:.4}"))
    }
}

/// Draws `legend` over `view`'s lower left corner.
pub fn draw(painter: &Painter, view: Rect, legend: &Legend) {
    let font = FontId::proportional(12.0);
    let text = Color32::from_gray(230);
    let (height, width) = legend.size();
    let rect = Rect::from_min_size(pos2(view.left() + MARGIN, view.bottom() - MARGIN - height), vec2(width, height));
    painter.rect_filled(rect.expand(4.0), 3.0, Color32::from_black_alpha(150));
    match legend {
        Legend::Classes { title, rows } => {
            painter.text(rect.left_top(), Align2::LEFT_TOP, title, font.clone(), text);
            for (row, ([r, g, b], label)) in rows.iter().enumerate() {
                let y = rect.top() + ROW * (row + 1) as f32;
                let swatch = Rect::from_min_size(pos2(rect.left(), y + 3.0), vec2(10.0, 10.0));
                painter.rect_filled(swatch, 1.0, Color32::from_rgb(*r, *g, *b));
                painter.text(pos2(rect.left() + 16.0, y + ROW / 2.0), Align2::LEFT_CENTER, label, font.clone(), text);
            }
        }
        Legend::Scale { title, colormap, range } => {
            painter.text(rect.left_top(), Align2::LEFT_TOP, title, font.clone(), text);
            let bar = Rect::from_min_size(pos2(rect.left(), rect.top() + ROW), vec2(rect.width(), 10.0));
            let steps = 64;
            for i in 0..steps {
                let [r, g, b] = colormap.colour((i as f64 + 0.5) / steps as f64);
                let x = bar.left() + bar.width() * i as f32 / steps as f32;
                let cell =
                    Rect::from_min_size(pos2(x, bar.top()), vec2(bar.width() / steps as f32 + 0.5, bar.height()));
                painter.rect_filled(cell, 0.0, Color32::from_rgb(r, g, b));
            }
            let (lo, hi) = Legend::range_labels(*range);
            let below = bar.bottom() + 2.0;
            painter.text(pos2(bar.left(), below), Align2::LEFT_TOP, lo, font.clone(), text);
            painter.text(pos2(bar.right(), below), Align2::RIGHT_TOP, hi, font, text);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::PointCloud;
    use crate::cloud::attributes::{Values, names};
    use crate::scene::Scene;

    /// Ground (class 2) from 0 to 10 m and trees (class 5) from 100 to 200 m.
    fn ground_and_trees() -> PointCloud {
        let n = 200;
        let z = |i: usize| if i % 2 == 0 { (i / 2) as f32 * 0.1 } else { 100.0 + (i / 2) as f32 };
        let mut cloud = PointCloud {
            positions: (0..n).map(|i| glam::Vec3::new(i as f32, 0.0, z(i))).collect(),
            normals: vec![glam::Vec3::Z; n],
            radii: vec![0.5; n],
            colours: vec![[10, 20, 30]; n],
            opacity: vec![1.0; n],
            two_sided: vec![false; n],
            ..Default::default()
        };
        cloud.attributes.push(names::CLASSIFICATION, Values::U8((0..n).map(|i| [2, 5][i % 2]).collect()));
        cloud
    }

    #[test]
    fn the_scale_spans_the_range_the_colours_used_after_hidden_classes_left() {
        let cloud = ground_and_trees();
        let summary = Summary::of(&cloud);
        let mut scene = Scene::from(cloud);
        let style = Style { color_by: Some(ColorBy::Elevation), classes: Some(vec![2]), ..Default::default() };
        scene.apply_style(&style).unwrap();
        let used = scene.colour_range().expect("elevation colours span a range");
        assert!(used.1 < 11.0, "the ground alone is coloured: {used:?}");
        let Some(Legend::Scale { range, .. }) = Legend::of(&style, &summary, scene.colour_range()) else {
            panic!("a scale");
        };
        assert_eq!(
            range,
            used,
            "the legend shows the colours' range, not the unstyled file's {:?}",
            summary.scalar_column(&style).unwrap().percentiles
        );
        // A range given by the user is the one the colours use, and so the legend's.
        let fixed = Style { range: Some((1.0, 5.0)), ..style };
        scene.apply_style(&fixed).unwrap();
        let Some(Legend::Scale { range, .. }) = Legend::of(&fixed, &summary, scene.colour_range()) else {
            panic!("a scale");
        };
        assert_eq!(range, (1.0, 5.0));
    }
}
