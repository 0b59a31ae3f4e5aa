//! A model as the viewer holds it: the loaded scene and its splats in world
//! space, its file's name and content hash (for screenshot sidecars), and
//! its load warnings. A scan with attributes keeps its scene as loaded
//! (`unstyled`) beside the one drawn, so the colour panel restyles it from
//! the file's own values ([`Model::with_style`]). While the camera moves, a large model is drawn under a
//! point budget (its multi-resolution hierarchy, see [`crate::lod`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::cloud::{LoadOptions, PointCloud};
use crate::grouping::{Grouping, GroupingSpec};
use crate::scene::{Materials, Scene};
use crate::style::Style;
use crate::style::summary::Summary;

/// The budget while the camera moves, measured to keep the preview of a
/// 1M-splat model near 100 ms a frame on lavapipe (docs/BENCHMARKS.md).
pub const DEFAULT_MOVING_BUDGET: u32 = 100_000;

/// A loaded model (cloning it shares its scene and splats).
#[derive(Debug, Clone)]
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
    /// The mean splat radius of `cloud` (what ε is a multiple of), found once.
    pub mean_radius: f32,
    pub warnings: Vec<String>,
    /// Tells models apart, also two loads of the same file.
    pub generation: u64,
    /// Seconds after which the scene's animations repeat (0: nothing moves).
    pub period: f64,
    /// The multi-resolution hierarchy frames under a point budget draw from,
    /// built while loading a still model above the default moving budget
    /// (else built by the render thread when first needed).
    pub hierarchy: Option<Arc<crate::lod::Hierarchy>>,
    /// The scene before colour and opacity by attribute, and the style drawn.
    pub unstyled: Arc<Scene>,
    pub style: Option<Arc<Style>>,
    /// The first object's attributes and classes, for the colour panel and the legend.
    pub summary: Arc<Summary>,
    /// The streamed file this model is one view's selection of.
    pub streamed: Option<Arc<super::stream_source::StreamedSource>>,
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
            return Err(format!("{}: the file holds no usable splats", crate::copc::shown(&path.to_string_lossy())));
        }
        Materials { style: None, ..materials.clone() }.apply(&mut scene)?;
        let model = Self::of_scene(path, scene, warnings, generation);
        match &materials.style {
            Some(style) => model.with_style(Some(style.clone()), generation),
            None => Ok(model),
        }
    }

    /// This model coloured and made translucent by `style` (or as loaded),
    /// from the file's own values; an error names what the file lacks.
    pub fn with_style(&self, style: Option<Arc<Style>>, generation: u64) -> Result<Model, String> {
        // No colours named: those the first object is drawn in (survey data's default), so the panel shows them.
        let first = self.unstyled.objects.first().map(|o| &o.cloud);
        let style = match (style, first) {
            (Some(s), Some(cloud)) if s.color_by.is_none() => {
                let color_by = Style::default_for(cloud).and_then(|d| d.color_by);
                Some(Arc::new(Style { color_by, ..(*s).clone() }))
            }
            (style, _) => style,
        };
        let mut scene = (*self.unstyled).clone();
        if let Some(style) = &style {
            scene.apply_style(style)?;
        }
        let model = Self::with_summary(&self.path, scene, self.warnings.clone(), generation, self.summary.clone());
        Ok(Model { unstyled: self.unstyled.clone(), style, ..model })
    }

    /// This model with every object at `opacity` (and two-sided when below 1).
    pub fn with_opacity(&self, opacity: f32, generation: u64) -> Model {
        self.with_materials(generation, |scene| scene.set_opacity(opacity))
    }

    /// This model with object k in `looks[k]` (each layer's opacity, colour and cut).
    pub fn with_looks(&self, looks: &[crate::scene::Look], generation: u64) -> Result<Model, String> {
        let mut checked = Ok(());
        let model = self.with_materials(generation, |scene| {
            let set = scene.set_looks(looks);
            checked = std::mem::replace(&mut checked, Ok(())).and(set);
        });
        checked.map(|()| model)
    }

    /// This model with `edit` made to its objects' materials (and cuts), drawn and as loaded alike.
    fn with_materials(&self, generation: u64, mut edit: impl FnMut(&mut Scene)) -> Model {
        let mut scene = (*self.scene).clone();
        edit(&mut scene);
        let mut unstyled = (*self.unstyled).clone();
        edit(&mut unstyled);
        let model = Self::with_summary(&self.path, scene, self.warnings.clone(), generation, self.summary.clone());
        Model { unstyled: Arc::new(unstyled), style: self.style.clone(), ..model }
    }

    /// This model in the environment map `map` (or in none).
    pub fn with_environment(
        &self,
        map: Option<Arc<crate::scene::environment_map::EnvironmentMap>>,
        generation: u64,
    ) -> Model {
        let mut scene = (*self.scene).clone();
        scene.environment = map.clone();
        let mut unstyled = (*self.unstyled).clone();
        unstyled.environment = map;
        let model = Self::with_summary(&self.path, scene, self.warnings.clone(), generation, self.summary.clone());
        Model { unstyled: Arc::new(unstyled), style: self.style.clone(), ..model }
    }

    /// The first object's opacity, and whether every object has it.
    pub fn opacity(&self) -> (f32, bool) {
        let first = self.scene.objects.first().map_or(1.0, |o| o.material.opacity);
        (first, self.scene.objects.iter().all(|o| o.material.opacity == first))
    }

    /// The model of an already loaded `scene`, drawn as it is (with the
    /// style its scene file gives, which the panel then shows and edits).
    pub fn of_scene(path: &Path, scene: Scene, warnings: Vec<String>, generation: u64) -> Model {
        let unstyled = scene.unstyled();
        let summary = Arc::new(unstyled.objects.first().map(|o| Summary::of(&o.cloud)).unwrap_or_default());
        let style = scene.objects.first().and_then(|o| Some(o.styled.as_ref()?.style.clone()));
        let model = Self::with_summary(path, scene, warnings, generation, summary);
        Model { unstyled: Arc::new(unstyled), style, ..model }
    }

    /// The model of `scene`, whose first object's attributes `summary` sums up.
    fn with_summary(path: &Path, scene: Scene, warnings: Vec<String>, generation: u64, summary: Arc<Summary>) -> Model {
        let hash = scene.geometry_hash();
        let cloud = scene.flattened();
        let period = scene.animation_period();
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "model".into());
        let transparent = scene.has_transparency();
        let mean_radius = cloud.mean_radius();
        let scene = Arc::new(scene);
        Model {
            path: path.to_path_buf(),
            name,
            hash,
            unstyled: scene.clone(),
            style: None,
            summary,
            scene,
            cloud,
            transparent,
            mean_radius,
            warnings,
            generation,
            period,
            hierarchy: None,
            streamed: None,
        }
    }

    /// This model with its hierarchy, when it is still and larger than the
    /// default moving budget: read from `cache`, or built (with a progress stage) and stored.
    pub fn with_hierarchy(mut self, cache: &crate::grouping::cache::Cache) -> Model {
        if self.is_animated() || self.streamed.is_some() || self.cloud.len() <= DEFAULT_MOVING_BUDGET as usize {
            return self;
        }
        crate::progress::stage("building the multi-resolution hierarchy");
        let (hierarchy, note) = crate::render::prepared_scene::load_hierarchy(cache, self.hash, &self.cloud);
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

    /// What a frame of this model is decided over ([`crate::frame::resolve`]),
    /// as the render thread's [`crate::render::PreparedScene::facts`] finds it.
    pub fn facts(&self) -> crate::frame::SceneFacts {
        crate::frame::SceneFacts {
            splats: self.cloud.len(),
            transparent: self.transparent,
            surfaces: self.scene.has_surfaces(),
            moving: self.is_animated(),
            streamed: self.streamed.is_some(),
            mean_radius: self.mean_radius,
            shadows_at_hand: true,
        }
    }

    pub fn hash_hex(&self) -> String {
        format!("{:016x}", self.hash)
    }
}
