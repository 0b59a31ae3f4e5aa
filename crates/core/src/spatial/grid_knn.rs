//! Exact k nearest neighbours over a uniform grid, cell by cell: the fast
//! path of [`super::knn::k_nearest`] for large surface scans.
//!
//! Hand-written because the general k-d tree (kiddo) spends ~2 µs per query
//! on a 2M-point lidar tile, most of it walking the tree again for every
//! point; here the points of one cell share one candidate list.
//!
//! The cell size is set so that an occupied cell holds about
//! [`TARGET_PER_CELL`] points (surface scans fill cells as h², so two or
//! three rounds of counting converge). Points are sorted by cell. Every point
//! of a cell takes its candidates from the 3×3×3 block of cells around it (a
//! few runs of the sorted order, one per column of cells, whose distances are
//! computed from one array per axis), keeps the k closest (selected among
//! those within a guess from the point before it, where k of them are), and
//! is exact when its k-th distance is within the block (no point outside the
//! block can be closer). The few points that fail the test take the block of
//! cells within [`MAX_RING`] instead; those still failing (outliers far from
//! everything) are left to the caller's tree.

use glam::Vec3;
use rayon::prelude::*;

use super::neighbours::Neighbours;

/// Points an occupied cell should hold: enough that a 3×3×3 block nearly
/// always holds a point's 16 nearest neighbours.
const TARGET_PER_CELL: f64 = 8.0;
/// Cells per axis stay below 2^21, so a cell's three indices pack into a u64.
const MAX_CELLS_PER_AXIS: f32 = 2_097_000.0;
/// How much a cell's previous point's k-th squared distance is grown to
/// guess the next one's (1.1-1.3 gave the same times on a 2M terrain, 2.0 less gain).
const GUESS_GROWTH: f32 = 1.3;
/// The widest block ring a point searches before it is left to the tree.
const MAX_RING: i64 = 2;

struct Grid {
    lo: Vec3,
    h: f32,
    /// Sorted keys of the occupied cells, and where each cell's points start in `sorted`.
    cells: Vec<u64>,
    /// Each occupied cell's place in `cells`, by key.
    lookup: rustc_hash::FxHashMap<u64, u32>,
    starts: Vec<u32>,
    /// Point indices, sorted by cell.
    sorted: Vec<u32>,
    /// The points' coordinates in that order, one array per axis, so a
    /// block's candidates are a few contiguous runs of each (read through
    /// `sorted` they were cache misses) whose distances are computed
    /// several at a time.
    xs: Vec<f32>,
    ys: Vec<f32>,
    zs: Vec<f32>,
}

fn key(c: [i64; 3]) -> u64 {
    (c[0] as u64) << 42 | (c[1] as u64) << 21 | c[2] as u64
}

impl Grid {
    /// The point at place `r` in sorted order.
    fn at(&self, r: u32) -> Vec3 {
        let r = r as usize;
        Vec3::new(self.xs[r], self.ys[r], self.zs[r])
    }

    fn cell_of(&self, p: Vec3) -> [i64; 3] {
        let c = ((p - self.lo) / self.h).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    }

    /// The places in sorted order of the points of the cells within `ring`
    /// of cell `centre`, into `out` as runs. A column of cells (one x and y, z
    /// ascending) is a run of consecutive keys, so its occupied cells are
    /// consecutive in `cells` and their points in `sorted`: one run per
    /// column, found from its lowest occupied cell (27 hash lookups a cell
    /// were a sixth of a terrain's neighbour search).
    fn block(&self, centre: [i64; 3], ring: i64, out: &mut Vec<std::ops::Range<u32>>) {
        let inside = |v: i64| (0..1 << 21).contains(&v);
        let (z0, z1) = ((centre[2] - ring).max(0), (centre[2] + ring).min((1 << 21) - 1));
        for x in (centre[0] - ring..=centre[0] + ring).filter(|&x| inside(x)) {
            for y in (centre[1] - ring..=centre[1] + ring).filter(|&y| inside(y)) {
                let Some(first) = (z0..=z1).find_map(|z| self.lookup.get(&key([x, y, z]))) else { continue };
                let (first, last) = (*first as usize, key([x, y, z1]));
                let end = first + 1 + self.cells[first + 1..].iter().take_while(|&&c| c <= last).count();
                out.push(self.starts[first]..self.starts[end]);
            }
        }
    }

