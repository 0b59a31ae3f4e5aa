//! Step 5 of hash regrouping (crates/core/src/grouping/regroup.rs), per
//! leaf: the labels, with Zhang & Pajarola's collision handling (2007 §4.3,
//! steps 1-3). A cell's first splat takes the Fig. 9 table's group; every
//! later one (a collision) takes the group of least overlap (the §6.1
//! overlap factor's weight) with the splats of the 5 × 5 cells around it
//! that is not used in its cell yet (any group, when all are). Leaves are
//! labelled in parallel, each from read-only state ([`LabelContext`]).

use super::MAX_GROUPS;
use super::hash_options::{Collisions, HashOptions};
use crate::cloud::PointCloud;

/// Cells along a leaf's side.
pub(super) const LEAF_CELLS: i32 = 16;
pub(super) const LEAF_AREA: usize = (LEAF_CELLS * LEAF_CELLS) as usize;
/// Cells searched on each side for overlapping splats: two splats of about
/// the median radius r overlap within 2r, two cells.
pub(super) const REACH: i32 = 2;
/// Most splats around a cell an overlap is summed over (see `labels.rs`).
pub(crate) const MAX_AROUND: usize = 256;

/// No leaf beside this one.
pub(super) const NO_LEAF: u32 = u32::MAX;

/// The read-only state step 5 labels a leaf from.
pub(super) struct LabelContext<'a> {
    pub(super) cloud: &'a PointCloud,
    pub(super) options: HashOptions,
    pub(super) leaf_neighbours: &'a [[u32; 9]],
    pub(super) cell_start: &'a [u32],
    pub(super) members: &'a [u32],
    pub(super) discs: &'a [[f32; 4]],
    pub(super) table: &'a [u8],
}

impl LabelContext<'_> {
    /// Labels leaf `l`'s splats in cell order into `out`; returns the collisions resolved.
    pub(super) fn label_leaf(&self, l: usize, out: &mut [u32]) -> usize {
        let k = self.options.k;
        let first = self.cell_start[l * LEAF_AREA] as usize;
        let p = &self.cloud.positions;
        let discs = self.discs;
        let mut resolved = 0;
        let mut overlap = [0f32; MAX_GROUPS];
        // The splats around a cell (places in cell order) and their groups,
        // gathered once per cell that has collisions.
        let mut around = Around::new();
        for local in 0..LEAF_AREA {
            let cell = l * LEAF_AREA + local;
            let (start, end) = (self.cell_start[cell] as usize, self.cell_start[cell + 1] as usize);
            let mut used = 0u64;
            let mut gathered = false;
            for m in start..end {
                let i = self.members[m] as usize;
                let own = self.table[m] as u32;
                let resolve = m > start
                    && match self.options.collisions {
                        Collisions::None => false,
                        Collisions::All => true,
                        Collisions::Near { eye, distance } => p[i].distance(eye) < distance,
                    };
                let label = if !resolve {
                    own
                } else {
                    resolved += 1;
                    if !gathered {
                        gathered = true;
                        self.gather(l, local, out, &mut around);
                        // This cell's splats labelled so far.
                        for j in start..m {
                            around.push(discs[j], out[j - first]);
                        }
                    }
                    around.overlaps(discs[m], &mut overlap[..k]);
                    let all_used = used.count_ones() as usize >= k;
                    (1..=k)
                        .map(|s| (own as usize + s) % k)
                        .filter(|&g| all_used || used & (1u64 << g) == 0)
                        .min_by(|&a, &b| overlap[a].total_cmp(&overlap[b]))
                        .unwrap_or(own as usize) as u32
                };
                used |= 1u64 << label;
                out[m - first] = label;
                if gathered {
                    around.push(discs[m], label);
                }
            }
        }
        resolved
    }

    /// Fills `around` with the splats around cell `local` of leaf `l` (the
    /// 5 × 5 cells but its own): every splat of this leaf's cells labelled
    /// already (in `out`), the first splat of any other cell, which keeps the
    /// table's group.
    fn gather(&self, l: usize, local: usize, out: &[u32], around: &mut Around) {
        let first = self.cell_start[l * LEAF_AREA] as usize;
        let (lx, ly) = ((local as i32) % LEAF_CELLS, (local as i32) / LEAF_CELLS);
        around.clear();
        // All splats of the cells [from, to) of this leaf, labelled already: one run in cell order.
        let labelled_run = |from: usize, to: usize, around: &mut Around| {
            let (s, e) = (self.cell_start[l * LEAF_AREA + from] as usize, self.cell_start[l * LEAF_AREA + to] as usize);
            for j in s..e {
                around.push(self.discs[j], out[j - first]);
            }
        };
        let inside = lx >= REACH && lx + REACH < LEAF_CELLS;
        for dy in -REACH..=REACH {
            let ny = ly + dy;
            let row = (ny * LEAF_CELLS) as usize;
            let (lo, hi) = ((lx - REACH) as usize, (lx + REACH) as usize);
            let dx_range = if inside && ny >= 0 && dy < 0 {
                // A row before this one, within the leaf: labelled.
                labelled_run(row + lo, row + hi + 1, around);
                continue;
            } else if inside && dy == 0 {
                // This row: the cells before this one are labelled.
                labelled_run(row + lo, row + lx as usize, around);
                1..=REACH
            } else {
                -REACH..=REACH
            };
            for dx in dx_range {
                if dx == 0 && dy == 0 {
                    continue;
                }
                let nx = lx + dx;
                let (a, b) = (nx.div_euclid(LEAF_CELLS), ny.div_euclid(LEAF_CELLS));
                let leaf = self.leaf_neighbours[l][((b + 1) * 3 + (a + 1)) as usize];
                if leaf == NO_LEAF {
                    continue;
                }
                let near_local = (ny.rem_euclid(LEAF_CELLS) * LEAF_CELLS + nx.rem_euclid(LEAF_CELLS)) as usize;
                if leaf as usize == l && near_local < local {
                    labelled_run(near_local, near_local + 1, around);
                    continue;
                }
                let near = leaf as usize * LEAF_AREA + near_local;
                let s = self.cell_start[near] as usize;
                if s < self.cell_start[near + 1] as usize {
                    // Not labelled yet: its first splat, which keeps the table's group.
                    around.push(self.discs[s], self.table[s] as u32);
                }
            }
        }
    }
}

