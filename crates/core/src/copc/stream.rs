//! A COPC file streamed node by node: each frame selects nodes by projected
//! spacing under the point budget (additive refinement, [`crate::lod`]),
//! reads the hierarchy pages the traversal reaches, loads the chunks the
//! selection lacks through the pool ([`super::load`]) into the LRU cache,
//! and builds the selected points into one [`PointCloud`] as a whole file
//! is built (the same re-centring and repairs), on the header bounds'
//! centre so that every selection shares one frame.
//!
//! Normals and radii a file lacks are estimated node by node, once, when a
//! node is first drawn, with a halo from the loaded nodes around it and
//! above it so that there is no seam at its border
//! ([`super::node_estimates`]); they stay in the cache beside its points,
//! so a selection that adds a few nodes estimates only those. So do the
//! groups of the grouped modes, labelled on a lattice fixed per level
//! ([`super::node_groups`]).
//!
//! A node that cannot be read (its page or chunk) is skipped: the first few
//! are logged with why, the rest counted in one line per load, and a frame
//! whose every node failed says why, naming the first.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use glam::DVec3;

use super::CopcError;
use super::cache::NodeCache;
use super::disk::DiskCache;
use super::header::CopcHeader;
use super::held::MemoryNodes;
use super::hierarchy::CopcTree;
use super::http::HttpOptions;
use super::load::{Fetch, Left};
use super::source::{ByteSource, is_url};
use rayon::prelude::*;

use super::drawn_estimates;
use super::node_estimates::{self, NodeEstimates};
use super::node_groups;
use crate::cloud::attributes::names;
use crate::cloud::estimate::EstimateOptions;
use crate::cloud::las_file::Columns;
use crate::cloud::load::from_columns;
use crate::cloud::{Estimates, LoadOptions, LoadReport, PointCloud, Values};
use crate::frame::Camera;
use crate::frame::subset::{NodeGrouping, NodeSpans};
use crate::grouping::hash::HashOptions;
use crate::lod::{self, LodTree, SelectOptions, Selection};

pub use super::budget::{DEFAULT_BUDGET, FINEST_PX, StreamBudget};

/// How a file is streamed.
#[derive(Debug, Clone)]
pub struct StreamOptions {
    /// The LRU cache's bound on decoded nodes.
    pub cache_bytes: usize,
    pub http: HttpOptions,
    /// Keep fetched chunks here (none are written to disk otherwise).
    pub disk_cache: Option<PathBuf>,
    /// Show progress bars.
    pub progress: bool,
}

impl Default for StreamOptions {
    fn default() -> Self {
        Self { cache_bytes: default_cache_bytes(), http: HttpOptions::default(), disk_cache: None, progress: false }
    }
}

/// A quarter of the free memory (1 GiB when it cannot be read).
pub fn default_cache_bytes() -> usize {
    crate::memory::available_bytes().map_or(1 << 30, |b| (b / 4) as usize)
}

/// What streaming has cost so far.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StreamStats {
    pub nodes_loaded: usize,
    pub points_loaded: u64,
    /// Bytes and requests the source served (header and pages included).
    pub bytes_read: u64,
    pub requests: u64,
    /// Nodes (and pages) that failed and were skipped.
    pub failed: usize,
    /// Seconds spent fetching and decoding.
    pub load_seconds: f64,
    /// Points whose normals and radii were estimated (each node once, when
    /// it arrived), and the seconds that took.
    pub points_estimated: u64,
    pub estimate_seconds: f64,
    /// Points given their groups (each node once per grouping), and the seconds that took.
    pub points_labelled: u64,
    pub label_seconds: f64,
}

pub struct CopcStream {
    pub(super) source: Box<dyn ByteSource>,
    pub header: CopcHeader,
    pub tree: CopcTree,
    cache: NodeCache,
    /// Nodes that failed, with why (skipped from then on).
    pub(super) failed: HashMap<u32, String>,
    /// Failures not logged one by one, for the next summary line.
    unlogged: usize,
    /// `--disk-cache DIR`, in the folder of this source's content.
    pub(super) disk: Option<DiskCache>,
    /// The nodes of a file held whole ([`super::memory`]), gathered rather than read.
    pub(super) memory: Option<Arc<MemoryNodes>>,
    pub(super) options: StreamOptions,
    stats: StreamStats,
    /// The levels' lattices for the groups ([`node_groups::lattice_depth`]), fixed at the first labelling.
    lattice_depth: Option<u32>,
}

