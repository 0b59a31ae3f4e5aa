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
//!
//! `pointblend group` turns a few more knobs than a name holds ([`Tuning`]:
//! MGC's search for K groups, WGC's graph c and plain-area weights, hashing's
//! near-only collisions) and prints what the run measured on the way
//! ([`GroupingReport`]); both go through the same computation and cache as a
//! spec, whose cache key is `spec|NAME|v3` (`spec|NAME-TUNING|v3` when tuned).

use std::time::Instant;

use glam::Vec3;

use super::{Grouping, GroupingError, MAX_GROUPS, cache, extend, hash, mgc, wgc};
use crate::cloud::PointCloud;
use crate::spatial::overlap::{OverlapGraph, OverlapOptions};

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

impl GroupingAlgo {
    /// A hash grouping's options, with every collision resolved or none
    /// (`None` for MGC and WGC).
    pub fn hash_options(self) -> Option<hash::HashOptions> {
        let GroupingAlgo::Hash { k, resolve_collisions } = self else { return None };
        let collisions = if resolve_collisions { hash::Collisions::All } else { hash::Collisions::None };
        Some(hash::HashOptions { k, collisions })
    }
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
    /// (2) by §4.4.2's estimate from the hash table's geometry,
    /// [`super::table::cover_scale`] of K (√50/4 for K = 8; Eq. 13 measures
    /// 1.71-1.74 on hash groups of our scans, so the estimate covers): what a
    /// grouping made every frame uses, as Eq. 13 cannot run every frame.
    /// Hash groupings only: MGC's and WGC's groups have no lattice.
    Estimate,
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
    pub fn compute(&self, cloud: &PointCloud) -> Result<Grouping, GroupingError> {
        Ok(self.compute_tuned(cloud, &Tuning::default())?.0)
    }

    /// Groups `cloud` with `tuning`, and says what the run measured.
    pub fn compute_tuned(
        &self,
        cloud: &PointCloud,
        tuning: &Tuning,
    ) -> Result<(Grouping, GroupingReport), GroupingError> {
        crate::progress::stage(&format!("grouping {self}"));
        let mut report = GroupingReport::default();
        let base = match self.algo {
            GroupingAlgo::Mgc { c } => self.group_mgc(cloud, c, tuning, &mut report)?,
            GroupingAlgo::Wgc { k, eq7 } => self.group_wgc(cloud, k, eq7, tuning, &mut report)?,
            GroupingAlgo::Hash { k, resolve_collisions } => {
                let started = Instant::now();
                let collisions = match (resolve_collisions, tuning.near) {
                    (false, _) => hash::Collisions::None,
                    (true, None) => hash::Collisions::All,
                    (true, Some((eye, distance))) => hash::Collisions::Near { eye, distance },
                };
                let (g, resolved) = hash::group(cloud, &hash::HashOptions { k, collisions })?;
                report.stages.push(("hash grouping", started.elapsed().as_secs_f64()));
                report.resolved = Some(resolved);
                g
            }
        };
        let started = Instant::now();
        let grouping = match self.extension {
            Extension::None => base,
            Extension::Duplicate => {
                crate::progress::stage("duplicating splats into the groups' holes");
                let g = extend::duplicate(cloud, &base);
                report.stages.push(("extend: duplication", started.elapsed().as_secs_f64()));
                g
            }
            Extension::Estimate => {
                let k = base.k();
                Grouping { radius_scale: vec![super::table::cover_scale(k); k], ..base }
            }
            Extension::Enlarge => {
                crate::progress::stage("enlarging the groups' radii");
                let (g, enlarged) = extend::enlarge(cloud, &base);
                report.stages.push(("extend: radius", started.elapsed().as_secs_f64()));
                report.enlarged = Some(enlarged);
                g
            }
        };
        Ok((grouping, report))
    }

