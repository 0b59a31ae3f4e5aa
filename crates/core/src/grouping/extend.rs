//! Extended grouping for transparency (Zhang & Pajarola 2007 §4.4.2): making
//! each group cover the whole surface.
//!
//! The surface is sampled at the splat centres (see [`super::metrics`]).
//!
//! (1) Duplication: for each group k, splats of other groups wait in a
//!     priority queue keyed by Clipped(p_i, r, k), the share of disc i's
//!     samples that S_k already covers, processed in descending order as the
//!     paper has it: the most clipped splat that is still under
//!     [`MAX_CLIPPED_SHARE`] first (it fills a small hole with the least new
//!     overlap); as the paper's step 2 does, a splat's key is refreshed when
//!     it is popped and it goes back into the queue if S_k has grown since
//!     (keys only grow), so the order is descending in the keys as last
//!     refreshed; a splat clipped by more than the share is dropped, so the
//!     group ends once its cover is (nearly) complete.
//!     Measured against taking the least clipped first (docs/BENCHMARKS.md,
//!     alg1 at opacity 0.5): the same ε with WGC K = 4, lower with MGC
//!     c = 0.4 (bunny 5.55 against 6.25, merged scans 10.74 against 12.02).
//!
//! (2) Radius enlargement: Eq. 13, with Eq. 11's covered area written as
//!     Covered_k(s) = n·π·(s r)² - Clipped, becomes
//!     s²_{t+1} = s²_t + (A - Covered_k(s_t)) / Σ_{i∈S_k} π r_i²,
//!     where A, the surface area, is Σ π r_i² over all splats divided by the
//!     mean number of splats covering a sample (exact for coincident points
//!     too). s only grows, and the iteration stops when s changes by less than
//!     1e-3, after [`MAX_ITERATIONS`], or at [`MAX_SCALE`], so it ends for any
//!     input. The hash-table approximation of §4.4.2 is
//!     [`super::table::cover_scale`] (√50/4 ≈ 1.77 for K = 8).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::Grouping;
use super::metrics::{coverage_at, nearest_cover};
use crate::cloud::PointCloud;
use crate::spatial::overlap::{OverlapGraph, OverlapOptions};

/// A splat whose disc is already covered beyond this share is not duplicated.
pub const MAX_CLIPPED_SHARE: f32 = 0.5;
/// Radius enlargement never goes beyond this factor.
pub const MAX_SCALE: f32 = 4.0;
pub const MAX_ITERATIONS: usize = 50;

/// How each group's radius enlargement went.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EnlargeReport {
    pub scales: Vec<f32>,
    pub iterations: Vec<usize>,
    /// False where the iteration stopped at a bound instead of converging.
    pub converged: Vec<bool>,
    pub surface_area: f64,
    /// §4.4.2's hash-table estimate for the same K, to compare with.
    pub hash_table_scale: f32,
}

