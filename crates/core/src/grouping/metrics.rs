//! Grouping quality: the overlap factor of §6.1, independence violations and coverage.
//!
//! - Overlap factor (Zhang & Pajarola 2007 §6.1, Table 2): for splat i, the sum
//!   over same-group splats k that overlap it of (r_i + r_k - |p_i - p_k|) /
//!   ((r_i + r_k)/2), which is the paper's (2r - |p_i - p_k|)/r for equal
//!   radii; averaged over all group members.
//! - Violations: same-group pairs that overlap by Eq. 5 (c = 1, no relaxation).
//! - Coverage: the surface is sampled at the splat centres; group k covers a
//!   sample when one of its splats (radius times the group's scale) contains
//!   it. [`nearest_cover`] gives, per sample and group, the smallest
//!   |p_j - p_i|/r_i over the group, so coverage at any radius scale is a count.
//!   Each splat's scan of the samples near it stops after [`MAX_COVER_SCAN`]
//!   (never reached on the real scans), so a crowd of thousands of splats at
//!   one spot costs O(n); such a crowd's coverage is then an underestimate.

use rayon::prelude::*;

use super::Grouping;
use crate::cloud::PointCloud;
use crate::spatial::grid::{HashGrid, typical_radius};
use crate::spatial::overlap::{OverlapGraph, OverlapOptions};

/// Quality figures of a grouping.
#[derive(Debug, Clone, serde::Serialize)]
pub struct GroupingMetrics {
    pub k: usize,
    pub group_sizes: Vec<usize>,
    pub overlap_factor: f64,
    pub violations: usize,
    /// Per group, the share of the surface samples it covers.
    pub coverage: Vec<f64>,
    /// Mean of `coverage`.
    pub mean_coverage: f64,
    /// Splats in all groups over splats in the model, minus 1 (0 without duplication).
    pub duplication_ratio: f64,
}

/// Samples one splat's cover scan visits, at most: far above what a real
/// scan's splat reaches within 4 radii, a bound on time where splats crowd.
pub const MAX_COVER_SCAN: usize = 16384;

/// For every splat centre j and group g: min over splats i of g of |p_j - p_i| / r_i,
/// for values below `max_ratio` (else infinity). Row-major, K per splat.
///
/// Each splat scatters to the samples within `max_ratio`·r_i of it, so the
/// search follows the splat's own radius; threads fill private tables that
/// are merged by minimum.
pub fn nearest_cover(cloud: &PointCloud, grouping: &Grouping, max_ratio: f32) -> Vec<f32> {
    let (n, k) = (cloud.len(), grouping.k());
    if n == 0 || k == 0 {
        return vec![f32::INFINITY; n * k];
    }
    let grid = HashGrid::new(&cloud.positions, (max_ratio * typical_radius(&cloud.radii)).max(f32::MIN_POSITIVE));
    let members: Vec<(u32, u32)> = (0..k).flat_map(|g| grouping.group(g).iter().map(move |&i| (i, g as u32))).collect();
    members
        .par_chunks(8192)
        .fold(
            || vec![f32::INFINITY; n * k],
            |mut nearest, chunk| {
                for &(i, g) in chunk {
                    let i = i as usize;
                    let (pi, ri) = (cloud.positions[i], cloud.radii[i]);
                    let reach = (max_ratio * ri / grid.cell_size()).ceil() as i32;
                    // Capped, so that crowds of splats cost O(n) scans, not O(n²);
                    // each starts at its own place, so a crowd's scans see all of it between them.
                    grid.scan_near(pi, reach, MAX_COVER_SCAN, i, |j| {
                        let ratio = pi.distance(cloud.positions[j as usize]) / ri;
                        if ratio < max_ratio {
                            let slot = &mut nearest[j as usize * k + g as usize];
                            *slot = slot.min(ratio);
                        }
                        true
                    });
                }
                nearest
            },
        )
        .reduce(
            || vec![f32::INFINITY; n * k],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x = x.min(y));
                a
            },
        )
}

/// Share of samples that group g covers with radii scaled by `scale`.
pub fn coverage_at(nearest: &[f32], k: usize, g: usize, scale: f32) -> f64 {
    let n = nearest.len() / k.max(1);
    if n == 0 {
        return 0.0;
    }
    nearest.chunks(k).filter(|row| row[g] < scale).count() as f64 / n as f64
}

/// Measures `grouping` of `cloud`.
pub fn measure(cloud: &PointCloud, grouping: &Grouping) -> GroupingMetrics {
    let k = grouping.k();
    let (p, r) = (&cloud.positions, &cloud.radii);
    let graph = OverlapGraph::build(cloud.discs(), &OverlapOptions::default());
    let mut in_group = vec![0u64; cloud.len()];
    for g in 0..k {
        for &i in grouping.group(g) {
            if let Some(bits) = in_group.get_mut(i as usize) {
                *bits |= 1u64 << g.min(63);
            }
        }
    }
    // Per member (splat, group): overlap factor and violations with same-group splats.
    let (overlap_sum, violations, members) = (0..k)
        .into_par_iter()
        .map(|g| {
            let bit = 1u64 << g.min(63);
            let (mut sum, mut violations) = (0.0f64, 0usize);
            for &i in grouping.group(g) {
                let i = i as usize;
                for &j in graph.neighbours_of(i) {
                    let j = j as usize;
                    if in_group[j] & bit != 0 {
                        let reach = r[i] + r[j];
                        sum += ((reach - p[i].distance(p[j])) / (0.5 * reach)) as f64;
                        violations += (j > i) as usize;
                    }
                }
            }
            (sum, violations, grouping.group(g).len())
        })
        .reduce(|| (0.0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
    let max_scale = grouping.radius_scale.iter().copied().fold(1.0f32, f32::max);
    let nearest = nearest_cover(cloud, grouping, max_scale * 1.001);
    let coverage: Vec<f64> =
        (0..k).map(|g| coverage_at(&nearest, k, g, grouping.radius_scale.get(g).copied().unwrap_or(1.0))).collect();
    GroupingMetrics {
        k,
        group_sizes: grouping.sizes(),
        overlap_factor: if members > 0 { overlap_sum / members as f64 } else { 0.0 },
        violations,
        mean_coverage: coverage.iter().sum::<f64>() / k.max(1) as f64,
        coverage,
        duplication_ratio: if cloud.is_empty() { 0.0 } else { members as f64 / cloud.len() as f64 - 1.0 },
    }
}
