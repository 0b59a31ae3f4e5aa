//! The normals and radii a streamed node's points are drawn with, per
//! frame: a point of a node whose finer nodes are drawn at its position
//! takes the estimate of the deepest of them, made once when that node
//! arrived ([`super::node_estimates::Refined`]: the point estimated with
//! that node's neighbours, at its density). No neighbour is searched here:
//! a walk down the drawn children per point, and a copy. Where the deepest
//! node has no such estimate (the point's node was not loaded when it
//! arrived), the point keeps its normal, and its radius is scaled from its
//! node's density to the deepest's by the ratio of their median radii.
//! Each node's points follow the frame's densest drawn level as a whole
//! file estimated at once would have them (Potree's adaptive point size
//! follows the deepest visible node the same way).

use std::collections::{HashMap, HashSet};

use glam::{DVec3, Vec3};

use super::hierarchy::CopcTree;
use super::node_estimates::{NodeEstimates, child_at};
use crate::cloud::las_file::Columns;

/// The normals and radii `node`'s points (`own`, with the `estimates` it
/// got) are drawn with among the `drawn` nodes, whose estimates `all` holds;
/// `None` when no finer node is drawn at any of them (they are drawn as estimated).
pub(super) fn drawn_estimates(
    tree: &CopcTree,
    (node, own, estimates): (u32, &Columns, &NodeEstimates),
    (drawn, all): (&HashSet<u32>, &HashMap<u32, &NodeEstimates>),
) -> Option<(Vec<Vec3>, Vec<f32>)> {
    let this = &tree.nodes[node as usize];
    if !this.children.iter().any(|c| drawn.contains(c)) {
        return None;
    }
    let deepest: Vec<u32> = (0..own.len())
        .map(|i| {
            let p = DVec3::new(own.x[i], own.y[i], own.z[i]);
            let (mut key, mut deepest) = (this.key, node);
            while let Some(child) = tree.node(&child_at(tree, key, p)).filter(|c| drawn.contains(c)) {
                (key, deepest) = (tree.nodes[child as usize].key, child);
            }
            deepest
        })
        .collect();
    let median = |n: u32| all.get(&n).map(|e| e.median_radius).filter(|m| *m > 0.0);
    let mut normals = estimates.estimates.normals.clone();
    let mut radii = estimates.estimates.radii.clone();
    for (i, &d) in deepest.iter().enumerate().filter(|&(_, &d)| d != node) {
        let ratio = median(d).zip(median(node)).map_or(1.0, |(m, own)| (m / own).min(1.0));
        radii[i] *= ratio;
    }
    let mut finer: Vec<u32> = deepest.iter().copied().filter(|&d| d != node).collect();
    finer.sort_unstable();
    finer.dedup();
    for d in finer {
        let Some(refined) = all.get(&d).and_then(|e| e.refined_for(node)) else { continue };
        for ((&i, &n), &r) in refined.points.iter().zip(&refined.normals).zip(&refined.radii) {
            if deepest.get(i as usize) == Some(&d) {
                (normals[i as usize], radii[i as usize]) = (n, r);
            }
        }
    }
    Some((normals, radii))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::Estimates;
    use crate::copc::header::CopcHeader;
    use crate::copc::node_estimates::Refined;
    use crate::copc::octree::Cube;
    use las::copc::VoxelKey;

    const ROOT: u32 = 0;
    const A: u32 = 1;
    const B: u32 = 2;
    const C: u32 = 3;
    const A_CHILD: u32 = 4;

    /// The cube [-1, 1]³: the root, three of its children (A, B, C) and one of A's (A_CHILD).
    fn tree() -> CopcTree {
        let cube =
            Cube { lo: DVec3::splat(-1.0), hi: DVec3::ONE, centre: DVec3::ZERO, halfsize: 1.0, spacing: 1.0 / 64.0 };
        let vlr = las::Vlr { data: crate::copc::write::info_data(&cube, (0, 0)), ..Default::default() };
        let info = las::copc::CopcInfoVlr::try_from(&vlr).expect("an info VLR");
        let las = las::Header::default();
        let header = CopcHeader {
            las,
            info,
            root_page: (0, 0),
            laz: None,
            fields: Vec::new(),
            warnings: Vec::new(),
            file_len: 0,
        };
        let key = |l, x, y, z| VoxelKey { l, x, y, z };
        let nodes = [(key(0, 0, 0, 0), 4), (key(1, 0, 0, 0), 1), (key(1, 1, 0, 0), 1), (key(1, 0, 1, 0), 1)];
        CopcTree::whole(&header, DVec3::ZERO, nodes.into_iter().chain([(key(2, 0, 0, 0), 1)]))
    }

    /// A node's estimates: every normal +z, every radius `radius`.
    fn estimates(count: usize, radius: f32, median_radius: f32, refined: Vec<Refined>) -> NodeEstimates {
        let estimates = Estimates { normals: vec![Vec3::Z; count], radii: vec![radius; count] };
        NodeEstimates { estimates, median_radius, refined }
    }

    /// A point of the root takes the estimate of the deepest drawn node at
    /// it where that node made one, and otherwise keeps its normal, its
    /// radius scaled by the deepest node's median over its own (never grown).
    #[test]
    fn a_coarse_point_follows_the_deepest_drawn_node_at_it() {
        let tree = tree();
        assert_eq!(tree.node(&VoxelKey { l: 2, x: 0, y: 0, z: 0 }), Some(A_CHILD));
        let mut root = Columns::default();
        // In A and A_CHILD; in B; in C; in the root's octant that has no node.
        (root.x, root.y, root.z) =
            (vec![-0.75, 0.5, -0.5, 0.5], vec![-0.75, -0.5, 0.5, 0.5], vec![-0.75, -0.5, -0.5, 0.5]);
        let root_estimates = estimates(4, 4.0, 4.0, Vec::new());
        let refined = |points: Vec<u32>, normal: Vec3, radius: f32| Refined {
            node: ROOT,
            normals: vec![normal; points.len()],
            radii: vec![radius; points.len()],
            points,
        };
        let a = estimates(1, 2.0, 2.0, vec![refined(vec![0], Vec3::Y, 1.5)]);
        let b = estimates(1, 1.0, 1.0, vec![refined(vec![1], Vec3::X, 0.7)]);
        // C and A_CHILD arrived before the root was loaded: no estimate of its points.
        let c = estimates(1, 8.0, 8.0, Vec::new());
        let a_child = estimates(1, 1.0, 1.0, Vec::new());
        let all: HashMap<u32, &NodeEstimates> =
            HashMap::from([(ROOT, &root_estimates), (A, &a), (B, &b), (C, &c), (A_CHILD, &a_child)]);
        let drawn = |nodes: &[u32]| nodes.iter().copied().collect::<HashSet<u32>>();
        let of = |nodes: &[u32]| drawn_estimates(&tree, (ROOT, &root, &root_estimates), (&drawn(nodes), &all));

        assert_eq!(of(&[ROOT]), None, "no finer node drawn: drawn as estimated");
        let (normals, radii) = of(&[ROOT, A, B, C, A_CHILD]).expect("finer nodes drawn");
        assert_eq!(normals, [Vec3::Z, Vec3::X, Vec3::Z, Vec3::Z]);
        // A_CHILD, not A: its median over the root's; B's estimate; C's
        // median is larger, so the radius stays; no node at the last point.
        assert_eq!(radii, [1.0, 0.7, 4.0, 4.0]);
        let (normals, radii) = of(&[ROOT, A]).expect("A drawn");
        assert_eq!((normals[0], radii[0]), (Vec3::Y, 1.5), "A is the deepest drawn at the first point");
        assert_eq!(radii[1..], [4.0, 4.0, 4.0]);
    }
}
