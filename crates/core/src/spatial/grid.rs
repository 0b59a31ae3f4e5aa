//! A hashed uniform grid for fixed-radius neighbour queries.
//!
//! Hand-written rather than `kiddo` because the overlap graph asks one
//! fixed-radius query per splat with radii near the grid's cell size: a
//! counting sort into hashed cells and a 3x3x3 cell scan is several times
//! faster than k-d tree range queries there, and builds in O(n). Cells are
//! hashed into a table of about n buckets, so memory stays linear whatever
//! the model's extent; points of other cells that share a bucket are
//! rejected by the caller's distance test.

use glam::{IVec3, Vec3};

/// Points bucketed by hashed grid cell.
pub struct HashGrid {
    cell: f32,
    origin: Vec3,
    /// `start[b]..start[b + 1]` indexes `items` for bucket b.
    start: Vec<u32>,
    /// Point indices, grouped by bucket.
    items: Vec<u32>,
    /// The cell of each entry of `items`.
    cells: Vec<IVec3>,
    mask: u64,
}

impl HashGrid {
    /// Buckets `points` into cells of side `cell` (clamped to a positive value).
    pub fn new(points: &[Vec3], cell: f32) -> Self {
        let origin = points.iter().fold(Vec3::splat(f32::INFINITY), |a, p| a.min(*p));
        let origin = if origin.is_finite() { origin } else { Vec3::ZERO };
        let buckets = (points.len().max(1) * 2).next_power_of_two();
        let mut grid = Self {
            cell: if cell.is_finite() && cell > 0.0 { cell } else { 1.0 },
            origin,
            start: vec![0; buckets + 1],
            items: vec![0; points.len()],
            cells: vec![IVec3::ZERO; points.len()],
            mask: buckets as u64 - 1,
        };
        let cells: Vec<IVec3> = points.iter().map(|p| grid.cell_of(*p)).collect();
        let keys: Vec<u32> = cells.iter().map(|c| grid.bucket(*c)).collect();
        for &k in &keys {
            grid.start[k as usize + 1] += 1;
        }
        for b in 0..buckets {
            grid.start[b + 1] += grid.start[b];
        }
        let mut fill = grid.start.clone();
        for (i, &k) in keys.iter().enumerate() {
            grid.items[fill[k as usize] as usize] = i as u32;
            grid.cells[fill[k as usize] as usize] = cells[i];
            fill[k as usize] += 1;
        }
        grid
    }

    pub fn cell_size(&self) -> f32 {
        self.cell
    }

    pub fn cell_of(&self, p: Vec3) -> IVec3 {
        let c = ((p - self.origin) / self.cell).floor();
        // Clamp so that absurd coordinates cannot overflow.
        c.clamp(Vec3::splat(-1e9), Vec3::splat(1e9)).as_ivec3()
    }

    fn bucket(&self, c: IVec3) -> u32 {
        let h = (c.x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (c.y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (c.z as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
        ((h ^ (h >> 29)) & self.mask) as u32
    }

    /// Calls `visit` with every point index whose cell lies within `reach`
    /// cells of `p`'s cell (a superset of the points within `reach * cell`).
    /// Each point is visited once: entries of a bucket that belong to another
    /// cell are skipped. When the block of cells to scan is larger than the
    /// number of points (a splat far larger than the typical one), every
    /// point is tested instead, so a query never costs more than O(n).
    pub fn for_each_near(&self, p: Vec3, reach: i32, mut visit: impl FnMut(u32)) {
        self.scan_near(p, reach, usize::MAX, 0, |i| {
            visit(i);
            true
        });
    }

    /// [`Self::for_each_near`] that visits at most `limit` points and stops
    /// when `visit` returns false; returns false when it stopped at the
    /// limit. A cap on what a query scans bounds its time where thousands of
    /// splats crowd one cell (coincident copies, a clump of tiny splats).
    /// Each bucket is read from entry `start` on (modulo its length,
    /// wrapping), so that capped queries from different splats of one crowd
    /// can see different parts of it instead of all the same first `limit`.
    pub fn scan_near(
        &self,
        p: Vec3,
        reach: i32,
        limit: usize,
        start: usize,
        mut visit: impl FnMut(u32) -> bool,
    ) -> bool {
        let c = self.cell_of(p);
        let reach = reach.max(0);
        let side = 2 * reach as u64 + 1;
        let mut left = limit;
        // None: go on; Some(whole): stop, and whether the scan was whole.
        let mut take = |i: u32| -> Option<bool> {
            if left == 0 {
                return Some(false);
            }
            left -= 1;
            if visit(i) { None } else { Some(true) }
        };
        // 0..len from `start` on, wrapping: two ranges, no division per entry.
        let rotated = |len: usize| {
            let from = if len == 0 { 0 } else { start % len };
            (from..len).chain(0..from)
        };
        if side.saturating_mul(side).saturating_mul(side) > self.items.len() as u64 {
            for k in rotated(self.items.len()) {
                let d = (self.cells[k] - c).abs();
                if d.x <= reach && d.y <= reach && d.z <= reach {
                    if let Some(whole) = take(self.items[k]) {
                        return whole;
                    }
                }
            }
            return true;
        }
        for dz in -reach..=reach {
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    let cell = c + IVec3::new(dx, dy, dz);
                    let b = self.bucket(cell) as usize;
                    let first = self.start[b] as usize;
                    let len = self.start[b + 1] as usize - first;
                    for k in rotated(len).map(|k| first + k) {
                        if self.cells[k] == cell {
                            if let Some(whole) = take(self.items[k]) {
                                return whole;
                            }
                        }
                    }
                }
            }
        }
        true
    }
}

/// The radius below which 90% of `radii` lie: a cell size that keeps most
/// searches to 3x3x3 cells without letting a few outliers inflate every cell.
pub fn typical_radius(radii: &[f32]) -> f32 {
    let mut r: Vec<f32> = radii.iter().copied().filter(|r| r.is_finite() && *r > 0.0).collect();
    if r.is_empty() {
        return 1.0;
    }
    let at = (r.len() * 9 / 10).min(r.len() - 1);
    *r.select_nth_unstable_by(at, f32::total_cmp).1
}
