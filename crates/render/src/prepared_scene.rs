//! The one way to render a scene in any mode: `pointblend render`, `bench`
//! and the viewer's render thread all go through [`PreparedScene`].
//!
//! A [`PreparedScene`] holds a scene, its splats in world space, the groupings
//! its modes draw and its GPU copies (one ungrouped, one per grouping). A
//! frame asks it for `settings`, a camera and a size; the registry says where
//! the mode runs: a GPU mode takes the grouping it draws (from the scene's
//! groupings, computed through the grouping cache when the front end lets
//! it), the matching upload, and its plan on the [`GpuRenderer`]; the
//! exact reference (a CPU mode) renders the scene itself. Either way the
//! frame comes back as an image and the plan that made it.

mod budget;
mod hybrid;
mod render_frame;
mod subset;

use std::sync::Arc;

pub use crate::report::{BudgetStats, FrameUpdate, HybridStats};
pub use budget::load_hierarchy;
pub use render_frame::{Frame, Readback};

use super::context::GpuError;
use super::gpu_renderer::GpuRenderer;
use super::gpu_scene::GpuScene;
use crate::cloud::PointCloud;
use crate::frame::{FrameSpec, RenderSettings};
use crate::grouping::hash::{Collisions, HashOptions};
use crate::grouping::regroup::{HashRegrouper, Lattice};
use crate::grouping::{Extension, Grouping, GroupingAlgo, GroupingError, GroupingSpec, cache::Cache};
use crate::report::FrameReport;
use crate::scene::Scene;
use crate::shadow::{self, ShadowCoefficients, ShadowInput};

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

/// A grouping of the scene, with what it cost.
#[derive(Debug, Clone)]
pub struct SceneGrouping {
    pub spec: GroupingSpec,
    pub grouping: Arc<Grouping>,
    /// Seconds it took to compute (0 when it came from the cache).
    pub seconds: f64,
    pub cached: bool,
}

/// Shadow coefficient sets kept per scene (each 4 bytes per splat and light).
const KEPT_SHADOWS: usize = 4;

