//! Ray casting of splat discs per pixel, ε-layering and front-to-back compositing.
//!
//! Every hit of a pixel's ray counts, with no cap on the number of layers. A
//! layer is the hits within ε of its front hit; when opacity is read
//! (transparent modes, the reference mode) hits whose surfaces face the other
//! way from the front hit form layers of their own even within ε, so a thin
//! shell seen through keeps its two layers. Each layer is normalised (Eq. 1:
//! weighted colour, normal and opacity), shaded facing the viewer, and
//! composited front to back; an opaque layer ends the ray.

use glam::Vec3;
use rayon::prelude::*;

use crate::frame::eye_ray::{EyeRay, Lens};

use super::environment_pass::Lookup;
use super::tiles::{self, EyeSplat, TILE};
use super::triangles;
use crate::frame::environment_effects::{EnvironmentSettings, GlassPixel};
use crate::frame::{Camera, Lights, Shading, SplatKernel};
use crate::scene::Scene;
use crate::shadow::{ShadowInput, rays::ShadowRays};

/// Parameters of a reference frame; the same values a GPU frame uses.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceOptions {
    /// Hits within this view-depth distance of a layer's front join the layer.
    pub epsilon: f32,
    pub backface_culling: bool,
    pub kernel: SplatKernel,
    pub shading: Shading,
    /// Phong lighting; without it layers show their normalised colour.
    pub lighting: bool,
    /// Every splat radius is multiplied by this.
    pub radius_scale: f32,
    /// Far splats are drawn at least this many (output) pixels in radius
    /// (`RenderSettings::min_pixel_radius`).
    pub min_pixel_radius: f32,
    /// Read opacity (the scene as defined); else every splat is opaque, as opaque modes draw it.
    pub transparent: bool,
    /// Show a progress bar.
    pub progress: bool,
    /// How the scene's environment map, if any, is reflected and refracted
    /// (read only with opacity, on the nearest transparent layer).
    pub environment: EnvironmentSettings,
    /// Scene lights (world space). With lighting on and lights given, each
    /// layer is lit by them, each through an exact shadow ray from the
    /// layer's point to the light ([`crate::shadow::rays`]); else the headlight.
    pub lights: Lights,
    /// Rays per pixel side: N×N rays on a regular grid inside each pixel,
    /// averaged (a box filter) before the colour is quantised. 1 casts one
    /// ray through the pixel's centre. The exact answer to aliasing, which
    /// the splat passes' prefilter approximates.
    pub supersample: u32,
    /// What is cut away (flattened frame): a hit whose point is not kept is dropped.
    pub clip: crate::frame::Clip,
    /// Eye-dome lighting of each pixel's nearest hit ([`crate::frame::EyeDome`]).
    pub eye_dome: Option<crate::frame::EyeDome>,
}

impl ReferenceOptions {
    /// [`crate::frame::settings::pixel_radius_floor`] of these options.
    pub fn pixel_radius_floor(&self, half_y: f32, height: u32) -> f32 {
        crate::frame::settings::pixel_radius_floor(self.min_pixel_radius, half_y, height)
    }

    /// The options that match a GPU frame of `scene` rendered with `settings`.
    pub fn matching(settings: &crate::frame::RenderSettings, scene: &Scene) -> Self {
        Self {
            epsilon: settings.epsilon(scene.flatten().cloud.mean_radius()),
            backface_culling: settings.backface_culling,
            kernel: settings.kernel,
            shading: settings.shading,
            lighting: settings.lighting,
            radius_scale: settings.radius_scale,
            min_pixel_radius: settings.min_pixel_radius,
            // An opaque scene is measured as opaque modes draw it: facing is not split.
            transparent: settings.mode.info().transparent && scene.has_transparency(),
            progress: false,
            // Only what the mode draws: a mode without the effects is measured without them.
            environment: EnvironmentSettings { enabled: settings.draws_environment(), ..settings.environment },
            lights: settings.lights,
            supersample: settings.supersample.max(1),
            clip: settings.clip,
            eye_dome: settings.eye_dome_drawn(),
        }
    }
}