    /// Sorts the points into cells of size `h`; `None` when the grid would be too fine.
    fn build(points: &[Vec3], lo: Vec3, hi: Vec3, h: f32) -> Option<Grid> {
        if h.is_nan() || h <= 0.0 || ((hi - lo) / h).max_element() >= MAX_CELLS_PER_AXIS {
            return None;
        }
        let mut grid = Grid {
            lo,
            h,
            cells: Vec::new(),
            lookup: Default::default(),
            starts: Vec::new(),
            sorted: Vec::new(),
            xs: Vec::new(),
            ys: Vec::new(),
            zs: Vec::new(),
        };
        let mut keyed: Vec<(u64, u32)> =
            points.par_iter().enumerate().map(|(i, p)| (key(grid.cell_of(*p)), i as u32)).collect();
        keyed.par_sort_unstable();
        for (at, &(k, _)) in keyed.iter().enumerate() {
            if grid.cells.last() != Some(&k) {
                grid.cells.push(k);
                grid.starts.push(at as u32);
            }
        }
        grid.starts.push(keyed.len() as u32);
        grid.sorted = keyed.into_iter().map(|(_, i)| i).collect();
        let axis = |a: usize| grid.sorted.par_iter().map(|&i| points[i as usize][a]).collect();
        (grid.xs, grid.ys, grid.zs) = (axis(0), axis(1), axis(2));
        grid.lookup = grid.cells.iter().enumerate().map(|(at, &k)| (k, at as u32)).collect();
        Some(grid)
    }
}

/// The `k` nearest neighbours of each of the first `queries` points (itself
/// excluded; the rest only serve as neighbours), and the points whose rows
/// are still to be found (far outliers); or `None` when the cloud is too
/// small or too uneven for a grid (the caller then uses the tree).
pub fn k_nearest(
    points: &[Vec3],
    queries: usize,
    k: usize,
    on_progress: &(dyn Fn(u64) + Sync),
) -> Option<(Neighbours, Vec<u32>)> {
    let n = points.len();
    if n < 4 * (k + 1) || n >= u32::MAX as usize {
        return None;
    }
    let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let size = hi - lo;
    // A surface of area ~ the two largest faces' mean spreads n points; then count and correct.
    let mut sides = size.to_array();
    sides.sort_by(f32::total_cmp);
    let area = (sides[1] * sides[2]).max(sides[2] * sides[2] * 1e-6) as f64;
    let mut h = (area / n as f64 * TARGET_PER_CELL).sqrt() as f32;
    let mut grid = Grid::build(points, lo, hi, h)?;
    for _ in 0..3 {
        let per_cell = n as f64 / grid.cells.len() as f64;
        if (per_cell / TARGET_PER_CELL - 1.0).abs() < 0.25 {
            break;
        }
        h *= (TARGET_PER_CELL / per_cell).sqrt().clamp(0.25, 4.0) as f32;
        grid = Grid::build(points, lo, hi, h)?;
    }
    let per_cell = n as f64 / grid.cells.len() as f64;
    if per_cell > 8.0 * TARGET_PER_CELL {
        // Dense clumps (the density varies too much for one cell size).
        return None;
    }
    let mut sorted_indices = vec![0u32; n * k];
    // Split the rows by cell, so every task owns the rows of its cells.
    let mut rows: Vec<&mut [u32]> = Vec::with_capacity(grid.cells.len());
    let mut rest = sorted_indices.as_mut_slice();
    for c in 0..grid.cells.len() {
        let len = (grid.starts[c + 1] - grid.starts[c]) as usize * k;
        let (cell, after) = std::mem::take(&mut rest).split_at_mut(len);
        rows.push(cell);
        rest = after;
    }
    let left = std::sync::Mutex::new(Vec::new());
    let widened = std::sync::atomic::AtomicUsize::new(0);
    // A task's scratch lists, and its last point's k-th squared distance,
    // grown: a guess at the next one's (the next cell is the one above or
    // beside, as dense).
    let scratches = || (Scratch::default(), Vec::new(), f32::INFINITY);
    rows.into_par_iter().enumerate().with_min_len(64).for_each_init(
        scratches,
        |(scratch, candidates, guess), (c, idx)| {
            let members = grid.starts[c]..grid.starts[c + 1];
            let centre = grid.cell_of(grid.at(members.start));
            candidates.clear();
            grid.block(centre, 1, candidates);
            // The wider block, made for the first point of the cell that needs it and kept for the others.
            let mut wider = Vec::new();
            for (row, r) in members.clone().enumerate() {
                if grid.sorted[r as usize] as usize >= queries {
                    continue;
                }
                let q = grid.at(r);
                let mut row = Row { idx: &mut idx[row * k..(row + 1) * k], scratch };
                let kth = nearest_among(&grid, r, candidates, &mut row, *guess);
                *guess = kth.map_or(f32::INFINITY, |d| d * d * GUESS_GROWTH);
                if kth.is_none_or(|kth| kth > inside_block(&grid, q, centre, 1))
                    && widened.fetch_add(1, std::sync::atomic::Ordering::Relaxed) < usize::MAX
                    && !widen(&grid, r, centre, &mut row, &mut wider)
                {
                    left.lock().unwrap_or_else(|e| e.into_inner()).push(grid.sorted[r as usize]);
                }
            }
            on_progress(members.len() as u64);
        },
    );
    let widened = widened.load(std::sync::atomic::Ordering::Relaxed);
    log::debug!("grid k-nn: cell {h}, {per_cell:.1} points per cell, {widened} points searched beyond their block");
    let neighbours = Neighbours::in_row_order(k, sorted_indices, grid.sorted, queries);
    Some((neighbours, left.into_inner().unwrap_or_else(|e| e.into_inner())))
}

