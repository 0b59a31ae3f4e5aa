//! The environment effects in the reference (Zhang & Pajarola §5.2.3-5.2.4):
//! after compositing, each pixel whose nearest layer is transparent looks
//! the map up along its reflected and refracted rays and is recomposed by
//! the shared model (`frame::environment_effects`), with the exact layer count of its
//! A-buffer and the nearest layer's exact normalised normal; pixels where
//! nothing is drawn show the map itself when it is a skybox.
//!
//! Lookups are pre-filtered as a GPU sampler's: the mip level comes from how
//! fast the looked-up direction turns between neighbouring pixels, taken
//! within 2x2 pixel quads as a fragment shader's fine derivatives are (the
//! other pixel of the quad's row, and of its column), so edges of a shape
//! blur as much as on the GPU and the ±180° meridian adds no seam.

use glam::Vec3;

use crate::frame::Camera;
use crate::frame::environment_effects::{EnvironmentSettings, GlassPixel, glass_colour, glass_directions};
use crate::scene::environment_map::EnvironmentMap;

/// What a frame needs to look the map up.
pub struct Lookup<'a> {
    pub map: &'a EnvironmentMap,
    pub camera: &'a Camera,
    pub settings: &'a EnvironmentSettings,
    pub width: u32,
    pub height: u32,
}

impl Lookup<'_> {
    /// Recomposes `colours` (row-major) given each pixel's eye-space view
    /// ray (unit), its glass layer and its layer count.
    pub fn apply(&self, rays: &[Vec3], glass: &[Option<GlassPixel>], layers: &[u32], colours: &mut [Vec3]) {
        let to_world = self.camera.view_matrix().inverse();
        let world = |v: Vec3| to_world.transform_vector3(v).normalize_or_zero();
        let frame = self.camera.up.frame();
        let n = rays.len();
        // The directions of each kind per pixel: sky, reflection, refraction r, g, b.
        let mut directions = vec![[None::<Vec3>; 5]; n];
        let mut totals = vec![[false; 3]; n];
        for i in 0..n {
            directions[i][0] = Some(world(rays[i]));
            if let Some(g) = &glass[i] {
                let (dirs, total) = glass_directions(rays[i], g, self.settings);
                for (k, d) in dirs.iter().enumerate() {
                    directions[i][k + 1] = Some(world(*d));
                }
                totals[i] = total;
            }
        }
        let texel_angle = std::f32::consts::TAU / self.map.width() as f32;
        let lod = |i: usize, k: usize| -> f32 {
            let Some(here) = directions[i][k] else { return 0.0 };
            let (x, y) = (i as u32 % self.width, i as u32 / self.width);
            let partner = |px: u32, py: u32| {
                (px < self.width && py < self.height)
                    .then(|| directions[(py * self.width + px) as usize][k])
                    .flatten()
                    .map(|d| (d - here).length())
            };
            let spread = partner(x ^ 1, y).into_iter().chain(partner(x, y ^ 1)).fold(0.0f32, f32::max);
            (spread / texel_angle).max(1.0).log2()
        };
        for i in 0..n {
            match &glass[i] {
                Some(g) => {
                    let mut seen = [Vec3::ZERO; 4];
                    for (k, s) in seen.iter_mut().enumerate() {
                        if let Some(d) = directions[i][k + 1] {
                            *s = Vec3::from_array(self.map.sample(d, frame, lod(i, k + 1)));
                        }
                    }
                    colours[i] = glass_colour(rays[i], g, self.settings, seen, totals[i]);
                }
                None if layers[i] == 0 && self.settings.skybox => {
                    if let Some(d) = directions[i][0] {
                        colours[i] = Vec3::from_array(self.map.sample(d, frame, lod(i, 0)));
                    }
                }
                None => {}
            }
        }
    }
}
