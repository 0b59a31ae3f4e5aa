//! Coincident splats merged on load.
//!
//! Splats with the same centre, normal and radius (bit for bit, after the
//! f64 re-centring; the centre's residual too, so two points 1 mm apart far
//! from the origin stay two) are one surface sample drawn several times: files carry
//! them where tiles or scans were exported twice. They are merged into one
//! splat whose colour and opacity are the means of theirs. Every renderer
//! that normalises a layer (Zhang & Pajarola Eq. 1: Σw·c/Σw, Σw·α/Σw) gives
//! the same image for the merged splat, since coincident discs carry equal
//! weights at every pixel; only plain α-blending, which blends one surface as
//! often as its discs overlap, sees fewer blends. Without merging, the point
//! grouping of §4 needs one group per copy (the copies all overlap), and its
//! overlap graph holds n² pairs.
//!
//! A normal or radius the file lacks (to be estimated) counts as equal among
//! copies: copies at one position get the same estimate.

use std::hash::{Hash, Hasher};

use rayon::prelude::*;
use rustc_hash::FxHasher;

use super::PointCloud;

/// What a splat is, bit for bit: position (and its residual), and the
/// normal and radius when the file gives them.
type Key = ([u32; 3], [u32; 3], Option<[u32; 3]>, Option<u32>);

/// Merges coincident splats of `cloud` in place (`needs_normal` and
/// `needs_radius` say which attributes are still to be estimated, and are
/// compacted with it); returns how many splats were merged away.
pub fn merge(cloud: &mut PointCloud, needs_normal: &mut Vec<bool>, needs_radius: &mut Vec<bool>) -> usize {
    let before = cloud.len();
    merge_indexed(cloud, needs_normal, needs_radius);
    before - cloud.len()
}

/// [`merge`], returning where each splat went: the index of the splat it
/// now is (its own, moved down, or its representative's).
pub fn merge_indexed(cloud: &mut PointCloud, needs_normal: &mut Vec<bool>, needs_radius: &mut Vec<bool>) -> Vec<u32> {
    let n = cloud.len();
    // -0.0 + 0.0 = +0.0: both zeros are one coordinate.
    let bits = |x: f32| (x + 0.0).to_bits();
    let key = |i: usize| -> Key {
        (
            cloud.positions[i].to_array().map(bits),
            cloud.residuals.get(i).map_or([0; 3], |r| r.to_array().map(bits)),
            (!needs_normal[i]).then(|| cloud.normals[i].to_array().map(bits)),
            (!needs_radius[i]).then(|| bits(cloud.radii[i])),
        )
    };
    let (representative, unique) = representatives(n, &key);
    if unique == n {
        return (0..n as u32).collect();
    }
    // Sums of colour and opacity per representative, then the means.
    let mut sums = vec![([0u64; 3], 0f64, 0u32); n];
    for (i, &r) in representative.iter().enumerate() {
        let s = &mut sums[r as usize];
        for c in 0..3 {
            s.0[c] += cloud.colours[i][c] as u64;
        }
        s.1 += cloud.opacity[i] as f64;
        s.2 += 1;
    }
    let mut write = 0;
    let mut moved_to = vec![0u32; n];
    for (i, &r) in representative.iter().enumerate() {
        if r as usize != i {
            continue;
        }
        moved_to[i] = write as u32;
        let (colour, opacity, count) = sums[i];
        cloud.positions[write] = cloud.positions[i];
        if !cloud.residuals.is_empty() {
            cloud.residuals[write] = cloud.residuals[i];
        }
        cloud.normals[write] = cloud.normals[i];
        cloud.radii[write] = cloud.radii[i];
        cloud.colours[write] = colour.map(|c| ((c as f64 / count as f64).round()).min(255.0) as u8);
        cloud.opacity[write] = (opacity / count as f64) as f32;
        if !cloud.two_sided.is_empty() {
            cloud.two_sided[write] = cloud.two_sided[i];
        }
        needs_normal[write] = needs_normal[i];
        needs_radius[write] = needs_radius[i];
        write += 1;
    }
    cloud.positions.truncate(write);
    if !cloud.residuals.is_empty() {
        cloud.residuals.truncate(write);
    }
    cloud.normals.truncate(write);
    cloud.radii.truncate(write);
    cloud.colours.truncate(write);
    cloud.opacity.truncate(write);
    if !cloud.two_sided.is_empty() {
        cloud.two_sided.truncate(write);
    }
    needs_normal.truncate(write);
    needs_radius.truncate(write);
    representative.iter().map(|&r| moved_to[r as usize]).collect()
}

