//! Point grouping (Zhang & Pajarola 2007 §4): splitting the splats into K
//! groups whose members overlap as little as possible, for deferred blending.
//!
//! - [`mgc`]: minimal graph colouring, largest first (§4.1); K comes out of it.
//! - [`wgc`]: weighted graph colouring with a given K (§4.2, Eq. 6-8).
//! - [`hash`]: dynamic hash grouping (§4.3, Eq. 9, Fig. 9), fast enough per frame;
//!   [`regroup`] does it frame after frame, incrementally.
//! - [`extend`]: extended grouping for transparency (§4.4.2): duplication or radius enlargement.
//! - [`metrics`]: overlap factor (§6.1), violations, coverage.
//! - [`spec`]: a grouping by name (`wgc-k4-dup`): algorithm, relaxations, extension.
//!
//! A [`Grouping`] is a permutation of the splats with one contiguous range per
//! group, ready to upload; [`cache`] stores it keyed by the model and parameters.

pub mod area;
pub mod cache;
pub mod extend;
pub mod hash;
mod hash_options;
pub(crate) mod labels;
pub mod metrics;
pub mod mgc;
pub mod regroup;
pub mod spec;
pub mod table;
pub mod wgc;

pub use spec::{Extension, GroupingAlgo, GroupingReport, GroupingSpec, Relaxations, Tuning};

use std::ops::Range;

/// Splats ordered group by group.
#[derive(Debug, Clone, PartialEq)]
pub struct Grouping {
    /// Splat indices, group 0 first; a splat may appear in several groups
    /// after extension by duplication.
    pub order: Vec<u32>,
    /// `order[ranges[k]]` are the splats of group k.
    pub ranges: Vec<Range<u32>>,
    /// Per group, the factor its splats' radii are multiplied by (1 unless enlarged).
    pub radius_scale: Vec<f32>,
}

impl Grouping {
    /// Builds the grouping from one group label per splat (labels < `k`).
    pub fn from_labels(labels: &[u32], k: usize) -> Self {
        let k = k.max(1);
        let mut counts = vec![0u32; k + 1];
        for &l in labels {
            counts[(l as usize).min(k - 1) + 1] += 1;
        }
        for g in 0..k {
            counts[g + 1] += counts[g];
        }
        let ranges: Vec<Range<u32>> = (0..k).map(|g| counts[g]..counts[g + 1]).collect();
        let mut fill = counts;
        let mut order = vec![0u32; labels.len()];
        for (i, &l) in labels.iter().enumerate() {
            let g = (l as usize).min(k - 1);
            order[fill[g] as usize] = i as u32;
            fill[g] += 1;
        }
        Self { order, ranges, radius_scale: vec![1.0; k] }
    }

    /// Number of groups K.
    pub fn k(&self) -> usize {
        self.ranges.len()
    }

    /// The splats of group `g`.
    pub fn group(&self, g: usize) -> &[u32] {
        let r = &self.ranges[g];
        &self.order[r.start as usize..r.end as usize]
    }

    pub fn sizes(&self) -> Vec<usize> {
        self.ranges.iter().map(|r| (r.end - r.start) as usize).collect()
    }

    /// The group of each splat (its first group, if duplicated), or `u32::MAX` for none.
    pub fn labels(&self, splats: usize) -> Vec<u32> {
        let mut labels = vec![u32::MAX; splats];
        for g in (0..self.k()).rev() {
            for &i in self.group(g) {
                if let Some(l) = labels.get_mut(i as usize) {
                    *l = g as u32;
                }
            }
        }
        labels
    }
}

/// Errors from grouping.
#[derive(Debug, thiserror::Error)]
pub enum GroupingError {
    #[error("K must be between 1 and {max}, not {k}")]
    BadK { k: usize, max: usize },
    #[error("c must be in 0..=1, not {0}")]
    BadC(f32),
    #[error("cache {path}: {reason}")]
    Cache { path: std::path::PathBuf, reason: String },
}

/// Largest K any algorithm accepts.
pub const MAX_GROUPS: usize = 64;
