//! The reference's mesh triangles: exact ray-triangle intersection
//! (Möller & Trumbore 1997) per pixel ray, with the vertex normals, colours
//! and opacities interpolated by the hit's barycentric coordinates, as the
//! GPU's triangle passes interpolate them (`vs_triangle`, shaders/splat.wgsl).
//!
//! A triangle hit joins the pixel's hits like a splat's, with the weight of a
//! splat's centre (the Gaussian's peak): a mesh alone is its triangles, and
//! where splats overlap triangles within ε they blend as on the GPU. One-sided
//! triangles facing away are culled by their plane's normal (the winding's),
//! as splats are by theirs.

use glam::{Mat4, Vec3};

use super::tiles::{EyeSplat, TILE, TileBins};
use crate::cloud::PointCloud;
use crate::frame::eye_ray::EyeRay;

/// A triangle in eye space.
#[derive(Debug, Clone, Copy)]
pub struct EyeTriangle {
    pub corners: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub colours: [Vec3; 3],
    pub opacity: [f32; 3],
    /// The plane's unit normal, by the winding.
    pub face: Vec3,
}

/// The triangles (flattened splat indices) of `cloud` in eye space, less
/// those culled (facing away and one-sided, when `culling`).
pub fn eye_triangles(
    cloud: &PointCloud,
    triangles: impl Iterator<Item = [u32; 3]>,
    view: &Mat4,
    culling: bool,
    transparent: bool,
) -> Vec<EyeTriangle> {
    triangles
        .filter_map(|t| {
            let corners = t.map(|v| view.transform_point3(cloud.positions[v as usize]));
            let face = (corners[1] - corners[0]).cross(corners[2] - corners[0]).try_normalize()?;
            if culling && !cloud.is_two_sided(t[0] as usize) && face.dot(corners[0]) > 0.0 {
                return None;
            }
            Some(EyeTriangle {
                corners,
                normals: t.map(|v| view.transform_vector3(cloud.normals[v as usize])),
                colours: t.map(|v| {
                    let [r, g, b] = cloud.colours[v as usize];
                    Vec3::new(r as f32, g as f32, b as f32) / 255.0
                }),
                opacity: t.map(|v| if transparent { cloud.opacity[v as usize].clamp(0.0, 1.0) } else { 1.0 }),
                face,
            })
        })
        .collect()
}

/// Adds each triangle to the bins of the tiles its projection may cover.
pub fn bin(triangles: &[EyeTriangle], proj: &Mat4, (width, height): (u32, u32), near: f32, bins: &mut TileBins) {
    let rows = height.div_ceil(TILE);
    for (i, t) in triangles.iter().enumerate() {
        let (lo, hi) = if t.corners.iter().any(|c| -c.z <= near) {
            // Part of it is behind the near plane: it may cover anything.
            (glam::Vec2::ZERO, glam::Vec2::new(width as f32, height as f32))
        } else {
            match super::tiles::screen_box(t.corners.into_iter(), proj, width, height) {
                Some(found) => found,
                None => continue,
            }
        };
        let tile = |v: f32, size: u32| (v.floor().max(0.0) as u32).min(size - 1) / TILE;
        let index = bins.first_triangle + i as u32;
        for ty in tile(lo.y, height)..=tile(hi.y, height).min(rows - 1) {
            for tx in tile(lo.x, width)..=tile(hi.x, width) {
                bins.bins[(ty * bins.columns + tx) as usize].push(index);
            }
        }
    }
}

/// Where `ray` (its direction has z = -1, so the parameter is the view
/// depth) meets `t` between `near` and `far`: the depth and the hit as
/// a splat record (the point, the interpolated normal, colour and opacity).
pub fn intersect(t: &EyeTriangle, ray: &EyeRay, near: f32, far: f32) -> Option<(f32, EyeSplat)> {
    let [a, b, c] = t.corners;
    let (e1, e2) = (b - a, c - a);
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-20 {
        return None;
    }
    let inv = 1.0 / det;
    let s = ray.origin - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let depth = e2.dot(q) * inv;
    if !(depth > near && depth < far) {
        return None;
    }
    let w = [1.0 - u - v, u, v];
    let mix = |values: [Vec3; 3]| values[0] * w[0] + values[1] * w[1] + values[2] * w[2];
    let normal = mix(t.normals).try_normalize().unwrap_or(t.face);
    let record = EyeSplat {
        centre: ray.at(depth),
        normal,
        plane: t.face,
        radius: 0.0,
        colour: mix(t.colours),
        opacity: t.opacity[0] * w[0] + t.opacity[1] * w[1] + t.opacity[2] * w[2],
    };
    Some((depth, record))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_through_a_triangle_hits_it_at_its_depth_with_interpolated_attributes() {
        let t = EyeTriangle {
            corners: [Vec3::new(-1.0, -1.0, -2.0), Vec3::new(1.0, -1.0, -2.0), Vec3::new(0.0, 1.0, -4.0)],
            normals: [Vec3::Z, Vec3::Z, Vec3::X],
            colours: [Vec3::X, Vec3::Y, Vec3::Z],
            opacity: [1.0; 3],
            face: Vec3::Z,
        };
        let along = |dir: Vec3| EyeRay { origin: Vec3::ZERO, dir };
        let (depth, hit) = intersect(&t, &along(Vec3::new(0.0, -0.5, -1.0)), 0.1, 10.0).expect("a hit");
        assert!((depth - 2.0).abs() < 1e-5, "{depth}");
        assert!((hit.colour - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-5, "{:?}", hit.colour);
        assert!(intersect(&t, &along(Vec3::new(1.0, 1.0, -1.0)), 0.1, 10.0).is_none(), "beside it");
        assert!(intersect(&t, &along(Vec3::new(0.0, -0.5, -1.0)), 2.5, 10.0).is_none(), "before the near plane");
        // A parallel ray from beside the eye meets the same point.
        let parallel = EyeRay { origin: Vec3::new(0.0, -1.0, 0.0), dir: Vec3::NEG_Z };
        let (depth, _) = intersect(&t, &parallel, 0.1, 10.0).expect("a parallel hit");
        assert!((depth - 2.0).abs() < 1e-5, "{depth}");
    }
}
