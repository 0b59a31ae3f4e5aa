//! Weighted graph colouring with a given K (Zhang & Pajarola 2007 §4.2, Eq. 6-8).
//!
//! Edge weights are Eq. 7, w_ij = (A_ij + A_ji)·(1 - n_i·n_j), with A_ij from
//! [`super::area`] (or the plain area sum). The two-step greedy method of §4.2:
//! 1. edges in descending weight; an uncoloured endpoint takes the colour
//!    `MinimizeOverlap` gives it: the colour whose splats overlap it least,
//!    by the plain overlap area ΣA_ij as the paper has it (or, as an option,
//!    by the Eq. 7 weights, which make nearly coplanar overlaps almost free);
//! 2. vertices in a priority queue by their same-colour weight Σw_ij; each
//!    moves to the colour `MinimizeOverlap` gives if that lowers the cost L
//!    (Eq. 6). The moved vertex and all its neighbours (whose colours' costs
//!    it changed) go back into the queue with their new priorities while
//!    these are above the threshold, so the optimisation ends where no
//!    vertex above it can lower L by its MinimizeOverlap colour.
//!
//! Ties go to the smallest group, so zero-weight regions are spread evenly.
//! Every move strictly lowers L, and the number of queue pops is bounded, so
//! the optimisation always ends.

use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::area::overlap_weight;
use super::{Grouping, GroupingError, MAX_GROUPS};
use crate::cloud::PointCloud;
use crate::spatial::overlap::{OverlapGraph, OverlapOptions};

#[derive(Debug, Clone, Copy)]
pub struct WgcOptions {
    pub k: usize,
    /// Weights are the plain overlap area, without Eq. 7's (1 - n_i·n_j).
    pub pure_area: bool,
    /// MinimizeOverlap picks the colour of least Eq. 7 weight instead of the
    /// paper's least overlap area.
    pub minimize_by_eq7: bool,
    pub overlap: OverlapOptions,
    /// A vertex leaves the queue when its same-colour weight is at most this.
    pub threshold: f32,
    /// Record the cost after every move (for tests).
    pub trace: bool,
}

impl Default for WgcOptions {
    fn default() -> Self {
        Self {
            k: 8,
            pure_area: false,
            minimize_by_eq7: false,
            overlap: OverlapOptions::default(),
            threshold: 0.0,
            trace: false,
        }
    }
}

/// What WGC did.
#[derive(Debug, Clone, Default)]
pub struct WgcReport {
    pub initial_cost: f64,
    pub final_cost: f64,
    pub moves: usize,
    /// Cost after every move, when traced.
    pub cost_trace: Vec<f64>,
    pub seconds_weights: f64,
    pub seconds_initialise: f64,
    pub seconds_optimise: f64,
}

/// A non-negative f32 as an order-preserving integer key.
fn key(w: f32) -> u32 {
    w.max(0.0).to_bits()
}

/// Groups `cloud` into `options.k` groups by WGC: edge weights, the greedy
/// initialisation (step 1), then the optimisation (step 2).
pub fn group(cloud: &PointCloud, options: &WgcOptions) -> Result<(Grouping, OverlapGraph, WgcReport), GroupingError> {
    let k = options.k;
    if k == 0 || k > MAX_GROUPS {
        return Err(GroupingError::BadK { k, max: MAX_GROUPS });
    }
    if !(0.0..=1.0).contains(&options.overlap.c) {
        return Err(GroupingError::BadC(options.overlap.c));
    }
    let graph = OverlapGraph::build(cloud.discs(), &options.overlap);
    let mut report = WgcReport::default();

    let started = std::time::Instant::now();
    // w_ij of the cost L and the queue priorities; and the overlap areas
    // MinimizeOverlap compares, unless it compares the same weights.
    let weights = edge_weights(cloud, &graph, options.pure_area);
    let areas = (!options.pure_area && !options.minimize_by_eq7).then(|| edge_weights(cloud, &graph, true));
    let colouring = Colouring { graph: &graph, k, weights: &weights, choice: areas.as_deref().unwrap_or(&weights) };
    report.seconds_weights = started.elapsed().as_secs_f64();

    let started = std::time::Instant::now();
    let mut overlaps = vec![0f64; k];
    let (mut colours, mut sizes) = colouring.initialise(&mut overlaps);
    report.seconds_initialise = started.elapsed().as_secs_f64();

    let started = std::time::Instant::now();
    colouring.optimise(&mut colours, &mut sizes, &mut overlaps, options, &mut report);
    report.seconds_optimise = started.elapsed().as_secs_f64();
    Ok((Grouping::from_labels(&colours, k), graph, report))
}

/// One weight per CSR entry of `graph`: Eq. 7, or the plain overlap area when `pure_area`.
fn edge_weights(cloud: &PointCloud, graph: &OverlapGraph, pure_area: bool) -> Vec<f32> {
    let (p, nrm, r) = (&cloud.positions, &cloud.normals, &cloud.radii);
    (0..graph.len())
        .into_par_iter()
        .flat_map_iter(|i| {
            graph.neighbours_of(i).iter().map(move |&j| {
                overlap_weight(p[i], nrm[i], r[i], p[j as usize], nrm[j as usize], r[j as usize], pure_area)
            })
        })
        .collect()
}

/// What both steps of WGC read: the graph, K, the weights w_ij of the cost,
/// and the weights MinimizeOverlap compares (`choice`, per CSR entry).
struct Colouring<'a> {
    graph: &'a OverlapGraph,
    k: usize,
    weights: &'a [f32],
    choice: &'a [f32],
}

