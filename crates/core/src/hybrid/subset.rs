//! The splats a hybrid frame draws beside its triangles, as a [`Subset`]:
//! each frame chooses which leaves are drawn as triangles and which as
//! splats (Guennebaud's hybrid rules, [`super::select`]), and gathers the
//! splats into one cloud only when they changed. The triangles chosen stay
//! with the last selection, for the renderer to draw their ranges.

use std::sync::Arc;
use std::time::Instant;

use super::select::{HybridOptions, HybridSelection, SceneSurfaces};
use crate::cloud::PointCloud;
use crate::frame::Camera;
use crate::frame::subset::Choosing;
use crate::frame::subset::{Choice, Subset};

/// The leaves of a scene's hybrid objects, and the last choice among them.
pub struct HybridSubset {
    pub surfaces: SceneSurfaces,
    /// The scene's splats in world space, the splats are chosen from.
    whole: Arc<PointCloud>,
    /// Names the scene's splats: choices are keyed by it and their splats.
    key: u64,
    selected: Option<HybridSelection>,
    /// The key of the last choice.
    chosen_key: u64,
    /// Leaves are drawn as triangles where their splats would pass this
    /// radius in pixels; set per frame (the frame's spec says it).
    pub pixels: f32,
    /// Choosing the leaves, in milliseconds, the last time.
    pub select_ms: f64,
}

impl HybridSubset {
    /// Nothing chosen yet from `surfaces` of the splats `whole`, which `key` names.
    pub fn new(surfaces: SceneSurfaces, whole: Arc<PointCloud>, key: u64) -> Self {
        HybridSubset { surfaces, whole, key, selected: None, chosen_key: key, pixels: 0.0, select_ms: 0.0 }
    }

    /// The last selection: its triangles, splats and leaves.
    pub fn selection(&self) -> Option<&HybridSelection> {
        self.selected.as_ref()
    }
}

impl Subset for HybridSubset {
    type Error = std::convert::Infallible;

    fn choose(&mut self, camera: &Camera, size: (u32, u32), choosing: Choosing) -> Result<Choice, Self::Error> {
        let started = Instant::now();
        let options = HybridOptions { pixels: self.pixels, radius_scale: choosing.radius_scale, cull: choosing.cull };
        let selection = self.surfaces.select(camera, size, options);
        self.select_ms = started.elapsed().as_secs_f64() * 1e3;
        let changed = self.selected.as_ref().is_none_or(|s| s.splats != selection.splats);
        let cloud = if changed {
            // Hashed only when the splats changed: a still view costs no pass over them.
            let splats: Vec<u8> = selection.splats.iter().flat_map(|v| v.to_le_bytes()).collect();
            self.chosen_key = crate::hash::fnv1a(self.key, &splats);
            Some(selection.gather(&self.whole))
        } else {
            None
        };
        self.selected = Some(selection);
        Ok(Choice { cloud, key: self.chosen_key, grouping: None, spans: None })
    }
}
