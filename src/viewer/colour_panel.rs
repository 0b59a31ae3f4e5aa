//! The colour panel of a scan with attributes: what the colours show (the
//! file's colours, its classes, the elevation or any attribute), the
//! colormap, the range over the column's histogram, each class shown or
//! hidden with its opacity, an attribute as opacity, and the filters
//! (`filter_panel.rs`). Every edit becomes
//! one [`Action::SetStyle`]: the model is restyled from the file's own values
//! in the background ([`crate::style`]), so every mode and the reference draw it.

use egui::{Color32, RichText, Ui};

use super::state::{Action, ModelInfo};
use crate::cloud::attributes::names;
use crate::style::summary::{ColumnSummary, Summary};
use crate::style::{ColorBy, Colormap, Style, classes};

/// The panel's section; nothing for a model without attributes.
pub fn colour_section(ui: &mut Ui, model: &ModelInfo<'_>, actions: &mut Vec<Action>) {
    let summary = model.summary;
    if summary.columns.is_empty() {
        return;
    }
    ui.heading("Colour");
    let current = model.style.cloned().unwrap_or_default();
    let mut edited = current.clone();
    color_by_widget(ui, &mut edited, summary);
    if let Some(column) = summary.scalar_column(&edited) {
        egui::ComboBox::new("colormap", "colormap").selected_text(edited.colormap.name()).show_ui(ui, |ui| {
            for map in Colormap::ALL {
                ui.selectable_value(&mut edited.colormap, map, map.name());
            }
        });
        range_widget(ui, &mut edited, column);
    }
    if !summary.classes.is_empty() {
        classes_widget(ui, &mut edited, &summary.classes);
    }
    opacity_by_widget(ui, &mut edited, summary);
    super::filter_panel::filter_section(ui, &mut edited, summary);
    if edited != current {
        actions.push(Action::SetStyle((!edited.is_plain()).then_some(edited)));
    }
}

fn color_by_widget(ui: &mut Ui, style: &mut Style, summary: &Summary) {
    let mut choices = vec![ColorBy::Rgb];
    if !summary.classes.is_empty() {
        choices.push(ColorBy::Classification);
    }
    // The classification column is coloured by its class colours (above), not through a colormap.
    choices.extend(
        summary.columns.iter().filter(|c| c.name != names::CLASSIFICATION).map(|c| ColorBy::of_column(&c.name)),
    );
    let shown = style.color_by.clone().unwrap_or(ColorBy::Rgb);
    egui::ComboBox::new("colour by", "colour by").selected_text(shown.text()).show_ui(ui, |ui| {
        for choice in choices {
            let label = choice.text();
            if ui.selectable_label(shown == choice, label).clicked() && shown != choice {
                style.color_by = Some(choice);
                style.range = None;
            }
        }
    });
}