/// The splats around a cell with their groups, as columns, so that the
/// overlaps of a splat with all of them are computed four or eight at a time;
/// at most [`MAX_AROUND`] (a crowd of coincident splats is cut there, so it
/// costs O(n), not O(n²)).
struct Around {
    x: [f32; MAX_AROUND],
    y: [f32; MAX_AROUND],
    z: [f32; MAX_AROUND],
    r: [f32; MAX_AROUND],
    label: [u32; MAX_AROUND],
    weight: [f32; MAX_AROUND],
    count: usize,
}

impl Around {
    fn new() -> Box<Self> {
        Box::new(Self {
            x: [0.0; MAX_AROUND],
            y: [0.0; MAX_AROUND],
            z: [0.0; MAX_AROUND],
            r: [0.0; MAX_AROUND],
            label: [0; MAX_AROUND],
            weight: [0.0; MAX_AROUND],
            count: 0,
        })
    }

    fn clear(&mut self) {
        self.count = 0;
    }

    fn push(&mut self, [x, y, z, r]: [f32; 4], label: u32) {
        if self.count < MAX_AROUND {
            let c = self.count;
            (self.x[c], self.y[c], self.z[c], self.r[c], self.label[c]) = (x, y, z, r, label);
            self.count += 1;
        }
    }

    /// The overlap of `disc` with the splats of each group, into `overlap` (one per group).
    fn overlaps(&mut self, [px, py, pz, pr]: [f32; 4], overlap: &mut [f32]) {
        let n = self.count;
        let columns = self.x[..n].iter().zip(&self.y[..n]).zip(&self.z[..n]).zip(&self.r[..n]);
        for (w, (((x, y), z), r)) in self.weight[..n].iter_mut().zip(columns) {
            *w = overlap_weight([px, py, pz, pr], [*x, *y, *z, *r]);
        }
        overlap.fill(0.0);
        for (w, label) in self.weight[..n].iter().zip(&self.label[..n]) {
            overlap[*label as usize] += w;
        }
    }
}

/// The §6.1 overlap factor's weight of two discs, (r_i + r_j - |p_i - p_j|) / ((r_i + r_j) / 2) where positive.
/// Branch-free: half the pairs overlap, and a mispredicted branch costs more than the sum.
#[inline(always)]
pub(crate) fn overlap_weight([px, py, pz, pr]: [f32; 4], [qx, qy, qz, qr]: [f32; 4]) -> f32 {
    let (dx, dy, dz, reach) = (px - qx, py - qy, pz - qz, pr + qr);
    let gap = (reach - (dx * dx + dy * dy + dz * dz).sqrt()).max(0.0);
    2.0 * gap / reach.max(f32::MIN_POSITIVE)
}
