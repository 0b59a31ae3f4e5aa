//! A scene: one or more objects, each a point cloud with a transform and a
//! material, rendered together. Opening one PLY file gives a scene of one
//! object. Every renderer (the GPU modes, the CPU reference, `bench`, the
//! viewer) takes a scene.
//!
//! Renderers see a scene through [`Scene::flatten`]: all objects' splats in
//! world space with their materials applied, in object order, plus the range
//! each object occupies. A scene of one object with the identity transform
//! and the default material flattens to its cloud as it is, without a copy.

mod material;

use std::borrow::Cow;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use glam::{Affine3A, Vec3};

use crate::cloud::{self, CloudError, LoadOptions, LoadReport, PointCloud};
use crate::grouping::cache::{FNV_OFFSET, fnv1a};
pub use material::Material;

/// One object of a scene.
#[derive(Debug, Clone)]
pub struct SceneObject {
    /// A name for messages (the file name).
    pub name: String,
    pub cloud: Arc<PointCloud>,
    /// Object to world.
    pub transform: Affine3A,
    pub material: Material,
    /// FNV-1a of the file the cloud came from (or of how it was generated).
    pub content_hash: u64,
}

impl SceneObject {
    fn is_plain(&self) -> bool {
        self.transform == Affine3A::IDENTITY && self.material == Material::default()
    }
}

/// Objects rendered together.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    pub objects: Vec<SceneObject>,
}

/// A scene's splats in world space, materials applied.
#[derive(Debug, Clone)]
pub struct FlatScene<'a> {
    pub cloud: Cow<'a, PointCloud>,
    /// The splats of each object, in `cloud`.
    pub objects: Vec<Range<u32>>,
}

impl Scene {
    /// A scene of `cloud` alone.
    pub fn single(name: impl Into<String>, cloud: PointCloud, content_hash: u64) -> Self {
        let object = SceneObject {
            name: name.into(),
            cloud: Arc::new(cloud),
            transform: Affine3A::IDENTITY,
            material: Material::default(),
            content_hash,
        };
        Scene { objects: vec![object] }
    }

    /// Loads the PLY file at `path` as a scene of one object.
    pub fn load(path: &Path, options: &LoadOptions) -> Result<(Scene, LoadReport), CloudError> {
        let (cloud, report) = cloud::load_with(path, options)?;
        let hash = crate::grouping::cache::file_hash(path).map_err(|e| CloudError::io(path, e))?;
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "model".into());
        Ok((Scene::single(name, cloud, hash), report))
    }

    /// Splats over all objects.
    pub fn len(&self) -> usize {
        self.objects.iter().map(|o| o.cloud.len()).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A name for the scene: its object's, or the first object's and how many more.
    pub fn name(&self) -> String {
        match self.objects.as_slice() {
            [] => "empty scene".into(),
            [one] => one.name.clone(),
            [first, rest @ ..] => format!("{} and {} more", first.name, rest.len()),
        }
    }

    /// Identifies the scene's content (files, transforms, materials) for caches.
    pub fn content_hash(&self) -> u64 {
        if let [one] = self.objects.as_slice() {
            if one.is_plain() {
                return one.content_hash; // the file's own hash: caches made from the file stay valid
            }
        }
        self.objects.iter().fold(FNV_OFFSET, |h, o| {
            let h = fnv1a(h, &o.content_hash.to_le_bytes());
            let h = fnv1a(h, bytemuck_floats(&o.transform.to_cols_array()).as_slice());
            fnv1a(h, format!("{:?}", o.material).as_bytes())
        })
    }

    /// All splats in world space with the materials applied (see the module doc).
    pub fn flatten(&self) -> FlatScene<'_> {
        if let [one] = self.objects.as_slice() {
            if one.is_plain() {
                return FlatScene {
                    cloud: Cow::Borrowed(one.cloud.as_ref()),
                    objects: std::iter::once(0..one.cloud.len() as u32).collect(),
                };
            }
        }
        let mut out = PointCloud::default();
        let mut objects = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            let start = out.len() as u32;
            let scale = o.transform.matrix3.determinant().abs().cbrt();
            let normal_matrix = o.transform.matrix3.inverse().transpose();
            out.positions.extend(o.cloud.positions.iter().map(|p| o.transform.transform_point3(*p)));
            out.normals.extend(
                o.cloud.normals.iter().map(|n| Vec3::from(normal_matrix * glam::Vec3A::from(*n)).normalize_or_zero()),
            );
            out.radii.extend(o.cloud.radii.iter().map(|r| r * scale));
            out.colors.extend(o.cloud.colors.iter().map(|c| o.material.colour(*c)));
            out.opacity.extend(o.cloud.opacity.iter().map(|a| o.material.opacity(*a)));
            objects.push(start..out.len() as u32);
        }
        if let Some(first) = self.objects.first() {
            out.origin = first.cloud.origin;
            out.scale_exponent = first.cloud.scale_exponent;
        }
        FlatScene { cloud: Cow::Owned(out), objects }
    }
}