/// (1): duplicates splats into groups until each covers the surface.
pub fn duplicate(cloud: &PointCloud, grouping: &Grouping) -> Grouping {
    let n = cloud.len();
    let k = grouping.k();
    if n == 0 {
        return grouping.clone();
    }
    // Samples on disc i: the splat centres within r_i of p_i (i included),
    // among the overlap graph's neighbours (at most MAX_FOUND_PAIRS a splat
    // in a crowd: see spatial::overlap).
    let graph = OverlapGraph::build(cloud.discs(), &OverlapOptions::default());
    let (p, r) = (&cloud.positions, &cloud.radii);
    let on_disc: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .map(|i| {
            std::iter::once(i as u32)
                .chain(graph.neighbours_of(i).iter().copied().filter(|&j| p[i].distance(p[j as usize]) < r[i]))
                .collect()
        })
        .collect();
    let groups: Vec<Vec<u32>> = (0..k)
        .into_par_iter()
        .map(|g| {
            let mut member = vec![false; n];
            let mut covered = vec![false; n];
            let mut members: Vec<u32> = grouping.group(g).to_vec();
            for &i in &members {
                member[i as usize] = true;
                for &j in &on_disc[i as usize] {
                    covered[j as usize] = true;
                }
            }
            let clipped = |i: usize, covered: &[bool]| -> f32 {
                let samples = &on_disc[i];
                samples.iter().filter(|&&j| covered[j as usize]).count() as f32 / samples.len() as f32
            };
            // Descending by Clipped, as §4.4.2 says (ties: the lower index first).
            let key = |c: f32| (c * 1e6) as u32;
            let mut queue: BinaryHeap<(u32, Reverse<u32>)> =
                (0..n).filter(|&i| !member[i]).map(|i| (key(clipped(i, &covered)), Reverse(i as u32))).collect();
            while let Some((stored, Reverse(i))) = queue.pop() {
                let i = i as usize;
                let now = clipped(i, &covered);
                if now > MAX_CLIPPED_SHARE {
                    continue;
                }
                if key(now) != stored {
                    queue.push((key(now), Reverse(i as u32)));
                    continue;
                }
                member[i] = true;
                members.push(i as u32);
                for &j in &on_disc[i] {
                    covered[j as usize] = true;
                }
            }
            members
        })
        .collect();
    let mut order = Vec::new();
    let mut ranges = Vec::new();
    for members in groups {
        let start = order.len() as u32;
        order.extend(members);
        ranges.push(start..order.len() as u32);
    }
    Grouping { order, ranges, radius_scale: grouping.radius_scale.clone() }
}

/// (2): enlarges each group's radii by Eq. 13 until it covers the surface.
pub fn enlarge(cloud: &PointCloud, grouping: &Grouping) -> (Grouping, EnlargeReport) {
    let k = grouping.k();
    let n = cloud.len();
    let mut out = grouping.clone();
    let mut report = EnlargeReport {
        scales: vec![1.0; k],
        iterations: vec![0; k],
        converged: vec![true; k],
        surface_area: 0.0,
        hash_table_scale: super::table::cover_scale(k),
    };
    if n == 0 {
        return (out, report);
    }
    let disc_area = |i: usize| std::f64::consts::PI * (cloud.radii[i] as f64).powi(2);
    // Surface area: Σ π r² over the mean number of splats covering a sample.
    let multiplicity = covering_counts(cloud);
    let mean_multiplicity = multiplicity.iter().map(|&m| m as f64).sum::<f64>() / n as f64;
    let area = (0..n).map(disc_area).sum::<f64>() / mean_multiplicity.max(1.0);
    report.surface_area = area;
    let nearest = nearest_cover(cloud, grouping, MAX_SCALE);
    for g in 0..k {
        let group_area: f64 = grouping.group(g).iter().map(|&i| disc_area(i as usize)).sum();
        if group_area <= 0.0 {
            report.converged[g] = false;
            continue;
        }
        let mut s = 1.0f64;
        for iteration in 1..=MAX_ITERATIONS {
            let covered = area * coverage_at(&nearest, k, g, s as f32);
            let next = (s * s + (area - covered).max(0.0) / group_area).sqrt().min(MAX_SCALE as f64);
            report.iterations[g] = iteration;
            let change = next - s;
            s = next;
            if change.abs() < 1e-3 {
                break;
            }
            if s >= MAX_SCALE as f64 || iteration == MAX_ITERATIONS {
                report.converged[g] = false;
                break;
            }
        }
        report.scales[g] = s as f32;
    }
    out.radius_scale = report.scales.clone();
    (out, report)
}

/// For every splat centre, how many splats contain it.
fn covering_counts(cloud: &PointCloud) -> Vec<u32> {
    let graph = OverlapGraph::build(cloud.discs(), &OverlapOptions::default());
    let (p, r) = (&cloud.positions, &cloud.radii);
    (0..cloud.len())
        .into_par_iter()
        .map(|j| {
            1 + graph.neighbours_of(j).iter().filter(|&&i| p[j].distance(p[i as usize]) < r[i as usize]).count() as u32
        })
        .collect()
}
