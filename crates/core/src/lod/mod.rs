//! A multi-resolution hierarchy of a cloud's splats, for frames under a
//! point budget (Guennebaud's SPBG'06 slides, "hybrid rendering":
//! leaves hold the original points; here inner nodes hold coarser ones).
//!
//! An octree over the cloud's bounding cube: a node with at most
//! [`LEAF_SPLATS`] splats (or at [`MAX_DEPTH`]) is a leaf and holds its
//! original splats; every other node is split in eight and holds a subsample
//! of its subtree: one representative per occupied cell of a
//! [`CELLS`]³ grid over its cube, at the mean position, normal, colour and
//! opacity of the splats in that cell, with the radius that reaches as far
//! across its disc as the farthest of their discs does, so a node's
//! representatives close the surface the way its originals do. A child's
//! cells are half as wide, so each level doubles the resolution.
//! [`select`] picks the nodes a frame draws, [`cache`] keeps built
//! hierarchies on disk.
//!
//! The build partitions splat indices in place (a counting sort into
//! octants per node, subtrees in parallel) and makes each inner node's
//! representatives in two passes over its subtree (the cells' sums, then
//! each disc's reach): O(n · depth) work.

pub mod cache;
pub mod select;
pub mod subset;

use glam::Vec3;
use rayon::prelude::*;

use crate::cloud::PointCloud;

pub use crate::frame::subset::Choosing;
pub use select::{LodTree, Refinement, SelectOptions, Selection, gather, select, select_in};

/// Most original splats a leaf holds. With [`CELLS`], chosen so that a
/// surface node just above the leaves holds about a quarter of their
/// splats, as every other level does (measured on the 1M-sample bunny at a
/// 250K budget, docs/BENCHMARKS.md: 1024/8 and 512/16 left coarse nodes
/// beside leaves, ε up to 2.8 above the full frame; 256/12 up to 1.5).
pub const LEAF_SPLATS: usize = 256;
/// Representative cells per side of an inner node's cube.
pub const CELLS: usize = 12;
/// A cell's half-diagonal, in cell sides: an inner node's coarseness, for the selection.
const CELL_HALF_DIAGONAL: f32 = 0.866;
/// Deepest level; a node there is a leaf whatever it holds (coincident splats).
pub const MAX_DEPTH: u32 = 21;
/// Subtrees with more splats than this are built in parallel.
const PARALLEL_SPLATS: usize = 32_768;

/// One node of the octree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// Centre and half side of its cube.
    pub centre: Vec3,
    pub half: f32,
    /// Its splats are `Hierarchy::splats[first..first + count]`.
    pub first: u32,
    pub count: u32,
    /// Its children are `nodes[children..children + child_count]` (none for a leaf).
    pub children: u32,
    pub child_count: u32,
    /// Radius of the sphere around `centre` that holds every disc of its
    /// subtree and its own (at radius scale 1).
    pub reach: f32,
    /// How coarse it is (its error, on screen): a leaf's largest splat
    /// radius; an inner node's cell half-diagonal, or its subtree's largest
    /// splat radius where that is more.
    pub radius: f32,
}

impl Node {
    pub fn is_leaf(&self) -> bool {
        self.child_count == 0
    }
}

/// The octree and every node's splats, node after node.
#[derive(Debug, Clone)]
pub struct Hierarchy {
    /// `nodes[0]` is the root; a node's children are contiguous.
    pub nodes: Vec<Node>,
    /// Each node's splats (a leaf's originals, an inner node's representatives).
    pub splats: PointCloud,
    /// Splats of the cloud it was built from.
    pub originals: usize,
    /// Seconds the build took (0 when read from the cache).
    pub seconds: f64,
}

/// A node while the tree is built: its representatives or its leaf's indices.
struct Built {
    centre: Vec3,
    half: f32,
    own: PointCloud,
    children: Vec<Built>,
    reach: f32,
    radius: f32,
}

impl Hierarchy {
    /// Builds the hierarchy of `cloud`.
    pub fn build(cloud: &PointCloud) -> Self {
        let started = std::time::Instant::now();
        let (centre, half) = bounding_cube(cloud);
        let mut indices: Vec<u32> = (0..cloud.len() as u32).collect();
        let root = build_node(cloud, &mut indices, centre, half, 0);
        let mut hierarchy = flatten(root, cloud);
        hierarchy.originals = cloud.len();
        hierarchy.seconds = started.elapsed().as_secs_f64();
        hierarchy
    }

