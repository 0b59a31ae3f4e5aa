//! The colour panel's filters: which points the view shows, by return (the
//! `--returns` shorthand) and by any attribute over a range (`--filter
//! NAME=MIN..MAX`), each drawn over its column's histogram. They edit the
//! [`Style`]'s `filters` and `returns`, so the colour panel's one
//! [`super::state::Action::SetStyle`] applies them (`crate::style::filter`)
//! to the view, every mode, picks, screenshots and their sidecars alike.

use egui::{Color32, RichText, Ui};

use crate::cloud::attributes::names;
use crate::style::filter::{Filter, Returns, Test};
use crate::style::summary::{ColumnSummary, Summary};
use crate::style::{ELEVATION, Style};

/// The filters of `style` over a model summed up by `summary`.
pub fn filter_section(ui: &mut Ui, style: &mut Style, summary: &Summary) {
    ui.label(RichText::new("filters: only the points every one keeps are shown").weak());
    let has = |name: &str| summary.columns.iter().any(|c| c.name == name);
    if has(names::RETURN_NUMBER) && has(names::NUMBER_OF_RETURNS) {
        returns_widget(ui, style, summary);
    }
    let mut removed = None;
    for (k, filter) in style.filters.iter_mut().enumerate() {
        let Some(column) = summary.columns.iter().find(|c| c.name == filter.name) else { continue };
        ui.horizontal(|ui| {
            ui.label(RichText::new(&filter.name).strong());
            if ui.small_button("remove").on_hover_text("stop filtering by this attribute").clicked() {
                removed = Some(k);
            }
        });
        range_test_widget(ui, filter, column, k);
    }
    if let Some(k) = removed {
        style.filters.remove(k);
    }
    add_filter_widget(ui, style, summary);
}

/// The return shorthand: all, first, last, only, or a return number.
fn returns_widget(ui: &mut Ui, style: &mut Style, summary: &Summary) {
    let most = summary.columns.iter().find(|c| c.name == names::NUMBER_OF_RETURNS).map_or(1, |c| c.max as u8).max(1);
    let label = |r: Option<Returns>| r.map_or("all".to_string(), Returns::text);
    let mut choices = vec![None, Some(Returns::First), Some(Returns::Last), Some(Returns::Only)];
    choices.extend((1..=most.min(15)).map(|n| Some(Returns::Number(n))));
    egui::ComboBox::new("returns", "returns").selected_text(label(style.returns)).show_ui(ui, |ui| {
        for choice in choices {
            ui.selectable_value(&mut style.returns, choice, label(choice));
        }
    });
}

/// MIN and MAX of a range filter over its column's histogram (the bars
/// kept bright); a filter of listed values shows its text.
fn range_test_widget(ui: &mut Ui, filter: &mut Filter, column: &ColumnSummary, k: usize) {
    let Test::Range(mut lo, mut hi) = filter.test else {
        ui.label(filter.text());
        return;
    };
    let span = (column.max - column.min).max(f64::MIN_POSITIVE);
    let (width, height) = (ui.available_width().min(260.0), 28.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, height), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    let tallest = column.histogram.iter().copied().max().unwrap_or(1).max(1) as f32;
    let bar = rect.width() / column.histogram.len().max(1) as f32;
    for (i, &count) in column.histogram.iter().enumerate() {
        let value = column.min + span * (i as f64 + 0.5) / column.histogram.len() as f64;
        let colour = if (lo..=hi).contains(&value) { Color32::from_rgb(120, 180, 255) } else { Color32::from_gray(80) };
        let h = rect.height() * (count as f32 / tallest).sqrt();
        let x = rect.left() + bar * i as f32;
        let bar_rect = egui::Rect::from_min_max(egui::pos2(x, rect.bottom() - h), egui::pos2(x + bar, rect.bottom()));
        painter.rect_filled(bar_rect, 0.0, colour);
    }
    let speed = span / 500.0;
    ui.horizontal(|ui| {
        ui.push_id(k, |ui| {
            let a = ui.add(egui::DragValue::new(&mut lo).speed(speed).prefix("from "));
            let b = ui.add(egui::DragValue::new(&mut hi).speed(speed).prefix("to "));
            if (a.changed() || b.changed()) && lo <= hi {
                filter.test = Test::Range(lo, hi);
            }
        });
    });
}

/// A new filter on an attribute, over its whole range (it keeps everything until narrowed).
fn add_filter_widget(ui: &mut Ui, style: &mut Style, summary: &Summary) {
    // Elevation is the points' z, not an attribute a filter reads.
    let free: Vec<&ColumnSummary> = summary
        .columns
        .iter()
        .filter(|c| c.name != ELEVATION && !style.filters.iter().any(|f| f.name == c.name))
        .collect();
    if free.is_empty() {
        return;
    }
    egui::ComboBox::new("add a filter", "add a filter").selected_text("attribute…").show_ui(ui, |ui| {
        for column in free {
            if ui.selectable_label(false, &column.name).clicked() {
                let test = Test::Range(column.min, column.max);
                style.filters.push(Filter { name: column.name.clone(), test });
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

    fn returns_tile() -> Summary {
        let mut cloud = PointCloud { positions: vec![glam::Vec3::ZERO; 30], ..Default::default() };
        cloud.attributes.push("intensity", Values::U16((0..30).map(|i| i * 10).collect()));
        cloud.attributes.push(names::RETURN_NUMBER, Values::U8((0..30).map(|i| (i % 3 + 1) as u8).collect()));
        cloud.attributes.push(names::NUMBER_OF_RETURNS, Values::U8(vec![3; 30]));
        Summary::of(&cloud)
    }

    fn panel(summary: &Summary) -> Harness<'_, Style> {
        Harness::new_ui_state(move |ui, style: &mut Style| filter_section(ui, style, summary), Style::default())
    }

    #[test]
    fn the_panel_sets_the_returns_and_adds_and_removes_an_attribute_filter() {
        let summary = returns_tile();
        let mut h = panel(&summary);
        h.get_by_label("returns").click();
        h.run();
        h.get_by_label("first").click();
        h.run();
        assert_eq!(h.state().returns, Some(Returns::First));
        h.get_by_label("add a filter").click();
        h.run();
        h.get_by_label("intensity").click();
        h.run();
        assert_eq!(h.state().filters, vec![Filter { name: "intensity".into(), test: Test::Range(0.0, 290.0) }]);
        h.get_by_label("remove").click();
        h.run();
        assert!(h.state().filters.is_empty());
    }
}
