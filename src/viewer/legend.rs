//! The legend of a scan coloured by attribute, drawn over the view's lower
//! left corner: the classes shown with their colours, names and opacity, or
//! the colormap as a bar with the values at its ends.

use egui::{Align2, Color32, FontId, Painter, Rect, pos2, vec2};

use super::colour_panel::scalar_column;
use crate::style::summary::Summary;
use crate::style::{ColorBy, Style, classes};

const MARGIN: f32 = 10.0;
const ROW: f32 = 16.0;

/// Draws the legend of `style` over `view` (nothing when the colours are the file's own).
pub fn draw(painter: &Painter, view: Rect, style: &Style, summary: &Summary) {
    let font = FontId::proportional(12.0);
    let text = Color32::from_gray(230);
    let panel = |height: f32, width: f32| {
        let rect =
            Rect::from_min_size(pos2(view.left() + MARGIN, view.bottom() - MARGIN - height), vec2(width, height));
        painter.rect_filled(rect.expand(4.0), 3.0, Color32::from_black_alpha(150));
        rect
    };
    match &style.color_by {
        Some(ColorBy::Classification) => {
            let shown: Vec<u8> = summary
                .classes
                .iter()
                .map(|c| c.0)
                .filter(|c| style.classes.as_ref().is_none_or(|list| list.contains(c)))
                .collect();
            let rect = panel(ROW * (shown.len() + 1) as f32, 190.0);
            // The title says what the colours show.
            painter.text(rect.left_top(), Align2::LEFT_TOP, "classification", font.clone(), text);
            for (row, class) in shown.iter().enumerate() {
                let y = rect.top() + ROW * (row + 1) as f32;
                let [r, g, b] = classes::colour(*class);
                painter.rect_filled(
                    Rect::from_min_size(pos2(rect.left(), y + 3.0), vec2(10.0, 10.0)),
                    1.0,
                    Color32::from_rgb(r, g, b),
                );
                let opacity = style.class_opacity.iter().find(|p| p.0 == *class).map(|p| format!(" · {:.2}", p.1));
                let label = format!("{class} {}{}", classes::name(*class), opacity.unwrap_or_default());
                painter.text(pos2(rect.left() + 16.0, y + ROW / 2.0), Align2::LEFT_CENTER, label, font.clone(), text);
            }
        }
        Some(by) => {
            let Some(column) = scalar_column(style, summary) else { return };
            let (lo, hi) = style.range.unwrap_or(column.percentiles);
            let rect = panel(ROW * 2.0 + 10.0, 200.0);
            painter.text(rect.left_top(), Align2::LEFT_TOP, by.text(), font.clone(), text);
            let bar = Rect::from_min_size(pos2(rect.left(), rect.top() + ROW), vec2(rect.width(), 10.0));
            let steps = 64;
            for i in 0..steps {
                let [r, g, b] = style.colormap.colour((i as f64 + 0.5) / steps as f64);
                let x = bar.left() + bar.width() * i as f32 / steps as f32;
                let cell =
                    Rect::from_min_size(pos2(x, bar.top()), vec2(bar.width() / steps as f32 + 0.5, bar.height()));
                painter.rect_filled(cell, 0.0, Color32::from_rgb(r, g, b));
            }
            let below = bar.bottom() + 2.0;
            painter.text(pos2(bar.left(), below), Align2::LEFT_TOP, format!("{lo:.4}"), font.clone(), text);
            painter.text(pos2(bar.right(), below), Align2::RIGHT_TOP, format!("{hi:.4}"), font, text);
        }
        None => {}
    }
}