/// Node failures logged one by one; later ones are counted in one line per load.
const LOGGED_FAILURES: usize = 3;

/// One frame's points.
pub struct StreamedFrame {
    pub cloud: PointCloud,
    pub report: LoadReport,
    pub selection: Selection,
    /// The selected nodes that were drawn (loaded), in file order.
    pub drawn: Vec<u32>,
    /// What identifies these points for caches: the source and the nodes drawn.
    pub hash: u64,
    /// The points' groups, each node's labelled once, when asked for.
    pub grouping: Option<NodeGrouping>,
    /// Which splats each drawn node holds.
    pub spans: Option<Arc<NodeSpans>>,
}

impl CopcStream {
    /// Opens `name` (a path or an http(s) URL): the header, the info VLR and the root page.
    pub fn open(name: &str, options: StreamOptions) -> Result<Self, CopcError> {
        let source = open_source(name, &options.http)?;
        let header = super::header::read(source.as_ref())?;
        let b = header.las.bounds();
        let origin = if b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z {
            DVec3::new(b.min.x + b.max.x, b.min.y + b.max.y, b.min.z + b.max.z) * 0.5
        } else {
            DVec3::new(header.info.center_x, header.info.center_y, header.info.center_z)
        };
        let mut tree = CopcTree::new(&header, origin);
        let (at, size) = header.root_page;
        let name = source.name();
        tree.claim_page(at).map_err(|e| CopcError::new(name, e))?;
        let page = source
            .read(at, size)
            .map_err(|e| CopcError::new(name, format!("its root hierarchy page: {}", e.reason)))?;
        tree.add_page(name, None, &page)?;
        if tree.root().is_none() {
            let reason = match &tree.refused.root {
                Some(why) => format!("its root node was refused: {why}"),
                None => "its root hierarchy page has no root node (0-0-0-0)".to_string(),
            };
            return Err(CopcError::new(name, reason));
        }
        let disk = options
            .disk_cache
            .as_deref()
            .map(|dir| DiskCache::new(dir, super::disk::source_id(source.identity(), source.len(), &page)));
        Ok(Self::assemble(source, (header, tree), disk, None, options))
    }

    /// A stream of `tree`'s nodes: read from `source` (through `disk`), or
    /// gathered from `memory` for a file held whole.
    pub(super) fn assemble(
        source: Box<dyn ByteSource>,
        (header, tree): (CopcHeader, CopcTree),
        disk: Option<DiskCache>,
        memory: Option<Arc<MemoryNodes>>,
        options: StreamOptions,
    ) -> Self {
        let cache = NodeCache::new(options.cache_bytes);
        Self {
            source,
            header,
            tree,
            cache,
            failed: HashMap::new(),
            unlogged: 0,
            disk,
            memory,
            options,
            stats: StreamStats::default(),
            lattice_depth: None,
        }
    }

    pub fn name(&self) -> &str {
        self.source.name()
    }

    /// Points the header counts.
    pub fn points(&self) -> u64 {
        self.header.las.number_of_points()
    }

    /// The nodes to draw, reading the hierarchy pages the traversal reaches.
    pub fn select(&mut self, camera: &Camera, size: (u32, u32), options: SelectOptions) -> Selection {
        loop {
            let selection = lod::select_in(&self.tree, camera, size, options);
            let pending: Vec<u32> = self.tree.pending(&selection.nodes).collect();
            if pending.is_empty() {
                self.log_unlogged();
                return selection;
            }
            for n in pending {
                self.read_page(n);
            }
        }
    }

