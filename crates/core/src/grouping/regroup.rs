//! Hash grouping fast enough for every frame of a deforming model
//! (Zhang & Pajarola 2007 §4.3, Eq. 9 and Fig. 9, with the collision
//! handling of its steps 1-3), deterministic and incremental.
//!
//! The splats live on a lattice of cubes whose side is the median radius r
//! (fixed by the rest pose, [`Lattice`], so the cells do not jump when a
//! deformation stretches the radii). Cubes of 16³ cells form *leaves*; a
//! leaf's mean normal picks its dominant axis d (the paper's BSP leaf
//! average), and a splat's Eq. 9 cell is its cell coordinates across d: a
//! leaf holds at most 16 × 16 of them, so every leaf owns a dense block of
//! 256 cells and neighbouring cells are found by arithmetic, not by search.
//!
//! One frame:
//! 1. lattice coordinates of every splat (parallel);
//! 2. leaves by a hash map of their coordinates, ids in order of first
//!    appearance, normals summed (one pass; a scan's consecutive splats
//!    mostly share a leaf, so most splats skip the map);
//! 3. per leaf: d, and the 8 leaves beside it across d that share d;
//! 4. a counting sort of the splats by cell, stable, so each cell lists its
//!    splats by index: by leaf in one pass, then by cell within each leaf,
//!    leaves in parallel;
//! 5. labels, in parallel over leaves and in order within one. The cell's
//!    first splat takes `table[x % K][y % K]` (Fig. 9); every later one
//!    (a collision) takes the group of least overlap (the §6.1 overlap
//!    factor's weight) with the splats of the 5 × 5 cells around it that
//!    is not used in its cell yet (any group, when all are). It counts every
//!    splat of the cells of its leaf labelled before it and the first splat
//!    of the other cells (whose group is the table's). Step 5 is
//!    `labels.rs`.
//!
//! Collisions are thus resolved by a fixed rule (the splat index orders a
//! cell) with no nearest-neighbour query, and the result does not depend on
//! the number of threads. A splat's group depends only on the splats of its
//! leaf and of the 8 leaves beside it, so after a local deformation only the
//! leaves within one leaf of a changed splat (before or after it moved) are
//! labelled again, and the result is exactly a full regroup's (tested).
//! Buffers are kept between frames: a frame allocates nothing per splat but
//! the grouping it returns (a few small lists per leaf).

use glam::{IVec3, Vec3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

pub use super::hash_options::{Collisions, HashOptions};
use super::labels::{LEAF_AREA, LEAF_CELLS, LabelContext, NO_LEAF};
use super::table::Table;
use super::{Grouping, GroupingError, MAX_GROUPS};
use crate::cloud::PointCloud;
use crate::spatial::overlap::median_radius;

/// The lattice the cells are counted on: cell side and origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    pub cell: f32,
    pub origin: Vec3,
}

impl Lattice {
    /// The median radius of `cloud` and its lowest corner.
    pub fn of(cloud: &PointCloud) -> Self {
        let cell = median_radius(&cloud.radii);
        let min = cloud.positions.iter().filter(|p| p.is_finite()).fold(Vec3::splat(f32::INFINITY), |a, p| a.min(*p));
        Self { cell, origin: if min.is_finite() { min } else { Vec3::ZERO } }
    }

    /// Integer cell coordinates of `p` (far or non-finite points are clamped, never a panic).
    fn coords(&self, p: Vec3) -> IVec3 {
        let q = (p - self.origin) / self.cell;
        // Not-a-number to 0, then clamped, so the casts below are exact.
        let q = Vec3::select(q.cmpeq(q), q, Vec3::ZERO).clamp(Vec3::splat(-1e9), Vec3::splat(1e9));
        // Floor by truncation: `f32::floor` is a libm call on baseline x86-64 (no SSE4.1).
        let t = q.as_ivec3();
        t - IVec3::from(t.as_vec3().cmpgt(q))
    }
}

/// What one regroup did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RegroupStats {
    /// Collisions resolved (in the leaves labelled this time).
    pub resolved: usize,
    /// Splats whose group was computed this time (all of them, unless incremental).
    pub labelled: usize,
    /// Splats that moved (or changed normal or radius) since the last frame.
    pub changed: usize,
    pub leaves: usize,
    pub incremental: bool,
}

