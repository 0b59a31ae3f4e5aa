//! The inspection tools in the 3D view: the clip box drawn with a handle on
//! each face (dragging one moves that face along its axis), the profile's
//! slab with a handle on each long side (dragging one sets its width), a click that
//! picks (the exact reference's layers under the pixel,
//! crates/core/src/reference/pick.rs) or adds a measured point, and the
//! markers and labels of both drawn over the frame.

use glam::{DVec3, Vec2, Vec3};

use super::annotate::Annotation;
use super::app::ViewerApp;
use super::state::Tool;
use crate::frame::clip::{ClipBox, Hidden};
use crate::inspect::PickReport;

/// Points within which a press grabs a handle.
const HANDLE_REACH: f32 = 10.0;

/// The `dragging` value of the profile's width handles (0-5 are the clip box's faces).
const WIDTH_HANDLE: usize = 6;

/// The profile's width handles: the middles of its slab's long sides, at the line's height.
fn width_handles(inspect: &super::state::Inspection) -> Option<[DVec3; 2]> {
    let [a, b] = inspect.profile_line[..] else { return None };
    let profile = crate::inspect::profile::Profile::new(a.truncate(), b.truncate(), inspect.profile_width).ok()?;
    let (_, left) = profile.axes();
    let (middle, half) = ((a + b) * 0.5, (left * profile.width * 0.5).extend(0.0));
    Some([middle + half, middle - half])
}

/// Screen positions (points) of file coordinates, for the view on screen.
struct Projector {
    view_projection: glam::Mat4,
    origin: DVec3,
    unit: f64,
    rect: egui::Rect,
}

impl Projector {
    fn to_screen(&self, file: DVec3) -> Option<egui::Pos2> {
        let p = ((file - self.origin) / self.unit).as_vec3();
        let clip = self.view_projection * p.extend(1.0);
        (clip.w > 0.0).then(|| {
            let ndc = Vec2::new(clip.x / clip.w, clip.y / clip.w);
            egui::pos2(
                self.rect.left() + (ndc.x + 1.0) * 0.5 * self.rect.width(),
                self.rect.top() + (1.0 - ndc.y) * 0.5 * self.rect.height(),
            )
        })
    }
}

/// A measured segment's label: its length in file units.
fn segment_label(a: DVec3, b: DVec3) -> String {
    format!("{:.3}", a.distance(b))
}

/// The centre of face `face` (axis · 2 + 1 for the max side) of the box.
fn face_centre(b: &ClipBox, face: usize) -> DVec3 {
    let (min, max) = (DVec3::from_array(b.min), DVec3::from_array(b.max));
    let mut c = (min + max) * 0.5;
    let axis = face / 2;
    c[axis] = if face % 2 == 1 { max[axis] } else { min[axis] };
    c
}

impl ViewerApp {
    fn projector(&self, rect: egui::Rect) -> Option<Projector> {
        let model = self.model.as_ref()?;
        let (origin, unit) = model.scene.frame_placement();
        let aspect = rect.width() / rect.height().max(1.0);
        let camera = &self.ui.camera;
        Some(Projector { view_projection: camera.projection(aspect) * camera.view_matrix(), origin, unit, rect })
    }

    /// Where the handle of box face `face` (axis · 2 + 1 for the max side) is on screen, in points.
    pub fn clip_handle(&self, face: usize) -> Option<egui::Pos2> {
        let b = self.ui.inspect.clip_box.as_ref().filter(|_| self.ui.inspect.clip_on)?;
        self.projector(self.view_rect)?.to_screen(face_centre(b, face))
    }

