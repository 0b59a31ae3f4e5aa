//! The exact baseline: every splat's view depth packed with its index into a
//! u64 key, then one comparison sort (rayon's parallel unstable sort).

use glam::Vec3;
use rayon::prelude::*;

use super::ViewRay;

/// Maps an f32 to a u32 with the same order (negative values included).
pub(super) fn ordered_bits(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits & 0x8000_0000 != 0 { !bits } else { bits | 0x8000_0000 }
}

/// `points`' indices sorted by decreasing view depth into `out`.
pub fn full_sort(points: &[Vec3], view: ViewRay, out: &mut Vec<u32>) {
    let mut keys: Vec<u64> =
        points.par_iter().enumerate().map(|(i, p)| ((!ordered_bits(view.depth(*p)) as u64) << 32) | i as u64).collect();
    keys.par_sort_unstable();
    out.clear();
    out.extend(keys.iter().map(|k| *k as u32));
}