/// The state of the last frame, for incremental regrouping.
#[derive(Default)]
struct Previous {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    radii: Vec<f32>,
    leaf_coord: Vec<IVec3>,
}

/// Hash grouping with its buffers, reused frame after frame.
pub struct HashRegrouper {
    lattice: Lattice,
    options: HashOptions,
    coords: Vec<IVec3>,
    leaf_of: Vec<u32>,
    cell_of: Vec<u32>,
    labels: Vec<u32>,
    leaves: FxHashMap<IVec3, u32>,
    leaf_coord: Vec<IVec3>,
    leaf_normal: Vec<Vec3>,
    leaf_axis: Vec<u8>,
    /// The leaves beside each one across its axis, [(b + 1) · 3 + (a + 1)] for offsets a, b in -1..=1.
    leaf_neighbours: Vec<[u32; 9]>,
    leaf_affected: Vec<bool>,
    cell_start: Vec<u32>,
    /// Where each leaf's splats start in cell order.
    leaf_start: Vec<u32>,
    /// The splats leaf by leaf, each leaf's in index order.
    by_leaf: Vec<u32>,
    members: Vec<u32>,
    sorted_labels: Vec<u32>,
    /// Position and radius of each splat in cell order (the overlap search reads them in runs).
    sorted_discs: Vec<[f32; 4]>,
    /// The table's group of each splat in cell order.
    sorted_table: Vec<u8>,
    changed: Vec<bool>,
    previous: Option<Previous>,
    /// Whether a frame is kept for the next one (not for a one-off grouping).
    remember_frames: bool,
    stats: RegroupStats,
}

impl HashRegrouper {
    /// A regrouper on `lattice` (see [`Lattice::of`]).
    pub fn new(lattice: Lattice, options: HashOptions) -> Result<Self, GroupingError> {
        if options.k == 0 || options.k > MAX_GROUPS {
            return Err(GroupingError::BadK { k: options.k, max: MAX_GROUPS });
        }
        Ok(Self {
            lattice,
            options,
            coords: Vec::new(),
            leaf_of: Vec::new(),
            cell_of: Vec::new(),
            labels: Vec::new(),
            leaves: FxHashMap::default(),
            leaf_coord: Vec::new(),
            leaf_normal: Vec::new(),
            leaf_axis: Vec::new(),
            leaf_neighbours: Vec::new(),
            leaf_affected: Vec::new(),
            cell_start: Vec::new(),
            leaf_start: Vec::new(),
            by_leaf: Vec::new(),
            members: Vec::new(),
            sorted_labels: Vec::new(),
            sorted_discs: Vec::new(),
            sorted_table: Vec::new(),
            changed: Vec::new(),
            previous: None,
            remember_frames: true,
            stats: RegroupStats::default(),
        })
    }

    pub fn lattice(&self) -> Lattice {
        self.lattice
    }

    pub fn options(&self) -> HashOptions {
        self.options
    }

    /// Changes the collision handling (the next regroup is a full one).
    pub fn set_options(&mut self, options: HashOptions) -> Result<(), GroupingError> {
        if options.k == 0 || options.k > MAX_GROUPS {
            return Err(GroupingError::BadK { k: options.k, max: MAX_GROUPS });
        }
        if options != self.options {
            self.options = options;
            self.previous = None;
        }
        Ok(())
    }

    /// What the last regroup did.
    pub fn stats(&self) -> RegroupStats {
        self.stats
    }

    /// The group of each splat after the last regroup.
    pub fn labels(&self) -> &[u32] {
        &self.labels
    }

    /// The Eq. 9 cell of each splat after the last regroup (cells are
    /// numbered per frame; two splats share a number exactly when they share a cell).
    pub fn cells(&self) -> &[u32] {
        &self.cell_of
    }

    /// Groups `cloud`: incrementally when it has the last frame's splat
    /// count (only leaves near changed splats are labelled again), else from scratch.
    pub fn regroup(&mut self, cloud: &PointCloud) -> Grouping {
        self.regroup_labels(cloud, true);
        Grouping::from_labels(&self.labels, self.options.k)
    }

    /// Groups `cloud` from scratch, whatever the last frame was.
    pub fn regroup_full(&mut self, cloud: &PointCloud) -> Grouping {
        self.regroup_labels(cloud, false);
        Grouping::from_labels(&self.labels, self.options.k)
    }

