//! A selection's box on screen as a clip in file coordinates
//! ([`crate::frame::ClipRegion`], which every mode and the reference apply
//! per pixel): the four planes through the box's edges and the camera's
//! rays (their inside kept), or, in an orthographic view along an axis, the
//! box of the file the screen box spans, through the whole model along the
//! view axis.

use glam::{DVec2, DVec3};

use super::state::ScreenSelection;
use crate::frame::clip::{ClipBox, Hidden};
use crate::frame::eye_ray::Lens;

/// The ray (origin, direction) through a point of the view (points), in file coordinates.
fn ray(selection: &ScreenSelection, at: egui::Pos2, origin: DVec3, unit: f64) -> (DVec3, DVec3) {
    let view = selection.view;
    let size = (view.width().max(1.0) as u32, view.height().max(1.0) as u32);
    let place = DVec2::new(f64::from(at.x - view.left()), f64::from(at.y - view.top()));
    let (eye_origin, eye_direction) = Lens::ray_f64_at(&selection.camera, size, place);
    let to_frame = selection.camera.view_matrix_f64().inverse();
    (to_frame.transform_point3(eye_origin) * unit + origin, to_frame.transform_vector3(eye_direction) * unit)
}

/// The four planes `[nx, ny, nz, d]` (n·x + d ≥ 0 kept) whose inside is what the box shows.
pub fn frustum_planes(selection: &ScreenSelection, origin: DVec3, unit: f64) -> Vec<[f64; 4]> {
    let r = selection.rect;
    let corners = [r.left_top(), r.right_top(), r.right_bottom(), r.left_bottom()];
    let rays: Vec<(DVec3, DVec3)> = corners.iter().map(|c| ray(selection, *c, origin, unit)).collect();
    let (centre_origin, centre_direction) = ray(selection, r.center(), origin, unit);
    let inside = centre_origin + centre_direction;
    (0..4)
        .map(|k| {
            let ((o1, d1), (o2, d2)) = (rays[k], rays[(k + 1) % 4]);
            // Through both rays: in perspective they share their origin, in orthographic their direction.
            let across = if (o2 - o1).length() > 1e-12 * (1.0 + o1.length()) { o2 - o1 } else { d2 - d1 };
            let mut n = d1.cross(across).normalize();
            if n.dot(inside - o1) < 0.0 {
                n = -n;
            }
            [n.x, n.y, n.z, -n.dot(o1)]
        })
        .collect()
}

/// The file box a screen box spans in an orthographic view along an axis,
/// through `bounds` along it, its inside hidden; none in other views.
pub fn axis_box(selection: &ScreenSelection, origin: DVec3, unit: f64, bounds: (DVec3, DVec3)) -> Option<ClipBox> {
    if !selection.camera.is_ortho() {
        return None;
    }
    let (o1, direction) = ray(selection, selection.rect.left_top(), origin, unit);
    let (o2, _) = ray(selection, selection.rect.right_bottom(), origin, unit);
    let axis = (0..3).find(|&k| direction.normalize()[k].abs() > 1.0 - 1e-9)?;
    let (mut min, mut max) = (o1.min(o2), o1.max(o2));
    min[axis] = bounds.0[axis].min(bounds.1[axis]) - 1.0;
    max[axis] = bounds.0[axis].max(bounds.1[axis]) + 1.0;
    Some(ClipBox { min: min.to_array(), max: max.to_array(), hide: Hidden::Inside })
}
