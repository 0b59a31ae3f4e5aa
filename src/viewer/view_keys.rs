//! The 3D view's keys for plan and elevation views, and the help overlay
//! that lists every input of the view.
//!
//! The digits 1-7 look from the named views of [`NamedView::ALL`] (top,
//! bottom, front, back, left, right, iso: the same directions as `--view`),
//! `O` switches between perspective and orthographic (`--projection`), `H`
//! shows or hides the help, `F` switches fly mode (W A S D Q E held move
//! the eye, `camera_input::fly`). The keys act only while no text field takes
//! the keyboard. [`INPUTS`] is the one list of the view's inputs: the
//! overlay draws it, and a test holds the user guide's table to it.

use egui::{Align2, Color32, FontId, Key, Painter, Rect, pos2, vec2};

use crate::frame::{Camera, NamedView, Projection};

/// The digit keys of the named views, in [`NamedView::ALL`]'s order.
pub const VIEW_KEYS: [(Key, NamedView); 7] = [
    (Key::Num1, NamedView::Top),
    (Key::Num2, NamedView::Bottom),
    (Key::Num3, NamedView::Front),
    (Key::Num4, NamedView::Back),
    (Key::Num5, NamedView::Left),
    (Key::Num6, NamedView::Right),
    (Key::Num7, NamedView::Iso),
];

/// Switches perspective and orthographic.
pub const PROJECTION_KEY: Key = Key::O;
/// Shows or hides the help overlay.
pub const HELP_KEY: Key = Key::H;
/// Switches fly mode.
pub const FLY_KEY: Key = Key::F;
/// Fly mode's moves while held: (key, (right, up, forward)).
pub const FLY_KEYS: [(Key, [f32; 3]); 6] = [
    (Key::W, [0.0, 0.0, 1.0]),
    (Key::S, [0.0, 0.0, -1.0]),
    (Key::A, [-1.0, 0.0, 0.0]),
    (Key::D, [1.0, 0.0, 0.0]),
    (Key::Q, [0.0, -1.0, 0.0]),
    (Key::E, [0.0, 1.0, 0.0]),
];

/// Every input of the 3D view: (the input, what it does), as the help
/// overlay and the user guide's table give them.
pub const INPUTS: [(&str, &str); 28] = [
    ("left drag", "orbit (in fly mode: look around)"),
    ("right or middle drag", "pan"),
    ("wheel", "zoom to the point under the cursor"),
    ("double-click", "re-centre on the surface under the cursor"),
    ("Home", "reset the camera"),
    ("O", "switch perspective and orthographic"),
    ("1", "top view"),
    ("2", "bottom view"),
    ("3", "front view"),
    ("4", "back view"),
    ("5", "left view"),
    ("6", "right view"),
    ("7", "iso view"),
    ("H", "show or hide this help"),
    ("F", "fly mode on or off"),
    ("W A S D Q E", "fly forward, left, back, right, down, up (fly mode; half the depth under the cursor a second)"),
    ("Ctrl+S", "save the 3D view"),
    ("Ctrl+Shift+S", "save the 3D view at N × its size"),
    ("click (Inspect: pick)", "list every layer under the pixel"),
    ("click (Inspect: measure)", "add the surface under the pixel to the measured polyline"),
    ("drag a clip-box handle", "move that face of the clip box"),
    ("drag (Inspect: select)", "draw the selection's box"),
    ("drag (Inspect: lasso)", "draw the selection's outline"),
    ("click (Inspect: polygon)", "add the surface under the pixel as a vertex of the polygon"),
    ("click (Inspect: profile)", "set an end of the profile's line"),
    ("drag a profile's side handle", "set the slab's width"),
    ("click the profile's section", "pick the point nearest; a second click measures the rise and slope"),
    ("cursor over the view", "its file coordinates in the status line (two-pass)"),
];

/// What a key pressed asks of the view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewKey {
    Look(NamedView),
    SwitchProjection,
    Help,
    Fly,
}

/// Fly mode's move this frame, as (right, up, forward) directions of the
/// keys held (none while a text field has the keyboard or a modifier is held).
pub fn fly_direction(ctx: &egui::Context) -> glam::Vec3 {
    if ctx.egui_wants_keyboard_input() {
        return glam::Vec3::ZERO;
    }
    ctx.input(|i| {
        if !i.modifiers.is_none() {
            return glam::Vec3::ZERO;
        }
        FLY_KEYS.iter().filter(|(key, _)| i.key_down(*key)).map(|(_, d)| glam::Vec3::from_array(*d)).sum()
    })
}