    /// Reads the hierarchy page node `n` waits on, if it still waits (a
    /// page read earlier may have settled it); a page that fails fails the node.
    pub(super) fn read_page(&mut self, n: u32) {
        let Some((at, size)) = self.tree.nodes[n as usize].page else { return };
        let owner = self.tree.nodes[n as usize].key;
        let page = match self.tree.claim_page(at) {
            Ok(()) => self
                .source
                .read(at, size)
                .and_then(|bytes| self.tree.add_page(self.source.name(), Some(owner), &bytes))
                .map_err(|e| e.reason),
            Err(reason) => Err(reason),
        };
        let node = &mut self.tree.nodes[n as usize];
        if let Err(reason) = page {
            node.page = None;
            self.fail(n, format!("its hierarchy page: {reason}"));
        } else if node.page.is_some() {
            // The page did not list its own key: the node holds nothing.
            node.page = None;
        }
    }

    fn fail(&mut self, node: u32, reason: String) {
        let k = self.tree.nodes[node as usize].key;
        if self.failed.len() < LOGGED_FAILURES {
            log::warn!("{}: node {}-{}-{}-{} skipped: {reason}", self.source.name(), k.l, k.x, k.y, k.z);
        } else {
            self.unlogged += 1;
        }
        self.failed.insert(node, reason);
        self.stats.failed = self.failed.len();
    }

    /// One line for the failures [`Self::fail`] did not log (at the end of a select or a load).
    fn log_unlogged(&mut self) {
        if self.unlogged > 0 {
            log::warn!("{}: {} more nodes skipped ({} in all)", self.source.name(), self.unlogged, self.failed.len());
            self.unlogged = 0;
        }
    }

    /// Loads the selected nodes that are neither cached nor failed; returns how many loaded.
    pub fn load(&mut self, selection: &Selection) -> usize {
        let wanted = self.missing(selection);
        self.load_nodes(&wanted, selection)
    }

    /// The selected nodes with points that are neither cached nor failed,
    /// in the selection's order (coarse first: largest projected spacing).
    pub fn missing(&self, selection: &Selection) -> Vec<u32> {
        let loadable =
            |n: u32| self.tree.nodes[n as usize].points > 0 && !self.cache.contains(n) && !self.failed.contains_key(&n);
        selection.nodes.iter().copied().filter(|&n| loadable(n)).collect()
    }

    /// Loads the first of the selected nodes the cache lacks, coarse first,
    /// while they hold at most `points` (but [`super::load::IN_FLIGHT`]
    /// nodes at least, so that the loader's requests stay in flight);
    /// returns what remains to load. A view refined in such steps shows
    /// its coarse nodes first, each step bounded in what it adds.
    pub fn load_up_to(&mut self, selection: &Selection, points: u64) -> Left {
        let missing = self.missing(selection);
        let held = |n: &u32| u64::from(self.tree.nodes[*n as usize].points);
        let mut sum = 0u64;
        let take = missing
            .iter()
            .enumerate()
            .take_while(|&(i, n)| {
                sum += held(n);
                i < super::load::IN_FLIGHT || sum <= points
            })
            .count();
        let left = Left { nodes: missing.len() - take, points: missing[take..].iter().map(held).sum() };
        self.load_nodes(&missing[..take], selection);
        left
    }

    /// Loads `wanted` (nodes of `selection`, which the cache keeps while it loads them); returns how many loaded.
    fn load_nodes(&mut self, wanted: &[u32], selection: &Selection) -> usize {
        if wanted.is_empty() {
            return 0;
        }
        let started = Instant::now();
        let total: u64 = wanted.iter().map(|&n| u64::from(self.tree.nodes[n as usize].points)).sum();
        let bar = crate::progress::bar(total, "streaming nodes", self.options.progress);
        let done = AtomicU64::new(0);
        let source = self.source.as_ref();
        let (header, tree, disk, memory) = (&self.header, &self.tree, self.disk.as_ref(), self.memory.as_deref());
        let fetch = Fetch { source, header, tree, disk, memory };
        let results = fetch.nodes(wanted, &|points| {
            done.fetch_add(points, Ordering::Relaxed);
            bar.inc(points);
        });
        bar.finish();
        let in_selection: std::collections::HashSet<u32> = selection.nodes.iter().copied().collect();
        let mut loaded = 0;
        for (n, result) in results {
            match result {
                Ok(columns) => {
                    self.stats.points_loaded += columns.len() as u64;
                    self.cache.insert(n, Arc::new(columns), &|m| in_selection.contains(&m));
                    loaded += 1;
                }
                Err(reason) => self.fail(n, reason),
            }
        }
        self.stats.nodes_loaded += loaded;
        self.stats.load_seconds += started.elapsed().as_secs_f64();
        self.log_unlogged();
        loaded
    }