impl Colouring<'_> {
    /// The weight (of `w`) each colour's neighbours put on v (uncoloured ones count for none).
    fn colour_sums(&self, v: usize, colours: &[u32], w: &[f32], costs: &mut [f64]) {
        costs.iter_mut().for_each(|c| *c = 0.0);
        let start = self.graph.offsets[v] as usize;
        for (e, &j) in self.graph.neighbours_of(v).iter().enumerate() {
            let c = colours[j as usize];
            if c != u32::MAX {
                costs[c as usize] += w[start + e] as f64;
            }
        }
    }

    /// Each colour's cost (Eq. 6 weight) on v.
    fn colour_costs(&self, v: usize, colours: &[u32], costs: &mut [f64]) {
        self.colour_sums(v, colours, self.weights, costs)
    }

    /// MinimizeOverlap: the colour of least same-colour overlap, ties to the
    /// smallest group (`overlaps` is scratch space of K entries).
    fn best_colour(&self, v: usize, colours: &[u32], sizes: &[usize], overlaps: &mut [f64]) -> usize {
        self.colour_sums(v, colours, self.choice, overlaps);
        (0..self.k).min_by(|&a, &b| overlaps[a].total_cmp(&overlaps[b]).then(sizes[a].cmp(&sizes[b]))).unwrap_or(0)
    }

    /// Step 1: edges in descending weight colour their uncoloured endpoints
    /// by MinimizeOverlap; splats without edges go to the smallest group.
    /// Returns the colours and the group sizes.
    fn initialise(&self, overlaps: &mut [f64]) -> (Vec<u32>, Vec<usize>) {
        let (graph, k) = (self.graph, self.k);
        let n = graph.len();
        let mut colours = vec![u32::MAX; n];
        let mut sizes = vec![0usize; k];
        let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(graph.edge_count());
        for i in 0..n {
            let start = graph.offsets[i] as usize;
            for (e, &j) in graph.neighbours_of(i).iter().enumerate() {
                if (j as usize) > i {
                    edges.push((key(self.weights[start + e]), i as u32, j));
                }
            }
        }
        edges.par_sort_unstable_by(|a, b| b.0.cmp(&a.0));
        for &(_, i, j) in &edges {
            for v in [i as usize, j as usize] {
                if colours[v] == u32::MAX {
                    let c = self.best_colour(v, &colours, &sizes, overlaps);
                    colours[v] = c as u32;
                    sizes[c] += 1;
                }
            }
        }
        drop(edges);
        // Splats without edges go to the smallest group.
        for colour in colours.iter_mut().filter(|c| **c == u32::MAX) {
            let c = (0..k).min_by_key(|&c| sizes[c]).unwrap_or(0);
            *colour = c as u32;
            sizes[c] += 1;
        }
        (colours, sizes)
    }

    /// Step 2: a max-queue of vertices by same-colour weight; each moves to
    /// its MinimizeOverlap colour where that lowers the cost L.
    fn optimise(
        &self,
        colours: &mut [u32],
        sizes: &mut [usize],
        overlaps: &mut [f64],
        options: &WgcOptions,
        report: &mut WgcReport,
    ) {
        let (graph, weights) = (self.graph, self.weights);
        let n = graph.len();
        let mut costs = vec![0f64; self.k];
        let mut conflict = vec![0f64; n];
        for (v, slot) in conflict.iter_mut().enumerate() {
            self.colour_costs(v, colours, &mut costs);
            *slot = costs[colours[v] as usize];
        }
        let mut cost: f64 = conflict.iter().sum::<f64>() / 2.0;
        report.initial_cost = cost;
        let threshold = options.threshold.max(0.0) as f64;
        let mut queue: BinaryHeap<(u32, u32)> =
            (0..n).filter(|&v| conflict[v] > threshold).map(|v| (key(conflict[v] as f32), v as u32)).collect();
        let max_pops = 50 * n + 1000;
        let mut pops = 0;
        while let Some((priority, v)) = queue.pop() {
            pops += 1;
            if pops > max_pops {
                log::warn!("WGC optimisation stopped after {max_pops} queue pops");
                break;
            }
            let v = v as usize;
            if priority != key(conflict[v] as f32) || conflict[v] <= threshold {
                continue; // stale entry
            }
            let old = colours[v] as usize;
            let best = self.best_colour(v, colours, sizes, overlaps);
            self.colour_costs(v, colours, &mut costs);
            let gain = costs[old] - costs[best];
            if best == old || gain <= 1e-9 * costs[old].max(f64::MIN_POSITIVE) {
                continue;
            }
            colours[v] = best as u32;
            sizes[old] -= 1;
            sizes[best] += 1;
            cost -= gain;
            report.moves += 1;
            if options.trace {
                report.cost_trace.push(cost);
            }
            let start = graph.offsets[v] as usize;
            for (e, &j) in graph.neighbours_of(v).iter().enumerate() {
                let j = j as usize;
                let w = weights[start + e] as f64;
                if colours[j] as usize == old {
                    conflict[j] = (conflict[j] - w).max(0.0);
                } else if colours[j] as usize == best {
                    conflict[j] += w;
                }
                // Back into the queue with its new priority (§4.2 step 2b), not
                // dropped: v's move changed what every neighbour's colours cost.
                if conflict[j] > threshold {
                    queue.push((key(conflict[j] as f32), j as u32));
                }
            }
            conflict[v] = costs[best];
            if conflict[v] > threshold {
                queue.push((key(conflict[v] as f32), v as u32));
            }
        }
        report.final_cost = cost;
    }
}