/// A scene ready to render in any mode.
pub struct PreparedScene {
    scene: Arc<Scene>,
    /// The splats in world space (the scene's, or a preview subsample of them).
    cloud: Arc<PointCloud>,
    /// The content hash that keys the grouping cache.
    hash: u64,
    /// Groupings the front end handed in, or computed through the cache.
    groupings: Vec<SceneGrouping>,
    /// Whether a grouping missing here is computed (through the cache) rather than refused.
    compute_groupings: bool,
    /// GPU copies: ungrouped (`None`) and one per grouping drawn.
    uploads: Vec<(Option<GroupingSpec>, GpuScene)>,
    /// Most grouped copies kept; the oldest goes first (the viewer keeps one).
    max_grouped: usize,
    /// Whether some splat of `cloud` is less than opaque (asked every frame, so kept).
    transparent: bool,
    /// The last shadow coefficients computed, newest last, and what for (see [`Self::shadow_key`]).
    shadows: Vec<(u64, Arc<ShadowCoefficients>)>,
    /// For a moving scene: a hash regrouper per grouping algorithm drawn
    /// (specs that differ only in their extension share one), redone every frame.
    regroupers: Option<Vec<(GroupingAlgo, HashRegrouper)>>,
    /// The lattice a moving scene's hash groups are counted on (see [`rest_lattice`]);
    /// the first frame's when none is given.
    lattice: Option<Lattice>,
    /// Counts the frames a moving scene has shown (keys the shadows).
    generation: u64,
    /// The splats are a streamed file's selection, made under its budget already.
    streamed: bool,
    /// The mean splat radius of `cloud` (what ε is a multiple of), found once.
    mean_radius: f32,
    /// Frames under a point budget (see `budget.rs`), made on first use.
    budget: Option<Box<budget::BudgetFrames>>,
    /// Frames that draw the scene's mesh triangles (see `hybrid.rs`), made on first use.
    hybrid: Option<Box<hybrid::HybridFrames>>,
    /// Where groupings and hierarchies are cached.
    cache: Cache,
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
        let transparent = cloud.has_transparency();
        let mean_radius = cloud.mean_radius();
        Self {
            scene,
            cloud,
            hash,
            groupings: Vec::new(),
            compute_groupings: true,
            uploads: Vec::new(),
            max_grouped: usize::MAX,
            shadows: Vec::new(),
            transparent,
            regroupers: None,
            lattice: None,
            generation: 0,
            streamed: false,
            mean_radius,
            budget: None,
            hybrid: None,
            cache: Cache::from_env(),
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
        self.regroupers = Some(Vec::new());
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

    /// Whether the scene moves.
    pub fn is_moving(&self) -> bool {
        self.regroupers.is_some()
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
        self.hash = scene.geometry_hash();
        self.transparent = cloud.has_transparency();
        self.mean_radius = cloud.mean_radius();
        self.scene = scene;
        self.cloud = cloud;
        self.generation += 1;
        self.shadows.clear();
        if self.regroupers.is_none() {
            self.regroupers = Some(Vec::new());
        }
        let mut update = FrameUpdate::default();
        let specs: Vec<GroupingSpec> = self.groupings.iter().map(|g| g.spec).collect();
        let mut fresh: Vec<SceneGrouping> = Vec::with_capacity(specs.len());
        for spec in specs {
            // A spec whose algorithm was regrouped this frame takes those groups.
            let shared = fresh.iter().find(|g| g.spec.algo == spec.algo).map(|g| (Arc::clone(&g.grouping), g.seconds));
            let grouping = match shared {
                Some((grouping, seconds)) => SceneGrouping {
                    spec,
                    grouping: Arc::new(with_extension(grouping.as_ref().clone(), spec)),
                    seconds,
                    cached: false,
                },
                None => {
                    let (grouping, labelled) = self.regroup(spec)?;
                    update.regrouped += labelled;
                    update.regroup_ms += grouping.seconds * 1e3;
                    grouping
                }
            };
            update.regroup_ms_of.push((spec, grouping.seconds * 1e3));
            fresh.push(grouping);
        }
        self.groupings = fresh;
        match gpu {
            Some(gpu) => {
                for (spec, upload) in &mut self.uploads {
                    let started = std::time::Instant::now();
                    let grouping = spec.and_then(|s| self.groupings.iter().find(|g| g.spec == s));
                    let grouping = grouping.map(|g| g.grouping.as_ref());
                    let bytes = upload.rewrite(&gpu.ctx.device, &gpu.ctx.queue, &self.cloud, grouping);
                    let ms = started.elapsed().as_secs_f64() * 1e3;
                    update.upload_of.push((*spec, ms, bytes));
                    update.upload_ms += ms;
                    update.uploaded_bytes += bytes;
                }
            }
            None => self.uploads.clear(),
        }
        Ok(update)
    }

    /// Hash grouping `spec` of the current splats by its regrouper (made on
    /// first use); returns it and the splats labelled.
    fn regroup(&mut self, spec: GroupingSpec) -> Result<(SceneGrouping, usize), FrameError> {
        let GroupingAlgo::Hash { k, resolve_collisions } = spec.algo else {
            return Err(FrameError::NoGrouping(spec));
        };
        let collisions = if resolve_collisions { Collisions::All } else { Collisions::None };
        let options = HashOptions { k, collisions };
        let regroupers = self.regroupers.get_or_insert_with(Vec::new);
        let at = match regroupers.iter().position(|(a, _)| *a == spec.algo) {
            Some(at) => at,
            None => {
                let lattice = self.lattice.unwrap_or_else(|| Lattice::of(&self.cloud));
                let regrouper =
                    HashRegrouper::new(lattice, options).map_err(|source| FrameError::Grouping { spec, source })?;
                regroupers.push((spec.algo, regrouper));
                regroupers.len() - 1
            }
        };
        let started = std::time::Instant::now();
        let regrouper = &mut regroupers[at].1;
        let grouping = with_extension(regrouper.regroup(&self.cloud), spec);
        let seconds = started.elapsed().as_secs_f64();
        let labelled = regrouper.stats().labelled;
        Ok((SceneGrouping { spec, grouping: Arc::new(grouping), seconds, cached: false }, labelled))
    }

    /// A scene with its own splats ([`Scene::flattened`]: shared, not copied, for a plain single object).
    pub fn of(scene: Arc<Scene>) -> Self {
        let cloud = scene.flattened();
        Self::new(scene, cloud)
    }

    /// Groupings come only from [`Self::add_grouping`] (the viewer computes
    /// them in a job of its own), and at most `max_grouped` grouped copies stay on the GPU.
    pub fn handed_groupings(mut self, max_grouped: usize) -> Self {
        self.compute_groupings = false;
        self.max_grouped = max_grouped.max(1);
        self
    }

    pub fn scene(&self) -> &Arc<Scene> {
        &self.scene
    }

    pub fn cloud(&self) -> &Arc<PointCloud> {
        &self.cloud
    }

    /// Hands in a grouping computed elsewhere (nothing happens when it is here
    /// already); past `max_grouped` of them, the oldest is dropped.
    pub fn add_grouping(&mut self, grouping: SceneGrouping) {
        if !self.groupings.iter().any(|g| g.spec == grouping.spec) {
            self.groupings.push(grouping);
            if self.groupings.len() > self.max_grouped {
                let dropped = self.groupings.remove(0).spec;
                self.uploads.retain(|(s, _)| *s != Some(dropped));
            }
        }
    }

    /// The grouping `spec`, computed through the cache when it is not here.
    pub fn grouping(&mut self, spec: GroupingSpec) -> Result<&SceneGrouping, FrameError> {
        if let Some(at) = self.groupings.iter().position(|g| g.spec == spec) {
            return Ok(&self.groupings[at]);
        }
        if self.is_moving() {
            let (grouping, _) = self.regroup(spec)?;
            self.groupings.push(grouping);
            return Ok(self.groupings.last().expect("just pushed"));
        }
        if !self.compute_groupings {
            return Err(FrameError::NoGrouping(spec));
        }
        let started = std::time::Instant::now();
        let (grouping, cached) = spec
            .compute_cached_for_hash(&self.cache, self.hash, &self.cloud)
            .map_err(|source| FrameError::Grouping { spec, source })?;
        let seconds = if cached { 0.0 } else { started.elapsed().as_secs_f64() };
        log::info!(
            "grouping {spec}: K = {} in {seconds:.2} s{}",
            grouping.k(),
            if cached { " (from the cache)" } else { "" }
        );
        self.groupings.push(SceneGrouping { spec, grouping: Arc::new(grouping), seconds, cached });
        Ok(self.groupings.last().expect("just pushed"))
    }

    /// Whether a frame of `settings` reads opacity (what its shadows see too).
    fn reads_opacity(&self, settings: &RenderSettings) -> bool {
        settings.mode.info().transparent && self.transparent
    }

    /// What the shadow coefficients of a frame of `settings` depend on, as a
    /// key; `None` for a frame not lit by scene lights.
    pub fn shadow_key(&self, settings: &RenderSettings) -> Option<u64> {
        settings.lit_by_lights().then(|| {
            let what = format!(
                "{}|{:?}|{:?}|{}|{}|{:?}|{}",
                self.generation,
                settings.lights,
                settings.shadows,
                settings.epsilon_scale,
                settings.radius_scale,
                settings.kernel,
                self.reads_opacity(settings)
            );
            pointblend_core::hash::fnv1a(pointblend_core::hash::FNV_OFFSET, what.as_bytes())
        })
    }

    /// The shadow coefficients of a frame of `settings` (none without scene
    /// lights), computed when the lights, the shadow settings or what the
    /// splats are drawn as changed since the last ones.
    pub fn shadows(&mut self, settings: &RenderSettings) -> Result<Option<Arc<ShadowCoefficients>>, FrameError> {
        Ok(self.keyed_shadows(settings)?.map(|(_, c)| c))
    }

    /// [`Self::shadows`] with their key.
    fn keyed_shadows(
        &mut self,
        settings: &RenderSettings,
    ) -> Result<Option<(u64, Arc<ShadowCoefficients>)>, FrameError> {
        let Some(key) = self.shadow_key(settings) else { return Ok(None) };
        if let Some(at) = self.shadows.iter().position(|(k, _)| *k == key) {
            let hit = self.shadows.remove(at);
            self.shadows.push(hit);
            return Ok(self.shadows.last().cloned());
        }
        let input = ShadowInput::new(&self.cloud, settings, self.reads_opacity(settings));
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
            self.cloud.len(),
            computed.seconds * 1e3
        );
        // A few are kept: bench alternates variants, the viewer a preview and a full frame.
        if self.shadows.len() == KEPT_SHADOWS {
            self.shadows.remove(0);
        }
        self.shadows.push((key, Arc::clone(&computed)));
        Ok(Some((key, computed)))
    }

