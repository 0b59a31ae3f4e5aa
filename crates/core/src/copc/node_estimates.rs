//! Each streamed node's normals and radii, estimated once, when it arrives,
//! and kept beside its points in the node cache: a pan or a zoom estimates
//! only the nodes it adds. (The splats of Botsch & Kobbelt and of Zhang &
//! Pajarola need both; a COPC file rarely holds them.)
//!
//! A point's neighbours come from its own node and a halo: the points near
//! the node's cube (within [`HALO_SPACINGS`] of the node's point spacing)
//! of the loaded nodes at its level and at every coarser level: its parent,
//! its ancestors and their neighbours. Those are the levels drawn wherever
//! the node is drawn (a selection is additive: a node comes with all its
//! ancestors), so a point at a border sees the same density on both sides
//! of it, and the halo is what keeps the normals and radii of the two sides
//! alike (no seam). Finer nodes are left out, so an estimate never changes
//! when they come or go. A neighbour at the node's level that arrives later
//! is not in its halo: the border points then see one side of the surface
//! (their normals hold; their radii grow a little).
//!
//! A radius follows the density of the node's level and the coarser ones.
//! Where finer nodes are drawn too, the density and the surface are
//! theirs. So a node, when it arrives, also estimates the points of its
//! loaded ancestors that lie in its cube, with the same neighbours as its
//! own ([`Refined`]): what a coarse point is where this node is the deepest
//! drawn at its position. A frame draws each point with the estimate of
//! the deepest node drawn there ([`super::drawn_estimates`], as Potree's
//! adaptive point size follows the deepest visible node at a point). So
//! with every node drawn a coarse point has the neighbours the whole
//! file would give it, and nothing is estimated again when finer nodes come
//! or go.

use std::collections::HashSet;

use glam::{DVec3, Vec3};
use las::copc::VoxelKey;

use super::hierarchy::CopcTree;
use crate::cloud::estimate::{EstimateOptions, Facing, estimate_node, median_radius};
use crate::cloud::las_file::Columns;
use crate::cloud::{Estimates, PointCloud};

/// How far past its cube a node's halo reaches, in the node's point
/// spacing: a point's 16 neighbours on a surface lie within about 2.3.
const HALO_SPACINGS: f64 = 4.0;

/// The nodes whose points may fall in `node`'s halo: at its level and every
/// coarser one, those whose cube meets the node's cube grown by the margin
/// (the node itself left out), and that `loaded` holds.
pub(super) fn halo_nodes(tree: &CopcTree, node: u32, loaded: &dyn Fn(u32) -> bool) -> Vec<u32> {
    let key = tree.nodes[node as usize].key;
    let (lo, hi) = grown_cube(tree, node);
    let (root_min, root_side) = tree.cube(&VoxelKey { l: 0, x: 0, y: 0, z: 0 });
    let mut found = Vec::new();
    for level in 0..=key.l {
        let cells = 1i64 << level;
        let side = root_side / cells as f64;
        let range = |axis: usize| {
            let first = ((lo[axis] - root_min[axis]) / side).floor() as i64;
            let last = ((hi[axis] - root_min[axis]) / side).floor() as i64;
            first.clamp(0, cells - 1)..=last.clamp(0, cells - 1)
        };
        for x in range(0) {
            for y in range(1) {
                for z in range(2) {
                    let cell = VoxelKey { l: level, x: x as i32, y: y as i32, z: z as i32 };
                    if cell == key {
                        continue;
                    }
                    if let Some(n) = tree.node(&cell).filter(|&n| tree.nodes[n as usize].points > 0 && loaded(n)) {
                        found.push(n);
                    }
                }
            }
        }
    }
    found
}

