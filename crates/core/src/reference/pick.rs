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
//! blends. A layer's point is where the ray meets its splats' planes (the
//! weighted mean of each splat's ray-plane point), computed in f64 from the
//! splats' exact positions ([`crate::cloud::PointCloud::frame_position`]), so
//! it stays within a fraction of a millimetre at any distance from the
//! file's origin; the layer also names the file position of its heaviest
//! splat, exact to the file's own precision. Triangles of mesh and hybrid
//! objects are not picked: their hits name no splat.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::raster::{Hit, ReferenceOptions, eye_splat, intersect, take_layer};
use crate::frame::Camera;
use crate::frame::eye_ray::Lens;
use crate::scene::Scene;

/// One ε-layer along a picked ray.
#[derive(Debug, Clone, PartialEq)]
pub struct PickedLayer {
    /// View depth of the layer (its hits' weighted mean), in frame units.
    pub depth: f32,
    /// Where the ray meets the layer, in file coordinates (f64).
    pub position: DVec3,
    /// The heaviest splat's own position in the file, in file coordinates
    /// (exact to the file's precision).
    pub stored: DVec3,
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
    let view = camera.view_matrix();
    let (near, far) = camera.near_far();
    let lens = Lens::of(camera, (width, height));
    let ray = lens.ray((width, height), (x, y));
    let clip = options.clip.in_eye(&view);
    let floor = options.pixel_radius_floor(camera.half_extent_y(), height);
    let surfaces = scene.surfaces(flat);
    let drawn = surfaces.loose_splats();
    let mut hits: Vec<(Hit, super::tiles::EyeSplat)> = (0..cloud.len())
        .into_par_iter()
        .filter(|&i| drawn[i])
        .filter_map(|i| {
            let s = eye_splat(cloud, i, &view, (near, far), floor, lens, options)?;
            let hit = intersect(&s, &ray, &options.kernel, near, far).filter(|h| clip.keeps_along(&ray, h.depth))?;
            Some((Hit { splat: i as u32, ..hit }, s))
        })
        .collect();
    hits.sort_unstable_by(|a, b| a.0.depth.total_cmp(&b.0.depth).then(a.0.splat.cmp(&b.0.splat)));
    // Each hit names its place in `hits` (for its record), `ids` its splat.
    let ids: Vec<u32> = hits.iter().map(|(h, _)| h.splat).collect();
    let sorted: Vec<Hit> = hits.iter().enumerate().map(|(k, (h, _))| Hit { splat: k as u32, ..*h }).collect();
    let (origin, unit) = scene.frame_placement();
    let eye_to_world = view.inverse();
    // The ray in the scene frame, in f64 from the camera's values (an f32
    // direction is 10 mm off at 150 km): eye + direction · depth (the eye
    // being the pixel's place on the eye's plane in orthographic).
    let to_frame = camera.view_matrix_f64().inverse();
    let (origin_eye, eye_ray) = crate::frame::eye_ray::Lens::ray_f64(camera, (width, height), (x, y));
    let (eye, direction) = (to_frame.transform_point3(origin_eye), to_frame.transform_vector3(eye_ray));
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
        // Each splat's ray-plane point from its exact centre, in f64.
        let on_plane = |k: usize| {
            let (centre, normal) = (cloud.frame_position(ids[k] as usize), cloud.normals[ids[k] as usize].as_dvec3());
            let facing = direction.dot(normal);
            let t = if facing.abs() > 1e-12 { (centre - eye).dot(normal) / facing } else { sorted[k].depth as f64 };
            eye + direction * t
        };
        let weight: f64 = members.iter().map(|&(w, _)| w as f64).sum();
        let frame_point = members.iter().map(|&(w, k)| on_plane(k) * w as f64).sum::<DVec3>() / weight;
        let radius = mean(&|k| hits[k].1.radius) as f64 * unit;
        members.sort_by(|a, b| b.0.total_cmp(&a.0).then(ids[a.1].cmp(&ids[b.1])));
        let heaviest = ids[members[0].1] as usize;
        layers.push(PickedLayer {
            depth,
            position: frame_point * unit + origin,
            stored: cloud.frame_position(heaviest) * unit + origin,
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
