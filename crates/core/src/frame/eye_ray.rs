//! A pixel's view ray in eye space, as every renderer casts it (the GPU's
//! `pixel_ray` and `pixel_origin` in frame.wgsl are the same): from the eye
//! through the pixel in perspective, and in orthographic from the pixel's
//! place on the eye's plane along -z ([`super::projection`]).
//! Its direction has z = -1, so a point at view depth t is origin + dir·t.

use glam::{DVec2, DVec3, Vec2, Vec3};

use super::Camera;

/// A ray: origin + dir · t, t the view depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeRay {
    pub origin: Vec3,
    pub dir: Vec3,
}

/// What casts a frame's rays: the window's half extent and the projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lens {
    /// tan of the half fields of view (x, y), or in orthographic the window's half extent.
    pub half: Vec2,
    pub ortho: bool,
}

impl Lens {
    /// The lens of `camera` for an image of `width`×`height`.
    pub fn of(camera: &Camera, (width, height): (u32, u32)) -> Self {
        Lens { half: camera.lens(width.max(1) as f32 / height.max(1) as f32), ortho: camera.is_ortho() }
    }

    /// The ray through the centre of pixel (`x`, `y`) of a `width`×`height` image.
    pub fn ray(&self, (width, height): (u32, u32), (x, y): (u32, u32)) -> EyeRay {
        let ndc = Vec2::new((x as f32 + 0.5) / width as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / height as f32 * 2.0);
        self.ray_at(ndc)
    }

    /// The ray through the point `ndc` of the window (-1..1, y up).
    pub fn ray_at(&self, ndc: Vec2) -> EyeRay {
        let place = ndc * self.half;
        if self.ortho {
            EyeRay { origin: place.extend(0.0), dir: Vec3::NEG_Z }
        } else {
            EyeRay { origin: Vec3::ZERO, dir: place.extend(-1.0) }
        }
    }

    /// [`Self::ray`] in f64, from the camera's own values, in eye space
    /// (origin, direction): what a pick far from the origin casts (an f32
    /// direction is 10 mm off at 150 km).
    pub fn ray_f64(camera: &Camera, size: (u32, u32), (x, y): (u32, u32)) -> (DVec3, DVec3) {
        Self::ray_f64_at(camera, size, DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5))
    }

    /// [`Self::ray_f64`] through the image position `at`, in pixels from
    /// the image's upper left corner (a pixel's centre is at its index + 0.5).
    pub fn ray_f64_at(camera: &Camera, (width, height): (u32, u32), at: DVec2) -> (DVec3, DVec3) {
        let tan_y = (f64::from(camera.fov_y_deg).to_radians() * 0.5).tan();
        let half_y = if camera.is_ortho() { tan_y * f64::from(camera.distance) } else { tan_y };
        let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
        let ndc = DVec2::new(at.x / w * 2.0 - 1.0, 1.0 - at.y / h * 2.0);
        let place = ndc * DVec2::new(half_y * w / h, half_y);
        if camera.is_ortho() { (place.extend(0.0), DVec3::NEG_Z) } else { (DVec3::ZERO, place.extend(-1.0)) }
    }

    /// From the eye towards the eye-space point `p`, not of unit length:
    /// what back faces and footprints are judged by (frame.wgsl's `towards`).
    pub fn towards(&self, p: Vec3) -> Vec3 {
        if self.ortho { Vec3::NEG_Z } else { p }
    }
}

impl EyeRay {
    /// The point at view depth `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_f64_ray_is_the_f32_ray_in_both_projections() {
        for projection in [crate::frame::Projection::Perspective, crate::frame::Projection::Ortho] {
            let camera = Camera { projection, distance: 7.0, fov_y_deg: 40.0, ..Camera::framing(Vec3::ZERO, 1.0, 1.6) };
            let size = (320, 200);
            for pixel in [(0, 0), (319, 199), (100, 37)] {
                let ray = Lens::of(&camera, size).ray(size, pixel);
                let (origin, dir) = Lens::ray_f64(&camera, size, pixel);
                assert!((origin.as_vec3() - ray.origin).length() < 1e-5, "{projection:?} {pixel:?}");
                assert!((dir.as_vec3() - ray.dir).length() < 1e-5, "{projection:?} {pixel:?}");
            }
        }
    }
}
