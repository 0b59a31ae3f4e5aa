//! Exact shadows: a ray from a surface point to a light through the splat
//! discs, the ruler TSM is measured against.
//!
//! The discs are bucketed into a uniform grid (each disc in every cell its
//! bounding box touches; cells about two mean radii wide, capped at four
//! cells per splat) and a ray walks the grid cell by cell (Amanatides & Woo's
//! 3D DDA), testing each disc of a cell and keeping a hit only in the cell
//! that holds the hit point, so a disc in several cells counts once. The
//! hits between the point and the light, and the point itself, are then
//! layered from the light's side exactly as a TSM cell is
//! ([`super::layers::sweep`]): the transmittance is that of the layers in
//! front of the point's own layer. Hand-written because the query is a
//! segment through discs, which a k-d tree or R-tree crate answers only as
//! many box queries.

use glam::{IVec3, Vec3};
use rayon::prelude::*;

use super::ShadowInput;
use super::layers::{self, Entry};
use crate::frame::{Light, LightKind};

/// The opacity that marks the probe entry (the point asking for its light;
/// its weight is 0, so it changes no layer).
const PROBE: f32 = -1.0;

/// The splats of a scene in a grid, ready for shadow rays.
pub struct ShadowRays<'a> {
    input: ShadowInput<'a>,
    origin: Vec3,
    cell: f32,
    dims: IVec3,
    /// `start[c]..start[c + 1]` indexes `items` for cell c.
    start: Vec<u32>,
    items: Vec<u32>,
    /// The scene's bounding sphere radius (how far a directional light's ray goes).
    reach: f32,
}

