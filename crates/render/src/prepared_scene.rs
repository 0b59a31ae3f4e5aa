//! The one way to render a scene in any mode: `pointblend render`, `bench`
//! and the viewer's render thread all go through [`PreparedScene`].
//!
//! A [`PreparedScene`] holds a scene, its splats in world space, the
//! subsets a frame may choose from them (the nodes under a point budget,
//! the splats beside a hybrid frame's triangles, [`crate::frame::subset`]),
//! and a [`SceneCache`] of what its frames prepared: groupings, GPU copies,
//! shadow coefficients and the triangles, each keyed by the
//! slot it serves ([`Slot`]), the grouping and the splats it was made from.
//! The decisions are made here, from the frame's spec: a still scene's
//! groupings are computed through the grouping cache (or only handed in,
//! for the viewer), a moving scene's and a subset's are hash groupings
//! redone per frame on a fixed lattice, a streamed selection's are the
//! groups its nodes were labelled with once (regrouped whole only where a
//! file's nodes have none), and a new set of splats in a slot
//! is written over that slot's GPU copies in place. The exact reference (a
//! CPU mode) renders the scene itself.

mod budget;
mod hybrid;
mod render_frame;
mod show;

use std::sync::Arc;

pub use crate::report::{BudgetStats, FrameUpdate, HybridStats};
pub use crate::scene_cache::SceneGrouping;
pub use budget::load_hierarchy;
pub use render_frame::{Frame, Readback};

use super::context::GpuError;
use super::gpu_renderer::GpuRenderer;
use super::gpu_scene::{Arrangement, GpuScene};
use crate::cloud::PointCloud;
use crate::frame::{FrameSpec, RenderSettings};
use crate::grouping::regroup::Lattice;
use crate::grouping::{Extension, Grouping, GroupingError, GroupingSpec, cache::Cache};
use crate::report::FrameReport;
use crate::scene::Scene;
use crate::scene_cache::{Keep, SceneCache, Slot};
use crate::shadow::{self, ShadowCoefficients, ShadowInput};
use show::Drawn;