    /// Bytes it holds (nodes and splats), for `--explain`.
    pub fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.splats.len() * SPLAT_BYTES
    }

    /// Depth of the deepest leaf (the root is at 0).
    pub fn depth(&self) -> u32 {
        let mut depth = vec![0u32; self.nodes.len()];
        let mut deepest = 0;
        for (i, node) in self.nodes.iter().enumerate() {
            for c in node.children..node.children + node.child_count {
                depth[c as usize] = depth[i] + 1;
                deepest = deepest.max(depth[i] + 1);
            }
        }
        deepest
    }
}

/// Bytes of one splat in memory (position, normal, radius, colour, opacity, two-sidedness).
const SPLAT_BYTES: usize = 12 + 12 + 4 + 3 + 4 + 1;

/// The cube around the cloud's bounds (a point's cube has a small side).
fn bounding_cube(cloud: &PointCloud) -> (Vec3, f32) {
    let Some(bounds) = cloud.bounds() else { return (Vec3::ZERO, 1.0) };
    let half = ((bounds.max - bounds.min).max_element() * 0.5).max(1e-6) * 1.0001;
    (bounds.center(), half)
}

fn octant(p: Vec3, centre: Vec3) -> usize {
    (p.x >= centre.x) as usize | (((p.y >= centre.y) as usize) << 1) | (((p.z >= centre.z) as usize) << 2)
}

fn build_node(cloud: &PointCloud, indices: &mut [u32], centre: Vec3, half: f32, depth: u32) -> Built {
    // The sphere holding every disc, and the widest disc.
    let (reach, widest) = indices.iter().fold((0.0f32, 0.0f32), |(reach, widest), &i| {
        let r = cloud.radii[i as usize];
        (reach.max((cloud.positions[i as usize] - centre).length() + r), widest.max(r))
    });
    if indices.len() <= LEAF_SPLATS || depth >= MAX_DEPTH {
        let own = cloud.select(indices);
        return Built { centre, half, own, children: Vec::new(), reach, radius: widest };
    }
    let own = representatives(cloud, indices, centre, half);
    // Its coarseness: the half-diagonal of its cells (or its widest original's
    // radius where that is more), not its widest representative, which a
    // single cell of scattered splats would set.
    let radius = (CELL_HALF_DIAGONAL * 2.0 * half / CELLS as f32).max(widest);
    // A representative's disc may reach past every original's.
    let reach = own.positions.iter().zip(&own.radii).map(|(p, r)| (*p - centre).length() + r).fold(reach, f32::max);
    // Counting sort of the indices into the eight octants.
    let mut counts = [0usize; 8];
    for &i in indices.iter() {
        counts[octant(cloud.positions[i as usize], centre)] += 1;
    }
    let mut starts = [0usize; 8];
    for o in 1..8 {
        starts[o] = starts[o - 1] + counts[o - 1];
    }
    let mut sorted = vec![0u32; indices.len()];
    let mut next = starts;
    for &i in indices.iter() {
        let o = octant(cloud.positions[i as usize], centre);
        sorted[next[o]] = i;
        next[o] += 1;
    }
    indices.copy_from_slice(&sorted);
    drop(sorted);
    let mut parts: Vec<(usize, &mut [u32])> = Vec::with_capacity(8);
    let mut rest = indices;
    for (o, &count) in counts.iter().enumerate() {
        let (part, tail) = rest.split_at_mut(count);
        rest = tail;
        if count > 0 {
            parts.push((o, part));
        }
    }
    let quarter = half * 0.5;
    let child_centre = |o: usize| {
        let sign = |bit: usize| if o & bit != 0 { quarter } else { -quarter };
        centre + Vec3::new(sign(1), sign(2), sign(4))
    };
    let total: usize = counts.iter().sum();
    let children: Vec<Built> = if total > PARALLEL_SPLATS {
        parts.into_par_iter().map(|(o, part)| build_node(cloud, part, child_centre(o), quarter, depth + 1)).collect()
    } else {
        parts.into_iter().map(|(o, part)| build_node(cloud, part, child_centre(o), quarter, depth + 1)).collect()
    };
    Built { centre, half, own, children, reach, radius }
}

/// Sums of the splats in one cell.
#[derive(Clone, Copy, Default)]
struct Cell {
    count: u32,
    position: Vec3,
    normal: Vec3,
    first_normal: Vec3,
    colour: [u32; 3],
    opacity: f32,
    two_sided: bool,
}

impl Cell {
    fn mean_position(&self) -> Vec3 {
        self.position / self.count as f32
    }

    /// The mean normal; where opposite normals (the two sides of a thin
    /// part) cancel, the first splat's.
    fn mean_normal(&self) -> Vec3 {
        if self.normal.length() > 0.1 * self.count as f32 { self.normal.normalize() } else { self.first_normal }
    }
}