/// One ray-splat intersection.
#[derive(Debug, Clone, Copy)]
pub(super) struct Hit {
    pub depth: f32,
    pub weight: f32,
    pub splat: u32,
    /// Whether the surface faces the viewer (its normal points against the ray).
    pub facing: bool,
}

/// Renders `scene` exactly, on the CPU, as the GPU modes would with the same camera.
pub fn render(scene: &Scene, camera: &Camera, options: &ReferenceOptions, width: u32, height: u32) -> image::RgbaImage {
    render_with_layers(scene, camera, options, width, height).0
}

/// [`render`], and per pixel (row-major) the number of layers its ray met
/// (the most of its rays when supersampled).
pub fn render_with_layers(
    scene: &Scene,
    camera: &Camera,
    options: &ReferenceOptions,
    width: u32,
    height: u32,
) -> (image::RgbaImage, Vec<u32>) {
    let (width, height) = (width.max(1), height.max(1));
    let n = options.supersample.max(1);
    let pixels = width as usize * height as usize;
    let mut sums = vec![Vec3::ZERO; pixels];
    let mut layer_counts = vec![0u32; pixels];
    // The nearest hit of each pixel's rays, for eye-dome lighting.
    let mut front = if options.eye_dome.is_some() { vec![f32::INFINITY; pixels] } else { Vec::new() };
    // N×N rays per pixel are the pixels of an N× larger image of the same
    // view: ray (i, j) of pixel (x, y) passes through (x + (i + ½)/N, y + (j + ½)/N).
    // They are cast a band of rows at a time, so memory stays bounded.
    render_samples(scene, camera, options, (width * n, height * n), n, |rows, band| {
        let sample_width = (width * n) as usize;
        for (r, y) in rows.enumerate() {
            let out_row = (y / n) as usize * width as usize;
            for x in 0..sample_width {
                let at = out_row + x / n as usize;
                let sample = r * sample_width + x;
                sums[at] += band.colours[sample].clamp(Vec3::ZERO, Vec3::ONE);
                layer_counts[at] = layer_counts[at].max(band.layers[sample]);
                if let Some(nearest) = front.get_mut(at) {
                    *nearest = nearest.min(band.front[sample]);
                }
            }
        }
    });
    // Eye-dome lighting shades the pixel's colour by its nearest hit (of its N×N rays).
    if let Some(edl) = options.eye_dome {
        for (sum, factor) in sums.iter_mut().zip(edl.factors(&front, (width, height))) {
            *sum *= factor;
        }
    }
    let mut image = image::RgbaImage::new(width, height);
    for (i, sum) in sums.iter().enumerate() {
        image.put_pixel(
            (i % width as usize) as u32,
            (i / width as usize) as u32,
            image::Rgba(to_rgba8(*sum / (n * n) as f32)),
        );
    }
    (image, layer_counts)
}

/// The splats `drawn` in eye space, culled (facing away, or outside the
/// depth range whole) as the GPU passes cull them.
fn eye_splats(
    cloud: &crate::cloud::PointCloud,
    drawn: &[bool],
    view: &glam::Mat4,
    (near, far): (f32, f32),
    floor: f32,
    lens: Lens,
    options: &ReferenceOptions,
) -> Vec<EyeSplat> {
    (0..cloud.len())
        .into_par_iter()
        .filter(|&i| drawn[i])
        .filter_map(|i| eye_splat(cloud, i, view, (near, far), floor, lens, options))
        .collect()
}