    /// The GPU copy a frame of `spec` draws, uploaded (and its grouping
    /// computed) on first use, with the frame's shadow coefficients beside its splats.
    pub fn gpu_scene(&mut self, gpu: &GpuRenderer, spec: &FrameSpec) -> Result<&GpuScene, FrameError> {
        Ok(self.gpu_scene_mut(gpu, spec, &mut FrameReport::default())?)
    }

    /// [`Self::gpu_scene`], to change, with what its shadows took in `report`.
    fn gpu_scene_mut(
        &mut self,
        gpu: &GpuRenderer,
        spec: &FrameSpec,
        report: &mut FrameReport,
    ) -> Result<&mut GpuScene, FrameError> {
        let shadows = self.keyed_shadows(&spec.drawn)?;
        if let Some((_, coefficients)) = &shadows {
            self.report_shadows(&spec.drawn, coefficients, report);
        }
        let at = self.upload(gpu, spec.grouping.map(|g| g.spec))?;
        let upload = &mut self.uploads[at].1;
        upload.set_shadows(&gpu.ctx.device, &gpu.ctx.queue, shadows.as_ref().map(|(key, c)| (c.as_ref(), *key)));
        Ok(&mut self.uploads[at].1)
    }

    /// The index of the upload drawing grouping `spec` (or none), made on first use.
    fn upload(&mut self, gpu: &GpuRenderer, spec: Option<GroupingSpec>) -> Result<usize, FrameError> {
        if let Some(at) = self.uploads.iter().position(|(s, _)| *s == spec) {
            return Ok(at);
        }
        let grouping = spec.map(|spec| self.grouping(spec).map(|g| Arc::clone(&g.grouping))).transpose()?;
        if spec.is_some() {
            // Free the oldest grouped copy first when the limit is reached.
            while self.uploads.iter().filter(|(s, _)| s.is_some()).count() >= self.max_grouped {
                let oldest = self.uploads.iter().position(|(s, _)| s.is_some()).expect("counted above");
                self.uploads.remove(oldest);
            }
        }
        let upload = gpu.upload_in(&self.cloud, self.scene.environment.as_deref(), grouping.as_deref());
        self.uploads.push((spec, upload));
        Ok(self.uploads.len() - 1)
    }

    /// What the frame's shadows `c` took, in `report`: in words, and the
    /// milliseconds and MiB of their tables.
    fn report_shadows(&self, settings: &RenderSettings, c: &ShadowCoefficients, report: &mut FrameReport) {
        let table_bytes: u64 = c.tables.iter().map(|t| t.bytes).sum();
        report.shadow_ms = Some(c.seconds * 1e3);
        report.shadow_table_mib = Some(table_bytes as f64 / (1u64 << 20) as f64);
        let mut notes = vec![format!(
            "{} scene light(s), shadows by {}: {:.1} ms; shadow coefficients {:.1} MiB on the GPU (8 B per splat)",
            settings.lights.len(),
            settings.shadows.method.name(),
            c.seconds * 1e3,
            (self.cloud.len() * 8) as f64 / (1 << 20) as f64
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