/// One representative splat per occupied cell of a [`CELLS`]³ grid over the
/// cube: at the mean position of the cell's splats, facing their mean
/// normal, with their mean colour and opacity. Its radius is the farthest
/// any of their discs reaches across its plane (a splat's offset from the
/// mean, without its part along the normal, plus its radius), so the
/// representatives cover what their splats cover: no hole opens where the
/// originals leave none. (A fixed √3/2 of the cell's side left pinholes
/// where a cell's splats lie off its centre: 3-6 pixels at 192² on half
/// the lion under a quarter of it, docs/BENCHMARKS.md 2026-12-02.)
fn representatives(cloud: &PointCloud, indices: &[u32], centre: Vec3, half: f32) -> PointCloud {
    let side = 2.0 * half / CELLS as f32;
    let origin = centre - Vec3::splat(half);
    let last = CELLS as i32 - 1;
    let cell_of = |p: Vec3| {
        // Truncation, not floor: the offset is never negative inside the cube.
        let at = |v: f32| ((v / side) as i32).clamp(0, last) as usize;
        let rel = p - origin;
        at(rel.x) + CELLS * (at(rel.y) + CELLS * at(rel.z))
    };
    let mut cells = vec![Cell::default(); CELLS * CELLS * CELLS];
    // Each splat's cell, kept for the second pass (CELLS³ fits a u16).
    let cell_index: Vec<u16> = indices.iter().map(|&i| cell_of(cloud.positions[i as usize]) as u16).collect();
    for (&i, &k) in indices.iter().zip(&cell_index) {
        let i = i as usize;
        let cell = &mut cells[usize::from(k)];
        if cell.count == 0 {
            cell.first_normal = cloud.normals[i];
        }
        cell.count += 1;
        cell.position += cloud.positions[i];
        cell.normal += cloud.normals[i];
        for c in 0..3 {
            cell.colour[c] += cloud.colours[i][c] as u32;
        }
        cell.opacity += cloud.opacity[i];
        cell.two_sided |= cloud.is_two_sided(i);
    }
    let discs: Vec<(Vec3, Vec3)> = cells
        .iter()
        .map(|c| if c.count == 0 { (Vec3::ZERO, Vec3::Z) } else { (c.mean_position(), c.mean_normal()) })
        .collect();
    let mut reach = vec![0.0f32; cells.len()];
    for (&i, &k) in indices.iter().zip(&cell_index) {
        let (i, k) = (i as usize, usize::from(k));
        let (mean, normal) = discs[k];
        let offset = cloud.positions[i] - mean;
        let across = (offset - normal * offset.dot(normal)).length() + cloud.radii[i];
        reach[k] = reach[k].max(across);
    }
    let occupied: Vec<usize> = (0..cells.len()).filter(|&k| cells[k].count > 0).collect();
    let any_two_sided = occupied.iter().any(|&k| cells[k].two_sided);
    let n = |k: usize| cells[k].count as f32;
    PointCloud {
        positions: occupied.iter().map(|&k| discs[k].0).collect(),
        normals: occupied.iter().map(|&k| discs[k].1).collect(),
        radii: occupied.iter().map(|&k| reach[k]).collect(),
        colours: occupied.iter().map(|&k| cells[k].colour.map(|s| (s as f32 / n(k)).round() as u8)).collect(),
        opacity: occupied.iter().map(|&k| cells[k].opacity / n(k)).collect(),
        two_sided: if any_two_sided { occupied.iter().map(|&k| cells[k].two_sided).collect() } else { Vec::new() },
        ..PointCloud::default()
    }
}

/// The tree as arrays, breadth first, so that a node's children are contiguous.
fn flatten(root: Built, cloud: &PointCloud) -> Hierarchy {
    let mut nodes = Vec::new();
    let mut splats = PointCloud {
        origin: cloud.origin,
        scale_exponent: cloud.scale_exponent,
        scanner_position: cloud.scanner_position,
        ..PointCloud::default()
    };
    let two_sided = !cloud.two_sided.is_empty();
    let mut queue = std::collections::VecDeque::from([root]);
    while let Some(built) = queue.pop_front() {
        let first = splats.len() as u32;
        let count = built.own.len() as u32;
        append_range(&mut splats, &built.own, 0..built.own.len(), two_sided);
        // Children are queued in order, so they take the next indices after the queue ahead of them.
        let children = (nodes.len() + 1 + queue.len()) as u32;
        let child_count = built.children.len() as u32;
        nodes.push(Node {
            centre: built.centre,
            half: built.half,
            first,
            count,
            children: if child_count == 0 { 0 } else { children },
            child_count,
            reach: built.reach,
            radius: built.radius,
        });
        queue.extend(built.children);
    }
    Hierarchy { nodes, splats, originals: 0, seconds: 0.0 }
}