/// Splat `i` in eye space, or `None` where the GPU passes cull it; `floor`:
/// the least radius per unit of view depth (`--min-pixel-radius`; at any
/// depth when `lens` is orthographic).
pub(super) fn eye_splat(
    cloud: &crate::cloud::PointCloud,
    i: usize,
    view: &glam::Mat4,
    (near, far): (f32, f32),
    floor: f32,
    lens: Lens,
    options: &ReferenceOptions,
) -> Option<EyeSplat> {
    let centre = view.transform_point3(cloud.positions[i]);
    let normal = view.transform_vector3(cloud.normals[i]).try_normalize().unwrap_or(Vec3::Z);
    let depth = -centre.z;
    let floor = if lens.ortho { floor } else { floor * depth.max(0.0) };
    let radius = (cloud.radii[i] * options.radius_scale).max(floor);
    let sight = lens.towards(centre);
    let culled = options.backface_culling && !cloud.is_two_sided(i) && normal.dot(sight) > 0.0;
    // Discs that cross the near or far plane keep the part between them (the per-hit test).
    let usable = depth - radius < far && depth + radius > near && radius > 0.0;
    if culled || !usable {
        return None;
    }
    let [r, g, b] = cloud.colours[i];
    Some(EyeSplat {
        centre,
        normal,
        plane: options.kernel.footprint_normal(normal, sight.normalize_or_zero()),
        radius,
        colour: Vec3::new(r as f32, g as f32, b as f32) / 255.0,
        opacity: if options.transparent { cloud.opacity[i].clamp(0.0, 1.0) } else { 1.0 },
    })
}

/// A band of rows of [`render_samples`], row-major.
struct Band {
    /// Linear colours.
    colours: Vec<Vec3>,
    /// The layers each ray met.
    layers: Vec<u32>,
    /// The view depth of each ray's nearest hit (infinite: none).
    front: Vec<f32>,
    /// What an environment lookup needs.
    glass: Vec<Option<GlassPixel>>,
}

/// The pixels of a band's tiles in the band's rows.
fn band_pixels(
    tiles: Vec<(u32, Vec<TilePixel>)>,
    rows: &std::ops::Range<u32>,
    (width, height): (u32, u32),
    columns: u32,
) -> Band {
    let band_pixels = rows.len() * width as usize;
    let mut band = Band {
        colours: vec![Vec3::ZERO; band_pixels],
        layers: vec![0u32; band_pixels],
        front: vec![f32::INFINITY; band_pixels],
        glass: vec![None; band_pixels],
    };
    for (tile, pixels) in tiles {
        let (tx, ty) = (tile % columns, tile / columns);
        let mut it = pixels.into_iter();
        for y in ty * TILE..((ty + 1) * TILE).min(height) {
            for x in tx * TILE..((tx + 1) * TILE).min(width) {
                if let Some(pixel) = it.next() {
                    let at = (y - rows.start) as usize * width as usize + x as usize;
                    (band.colours[at], band.layers[at], band.glass[at], band.front[at]) =
                        (pixel.colour, pixel.layers, pixel.glass, pixel.front);
                }
            }
        }
    }
    band
}

/// Most rays a band of [`render_samples`] holds at once.
const BAND_RAYS: usize = 1 << 22;