/// How far `q` (in cell `centre`) is from the outside of the block of cells within `ring` of it.
fn inside_block(grid: &Grid, q: Vec3, centre: [i64; 3], ring: i64) -> f32 {
    let c = Vec3::new(centre[0] as f32, centre[1] as f32, centre[2] as f32);
    let block_lo = grid.lo + (c - ring as f32) * grid.h;
    let block_hi = grid.lo + (c + 1.0 + ring as f32) * grid.h;
    (q - block_lo).min(block_hi - q).min_element()
}

/// A task's scratch lists: the candidates' squared distances (as bits),
/// and the candidates kept as `squared distance bits << 32 | point index`
/// (a non-negative f32's bits order as the value does, so plain u64 order
/// is distance, then index).
#[derive(Default)]
struct Scratch {
    distances: Vec<u32>,
    keys: Vec<u64>,
}

/// Where one point's k neighbours go (k = the rows' length), and the task's scratch lists.
struct Row<'a> {
    idx: &'a mut [u32],
    scratch: &'a mut Scratch,
}

/// The k nearest of the points in `runs` (places in sorted order) to the
/// point at place `r` (itself excluded), nearest first, into `row` as point
/// indices, and the k-th's distance; `None` when there are fewer than k
/// others. `guess` is a squared distance the k-th likely lies within (the
/// previous point's, grown by [`GUESS_GROWTH`]): the k nearest are selected
/// from the candidates within it when at least k are, which holds them
/// all, so the rows are exact whatever the guess.
fn nearest_among(grid: &Grid, r: u32, runs: &[std::ops::Range<u32>], row: &mut Row<'_>, guess: f32) -> Option<f32> {
    let (q, k) = (grid.at(r), row.idx.len());
    let count: usize = runs.iter().map(|run| run.len()).sum();
    if count <= k {
        return None;
    }
    let Scratch { distances, keys } = &mut *row.scratch;
    // Every candidate's squared distance, a run at a time over the axes'
    // arrays (no gather, no branch: the compiler computes several at once).
    distances.resize(count, 0);
    let mut at = 0;
    for run in runs {
        let (from, to) = (run.start as usize, run.end as usize);
        let out = &mut distances[at..at + run.len()];
        for (((d, x), y), z) in out.iter_mut().zip(&grid.xs[from..to]).zip(&grid.ys[from..to]).zip(&grid.zs[from..to]) {
            let (dx, dy, dz) = (x - q.x, y - q.y, z - q.z);
            *d = (dx * dx + dy * dy + dz * dz).max(0.0).to_bits();
        }
        if run.contains(&r) {
            // The point itself (its own cell is in every block): above every
            // limit but the last, and then the largest key.
            out[(r - run.start) as usize] = u32::MAX;
        }
        at += run.len();
    }
    // Keys are written in place and kept (the count moved on) only when
    // within `limit`: no branch (a filtered iterator grew the list one
    // checked push at a time, a fifth of an airborne tile's load). Ties go
    // to the lower point index.
    keys.resize(count, u64::MAX);
    let within = |limit: u32, keys: &mut [u64]| {
        let (mut kept, mut at) = (0, 0);
        for run in runs {
            let places = &grid.sorted[run.start as usize..run.end as usize];
            for (&d, &point) in distances[at..at + run.len()].iter().zip(places) {
                keys[kept] = (u64::from(d) << 32) | u64::from(point);
                kept += usize::from(d <= limit);
            }
            at += run.len();
        }
        kept
    };
    // Those within the guess first; when fewer than k are, the guess was
    // too small: all of them.
    let mut kept = within(guess.to_bits(), keys);
    if kept < k {
        kept = within(u32::MAX, keys);
    }
    let keys = &mut keys[..kept];
    // Within a good guess few more than k are kept: sorting them all is
    // cheaper than selecting first.
    if kept > 2 * k {
        keys.select_nth_unstable(k - 1);
        keys[..k].sort_unstable();
    } else {
        keys.sort_unstable();
    }
    for (slot, &packed) in keys[..k].iter().enumerate() {
        row.idx[slot] = packed as u32;
    }
    Some(f32::from_bits((keys[k - 1] >> 32) as u32).sqrt())
}

