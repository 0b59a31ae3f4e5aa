//! Each streamed node's groups for the grouped modes (Zhang & Pajarola 2007
//! §4.3's hash grouping, Eq. 9 and Fig. 9, with its collision handling),
//! labelled once, when the node is first drawn in such a mode, and kept
//! beside its points in the node cache: a pan labels only the nodes it
//! adds, and no label changes when a neighbour arrives.
//!
//! A point's first choice comes from its position alone, on a lattice fixed
//! for the whole file, one per level: level l's cells are the octree's cube
//! divided 2^(l + m) times along each axis, m fixed once from the root
//! node's median radius so that a cell is about one radius (the hash
//! grouping's cell, [`crate::grouping::regroup::Lattice`]). Two nodes of one
//! level thus share one lattice, and Fig. 9's table keeps same-group cells
//! apart across their border as inside a node. A leaf of 16 × 16 × 16
//! cells takes the dominant axis of the node's own normals in it (the
//! paper averages over a BSP leaf); where m ≥ 4, as on dense scans, a leaf
//! never straddles two nodes, so the axis is the leaf's whole.
//!
//! Collisions: a point whose table group is already held by a splat it
//! overlaps takes the group of least overlap (the §6.1 overlap factor)
//! among the splats around it, as the whole-selection regrouping does. The
//! splats around it are the node's points labelled before it and the halo:
//! the labelled points near the node of the loaded nodes at its level and
//! the coarser ones (its ancestors and their neighbours are always drawn
//! with it, since a selection is additive), with their radii scaled to
//! this level's as a frame draws them. Their labels were fixed when they
//! arrived and never change: a node resolves its collisions against the
//! neighbours already there, and a neighbour that arrives later resolves
//! its own against it. A level's new nodes are labelled in eight waves by
//! the parity of their coordinates, so that two neighbours are never
//! labelled at once (and the labels do not depend on the threads). So a
//! coarse splat and a finer one drawn at one place, or two splats on
//! either side of a border, do not share a group where they overlap,
//! unless every group is taken there. (The whole-selection regrouper,
//! `grouping/regroup.rs`, labels every splat it is given; here the halo's
//! labels are fixed, so the labelling is a loop of its own, with the
//! regrouper's table, axis and overlap weight.)

use std::sync::Arc;

use glam::{DVec3, IVec3, Vec3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::cache::NodeCache;
use super::hierarchy::CopcTree;
use super::node_estimates::{NodeEstimates, grown_cube, halo_nodes};
use crate::cloud::las_file::Columns;
use crate::grouping::Grouping;
use crate::grouping::MAX_GROUPS;
use crate::grouping::hash::{Collisions, HashOptions};
use crate::grouping::labels::{MAX_AROUND, overlap_weight};
use crate::grouping::regroup::{across, dominant_axis};
use crate::grouping::table::Table;

/// Cells per leaf along an axis, as a power of two.
const LEAF_DEPTH: u32 = 4;
/// Finest division of a node's cube into cells, as a power of two (far past any node's point count).
const MAX_DEPTH: u32 = 16;
/// Most grid cells searched on each side of a point for splats it overlaps.
const MAX_REACH: i32 = 3;

/// How many times each level's cube is halved into cells: the power of two
/// that makes the root's cells its median radius (a leaf's worth when the
/// root has no radius).
pub(super) fn lattice_depth(root_side: f64, root_median_radius: f32) -> u32 {
    let measured = root_median_radius > 0.0 && root_side > 0.0;
    if !measured {
        return LEAF_DEPTH;
    }
    let depth = (root_side / f64::from(root_median_radius)).log2().round();
    (depth.max(0.0) as u32).min(MAX_DEPTH)
}

/// A labelled node near the one labelled: its points, what they were given, and their groups.
pub(super) struct LabelledNode<'a> {
    pub node: u32,
    pub level: i32,
    pub columns: &'a Columns,
    pub estimates: &'a NodeEstimates,
    pub labels: &'a [u8],
}

/// Splats already labelled, on a uniform grid: position (relative to the
/// node's centre), radius as drawn at the node's level, and group.
struct Placed {
    cell: f32,
    grid: FxHashMap<IVec3, Vec<(Vec3, f32, u8)>>,
}

impl Placed {
    fn key(&self, p: Vec3) -> IVec3 {
        (p / self.cell).floor().as_ivec3()
    }

    fn add(&mut self, p: Vec3, r: f32, g: u8) {
        if p.is_finite() && r.is_finite() {
            self.grid.entry(self.key(p)).or_default().push((p, r, g));
        }
    }

