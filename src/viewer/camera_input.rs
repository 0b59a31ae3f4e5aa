//! Mouse and keyboard to camera: orbit (left drag), pan (right or middle
//! drag), zoom (wheel) towards the point under the cursor, re-centre on the
//! surface point under a double-click.
//!
//! Zooming by a factor f about a point Q scales the eye's offset from Q:
//! eye' = Q + f·(eye − Q). The orbit camera keeps its direction, so its
//! target moves the same way, target' = Q + f·(target − Q), and its
//! distance becomes f·distance. Q stays where it was on screen, in
//! perspective and in orthographic (whose window scales by f about Q's
//! place). Q is the surface under the cursor where one is found, else the
//! cursor's point on the plane through the target facing the camera.
//!
//! The orbit camera's near/far planes enclose a sphere around its target, so
//! when the target moves the sphere grows to keep the whole scene inside.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::cloud::PointCloud;
use crate::frame::Camera;

/// Degrees of orbit per point of drag.
const ORBIT_DEG_PER_POINT: f32 = 0.4;
/// Zoom factor per point of wheel scroll.
const ZOOM_PER_POINT: f32 = 0.002;

/// The scene a camera must keep inside its depth range.
#[derive(Debug, Clone, Copy)]
pub struct SceneSphere {
    pub centre: Vec3,
    pub radius: f32,
}

impl SceneSphere {
    /// Moves the camera's target, keeping the scene within its depth range.
    pub fn retarget(&self, camera: &mut Camera, target: Vec3) {
        camera.target = target;
        camera.scene_radius = self.radius + (target - self.centre).length();
    }
}

pub fn orbit(camera: &mut Camera, drag: Vec2) {
    camera.azimuth_deg = (camera.azimuth_deg - drag.x * ORBIT_DEG_PER_POINT).rem_euclid(360.0);
    camera.elevation_deg = (camera.elevation_deg + drag.y * ORBIT_DEG_PER_POINT).clamp(-89.5, 89.5);
}

/// Moves the target with the drag, so the point under the cursor follows it
/// (at the target's depth); `view_height` is the view's height in points.
pub fn pan(camera: &mut Camera, scene: &SceneSphere, drag: Vec2, view_height: f32) {
    let view = camera.view_matrix();
    let right = view.row(0).truncate();
    let up = view.row(1).truncate();
    let units_per_point = 2.0 * camera.distance * (camera.fov_y_deg.to_radians() * 0.5).tan() / view_height.max(1.0);
    let target = camera.target - right * drag.x * units_per_point + up * drag.y * units_per_point;
    scene.retarget(camera, target);
}

pub fn zoom(camera: &mut Camera, scroll: f32) {
    let factor = (-scroll * ZOOM_PER_POINT).exp();
    camera.distance = (camera.distance * factor).clamp(camera.scene_radius * 1e-4, camera.scene_radius * 100.0);
}

/// Fly mode's mouse look: turns the view by the drag about the eye, which
/// stays where it is (the target swings round it at the same distance).
pub fn look(camera: &mut Camera, scene: &SceneSphere, drag: Vec2) {
    let eye = camera.target + camera.direction() * camera.distance;
    camera.azimuth_deg = (camera.azimuth_deg + drag.x * ORBIT_DEG_PER_POINT).rem_euclid(360.0);
    camera.elevation_deg = (camera.elevation_deg - drag.y * ORBIT_DEG_PER_POINT).clamp(-89.5, 89.5);
    scene.retarget(camera, eye - camera.direction() * camera.distance);
}

/// Fly mode's step: moves the eye and the target together by `step` =
/// (right, up, forward) in the scene's units, forward being where the view looks.
pub fn fly(camera: &mut Camera, scene: &SceneSphere, step: Vec3) {
    let view = camera.view_matrix();
    let (right, up) = (view.row(0).truncate(), view.row(1).truncate());
    let forward = -camera.direction();
    scene.retarget(camera, camera.target + right * step.x + up * step.y + forward * step.z);
}

/// Fly mode's speed, in scene units per second: half the depth of the
/// surface under the cursor, else half the distance to the target, so a
/// flight slows as it nears what it looks at.
pub fn fly_speed(camera: &Camera, depth_under_cursor: Option<f32>) -> f32 {
    0.5 * depth_under_cursor.filter(|d| *d > 0.0).unwrap_or(camera.distance)
}

/// Zooms by `scroll` about `about` (world), which keeps its place on screen.
pub fn zoom_about(camera: &mut Camera, scene: &SceneSphere, scroll: f32, about: Vec3) {
    let before = camera.distance;
    zoom(camera, scroll);
    let factor = camera.distance / before;
    scene.retarget(camera, about + (camera.target - about) * factor);
}

/// The point at normalised image position `uv` (0..1, y down) on the plane
/// through the target facing the camera, in a view of `aspect`.
pub fn on_target_plane(camera: &Camera, uv: Vec2, aspect: f32) -> Vec3 {
    let ndc = Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    // At the target's depth both projections span distance · tan(fov/2) to either side.
    let half = Vec2::new(aspect, 1.0) * camera.distance * (camera.fov_y_deg.to_radians() * 0.5).tan();
    let view = camera.view_matrix();
    let (right, up) = (view.row(0).truncate(), view.row(1).truncate());
    camera.target + right * ndc.x * half.x + up * ndc.y * half.y
}