/// Each splat's representative (the first splat with its key), and how
/// many keys there are.
///
/// The splats are sorted by a hash of their key, in parallel, and only
/// runs of equal hashes are compared: a hash map of the keys took 0.2-0.35 s
/// for a streamed selection of a million points on 2 cores, each time the
/// selection changed. FxHash: the keys are raw float bits, with no
/// adversary to guard against.
fn representatives(n: usize, key: &(dyn Fn(usize) -> Key + Sync)) -> (Vec<u32>, usize) {
    let hash = |i: usize| {
        let mut h = FxHasher::default();
        key(i).hash(&mut h);
        h.finish()
    };
    let mut order: Vec<(u64, u32)> = (0..n).into_par_iter().map(|i| (hash(i), i as u32)).collect();
    order.par_sort_unstable();
    let mut representative: Vec<u32> = (0..n as u32).collect();
    let mut unique = n;
    for run in order.chunk_by(|a, b| a.0 == b.0).filter(|run| run.len() > 1) {
        // Sorted by index within the run: the first of equal keys comes first.
        for (j, &(_, i)) in run.iter().enumerate() {
            let first = run[..j]
                .iter()
                .map(|&(_, f)| f)
                .find(|&f| representative[f as usize] == f && key(f as usize) == key(i as usize));
            if let Some(first) = first {
                representative[i as usize] = first;
                unique -= 1;
            }
        }
    }
    (representative, unique)
}

/// For each of `count` splats, the file vertex it came from: the first of those merged into it.
pub(super) fn first_of_each(merged_into: &[u32], kept: &[usize], count: usize) -> Vec<u32> {
    let mut source = vec![u32::MAX; count];
    for (k, &splat) in merged_into.iter().enumerate() {
        let s = &mut source[splat as usize];
        if *s == u32::MAX {
            *s = kept[k] as u32;
        }
    }
    source
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn cloud(points: &[(Vec3, [u8; 3], f32)]) -> PointCloud {
        PointCloud {
            positions: points.iter().map(|p| p.0).collect(),
            normals: vec![Vec3::Z; points.len()],
            radii: vec![1.0; points.len()],
            colours: points.iter().map(|p| p.1).collect(),
            opacity: points.iter().map(|p| p.2).collect(),
            ..Default::default()
        }
    }

    #[test]
    fn copies_become_one_splat_with_the_mean_colour_and_opacity() {
        let a = Vec3::new(1.0, 0.0, 3.0);
        let b = Vec3::new(1.0, 0.0, 3.000_001);
        let minus_zero = Vec3::new(1.0, -0.0, 3.0);
        let mut c = cloud(&[(a, [200, 100, 100], 0.2), (b, [9, 9, 9], 1.0), (minus_zero, [100, 100, 201], 0.6)]);
        let (mut nn, mut nr) = (vec![false; 3], vec![false; 3]);
        assert_eq!(merge(&mut c, &mut nn, &mut nr), 1);
        assert_eq!(c.positions, vec![a, b], "the first copy's place, the others kept in order");
        assert_eq!(c.colours, vec![[150, 100, 151], [9, 9, 9]]);
        assert!((c.opacity[0] - 0.4).abs() < 1e-6);
        assert_eq!(nn.len(), 2);
    }

    #[test]
    fn a_different_normal_or_radius_is_another_splat_unless_it_is_still_to_be_estimated() {
        let mut c = cloud(&[(Vec3::ZERO, [1, 1, 1], 1.0), (Vec3::ZERO, [3, 3, 3], 1.0)]);
        c.normals[1] = Vec3::X;
        let (mut nn, mut nr) = (vec![false; 2], vec![false; 2]);
        assert_eq!(merge(&mut c.clone(), &mut nn.clone(), &mut nr.clone()), 0);
        nn = vec![true; 2];
        assert_eq!(merge(&mut c, &mut nn, &mut nr), 1);
        assert_eq!(c.colours, vec![[2, 2, 2]]);
    }
}