    /// Per group, the summed overlap factor of the splats placed that
    /// overlap (p, r): the regrouping's own weight, over at most
    /// [`MAX_AROUND`] splats (a crowd of coincident points costs O(n), not O(n²)).
    fn overlap(&self, p: Vec3, r: f32, k: usize) -> [f32; MAX_GROUPS] {
        let mut by_group = [0f32; MAX_GROUPS];
        if !p.is_finite() || r.is_nan() || r <= 0.0 {
            return by_group;
        }
        let reach = ((2.0 * r / self.cell).ceil() as i32).clamp(1, MAX_REACH);
        let centre = self.key(p);
        let mut seen = 0;
        for dx in -reach..=reach {
            for dy in -reach..=reach {
                for dz in -reach..=reach {
                    let Some(placed) = self.grid.get(&(centre + IVec3::new(dx, dy, dz))) else { continue };
                    for &(q, rq, g) in placed.iter().take(MAX_AROUND - seen) {
                        if usize::from(g) < k {
                            by_group[usize::from(g)] += overlap_weight([p.x, p.y, p.z, r], [q.x, q.y, q.z, rq]);
                        }
                    }
                    seen = (seen + placed.len()).min(MAX_AROUND);
                    if seen == MAX_AROUND {
                        return by_group;
                    }
                }
            }
        }
        by_group
    }
}

/// The group of each of `node`'s points (`own`, as decoded, with its
/// `estimates`), on its level's lattice ([`lattice_depth`] `depth`), with
/// collisions resolved against its earlier points and the labelled `halo`.
pub(super) fn label(
    tree: &CopcTree,
    node: u32,
    (own, estimates): (&Columns, &NodeEstimates),
    halo: &[LabelledNode],
    depth: u32,
    options: HashOptions,
) -> Vec<u8> {
    let (min, side) = tree.cube(&tree.nodes[node as usize].key);
    let centre = min + DVec3::splat(side * 0.5);
    // Relative to the node's centre, as its estimates were made; the cube's
    // corner is a whole number of cells from it, so the lattice is the level's.
    let local = |c: &Columns, i: usize| (DVec3::new(c.x[i], c.y[i], c.z[i]) - centre).as_vec3();
    let cell = (side / f64::from(1u32 << depth)) as f32;
    let corner = Vec3::splat(-(side * 0.5) as f32);
    let coords: Vec<IVec3> = (0..own.len()).map(|i| ((local(own, i) - corner) / cell).floor().as_ivec3()).collect();
    let (normals, radii) = (&estimates.estimates.normals, &estimates.estimates.radii);
    let mut leaves: FxHashMap<IVec3, Vec3> = FxHashMap::default();
    for (c, n) in coords.iter().zip(normals) {
        *leaves.entry(*c >> LEAF_DEPTH as i32).or_default() += if n.is_finite() { *n } else { Vec3::ZERO };
    }
    let axis: FxHashMap<IVec3, u8> = leaves.into_iter().map(|(leaf, n)| (leaf, dominant_axis(n))).collect();
    let table = Table::new(options.k);
    let first_choice = |i: usize| table.at(across(coords[i], axis[&(coords[i] >> LEAF_DEPTH as i32)])) as u8;
    if options.collisions == Collisions::None {
        return (0..own.len()).map(first_choice).collect();
    }
    let mut placed = Placed { cell: 2.0 * estimates.median_radius.max(cell), grid: FxHashMap::default() };
    let (lo, hi) = grown_cube(tree, node);
    let level = tree.nodes[node as usize].key.l;
    for near in halo {
        // A coarser node's radii as drawn where this level is the deepest
        // (`super::drawn_estimates`): this node's estimate of its points in
        // this node's cube, and elsewhere its own scaled to this level's density.
        let scale = if near.level < level { estimates.median_radius / near.estimates.median_radius } else { 1.0 };
        let scale = if scale.is_finite() && scale > 0.0 { scale.min(1.0) } else { 1.0 };
        let c = near.columns;
        // This node's estimates of the near node's points, in index order.
        let mut refined = estimates.refined_for(near.node).map(|r| r.points.iter().zip(&r.radii).peekable());
        for (i, &own_radius) in near.estimates.estimates.radii.iter().enumerate().take(c.len()) {
            let mine = refined.as_mut().and_then(|r| r.next_if(|(at, _)| **at as usize == i)).map(|(_, &r)| r);
            let p = DVec3::new(c.x[i], c.y[i], c.z[i]);
            if p.cmpge(lo).all() && p.cmple(hi).all() {
                placed.add(local(c, i), mine.unwrap_or(own_radius * scale), near.labels[i]);
            }
        }
    }
    let mut labels = Vec::with_capacity(own.len());
    for (i, &r) in radii.iter().enumerate().take(own.len()) {
        let (p, wanted) = (local(own, i), first_choice(i));
        let overlap = placed.overlap(p, r, options.k);
        let group = if overlap[usize::from(wanted)] == 0.0 {
            wanted
        } else {
            // The least overlapped group, the table's first among equals.
            (0..options.k)
                .map(|step| ((usize::from(wanted) + step) % options.k) as u8)
                .min_by(|a, b| overlap[usize::from(*a)].total_cmp(&overlap[usize::from(*b)]))
                .unwrap_or(wanted)
        };
        placed.add(p, r, group);
        labels.push(group);
    }
    labels
}

