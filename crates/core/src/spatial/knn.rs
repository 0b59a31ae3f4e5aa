//! k-nearest-neighbour lists for every point: over a uniform grid where
//! the cloud suits one ([`super::grid_knn`], surface scans), else from a
//! `kiddo` k-d tree.
//!
//! Queries run in parallel with rayon. The result is a table of `k`
//! neighbour indices per point, nearest first (the point itself excluded);
//! clouds with fewer than `k + 1` points get padded rows.

use std::num::NonZero;

use glam::Vec3;
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use rayon::prelude::*;

pub use super::neighbours::Neighbours;

/// Finds the `k` nearest neighbours of every point (excluding itself).
///
/// When the cloud has `k` points or fewer, missing entries repeat the point
/// itself (at distance 0).
pub fn k_nearest(points: &[Vec3], k: usize, on_progress: &(dyn Fn(u64) + Sync)) -> Neighbours {
    k_nearest_of_first(points, points.len(), k, on_progress)
}

/// The `k` nearest neighbours, among all of `points`, of the first
/// `queries` of them: one row each. The points after them only serve as
/// neighbours (a node's halo from the nodes around it).
pub fn k_nearest_of_first(points: &[Vec3], queries: usize, k: usize, on_progress: &(dyn Fn(u64) + Sync)) -> Neighbours {
    let k = k.max(1);
    let queries = queries.min(points.len());
    match super::grid_knn::k_nearest(points, queries, k, on_progress) {
        Some((mut found, left)) => {
            if !left.is_empty() {
                let (tree, coords) = tree_of(points);
                for i in left {
                    let i = i as usize;
                    query(&tree, &coords, i, k, found.row_mut(i));
                }
            }
            found
        }
        None => k_nearest_in_tree(points, queries, k, on_progress),
    }
}

type Tree = ImmutableKdTree<f32, u32, 3, 64>;

fn tree_of(points: &[Vec3]) -> (Tree, Vec<[f32; 3]>) {
    let coords: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    // Bucket size 64 keeps clouds with many duplicate points from overflowing leaves.
    (ImmutableKdTree::new_from_slice(&coords), coords)
}

/// Point `i`'s row from the tree; rows of clouds with k points or fewer repeat the point itself.
fn query(tree: &Tree, coords: &[[f32; 3]], i: usize, k: usize, idx_row: &mut [u32]) {
    let want = NonZero::new(k + 1).expect("k + 1 > 0");
    let found = tree.nearest_n::<SquaredEuclidean>(&coords[i], want);
    let mut j = 0;
    for nb in found.iter().filter(|nb| nb.item as usize != i).take(k) {
        idx_row[j] = nb.item;
        j += 1;
    }
    idx_row[j..k].fill(i as u32);
}

/// The rows of the first `queries` points from a `kiddo` k-d tree of all
/// of them (clouds a grid does not suit).
pub fn k_nearest_in_tree(points: &[Vec3], queries: usize, k: usize, on_progress: &(dyn Fn(u64) + Sync)) -> Neighbours {
    let (tree, coords) = tree_of(points);
    let mut indices = vec![0u32; queries * k];
    const CHUNK: usize = 4096;
    indices.par_chunks_mut(CHUNK * k).enumerate().for_each(|(chunk, idx)| {
        let first = chunk * CHUNK;
        for (row, idx_row) in idx.chunks_mut(k).enumerate() {
            query(&tree, &coords, first + row, k, idx_row);
        }
        on_progress((idx.len() / k) as u64);
    });
    Neighbours::in_point_order(k, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(seed: &mut u64) -> f32 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 40) as f32 / (1u64 << 24) as f32
    }

    /// The grid's rows have the tree's distances, on a noisy terrain with trees, a sphere, and far outliers.
    #[test]
    fn the_grid_finds_the_same_neighbours_as_the_tree() {
        let mut seed = 7;
        let mut terrain: Vec<Vec3> = (0..20_000)
            .map(|_| {
                let (x, y) = (lcg(&mut seed) * 100.0, lcg(&mut seed) * 60.0);
                let canopy = if lcg(&mut seed) < 0.2 { lcg(&mut seed) * 12.0 } else { 0.0 };
                Vec3::new(x, y, 0.05 * x + canopy + lcg(&mut seed) * 0.1)
            })
            .collect();
        terrain.extend([Vec3::new(5000.0, 0.0, 0.0), Vec3::new(-300.0, 900.0, 40.0)]);
        let sphere: Vec<Vec3> = (0..8000)
            .map(|_| {
                let v = Vec3::new(lcg(&mut seed) - 0.5, lcg(&mut seed) - 0.5, lcg(&mut seed) - 0.5);
                v.normalize_or(Vec3::X)
            })
            .collect();
        for (name, points) in [("terrain", terrain), ("sphere", sphere)] {
            let k = 16;
            let (_, left) = super::super::grid_knn::k_nearest(&points, points.len(), k, &|_| {})
                .expect("a grid suits these clouds");
            assert!(
                left.len() * 100 <= points.len(),
                "{name}: {} of {} points left to the tree",
                left.len(),
                points.len()
            );
            // The rows the grid found, completed by the tree, against the tree alone.
            let grid = k_nearest(&points, k, &|_| {});
            let tree = k_nearest_in_tree(&points, points.len(), k, &|_| {});
            for i in 0..points.len() {
                let distances = |nb: &Neighbours| {
                    nb.of(i).iter().map(|&j| points[j as usize].distance(points[i])).collect::<Vec<f32>>()
                };
                for (a, b) in distances(&grid).iter().zip(distances(&tree)) {
                    assert!((a - b).abs() <= 1e-6 * b.max(1.0), "{name}: point {i}: {a} vs {b}");
                }
            }
        }
    }

    /// The rows of the first points, the rest serving only as neighbours,
    /// are the rows those points have among all of them; the rest get none.
    #[test]
    fn the_first_points_rows_are_their_rows_among_all_the_points() {
        let mut seed = 11;
        let points: Vec<Vec3> =
            (0..6000).map(|_| Vec3::new(lcg(&mut seed) * 40.0, lcg(&mut seed) * 40.0, lcg(&mut seed) * 0.2)).collect();
        let (k, queries) = (16, 2500);
        let all = k_nearest(&points, k, &|_| {});
        let first = k_nearest_of_first(&points, queries, k, &|_| {});
        assert_eq!(first.rows(), queries);
        let rows = |nb: &Neighbours| (0..queries).flat_map(|i| nb.of(i).to_vec()).collect::<Vec<u32>>();
        assert_eq!(rows(&first), rows(&all));
        assert!(rows(&first).iter().any(|&j| j as usize >= queries), "later points are neighbours too");
        let tree_first = k_nearest_in_tree(&points, queries, k, &|_| {});
        let tree_all = k_nearest_in_tree(&points, points.len(), k, &|_| {});
        assert_eq!(tree_first.rows(), queries, "the tree makes rows for the first points only");
        assert_eq!(rows(&tree_first), rows(&tree_all));
    }
}