/// One ray through the centre of each pixel of a `width`×`height` image,
/// a band of rows at a time (whole tiles, and whole groups of `row_multiple`
/// rows): `emit` gets each band's rows and their pixels.
fn render_samples(
    scene: &Scene,
    camera: &Camera,
    options: &ReferenceOptions,
    (width, height): (u32, u32),
    row_multiple: u32,
    mut emit: impl FnMut(std::ops::Range<u32>, &Band),
) {
    let flat = scene.flatten();
    let cloud = flat.cloud.as_ref();
    let (width, height) = (width.max(1), height.max(1));
    let aspect = width as f32 / height as f32;
    let view = camera.view_matrix();
    let proj = camera.projection(aspect);
    let (near, far) = camera.near_far();
    // Objects with triangles are drawn as their triangles, and only their splats no triangle uses.
    let surfaces = scene.surfaces(&flat);
    let drawn = surfaces.loose_splats();
    // The floor is in output pixels: `row_multiple` rays per pixel side.
    let floor = options.pixel_radius_floor(camera.half_extent_y(), height / row_multiple.max(1));
    let lens = Lens::of(camera, (width, height));
    let splats = eye_splats(cloud, drawn, &view, (near, far), floor, lens, options);
    let mut bins = tiles::bin(&splats, &proj, width, height, near);
    let eye_triangles =
        triangles::eye_triangles(cloud, surfaces.triangles(), &view, options.backface_culling, options.transparent);
    triangles::bin(&eye_triangles, &proj, (width, height), near, &mut bins);
    let centre_weight = options.kernel.weight(0.0);
    let clip = options.clip.in_eye(&view);
    let environment = scene.environment.as_deref().filter(|_| options.transparent && options.environment.enabled);
    let glassy = environment.is_some();
    let lit = (options.lighting && !options.lights.is_empty()).then(|| LitLayers {
        rays: ShadowRays::new(&ShadowInput {
            cloud,
            radius_scale: options.radius_scale,
            transparent: options.transparent,
            epsilon: options.epsilon,
            kernel: options.kernel,
            clip: options.clip,
        }),
        view,
        eye_to_world: view.inverse(),
        lights: &options.lights,
    });
    let bar = crate::progress::bar(bins.bins.len() as u64, "reference render", options.progress);
    // Whole tile rows and whole output pixels per band.
    let unit = TILE * row_multiple / gcd(TILE, row_multiple);
    let band = unit * (BAND_RAYS / (width as usize * unit as usize)).max(1) as u32;
    let mut start = 0;
    while start < height {
        let rows = start..(start + band).min(height);
        start = rows.end;
        let tile_rows = rows.start / TILE..rows.end.div_ceil(TILE);
        let first_tile = tile_rows.start * bins.columns;
        let tiles: Vec<(u32, Vec<TilePixel>)> = (first_tile..tile_rows.end * bins.columns)
            .into_par_iter()
            .map(|tile| {
                if bar.is_cancelled() {
                    return (tile, Vec::new()); // the caller drops a cancelled image
                }
                let (tx, ty) = (tile % bins.columns, tile / bins.columns);
                let mut hits = Vec::new();
                let mut used = Vec::new();
                let mut triangle_hits = Vec::new();
                let mut pixels = Vec::with_capacity((TILE * TILE) as usize);
                for y in ty * TILE..((ty + 1) * TILE).min(height) {
                    for x in tx * TILE..((tx + 1) * TILE).min(width) {
                        let ray = lens.ray((width, height), (x, y));
                        hits.clear();
                        triangle_hits.clear();
                        for &s in &bins.bins[tile as usize] {
                            if s >= bins.first_triangle {
                                let t = &eye_triangles[(s - bins.first_triangle) as usize];
                                let hit = triangles::intersect(t, &ray, near, far);
                                if let Some((depth, record)) = hit.filter(|(d, _)| clip.keeps_along(&ray, *d)) {
                                    let splat = bins.first_triangle + triangle_hits.len() as u32;
                                    let facing = t.face.dot(ray.dir) < 0.0;
                                    hits.push(Hit { depth, weight: centre_weight, splat, facing });
                                    triangle_hits.push(record);
                                }
                            } else if let Some(hit) = intersect(&splats[s as usize], &ray, &options.kernel, near, far)
                                .filter(|h| clip.keeps_along(&ray, h.depth))
                            {
                                hits.push(Hit { splat: s, ..hit });
                            }
                        }
                        let records = Records { splats: &splats, triangle_hits: &triangle_hits };
                        let (colour, layers, glass) =
                            composite(&mut hits, &mut used, &records, &ray, options, glassy, lit.as_ref());
                        // `composite` sorted the hits by depth.
                        let front = hits.first().map_or(f32::INFINITY, |h| h.depth);
                        pixels.push(TilePixel { colour, layers, glass, front });
                    }
                }
                bar.inc(1);
                (tile, pixels)
            })
            .collect();
        let mut band = band_pixels(tiles, &rows, (width, height), bins.columns);
        if let Some(map) = environment {
            let band_height = rows.len() as u32;
            let rays = (0..width * band_height)
                .map(|i| {
                    let (x, y) = (i % width, rows.start + i / width);
                    lens.ray((width, height), (x, y)).dir.normalize()
                })
                .collect::<Vec<_>>();
            // The band starts on a tile row (even), so the lookup's 2×2 pixel quads stay whole.
            let lookup = Lookup { map, camera, settings: &options.environment, width, height: band_height };
            lookup.apply(&rays, &band.glass, &band.layers, &mut band.colours);
        }
        emit(rows, &band);
    }
    bar.finish();
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// What a pixel's hits name: splats, then the pixel's triangle hits (from
/// `splats.len()` on, as [`triangles::intersect`] made them).
struct Records<'a> {
    splats: &'a [EyeSplat],
    triangle_hits: &'a [EyeSplat],
}

