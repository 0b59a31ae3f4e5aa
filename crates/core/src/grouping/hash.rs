//! Dynamic hash grouping (Zhang & Pajarola 2007 §4.3, Eq. 9, Fig. 9).
//!
//! Each splat is mapped to 2D cell coordinates (x, y) in the plane across the
//! dominant axis d of its neighbourhood's mean normal (Eq. 9), and its group
//! is `table[x % K][y % K]`, the K x K generalisation of Fig. 9:
//! `table[x][y] = (x + s·y) mod K` with s the integer nearest √K (s = 3 for
//! K = 8 reproduces Fig. 9 exactly). Where the paper averages normals over a
//! BSP leaf, we average them over coarse grid cells of 16 radii ("leaves").
//! The cell size is the median radius for all splats, so that neighbours
//! share one lattice.
//!
//! Collisions are two splats in the same leaf and cell. Modes:
//! (1) ignore them; (2) handle all: the first splat keeps its table group and
//! every later one takes the group of least overlap with its neighbours that
//! no splat of its cell has yet; (3) handle only the splats nearer to the eye
//! than a given distance.

use glam::{IVec3, Vec3};
use rayon::prelude::*;

use super::{Grouping, GroupingError, MAX_GROUPS};
use crate::cloud::PointCloud;
use crate::spatial::grid::{HashGrid, typical_radius};
use crate::spatial::overlap::median_radius;

/// Which collisions are resolved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Collisions {
    None,
    All,
    /// Only for splats closer to `eye` than `distance`.
    Near {
        eye: Vec3,
        distance: f32,
    },
}

#[derive(Debug, Clone, Copy)]
pub struct HashOptions {
    pub k: usize,
    pub collisions: Collisions,
}

/// Size of a "leaf" (normal-averaging cell), in median radii.
const LEAF_RADII: f32 = 16.0;

/// The K x K hash table entry for cell (x, y).
pub fn table(k: usize, x: i64, y: i64) -> u32 {
    let k = k.max(1) as i64;
    let s = ((k as f64).sqrt().round() as i64).max(1);
    (x.rem_euclid(k) + s * y.rem_euclid(k)).rem_euclid(k) as u32
}

/// Per-splat cell keys: (leaf hash, x, y) packed, and the cell coordinates.
pub struct Cells {
    pub key: Vec<u64>,
    pub xy: Vec<(i64, i64)>,
}