#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("grouping {spec}: {source}")]
    Grouping {
        spec: GroupingSpec,
        #[source]
        source: GroupingError,
    },
    #[error("grouping {0} is not ready yet")]
    NoGrouping(GroupingSpec),
    #[error("mode {0} runs on the GPU, and no GPU was opened")]
    NoGpu(&'static str),
    #[error(transparent)]
    Shadow(#[from] crate::shadow::ShadowError),
}

/// Shadow coefficient sets kept per scene (each 4 bytes per splat and light).
const KEPT_SHADOWS: usize = 4;

/// A scene ready to render in any mode.
pub struct PreparedScene {
    scene: Arc<Scene>,
    /// The content hash that keys the grouping cache.
    hash: u64,
    /// The splats each slot draws now: the whole scene's (in world space),
    /// and each subset's last choice (`None` before its first).
    drawn: [Option<Drawn>; 3],
    /// What the frames prepared, by slot, grouping and splats.
    prepared: SceneCache,
    /// Whether a whole-scene grouping missing here is computed (through the cache) rather than refused.
    compute_groupings: bool,
    /// Most groupings handed in, and grouped copies kept per slot; the oldest goes first (the viewer keeps one).
    max_grouped: usize,
    /// The whole scene moves: its groupings are hash groupings redone every frame.
    moving: bool,
    /// The lattice a moving scene's hash groups are counted on (see [`rest_lattice`]);
    /// the first frame's when none is given.
    lattice: Option<Lattice>,
    /// The lattice a subset's hash groups are counted on: the whole scene's, whatever is chosen.
    subset_lattice: Option<Lattice>,
    /// Counts the frames a moving scene has shown (names its splats).
    generation: u64,
    /// The splats are a streamed file's selection, made under its budget already.
    streamed: bool,
    /// The mean splat radius of the whole scene (what ε is a multiple of), found once.
    mean_radius: f32,
    /// The hierarchy's nodes under a budget (see `budget.rs`), made on first use.
    budget: Option<crate::lod::subset::BudgetSubset>,
    /// The leaves drawn as triangles and the splats beside them (see `hybrid.rs`), made on first use.
    hybrid: Option<Box<hybrid::HybridSubsetState>>,
    /// Where groupings and hierarchies are cached on disk.
    cache: Cache,
    /// Bytes of splat records written to the GPU so far (uploads and rewrites).
    uploaded_bytes: u64,
}

/// The lattice of a moving scene's hash groups: that of its splats at 0 s
/// (the rest pose, or a sequence's first frame).
pub fn rest_lattice(scene: &Scene) -> Result<Lattice, String> {
    Ok(Lattice::of(&scene.at_time(0.0)?.scene.flattened()))
}

pub use crate::frame::spec::per_frame_grouping;

/// A hash grouping with `spec`'s extension: §4.4.2's radius estimate, or none.
fn with_extension(mut grouping: Grouping, spec: GroupingSpec) -> Grouping {
    let scale =
        if spec.extension == Extension::Estimate { crate::grouping::table::cover_scale(grouping.k()) } else { 1.0 };
    grouping.radius_scale = vec![scale; grouping.k()];
    grouping
}

impl PreparedScene {
    /// `scene` with its splats in world space, `cloud` (`scene.flatten()`'s).
    /// Missing groupings are computed through the grouping cache, and every
    /// upload is kept.
    pub fn new(scene: Arc<Scene>, cloud: Arc<PointCloud>) -> Self {
        let hash = scene.geometry_hash();
        let mean_radius = cloud.mean_radius();
        let spans = scene.node_spans.clone();
        Self {
            scene,
            hash,
            drawn: [Some(Drawn::new(hash, cloud).in_nodes(spans)), None, None],
            prepared: SceneCache::new(KEPT_SHADOWS),
            compute_groupings: true,
            max_grouped: usize::MAX,
            moving: false,
            lattice: None,
            subset_lattice: None,
            generation: 0,
            streamed: false,
            mean_radius,
            budget: None,
            hybrid: None,
            cache: Cache::from_env(),
            uploaded_bytes: 0,
        }
    }

    /// Groupings and hierarchies are cached in `cache` (default: [`Cache::from_env`]).
    pub fn with_cache(mut self, cache: Cache) -> Self {
        self.cache = cache;
        self
    }

    /// The scene moves: its groupings are hash groupings redone every frame
    /// (see [`per_frame_grouping`]), never cached, and [`Self::advance`] moves it on.
    pub fn moving(mut self) -> Self {
        self.moving = true;
        self
    }

    /// A moving scene whose hash groups are counted on `lattice` (its rest
    /// pose's, [`rest_lattice`]), so that a frame's groups depend on that
    /// frame alone, not on the frame the scene was first shown at.
    pub fn moving_on(mut self, lattice: Lattice) -> Self {
        self.lattice = Some(lattice);
        self.moving()
    }

    /// The splats are a streamed file's selection, made under its budget
    /// already: a frame draws them all ([`crate::frame::spec::Selection::Streamed`]).
    pub fn streamed(mut self) -> Self {
        self.streamed = true;
        self
    }

    /// Groupings come only from [`Self::add_grouping`] (the viewer computes
    /// them in a job of its own), and at most `max_grouped` grouped copies
    /// of a slot's splats stay on the GPU.
    pub fn handed_groupings(mut self, max_grouped: usize) -> Self {
        self.compute_groupings = false;
        self.max_grouped = max_grouped.max(1);
        self
    }

    /// A scene with its own splats ([`Scene::flattened`]: shared, not copied, for a plain single object).
    pub fn of(scene: Arc<Scene>) -> Self {
        let cloud = scene.flattened();
        Self::new(scene, cloud)
    }

    /// Bytes of splat records this scene's frames have written to the GPU so
    /// far: every upload and every rewrite of one.
    pub fn uploaded_bytes(&self) -> u64 {
        self.uploaded_bytes
    }

    /// Whether the splats are a streamed file's selection.
    pub fn is_streamed(&self) -> bool {
        self.streamed
    }

    /// Whether the scene moves.
    pub fn is_moving(&self) -> bool {
        self.moving
    }

    pub fn scene(&self) -> &Arc<Scene> {
        &self.scene
    }

    /// The whole scene's splats in world space.
    pub fn cloud(&self) -> &Arc<PointCloud> {
        &self.whole().cloud
    }

    fn whole(&self) -> &Drawn {
        self.drawn(Slot::Whole)
    }

    /// Moves a moving scene on to another frame: `scene` at that time and
    /// its splats in world space. Every grouping kept is regrouped (only
    /// near what moved), every GPU copy rewritten in place (only the records
    /// that changed), the shadows recomputed on their next use.
    pub fn advance(
        &mut self,
        gpu: Option<&GpuRenderer>,
        scene: Arc<Scene>,
        cloud: Arc<PointCloud>,
    ) -> Result<FrameUpdate, FrameError> {
        self.take_scene(scene, &cloud);
        self.generation += 1;
        self.moving = true;
        let key = pointblend_core::hash::fnv1a(self.hash, &self.generation.to_le_bytes());
        self.show(gpu, Slot::Whole, Drawn::new(key, cloud))
    }

    /// Hands in a grouping of the whole scene computed elsewhere (nothing
    /// happens when it is here already); past `max_grouped` of them, the
    /// oldest goes, with its GPU copy.
    pub fn add_grouping(&mut self, grouping: SceneGrouping) {
        let key = (Slot::Whole, grouping.spec);
        if self.prepared.groupings.contains(&key) {
            return;
        }
        let drawn = self.whole().key;
        self.prepared.groupings.insert(key, Keep { drawn, value: grouping });
        let handed: Vec<GroupingSpec> =
            self.prepared.groupings.keys().filter(|(slot, _)| *slot == Slot::Whole).map(|(_, spec)| spec).collect();
        if handed.len() > self.max_grouped {
            self.prepared.groupings.remove(&(Slot::Whole, handed[0]));
            self.prepared.uploads.remove(&(Slot::Whole, Some(handed[0])));
        }
    }

    /// The grouping `spec` of the whole scene, computed through the cache when it is not here.
    pub fn grouping(&mut self, spec: GroupingSpec) -> Result<&SceneGrouping, FrameError> {
        self.grouping_in(Slot::Whole, spec)
    }

    /// The grouping `spec` of the splats `slot` draws: kept, or made as the
    /// slot's splats are (regrouped for a moving scene and a subset,
    /// computed through the cache or refused for a still one).
    fn grouping_in(&mut self, slot: Slot, spec: GroupingSpec) -> Result<&SceneGrouping, FrameError> {
        let drawn = self.drawn(slot).key;
        let key = (slot, spec);
        if self.prepared.groupings.get(&key).is_none_or(|kept| kept.drawn != drawn) {
            let node_grouping = if slot == Slot::Whole && self.streamed { self.node_grouping(spec) } else { None };
            let grouping = if let Some(grouping) = node_grouping {
                grouping
            } else if slot != Slot::Whole || self.moving || self.streamed {
                self.regroup(slot, spec)?.0
            } else if self.compute_groupings {
                self.compute_grouping(spec)?
            } else {
                return Err(FrameError::NoGrouping(spec));
            };
            self.prepared.groupings.insert(key, Keep { drawn, value: grouping });
        }
        Ok(&self.prepared.groupings.get(&key).expect("kept above").value)
    }

    /// The groups a streamed selection came with ([`Scene::node_grouping`]:
    /// each node labelled once, when it arrived), when they are hash
    /// grouping `spec`'s; §4.4.2's extension is added here, as a regroup adds it.
    pub(super) fn node_grouping(&self, spec: GroupingSpec) -> Option<SceneGrouping> {
        let given = self.scene.node_grouping.as_ref()?;
        let fits = given.grouping.order.len() == self.cloud().len();
        (fits && spec.algo.hash_options() == Some(given.options)).then(|| SceneGrouping {
            spec,
            grouping: Arc::new(with_extension(given.grouping.as_ref().clone(), spec)),
            seconds: 0.0,
            cached: false,
        })
    }

    /// The nodes `slot`'s splats came in, when its GPU copy keeps them in a
    /// node pool ([`crate::node_pool`]): an opaque selection of a tree of
    /// nodes whose nodes add up to its splats. That is a streamed file's
    /// selection in the whole scene's slot, grouped or not, and the nodes
    /// under a point budget in the budget's slot when its copy is not
    /// `grouped` (the hierarchy's nodes are small, a few hundred splats, so
    /// a group's runs node by node would be thousands of draws; the modes
    /// that preview a moving view draw no groups). A transparent selection
    /// is sorted back to front, record by record, so it stays packed.
    fn pooled_nodes(&self, slot: Slot, grouped: bool) -> Option<Arc<crate::frame::subset::NodeSpans>> {
        let drawn = self.drawn[slot.index()].as_ref()?;
        let spans = drawn.spans.as_ref()?;
        let fits = spans.splats() as usize == drawn.cloud.len();
        let pooled = match slot {
            Slot::Whole => self.streamed,
            Slot::Budget => !grouped,
            Slot::Hybrid => false,
        };
        (pooled && fits && !drawn.transparent).then(|| Arc::clone(spans))
    }

    /// Draws `scene` (its splats in world space `cloud`) from now on; its GPU
    /// copies are made again when its environment map is another.
    fn take_scene(&mut self, scene: Arc<Scene>, cloud: &PointCloud) {
        let same_map = match (&self.scene.environment, &scene.environment) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (a, b) => a.is_none() && b.is_none(),
        };
        if !same_map {
            self.prepared.uploads.retain(|_| false); // made again with the new map beside them
        }
        self.hash = scene.geometry_hash();
        self.mean_radius = cloud.mean_radius();
        self.scene = scene;
    }

    /// Shows a streamed file's next selection, `scene` (one object, its
    /// nodes' splats in world space, `cloud`): its groupings are its nodes'
    /// labels (or a regroup), and the whole scene's GPU copies are kept and
    /// rewritten, where its nodes are pooled only the nodes that changed
    /// ([`crate::node_pool`]); the rest the frames prepared is dropped.
    /// Returns what that took.
    pub fn show_selection(
        &mut self,
        gpu: Option<&GpuRenderer>,
        scene: Arc<Scene>,
        cloud: Arc<PointCloud>,
    ) -> Result<FrameUpdate, FrameError> {
        self.take_scene(scene, &cloud);
        // Subsets of the last selection (a preview's budget) are made again from this one.
        (self.budget, self.hybrid, self.subset_lattice) = (None, None, None);
        self.drawn[Slot::Budget.index()] = None;
        self.drawn[Slot::Hybrid.index()] = None;
        // The whole scene's groupings and copies are carried over: `show` takes this
        // selection's node labels for them (or regroups it) and rewrites the copies.
        self.prepared.groupings.retain(|(slot, _)| *slot == Slot::Whole);
        self.prepared.regroupers.retain(|_| false);
        self.prepared.uploads.retain(|(slot, _)| *slot == Slot::Whole);
        let spans = self.scene.node_spans.clone();
        self.show(gpu, Slot::Whole, show::Drawn::new(self.hash, cloud).in_nodes(spans))
    }

    /// The grouping `spec` of the whole still scene, through the grouping cache.
    fn compute_grouping(&self, spec: GroupingSpec) -> Result<SceneGrouping, FrameError> {
        let started = std::time::Instant::now();
        let (grouping, cached) = spec
            .compute_cached_for_hash(&self.cache, self.hash, self.cloud())
            .map_err(|source| FrameError::Grouping { spec, source })?;
        let seconds = if cached { 0.0 } else { started.elapsed().as_secs_f64() };
        log::info!(
            "grouping {spec}: K = {} in {seconds:.2} s{}",
            grouping.k(),
            if cached { " (from the cache)" } else { "" }
        );
        Ok(SceneGrouping { spec, grouping: Arc::new(grouping), seconds, cached })
    }

    /// Whether a frame of `settings` reads the opacity of the splats `slot`
    /// draws (what its shadows see too).
    fn reads_opacity(&self, slot: Slot, settings: &RenderSettings) -> bool {
        settings.mode.info().transparent && self.drawn(slot).transparent
    }

    /// What the shadow coefficients of a frame of `settings` drawing `slot`
    /// depend on, as a key; `None` for a frame not lit by scene lights.
    fn shadow_key(&self, slot: Slot, settings: &RenderSettings) -> Option<u64> {
        settings.lit_by_lights().then(|| {
            let what = format!(
                "{}|{:?}|{:?}|{}|{}|{:?}|{}",
                self.drawn(slot).key,
                settings.lights,
                settings.shadows,
                settings.epsilon_scale,
                settings.radius_scale,
                settings.kernel,
                self.reads_opacity(slot, settings)
            );
            pointblend_core::hash::fnv1a(pointblend_core::hash::FNV_OFFSET, what.as_bytes())
        })
    }

    /// The shadow coefficients of a frame of `settings` over the whole
    /// scene (none without scene lights), computed when the lights, the
    /// shadow settings or what the splats are drawn as changed since the last ones.
    pub fn shadows(&mut self, settings: &RenderSettings) -> Result<Option<Arc<ShadowCoefficients>>, FrameError> {
        Ok(self.keyed_shadows(Slot::Whole, settings)?.map(|(_, c)| c))
    }

    /// The shadow coefficients of a frame of `settings` over the splats `slot` draws, with their key.
    fn keyed_shadows(
        &mut self,
        slot: Slot,
        settings: &RenderSettings,
    ) -> Result<Option<(u64, Arc<ShadowCoefficients>)>, FrameError> {
        let Some(key) = self.shadow_key(slot, settings) else { return Ok(None) };
        if let Some(kept) = self.prepared.shadows.get(&key) {
            return Ok(Some((key, Arc::clone(kept))));
        }
        let cloud = &self.drawn(slot).cloud;
        let input = ShadowInput::new(cloud, settings, self.reads_opacity(slot, settings));
        let computed = Arc::new(shadow::coefficients(
            &input,
            settings.lights.as_slice(),
            settings.shadows.method,
            settings.shadows.cells,
        )?);
        log::info!(
            "shadows ({}) of {} lights over {} splats in {:.1} ms",
            settings.shadows.method.name(),
            settings.lights.len(),
            cloud.len(),
            computed.seconds * 1e3
        );
        // A few are kept: bench alternates variants, the viewer a preview and a full frame.
        self.prepared.shadows.insert(key, Arc::clone(&computed));
        Ok(Some((key, computed)))
    }

    /// The GPU copy of the whole scene a frame of `spec` draws, uploaded
    /// (and its grouping computed) on first use, with the frame's shadow
    /// coefficients beside its splats.
    pub fn gpu_scene(&mut self, gpu: &GpuRenderer, spec: &FrameSpec) -> Result<&GpuScene, FrameError> {
        Ok(self.gpu_scene_mut(gpu, Slot::Whole, spec, &mut FrameReport::default())?)
    }

    /// The GPU copy of the splats `slot` draws for a frame of `spec`, to
    /// change, with what its shadows took in `report`.
    fn gpu_scene_mut(
        &mut self,
        gpu: &GpuRenderer,
        slot: Slot,
        spec: &FrameSpec,
        report: &mut FrameReport,
    ) -> Result<&mut GpuScene, FrameError> {
        let shadows = self.keyed_shadows(slot, &spec.drawn)?;
        if let Some((_, coefficients)) = &shadows {
            self.report_shadows(slot, &spec.drawn, coefficients, report);
        }
        let upload = self.upload(gpu, slot, spec.grouping.map(|g| g.spec))?;
        upload.set_shadows(&gpu.ctx.device, &gpu.ctx.queue, shadows.as_ref().map(|(key, c)| (c.as_ref(), *key)));
        Ok(upload)
    }

    /// The GPU copy of the splats `slot` draws in grouping `spec` (or
    /// none), made on first use; past `max_grouped` grouped copies of the
    /// slot, the least recently used goes first.
    fn upload(
        &mut self,
        gpu: &GpuRenderer,
        slot: Slot,
        spec: Option<GroupingSpec>,
    ) -> Result<&mut GpuScene, FrameError> {
        let key = (slot, spec);
        let drawn = self.drawn(slot).key;
        if self.prepared.uploads.get(&key).is_none_or(|kept| kept.drawn != drawn) {
            self.prepared.uploads.remove(&key);
            let grouping =
                spec.map(|spec| self.grouping_in(slot, spec).map(|g| Arc::clone(&g.grouping))).transpose()?;
            if spec.is_some() {
                let grouped: Vec<_> = self.prepared.uploads.keys().filter(|(s, g)| *s == slot && g.is_some()).collect();
                let over = (grouped.len() + 1).saturating_sub(self.max_grouped);
                grouped.iter().take(over).for_each(|oldest| drop(self.prepared.uploads.remove(oldest)));
            }
            let spans = self.pooled_nodes(slot, grouping.is_some());
            let arrangement = Arrangement::of(spans.as_deref(), grouping.as_deref());
            let cloud = &self.drawn(slot).cloud;
            let upload = gpu.upload_arranged(cloud, self.scene.environment.as_deref(), arrangement);
            self.uploaded_bytes += upload.splat_bytes();
            self.prepared.uploads.insert(key, Keep { drawn, value: upload });
        }
        Ok(&mut self.prepared.uploads.get(&key).expect("kept above").value)
    }

    /// What the frame's shadows `c` over the splats `slot` draws took, in
    /// `report`: in words, and the milliseconds and MiB of their tables.
    fn report_shadows(&self, slot: Slot, settings: &RenderSettings, c: &ShadowCoefficients, report: &mut FrameReport) {
        let table_bytes: u64 = c.tables.iter().map(|t| t.bytes).sum();
        report.shadow_ms = Some(c.seconds * 1e3);
        report.shadow_table_mib = Some(table_bytes as f64 / (1u64 << 20) as f64);
        let mut notes = vec![format!(
            "{} scene light(s), shadows by {}: {:.1} ms; shadow coefficients {:.1} MiB on the GPU (8 B per splat)",
            settings.lights.len(),
            settings.shadows.method.name(),
            c.seconds * 1e3,
            (self.drawn(slot).cloud.len() * 8) as f64 / (1 << 20) as f64
        )];
        for (k, t) in c.tables.iter().enumerate() {
            notes.push(format!(
                "TSM table of light {}: {}x{} cells, {} entries, {:.1} MiB, built in {:.1} ms",
                k + 1,
                t.cells[0],
                t.cells[1],
                t.entries,
                t.bytes as f64 / (1 << 20) as f64,
                t.build_ms
            ));
        }
        report.shadows = notes;
    }
}
