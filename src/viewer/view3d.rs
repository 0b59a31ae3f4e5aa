//! The 3D view: the latest frame from the render thread, the camera controls
//! on it (orbit, pan, zoom to the cursor, double-click to re-centre), the
//! inspection tools' input and overlay (`inspect.rs`), keyboard shortcuts
//! (the view keys and the help overlay: `view_keys.rs`), the scale bar of an
//! orthographic view (`scale_bar.rs`) and the scripted
//! screenshot-and-exit sequence.

use std::path::PathBuf;

use glam::Vec2;

use super::app::ViewerApp;
use super::{camera_input, scale_bar, view_keys};

impl ViewerApp {
    /// Handles dropped files and keyboard shortcuts.
    pub(super) fn handle_input(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).collect());
        for path in &dropped {
            self.open_or_add(ctx, path);
        }
        let command_shift = egui::Modifiers::COMMAND | egui::Modifiers::SHIFT;
        if ctx.input_mut(|i| i.consume_key(command_shift, egui::Key::S)) {
            self.save_large_screenshot();
        }
        if ctx.input_mut(|i| i.consume_key(egui::Modifiers::COMMAND, egui::Key::S)) {
            self.save_screenshot();
        }
        if ctx.input(|i| i.key_pressed(egui::Key::Home)) && !ctx.egui_wants_keyboard_input() {
            self.reset_camera();
        }
        for key in view_keys::pressed(ctx) {
            match key {
                view_keys::ViewKey::Help => self.ui.help_shown = !self.ui.help_shown,
                view_keys::ViewKey::Fly => self.ui.fly = !self.ui.fly,
                _ if view_keys::apply(&mut self.ui.camera, key) => self.camera_moved(),
                _ => {}
            }
        }
        self.fly_keys(ctx);
    }

    /// Fly mode: the W A S D Q E held move the eye by this frame's share of the speed.
    fn fly_keys(&mut self, ctx: &egui::Context) {
        let direction = view_keys::fly_direction(ctx);
        if !self.ui.fly || direction == glam::Vec3::ZERO {
            return;
        }
        let seconds = ctx.input(|i| i.stable_dt).min(0.1);
        let speed = camera_input::fly_speed(&self.ui.camera, self.depth_under_pointer());
        camera_input::fly(&mut self.ui.camera, &self.scene, direction.normalize() * speed * seconds);
        self.camera_moved();
        ctx.request_repaint();
    }

    /// The 3D view: the latest frame, and the camera controls on it.
    pub(super) fn view_ui(&mut self, ui: &mut egui::Ui) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), egui::Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point();
        self.view_rect = rect;
        let max_side = 8192.0;
        self.view_size = (
            (rect.width() * ppp).round().clamp(1.0, max_side) as u32,
            (rect.height() * ppp).round().clamp(1.0, max_side) as u32,
        );
        let painter = ui.painter_at(rect);
        let bg = self.ui.settings.shading.background;
        painter.rect_filled(
            rect,
            0.0,
            egui::Color32::from_rgb((bg.x * 255.0) as u8, (bg.y * 255.0) as u8, (bg.z * 255.0) as u8),
        );
        if let Some(shown) = &self.shown {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            painter.image(shown.texture.id(), rect, uv, egui::Color32::WHITE);
        }
        self.draw_inspection(&painter, rect);
        self.draw_selection(&painter);
        if let Some(legend) = self.legend() {
            super::legend::draw(&painter, rect, &legend);
        }
        if let Some(model) = &self.model {
            let (_, unit) = model.scene.frame_placement();
            if let Some(bar) = scale_bar::of(&self.ui.camera, rect.height(), unit, &model.cloud.units) {
                scale_bar::draw(&painter, rect, &bar);
            }
        }
        if self.ui.help_shown {
            view_keys::draw_help(&painter, rect);
        }
        if let Some(e) = &self.frame_error {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                e,
                egui::FontId::proportional(16.0),
                egui::Color32::LIGHT_RED,
            );
        }
        let to_vec = |v: egui::Vec2| Vec2::new(v.x, v.y);
        let mut moved = false;
        // A clip-box handle's drag moves the box, not the camera; a click picks or measures.
        let taken = self.inspect_input(&response, rect, ppp);
        if response.dragged_by(egui::PointerButton::Primary) && !taken {
            match self.ui.fly {
                true => camera_input::look(&mut self.ui.camera, &self.scene, to_vec(response.drag_delta())),
                false => camera_input::orbit(&mut self.ui.camera, to_vec(response.drag_delta())),
            }
            moved = true;
        }
        if response.dragged_by(egui::PointerButton::Secondary) || response.dragged_by(egui::PointerButton::Middle) {
            camera_input::pan(&mut self.ui.camera, &self.scene, to_vec(response.drag_delta()), rect.height());
            moved = true;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                if let Some(cursor) = response.hover_pos() {
                    let about = self.zoom_anchor(cursor, rect);
                    camera_input::zoom_about(&mut self.ui.camera, &self.scene, scroll, about);
                }
                moved = true;
            }
        }
        if response.double_clicked() {
            if let (Some(pos), Some(model)) = (response.interact_pointer_pos(), &self.model) {
                let uv = Vec2::new((pos.x - rect.left()) / rect.width(), (pos.y - rect.top()) / rect.height());
                let aspect = rect.width() / rect.height().max(1.0);
                if let Some(hit) = camera_input::pick(&model.cloud, &self.ui.camera, uv, aspect) {
                    self.scene.retarget(&mut self.ui.camera, hit);
                    moved = true;
                }
            }
        }
        if moved {
            self.camera_moved();
        }
    }

    /// The point a wheel zoom keeps under the cursor at `cursor`: the surface
    /// there, else the cursor's point on the target's plane. Kept while the
    /// cursor stays put, which the zoom keeps it under, so a turn of the
    /// wheel looks for the surface once.
    fn zoom_anchor(&mut self, cursor: egui::Pos2, rect: egui::Rect) -> glam::Vec3 {
        if let Some((_, point)) = self.zoom_anchor.filter(|(at, _)| at.distance(cursor) < 0.5) {
            return point;
        }
        let uv = Vec2::new((cursor.x - rect.left()) / rect.width(), (cursor.y - rect.top()) / rect.height());
        let aspect = rect.width() / rect.height().max(1.0);
        let surface = self.model.as_ref().and_then(|m| camera_input::pick(&m.cloud, &self.ui.camera, uv, aspect));
        let point = surface.unwrap_or_else(|| camera_input::on_target_plane(&self.ui.camera, uv, aspect));
        self.zoom_anchor = Some((cursor, point));
        point
    }

    /// `--screenshot` / `--exit-after-frames`: once settled, count frames, then shoot and close.
    pub(super) fn scripted_exit(&mut self, ctx: &egui::Context) {
        let Some(limit) = self.options.exit_after_frames.or(self.options.screenshot.as_ref().map(|_| 2)) else {
            return;
        };
        ctx.request_repaint();
        if !self.is_settled() || self.window_shot_requested {
            return;
        }
        self.frames_since_ready += 1;
        if self.frames_since_ready < limit {
            return;
        }
        self.window_shot_requested = true;
        let Some(path) = self.options.screenshot.clone() else {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        };
        let close = ctx.clone();
        // What the window shows, for the line that reports the shot.
        let shown = self.shown_frame().map(|(_, key)| key.settings.mode);
        let showing = match (self.model(), shown) {
            (Some(model), Some(mode)) => format!(" ({} in {mode})", model.name),
            _ => String::new(),
        };
        ctx.request_screenshot(move |shot| {
            let [w, h] = shot.size;
            let bytes: Vec<u8> = shot.pixels.iter().flat_map(|c| c.to_array()).collect();
            match image::RgbaImage::from_raw(w as u32, h as u32, bytes) {
                Some(image) => match crate::output::save_png(&image, &path) {
                    Ok(()) => eprintln!("saved the window to {}{showing}", path.display()),
                    Err(e) => eprintln!("error: {}: {e}", path.display()),
                },
                None => eprintln!("error: the window screenshot has the wrong size"),
            }
            close.send_viewport_cmd(egui::ViewportCommand::Close);
        });
    }
}
