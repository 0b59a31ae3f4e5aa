//! A model as the viewer holds it: the loaded scene and its splats in world
//! space, its file's name and content hash (for screenshot sidecars), its
//! load warnings, and a subsampled preview cloud that large models draw while
//! the camera moves.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::cloud::{LoadOptions, PointCloud};
use crate::grouping::{Grouping, GroupingSpec};
use crate::scene::{Materials, Scene};

/// Models with more splats than this get a preview cloud of this many.
pub const PREVIEW_SPLATS: usize = 200_000;

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
    /// A subsample with enlarged splats, for models above [`PREVIEW_SPLATS`].
    /// Whether some splat is drawn less than opaque (known once, not per frame).
    pub transparent: bool,
    pub preview: Option<Arc<PointCloud>>,
    pub warnings: Vec<String>,
    /// Tells models apart, also two loads of the same file.
    pub generation: u64,
    /// Seconds after which the scene's animations repeat (0: nothing moves).
    pub period: f64,
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
        crate::progress::stage("building the preview");
        let period = scene.animation_period();
        // A moving scene has no preview: its subsample would have to move too.
        let preview =
            (cloud.len() > PREVIEW_SPLATS && period <= 0.0).then(|| Arc::new(subsample(&cloud, PREVIEW_SPLATS)));
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "model".into());
        let transparent = scene.has_transparency();
        Model {
            path: path.to_path_buf(),
            name,
            hash,
            scene: Arc::new(scene),
            cloud,
            preview,
            transparent,
            warnings,
            generation,
            period,
        }
    }

    /// Whether something in the scene moves.
    pub fn is_animated(&self) -> bool {
        self.period > 0.0
    }

    pub fn hash_hex(&self) -> String {
        format!("{:016x}", self.hash)
    }
}

/// Every (n/count)-th splat, with radii grown by sqrt(n/count) so that the
/// subsample still covers the surface.
pub fn subsample(cloud: &PointCloud, count: usize) -> PointCloud {
    let n = cloud.len();
    let count = count.clamp(1, n.max(1));
    let picks: Vec<usize> = (0..count).map(|i| i * n / count).collect();
    let grow = (n as f32 / count as f32).sqrt();
    PointCloud {
        positions: picks.iter().map(|&i| cloud.positions[i]).collect(),
        normals: picks.iter().map(|&i| cloud.normals[i]).collect(),
        radii: picks.iter().map(|&i| cloud.radii[i] * grow).collect(),
        colours: picks.iter().map(|&i| cloud.colours[i]).collect(),
        opacity: picks.iter().map(|&i| cloud.opacity[i]).collect(),
        two_sided: if cloud.two_sided.is_empty() {
            Vec::new()
        } else {
            picks.iter().map(|&i| cloud.two_sided[i]).collect()
        },
        origin: cloud.origin,
        scale_exponent: cloud.scale_exponent,
        scanner_position: cloud.scanner_position,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_subsample_keeps_the_coverage_of_the_surface() {
        let n = 10_000;
        let cloud = PointCloud {
            positions: (0..n).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect(),
            normals: vec![Vec3::Z; n],
            radii: vec![1.0; n],
            colours: vec![[1, 2, 3]; n],
            opacity: vec![1.0; n],
            ..Default::default()
        };
        let sub = subsample(&cloud, 2_500);
        assert_eq!(sub.len(), 2_500);
        assert!(sub.is_consistent());
        // Total disc area (Σ r²) is preserved.
        let area = |c: &PointCloud| c.radii.iter().map(|r| r * r).sum::<f32>();
        assert!((area(&sub) / area(&cloud) - 1.0).abs() < 1e-3);
        assert_eq!(sub.positions[1].x, 4.0);
    }
}