    /// MGC at `c`, or at the largest c with at most [`Tuning::max_groups`] groups.
    fn group_mgc(
        &self,
        cloud: &PointCloud,
        c: f32,
        tuning: &Tuning,
        report: &mut GroupingReport,
    ) -> Result<Grouping, GroupingError> {
        let started = Instant::now();
        let mut options = self.overlap(c);
        if let Some(k) = tuning.max_groups {
            options.c = mgc::c_for_groups(cloud, k, &options);
            report.c = Some(options.c);
        }
        let (g, graph) = mgc::group(cloud, &options)?;
        report.degrees = Some(degrees(&graph));
        report.stages.push(("graph + colouring", started.elapsed().as_secs_f64()));
        Ok(g)
    }

    /// WGC with K = `k`, on the graph of [`Tuning::wgc_c`].
    fn group_wgc(
        &self,
        cloud: &PointCloud,
        k: usize,
        eq7: bool,
        tuning: &Tuning,
        report: &mut GroupingReport,
    ) -> Result<Grouping, GroupingError> {
        let started = Instant::now();
        let options = wgc::WgcOptions {
            k,
            pure_area: tuning.pure_area,
            minimize_by_eq7: eq7,
            overlap: self.overlap(tuning.wgc_c()),
            ..Default::default()
        };
        let (g, graph, wgc) = wgc::group(cloud, &options)?;
        report.degrees = Some(degrees(&graph));
        let total = started.elapsed().as_secs_f64();
        report.stages.extend([
            ("graph", total - wgc.seconds_weights - wgc.seconds_initialise - wgc.seconds_optimise),
            ("weights", wgc.seconds_weights),
            ("initialise", wgc.seconds_initialise),
            ("optimise", wgc.seconds_optimise),
        ]);
        report.wgc = Some(wgc);
        Ok(g)
    }

    /// The cache key of this spec with `tuning`, for a model whose
    /// [`crate::hash::file_hash`] is `file_hash`.
    pub fn cache_key(&self, file_hash: u64, tuning: &Tuning) -> u64 {
        // v2: WGC's MinimizeOverlap by area and its re-queueing changed its results;
        // v3: duplication takes the most clipped splat first (§4.4.2);
        // v4: hash grouping resolves collisions by a fixed rule on dense leaf lattices.
        cache::key_for_hash(file_hash, &format!("spec|{self}{tuning}|v4"))
    }

    /// Groups the cloud loaded from `model`, through `cache`; returns the
    /// grouping and whether it came from the cache.
    pub fn compute_cached(
        &self,
        cache: &cache::Cache,
        model: &std::path::Path,
        cloud: &PointCloud,
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
        cloud: &PointCloud,
    ) -> Result<(Grouping, bool), GroupingError> {
        let (g, report) = self.compute_tuned_cached(cache, file_hash, cloud, &Tuning::default())?;
        Ok((g, report.is_none()))
    }

    /// [`Self::compute_tuned`] through `cache`: the grouping, and its report
    /// when it was computed (`None`: it came from the cache).
    pub fn compute_tuned_cached(
        &self,
        cache: &cache::Cache,
        file_hash: u64,
        cloud: &PointCloud,
        tuning: &Tuning,
    ) -> Result<(Grouping, Option<GroupingReport>), GroupingError> {
        let key = self.cache_key(file_hash, tuning);
        if let Some(g) = cache.load(key, cloud.len()) {
            return Ok((g, None));
        }
        let (g, report) = self.compute_tuned(cloud, tuning)?;
        if let Err(e) = cache.store(key, &g, cloud.len()) {
            log::warn!("{e}");
        }
        Ok((g, Some(report)))
    }
}

/// The largest and the average degree of `graph`.
fn degrees(graph: &OverlapGraph) -> (usize, f64) {
    (graph.max_degree(), graph.average_degree())
}

/// The knobs of `pointblend group` that a spec's name does not hold; the
/// default keeps the spec's own choices.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Tuning {
    /// MGC: the largest c (to 1/64) at which it needs at most this many groups, in place of the spec's c.
    pub max_groups: Option<usize>,
    /// WGC: the overlap graph's relaxation c (1 when `None`).
    pub wgc_c: Option<f32>,
    /// WGC: weights are the plain overlap area, without Eq. 7's (1 - n_i·n_j).
    pub pure_area: bool,
    /// Hashing that resolves collisions: only for splats closer to this eye than this distance.
    pub near: Option<(Vec3, f32)>,
}

