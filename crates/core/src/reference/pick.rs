//! Picking: every surface layer one pixel's ray passes, as the exact
//! reference composites them.
//!
//! The ray through the pixel's centre is cast on every splat the reference
//! would draw (the same culling, footprint, kernel and clip), the hits are
//! sorted by depth and grouped into ε-layers by the reference's own rule
//! (`take_layer`: split by facing when opacity is read), and each layer is
//! normalised as the reference shades it (Eq. 1: Σw·x / Σw of colour,
//! normal, opacity, depth and radius). Layers are listed nearest first up to
//! and including the first opaque one, where the reference's ray ends, so an
//! opaque scene lists one layer and a transparent scene every layer it
//! blends. A layer's point is the ray's point at the layer's mean depth,
//! given in f64 file coordinates. Triangles of mesh and hybrid objects are
//! not picked: their hits name no splat.

use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;

use super::raster::{Hit, ReferenceOptions, eye_splat, intersect, pixel_ray, take_layer};
use crate::frame::Camera;
use crate::scene::Scene;

/// One ε-layer along a picked ray.
#[derive(Debug, Clone, PartialEq)]
pub struct PickedLayer {
    /// View depth of the layer (its hits' weighted mean), in frame units.
    pub depth: f32,
    /// Where the ray meets the layer, in file coordinates.
    pub position: DVec3,
    /// The splats of the layer (indices in the scene's flattened cloud: a
    /// single file's loaded splats), heaviest first.
    pub splats: Vec<u32>,
    /// The layer's normal (Σw·n, normalised) in the file's axes.
    pub normal: Vec3,
    /// The layer's weighted mean splat radius, in file units.
    pub radius: f64,
    /// The layer's colour (Σw·c / Σw), sRGB 0..255.
    pub colour: [u8; 3],
    /// Σw·α / Σw (1 in an opaque frame).
    pub opacity: f32,
}

/// The options a pick casts with: a reference frame's of `settings` (its
/// ε, kernel, culling, radius scale and clip), reading the scene's opacity
/// whatever the mode, so a transparent scene lists every layer.
pub fn options(settings: &crate::frame::RenderSettings, scene: &Scene) -> ReferenceOptions {
    let reference = crate::frame::RenderSettings { mode: crate::frame::RenderMode::RULER, ..*settings };
    ReferenceOptions { transparent: scene.has_transparency(), ..ReferenceOptions::matching(&reference, scene) }
}

/// The layers the ray through pixel (`x`, `y`) of a `width`×`height` image
/// meets, nearest first (see the module doc); empty where it meets none.
pub fn pick(
    scene: &Scene,
    camera: &Camera,
    options: &ReferenceOptions,
    size: (u32, u32),
    pixel: (u32, u32),
) -> Vec<PickedLayer> {
    pick_in(scene, &scene.flatten(), camera, options, size, pixel)
}

/// [`pick`] in `flat`, the scene's [`Scene::flatten`] (made once by a caller that reads it too).
pub fn pick_in(
    scene: &Scene,
    flat: &crate::scene::FlatScene<'_>,
    camera: &Camera,
    options: &ReferenceOptions,
    (width, height): (u32, u32),
    (x, y): (u32, u32),
) -> Vec<PickedLayer> {
    let cloud = flat.cloud.as_ref();
    let (width, height) = (width.max(1), height.max(1));
    let aspect = width as f32 / height as f32;
    let view = camera.view_matrix();
    let (near, far) = camera.near_far();
    let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let ray = pixel_ray(Vec2::new(tan_y * aspect, tan_y), (width, height), (x, y));
    let clip = options.clip.in_eye(&view);
    let floor = options.pixel_radius_floor(camera.fov_y_deg, height);
    let surfaces = scene.surfaces(flat);
    let drawn = surfaces.loose_splats();
    let mut hits: Vec<(Hit, super::tiles::EyeSplat)> = (0..cloud.len())
        .into_par_iter()
        .filter(|&i| drawn[i])
        .filter_map(|i| {
            let s = eye_splat(cloud, i, &view, (near, far), floor, options)?;
            let hit = intersect(&s, ray, &options.kernel, near, far).filter(|h| clip.keeps_along(ray, h.depth))?;
            Some((Hit { splat: i as u32, ..hit }, s))
        })
        .collect();
    hits.sort_unstable_by(|a, b| a.0.depth.total_cmp(&b.0.depth).then(a.0.splat.cmp(&b.0.splat)));
    // Each hit names its place in `hits` (for its record), `ids` its splat.
    let ids: Vec<u32> = hits.iter().map(|(h, _)| h.splat).collect();
    let sorted: Vec<Hit> = hits.iter().enumerate().map(|(k, (h, _))| Hit { splat: k as u32, ..*h }).collect();
    let (origin, unit) = scene.frame_placement();
    let eye_to_world = view.inverse();
    let mut used = vec![false; sorted.len()];
    let mut layers = Vec::new();
    let mut start = 0;
    while start < sorted.len() {
        let mut members: Vec<(f32, usize)> = Vec::new();
        start = take_layer(&sorted, &mut used, start, options.epsilon, options.transparent, |h| {
            members.push((h.weight, h.splat as usize))
        });
        let sum_w: f32 = members.iter().map(|m| m.0).sum();
        if sum_w <= 0.0 || sum_w.is_nan() {
            continue;
        }
        let mean = |f: &dyn Fn(usize) -> f32| members.iter().map(|&(w, k)| w * f(k)).sum::<f32>() / sum_w;
        let depth = mean(&|k| sorted[k].depth);
        let opacity = mean(&|k| hits[k].1.opacity);
        let colour = [0, 1, 2].map(|c| (mean(&|k| hits[k].1.colour[c]) * 255.0).round().clamp(0.0, 255.0) as u8);
        let normal_eye: Vec3 = members.iter().map(|&(w, k)| hits[k].1.normal * w).sum();
        let normal = eye_to_world.transform_vector3(normal_eye).normalize_or_zero();
        let frame_point = eye_to_world.transform_point3(ray * depth);
        let radius = mean(&|k| hits[k].1.radius) as f64 * unit;
        members.sort_by(|a, b| b.0.total_cmp(&a.0).then(ids[a.1].cmp(&ids[b.1])));
        layers.push(PickedLayer {
            depth,
            position: frame_point.as_dvec3() * unit + origin,
            splats: members.iter().map(|m| ids[m.1]).collect(),
            normal,
            radius,
            colour,
            opacity,
        });
        if opacity >= 1.0 {
            break; // an opaque layer ends the ray, as in the reference
        }
    }
    layers
}