/// The colormap's ends over the column's histogram: two values, and the
/// bars outside them dimmed; "2-98 %" goes back to the default percentiles.
fn range_widget(ui: &mut Ui, style: &mut Style, column: &ColumnSummary) {
    let (mut lo, mut hi) = style.range.unwrap_or(column.percentiles);
    let span = (column.max - column.min).max(f64::MIN_POSITIVE);
    let (width, height) = (ui.available_width().min(260.0), 36.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, height), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    let tallest = column.histogram.iter().copied().max().unwrap_or(1).max(1) as f32;
    let bar = rect.width() / column.histogram.len() as f32;
    for (i, &count) in column.histogram.iter().enumerate() {
        let value = column.min + span * (i as f64 + 0.5) / column.histogram.len() as f64;
        let t = ((value - lo) / (hi - lo).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        let [r, g, b] = style.colormap.colour(t);
        let inside = (lo..=hi).contains(&value);
        let colour = if inside { Color32::from_rgb(r, g, b) } else { Color32::from_gray(90) };
        let h = rect.height() * (count as f32 / tallest).sqrt();
        let x = rect.left() + bar * i as f32;
        painter.rect_filled(
            egui::Rect::from_min_max(egui::pos2(x, rect.bottom() - h), egui::pos2(x + bar, rect.bottom())),
            0.0,
            colour,
        );
    }
    let speed = span / 500.0;
    ui.horizontal(|ui| {
        let a = ui.add(egui::DragValue::new(&mut lo).speed(speed).prefix("from "));
        let b = ui.add(egui::DragValue::new(&mut hi).speed(speed).prefix("to "));
        if (a.changed() || b.changed()) && lo < hi {
            style.range = Some((lo, hi));
        }
        if ui.button("2-98 %").on_hover_text("the 2nd to 98th percentile of the values").clicked() {
            style.range = None;
        }
    });
}

/// A checkbox and an opacity slider per class present.
fn classes_widget(ui: &mut Ui, style: &mut Style, present: &[(u8, usize)]) {
    ui.label(RichText::new("classes: shown, and their opacity").weak());
    for &(class, count) in present {
        ui.horizontal(|ui| {
            let mut shown = style.classes.as_ref().is_none_or(|c| c.contains(&class));
            let [r, g, b] = classes::colour(class);
            let label =
                RichText::new(format!("{class} {} ({count})", classes::name(class))).color(Color32::from_rgb(r, g, b));
            if ui.checkbox(&mut shown, label).changed() {
                let mut list: Vec<u8> = style.classes.clone().unwrap_or_else(|| present.iter().map(|p| p.0).collect());
                list.retain(|&c| c != class);
                if shown {
                    list.push(class);
                    list.sort_unstable();
                }
                style.classes = (list.len() < present.len()).then_some(list);
            }
            let mut opacity = style.class_opacity.iter().find(|p| p.0 == class).map_or(1.0, |p| p.1);
            let slider = ui.add(egui::Slider::new(&mut opacity, 0.0..=1.0).fixed_decimals(2).text("opacity"));
            if slider.drag_stopped() || (slider.changed() && !slider.dragged()) {
                style.class_opacity.retain(|p| p.0 != class);
                if opacity < 1.0 {
                    style.class_opacity.push((class, opacity));
                    style.class_opacity.sort_by_key(|p| p.0);
                }
            }
        });
    }
}

fn opacity_by_widget(ui: &mut Ui, style: &mut Style, summary: &Summary) {
    let shown = style.opacity_by.clone().unwrap_or_else(|| "none".into());
    egui::ComboBox::new("opacity by", "opacity by").selected_text(&shown).show_ui(ui, |ui| {
        if ui.selectable_label(style.opacity_by.is_none(), "none").clicked() {
            style.opacity_by = None;
        }
        for column in summary.columns.iter().filter(|c| c.name != crate::style::ELEVATION) {
            if ui.selectable_label(shown == column.name, &column.name).clicked() {
                style.opacity_by = Some(column.name.clone());
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::{PointCloud, Values};
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;

    fn tile() -> Summary {
        let mut cloud = PointCloud {
            positions: (0..30).map(|i| glam::Vec3::new(i as f32, 0.0, (i % 7) as f32)).collect(),
            ..Default::default()
        };
        cloud.attributes.push("intensity", Values::U16((0..30).map(|i| i * 10).collect()));
        cloud.attributes.push("classification", Values::U8((0..30).map(|i| [2, 5, 6][i % 3]).collect()));
        Summary::of(&cloud)
    }

    fn panel(summary: &Summary, style: Option<Style>) -> Harness<'_, (Option<Style>, Vec<Action>)> {
        Harness::new_ui_state(
            move |ui, (style, actions): &mut (Option<Style>, Vec<Action>)| {
                let model = ModelInfo {
                    name: "tile.laz",
                    path: std::path::Path::new("tile.laz"),
                    splats: 30,
                    warnings: &[],
                    opacity: (1.0, true),
                    transparent: false,
                    environment: None,
                    period: 0.0,
                    style: style.as_ref(),
                    summary,
                };
                colour_section(ui, &model, actions);
            },
            (style, Vec::new()),
        )
    }

    #[test]
    fn choosing_classification_in_the_panel_asks_for_class_colours() {
        let summary = tile();
        let mut harness = panel(&summary, None);
        harness.get_by_label("colour by").click();
        harness.run();
        harness.get_by_label("classification").click();
        harness.run();
        let asked = harness.state().1.last().cloned();
        let want = Style { color_by: Some(ColorBy::Classification), ..Default::default() };
        assert_eq!(asked, Some(Action::SetStyle(Some(want))));
    }

    #[test]
    fn unticking_a_class_hides_it_and_the_others_stay() {
        let summary = tile();
        let style = Style { color_by: Some(ColorBy::Classification), ..Default::default() };
        let mut harness = panel(&summary, Some(style));
        harness.get_by_label_contains("high vegetation").click();
        harness.run();
        match harness.state().1.last() {
            Some(Action::SetStyle(Some(s))) => assert_eq!(s.classes, Some(vec![2, 6])),
            other => panic!("asked {other:?}"),
        }
    }
}