impl Tuning {
    /// The c of WGC's overlap graph.
    fn wgc_c(&self) -> f32 {
        self.wgc_c.unwrap_or(1.0)
    }
}

/// Appended to the spec's name in cache keys: nothing for the default.
impl std::fmt::Display for Tuning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(k) = self.max_groups {
            write!(f, "-groups{k}")?;
        }
        if self.wgc_c() != 1.0 {
            write!(f, "-graph-c{}", self.wgc_c())?;
        }
        if self.pure_area {
            f.write_str("-pure-area")?;
        }
        if let Some((eye, distance)) = self.near {
            write!(f, "-near{},{},{},{distance}", eye.x, eye.y, eye.z)?;
        }
        Ok(())
    }
}

/// What a grouping run measured on the way ([`GroupingSpec::compute_tuned`]).
#[derive(Debug, Clone, Default)]
pub struct GroupingReport {
    /// The stages and their seconds, in order.
    pub stages: Vec<(&'static str, f64)>,
    /// The overlap graph's largest and average degree (MGC, WGC).
    pub degrees: Option<(usize, f64)>,
    /// MGC with [`Tuning::max_groups`]: the c it found.
    pub c: Option<f32>,
    /// WGC's costs, moves and stage times.
    pub wgc: Option<wgc::WgcReport>,
    /// Hashing: how many collisions were resolved.
    pub resolved: Option<usize>,
    /// Radius enlargement: each group's scale and whether it converged.
    pub enlarged: Option<extend::EnlargeReport>,
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
            Extension::Estimate => f.write_str("-est"),
        }
    }
}

/// How a grouping is written, for help texts and errors.
pub const GRAMMAR: &str = "mgc-cC, wgc-kK or hash-kK, then any of -kept (hash), -eq7 (wgc), -coplanar, -opposite \
                           (mgc, wgc), then one of -dup, -radius or -est (hash)";

impl std::str::FromStr for GroupingSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || format!("'{s}' is not a grouping; use {GRAMMAR} (e.g. mgc-c0.4, wgc-k4-dup, hash-k8-radius)");
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
                ("est", _) if graph => {
                    return Err(format!(
                        "'{s}': -est is the hash table's radius estimate (§4.4.2) and applies to hash-kK only; \
                         use -radius or -dup with mgc and wgc"
                    ));
                }
                ("est", _) if spec.extension == Extension::None => spec.extension = Extension::Estimate,
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
            "hash-k8-est",
            "mgc-c1-coplanar-opposite",
            "wgc-k4-opposite-radius",
        ] {
            let spec: GroupingSpec = text.parse().unwrap();
            assert_eq!(spec.to_string(), text);
        }
        for wrong in [
            "hash-k8-coplanar",
            "mgc-c0.4-kept",
            "hash-k8-eq7",
            "wgc-k4-dup-radius",
            "wgc-k4-x",
            "wgc-k0",
            "mgc-c0.4-est",
            "wgc-k4-est",
        ] {
            assert!(wrong.parse::<GroupingSpec>().is_err(), "{wrong}");
        }
    }

    #[test]
    fn the_estimate_scales_each_hash_grouping_by_its_own_k() {
        let positions: Vec<Vec3> = (0..400).map(|i| Vec3::new((i % 20) as f32, (i / 20) as f32, 0.0)).collect();
        let cloud = PointCloud::facing_z(positions, 1.0, [128; 3]);
        assert_ne!(super::super::table::cover_scale(4), super::super::table::cover_scale(8));
        for k in [4, 8] {
            let spec: GroupingSpec = format!("hash-k{k}-est").parse().unwrap();
            let grouping = spec.compute(&cloud).unwrap();
            assert!(grouping.radius_scale.iter().all(|&s| s == super::super::table::cover_scale(k)), "K = {k}");
        }
    }
}