    /// The selected nodes' points as one cloud (nodes in file order), with
    /// the normals and radii each node got when it arrived, and the groups
    /// of hash grouping `groups` each got when first drawn so grouped.
    pub fn gather(
        &mut self,
        selection: &Selection,
        options: &LoadOptions,
        groups: Option<HashOptions>,
    ) -> Result<StreamedFrame, CopcError> {
        let drawn = self.drawn(selection);
        self.estimate_new(&drawn, &options.estimate);
        let labels = groups.and_then(|g| self.labels_of(&drawn, g));
        let mut columns = Columns::default();
        let mut estimates = Estimates::default();
        let nodes: Vec<(u32, Arc<Columns>, Option<Arc<NodeEstimates>>)> =
            drawn.iter().map(|&n| (n, self.cache.get(n).expect("checked above"), self.cache.estimates(n))).collect();
        let drawn_set: std::collections::HashSet<u32> = drawn.iter().copied().collect();
        let all: HashMap<u32, &NodeEstimates> =
            nodes.iter().filter_map(|(n, _, e)| Some((*n, e.as_deref()?))).collect();
        let tree = &self.tree;
        // Where finer nodes are drawn, as the deepest of them estimated them; the others as estimated.
        let as_drawn: Vec<Option<(Vec<glam::Vec3>, Vec<f32>)>> = nodes
            .par_iter()
            .map(|(n, own, e)| drawn_estimates::drawn_estimates(tree, (*n, own, e.as_deref()?), (&drawn_set, &all)))
            .collect();
        // Records of nodes that stand for finer points not drawn: a radius the file gives grows there.
        let mut coarse = Vec::new();
        for ((n, own, e), as_drawn) in nodes.iter().zip(as_drawn) {
            columns.extend(own);
            coarse.extend(std::iter::repeat_n(node_estimates::stands_for_more(tree, *n, &drawn_set), own.len()));
            if let Some(e) = e {
                match as_drawn {
                    Some((normals, radii)) => {
                        estimates.normals.extend(normals);
                        estimates.radii.extend(radii);
                    }
                    None => {
                        estimates.normals.extend_from_slice(&e.estimates.normals);
                        estimates.radii.extend_from_slice(&e.estimates.radii);
                    }
                }
            }
        }
        if columns.len() == 0 {
            return Err(CopcError::new(self.name(), self.why_nothing_is_drawn(selection)));
        }
        let (encoding, mut info) = self.described(drawn.len());
        let (data, mut attributes) = columns.finish(&self.header.fields, encoding, &mut info.warnings);
        // Each point's octree level: `--color-by node_level` shows the selection.
        let mut levels = Vec::with_capacity(data.vertex_count);
        for &n in &drawn {
            let node = &self.tree.nodes[n as usize];
            levels.extend(std::iter::repeat_n(node.key.l as u8, node.points as usize));
        }
        if levels.len() == data.vertex_count {
            attributes.push(names::NODE_LEVEL, Values::U8(levels));
        }
        let estimated = Arc::new(estimates);
        let grow = self.gives_radii().then(|| estimated.clone());
        let estimated = Some(estimated);
        let options = LoadOptions { origin: Some(self.tree.origin.to_array()), estimated, ..options.clone() };
        let (cloud, report, splat_of) = from_columns(Path::new(self.name()), data, (attributes, info), &options)
            .map_err(|e| CopcError::new(self.name(), e.to_string()))?;
        let mut cloud = cloud;
        if let Some(estimated) = grow {
            node_estimates::grow_given_radii(&mut cloud, &splat_of, (&estimated.radii, &coarse));
        }
        let hash = self.key_of(&drawn);
        let grouping = labels.filter(|(_, l)| l.len() == splat_of.len()).map(|(options, per_record)| NodeGrouping {
            options,
            grouping: Arc::new(node_groups::groups_of_splats(&per_record, &splat_of, cloud.len(), options.k)),
        });
        let records = drawn.iter().map(|&n| (n, self.tree.nodes[n as usize].points as usize));
        let spans = NodeSpans::of_records(records, &splat_of).map(Arc::new);
        Ok(StreamedFrame { cloud, report, selection: selection.clone(), drawn, hash, grouping, spans })
    }

