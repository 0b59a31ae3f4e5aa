//! Frames under a point budget: the splats a frame draws are chosen from
//! the scene's multi-resolution hierarchy ([`crate::lod`]) by screen-space
//! error, then drawn by the frame's mode like any scene.
//!
//! The hierarchy is built on first use (through the cache beside the
//! groupings) over the scene's splats in world space. Each frame selects
//! its nodes (part of the frame's time); when the selection changed, its
//! splats are gathered into one cloud and handed to a [`PreparedScene`] of
//! their own as a moving scene's next frame: modes that draw groups get
//! Zhang & Pajarola's hash grouping of the selected splats, redone in
//! milliseconds on the lattice of the whole scene (cells of the originals'
//! median radius: coarse nodes' larger splats overlap more within a group),
//! and the GPU copies are rewritten (reallocated when the count changed).
//! A frame lit by scene lights keeps the nodes outside the view, which still
//! cast shadows. A budget at or above the scene's splats, a moving scene and
//! the reference draw every splat.

use std::sync::Arc;
use std::time::Instant;

use super::subset::SubsetScene;
use super::{FrameError, PreparedScene};
use crate::cloud::PointCloud;
use crate::frame::subset::{Choosing, Subset};
use crate::frame::{Camera, FrameSpec};
use crate::gpu_renderer::GpuRenderer;
use crate::gpu_scene::GpuScene;
use crate::grouping::cache::Cache;
use crate::lod::subset::BudgetSubset;
use crate::lod::{self, Hierarchy};
use crate::report::{BudgetStats, FrameReport};

/// The hierarchy of `cloud`, a scene's splats in world space whose scene
/// has geometry hash `geometry`: from `cache`, else built and stored; and a
/// line to show when a cache entry was there but not used.
pub fn load_hierarchy(cache: &Cache, geometry: u64, cloud: &PointCloud) -> (Hierarchy, Option<String>) {
    lod::cache::cached(cache, hierarchy_key(geometry, cloud), cloud)
}

/// What keys a scene's hierarchy in the cache: its geometry hash, and the
/// splat count, opacities, colours and sidedness of its splats in world space.
fn hierarchy_key(geometry: u64, cloud: &PointCloud) -> u64 {
    use pointblend_core::hash::fnv1a;
    let mut key = fnv1a(geometry, &(cloud.len() as u64).to_le_bytes());
    let opacity: Vec<u8> = cloud.opacity.iter().flat_map(|a| a.to_le_bytes()).collect();
    key = fnv1a(key, &opacity);
    key = fnv1a(key, &cloud.colours.concat());
    let sides: Vec<u8> = cloud.two_sided.iter().map(|&t| t as u8).collect();
    fnv1a(key, &sides)
}

/// The hierarchy's nodes under a budget, and the frames of their last choice.
pub(super) struct BudgetFrames {
    subset: BudgetSubset,
    chosen: SubsetScene,
}

impl BudgetFrames {
    /// Nothing selected yet from `hierarchy` (cache key `key`) of `parent`'s splats.
    fn new(key: u64, hierarchy: Arc<Hierarchy>, parent: &PreparedScene) -> Box<Self> {
        Box::new(Self { subset: BudgetSubset::new(hierarchy, key), chosen: SubsetScene::of(parent, "budget") })
    }
}

impl PreparedScene {
    /// The hierarchy of the scene's splats, built (or read from the cache) on first use.
    pub fn hierarchy(&mut self) -> Arc<Hierarchy> {
        self.budget_frames().subset.hierarchy.clone()
    }

    /// Frames under a budget draw from `hierarchy`, made elsewhere (the
    /// viewer builds it while loading) from these splats ([`load_hierarchy`]).
    pub fn with_hierarchy(mut self, hierarchy: Arc<Hierarchy>) -> Self {
        if hierarchy.originals == self.cloud.len() {
            self.budget = Some(BudgetFrames::new(hierarchy_key(self.hash, &self.cloud), hierarchy, &self));
        }
        self
    }

    fn budget_frames(&mut self) -> &mut BudgetFrames {
        if self.budget.is_none() {
            let key = hierarchy_key(self.hash, &self.cloud);
            let (hierarchy, note) = lod::cache::cached(&self.cache, key, &self.cloud);
            if let Some(note) = note {
                log::warn!("{note}");
            }
            log::info!(
                "hierarchy of {} splats: {} nodes, {:.1} MiB{}",
                hierarchy.originals,
                hierarchy.nodes.len(),
                hierarchy.bytes() as f64 / (1 << 20) as f64,
                if hierarchy.seconds > 0.0 { format!(", built in {:.2} s", hierarchy.seconds) } else { String::new() }
            );
            self.budget = Some(BudgetFrames::new(key, Arc::new(hierarchy), self));
        }
        self.budget.as_mut().expect("made above")
    }

    /// Selects the nodes the frame `spec` from `camera` draws under
    /// `budget` and, when they changed, hands their splats to the budget's
    /// frames. Returns those frames, and what the selection drew and cost.
    pub(super) fn select_for(
        &mut self,
        gpu: Option<&GpuRenderer>,
        camera: &Camera,
        spec: &FrameSpec,
        budget: u32,
    ) -> Result<(&mut PreparedScene, BudgetStats), FrameError> {
        let state = self.budget_frames();
        let started = Instant::now();
        state.subset.budget = budget;
        let Ok(choice) = state.subset.choose(camera, spec.size, Choosing::of(&spec.drawn));
        let chosen = state.subset.last;
        let frames = state.chosen.next(gpu, choice)?;
        let h = &state.subset.hierarchy;
        let stats = BudgetStats {
            budget,
            nodes: chosen.nodes,
            splats: chosen.splats,
            select_ms: chosen.select_ms,
            update_ms: (started.elapsed().as_secs_f64() * 1e3 - chosen.select_ms).max(0.0),
            changed: chosen.changed,
            build_s: h.seconds,
            hierarchy_nodes: h.nodes.len(),
            hierarchy_bytes: h.bytes(),
        };
        Ok((frames, stats))
    }

    /// The GPU copy of the splats selected under `budget` from `camera` for
    /// the frame `spec` (whose selection is this budget, [`crate::frame::resolve`]),
    /// with what the selection and its shadows cost in `report`.
    pub(super) fn budgeted_scene(
        &mut self,
        gpu: &GpuRenderer,
        camera: &Camera,
        spec: &FrameSpec,
        budget: u32,
        report: &mut FrameReport,
    ) -> Result<&mut GpuScene, FrameError> {
        let (frames, stats) = self.select_for(Some(gpu), camera, spec, budget)?;
        report.budget = Some(stats);
        frames.gpu_scene_mut(gpu, spec, report)
    }
}