/// The node's cube grown by its halo's margin, in file coordinates.
pub(super) fn grown_cube(tree: &CopcTree, node: u32) -> (DVec3, DVec3) {
    let n = &tree.nodes[node as usize];
    let (min, side) = tree.cube(&n.key);
    // The spacing of the node's points over a face of its cube (a surface
    // crossing it), read from the node itself: the header's spacing is
    // not always written.
    let spacing = side / f64::from(n.points.max(1)).sqrt();
    let margin = (HALO_SPACINGS * spacing).min(side);
    (min - DVec3::splat(margin), min + DVec3::splat(side + margin))
}

/// How the signs of a file's estimated normals are chosen, in the file's
/// coordinates: decided once per file, so that every node's agree across
/// its borders ([`Facing`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum FileFacing {
    /// Up (+z): airborne lidar (every COPC, LAS and LAZ file) and
    /// geo-referenced terrain.
    #[default]
    Up,
    /// Towards the scanner of a single-view scan.
    Towards(DVec3),
    /// Away from the centre of an object scanned all round.
    AwayFrom(DVec3),
}

impl FileFacing {
    /// The rule for points placed relative to `centre`.
    fn relative_to(self, centre: DVec3) -> Facing {
        match self {
            Self::Up => Facing::Up,
            Self::Towards(p) => Facing::Towards((p - centre).as_vec3()),
            Self::AwayFrom(p) => Facing::AwayFrom((p - centre).as_vec3()),
        }
    }
}

/// What a node's points were given once, when it arrived: their normals and
/// radii, the median radius that [`super::drawn_estimates`] scales by where
/// no finer estimate is at hand, and its ancestors' points in its cube as
/// estimated at its density.
pub struct NodeEstimates {
    pub estimates: Estimates,
    /// 0 when no radius is positive.
    pub median_radius: f32,
    /// One per ancestor that was loaded when the node arrived.
    pub refined: Vec<Refined>,
}

/// An ancestor's points that lie in a node's cube, estimated with the
/// node's neighbours: as they are drawn where the node is the deepest.
pub struct Refined {
    /// The ancestor, and its points' indices among its records (ascending).
    pub node: u32,
    pub points: Vec<u32>,
    pub normals: Vec<Vec3>,
    pub radii: Vec<f32>,
}

impl NodeEstimates {
    /// Bytes held, for the node cache's accounting.
    pub fn bytes(&self) -> usize {
        let refined: usize = self.refined.iter().map(|r| r.points.len() * (4 + 12 + 4)).sum();
        self.estimates.normals.len() * 12 + self.estimates.radii.len() * 4 + refined
    }

    /// What this node made of `ancestor`'s points, if it was loaded when this node arrived.
    pub fn refined_for(&self, ancestor: u32) -> Option<&Refined> {
        self.refined.iter().find(|r| r.node == ancestor)
    }
}