/// The view keys pressed this frame, in the order above (none while a text
/// field has the keyboard).
pub fn pressed(ctx: &egui::Context) -> Vec<ViewKey> {
    if ctx.egui_wants_keyboard_input() {
        return Vec::new();
    }
    ctx.input(|i| {
        let plain = |key| i.key_pressed(key) && i.modifiers.is_none();
        let mut keys: Vec<ViewKey> =
            VIEW_KEYS.iter().filter(|(key, _)| plain(*key)).map(|(_, view)| ViewKey::Look(*view)).collect();
        if plain(PROJECTION_KEY) {
            keys.push(ViewKey::SwitchProjection);
        }
        if plain(HELP_KEY) {
            keys.push(ViewKey::Help);
        }
        if plain(FLY_KEY) {
            keys.push(ViewKey::Fly);
        }
        keys
    })
}

/// Applies a view key to the camera; whether the camera changed.
pub fn apply(camera: &mut Camera, key: ViewKey) -> bool {
    match key {
        ViewKey::Look(view) => camera.look_from(view),
        ViewKey::SwitchProjection => camera.projection = other(camera.projection),
        ViewKey::Help | ViewKey::Fly => return false,
    }
    true
}

/// The other projection.
pub fn other(projection: Projection) -> Projection {
    match projection {
        Projection::Perspective => Projection::Ortho,
        Projection::Ortho => Projection::Perspective,
    }
}

/// The help overlay: [`INPUTS`] in two columns over a dark panel in the
/// view's upper right corner, as wide as its longest line (at most the view's width).
pub fn draw_help(painter: &Painter, view: Rect) {
    let font = FontId::proportional(13.0);
    let row = 17.0;
    let width = |text: &str| painter.layout_no_wrap(text.to_string(), font.clone(), Color32::WHITE).size().x;
    let key_width = INPUTS.iter().map(|(input, _)| width(input)).fold(0.0, f32::max) + 24.0;
    let does_width = INPUTS.iter().map(|(_, does)| width(does)).fold(0.0, f32::max) + 16.0;
    let size = vec2((key_width + does_width).min(view.width() - 20.0), row * (INPUTS.len() as f32 + 1.0) + 12.0);
    let panel = Rect::from_min_size(pos2(view.right() - size.x - 10.0, view.top() + 10.0), size);
    painter.rect_filled(panel, 4.0, Color32::from_black_alpha(200));
    let mut y = panel.top() + 6.0;
    painter.text(pos2(panel.left() + 8.0, y), Align2::LEFT_TOP, "View inputs (H hides)", font.clone(), Color32::WHITE);
    for (input, does) in INPUTS {
        y += row;
        let key_colour = Color32::from_rgb(255, 220, 120);
        painter.text(pos2(panel.left() + 8.0, y), Align2::LEFT_TOP, input, font.clone(), key_colour);
        painter.text(pos2(panel.left() + key_width, y), Align2::LEFT_TOP, does, font.clone(), Color32::LIGHT_GRAY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_view_has_its_digit_and_its_line_of_help() {
        for (k, (key, view)) in VIEW_KEYS.iter().enumerate() {
            assert_eq!(*view, NamedView::ALL[k]);
            let digit = key.name();
            let line =
                INPUTS.iter().find(|(input, _)| *input == digit).unwrap_or_else(|| panic!("no help for {digit}"));
            assert_eq!(line.1, format!("{} view", view.name()));
        }
        for key in [PROJECTION_KEY, HELP_KEY, FLY_KEY] {
            assert!(INPUTS.iter().any(|(input, _)| *input == key.name()), "no help for {}", key.name());
        }
    }

    #[test]
    fn the_user_guide_lists_every_input_of_the_view() {
        let guide = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/USER_GUIDE.md")).unwrap();
        for (input, _) in INPUTS {
            let row = format!("| {input} |");
            assert!(guide.contains(&row), "docs/USER_GUIDE.md's viewer table has no row `{row}`");
        }
    }

    #[test]
    fn the_projection_key_switches_and_a_view_key_looks_from_its_view() {
        let mut camera = Camera::framing(glam::Vec3::ZERO, 1.0, 1.0);
        assert!(apply(&mut camera, ViewKey::SwitchProjection));
        assert_eq!(camera.projection, Projection::Ortho);
        assert!(apply(&mut camera, ViewKey::Look(NamedView::Top)));
        assert_eq!((camera.azimuth_deg, camera.elevation_deg), NamedView::Top.angles());
        apply(&mut camera, ViewKey::SwitchProjection);
        assert_eq!(camera.projection, Projection::Perspective);
    }
}