/// Eq. 9 for every splat.
pub fn cells(cloud: &PointCloud) -> Cells {
    let r = median_radius(&cloud.radii);
    let leaf_size = LEAF_RADII * r;
    let origin = cloud.positions.iter().fold(Vec3::splat(f32::INFINITY), |a, p| a.min(*p));
    let origin = if origin.is_finite() { origin } else { Vec3::ZERO };
    let leaf_of = |p: Vec3| ((p - origin) / leaf_size).floor().clamp(Vec3::splat(-1e9), Vec3::splat(1e9)).as_ivec3();
    let table_bits = (cloud.len().max(16) / 8).next_power_of_two();
    let leaf_hash = |c: IVec3| -> usize {
        let h = (c.x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (c.y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (c.z as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
        ((h ^ (h >> 31)) as usize) & (table_bits - 1)
    };
    let leaf: Vec<usize> = cloud.positions.par_iter().map(|p| leaf_hash(leaf_of(*p))).collect();
    let mut mean_normal = vec![Vec3::ZERO; table_bits];
    for (i, &l) in leaf.iter().enumerate() {
        mean_normal[l] += cloud.normals[i];
    }
    let (key, xy): (Vec<u64>, Vec<(i64, i64)>) = (0..cloud.len())
        .into_par_iter()
        .map(|i| {
            let n = mean_normal[leaf[i]].abs();
            let d = if n.x >= n.y && n.x >= n.z {
                0
            } else if n.y >= n.z {
                1
            } else {
                2
            };
            let q = (cloud.positions[i] - origin) / r;
            let x = q[(d + 1) % 3].floor() as i64;
            let y = q[(d + 2) % 3].floor() as i64;
            let packed = (leaf[i] as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                ^ (x as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
                ^ (y as u64).wrapping_mul(0x1656_67B1_9E37_79F9)
                ^ d as u64;
            (packed, (x, y))
        })
        .unzip();
    Cells { key, xy }
}

/// An open-addressing set of cell keys with the groups used in each cell.
struct CellTable {
    keys: Vec<u64>,
    used: Vec<u64>,
    mask: usize,
}

impl CellTable {
    fn new(n: usize) -> Self {
        let size = (n.max(8) * 2).next_power_of_two();
        Self { keys: vec![u64::MAX; size], used: vec![0; size], mask: size - 1 }
    }

    /// The slot of `key`, inserting it when absent; returns (slot, was present).
    fn slot(&mut self, key: u64) -> (usize, bool) {
        let key = if key == u64::MAX { u64::MAX - 1 } else { key };
        let mut s = (key ^ (key >> 33)) as usize & self.mask;
        loop {
            if self.keys[s] == key {
                return (s, true);
            }
            if self.keys[s] == u64::MAX {
                self.keys[s] = key;
                return (s, false);
            }
            s = (s + 1) & self.mask;
        }
    }
}

/// Groups `cloud` by hashing; returns the grouping and the number of collisions resolved.
pub fn group(cloud: &PointCloud, options: &HashOptions) -> Result<(Grouping, usize), GroupingError> {
    let k = options.k;
    if k == 0 || k > MAX_GROUPS {
        return Err(GroupingError::BadK { k, max: MAX_GROUPS });
    }
    let cells = cells(cloud);
    let mut labels: Vec<u32> = cells.xy.par_iter().map(|&(x, y)| table(k, x, y)).collect();
    if options.collisions == Collisions::None {
        return Ok((Grouping::from_labels(&labels, k), 0));
    }
    let resolve = |i: usize| match options.collisions {
        Collisions::None => false,
        Collisions::All => true,
        Collisions::Near { eye, distance } => cloud.positions[i].distance(eye) < distance,
    };
    let mut table_of_cells = CellTable::new(cloud.len());
    let mut queue = Vec::new();
    for (i, (&key, &label)) in cells.key.iter().zip(&labels).enumerate() {
        let (slot, present) = table_of_cells.slot(key);
        if present && resolve(i) {
            queue.push((i, slot));
        } else {
            table_of_cells.used[slot] |= 1u64 << label;
        }
    }
    if queue.is_empty() {
        return Ok((Grouping::from_labels(&labels, k), 0));
    }
    // Neighbours are searched within 2·r_i: overlaps with much larger splats are not counted.
    let grid = HashGrid::new(&cloud.positions, 2.0 * typical_radius(&cloud.radii));
    let mut overlap = vec![0f32; k];
    let (p, radii) = (&cloud.positions, &cloud.radii);
    let mut pending = vec![false; cloud.len()];
    for &(i, _) in &queue {
        pending[i] = true;
    }
    let mut crowded = 0;
    for &(i, slot) in &queue {
        let reach = (2.0 * radii[i] / grid.cell_size()).ceil() as i32;
        // Capped like the overlap graph's queries, so a crowd of splats costs
        // O(n), not O(n²); a capped scan is done again from this splat's own
        // place in the buckets, so that a crowd's scans see different parts of it.
        let mut sum_overlaps = |start: usize| {
            overlap.iter_mut().for_each(|o| *o = 0.0);
            grid.scan_near(p[i], reach, crate::spatial::overlap::MAX_SCANNED, start, |j| {
                let j = j as usize;
                if j != i && !pending[j] {
                    let d = p[i].distance(p[j]);
                    let reach = radii[i] + radii[j];
                    if d < reach {
                        overlap[labels[j] as usize] += (reach - d) / (0.5 * reach);
                    }
                }
                true
            })
        };
        if !sum_overlaps(0) {
            crowded += 1;
            sum_overlaps(i);
        }
        let used = table_of_cells.used[slot];
        let free = |g: usize| used & (1u64 << g) == 0;
        let all_used = (0..k).all(|g| !free(g));
        let best = (0..k)
            .filter(|&g| all_used || free(g))
            .min_by(|&a, &b| overlap[a].total_cmp(&overlap[b]))
            .unwrap_or(labels[i] as usize);
        labels[i] = best as u32;
        table_of_cells.used[slot] |= 1u64 << best;
        pending[i] = false;
    }
    if crowded > 0 {
        crate::progress::warn_once(format!(
            "{crowded} splats met more than {} others where collisions were resolved (coincident or crowded \
             splats): each was placed by the overlaps of that many",
            crate::spatial::overlap::MAX_SCANNED
        ));
    }
    Ok((Grouping::from_labels(&labels, k), queue.len()))
}
