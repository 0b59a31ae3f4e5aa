//! k-nearest-neighbour lists for every point, from a `kiddo` k-d tree.
//!
//! Queries run in parallel with rayon. The result is a flat table of `k`
//! neighbour indices and distances per point (the point itself excluded);
//! clouds with fewer than `k + 1` points get padded rows.

use std::num::NonZero;

use glam::Vec3;
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use rayon::prelude::*;

/// `k` neighbours per point, row-major.
#[derive(Debug, Clone)]
pub struct Neighbours {
    pub k: usize,
    /// `indices[i * k + j]`: the j-th nearest neighbour of point i.
    pub indices: Vec<u32>,
    /// Euclidean distances matching `indices`.
    pub distances: Vec<f32>,
}

impl Neighbours {
    pub fn of(&self, i: usize) -> &[u32] {
        &self.indices[i * self.k..(i + 1) * self.k]
    }

    pub fn distances_of(&self, i: usize) -> &[f32] {
        &self.distances[i * self.k..(i + 1) * self.k]
    }
}

/// Finds the `k` nearest neighbours of every point (excluding itself).
///
/// When the cloud has `k` points or fewer, missing entries repeat the point
/// itself with distance 0.
pub fn k_nearest(points: &[Vec3], k: usize, on_progress: &(dyn Fn(u64) + Sync)) -> Neighbours {
    let k = k.max(1);
    let coords: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    // Bucket size 64 keeps clouds with many duplicate points from overflowing leaves.
    let tree: ImmutableKdTree<f32, u32, 3, 64> = ImmutableKdTree::new_from_slice(&coords);
    let want = NonZero::new(k + 1).expect("k + 1 > 0");
    let mut indices = vec![0u32; points.len() * k];
    let mut distances = vec![0f32; points.len() * k];
    const CHUNK: usize = 4096;
    indices.par_chunks_mut(CHUNK * k).zip(distances.par_chunks_mut(CHUNK * k)).enumerate().for_each(
        |(chunk, (idx, dist))| {
            let first = chunk * CHUNK;
            for (row, (idx_row, dist_row)) in idx.chunks_mut(k).zip(dist.chunks_mut(k)).enumerate() {
                let i = first + row;
                let found = tree.nearest_n::<SquaredEuclidean>(&coords[i], want);
                let mut j = 0;
                for nb in found.iter().filter(|nb| nb.item as usize != i).take(k) {
                    idx_row[j] = nb.item;
                    dist_row[j] = nb.distance.max(0.0).sqrt();
                    j += 1;
                }
                for slot in j..k {
                    idx_row[slot] = i as u32;
                    dist_row[slot] = 0.0;
                }
            }
            on_progress((idx.len() / k) as u64);
        },
    );
    Neighbours { k, indices, distances }
}
