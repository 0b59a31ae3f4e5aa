//! The shading model: Phong with a light fixed to the camera (the
//! headlight), or, in a frame with scene lights, Phong summed over those
//! lights, each scaled by the transmittance its light keeps on the way to the
//! surface (its shadow coefficient, `crate::shadow`).
//!
//! Colours are used as stored (sRGB values taken as they are, as is common
//! for scan data), so a splat's colour with the normal facing the light and
//! no highlight comes out as `ambient + diffuse` times its colour.

use glam::Vec3;

/// Phong lighting in eye space, and the background colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shading {
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
    /// Direction towards the light, in eye space (camera looks down -z).
    pub light_dir_eye: Vec3,
    /// Background colour, 0..1.
    pub background: Vec3,
}

impl Default for Shading {
    fn default() -> Self {
        Self {
            ambient: 0.25,
            diffuse: 0.75,
            specular: 0.2,
            shininess: 32.0,
            light_dir_eye: Vec3::new(0.3, 0.4, 1.0).normalize(),
            background: Vec3::new(0.11, 0.12, 0.14),
        }
    }
}

impl Shading {
    /// Shades `albedo` (0..1) with eye-space unit `normal`; `to_eye` points from
    /// the surface to the camera. Normals facing away are flipped (two-sided).
    pub fn shade(&self, albedo: Vec3, normal: Vec3, to_eye: Vec3) -> Vec3 {
        let n = if normal.dot(to_eye) < 0.0 { -normal } else { normal };
        let l = self.light_dir_eye;
        let diffuse = n.dot(l).max(0.0);
        let reflected = 2.0 * n.dot(l) * n - l;
        let specular = if diffuse > 0.0 { reflected.dot(to_eye).max(0.0).powf(self.shininess) } else { 0.0 };
        (albedo * (self.ambient + self.diffuse * diffuse) + Vec3::splat(self.specular * specular))
            .clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// Shades `albedo` lit by scene lights instead of the headlight. Each of
    /// `incident` is (unit direction towards the light, light arriving,
    /// shadowed: colour × intensity × falloff × transmittance). Vectors are
    /// in any one frame (the GPU uses eye space, the reference world space).
    pub fn shade_lit(&self, albedo: Vec3, normal: Vec3, to_eye: Vec3, incident: &[(Vec3, Vec3)]) -> Vec3 {
        let n = if normal.dot(to_eye) < 0.0 { -normal } else { normal };
        let (mut diffuse, mut specular) = (Vec3::ZERO, Vec3::ZERO);
        for &(l, light) in incident {
            let cos = n.dot(l);
            if cos > 0.0 {
                diffuse += light * cos;
                let reflected = 2.0 * cos * n - l;
                specular += light * reflected.dot(to_eye).max(0.0).powf(self.shininess);
            }
        }
        (albedo * (Vec3::splat(self.ambient) + self.diffuse * diffuse) + self.specular * specular)
            .clamp(Vec3::ZERO, Vec3::ONE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_light_along_the_headlight_shades_as_the_headlight() {
        let s = Shading::default();
        let (albedo, n, eye) = (Vec3::new(0.8, 0.5, 0.2), Vec3::new(0.1, 0.3, 1.0).normalize(), Vec3::Z);
        let lit = s.shade_lit(albedo, n, eye, &[(s.light_dir_eye, Vec3::ONE)]);
        assert!((lit - s.shade(albedo, n, eye)).abs().max_element() < 1e-6);
        let dark = s.shade_lit(albedo, n, eye, &[(s.light_dir_eye, Vec3::ZERO)]);
        assert!((dark - albedo * s.ambient).abs().max_element() < 1e-6, "a light in full shadow leaves ambient");
    }
}
