//! A grouping as the CLI, the cache, the viewer and `bench` name it: the
//! algorithm with its parameter, the overlap relaxations of §4.1 its graph
//! uses, and the extension of §4.4.2 that makes every group cover the surface
//! (what the transparent algorithms need).
//!
//! Written `ALGO-PARAM[-FLAG...]`, flags in this order:
//! - `mgc-cC`, `wgc-kK`, `hash-kK` (Zhang & Pajarola §4.1, §4.2, §4.3);
//! - `kept` (hash): leave splats where they hash instead of resolving
//!   collisions (Fig. 9);
//! - `eq7` (wgc): MinimizeOverlap picks the colour of least Eq. 7 weight
//!   instead of the paper's least overlap area ΣA_ij;
//! - `coplanar`, `opposite` (mgc, wgc): relaxations (1) and (2) of §4.1, no
//!   edge between nearly coplanar splats of one colour, or between splats
//!   whose normals point opposite ways;
//! - `dup` or `radius`: extension (1) duplication or (2) radius enlargement.
//!
//! E.g. `mgc-c0.4` (the opaque default), `wgc-k4-dup`, `hash-k8-radius`,
//! `mgc-c1-coplanar-opposite`.

use super::{Grouping, GroupingError, MAX_GROUPS, cache, extend, hash, mgc, wgc};
use crate::spatial::overlap::OverlapOptions;

/// The grouping algorithm and its own parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GroupingAlgo {
    Mgc {
        c: f32,
    },
    /// `eq7`: MinimizeOverlap by Eq. 7 weights rather than plain overlap area.
    Wgc {
        k: usize,
        eq7: bool,
    },
    /// `resolve_collisions`: splats that overlap in a hash cell are moved to
    /// another group (Fig. 9's collision handling), or left where they hash.
    Hash {
        k: usize,
        resolve_collisions: bool,
    },
}

/// Relaxations (1) and (2) of the overlap graph (§4.1); (3) is MGC's c.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Relaxations {
    pub coplanar: bool,
    pub opposite: bool,
}

/// Extended grouping (§4.4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Extension {
    #[default]
    None,
    /// (1): splats of other groups are duplicated into a group where it has holes.
    Duplicate,
    /// (2): each group's radii are enlarged by Eq. 13 until it covers the surface.
    Enlarge,
}

/// A grouping algorithm with its parameter, relaxations and extension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupingSpec {
    pub algo: GroupingAlgo,
    pub relax: Relaxations,
    pub extension: Extension,
}

impl Default for GroupingSpec {
    /// The paper's setting for opaque rendering (§6.2): MGC at c = 0.4.
    fn default() -> Self {
        Self::mgc(0.4)
    }
}

impl From<GroupingAlgo> for GroupingSpec {
    fn from(algo: GroupingAlgo) -> Self {
        Self { algo, relax: Relaxations::default(), extension: Extension::None }
    }
}

impl GroupingSpec {
    pub fn mgc(c: f32) -> Self {
        GroupingAlgo::Mgc { c }.into()
    }

    pub fn wgc(k: usize) -> Self {
        GroupingAlgo::Wgc { k, eq7: false }.into()
    }

    pub fn hash(k: usize, resolve_collisions: bool) -> Self {
        GroupingAlgo::Hash { k, resolve_collisions }.into()
    }

    /// This spec with `extension`.
    pub fn extended(self, extension: Extension) -> Self {
        Self { extension, ..self }
    }

    /// The overlap graph options of a graph algorithm.
    fn overlap(&self, c: f32) -> OverlapOptions {
        OverlapOptions { c, skip_opposite_normals: self.relax.opposite, skip_coplanar_same_colour: self.relax.coplanar }
    }