/// The normals and radii of `node`'s points (`own`, as decoded), estimated
/// with the points of the loaded nodes `halo` that lie within its grown
/// cube, their signs chosen by the file's `facing`; and, with the same
/// neighbours, those of its ancestors' points (among `halo`) that lie in its cube.
pub(super) fn estimate(
    tree: &CopcTree,
    node: u32,
    (own, halo): (&Columns, &[(u32, &Columns)]),
    options: &EstimateOptions,
    facing: FileFacing,
) -> NodeEstimates {
    let (lo, hi) = grown_cube(tree, node);
    let centre = (lo + hi) * 0.5;
    let key = tree.nodes[node as usize].key;
    // Relative to the node's centre, f32 keeps the points' own precision at any extent.
    let local = |c: &Columns, i: usize| DVec3::new(c.x[i], c.y[i], c.z[i]);
    let finite: Vec<usize> = (0..own.len()).filter(|&i| local(own, i).is_finite()).collect();
    let mut queries: Vec<Vec3> = finite.iter().map(|&i| (local(own, i) - centre).as_vec3()).collect();
    let mut refined: Vec<Refined> = Vec::new();
    let mut around = Vec::new();
    for &(m, columns) in halo {
        let above = tree.nodes[m as usize].key;
        let ancestor = above.l < key.l && key_at(tree, above, centre, key.l) == key;
        let mut inside = Vec::new();
        for i in 0..columns.len() {
            let p = local(columns, i);
            if !(p.cmpge(lo).all() && p.cmple(hi).all()) {
                continue;
            }
            if ancestor && key_at(tree, above, p, key.l) == key {
                inside.push(i as u32);
            } else {
                around.push((p - centre).as_vec3());
            }
        }
        if ancestor {
            queries.extend(inside.iter().map(|&i| (local(columns, i as usize) - centre).as_vec3()));
            refined.push(Refined { node: m, points: inside, normals: Vec::new(), radii: Vec::new() });
        }
    }
    let (mut normals, mut radii) = estimate_node(&queries, &around, options, facing.relative_to(centre));
    let (mut more_normals, mut more_radii) = (normals.split_off(finite.len()), radii.split_off(finite.len()));
    for r in &mut refined {
        let rest = (more_normals.split_off(r.points.len()), more_radii.split_off(r.points.len()));
        (r.normals, r.radii) =
            (std::mem::replace(&mut more_normals, rest.0), std::mem::replace(&mut more_radii, rest.1));
    }
    let median_radius = median_radius(&radii).unwrap_or(0.0);
    let mut out = Estimates { normals: vec![Vec3::Z; own.len()], radii: vec![0.0; own.len()] };
    for (k, &i) in finite.iter().enumerate() {
        out.normals[i] = normals[k];
        out.radii[i] = radii[k];
    }
    NodeEstimates { estimates: out, median_radius, refined }
}

/// The key at `level` of the cube that holds `p`, found from the cube of
/// `from` (which holds it) down by halves, a point on a half's boundary
/// going to the upper half: the one rule for where a point lies.
pub(super) fn key_at(tree: &CopcTree, from: VoxelKey, p: DVec3, level: i32) -> VoxelKey {
    let mut key = from;
    while key.l < level {
        key = child_at(tree, key, p);
    }
    key
}

/// The child of `key`'s cube that holds `p` (by halves, as [`key_at`]).
pub(super) fn child_at(tree: &CopcTree, key: VoxelKey, p: DVec3) -> VoxelKey {
    let (min, side) = tree.cube(&key);
    let half = min + DVec3::splat(side * 0.5);
    VoxelKey {
        l: key.l + 1,
        x: 2 * key.x + i32::from(p.x >= half.x),
        y: 2 * key.y + i32::from(p.y >= half.y),
        z: 2 * key.z + i32::from(p.z >= half.z),
    }
}

/// Whether `node` stands for finer points that are not drawn: a child of
/// it that holds points is not among the `drawn` nodes.
pub(super) fn stands_for_more(tree: &CopcTree, node: u32, drawn: &HashSet<u32>) -> bool {
    tree.nodes[node as usize].children.iter().any(|&c| tree.nodes[c as usize].points > 0 && !drawn.contains(&c))
}

/// Each splat's radius given by the file, grown to at least its record's
/// estimated radius as drawn ([`super::drawn_estimates`]) where its record's node is
/// `coarse` (it stands for finer points not drawn), so a coarse view has no
/// holes; elsewhere the file's radius stands. `splat_of[i]`: record i's
/// splat; nothing is grown when the estimates do not match the records.
pub(super) fn grow_given_radii(cloud: &mut PointCloud, splat_of: &[u32], (estimated, coarse): (&[f32], &[bool])) {
    if estimated.len() != splat_of.len() || coarse.len() != splat_of.len() {
        return;
    }
    for ((&splat, &radius), _) in splat_of.iter().zip(estimated).zip(coarse).filter(|(_, c)| **c) {
        if let Some(r) = cloud.radii.get_mut(splat as usize) {
            *r = r.max(radius);
        }
    }
}