/// Appends splats `range` of `from` to `to`; with `two_sided`, their
/// sidedness too (false where `from` keeps none).
fn append_range(to: &mut PointCloud, from: &PointCloud, range: std::ops::Range<usize>, two_sided: bool) {
    to.positions.extend_from_slice(&from.positions[range.clone()]);
    to.normals.extend_from_slice(&from.normals[range.clone()]);
    to.radii.extend_from_slice(&from.radii[range.clone()]);
    to.colours.extend_from_slice(&from.colours[range.clone()]);
    to.opacity.extend_from_slice(&from.opacity[range.clone()]);
    if two_sided {
        if from.two_sided.is_empty() {
            to.two_sided.extend(std::iter::repeat_n(false, range.len()));
        } else {
            to.two_sided.extend_from_slice(&from.two_sided[range]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(n: usize) -> PointCloud {
        crate::scene::primitives::plane(n, 2.0, Vec3::ZERO, Vec3::new(0.3, 1.0, 0.2))
    }

    #[test]
    fn leaves_hold_every_original_splat_once() {
        let cloud = plane(40_000);
        let h = Hierarchy::build(&cloud);
        let leaves: Vec<&Node> = h.nodes.iter().filter(|n| n.is_leaf()).collect();
        let mut seen: Vec<[u32; 3]> = leaves
            .iter()
            .flat_map(|n| {
                (n.first..n.first + n.count).map(|i| h.splats.positions[i as usize].to_array().map(f32::to_bits))
            })
            .collect();
        let mut originals: Vec<[u32; 3]> = cloud.positions.iter().map(|p| p.to_array().map(f32::to_bits)).collect();
        seen.sort_unstable();
        originals.sort_unstable();
        assert_eq!(seen, originals);
        assert!(leaves.iter().all(|n| n.count as usize <= LEAF_SPLATS));
        assert!(h.nodes.len() > 8, "a 40,000-splat plane is split: {} nodes", h.nodes.len());
    }

    #[test]
    fn children_are_contiguous_inside_their_parent_and_coarser_nodes_hold_fewer_larger_splats() {
        let cloud = plane(40_000);
        let h = Hierarchy::build(&cloud);
        for node in h.nodes.iter().filter(|n| !n.is_leaf()) {
            let children = &h.nodes[node.children as usize..(node.children + node.child_count) as usize];
            for child in children {
                assert!((child.half - node.half * 0.5).abs() < 1e-6);
                assert!((child.centre - node.centre).abs().max_element() <= node.half * 0.5 + 1e-5);
            }
            let below: u32 = children.iter().map(|c| c.count).sum();
            assert!(node.count <= below, "a node holds no more splats than its children together");
            assert!(node.radius >= children.iter().filter(|c| !c.is_leaf()).map(|c| c.radius).fold(0.0, f32::max));
        }
        let root = &h.nodes[0];
        assert!(root.count as usize <= CELLS * CELLS * CELLS);
        assert_eq!(h.originals, cloud.len());
    }

    /// Every splat's disc lies within a representative's, measured across
    /// that representative's plane: on a sphere, whose cells' splats sit
    /// off their cells' centres, coarse splats then leave no hole.
    #[test]
    fn each_splats_disc_lies_within_a_representatives() {
        let cloud = crate::scene::primitives::sphere(30_000, 1.0, Vec3::new(0.2, -0.1, 0.3));
        let indices: Vec<u32> = (0..cloud.len() as u32).collect();
        let (centre, half) = bounding_cube(&cloud);
        let reps = representatives(&cloud, &indices, centre, half);
        assert!(reps.len() > 100 && reps.len() < cloud.len(), "{} representatives", reps.len());
        let side = 2.0 * half / CELLS as f32;
        for (p, r) in cloud.positions.iter().zip(&cloud.radii) {
            let covered = reps.positions.iter().zip(&reps.normals).zip(&reps.radii).any(|((m, n), reach)| {
                let offset = *p - *m;
                let along = offset.dot(*n);
                // Its own cell's disc, not one across the sphere.
                along.abs() < side && (offset - *n * along).length() + r <= reach * (1.0 + 1e-5)
            });
            assert!(covered, "the disc at {p} (radius {r}) lies within no representative's");
        }
    }

    #[test]
    fn an_empty_cloud_and_coincident_splats_build() {
        let empty = Hierarchy::build(&PointCloud::default());
        assert_eq!(empty.nodes.len(), 1);
        assert_eq!(empty.splats.len(), 0);
        let mut same = plane(3000);
        same.positions.iter_mut().for_each(|p| *p = Vec3::ONE);
        let h = Hierarchy::build(&same);
        assert!(h.depth() <= MAX_DEPTH);
        assert!(h.splats.positions.iter().all(|p| p.is_finite()));
    }
}