impl Records<'_> {
    fn get(&self, i: u32) -> &EyeSplat {
        let i = i as usize;
        if i < self.splats.len() { &self.splats[i] } else { &self.triangle_hits[i - self.splats.len()] }
    }
}

/// One pixel of a tile: its colour, how many layers it composited, and its
/// nearest transparent layer for the environment effects.
/// One ray's result: its colour, the layers it met, what an environment
/// lookup needs, and the view depth of its nearest hit.
struct TilePixel {
    colour: Vec3,
    layers: u32,
    glass: Option<GlassPixel>,
    front: f32,
}

/// Exact ray-disc intersection: the pixel's ray (z = -1 per unit of depth)
/// meets the splat's footprint plane (see `SplatKernel::footprint_normal`) at
/// view depth t; inside the disc it gets the Gaussian weight.
pub(super) fn intersect(s: &EyeSplat, ray: &EyeRay, kernel: &SplatKernel, near: f32, far: f32) -> Option<Hit> {
    let denom = s.plane.dot(ray.dir);
    if denom.abs() < 1e-12 {
        return None;
    }
    // The centre seen from the ray's origin (the centre itself in perspective).
    let centre = s.centre - ray.origin;
    let t = s.plane.dot(centre) / denom;
    if !(t > near && t < far) {
        return None;
    }
    let rho2 = (ray.dir * t - centre).length_squared() / (s.radius * s.radius);
    (rho2 < 1.0).then(|| Hit { depth: t, weight: kernel.weight(rho2), splat: 0, facing: s.normal.dot(ray.dir) < 0.0 })
}

/// Sorts the hits, groups them into ε-layers (by facing too when opacity is
/// read), normalises and shades each layer, and composites the layers front
/// to back over the background. Returns the colour, the number of layers,
/// and, when `glassy` and the nearest layer is transparent, that layer and
/// what lies behind it (for the environment effects).
fn composite(
    hits: &mut [Hit],
    used: &mut Vec<bool>,
    splats: &Records<'_>,
    ray: &EyeRay,
    options: &ReferenceOptions,
    glassy: bool,
    lit: Option<&LitLayers>,
) -> (Vec3, u32, Option<GlassPixel>) {
    let background = options.shading.background;
    if hits.is_empty() {
        return (background, 0, None);
    }
    hits.sort_unstable_by(|a, b| a.depth.total_cmp(&b.depth));
    used.clear();
    used.resize(hits.len(), false);
    let to_eye = -ray.dir.normalize();
    let mut colour = Vec3::ZERO;
    let mut transmittance = 1.0f32;
    let mut layers = 0;
    let mut glass: Option<GlassPixel> = None;
    let mut start = 0;
    while start < hits.len() {
        let (mut sum_w, mut sum_c, mut sum_n, mut sum_a, mut sum_d) = (0.0f32, Vec3::ZERO, Vec3::ZERO, 0.0f32, 0.0f32);
        start = take_layer(hits, used, start, options.epsilon, options.transparent, |h| {
            let s = splats.get(h.splat);
            sum_w += h.weight;
            sum_c += s.colour * h.weight;
            sum_n += s.normal * h.weight;
            sum_a += s.opacity * h.weight;
            sum_d += h.depth * h.weight;
        });
        if sum_w <= 0.0 || sum_w.is_nan() {
            continue;
        }
        layers += 1;
        let alpha = (sum_a / sum_w).clamp(0.0, 1.0);
        if let Some(g) = glass.as_mut() {
            // Counted even where too little shows through to change a colour.
            if alpha < 1.0 { g.layers_behind += 1.0 } else { g.closed = true }
        }
        if transmittance <= 1e-6 {
            continue; // too little shows through to change a colour; the layer is only counted
        }
        let normal = sum_n.try_normalize().unwrap_or(to_eye);
        let albedo = sum_c / sum_w;
        let shaded = if let Some(lit) = lit {
            lit.shade(&options.shading, albedo, normal, to_eye, ray.at(sum_d / sum_w))
        } else if options.lighting {
            options.shading.shade(albedo, normal, to_eye)
        } else {
            albedo.clamp(Vec3::ZERO, Vec3::ONE)
        };
        match glass.as_mut() {
            Some(g) => {
                g.behind += g.through * alpha * shaded;
                g.through *= 1.0 - alpha;
            }
            None if glassy && layers == 1 && alpha < 1.0 => {
                let normal = if normal.dot(to_eye) < 0.0 { -normal } else { normal };
                glass = Some(GlassPixel {
                    front: shaded,
                    alpha,
                    normal,
                    behind: Vec3::ZERO,
                    through: 1.0,
                    layers_behind: 0.0,
                    closed: false,
                });
            }
            None => {}
        }
        colour += transmittance * alpha * shaded;
        transmittance *= 1.0 - alpha;
        if transmittance <= 0.0 {
            if let Some(g) = glass.as_mut() {
                g.closed = true;
            }
            break; // an opaque layer ends the ray
        }
    }
    (colour + transmittance * background, layers, glass)
}