/// The neighbours of the point at place `r` from the block of cells within
/// [`MAX_RING`] of its own, if the k-th lies inside it; false when it does
/// not. `wider` keeps that block's points for the next point of the same
/// cell (on an airborne tile 6 % of the points widen, most of them beside
/// another of their cell that does).
fn widen(grid: &Grid, r: u32, centre: [i64; 3], row: &mut Row<'_>, wider: &mut Vec<std::ops::Range<u32>>) -> bool {
    let q = grid.at(r);
    if wider.is_empty() {
        grid.block(centre, MAX_RING, wider);
    }
    nearest_among(grid, r, wider, row, f32::INFINITY).is_some_and(|kth| kth <= inside_block(grid, q, centre, MAX_RING))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row the grid finds is the k nearest of an exhaustive search,
    /// in its order, ties (a lattice has many) going to the lower index.
    #[test]
    fn grid_knn_exact_rows_match_an_exhaustive_search() {
        // Two layers of a unit lattice, a noisy sheet above them, and an outlier.
        let mut points: Vec<Vec3> =
            (0..30 * 30 * 2).map(|i| Vec3::new((i / 60) as f32, (i / 2 % 30) as f32, (i % 2) as f32 * 0.5)).collect();
        let mut seed = 5u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        points.extend((0..1500).map(|_| Vec3::new(next() * 30.0, next() * 30.0, 3.0 + next() * 0.3)));
        points.push(Vec3::new(200.0, 0.0, 0.0));
        let k = 16;
        let (found, left) = k_nearest(&points, points.len(), k, &|_| {}).expect("a grid suits these points");
        assert!(left.len() <= 1, "{} points left to the tree", left.len());
        for i in (0..points.len()).filter(|&i| !left.contains(&(i as u32))) {
            let mut all: Vec<u64> = (0..points.len())
                .filter(|&j| j != i)
                .map(|j| (u64::from(points[j].distance_squared(points[i]).max(0.0).to_bits()) << 32) | j as u64)
                .collect();
            all.select_nth_unstable(k - 1);
            all[..k].sort_unstable();
            let expected: Vec<u32> = all[..k].iter().map(|&key| key as u32).collect();
            assert_eq!(found.of(i), expected.as_slice(), "point {i} at {}", points[i]);
        }
    }
}