impl Scene {
    /// [`Scene::flatten`] as a shared cloud (the object's own for a plain single object).
    pub fn flattened(&self) -> Arc<PointCloud> {
        if let [one] = self.objects.as_slice() {
            if one.is_plain() {
                return Arc::clone(&one.cloud);
            }
        }
        Arc::new(self.flatten().cloud.into_owned())
    }
}

impl From<PointCloud> for Scene {
    /// A scene of one cloud made in memory, keyed for caches by its content.
    fn from(cloud: PointCloud) -> Self {
        let floats = |v: &[Vec3]| bytemuck_floats(&v.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>());
        let mut hash = fnv1a(FNV_OFFSET, &floats(&cloud.positions));
        hash = fnv1a(hash, &floats(&cloud.normals));
        hash = fnv1a(hash, &bytemuck_floats(&cloud.radii));
        hash = fnv1a(hash, &cloud.colors.concat());
        Scene::single("cloud", cloud, hash)
    }
}

/// The bytes of some floats, for hashing.
fn bytemuck_floats(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dot(colour: [u8; 3]) -> PointCloud {
        PointCloud {
            positions: vec![Vec3::new(1.0, 0.0, 0.0)],
            normals: vec![Vec3::X],
            radii: vec![0.5],
            colors: vec![colour],
            opacity: vec![1.0],
            ..Default::default()
        }
    }

    #[test]
    fn one_plain_object_flattens_to_its_cloud_without_a_copy() {
        let scene = Scene::single("a", dot([1, 2, 3]), 7);
        let flat = scene.flatten();
        assert!(matches!(flat.cloud, Cow::Borrowed(_)));
        assert_eq!(scene.content_hash(), 7, "the file's hash keys the caches");
    }

    #[test]
    fn objects_are_placed_scaled_and_coloured_in_world_space() {
        let mut scene = Scene::single("a", dot([1, 2, 3]), 7);
        let mut second = scene.objects[0].clone();
        second.transform = Affine3A::from_scale_rotation_translation(
            Vec3::splat(2.0),
            glam::Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
            Vec3::new(0.0, 0.0, 5.0),
        );
        second.material = Material { colour: Some([9, 9, 9]), opacity: 0.5 };
        scene.objects.push(second);
        let flat = scene.flatten();
        assert_eq!(flat.objects, vec![0..1, 1..2]);
        let c = &flat.cloud;
        assert!((c.positions[1] - Vec3::new(0.0, 2.0, 5.0)).length() < 1e-5);
        assert!((c.normals[1] - Vec3::Y).length() < 1e-5);
        assert!((c.radii[1] - 1.0).abs() < 1e-5);
        assert_eq!((c.colors[1], c.opacity[1]), ([9, 9, 9], 0.5));
        assert_eq!((c.colors[0], c.opacity[0]), ([1, 2, 3], 1.0));
        assert_ne!(scene.content_hash(), 7);
    }
}