/// The grouping of `splats` splats whose record r has group `per_record[r]`
/// and became splat `splat_of[r]` (copies merged: the first record's group).
pub(super) fn groups_of_splats(per_record: &[u8], splat_of: &[u32], splats: usize, k: usize) -> Grouping {
    let mut labels = vec![u32::MAX; splats];
    for (&group, &splat) in per_record.iter().zip(splat_of) {
        if let Some(label) = labels.get_mut(splat as usize).filter(|l| **l == u32::MAX) {
            *label = u32::from(group);
        }
    }
    Grouping::from_labels(&labels, k)
}

/// Labels the `drawn` nodes that have no groups of hash grouping `options`
/// yet, on the levels' lattices ([`lattice_depth`] `depth`), and keeps them
/// in `cache`; returns the points labelled. Coarse first, and a level in
/// eight waves by the parity of its coordinates, so that no two neighbours
/// are labelled at once: a node's halo is the labelled nodes around it, at
/// its level and above. Nodes of one wave are labelled in parallel.
pub(super) fn label_new(
    cache: &mut NodeCache,
    tree: &CopcTree,
    drawn: &[u32],
    (depth, options): (u32, HashOptions),
) -> u64 {
    let mut new: Vec<u32> = drawn.iter().copied().filter(|&n| cache.labels(n, options).is_none()).collect();
    let wave = |n: &u32| {
        let k = tree.nodes[*n as usize].key;
        (k.l, (k.x & 1) | (k.y & 1) << 1 | (k.z & 1) << 2)
    };
    new.sort_by_key(wave);
    let mut labelled = 0;
    for nodes in new.chunk_by(|a, b| wave(a) == wave(b)) {
        let shared = &*cache;
        let made: Vec<(u32, Vec<u8>)> = nodes
            .par_iter()
            .filter_map(|&n| {
                let (own, estimates) = (shared.peek(n)?, shared.estimates(n)?);
                let around = halo_nodes(tree, n, &|m| shared.contains(m));
                let kept: Vec<_> = around
                    .into_iter()
                    .filter_map(|m| {
                        let level = tree.nodes[m as usize].key.l;
                        Some((m, level, shared.peek(m)?, shared.estimates(m)?, shared.labels(m, options)?))
                    })
                    .collect();
                let halo: Vec<LabelledNode> = kept
                    .iter()
                    .map(|(node, level, columns, estimates, labels)| LabelledNode {
                        node: *node,
                        level: *level,
                        columns,
                        estimates,
                        labels,
                    })
                    .collect();
                Some((n, label(tree, n, (own, &estimates), &halo, depth, options)))
            })
            .collect();
        for (n, labels) in made {
            labelled += labels.len() as u64;
            cache.set_labels(n, (options, Arc::new(labels)));
        }
    }
    labelled
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The root's cells (its side over 2^depth) are its median radius
    /// within a factor √2, wherever the bounds do not hold the depth; a
    /// root with no radius gets a leaf's worth.
    #[test]
    fn a_cell_is_the_roots_median_radius_within_a_factor_of_root_two() {
        use std::f64::consts::{FRAC_1_SQRT_2, SQRT_2};
        for (side, median) in [(1024.0, 1.0f32), (1024.0, 1.3), (1024.0, 1.6), (4635.7, 600.0), (40.76, 0.05)] {
            let depth = lattice_depth(side, median);
            let ratio = side / f64::from(1u32 << depth) / f64::from(median);
            assert!((FRAC_1_SQRT_2..=SQRT_2).contains(&ratio), "side {side}, median {median}: depth {depth}");
        }
        assert_eq!(lattice_depth(1024.0, 5000.0), 0, "a root smaller than its radius is one cell");
        assert_eq!(lattice_depth(1e9, 1e-6), MAX_DEPTH, "bounded");
        for none in [0.0, -1.0, f32::NAN] {
            assert_eq!(lattice_depth(1024.0, none), LEAF_DEPTH);
        }
    }
}