    /// Groups `cloud` once: from scratch, and nothing is kept for a next frame.
    pub fn group_once(mut self, cloud: &PointCloud) -> (Grouping, RegroupStats) {
        self.remember_frames = false;
        self.regroup_labels(cloud, false);
        (Grouping::from_labels(&self.labels, self.options.k), self.stats)
    }

    /// The labels of `cloud` (see [`Self::regroup`]).
    pub fn regroup_labels(&mut self, cloud: &PointCloud, incremental: bool) -> &[u32] {
        let n = cloud.len();
        let previous = self.previous.take().filter(|p| incremental && p.positions.len() == n && n == self.labels.len());
        let changed = previous.as_ref().map(|p| self.mark_changed(cloud, p));
        if changed == Some(0) {
            self.stats = RegroupStats { incremental: true, leaves: self.leaf_coord.len(), ..Default::default() };
            self.previous = previous;
            return &self.labels;
        }
        if self.options.collisions == Collisions::None {
            // Every splat keeps its table group: no cells, no neighbours.
            self.find_leaves(cloud);
            self.label_by_table();
            self.stats = RegroupStats { labelled: n, changed: n, leaves: self.leaf_coord.len(), ..Default::default() };
            self.previous = None;
            return &self.labels;
        }
        self.find_cells(cloud);
        let incremental = match (&previous, changed) {
            (Some(previous), Some(changed)) => {
                self.mark_affected(previous);
                self.stats.changed = changed;
                true
            }
            _ => {
                self.leaf_affected.clear();
                self.leaf_affected.resize(self.leaf_coord.len(), true);
                self.stats.changed = n;
                false
            }
        };
        self.stats.incremental = incremental;
        self.label(cloud);
        if self.remember_frames {
            self.remember(cloud, previous);
        }
        &self.labels
    }

