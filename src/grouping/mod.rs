//! Point grouping (Zhang & Pajarola 2007 §4): splitting the splats into K
//! groups whose members overlap as little as possible, for deferred blending.
//!
//! - [`mgc`]: minimal graph colouring, largest first (§4.1); K comes out of it.
//! - [`wgc`]: weighted graph colouring with a given K (§4.2, Eq. 6-8).
//! - [`hash`]: dynamic hash grouping (§4.3, Eq. 9, Fig. 9), fast enough per frame.
//! - [`extend`]: extended grouping for transparency (§4.4.2): duplication or radius enlargement.
//! - [`metrics`]: overlap factor (§6.1), violations, coverage.
//!
//! A [`Grouping`] is a permutation of the splats with one contiguous range per
//! group, ready to upload; [`cache`] stores it keyed by the model and parameters.

pub mod area;
pub mod cache;
pub mod extend;
pub mod hash;
pub mod metrics;
pub mod mgc;
pub mod wgc;

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

/// A grouping algorithm with its parameter, as the render modes name it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GroupingSpec {
    Mgc {
        c: f32,
    },
    Wgc {
        k: usize,
    },
    /// `resolve_collisions`: splats that overlap in a hash cell are moved to
    /// another group (Fig. 9's collision handling), or left where they hash.
    Hash {
        k: usize,
        resolve_collisions: bool,
    },
}

impl Default for GroupingSpec {
    /// The paper's setting for opaque rendering (§6.2): MGC at c = 0.4.
    fn default() -> Self {
        GroupingSpec::Mgc { c: 0.4 }
    }
}

impl std::fmt::Display for GroupingSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GroupingSpec::Mgc { c } => write!(f, "mgc-c{c}"),
            GroupingSpec::Wgc { k } => write!(f, "wgc-k{k}"),
            GroupingSpec::Hash { k, resolve_collisions: true } => write!(f, "hash-k{k}"),
            GroupingSpec::Hash { k, resolve_collisions: false } => write!(f, "hash-k{k}-kept"),
        }
    }
}

impl std::str::FromStr for GroupingSpec {
    type Err = String;
    /// `mgc-c0.4`, `wgc-k8`, `hash-k8`, and `hash-k8-kept` for hashing that keeps collisions.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad =
            || format!("'{s}' is not a grouping; use mgc-cC, wgc-kK, hash-kK or hash-kK-kept (e.g. mgc-c0.4, wgc-k8)");
        let (algo, value) = s.split_once('-').ok_or_else(bad)?;
        let (value, resolve_collisions) = match value.strip_suffix("-kept") {
            Some(v) if algo == "hash" => (v, false),
            _ => (value, true),
        };
        let number = |prefix: char| value.strip_prefix(prefix).ok_or_else(bad);
        let spec = match algo {
            "mgc" => GroupingSpec::Mgc { c: number('c')?.parse().map_err(|_| bad())? },
            "wgc" => GroupingSpec::Wgc { k: number('k')?.parse().map_err(|_| bad())? },
            "hash" => GroupingSpec::Hash { k: number('k')?.parse().map_err(|_| bad())?, resolve_collisions },
            _ => return Err(bad()),
        };
        match spec {
            GroupingSpec::Mgc { c } if !(0.0..=1.0).contains(&c) => Err(format!("c must be in 0..=1, not {c}")),
            GroupingSpec::Wgc { k } | GroupingSpec::Hash { k, .. } if k == 0 || k > MAX_GROUPS => {
                Err(format!("K must be 1..={MAX_GROUPS}, not {k}"))
            }
            _ => Ok(spec),
        }
    }
}

impl GroupingSpec {
    /// Groups `cloud`.
    pub fn compute(&self, cloud: &crate::cloud::PointCloud) -> Result<Grouping, GroupingError> {
        use crate::spatial::overlap::OverlapOptions;
        crate::progress::stage(&format!("grouping {self}"));
        Ok(match *self {
            GroupingSpec::Mgc { c } => mgc::group(cloud, &OverlapOptions { c, ..Default::default() })?.0,
            GroupingSpec::Wgc { k } => wgc::group(cloud, &wgc::WgcOptions { k, ..Default::default() })?.0,
            GroupingSpec::Hash { k, resolve_collisions } => {
                let collisions = if resolve_collisions { hash::Collisions::All } else { hash::Collisions::None };
                hash::group(cloud, &hash::HashOptions { k, collisions })?.0
            }
        })
    }

    /// Groups the cloud loaded from `model`, through `cache`; returns the
    /// grouping and whether it came from the cache.
    pub fn compute_cached(
        &self,
        cache: &cache::Cache,
        model: &std::path::Path,
        cloud: &crate::cloud::PointCloud,
    ) -> Result<(Grouping, bool), GroupingError> {
        match cache::file_hash(model) {
            Ok(hash) => self.compute_cached_for_hash(cache, hash, cloud),
            Err(_) => Ok((self.compute(cloud)?, false)), // unreadable: no cache
        }
    }

    /// [`Self::compute_cached`] for a model whose [`cache::file_hash`] is known.
    pub fn compute_cached_for_hash(
        &self,
        cache: &cache::Cache,
        file_hash: u64,
        cloud: &crate::cloud::PointCloud,
    ) -> Result<(Grouping, bool), GroupingError> {
        let key = cache::key_for_hash(file_hash, &format!("spec|{self}|v1"));
        if let Some(g) = cache.load(key, cloud.len()) {
            return Ok((g, true));
        }
        let g = self.compute(cloud)?;
        if let Err(e) = cache.store(key, &g, cloud.len()) {
            log::warn!("{e}");
        }
        Ok((g, false))
    }
}