impl<'a> ShadowRays<'a> {
    pub fn new(input: &ShadowInput<'a>) -> Self {
        let cloud = input.cloud;
        let n = cloud.len();
        let (lo, hi) = (0..n).fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), i| {
            let r = Vec3::splat(input.radius(i));
            (lo.min(cloud.positions[i] - r), hi.max(cloud.positions[i] + r))
        });
        let (lo, hi) = if n == 0 { (Vec3::ZERO, Vec3::ONE) } else { (lo, hi) };
        let extent = (hi - lo).max(Vec3::splat(1e-6));
        // Cells of about two mean radii, but no more than 4 per splat in all.
        let by_radius = 2.0 * (cloud.mean_radius() * input.radius_scale).max(1e-9);
        let by_count = (extent.x * extent.y * extent.z / (4.0 * n.max(1) as f32)).cbrt();
        let cell = by_radius.max(by_count);
        let dims = ((extent / cell).ceil().as_ivec3()).max(IVec3::ONE);
        let cell_of = |p: Vec3| ((p - lo) / cell).floor().as_ivec3().clamp(IVec3::ZERO, dims - 1);
        let index = |c: IVec3| (c.x + dims.x * (c.y + dims.y * c.z)) as usize;
        let total = (dims.x as usize) * (dims.y as usize) * (dims.z as usize);
        let mut start = vec![0u32; total + 1];
        let boxes: Vec<(IVec3, IVec3)> = (0..n)
            .map(|i| {
                let r = Vec3::splat(input.radius(i));
                (cell_of(cloud.positions[i] - r), cell_of(cloud.positions[i] + r))
            })
            .collect();
        let each = |(a, b): (IVec3, IVec3), f: &mut dyn FnMut(usize)| {
            for z in a.z..=b.z {
                for y in a.y..=b.y {
                    for x in a.x..=b.x {
                        f(index(IVec3::new(x, y, z)));
                    }
                }
            }
        };
        for &b in &boxes {
            each(b, &mut |c| start[c + 1] += 1);
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut items = vec![0u32; start[total] as usize];
        let mut fill = start.clone();
        for (i, &b) in boxes.iter().enumerate() {
            each(b, &mut |c| {
                items[fill[c] as usize] = i as u32;
                fill[c] += 1;
            });
        }
        let reach = extent.length();
        Self { input: *input, origin: lo, cell, dims, start, items, reach }
    }

    /// Each splat's shadow coefficient for `light`: a ray from its centre.
    pub fn per_splat(&self, light: &Light) -> Vec<f32> {
        let cloud = self.input.cloud;
        (0..cloud.len())
            .into_par_iter()
            .map_init(
                || (Vec::new(), super::layers::Scratch::default()),
                |(entries, scratch), i| {
                    let facing = self.input.faces(i, light);
                    self.transmittance_with(cloud.positions[i], facing, light, Some(i as u32), entries, scratch)
                },
            )
            .collect()
    }

    /// The light `light` leaves at world point `p` of a surface whose normal
    /// faces it (`facing`) or not.
    pub fn transmittance(&self, p: Vec3, facing: bool, light: &Light) -> f32 {
        self.transmittance_with(p, facing, light, None, &mut Vec::new(), &mut Default::default())
    }

    fn transmittance_with(
        &self,
        p: Vec3,
        facing: bool,
        light: &Light,
        own: Option<u32>,
        entries: &mut Vec<Entry>,
        scratch: &mut super::layers::Scratch,
    ) -> f32 {
        // The segment from p towards the light, and its length.
        let (dir, length) = match light.kind {
            LightKind::Point(position) => {
                let d = position - p;
                let l = d.length();
                if !l.is_finite() || l <= 0.0 {
                    return 1.0;
                }
                (d / l, l)
            }
            LightKind::Directional(d) => (-d.normalize(), self.reach * 2.0 + self.cell),
        };
        entries.clear();
        // The point itself, as a probe: distance from the light end of the segment.
        entries.push(Entry { distance: length, weight: 0.0, opacity: PROBE, facing });
        let cloud = self.input.cloud;
        self.walk(p, dir, length, |i, cell| {
            if Some(i) == own {
                return;
            }
            let i = i as usize;
            let (c, n, r) = (cloud.positions[i], cloud.normals[i], self.input.radius(i));
            let cos = n.dot(dir);
            if cos.abs() < 1e-9 {
                return;
            }
            let t = n.dot(c - p) / cos;
            if !(t > 0.0 && t < length) {
                return;
            }
            let hit = p + dir * t;
            let rho2 = (hit - c).length_squared() / (r * r);
            if rho2 < 1.0 && self.cell_of(hit) == cell && self.input.clip.keeps(hit) {
                entries.push(Entry {
                    distance: length - t,
                    weight: self.input.kernel.weight(rho2),
                    opacity: self.input.opacity(i),
                    facing: self.input.faces(i, light),
                });
            }
        });
        entries.sort_unstable_by(|a, b| a.distance.total_cmp(&b.distance));
        let mut result = 1.0;
        let probe = entries.iter().position(|e| e.opacity == PROBE).unwrap_or(0);
        layers::sweep(entries, self.input.epsilon, scratch, |k, a| {
            if k == probe {
                result = layers::transmittance(a);
            }
        });
        result
    }

    fn cell_of(&self, p: Vec3) -> IVec3 {
        ((p - self.origin) / self.cell).floor().as_ivec3().clamp(IVec3::ZERO, self.dims - 1)
    }

    /// Calls `visit(splat, cell)` for every splat of every cell the segment
    /// p + t·dir, 0 ≤ t ≤ length, passes through (3D DDA).
    fn walk(&self, p: Vec3, dir: Vec3, length: f32, mut visit: impl FnMut(u32, IVec3)) {
        let hi = self.origin + self.dims.as_vec3() * self.cell;
        // Clip the segment to the grid's box.
        let (mut t0, mut t1) = (0.0f32, length);
        for axis in 0..3 {
            if dir[axis].abs() < 1e-12 {
                if p[axis] < self.origin[axis] || p[axis] > hi[axis] {
                    return;
                }
                continue;
            }
            let (a, b) = ((self.origin[axis] - p[axis]) / dir[axis], (hi[axis] - p[axis]) / dir[axis]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        if t0 > t1 {
            return;
        }
        let start = p + dir * t0;
        let mut cell = self.cell_of(start);
        let step = IVec3::new(dir.x.signum() as i32, dir.y.signum() as i32, dir.z.signum() as i32);
        let mut next = Vec3::ZERO;
        let mut delta = Vec3::ZERO;
        for axis in 0..3 {
            if dir[axis].abs() < 1e-12 {
                next[axis] = f32::INFINITY;
                delta[axis] = f32::INFINITY;
                continue;
            }
            let boundary = self.origin[axis] + (cell[axis] + (step[axis] > 0) as i32) as f32 * self.cell;
            next[axis] = (boundary - p[axis]) / dir[axis];
            delta[axis] = self.cell / dir[axis].abs();
        }
        // A segment crosses at most this many cells; the cap also ends a walk on non-finite input.
        let most = (self.dims.x + self.dims.y + self.dims.z) as usize + 1;
        for _ in 0..most {
            let c = (cell.x + self.dims.x * (cell.y + self.dims.y * cell.z)) as usize;
            for &i in &self.items[self.start[c] as usize..self.start[c + 1] as usize] {
                visit(i, cell);
            }
            let axis = if next.x <= next.y && next.x <= next.z {
                0
            } else if next.y <= next.z {
                1
            } else {
                2
            };
            if next[axis] > t1 {
                return;
            }
            cell[axis] += step[axis];
            if cell[axis] < 0 || cell[axis] >= self.dims[axis] {
                return;
            }
            next[axis] += delta[axis];
        }
    }
}
