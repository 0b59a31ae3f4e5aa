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