/// The ε-layer of `hits` (sorted by depth) that starts at `start`: the
/// hits within ε of its front hit not yet `used` (of the front hit's facing
/// too, when `split_facing`), each marked and given to `visit`. Returns
/// where the next layer starts.
pub(super) fn take_layer(
    hits: &[Hit],
    used: &mut [bool],
    mut start: usize,
    epsilon: f32,
    split_facing: bool,
    mut visit: impl FnMut(&Hit),
) -> usize {
    let (front, facing) = (hits[start].depth, hits[start].facing);
    for (h, taken) in hits[start..].iter().zip(&mut used[start..]).take_while(|(h, _)| h.depth <= front + epsilon) {
        if *taken || (split_facing && h.facing != facing) {
            continue;
        }
        *taken = true;
        visit(h);
    }
    while start < hits.len() && used[start] {
        start += 1;
    }
    start
}

/// Scene lights and the exact shadow rays the reference lights a layer with.
struct LitLayers<'a> {
    rays: ShadowRays<'a>,
    view: glam::Mat4,
    eye_to_world: glam::Mat4,
    lights: &'a Lights,
}

impl LitLayers<'_> {
    /// Shades a layer (eye-space `normal`, Σw·n unflipped, and mean point
    /// `point`) lit by each light through an exact shadow ray.
    fn shade(&self, shading: &Shading, albedo: Vec3, normal: Vec3, to_eye: Vec3, point: Vec3) -> Vec3 {
        let world = self.eye_to_world.transform_point3(point);
        let normal_world = self.eye_to_world.transform_vector3(normal);
        let mut incident = [(Vec3::ZERO, Vec3::ZERO); crate::frame::lights::MAX_LIGHTS];
        for (slot, light) in incident.iter_mut().zip(self.lights.as_slice()) {
            let (l, radiance) = light.incident(world);
            let t = self.rays.transmittance(world, normal_world.dot(l) > 0.0, light);
            *slot = (self.view.transform_vector3(l), radiance * t);
        }
        shading.shade_lit(albedo, normal, to_eye, &incident[..self.lights.len()])
    }
}

/// Quantises as the GPU's Rgba8Unorm target does (round to nearest).
fn to_rgba8(c: Vec3) -> [u8; 4] {
    let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    [q(c.x), q(c.y), q(c.z), 255]
}
