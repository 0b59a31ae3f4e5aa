//! The nearest surface under each pixel of a drawn frame, as view depth:
//! what a frame's visibility pass already wrote (Botsch & Kobbelt's §3.3
//! depth pass of two-pass, read back by the renderer), so that the point
//! under the cursor is found without picking again.
//!
//! The depth target holds the view depth mapped linearly to 0..1 over the
//! camera's near..far ([`Camera::near_far`]), pushed back by ε where the
//! visibility pass pushes it (filtered two-pass); 1 where nothing was drawn.
//! [`FrontDepth::from_buffer`] undoes both, as the eye-dome pass does
//! (`eye_dome.wgsl`'s `front_depth`). [`FrontDepth::point_at`] then goes
//! along the f64 ray through an image position ([`Lens::ray_f64_at`]) to
//! that depth, in the frame's coordinates.

use glam::{DVec2, DVec3};

use super::Camera;
use super::eye_ray::Lens;

/// A frame's nearest surface per pixel, and the camera it was drawn from.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontDepth {
    pub size: (u32, u32),
    /// View depth per pixel, row by row from the top; `None` where nothing was drawn.
    pub depth: Vec<Option<f32>>,
    pub camera: Camera,
}

impl FrontDepth {
    /// From a depth target's values (0..1 over near..far, pushed back by
    /// `push` view units; 1 where nothing was drawn) of a frame of `size` from `camera`.
    pub fn from_buffer(camera: &Camera, size: (u32, u32), buffer: &[f32], push: f32) -> Self {
        let (near, far) = camera.near_far();
        let span = far - near;
        let depth = buffer.iter().map(|&d| (d < 1.0 && d.is_finite()).then_some(d * span + near - push)).collect();
        FrontDepth { size, depth, camera: *camera }
    }

    /// The view depth of the surface drawn at pixel (x, y), if any.
    pub fn depth_at(&self, x: u32, y: u32) -> Option<f32> {
        let (w, h) = self.size;
        if x >= w || y >= h {
            return None;
        }
        self.depth[(y * w + x) as usize]
    }

    /// The surface point at image position `at` (pixels from the upper left
    /// corner), in the frame's coordinates, f64: on the ray through `at`, at
    /// the depth of the pixel `at` falls in.
    pub fn point_at(&self, at: DVec2) -> Option<DVec3> {
        if at.x < 0.0 || at.y < 0.0 {
            return None;
        }
        let depth = f64::from(self.depth_at(at.x as u32, at.y as u32)?);
        let (origin, direction) = Lens::ray_f64_at(&self.camera, self.size, at);
        let eye_point = origin + direction * depth;
        Some(self.camera.view_matrix_f64().inverse().transform_point3(eye_point))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Projection;

    /// A frame whose every pixel saw the plane z = 0, looking down z, pushed back by `push`.
    fn looking_at_the_floor(projection: Projection, push: f32) -> (Camera, FrontDepth) {
        let mut camera = Camera::framing(glam::Vec3::ZERO, 2.0, 1.5);
        camera.up = crate::frame::UpAxis::PosZ;
        camera.look_from(crate::frame::NamedView::Top);
        camera.projection = projection;
        let size = (48, 32);
        let (near, far) = camera.near_far();
        let floor = camera.eye_distance();
        let mapped = (floor + push - near) / (far - near);
        let mut buffer = vec![mapped; 48 * 32];
        buffer[5] = 1.0; // nothing drawn at pixel (5, 0)
        (camera, FrontDepth::from_buffer(&camera, size, &buffer, push))
    }

    #[test]
    fn the_point_under_a_position_lies_on_the_surface_along_its_ray() {
        for projection in [Projection::Perspective, Projection::Ortho] {
            let (camera, front) = looking_at_the_floor(projection, 0.05);
            assert_eq!(front.depth_at(5, 0), None, "nothing drawn there");
            assert_eq!(front.point_at(DVec2::new(5.5, 0.5)), None);
            assert_eq!(front.depth_at(48, 0), None, "outside the image");
            // The image's centre sees the target; an off-centre position its own place on the floor.
            let centre = front.point_at(DVec2::new(24.0, 16.0)).unwrap();
            assert!((centre - camera.target.as_dvec3()).length() < 1e-4, "{projection}: {centre}");
            let at = DVec2::new(40.25, 7.75);
            let p = front.point_at(at).unwrap();
            assert!(p.z.abs() < 1e-4, "{projection}: on the floor, not ε behind it: {p}");
            let view_projection = camera.projection(1.5) * camera.view_matrix();
            let clip = view_projection * p.as_vec3().extend(1.0);
            let ndc = glam::Vec2::new(clip.x, clip.y) / clip.w;
            let back = DVec2::new(f64::from(ndc.x + 1.0) * 24.0, f64::from(1.0 - ndc.y) * 16.0);
            assert!((back - at).length() < 1e-3, "{projection}: {p} is seen at {back}, not {at}");
        }
    }
}