    /// Groups `cloud`.
    pub fn compute(&self, cloud: &crate::cloud::PointCloud) -> Result<Grouping, GroupingError> {
        crate::progress::stage(&format!("grouping {self}"));
        let base = match self.algo {
            GroupingAlgo::Mgc { c } => mgc::group(cloud, &self.overlap(c))?.0,
            GroupingAlgo::Wgc { k, eq7 } => {
                let options =
                    wgc::WgcOptions { k, minimize_by_eq7: eq7, overlap: self.overlap(1.0), ..Default::default() };
                wgc::group(cloud, &options)?.0
            }
            GroupingAlgo::Hash { k, resolve_collisions } => {
                let collisions = if resolve_collisions { hash::Collisions::All } else { hash::Collisions::None };
                hash::group(cloud, &hash::HashOptions { k, collisions })?.0
            }
        };
        Ok(match self.extension {
            Extension::None => base,
            Extension::Duplicate => {
                crate::progress::stage("duplicating splats into the groups' holes");
                extend::duplicate(cloud, &base)
            }
            Extension::Enlarge => {
                crate::progress::stage("enlarging the groups' radii");
                extend::enlarge(cloud, &base).0
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
        match crate::hash::file_hash(model) {
            Ok(hash) => self.compute_cached_for_hash(cache, hash, cloud),
            Err(_) => Ok((self.compute(cloud)?, false)), // unreadable: no cache
        }
    }

    /// [`Self::compute_cached`] for a model whose [`crate::hash::file_hash`] is known.
    pub fn compute_cached_for_hash(
        &self,
        cache: &cache::Cache,
        file_hash: u64,
        cloud: &crate::cloud::PointCloud,
    ) -> Result<(Grouping, bool), GroupingError> {
        // v2: WGC's MinimizeOverlap by area and its re-queueing changed its results;
        // v3: duplication takes the most clipped splat first (§4.4.2).
        let key = cache::key_for_hash(file_hash, &format!("spec|{self}|v3"));
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

impl std::fmt::Display for GroupingSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.algo {
            GroupingAlgo::Mgc { c } => write!(f, "mgc-c{c}")?,
            GroupingAlgo::Wgc { k, eq7 } => write!(f, "wgc-k{k}{}", if eq7 { "-eq7" } else { "" })?,
            GroupingAlgo::Hash { k, resolve_collisions } => {
                write!(f, "hash-k{k}{}", if resolve_collisions { "" } else { "-kept" })?
            }
        }
        if self.relax.coplanar {
            f.write_str("-coplanar")?;
        }
        if self.relax.opposite {
            f.write_str("-opposite")?;
        }
        match self.extension {
            Extension::None => Ok(()),
            Extension::Duplicate => f.write_str("-dup"),
            Extension::Enlarge => f.write_str("-radius"),
        }
    }
}

impl std::str::FromStr for GroupingSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || {
            format!(
                "'{s}' is not a grouping; use mgc-cC, wgc-kK or hash-kK, then any of -kept (hash), -eq7 (wgc), \
                 -coplanar, -opposite (mgc, wgc), -dup or -radius (e.g. mgc-c0.4, wgc-k4-dup, hash-k8-radius)"
            )
        };
        let mut words = s.split('-');
        let (algo, value) = (words.next().ok_or_else(bad)?, words.next().ok_or_else(bad)?);
        let number = |prefix: char| value.strip_prefix(prefix).ok_or_else(bad);
        let mut spec: GroupingSpec = match algo {
            "mgc" => GroupingAlgo::Mgc { c: number('c')?.parse().map_err(|_| bad())? },
            "wgc" => GroupingAlgo::Wgc { k: number('k')?.parse().map_err(|_| bad())?, eq7: false },
            "hash" => GroupingAlgo::Hash { k: number('k')?.parse().map_err(|_| bad())?, resolve_collisions: true },
            _ => return Err(bad()),
        }
        .into();
        for flag in words {
            let graph = !matches!(spec.algo, GroupingAlgo::Hash { .. });
            match (flag, &mut spec.algo) {
                ("kept", GroupingAlgo::Hash { resolve_collisions, .. }) => *resolve_collisions = false,
                ("eq7", GroupingAlgo::Wgc { eq7, .. }) => *eq7 = true,
                ("coplanar", _) if graph => spec.relax.coplanar = true,
                ("opposite", _) if graph => spec.relax.opposite = true,
                ("dup", _) if spec.extension == Extension::None => spec.extension = Extension::Duplicate,
                ("radius", _) if spec.extension == Extension::None => spec.extension = Extension::Enlarge,
                _ => return Err(format!("{}: '-{flag}' does not apply here", bad())),
            }
        }
        match spec.algo {
            GroupingAlgo::Mgc { c } if !(0.0..=1.0).contains(&c) => Err(format!("c must be in 0..=1, not {c}")),
            GroupingAlgo::Wgc { k, .. } | GroupingAlgo::Hash { k, .. } if k == 0 || k > MAX_GROUPS => {
                Err(format!("K must be 1..={MAX_GROUPS}, not {k}"))
            }
            _ => Ok(spec),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_flag_round_trips_and_misplaced_flags_are_refused() {
        for text in [
            "mgc-c0.4",
            "wgc-k8",
            "wgc-k4-eq7-dup",
            "hash-k8-kept",
            "hash-k8-radius",
            "mgc-c1-coplanar-opposite",
            "wgc-k4-opposite-radius",
        ] {
            let spec: GroupingSpec = text.parse().unwrap();
            assert_eq!(spec.to_string(), text);
        }
        for wrong in ["hash-k8-coplanar", "mgc-c0.4-kept", "hash-k8-eq7", "wgc-k4-dup-radius", "wgc-k4-x", "wgc-k0"] {
            assert!(wrong.parse::<GroupingSpec>().is_err(), "{wrong}");
        }
    }
}