    /// Flags the splats that differ from the last frame; returns how many.
    fn mark_changed(&mut self, cloud: &PointCloud, previous: &Previous) -> usize {
        let same = |a: Vec3, b: Vec3| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits);
        self.changed.resize(cloud.len(), false);
        self.changed
            .par_iter_mut()
            .enumerate()
            .map(|(i, c)| {
                *c = !(same(cloud.positions[i], previous.positions[i])
                    && same(cloud.normals[i], previous.normals[i])
                    && cloud.radii[i].to_bits() == previous.radii[i].to_bits());
                *c as usize
            })
            .sum()
    }

    /// Steps 1-2 and the leaves' axes.
    fn find_leaves(&mut self, cloud: &PointCloud) {
        let n = cloud.len();
        let lattice = self.lattice;
        self.coords.resize(n, IVec3::ZERO);
        self.coords.par_iter_mut().zip(&cloud.positions).for_each(|(c, p)| *c = lattice.coords(*p));

        self.leaves.clear();
        self.leaf_coord.clear();
        self.leaf_normal.clear();
        self.leaf_of.resize(n, 0);
        let mut last = (IVec3::MAX, 0u32);
        for i in 0..n {
            let coord = self.coords[i].div_euclid(IVec3::splat(LEAF_CELLS));
            let id = if coord == last.0 {
                last.1
            } else {
                let next = self.leaf_coord.len() as u32;
                let id = *self.leaves.entry(coord).or_insert(next);
                if id == next {
                    self.leaf_coord.push(coord);
                    self.leaf_normal.push(Vec3::ZERO);
                }
                last = (coord, id);
                id
            };
            self.leaf_of[i] = id;
            let normal = cloud.normals[i];
            if normal.is_finite() {
                self.leaf_normal[id as usize] += normal;
            }
        }
        self.leaf_axis.clear();
        self.leaf_axis.extend(self.leaf_normal.iter().map(|n| dominant_axis(*n)));
    }

    /// Every splat in its table group, collisions kept.
    fn label_by_table(&mut self) {
        let table = Table::new(self.options.k);
        let (coords, leaf_of, axis) = (&self.coords, &self.leaf_of, &self.leaf_axis);
        self.labels.resize(coords.len(), 0);
        self.labels.par_iter_mut().enumerate().for_each(|(i, label)| {
            *label = table.at(across(coords[i], axis[leaf_of[i] as usize]));
        });
    }

    /// Steps 1-4: cells, leaves, their axes and neighbours, splats by cell.
    fn find_cells(&mut self, cloud: &PointCloud) {
        let n = cloud.len();
        self.find_leaves(cloud);
        let leaves = self.leaf_coord.len();
        self.leaf_neighbours.resize(leaves, [NO_LEAF; 9]);
        let (map, coord, axis) = (&self.leaves, &self.leaf_coord, &self.leaf_axis);
        self.leaf_neighbours.par_iter_mut().enumerate().for_each(|(l, out)| {
            let d = axis[l] as usize;
            for b in -1..=1 {
                for a in -1..=1 {
                    let mut c = coord[l];
                    c[(d + 1) % 3] += a;
                    c[(d + 2) % 3] += b;
                    let found = map.get(&c).copied().filter(|&m| axis[m as usize] as usize == d);
                    out[((b + 1) * 3 + (a + 1)) as usize] = found.unwrap_or(NO_LEAF);
                }
            }
        });

        self.cell_of.resize(n, 0);
        let (coords, leaf_of) = (&self.coords, &self.leaf_of);
        self.cell_of.par_iter_mut().enumerate().for_each(|(i, cell)| {
            let leaf = leaf_of[i] as usize;
            let (x, y) = across(coords[i], axis[leaf]);
            let local = (y.rem_euclid(LEAF_CELLS) * LEAF_CELLS + x.rem_euclid(LEAF_CELLS)) as usize;
            *cell = (leaf * LEAF_AREA + local) as u32;
        });

        // A stable counting sort in two levels: splats by leaf (one pass in
        // order), then each leaf's by cell, leaves in parallel. Each cell then
        // lists its splats by index.
        self.leaf_start.clear();
        self.leaf_start.resize(leaves + 1, 0);
        for &l in &self.leaf_of {
            self.leaf_start[l as usize + 1] += 1;
        }
        for l in 0..leaves {
            self.leaf_start[l + 1] += self.leaf_start[l];
        }
        self.by_leaf.resize(n, 0);
        {
            let mut fill = self.leaf_start[..leaves].to_vec();
            for (i, &l) in self.leaf_of.iter().enumerate() {
                self.by_leaf[fill[l as usize] as usize] = i as u32;
                fill[l as usize] += 1;
            }
        }
        let cells = leaves * LEAF_AREA;
        self.cell_start.clear();
        self.cell_start.resize(cells + 1, 0);
        self.cell_start[cells] = n as u32;
        self.members.resize(n, 0);
        self.sorted_discs.resize(n, [0.0; 4]);
        self.sorted_table.resize(n, 0);
        // Each leaf's runs of the outputs, split apart for the parallel pass.
        let mut runs = Vec::with_capacity(leaves);
        let (mut members, mut discs, mut table_out) =
            (self.members.as_mut_slice(), self.sorted_discs.as_mut_slice(), self.sorted_table.as_mut_slice());
        let mut starts = self.cell_start.as_mut_slice();
        for l in 0..leaves {
            let size = (self.leaf_start[l + 1] - self.leaf_start[l]) as usize;
            let (m, rest_m) = members.split_at_mut(size);
            let (d, rest_d) = discs.split_at_mut(size);
            let (t, rest_t) = table_out.split_at_mut(size);
            let (c, rest_c) = starts.split_at_mut(LEAF_AREA);
            runs.push((l, m, d, t, c));
            (members, discs, table_out, starts) = (rest_m, rest_d, rest_t, rest_c);
        }
        let table = Table::new(self.options.k);
        let (by_leaf, leaf_start, cell_of) = (&self.by_leaf, &self.leaf_start, &self.cell_of);
        let (coords, axis) = (&self.coords, &self.leaf_axis);
        runs.into_par_iter().for_each(|(l, members, discs, groups, starts)| {
            let first = leaf_start[l] as usize;
            let splats = &by_leaf[first..leaf_start[l + 1] as usize];
            let mut count = [0u32; LEAF_AREA];
            for &i in splats {
                count[cell_of[i as usize] as usize - l * LEAF_AREA] += 1;
            }
            let mut at = 0u32;
            for (c, start) in starts.iter_mut().enumerate() {
                *start = first as u32 + at;
                at += count[c];
                count[c] = *start - first as u32;
            }
            for &i in splats {
                let i = i as usize;
                let local = cell_of[i] as usize - l * LEAF_AREA;
                let m = count[local] as usize;
                count[local] += 1;
                let p = cloud.positions[i];
                members[m] = i as u32;
                discs[m] = [p.x, p.y, p.z, cloud.radii[i]];
                groups[m] = table.at(across(coords[i], axis[l])) as u8;
            }
        });
        self.stats.leaves = leaves;
    }

    /// Flags the leaves to label again: those holding a changed splat before
    /// or after it moved, and those beside them.
    fn mark_affected(&mut self, previous: &Previous) {
        let mut dirty: rustc_hash::FxHashSet<IVec3> = rustc_hash::FxHashSet::default();
        for (i, _) in self.changed.iter().enumerate().filter(|(_, c)| **c) {
            dirty.insert(previous.leaf_coord[i]);
            dirty.insert(self.leaf_coord[self.leaf_of[i] as usize]);
        }
        let (coord, axis) = (&self.leaf_coord, &self.leaf_axis);
        self.leaf_affected.resize(coord.len(), false);
        self.leaf_affected.par_iter_mut().enumerate().for_each(|(l, affected)| {
            let d = axis[l] as usize;
            *affected = (-1..=1).any(|b| {
                (-1..=1).any(|a| {
                    let mut c = coord[l];
                    c[(d + 1) % 3] += a;
                    c[(d + 2) % 3] += b;
                    dirty.contains(&c)
                })
            });
        });
    }

    /// Step 5, over the affected leaves; the others keep their last labels.
    fn label(&mut self, cloud: &PointCloud) {
        let n = cloud.len();
        self.sorted_labels.resize(n, 0);
        let mut per_leaf: Vec<&mut [u32]> = Vec::with_capacity(self.leaf_coord.len());
        let mut rest = self.sorted_labels.as_mut_slice();
        for l in 0..self.leaf_coord.len() {
            let size = (self.cell_start[(l + 1) * LEAF_AREA] - self.cell_start[l * LEAF_AREA]) as usize;
            let (this, tail) = rest.split_at_mut(size);
            per_leaf.push(this);
            rest = tail;
        }
        let context = LabelContext {
            cloud,
            options: self.options,
            leaf_neighbours: &self.leaf_neighbours,
            cell_start: &self.cell_start,
            members: &self.members,
            discs: &self.sorted_discs,
            table: &self.sorted_table,
        };
        let (affected, previous_labels) = (&self.leaf_affected, &self.labels);
        let keep = previous_labels.len() == n;
        let (resolved, labelled) = per_leaf
            .into_par_iter()
            .enumerate()
            .map(|(l, out)| {
                if affected[l] || !keep {
                    (context.label_leaf(l, out), out.len())
                } else {
                    let first = context.cell_start[l * LEAF_AREA] as usize;
                    for (m, label) in out.iter_mut().enumerate() {
                        *label = previous_labels[context.members[first + m] as usize];
                    }
                    (0, 0)
                }
            })
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        self.labels.resize(n, 0);
        for (m, &i) in self.members.iter().enumerate() {
            self.labels[i as usize] = self.sorted_labels[m];
        }
        self.stats.resolved = resolved;
        self.stats.labelled = labelled;
    }

    /// Keeps this frame's splats and leaves for the next one.
    fn remember(&mut self, cloud: &PointCloud, previous: Option<Previous>) {
        let mut p = previous.unwrap_or_default();
        p.positions.clear();
        p.positions.extend_from_slice(&cloud.positions);
        p.normals.clear();
        p.normals.extend_from_slice(&cloud.normals);
        p.radii.clear();
        p.radii.extend_from_slice(&cloud.radii);
        p.leaf_coord.clear();
        p.leaf_coord.extend(self.leaf_of.iter().map(|&l| self.leaf_coord[l as usize]));
        self.previous = Some(p);
    }
}

/// The axis (0, 1, 2) of the largest component of `n` (z for a zero or non-finite sum).
pub(crate) fn dominant_axis(n: Vec3) -> u8 {
    let n = n.abs();
    if !n.is_finite() || n == Vec3::ZERO {
        2
    } else if n.x >= n.y && n.x >= n.z {
        0
    } else if n.y >= n.z {
        1
    } else {
        2
    }
}

/// Eq. 9's (x, y): the cell coordinates across axis `d`.
pub(crate) fn across(c: IVec3, d: u8) -> (i32, i32) {
    let d = d as usize;
    (c[(d + 1) % 3], c[(d + 2) % 3])
}