    /// The groups of the `drawn` nodes' points in hash grouping `options`,
    /// one per record in drawn order: each node labelled once (in
    /// parallel), the first time it is drawn so grouped. `None` for a file
    /// that gives its splats' normals and radii: the labels would come from
    /// the estimates, not from the splats drawn.
    fn labels_of(&mut self, drawn: &[u32], options: HashOptions) -> Option<(HashOptions, Vec<u8>)> {
        let gives = |name: &str| self.header.fields.iter().any(|f| f.name == name);
        if ["nx", "ny", "nz", "radius"].into_iter().all(gives) {
            return None;
        }
        let root = self.tree.node(&las::copc::VoxelKey { l: 0, x: 0, y: 0, z: 0 })?;
        if self.lattice_depth.is_none() {
            let median = self.cache.estimates(root)?.median_radius;
            let (_, side) = self.tree.cube(&self.tree.nodes[root as usize].key);
            self.lattice_depth = Some(node_groups::lattice_depth(side, median));
        }
        let depth = self.lattice_depth?;
        let started = Instant::now();
        self.stats.points_labelled += node_groups::label_new(&mut self.cache, &self.tree, drawn, (depth, options));
        self.stats.label_seconds += started.elapsed().as_secs_f64();
        let mut out = Vec::new();
        for &n in drawn {
            out.extend_from_slice(&self.cache.labels(n, options)?);
        }
        Some((options, out))
    }

    /// Whether the file gives each point its radius (a splat's, as
    /// `convert` writes it): a point of a node that stands for finer points
    /// not drawn is then drawn at least as large as its node's density asks
    /// ([`node_estimates::grow_given_radii`]).
    fn gives_radii(&self) -> bool {
        self.header.fields.iter().any(|f| f.name == "radius")
    }

    /// Estimates the normals and radii of the loaded nodes of `selection`
    /// that have none yet ([`Self::estimate_new`]), as a loading step does
    /// so that the gather after it only assembles.
    pub fn estimate_loaded(&mut self, selection: &Selection, options: &EstimateOptions) {
        let drawn = self.drawn(selection);
        self.estimate_new(&drawn, options);
    }

    /// Estimates the normals and radii of the `drawn` nodes that have none
    /// yet, each once and in parallel, with its halo from the nodes loaded
    /// now ([`node_estimates`]).
    fn estimate_new(&mut self, drawn: &[u32], options: &EstimateOptions) {
        let new: Vec<u32> = drawn.iter().copied().filter(|&n| self.cache.estimates(n).is_none()).collect();
        if new.is_empty() {
            return;
        }
        let started = Instant::now();
        let (cache, tree) = (&self.cache, &self.tree);
        let facing = self.memory.as_ref().map_or_else(Default::default, |m| m.facing);
        let made: Vec<(u32, NodeEstimates)> = new
            .par_iter()
            .filter_map(|&n| {
                let own = cache.peek(n)?;
                let around = node_estimates::halo_nodes(tree, n, &|m| cache.contains(m));
                let halo: Vec<(u32, &Columns)> =
                    around.iter().filter_map(|&m| cache.peek(m).map(|c| (m, c.as_ref()))).collect();
                Some((n, node_estimates::estimate(tree, n, (own, &halo), options, facing)))
            })
            .collect();
        for (n, estimates) in made {
            self.stats.points_estimated += estimates.estimates.radii.len() as u64;
            self.cache.set_estimates(n, Arc::new(estimates));
        }
        self.stats.estimate_seconds += started.elapsed().as_secs_f64();
    }