/// The nearest splat surface point under normalised image position `uv`
/// (0..1, y down) in a view of `aspect`, if any.
pub fn pick(cloud: &PointCloud, camera: &Camera, uv: Vec2, aspect: f32) -> Option<Vec3> {
    let ndc = Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    // From the eye, or in orthographic from the cursor's place on the eye's plane.
    let lens = crate::frame::eye_ray::Lens { half: camera.lens(aspect), ortho: camera.is_ortho() };
    let eye_ray = lens.ray_at(ndc);
    let to_world = camera.view_matrix().inverse();
    let origin = to_world.transform_point3(eye_ray.origin);
    let dir = to_world.transform_vector3(eye_ray.dir).normalize();
    (0..cloud.len())
        .into_par_iter()
        .filter_map(|i| {
            let (p, n, r) = (cloud.positions[i], cloud.normals[i], cloud.radii[i]);
            let facing = dir.dot(n);
            if facing.abs() < 1e-6 {
                return None;
            }
            let t = (p - origin).dot(n) / facing;
            (t > 0.0 && (origin + dir * t - p).length_squared() <= r * r).then_some(t)
        })
        .min_by(f32::total_cmp)
        .map(|t| origin + dir * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_double_click_in_the_middle_picks_the_front_disc() {
        let cloud = PointCloud {
            positions: vec![Vec3::new(0.0, 0.0, 0.5), Vec3::new(0.0, 0.0, -0.5)],
            normals: vec![Vec3::Z; 2],
            radii: vec![0.2; 2],
            colours: vec![[0; 3]; 2],
            opacity: vec![1.0; 2],
            ..Default::default()
        };
        let camera = Camera::framing(Vec3::ZERO, 1.0, 1.0);
        let hit = pick(&cloud, &camera, Vec2::splat(0.5), 1.0).unwrap();
        assert!((hit - Vec3::new(0.0, 0.0, 0.5)).length() < 1e-4, "{hit}");
        assert!(pick(&cloud, &camera, Vec2::new(0.02, 0.02), 1.0).is_none());
    }

    /// Where a world point falls on screen, in normalised device coordinates.
    fn on_screen(camera: &Camera, p: Vec3, aspect: f32) -> Vec2 {
        let clip = camera.projection(aspect) * camera.view_matrix() * p.extend(1.0);
        Vec2::new(clip.x, clip.y) / clip.w
    }

    #[test]
    fn zooming_keeps_the_point_under_the_cursor_in_both_projections() {
        let scene = SceneSphere { centre: Vec3::ZERO, radius: 1.0 };
        for projection in [crate::frame::Projection::Perspective, crate::frame::Projection::Ortho] {
            let mut camera = Camera::framing(Vec3::ZERO, 1.0, 1.5);
            camera.projection = projection;
            camera.azimuth_deg = 30.0;
            let uv = Vec2::new(0.8, 0.3);
            let on_plane = on_target_plane(&camera, uv, 1.5);
            let ndc = Vec2::new(0.6, 0.4);
            assert!((on_screen(&camera, on_plane, 1.5) - ndc).length() < 1e-4, "{projection}");
            // A surface point off the target's plane, under some other pixel.
            let surface = on_plane + camera.direction() * 0.3;
            let seen = on_screen(&camera, surface, 1.5);
            for (about, at) in [(on_plane, ndc), (surface, seen)] {
                let mut zoomed = camera;
                zoom_about(&mut zoomed, &scene, 300.0, about);
                assert!(zoomed.distance < camera.distance * 0.6, "it zoomed in");
                let after = on_screen(&zoomed, about, 1.5);
                assert!((after - at).length() < 1e-4, "{projection}: {at} moved to {after}");
            }
            let mut centred = camera;
            zoom(&mut centred, 300.0);
            assert!((on_screen(&centred, surface, 1.5) - seen).length() > 0.05, "a plain zoom moves it");
        }
    }

    #[test]
    fn mouse_look_keeps_the_eye_and_a_fly_step_moves_it_along_the_view() {
        let scene = SceneSphere { centre: Vec3::ZERO, radius: 1.0 };
        let camera = Camera::framing(Vec3::ZERO, 1.0, 1.0);
        let eye = camera.eye();
        let mut looked = camera;
        look(&mut looked, &scene, Vec2::new(50.0, -30.0));
        assert!((looked.eye() - eye).length() < 1e-4, "the eye stays: {} and {eye}", looked.eye());
        assert!((looked.azimuth_deg - camera.azimuth_deg).abs() > 10.0 && looked.target != camera.target);
        let mut flown = camera;
        fly(&mut flown, &scene, Vec3::new(0.0, 0.0, 0.5));
        let moved = flown.eye() - eye;
        assert!((moved - (-camera.direction() * 0.5)).length() < 1e-4, "forward is where the view looks: {moved}");
        assert_eq!(flown.distance, camera.distance);
        assert_eq!(fly_speed(&camera, Some(4.0)), 2.0, "half the depth under the cursor a second");
        assert_eq!(fly_speed(&camera, None), 0.5 * camera.distance);
    }

    #[test]
    fn panning_keeps_the_scene_inside_the_depth_range() {
        let scene = SceneSphere { centre: Vec3::ZERO, radius: 1.0 };
        let mut camera = Camera::framing(Vec3::ZERO, 1.0, 1.0);
        pan(&mut camera, &scene, Vec2::new(200.0, 0.0), 400.0);
        let moved = camera.target.length();
        assert!(moved > 0.1);
        assert!((camera.scene_radius - (1.0 + moved)).abs() < 1e-5);
    }
}