    /// The measurement drawn over a screenshot of `size` pixels of the view
    /// (its own projection: a fixed size may have another aspect).
    pub(super) fn screenshot_annotation(&self, size: (u32, u32)) -> Annotation {
        let measured = &self.ui.inspect.measured;
        let rect = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(size.0 as f32, size.1 as f32));
        let scale = size.0 as f32 / self.view_size.0.max(1) as f32;
        let legend = self.legend();
        let Some(projector) = self.projector(rect).filter(|_| measured.len() >= 2) else {
            return Annotation { scale, legend, ..Annotation::default() };
        };
        Annotation {
            points: measured.iter().map(|(_, p)| projector.to_screen(*p).map(|s| (s.x, s.y))).collect(),
            segment_labels: measured.windows(2).map(|pair| segment_label(pair[0].1, pair[1].1)).collect(),
            scale,
            legend,
        }
    }

    /// The legend drawn over the view (and burnt into screenshots), if the colours show an attribute.
    pub fn legend_shown(&self) -> Option<super::legend::Legend> {
        self.legend()
    }

    /// The legend of the model's colours, if they show an attribute.
    pub(super) fn legend(&self) -> Option<super::legend::Legend> {
        let model = self.model.as_ref()?;
        super::legend::Legend::of(model.style.as_ref()?, &model.summary, model.scene.colour_range())
    }

    /// Where the file point `p` is on screen, in points.
    pub fn screen_position(&self, p: DVec3) -> Option<egui::Pos2> {
        self.projector(self.view_rect)?.to_screen(p)
    }

    /// Gives the clip box the model's bounds (file coordinates) when the clip is switched on without one.
    pub(super) fn ensure_clip_box(&mut self) {
        let inspect = &mut self.ui.inspect;
        if !inspect.clip_on || inspect.clip_box.is_some() {
            return;
        }
        let Some(model) = &self.model else { return };
        let Some(bounds) = model.cloud.bounds() else { return };
        let (origin, unit) = model.scene.frame_placement();
        let file = |p: Vec3| (p.as_dvec3() * unit + origin).to_array();
        inspect.clip_box = Some(ClipBox { min: file(bounds.min), max: file(bounds.max), hide: Hidden::Outside });
    }

    /// The layers under `pixel` of the view, by the exact reference with the frame's settings (clip included).
    pub fn pick_pixel(&self, pixel: [u32; 2]) -> Option<PickReport> {
        let model = self.model.as_ref()?;
        let key = self.current_key()?;
        let options = crate::reference::pick::options(&key.settings, &model.scene);
        Some(PickReport::of(&model.scene, &self.ui.camera, &options, self.view_size, pixel))
    }

    /// A click in the view at `pos`: a pick, or a measured point, by the tool chosen.
    fn click(&mut self, pos: egui::Pos2, rect: egui::Rect, ppp: f32) {
        if self.ui.inspect.tool == Tool::Look {
            return;
        }
        let to_pixel = |v: f32, side: u32| ((v * ppp).floor().max(0.0) as u32).min(side.saturating_sub(1));
        let pixel = [to_pixel(pos.x - rect.left(), self.view_size.0), to_pixel(pos.y - rect.top(), self.view_size.1)];
        let Some(report) = self.pick_pixel(pixel) else { return };
        if matches!(self.ui.inspect.tool, Tool::Measure | Tool::Polygon | Tool::Profile) {
            match report.layers.first() {
                Some(nearest) if self.ui.inspect.tool == Tool::Profile => {
                    self.ui.inspect.add_profile_end(nearest.position)
                }
                Some(nearest) if self.ui.inspect.tool == Tool::Polygon => {
                    self.ui.inspect.polygon.push(nearest.position)
                }
                Some(nearest) => self.ui.inspect.measured.push((pixel, nearest.position)),
                None => self.status = Some(format!("pixel ({}, {}) shows no surface to measure", pixel[0], pixel[1])),
            }
        }
        self.ui.inspect.picked = Some(report);
    }

    /// The handle (a box face, or the profile's width) within reach of `pos`, nearest first.
    fn handle_at(&self, pos: egui::Pos2, projector: &Projector) -> Option<usize> {
        let inspect = &self.ui.inspect;
        let faces =
            inspect.clip_box.as_ref().filter(|_| inspect.clip_on).map(|b| (0..6).map(|f| (f, face_centre(b, f))));
        let widths = width_handles(inspect).map(|w| w.map(|p| (WIDTH_HANDLE, p)));
        faces
            .into_iter()
            .flatten()
            .chain(widths.into_iter().flatten())
            .filter_map(|(handle, p)| Some((handle, projector.to_screen(p)?.distance(pos))))
            .filter(|(_, d)| *d <= HANDLE_REACH)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(handle, _)| handle)
    }

    /// Sets the profile's width to twice the pointer's distance from its
    /// line, across it on screen (exact in an orthographic top view).
    fn drag_width(&mut self, at: egui::Pos2, projector: &Projector) {
        let inspect = &mut self.ui.inspect;
        let Some([side, other]) = width_handles(inspect) else { return };
        let middle = (side + other) * 0.5;
        let unit_across = (side - middle).normalize_or_zero();
        let (Some(m), Some(c)) = (projector.to_screen(middle), projector.to_screen(middle + unit_across)) else {
            return;
        };
        let across = c - m;
        if across.length_sq() < 1e-6 {
            return; // the slab is seen edge-on
        }
        let offset = f64::from((at - m).dot(across) / across.length_sq());
        inspect.profile_width = (2.0 * offset.abs()).max(1e-6);
    }

    /// Moves the dragged face along its axis by the drag's share of the axis on screen.
    fn drag_face(&mut self, face: usize, drag: egui::Vec2, projector: &Projector) {
        let Some(b) = self.ui.inspect.clip_box.as_mut() else { return };
        let axis = face / 2;
        let (min, max) = (DVec3::from_array(b.min), DVec3::from_array(b.max));
        let length = (max - min).max_element().max(1e-9) * 0.1;
        let centre = face_centre(b, face);
        let mut ahead = centre;
        ahead[axis] += length;
        let (Some(a), Some(c)) = (projector.to_screen(centre), projector.to_screen(ahead)) else { return };
        let along = c - a;
        if along.length_sq() < 1e-6 {
            return; // the axis points at the viewer: no drag moves the face
        }
        let moved = (drag.dot(along) / along.length_sq()) as f64 * length;
        let value = if face % 2 == 1 { &mut b.max[axis] } else { &mut b.min[axis] };
        *value += moved;
        // The box keeps min <= max.
        if b.min[axis] > b.max[axis] {
            let middle = if face % 2 == 1 { b.min[axis] } else { b.max[axis] };
            b.min[axis] = middle;
            b.max[axis] = middle;
        }
    }

    /// The view's inspection input: a press on a handle drags its face
    /// (the camera stays), a click picks or measures. Returns whether the
    /// input was taken (the camera must not move for it).
    pub(super) fn inspect_input(&mut self, response: &egui::Response, rect: egui::Rect, ppp: f32) -> bool {
        if matches!(self.ui.inspect.tool, Tool::Select | Tool::Lasso) {
            return self.select_input(response);
        }
        let Some(projector) = self.projector(rect) else { return false };
        if response.drag_started_by(egui::PointerButton::Primary) {
            let press = response.interact_pointer_pos().map(|p| p - response.drag_delta());
            self.ui.inspect.dragging = press.and_then(|p| self.handle_at(p, &projector));
        }
        if let Some(face) = self.ui.inspect.dragging {
            match response.interact_pointer_pos() {
                Some(at) if face == WIDTH_HANDLE => self.drag_width(at, &projector),
                _ if response.dragged_by(egui::PointerButton::Primary) => {
                    self.drag_face(face, response.drag_delta(), &projector)
                }
                _ => {}
            }
            if response.drag_stopped() {
                self.ui.inspect.dragging = None;
            }
            return true;
        }
        if response.clicked() {
            if let Some(pos) = response.interact_pointer_pos() {
                self.click(pos, rect, ppp);
            }
        }
        false
    }

    /// Draws the clip box and its handles, the pick's marker and the measured polyline with its labels.
    pub(super) fn draw_inspection(&self, painter: &egui::Painter, rect: egui::Rect) {
        let Some(projector) = self.projector(rect) else { return };
        let inspect = &self.ui.inspect;
        let font = egui::FontId::proportional(13.0);
        if let Some(b) = inspect.clip_box.as_ref().filter(|_| inspect.clip_on) {
            let corner = |k: usize| {
                DVec3::new(
                    if k & 1 == 0 { b.min[0] } else { b.max[0] },
                    if k & 2 == 0 { b.min[1] } else { b.max[1] },
                    if k & 4 == 0 { b.min[2] } else { b.max[2] },
                )
            };
            let stroke = egui::Stroke::new(1.5, egui::Color32::from_rgb(250, 200, 60));
            for a in 0..8usize {
                for bit in [1, 2, 4] {
                    if a & bit == 0 {
                        if let (Some(p), Some(q)) =
                            (projector.to_screen(corner(a)), projector.to_screen(corner(a | bit)))
                        {
                            painter.line_segment([p, q], stroke);
                        }
                    }
                }
            }
            for face in 0..6 {
                if let Some(p) = projector.to_screen(face_centre(b, face)) {
                    let active = inspect.dragging == Some(face);
                    let fill = if active { egui::Color32::WHITE } else { egui::Color32::from_rgb(250, 200, 60) };
                    painter.circle(p, 6.0, fill, egui::Stroke::new(1.0, egui::Color32::BLACK));
                }
            }
        }
        if let Some(report) = &inspect.picked {
            if let Some(p) = report.layers.first().and_then(|l| projector.to_screen(l.position)) {
                painter.circle_stroke(p, 7.0, egui::Stroke::new(2.0, egui::Color32::from_rgb(80, 220, 255)));
                let text = format!("{} layer(s)", report.layers.len());
                painter.text(
                    p + egui::vec2(10.0, -10.0),
                    egui::Align2::LEFT_BOTTOM,
                    text,
                    font.clone(),
                    egui::Color32::WHITE,
                );
            }
        }
        let measured: Vec<Option<egui::Pos2>> = inspect.measured.iter().map(|(_, p)| projector.to_screen(*p)).collect();
        let [r, g, b] = super::annotate::MEASURE_RGB;
        let line = egui::Stroke::new(2.0, egui::Color32::from_rgb(r, g, b));
        for (k, pair) in inspect.measured.windows(2).enumerate() {
            if let (Some(a), Some(b)) = (measured[k], measured[k + 1]) {
                painter.line_segment([a, b], line);
                let label = segment_label(pair[0].1, pair[1].1);
                painter.text(a + (b - a) * 0.5, egui::Align2::CENTER_BOTTOM, label, font.clone(), egui::Color32::WHITE);
            }
        }
        for p in measured.iter().flatten() {
            painter.circle_filled(*p, 4.0, line.color);
        }
        let corners: Vec<egui::Pos2> = inspect.polygon.iter().filter_map(|p| projector.to_screen(*p)).collect();
        let edge = egui::Stroke::new(2.0, egui::Color32::from_rgb(120, 255, 140));
        if corners.len() >= 2 {
            let mut closed = corners.clone();
            closed.push(corners[0]);
            painter.add(egui::Shape::line(closed, edge));
        }
        for p in &corners {
            painter.circle_filled(*p, 4.0, edge.color);
        }
        draw_profile(painter, &projector, inspect);
    }
}

