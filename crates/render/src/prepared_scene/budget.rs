//! Frames under a point budget: the splats a frame draws are chosen from
//! the scene's multi-resolution hierarchy ([`crate::lod`]) by screen-space
//! error, then drawn by the frame's mode like any scene.
//!
//! The hierarchy is built on first use (through the cache beside the
//! groupings) over the scene's splats in world space. Each frame selects
//! its nodes (part of the frame's time); when the selection changed, its
//! splats are gathered into one cloud and shown in the budget's slot of the
//! scene's cache as a moving scene's next frame (`show.rs`): modes that draw groups get
//! Zhang & Pajarola's hash grouping of the selected splats, redone in
//! milliseconds on the lattice of the whole scene (cells of the originals'
//! median radius: coarse nodes' larger splats overlap more within a group),
//! and the GPU copies are rewritten (reallocated when the count changed):
//! the ungrouped copy keeps the selection's nodes in a node pool
//! ([`crate::node_pool`]), so only the nodes a view adds are written, and
//! the grouped copies are packed and written where their records changed.
//! A frame lit by scene lights keeps the nodes outside the view, which still
//! cast shadows. A budget at or above the scene's splats, a moving scene and
//! the reference draw every splat.

use std::sync::Arc;
use std::time::Instant;

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
use crate::scene_cache::Slot;

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

impl PreparedScene {
    /// The hierarchy of the scene's splats, built (or read from the cache) on first use.
    pub fn hierarchy(&mut self) -> Arc<Hierarchy> {
        Arc::clone(&self.budget_subset().hierarchy)
    }

    /// Frames under a budget draw from `hierarchy`, made elsewhere (the
    /// viewer builds it while loading) from these splats ([`load_hierarchy`]).
    pub fn with_hierarchy(mut self, hierarchy: Arc<Hierarchy>) -> Self {
        if hierarchy.originals == self.cloud().len() {
            let key = hierarchy_key(self.hash, self.cloud());
            self.budget = Some(BudgetSubset::new(hierarchy, key));
        }
        self
    }

    /// The hierarchy's nodes under a budget, over the hierarchy read from
    /// the cache or built on first use (made once per scene, it is the
    /// subset's own: what it chooses from).
    fn budget_subset(&mut self) -> &mut BudgetSubset {
        if self.budget.is_none() {
            let key = hierarchy_key(self.hash, self.cloud());
            let hierarchy = Arc::new(self.load_hierarchy(key));
            self.budget = Some(BudgetSubset::new(hierarchy, key));
        }
        self.budget.as_mut().expect("made above")
    }

    /// The hierarchy of the scene's splats under cache key `key`, read or built, and said.
    fn load_hierarchy(&self, key: u64) -> Hierarchy {
        let (hierarchy, note) = lod::cache::cached(&self.cache, key, self.cloud());
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
        hierarchy
    }

    /// The GPU copy of the splats selected under `budget` from `camera` for
    /// the frame `spec` (whose selection is this budget, [`crate::frame::resolve`]):
    /// the nodes are selected and, when they changed, their splats shown in
    /// the budget's slot. What the selection and its shadows cost goes in `report`.
    pub(super) fn budgeted_scene(
        &mut self,
        gpu: &GpuRenderer,
        camera: &Camera,
        spec: &FrameSpec,
        budget: u32,
        report: &mut FrameReport,
    ) -> Result<&mut GpuScene, FrameError> {
        let started = Instant::now();
        let subset = self.budget_subset();
        subset.budget = budget;
        let Ok(choice) = subset.choose(camera, spec.size, Choosing::of(&spec.drawn));
        let (chosen, hierarchy) = (subset.last, Arc::clone(&subset.hierarchy));
        self.show_choice(Some(gpu), Slot::Budget, choice)?;
        report.budget = Some(BudgetStats {
            budget,
            nodes: chosen.nodes,
            splats: chosen.splats,
            select_ms: chosen.select_ms,
            update_ms: (started.elapsed().as_secs_f64() * 1e3 - chosen.select_ms).max(0.0),
            changed: chosen.changed,
            build_s: hierarchy.seconds,
            hierarchy_nodes: hierarchy.nodes.len(),
            hierarchy_bytes: hierarchy.bytes(),
        });
        self.gpu_scene_mut(gpu, Slot::Budget, spec, report)
    }
}
