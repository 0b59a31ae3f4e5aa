//! Gunjee et al.'s hierarchical bucket sort (§4.2, Eq. 10-13): a view-aligned
//! slicing of the splats into slabs of thickness ε, back to front, without
//! sorting inside a slab.
//!
//! Step 1 finds the nearest and farthest view depths (Eq. 12). The depth
//! range holds N_slices = (far - near)/ε slices (Eq. 10), served by
//! N = ⌈√N_slices⌉ first-level buckets of N·ε each and N accurate buckets of
//! ε (Eq. 11). Step 2 distributes the splats into the
//! first-level buckets (Eq. 13); step 3 takes those back to front and
//! distributes each non-empty one into the accurate buckets, whose runs are
//! appended back to front to the result. Both distributions are counting
//! sorts (count, prefix sum, scatter), so the whole is O(n + N·used first
//! level buckets) with two buffers of n entries.
//!
//! ε is Gunjee's smallest splat size, here the smallest radius, but never
//! thinner than the depth range over 2^22 slices (so N stays ≤ 2048).

use glam::Vec3;
use rayon::prelude::*;

use super::ViewRay;

/// At most this many slices (Eq. 10), so that N (Eq. 11) stays ≤ 2048.
pub const MAX_SLICES: f32 = (1u32 << 22) as f32;

/// A splat's two bucket numbers (first level, accurate; both counted from the
/// far end) and its index, packed: bits 43.. first level, 32..43 accurate.
type Packed = u64;

const LOW_BITS: u32 = 11;

fn pack(first: u32, accurate: u32, index: u32) -> Packed {
    ((first as u64) << (32 + LOW_BITS)) | ((accurate as u64) << 32) | index as u64
}

fn first_of(p: Packed) -> usize {
    (p >> (32 + LOW_BITS)) as usize
}

fn accurate_of(p: Packed) -> usize {
    ((p >> 32) as usize) & ((1 << LOW_BITS) - 1)
}

/// The slicer, with its buffers kept between views.
#[derive(Debug, Clone, Default)]
pub struct BucketSort {
    /// The slab thickness ε asked for.
    pub epsilon: f32,
    keys: Vec<Packed>,
    first_level: Vec<Packed>,
}

impl BucketSort {
    /// A slicer of slab thickness `epsilon`.
    pub fn new(epsilon: f32) -> Self {
        Self { epsilon, ..Default::default() }
    }

    /// Gunjee's choice: ε is the smallest splat size (radius).
    pub fn for_radii(radii: &[f32]) -> Self {
        Self::new(radii.iter().copied().filter(|r| *r > 0.0).fold(f32::INFINITY, f32::min))
    }

    /// Writes `points`' indices back to front for `view` into `out` and
    /// returns the slab thickness used.
    pub fn back_to_front(&mut self, points: &[Vec3], view: ViewRay, out: &mut Vec<u32>) -> f32 {
        out.clear();
        if points.is_empty() {
            return 0.0;
        }
        // Step 1: the range of the depths (Eq. 12).
        let (near, far) = points
            .par_iter()
            .fold(
                || (f32::INFINITY, f32::NEG_INFINITY),
                |(lo, hi), p| {
                    let d = view.depth(*p);
                    (lo.min(d), hi.max(d))
                },
            )
            .reduce(|| (f32::INFINITY, f32::NEG_INFINITY), |a, b| (a.0.min(b.0), a.1.max(b.1)));
        let range = far - near;
        if range.is_nan() || range <= 0.0 {
            out.extend(0..points.len() as u32);
            return 0.0;
        }
        // Eq. 10 and 11.
        let wanted = if self.epsilon.is_finite() && self.epsilon > 0.0 { self.epsilon } else { range };
        let slices = (range / wanted).ceil().clamp(1.0, MAX_SLICES) as u32;
        let epsilon = range / slices as f32;
        let buckets = ((slices as f32).sqrt().ceil() as u32).max(1);
        // Each splat's slice, counted from the far end, as its first-level
        // bucket (Eq. 13: slice / N, the first level being N slices thick) and
        // its accurate bucket within it, computed once and in parallel.
        let per_depth = slices as f32 / range;
        points
            .par_iter()
            .enumerate()
            .map(|(i, p)| {
                let slice = (((view.depth(*p) - near) * per_depth) as u32).min(slices - 1);
                let from_far = slices - 1 - slice;
                let first = from_far / buckets;
                pack(first, from_far - first * buckets, i as u32)
            })
            .collect_into_vec(&mut self.keys);

        // Step 2: the first-level buckets (a counting sort).
        let mut starts = vec![0u32; buckets as usize + 1];
        for &k in &self.keys {
            starts[first_of(k) + 1] += 1;
        }
        for b in 0..buckets as usize {
            starts[b + 1] += starts[b];
        }
        let mut fill = starts.clone();
        self.first_level.clear();
        self.first_level.resize(points.len(), 0);
        for &k in &self.keys {
            let b = first_of(k);
            self.first_level[fill[b] as usize] = k;
            fill[b] += 1;
        }

        // Step 3: each first-level bucket into the accurate buckets, back to
        // front. The buckets own disjoint runs of the output, so they run in
        // parallel.
        out.resize(points.len(), 0);
        let mut runs = Vec::with_capacity(buckets as usize);
        let mut rest: &mut [u32] = out;
        for b in 0..buckets as usize {
            let (run, tail) = rest.split_at_mut((starts[b + 1] - starts[b]) as usize);
            rest = tail;
            let items = &self.first_level[starts[b] as usize..starts[b + 1] as usize];
            if !items.is_empty() {
                runs.push((items, run));
            }
        }
        let accurate_buckets = buckets as usize;
        runs.into_par_iter().for_each_init(
            || vec![0u32; accurate_buckets + 1],
            |counts, (items, run)| {
                counts.fill(0);
                for &k in items {
                    counts[accurate_of(k) + 1] += 1;
                }
                for a in 0..accurate_buckets {
                    counts[a + 1] += counts[a];
                }
                for &k in items {
                    let a = accurate_of(k);
                    run[counts[a] as usize] = k as u32;
                    counts[a] += 1;
                }
            },
        );
        epsilon
    }
}
