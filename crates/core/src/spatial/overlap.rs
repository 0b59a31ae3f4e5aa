//! The overlap graph of Zhang & Pajarola 2007 §4.1 (Eq. 5) in CSR form.
//!
//! An edge joins splats i and j when |p_i - p_j| < c·(r_i + r_j), with the
//! relaxations of §4.1: (1) drop nearly coplanar pairs of the same colour,
//! (2) drop pairs with n_i·n_j < 0, (3) the factor c in [0, 1]. Each pair is
//! found once, by its larger-radius endpoint, which searches only 2c·r around
//! itself in a [`HashGrid`]; the queries run in parallel with rayon, and the
//! pairs are then made symmetric in compressed sparse rows.
//!
//! Memory is bounded by the number of splats, not of overlapping pairs: a
//! splat keeps at most [`MAX_FOUND_PAIRS`] of the pairs it finds, and scans at
//! most [`MAX_SCANNED`] candidates. On the real scans no splat comes near
//! either cap (the largest degree is 52); where thousands of splats crowd one
//! spot, the graph keeps a bounded part of their overlaps, the grouping puts
//! some overlapping splats together, and a counted warning says so.

use glam::Vec3;
use rayon::prelude::*;

use super::grid::{HashGrid, typical_radius};

/// The splats a graph is built over: one entry per splat in each slice (a
/// point cloud's own arrays).
#[derive(Debug, Clone, Copy)]
pub struct Discs<'a> {
    pub positions: &'a [Vec3],
    /// Unit normals.
    pub normals: &'a [Vec3],
    pub radii: &'a [f32],
    /// sRGB colours, 0-255 (relaxation (1) compares them).
    pub colours: &'a [[u8; 3]],
}

/// Which pairs of overlapping splats become edges.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OverlapOptions {
    /// Relaxation (3): edges need |p_i - p_j| < c·(r_i + r_j).
    pub c: f32,
    /// Relaxation (2): skip pairs whose normals point into opposite directions.
    pub skip_opposite_normals: bool,
    /// Relaxation (1): skip nearly coplanar pairs of (nearly) the same colour.
    pub skip_coplanar_same_colour: bool,
}

impl Default for OverlapOptions {
    fn default() -> Self {
        Self { c: 1.0, skip_opposite_normals: false, skip_coplanar_same_colour: false }
    }
}

/// Relaxation (1): normals within ~8° and each centre within 5% of the
/// radius of the other's tangent plane, colours within 8/255 per channel.
const COPLANAR_COS: f32 = 0.99;
const COPLANAR_OFFSET: f32 = 0.05;
const SAME_COLOUR: u8 = 8;

/// Pairs one splat records, at most (see the module's doc).
pub const MAX_FOUND_PAIRS: usize = 64;
/// Candidates one splat's query scans, at most.
pub const MAX_SCANNED: usize = 4096;

/// An undirected graph over splats, as compressed sparse rows.
#[derive(Debug, Clone, Default)]
pub struct OverlapGraph {
    /// `offsets[i]..offsets[i + 1]` indexes `neighbours` for splat i.
    pub offsets: Vec<u32>,
    pub neighbours: Vec<u32>,
    /// Splats whose search stopped at a cap: they may overlap more splats than the graph says.
    pub crowded: usize,
}

