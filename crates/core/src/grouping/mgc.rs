//! Minimal graph colouring with largest-first ordering (Zhang & Pajarola 2007 §4.1).
//!
//! Vertices are coloured in order of non-increasing degree; each takes the
//! smallest colour none of its neighbours has. K is the number of colours used.

use super::{Grouping, GroupingError};
use crate::cloud::PointCloud;
use crate::spatial::overlap::{OverlapGraph, OverlapOptions};

/// Colours `graph` largest first; returns one colour per vertex and K.
pub fn colour(graph: &OverlapGraph) -> (Vec<u32>, usize) {
    let n = graph.len();
    let max_degree = graph.max_degree();
    // Counting sort by degree, largest first.
    let mut by_degree = vec![0u32; max_degree + 2];
    for i in 0..n {
        by_degree[max_degree - graph.degree(i) + 1] += 1;
    }
    for d in 0..=max_degree {
        by_degree[d + 1] += by_degree[d];
    }
    let mut order = vec![0u32; n];
    for i in 0..n {
        let slot = &mut by_degree[max_degree - graph.degree(i)];
        order[*slot as usize] = i as u32;
        *slot += 1;
    }
    let mut colours = vec![u32::MAX; n];
    let mut taken = vec![u32::MAX; max_degree + 2];
    let mut k = 0usize;
    for &v in &order {
        let v = v as usize;
        for &j in graph.neighbours_of(v) {
            let c = colours[j as usize];
            if (c as usize) < taken.len() {
                taken[c as usize] = v as u32;
            }
        }
        let c = (0..taken.len()).find(|&c| taken[c] != v as u32).unwrap_or(taken.len() - 1);
        colours[v] = c as u32;
        k = k.max(c + 1);
    }
    (colours, k.max(1))
}

/// Groups `cloud` by MGC of its overlap graph under `options`.
pub fn group(cloud: &PointCloud, options: &OverlapOptions) -> Result<(Grouping, OverlapGraph), GroupingError> {
    if !(0.0..=1.0).contains(&options.c) {
        return Err(GroupingError::BadC(options.c));
    }
    let graph = OverlapGraph::build(cloud.discs(), options);
    let (colours, k) = colour(&graph);
    Ok((Grouping::from_labels(&colours, k), graph))
}

/// The largest relaxation c (to 1/64) at which MGC needs at most `k` groups.
pub fn c_for_groups(cloud: &PointCloud, k: usize, base: &OverlapOptions) -> f32 {
    let (mut lo, mut hi) = (0.0f32, 1.0f32);
    let fits = |c: f32| colour(&OverlapGraph::build(cloud.discs(), &OverlapOptions { c, ..*base })).1 <= k;
    if fits(1.0) {
        return 1.0;
    }
    for _ in 0..6 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) { lo = mid } else { hi = mid }
    }
    lo
}
