//! A model as the viewer holds it: the loaded scene and its splats in world
//! space, its file's name and content hash (for screenshot sidecars), and
//! its load warnings. While the camera moves, a large model is drawn under a
//! point budget (its multi-resolution hierarchy, see [`crate::lod`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::cloud::{LoadOptions, PointCloud};
use crate::grouping::{Grouping, GroupingSpec};
use crate::scene::{Materials, Scene};

/// The budget while the camera moves, measured to keep the preview of a
/// 1M-splat model near 100 ms a frame on lavapipe (docs/BENCHMARKS.md).
pub const DEFAULT_MOVING_BUDGET: u32 = 100_000;

/// A loaded model.
#[derive(Debug)]
pub struct Model {
    pub path: PathBuf,
    pub name: String,
    /// What identifies the scene's content for caches and sidecars (the file's FNV-1a 64).
    pub hash: u64,
    pub scene: Arc<Scene>,
    /// The scene's splats in world space (see [`Scene::flatten`]).
    pub cloud: Arc<PointCloud>,
    /// Whether some splat is drawn less than opaque (known once, not per frame).
    pub transparent: bool,
    pub warnings: Vec<String>,
    /// Tells models apart, also two loads of the same file.
    pub generation: u64,
    /// Seconds after which the scene's animations repeat (0: nothing moves).
    pub period: f64,
    /// The multi-resolution hierarchy frames under a point budget draw from,
    /// built while loading a still model above the default moving budget
    /// (else built by the render thread when first needed).
    pub hierarchy: Option<Arc<crate::lod::Hierarchy>>,
}

/// A model's grouping for the deferred mode.
#[derive(Debug)]
pub struct GroupedModel {
    pub generation: u64,
    pub spec: GroupingSpec,
    /// Shared with the render thread's copy of the scene (never copied per frame).
    pub grouping: Arc<Grouping>,
    pub seconds: f64,
    pub cached: bool,
}

impl Model {
    /// Loads `path`, a PLY or a scene file (on a worker thread: this decodes,
    /// estimates and hashes), and gives its objects `materials`.
    pub fn load(path: &Path, generation: u64, materials: &Materials) -> Result<Model, String> {
        crate::progress::stage("reading the file");
        let (mut scene, warnings) = crate::scene::open(path, &LoadOptions::default()).map_err(|e| e.to_string())?;
        if scene.is_empty() {
            return Err(format!("{}: the file holds no usable splats", path.display()));
        }
        if let Some(opacity) = materials.opacity {
            scene.set_opacity(opacity);
        }
        if let Some(colour) = materials.colour {
            scene.set_colour(colour);
        }
        Ok(Self::of_scene(path, scene, warnings, generation))
    }

    /// This model with every object at `opacity` (and two-sided when below 1).
    pub fn with_opacity(&self, opacity: f32, generation: u64) -> Model {
        let mut scene = (*self.scene).clone();
        scene.set_opacity(opacity);
        Self::of_scene(&self.path, scene, self.warnings.clone(), generation)
    }

    /// This model in the environment map `map` (or in none).
    pub fn with_environment(
        &self,
        map: Option<Arc<crate::scene::environment::EnvironmentMap>>,
        generation: u64,
    ) -> Model {
        let mut scene = (*self.scene).clone();
        scene.environment = map;
        Self::of_scene(&self.path, scene, self.warnings.clone(), generation)
    }

    /// The first object's opacity, and whether every object has it.
    pub fn opacity(&self) -> (f32, bool) {
        let first = self.scene.objects.first().map_or(1.0, |o| o.material.opacity);
        (first, self.scene.objects.iter().all(|o| o.material.opacity == first))
    }

    /// The model of an already loaded `scene`.
    pub fn of_scene(path: &Path, scene: Scene, warnings: Vec<String>, generation: u64) -> Model {
        let hash = scene.geometry_hash();
        let cloud = scene.flattened();
        let period = scene.animation_period();
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "model".into());
        let transparent = scene.has_transparency();
        Model {
            path: path.to_path_buf(),
            name,
            hash,
            scene: Arc::new(scene),
            cloud,
            transparent,
            warnings,
            generation,
            period,
            hierarchy: None,
        }
    }

    /// This model with its hierarchy, when it is still and larger than the
    /// default moving budget: read from `cache`, or built (with a progress stage) and stored.
    pub fn with_hierarchy(mut self, cache: &crate::grouping::cache::Cache) -> Model {
        if self.is_animated() || self.cloud.len() <= DEFAULT_MOVING_BUDGET as usize {
            return self;
        }
        crate::progress::stage("building the multi-resolution hierarchy");
        let (hierarchy, note) = crate::render::scene_frames::load_hierarchy(cache, self.hash, &self.cloud);
        if let Some(note) = note {
            log::warn!("{note}");
        }
        self.hierarchy = Some(Arc::new(hierarchy));
        self
    }

    /// Whether something in the scene moves.
    pub fn is_animated(&self) -> bool {
        self.period > 0.0
    }

    pub fn hash_hex(&self) -> String {
        format!("{:016x}", self.hash)
    }
}
