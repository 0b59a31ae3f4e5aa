//! The octree a COPC file is made of, built over points held in memory:
//! for `convert` ([`super::write`]) and for a point file opened whole as a
//! tree of nodes ([`super::memory`]).
//!
//! It follows COPC 1.0 and Entwine: a cube around the bounds, and at each
//! node one point per cell of a [`GRID`]³ grid over its cube stays there (the
//! root's spacing is the cube's side / [`GRID`]); the rest go to the eight
//! children, until a node holds at most [`LEAF_POINTS`]. Each level is one
//! pass over the points still to place, its nodes split in parallel; a
//! node's taken cells are a bitset of the grid (256 KiB), so a point costs a
//! cell index and a bit test, as PotreeConverter's counting pass does.

use glam::DVec3;
use las::copc::VoxelKey;
use rayon::prelude::*;

/// Cells per side of a node's sampling grid.
pub const GRID: u32 = 128;
/// A node with at most this many points is a leaf.
pub const LEAF_POINTS: usize = 100_000;
const MAX_LEVEL: i32 = 20;

/// One node: its key and the indices of the points it keeps.
pub struct Node {
    pub key: VoxelKey,
    pub points: Vec<u32>,
}

/// The octree's cube around the points, and their bounds.
pub struct Cube {
    pub lo: DVec3,
    pub hi: DVec3,
    pub centre: DVec3,
    pub halfsize: f64,
    /// The root's point spacing: the cube's side / [`GRID`].
    pub spacing: f64,
}

impl Cube {
    /// The cube around the `count` (at least one) points `position` gives,
    /// widened by the file's `scale` so every point is inside.
    pub fn around(position: &(impl Fn(usize) -> DVec3 + Sync), count: usize, scale: f64) -> Cube {
        let first = position(0);
        let (lo, hi) = (0..count)
            .into_par_iter()
            .fold(|| (first, first), |(lo, hi), i| (lo.min(position(i)), hi.max(position(i))))
            .reduce(|| (first, first), |a, b| (a.0.min(b.0), a.1.max(b.1)));
        let halfsize = ((hi - lo).max_element() * 0.5).max(1e-3) * (1.0 + 1e-9) + scale.abs();
        Cube { lo, hi, centre: (lo + hi) * 0.5, halfsize, spacing: 2.0 * halfsize / f64::from(GRID) }
    }
}

/// The octree's nodes, level by level (coarse ones first), empty ones left
/// out; and the deepest level.
pub fn octree(position: &(impl Fn(usize) -> DVec3 + Sync), count: usize, cube: &Cube) -> (Vec<Node>, i32) {
    let mut nodes = Vec::new();
    let mut level = vec![Node { key: VoxelKey::ROOT, points: (0..count as u32).collect() }];
    let mut depth = 0;
    while !level.is_empty() {
        let next: Vec<Vec<Node>> = level.par_iter_mut().map(|node| split(node, position, cube)).collect();
        depth = level[0].key.l;
        nodes.extend(level.into_iter().filter(|n| !n.points.is_empty()));
        level = next.into_iter().flatten().collect();
    }
    (nodes, depth)
}

/// Keeps one point per grid cell in `node` (all of them in a leaf) and
/// returns its children with the rest.
fn split(node: &mut Node, position: &(impl Fn(usize) -> DVec3 + Sync), cube: &Cube) -> Vec<Node> {
    if node.points.len() <= LEAF_POINTS || node.key.l >= MAX_LEVEL {
        return Vec::new();
    }
    let side = 2.0 * cube.halfsize / f64::from(1u32 << node.key.l);
    let key = node.key;
    let min = cube.centre - DVec3::splat(cube.halfsize) + DVec3::new(key.x as f64, key.y as f64, key.z as f64) * side;
    let per_cell = f64::from(GRID) / side;
    let mut taken = vec![0u64; (GRID * GRID * GRID / 64) as usize];
    let mut children: [Vec<u32>; 8] = Default::default();
    let mut kept = Vec::new();
    let top = f64::from(GRID - 1);
    for &i in &node.points {
        let local = (position(i as usize) - min) * per_cell;
        let c = local.floor().clamp(DVec3::ZERO, DVec3::splat(top));
        let (cx, cy, cz) = (c.x as u32, c.y as u32, c.z as u32);
        let cell = ((cx * GRID + cy) * GRID + cz) as usize;
        let bit = 1u64 << (cell % 64);
        if taken[cell / 64] & bit == 0 {
            taken[cell / 64] |= bit;
            kept.push(i);
        } else {
            let half = GRID / 2;
            let octant = (cx >= half) as usize | ((cy >= half) as usize) << 1 | ((cz >= half) as usize) << 2;
            children[octant].push(i);
        }
    }
    node.points = kept;
    children
        .into_iter()
        .enumerate()
        .filter(|(_, points)| !points.is_empty())
        .map(|(octant, points)| {
            let bit = |b: usize| ((octant >> b) & 1) as i32;
            let key = VoxelKey { l: key.l + 1, x: 2 * key.x + bit(0), y: 2 * key.y + bit(1), z: 2 * key.z + bit(2) };
            Node { key, points }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point in exactly one node, inside its cube; an inner node
    /// keeps at most one point per cell; a leaf holds at most LEAF_POINTS.
    #[test]
    fn every_point_lies_in_one_node_that_keeps_one_per_cell() {
        let n = 300_000usize;
        // A hash-scattered cloud: dense enough to need two levels.
        let hash = |i: usize, k: u64| {
            ((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ k).wrapping_mul(0xBF58_476D_1CE4_E5B9) >> 40
        };
        let points: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(hash(i, 1) as f64, hash(i, 2) as f64, (hash(i, 3) % 1000) as f64) * 1e-3)
            .collect();
        let position = |i: usize| points[i];
        let cube = Cube::around(&position, n, 0.001);
        let (nodes, depth) = octree(&position, n, &cube);
        assert!(depth >= 1 && nodes.len() > 1, "{depth} {}", nodes.len());
        let mut seen = vec![false; n];
        for node in &nodes {
            let side = 2.0 * cube.halfsize / f64::from(1u32 << node.key.l);
            let k = node.key;
            let min = cube.centre - DVec3::splat(cube.halfsize) + DVec3::new(k.x as f64, k.y as f64, k.z as f64) * side;
            let mut cells = std::collections::HashSet::new();
            let inner = nodes.iter().any(|m| m.key.l == k.l + 1 && m.key.parent() == k);
            let mut one_per_cell = true;
            for &i in &node.points {
                assert!(!std::mem::replace(&mut seen[i as usize], true), "point {i} in two nodes");
                let p = points[i as usize];
                assert!(p.cmpge(min).all() && p.cmple(min + DVec3::splat(side)).all(), "{p} outside {k:?}");
                let c = ((p - min) * f64::from(GRID) / side).floor();
                one_per_cell &= cells.insert((c.x as i64, c.y as i64, c.z as i64));
            }
            assert!(if inner { one_per_cell } else { one_per_cell || node.points.len() <= LEAF_POINTS }, "{k:?}");
        }
        assert!(seen.iter().all(|&s| s), "a point in no node");
    }
}