    /// The nodes of `selection` that are drawn (loaded), in file order.
    pub fn drawn(&self, selection: &Selection) -> Vec<u32> {
        let mut drawn: Vec<u32> = selection.nodes.iter().copied().filter(|&n| self.cache.contains(n)).collect();
        drawn.sort_by_key(|&n| self.tree.nodes[n as usize].offset);
        drawn
    }

    /// What identifies the points of the nodes `drawn` for caches: the source and the nodes.
    pub fn key_of(&self, drawn: &[u32]) -> u64 {
        let mut hash = crate::hash::fnv1a(0, self.source.identity().as_bytes());
        for &n in drawn {
            hash = crate::hash::fnv1a(hash, &n.to_le_bytes());
        }
        hash
    }

    /// Why a selection gave no point: nothing in view, or the nodes in view failed (the first named).
    fn why_nothing_is_drawn(&self, selection: &Selection) -> String {
        let failed: Vec<String> = selection
            .nodes
            .iter()
            .filter_map(|n| {
                let k = self.tree.nodes[*n as usize].key;
                self.failed.get(n).map(|why| format!("node {}-{}-{}-{}: {why}", k.l, k.x, k.y, k.z))
            })
            .collect();
        match failed.first() {
            None if selection.nodes.is_empty() => "no point of the file is in view".to_string(),
            None => "the nodes in view hold no points".to_string(),
            Some(first) if failed.len() == 1 => format!("the only node in view with points could not be read: {first}"),
            Some(first) => {
                format!(
                    "none of the {} nodes in view could be read ({first}; and {} more)",
                    failed.len(),
                    failed.len() - 1
                )
            }
        }
    }

    /// Selects, loads and gathers the points of one frame under `budget`,
    /// chosen as `choosing` says (refused in one line when `all` would not
    /// fit the node cache); see [`StreamBudget::select_options`].
    pub fn frame_under(
        &mut self,
        camera: &Camera,
        size: (u32, u32),
        (budget, choosing): (StreamBudget, crate::lod::Choosing),
        load: &LoadOptions,
    ) -> Result<StreamedFrame, CopcError> {
        self.check_fits(budget)?;
        self.frame(camera, size, budget.select_options(choosing), load)
    }

    /// Whether `budget`'s points fit the node cache (an error says what to change).
    pub fn check_fits(&self, budget: StreamBudget) -> Result<(), CopcError> {
        let record = u64::from(self.header.las.point_format().len());
        budget.check_fits(self.name(), self.points(), record, self.options.cache_bytes)
    }

    /// Selects, loads and gathers one frame's points.
    pub fn frame(
        &mut self,
        camera: &Camera,
        size: (u32, u32),
        select: SelectOptions,
        load: &LoadOptions,
    ) -> Result<StreamedFrame, CopcError> {
        let selection = self.select(camera, size, select);
        self.load(&selection);
        self.gather(&selection, load, None)
    }

    /// What streaming has cost so far.
    pub fn stats(&self) -> StreamStats {
        let c = self.source.counters();
        StreamStats { bytes_read: c.bytes(), requests: c.requests(), ..self.stats.clone() }
    }

    /// Bytes, nodes and the bound of the node cache.
    pub fn cache_usage(&self) -> (usize, usize, usize) {
        self.cache.usage()
    }

    /// Points the node decoded to, while it is cached.
    pub fn decoded_points(&mut self, node: u32) -> Option<usize> {
        self.cache.get(node).map(|c| c.len())
    }

    /// Why the node failed, if it did.
    pub fn failure(&self, node: u32) -> Option<&str> {
        self.failed.get(&node).map(String::as_str)
    }

    /// Why each failed node failed.
    pub fn failures(&self) -> impl Iterator<Item = &String> {
        self.failed.values()
    }
}

/// Opens `name`: a URL through HTTP, anything else as a local file.
fn open_source(name: &str, options: &HttpOptions) -> Result<Box<dyn ByteSource>, CopcError> {
    if is_url(name) {
        Ok(Box::new(super::http::HttpSource::open(name, options)?))
    } else {
        Ok(Box::new(super::source::FileSource::open(Path::new(name))?))
    }
}
