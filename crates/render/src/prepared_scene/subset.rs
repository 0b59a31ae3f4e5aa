//! Frames of the splats a [`Subset`](crate::frame::subset::Subset) chooses
//! per view from a scene: the nodes under a point budget (`budget.rs`), or
//! the splats drawn beside a frame's mesh triangles (`hybrid.rs`). Each new
//! choice is shown as a moving scene's next frame, so the modes that draw groups get
//! Zhang & Pajarola's hash grouping of the chosen splats, redone in
//! milliseconds on the whole scene's lattice, and the GPU copies are
//! rewritten (reallocated when the count changed).

use std::sync::Arc;

use super::{FrameError, PreparedScene};
use crate::frame::subset::Choice;
use crate::gpu_renderer::GpuRenderer;
use crate::grouping::cache::Cache;
use crate::grouping::regroup::Lattice;
use crate::scene::Scene;
use crate::scene::environment_map::EnvironmentMap;

/// The frames of the last choice from one scene, and what they take from it.
pub(super) struct SubsetScene {
    frames: Option<Box<PreparedScene>>,
    /// The whole scene's lattice: groups are counted on it, whatever is chosen.
    lattice: Lattice,
    environment: Option<Arc<EnvironmentMap>>,
    cache: Cache,
    /// The chosen scene's name ("budget", "hybrid").
    name: &'static str,
}

impl SubsetScene {
    /// Nothing chosen yet from `parent`'s splats.
    pub(super) fn of(parent: &PreparedScene, name: &'static str) -> Self {
        Self {
            frames: None,
            lattice: Lattice::of(&parent.cloud),
            environment: parent.scene.environment.clone(),
            cache: parent.cache.clone(),
            name,
        }
    }

    /// The frames of the splats `choice` names: the last ones when it holds
    /// no new cloud, else its cloud as the next frame of a moving scene.
    pub(super) fn next(&mut self, gpu: Option<&GpuRenderer>, choice: Choice) -> Result<&mut PreparedScene, FrameError> {
        if choice.cloud.is_none() && self.frames.is_some() {
            return Ok(self.frames.as_deref_mut().expect("checked above"));
        }
        // A subset's first choice always holds its splats.
        let (cloud, key) = (choice.cloud.unwrap_or_default(), choice.key);
        let shown = self.frames.take();
        let mut scene = Scene::single(self.name, cloud, key);
        scene.environment = self.environment.clone();
        let scene = Arc::new(scene);
        let cloud = scene.flattened();
        let frames = match shown {
            Some(mut frames) => {
                frames.advance(gpu, scene, cloud)?;
                frames
            }
            None => Box::new(PreparedScene::new(scene, cloud).moving_on(self.lattice).with_cache(self.cache.clone())),
        };
        Ok(self.frames.insert(frames))
    }
}