impl OverlapGraph {
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn neighbours_of(&self, i: usize) -> &[u32] {
        &self.neighbours[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    pub fn degree(&self, i: usize) -> usize {
        (self.offsets[i + 1] - self.offsets[i]) as usize
    }

    pub fn edge_count(&self) -> usize {
        self.neighbours.len() / 2
    }

    pub fn max_degree(&self) -> usize {
        (0..self.len()).map(|i| self.degree(i)).max().unwrap_or(0)
    }

    pub fn average_degree(&self) -> f64 {
        if self.is_empty() { 0.0 } else { self.neighbours.len() as f64 / self.len() as f64 }
    }

    /// Builds the graph of `discs` under `options`.
    pub fn build(discs: Discs<'_>, options: &OverlapOptions) -> Self {
        let n = discs.positions.len();
        let c = options.c.clamp(0.0, 1.0);
        if n == 0 {
            return Self { offsets: vec![0], neighbours: Vec::new(), crowded: 0 };
        }
        let (positions, normals, radii) = (discs.positions, discs.normals, discs.radii);
        let typical = typical_radius(radii);
        // Cells of the typical search diameter: most queries scan 3x3x3 cells.
        let grid = HashGrid::new(positions, (2.0 * c * typical).max(typical * 1e-3).max(f32::MIN_POSITIVE));
        let accept = |i: usize, j: usize| -> bool {
            let d = positions[i].distance(positions[j]);
            if d >= c * (radii[i] + radii[j]) || d.is_nan() {
                return false;
            }
            let dot = normals[i].dot(normals[j]);
            if options.skip_opposite_normals && dot < 0.0 {
                return false;
            }
            if options.skip_coplanar_same_colour && dot > COPLANAR_COS {
                let offset_i = normals[i].dot(positions[j] - positions[i]).abs();
                let offset_j = normals[j].dot(positions[i] - positions[j]).abs();
                let same_colour = (0..3).all(|k| discs.colours[i][k].abs_diff(discs.colours[j][k]) <= SAME_COLOUR);
                if same_colour && offset_i < COPLANAR_OFFSET * radii[i] && offset_j < COPLANAR_OFFSET * radii[j] {
                    return false;
                }
            }
            true
        };
        // Each pair once: the endpoint with the larger radius (ties: smaller index) finds it.
        let owns = |i: usize, j: usize| radii[j] < radii[i] || (radii[j] == radii[i] && j > i);
        // The pairs splat i owns, scanned from entry `start` of each bucket:
        // whether it saw every candidate and every pair (else it is crowded).
        let scan = |i: usize, start: usize, out: &mut Vec<(u32, u32)>| -> bool {
            let reach = (2.0 * c * radii[i] / grid.cell_size()).ceil() as i32;
            let mut kept = 0;
            let mut full = false;
            let whole = grid.scan_near(positions[i], reach, MAX_SCANNED, start, |j| {
                let j = j as usize;
                if j != i && owns(i, j) && accept(i, j) {
                    if kept == MAX_FOUND_PAIRS {
                        full = true;
                        return false;
                    }
                    out.push((i as u32, j as u32));
                    kept += 1;
                }
                true
            });
            whole && !full
        };
        let found: Vec<(Vec<(u32, u32)>, usize)> = (0..n)
            .into_par_iter()
            .chunks(4096)
            .map(|chunk| {
                let (mut out, mut crowded) = (Vec::new(), 0);
                for i in chunk {
                    let mark = out.len();
                    if scan(i, 0, &mut out) {
                        continue;
                    }
                    crowded += 1;
                    // A crowd: scan again from this splat's own place in the
                    // buckets (their entries are in index order), so that its
                    // window holds the splats it owns (higher indices) rather
                    // than the same first candidates every member of the crowd sees.
                    out.truncate(mark);
                    scan(i, i, &mut out);
                }
                (out, crowded)
            })
            .collect();
        let crowded = found.iter().map(|f| f.1).sum();
        if crowded > 0 {
            crate::progress::warn_once(format!(
                "{crowded} of {n} splats overlap too many others to list (coincident or crowded splats): the grouping \
                 sees at most {MAX_FOUND_PAIRS} overlaps of each, so some overlapping splats may share a group"
            ));
        }
        Self { crowded, ..Self::from_pairs(n, found.iter().flat_map(|f| f.0.iter().copied())) }
    }

    /// Builds the symmetric CSR form from undirected pairs (each given once).
    pub fn from_pairs(n: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Self {
        let mut offsets = vec![0u32; n + 1];
        for (a, b) in pairs.clone() {
            offsets[a as usize + 1] += 1;
            offsets[b as usize + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut neighbours = vec![0u32; offsets[n] as usize];
        for (a, b) in pairs {
            neighbours[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            neighbours[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        Self { offsets, neighbours, crowded: 0 }
    }
}

/// Median of the radii (1 when there are none).
pub fn median_radius(radii: &[f32]) -> f32 {
    let mut r: Vec<f32> = radii.iter().copied().filter(|r| r.is_finite() && *r > 0.0).collect();
    if r.is_empty() {
        return 1.0;
    }
    let mid = r.len() / 2;
    *r.select_nth_unstable_by(mid, f32::total_cmp).1
}