/// The profile's line, and its slab's outline at the line's height.
fn draw_profile(painter: &egui::Painter, projector: &Projector, inspect: &super::state::Inspection) {
    let colour = egui::Color32::from_rgb(255, 170, 60);
    let ends: Vec<egui::Pos2> = inspect.profile_line.iter().filter_map(|p| projector.to_screen(*p)).collect();
    for p in &ends {
        painter.circle_filled(*p, 4.0, colour);
    }
    let [a, b] = inspect.profile_line[..] else { return };
    if let [p, q] = ends[..] {
        painter.line_segment([p, q], egui::Stroke::new(2.0, colour));
    }
    let Ok(profile) = crate::inspect::profile::Profile::new(a.truncate(), b.truncate(), inspect.profile_width) else {
        return;
    };
    let (_, left) = profile.axes();
    let half = left * profile.width * 0.5;
    let z = (a.z + b.z) * 0.5;
    let outline: Vec<egui::Pos2> =
        [profile.start + half, profile.end + half, profile.end - half, profile.start - half, profile.start + half]
            .iter()
            .filter_map(|c| projector.to_screen(c.extend(z)))
            .collect();
    painter.add(egui::Shape::line(outline, egui::Stroke::new(1.0, colour)));
    for handle in width_handles(inspect).into_iter().flatten() {
        if let Some(p) = projector.to_screen(handle) {
            let active = inspect.dragging == Some(WIDTH_HANDLE);
            let fill = if active { egui::Color32::WHITE } else { colour };
            painter.circle(p, 6.0, fill, egui::Stroke::new(1.0, egui::Color32::BLACK));
        }
    }
}
