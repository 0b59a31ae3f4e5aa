//! Binning splats into screen tiles for the reference renderer.
//!
//! Each splat's disc is bounded in eye space by c ± r·sqrt(1 - n_i²) per
//! axis (the exact axis-aligned box of a disc); the box's corners are
//! projected to find the tiles it may cover.

use glam::{Mat4, Vec3};

/// Side of a square tile, in pixels.
pub const TILE: u32 = 16;

/// A splat transformed to eye space, ready for ray intersection.
#[derive(Debug, Clone, Copy)]
pub struct EyeSplat {
    pub centre: Vec3,
    /// Unit normal, for shading.
    pub normal: Vec3,
    /// Unit normal of the plane the footprint is cast on (tilted when grazing).
    pub plane: Vec3,
    pub radius: f32,
    pub colour: Vec3,
    pub opacity: f32,
}

/// Splat indices per tile, row-major over the tile grid; indices from
/// `first_triangle` on are triangles (`first_triangle` + their index).
pub struct TileBins {
    pub columns: u32,
    pub bins: Vec<Vec<u32>>,
    pub first_triangle: u32,
}

/// Screen-space pixel bounds of a splat, or `None` if it is off screen.
fn pixel_bounds(s: &EyeSplat, proj: &Mat4, width: u32, height: u32, near: f32) -> Option<(u32, u32, u32, u32)> {
    let n = s.plane;
    let half = Vec3::new(1.0 - n.x * n.x, 1.0 - n.y * n.y, 1.0 - n.z * n.z).max(Vec3::ZERO).to_array().map(f32::sqrt);
    let half = Vec3::from_array(half) * s.radius;
    let (lo, hi) = (s.centre - half, s.centre + half);
    if hi.z >= -near {
        // The box reaches the near plane: its corners do not project, and the splat may cover anything.
        return Some((0, 0, width - 1, height - 1));
    }
    let corners = (0..8).map(|corner| {
        Vec3::new(
            if corner & 1 == 0 { lo.x } else { hi.x },
            if corner & 2 == 0 { lo.y } else { hi.y },
            if corner & 4 == 0 { lo.z } else { hi.z },
        )
    });
    let (min, max) = screen_box(corners, proj, width, height)?;
    let clamp_x = |v: f32| (v.floor().max(0.0) as u32).min(width - 1);
    let clamp_y = |v: f32| (v.floor().max(0.0) as u32).min(height - 1);
    Some((clamp_x(min.x), clamp_y(min.y), clamp_x(max.x), clamp_y(max.y)))
}

/// The pixel box of eye-space `points` (all in front of the near plane),
/// or `None` when it is off screen.
pub fn screen_box(
    points: impl Iterator<Item = Vec3>,
    proj: &Mat4,
    width: u32,
    height: u32,
) -> Option<(glam::Vec2, glam::Vec2)> {
    let mut min = glam::Vec2::splat(f32::INFINITY);
    let mut max = glam::Vec2::splat(f32::NEG_INFINITY);
    for p in points {
        let clip = *proj * p.extend(1.0);
        let ndc = glam::Vec2::new(clip.x, clip.y) / clip.w;
        let px = glam::Vec2::new((ndc.x * 0.5 + 0.5) * width as f32, (0.5 - ndc.y * 0.5) * height as f32);
        min = min.min(px);
        max = max.max(px);
    }
    let off_screen = max.x < 0.0 || max.y < 0.0 || min.x > width as f32 || min.y > height as f32;
    (min.is_finite() && max.is_finite() && !off_screen).then_some((min, max))
}

/// Bins `splats` into tiles of [`TILE`] pixels.
pub fn bin(splats: &[EyeSplat], proj: &Mat4, width: u32, height: u32, near: f32) -> TileBins {
    let columns = width.div_ceil(TILE);
    let rows = height.div_ceil(TILE);
    let mut bins = vec![Vec::new(); (columns * rows) as usize];
    for (i, s) in splats.iter().enumerate() {
        if let Some((x0, y0, x1, y1)) = pixel_bounds(s, proj, width, height, near) {
            for ty in y0 / TILE..=y1 / TILE {
                for tx in x0 / TILE..=x1 / TILE {
                    bins[(ty * columns + tx) as usize].push(i as u32);
                }
            }
        }
    }
    TileBins { columns, bins, first_triangle: splats.len() as u32 }
}
