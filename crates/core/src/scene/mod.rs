//! A scene: one or more objects, each a point cloud with a transform and a
//! material, rendered together, with an optional background and camera.
//! Opening one PLY file gives a scene of one object; a scene file ([`file`],
//! TOML) lists several, PLY files or generated spheres. Every renderer (the
//! GPU modes, the CPU reference, `bench`, the viewer) takes a scene.
//!
//! Renderers see a scene through [`Scene::flatten`]: all objects' splats in
//! one frame (the first object's re-centred file coordinates; every other
//! object is placed by its file coordinates, then transformed), materials
//! applied, in object order, with the range and material of each object. A
//! scene of one object with the identity transform and the default material
//! flattens to its cloud as it is, without a copy.

pub mod animation;
pub mod cut;
pub mod environment_map;
pub mod file;
pub(crate) mod layer_seams;
pub mod layers;
mod material;
pub mod primitives;
pub mod vpc;

use std::borrow::Cow;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use glam::{Affine3A, Vec3};

use crate::cloud::{self, CloudError, LoadOptions, LoadReport, PointCloud};
use crate::hash::{FNV_OFFSET, fnv1a};
pub use file::SceneError;

/// The scale factors an object or a keyframe may have: beyond them a model's
/// splats leave what f32 arithmetic can draw (a blank or garbled image).
pub const SCALES: std::ops::RangeInclusive<f32> = 1e-6..=1e6;
pub use material::{Look, Material, Materials};

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
    /// How the object moves, if it does (see [`Scene::at_time`]).
    pub animation: Option<Arc<animation::Animation>>,
    /// A mesh's triangles over the cloud's splats (`mesh =` and `hybrid =` objects).
    pub surface: Option<Arc<crate::hybrid::Surface>>,
    /// The colour and opacity by attribute `cloud` shows, and the object before it.
    pub styled: Option<Styled>,
    /// The box the object is cut to, and the object before it ([`cut`]).
    pub cut: Option<Arc<cut::Cut>>,
}

/// A style applied to an object, and what the object was before it (so a
/// viewer can restyle it from the file's own values).
#[derive(Debug, Clone)]
pub struct Styled {
    pub style: Arc<crate::style::Style>,
    pub source: Arc<PointCloud>,
    pub source_hash: u64,
    /// What applying the style did: the range its colours span, the splats it hid.
    pub applied: crate::style::Applied,
}

impl SceneObject {
    /// Shows this object's cloud (as loaded) in `style`; an error names what its file lacks.
    pub fn restyle(&mut self, style: &Arc<crate::style::Style>) -> Result<(), String> {
        let (source, source_hash) = match self.styled.take() {
            Some(styled) => (styled.source, styled.source_hash),
            None => (self.cloud.clone(), self.content_hash),
        };
        let (cloud, applied) = style.apply(&source).map_err(|e| format!("{}: {e}", self.name))?;
        if let Some((lo, hi)) = applied.range {
            log::info!("{}: the colormap spans {lo} .. {hi}", self.name);
        }
        if applied.opacity_unset > 0 {
            log::warn!(
                "{}: {} splats have no --opacity-by value (NaN) and are drawn fully transparent",
                self.name,
                applied.opacity_unset
            );
        }
        self.cloud = Arc::new(cloud);
        self.content_hash = fnv1a(source_hash, style.key().as_bytes());
        self.material.two_sided |= applied.translucent;
        self.styled = Some(Styled { style: style.clone(), source, source_hash, applied });
        Ok(())
    }

    fn is_plain(&self) -> bool {
        self.transform == Affine3A::IDENTITY && self.material == Material::default()
    }
}

/// An animated scene at one time.
#[derive(Debug, Clone)]
pub struct SceneAtTime {
    /// The objects as they are then, with no animation left.
    pub scene: Scene,
    /// The time, looped into the animation's period.
    pub time: f64,
    /// The sequence frame each object shows, where it has a sequence.
    pub frames: Vec<Option<usize>>,
}

/// Objects rendered together.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    pub objects: Vec<SceneObject>,
    /// Background colour (0..1), when the scene sets one.
    pub background: Option<Vec3>,
    /// How the scene file asks to be seen (`[camera]`); what it leaves out, the defaults frame.
    pub camera: Option<crate::frame::CameraRequest>,
    /// The environment map transparent surfaces reflect and refract (§5.2.3).
    pub environment: Option<Arc<environment_map::EnvironmentMap>>,
    /// The scene file's `[[light]]`s, in file coordinates (see [`Scene::light_in_frame`]).
    pub lights: Vec<crate::frame::Light>,
    /// The scene file's `[clip]`, in file coordinates (see [`Scene::clip_in_frame`]).
    pub clip: crate::frame::ClipRegion,
    /// The groups its one object's splats came with: a streamed file's
    /// nodes, each labelled once when it arrived (the frames draw them
    /// instead of grouping the selection again).
    pub node_grouping: Option<crate::frame::subset::NodeGrouping>,
    /// Which of its one object's splats each node holds: a streamed
    /// file's nodes (the GPU keeps each node's splats where they are while it is drawn).
    pub node_spans: Option<Arc<crate::frame::subset::NodeSpans>>,
}

/// A scene's splats in one frame, materials applied.
#[derive(Debug, Clone)]
pub struct FlatScene<'a> {
    pub cloud: Cow<'a, PointCloud>,
    /// The splats of each object, in `cloud`, and its material.
    pub objects: Vec<(Range<u32>, Material)>,
}

/// Opening a scene: a PLY file or a scene file, by extension.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    #[error(transparent)]
    Cloud(#[from] CloudError),
    #[error(transparent)]
    Scene(#[from] SceneError),
}

/// Opens `path`: a scene file (`.toml`), a virtual point cloud (`.vpc`, its
/// files as layers) or a cloud file (anything else, as a scene of one object). Returns the scene and the load warnings of its objects.
pub fn open(path: &Path, options: &LoadOptions) -> Result<(Scene, Vec<String>), OpenError> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
        return Ok(file::read(path, options)?);
    }
    if vpc::is_vpc(path) {
        // Every file of it, as layers (`render` opens only those its view reaches: commands/shared.rs).
        let files = layers::layer_files(&[path.to_path_buf()])?;
        let paths: Vec<&Path> = files.iter().map(|f| f.path.as_path()).collect();
        return layers::open_layers(&paths, options);
    }
    let (scene, report) = Scene::load(path, options)?;
    let warnings = report.warnings.iter().map(|w| format!("{}: {w}", path.display())).collect();
    Ok((scene, warnings))
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
            animation: None,
            surface: None,
            styled: None,
            cut: None,
        };
        Scene { objects: vec![object], ..Default::default() }
    }

    /// Loads the PLY file at `path` as a scene of one object.
    pub fn load(path: &Path, options: &LoadOptions) -> Result<(Scene, LoadReport), CloudError> {
        let (cloud, report) = cloud::load_with(path, options)?;
        let hash = crate::hash::file_hash(path).map_err(|e| CloudError::io(path, e))?;
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "model".into());
        Ok((Scene::single(name, cloud, hash).coloured_by_default(), report))
    }

    /// The scene with the groups its splats came with (see [`Scene::node_grouping`]).
    pub fn with_node_grouping(mut self, grouping: Option<crate::frame::subset::NodeGrouping>) -> Scene {
        self.node_grouping = grouping;
        self
    }

    /// The scene with the nodes its splats came in (see [`Scene::node_spans`]).
    pub fn with_node_spans(mut self, spans: Option<Arc<crate::frame::subset::NodeSpans>>) -> Scene {
        self.node_spans = spans;
        self
    }

    /// This scene with every survey object that has no colours coloured
    /// as [`crate::style::Style::default_for`] says (by class, else by
    /// elevation), and a line saying so.
    pub fn coloured_by_default(mut self) -> Scene {
        for o in &mut self.objects {
            let Some(style) = crate::style::Style::default_for(&o.cloud) else { continue };
            let shown = style.color_by.as_ref().map(|c| c.text()).unwrap_or_default();
            if o.restyle(&Arc::new(style)).is_ok() {
                log::info!("{}: the file has no colours; coloured by {shown} (--color-by to choose)", o.name);
            }
        }
        self
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

    /// Identifies the scene's geometry (files and transforms) for caches of
    /// what materials do not change (groupings) and for sidecars: for one
    /// object in place it is its file's hash.
    pub fn geometry_hash(&self) -> u64 {
        if let [one] = self.objects.as_slice() {
            if one.transform == Affine3A::IDENTITY {
                return one.content_hash;
            }
        }
        self.objects.iter().fold(FNV_OFFSET, |h, o| {
            let h = fnv1a(h, &o.content_hash.to_le_bytes());
            fnv1a(h, bytemuck_floats(&o.transform.to_cols_array()).as_slice())
        })
    }

    /// Identifies everything that decides the scene's splats (files,
    /// transforms, materials), for caches of images.
    pub fn content_hash(&self) -> u64 {
        let geometry = self.geometry_hash();
        if self.objects.iter().all(|o| o.material == Material::default()) {
            return geometry;
        }
        self.objects.iter().fold(geometry, |h, o| fnv1a(h, format!("{:?}", o.material).as_bytes()))
    }

    /// A light given in file coordinates (those of the PLY files and of the
    /// generated objects' centres), moved into the flattened frame.
    pub fn light_in_frame(&self, light: &crate::frame::Light) -> crate::frame::Light {
        let Some(first) = self.objects.first() else { return *light };
        match light.kind {
            crate::frame::LightKind::Point(p) => {
                let origin = glam::DVec3::from_array(first.cloud.origin);
                let at = ((p.as_dvec3() - origin) / first.cloud.unit()).as_vec3();
                crate::frame::Light { kind: crate::frame::LightKind::Point(at), ..*light }
            }
            crate::frame::LightKind::Directional(_) => *light,
        }
    }

    /// A clip region given in file coordinates (like lights), in the flattened frame.
    pub fn clip_in_frame(&self, region: &crate::frame::ClipRegion) -> crate::frame::Clip {
        let (origin, unit) = self.frame_placement();
        region.in_frame(origin, unit)
    }

    /// Where the flattened frame lies in file coordinates: file = frame · unit + origin
    /// (the first object's origin and unit).
    pub fn frame_placement(&self) -> (glam::DVec3, f64) {
        self.objects
            .first()
            .map_or((glam::DVec3::ZERO, 1.0), |o| (glam::DVec3::from_array(o.cloud.origin), o.cloud.unit()))
    }

    /// All splats in one frame with the materials applied (see the module doc).
    pub fn flatten(&self) -> FlatScene<'_> {
        if let [one] = self.objects.as_slice() {
            if one.is_plain() {
                let all = 0..one.cloud.len() as u32;
                return FlatScene { cloud: Cow::Borrowed(one.cloud.as_ref()), objects: vec![(all, one.material)] };
            }
        }
        let mut out = PointCloud::default();
        let mut objects = Vec::with_capacity(self.objects.len());
        let (frame_origin, frame_unit) = self.frame_placement();
        let exact = self.objects.iter().any(|o| !o.cloud.residuals.is_empty());
        for o in &self.objects {
            let start = out.len() as u32;
            // From the object's stored coordinates to the scene frame, in f64: the file
            // coordinates are stored · unit + origin.
            let unit = o.cloud.unit();
            let shift = (glam::DVec3::from_array(o.cloud.origin) - frame_origin) / frame_unit;
            let to_frame = |p: Vec3| (p.as_dvec3() * (unit / frame_unit) + shift).as_vec3();
            let scale = o.transform.matrix3.determinant().abs().cbrt() * (unit / frame_unit) as f32;
            let normal_matrix = o.transform.matrix3.inverse().transpose();
            if exact {
                // The file positions in the scene frame, in f64, and what f32 loses of them.
                let transform = glam::DAffine3::from_mat4(glam::Mat4::from(o.transform).as_dmat4());
                for i in 0..o.cloud.len() {
                    let at = transform.transform_point3(o.cloud.frame_position(i) * (unit / frame_unit) + shift);
                    out.positions.push(at.as_vec3());
                    out.residuals.push((at - at.as_vec3().as_dvec3()).as_vec3());
                }
            } else {
                out.positions.extend(o.cloud.positions.iter().map(|p| o.transform.transform_point3(to_frame(*p))));
            }
            out.normals.extend(
                o.cloud.normals.iter().map(|n| Vec3::from(normal_matrix * glam::Vec3A::from(*n)).normalize_or_zero()),
            );
            out.radii.extend(o.cloud.radii.iter().map(|r| r * scale));
            out.colours.extend(o.cloud.colours.iter().map(|c| o.material.colour(*c)));
            out.opacity.extend(o.cloud.opacity.iter().map(|a| o.material.opacity(*a)));
            objects.push((start..out.len() as u32, o.material));
        }
        if self.objects.iter().any(|o| o.material.two_sided) {
            out.two_sided = objects.iter().flat_map(|(r, m)| std::iter::repeat_n(m.two_sided, r.len())).collect();
        }
        if let Some(first) = self.objects.first() {
            out.origin = first.cloud.origin;
            out.scale_exponent = first.cloud.scale_exponent;
            out.z_up = first.cloud.z_up;
            out.units = first.cloud.units.clone();
            // Only a scene of one object keeps the scanner's view.
            if self.objects.len() == 1 && first.transform == Affine3A::IDENTITY {
                out.scanner_position = first.cloud.scanner_position;
            }
        }
        FlatScene { cloud: Cow::Owned(out), objects }
    }

    /// The objects' mesh triangles in the flattened frame of `flat` (this scene's [`Scene::flatten`]).
    pub fn surfaces(&self, flat: &FlatScene<'_>) -> crate::hybrid::select::SceneSurfaces {
        let surfaces = self
            .objects
            .iter()
            .zip(&flat.objects)
            .filter_map(|(o, (range, _))| o.surface.as_ref().map(|s| (Arc::clone(s), range.start)));
        crate::hybrid::select::SceneSurfaces::new(&flat.cloud, surfaces)
    }

    /// Whether some object has triangles (`mesh` or `hybrid`).
    pub fn has_surfaces(&self) -> bool {
        self.objects.iter().any(|o| o.surface.is_some())
    }

    /// What a still frame of this scene drawn whole from its splats in world
    /// space, `cloud`, is decided over ([`crate::frame::resolve`]; the front
    /// ends that ray cast it, `pick` and `measure`, and the viewer's model).
    pub fn facts(&self, cloud: &crate::cloud::PointCloud) -> crate::frame::SceneFacts {
        crate::frame::SceneFacts {
            splats: cloud.len(),
            transparent: cloud.has_transparency(),
            surfaces: self.has_surfaces(),
            moving: self.is_animated(),
            streamed: false,
            mean_radius: cloud.mean_radius(),
            shadows_at_hand: true,
        }
    }

    /// Sets every object's opacity (and makes transparent ones two-sided).
    pub fn set_opacity(&mut self, opacity: f32) {
        for o in &mut self.objects {
            o.material.opacity = opacity;
            o.material.two_sided = opacity < 1.0;
        }
    }

    /// Colours every object and sets its opacity by its attributes (objects
    /// that become translucent are drawn two-sided); an error names the object
    /// whose file lacks an attribute the style reads.
    pub fn apply_style(&mut self, style: &crate::style::Style) -> Result<(), String> {
        if style.is_plain() {
            // The file's own colours (`--color-by rgb`): no style, not even the default one.
            *self = self.unstyled();
            return Ok(());
        }
        let style = Arc::new(style.clone());
        for o in &mut self.objects {
            o.restyle(&style)?;
        }
        Ok(())
    }

    /// The range of values the first object's colours span, when its style
    /// colours by a scalar: what the legend shows (the first object's, as
    /// the colour panel's summary is), taken where the colours were made,
    /// after hidden classes left.
    pub fn colour_range(&self) -> Option<(f64, f64)> {
        self.objects.first()?.styled.as_ref()?.applied.range
    }

    /// The first object's style with its colormap's range fixed where the
    /// style left it to the percentiles: what a streamed file's later
    /// selections are styled with, so that their colours do not shift as
    /// the nodes drawn change. `None` when the scene is not styled.
    pub fn pinned_style(&self) -> Option<crate::style::Style> {
        let styled = self.objects.first()?.styled.as_ref()?;
        Some(crate::style::Style { range: styled.style.range.or(styled.applied.range), ..(*styled.style).clone() })
    }

    /// This scene as loaded: every object's cloud before its style.
    pub fn unstyled(&self) -> Scene {
        let mut scene = self.clone();
        for o in &mut scene.objects {
            if let Some(styled) = o.styled.take() {
                o.cloud = styled.source;
                o.content_hash = styled.source_hash;
            }
        }
        scene
    }

    /// Sets every object's colour.
    pub fn set_colour(&mut self, colour: [u8; 3]) {
        for o in &mut self.objects {
            o.material.colour = Some(colour);
        }
    }

    /// Whether some object moves.
    pub fn is_animated(&self) -> bool {
        self.objects.iter().any(|o| o.animation.as_ref().is_some_and(|a| a.period() > 0.0))
    }

    /// Seconds after which the longest animation repeats (0 for a still scene).
    pub fn animation_period(&self) -> f64 {
        self.objects.iter().filter_map(|o| o.animation.as_ref()).map(|a| a.period()).fold(0.0, f64::max)
    }

    /// The scene at time `t` seconds (each animation loops over its own
    /// period): every object's keyed transform after its own, its sequence
    /// frame, deformed. A still object is shared, not copied. Errors are one
    /// line naming the object (a sequence none of whose frames can be read,
    /// or a time that is not a number ≥ 0).
    pub fn at_time(&self, t: f64) -> Result<SceneAtTime, String> {
        if !(t.is_finite() && t >= 0.0) {
            return Err(format!("the time must be a number of seconds ≥ 0, not {t}"));
        }
        let mut scene = Scene { objects: Vec::with_capacity(self.objects.len()), ..self.clone() };
        let mut frames = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            let Some(animation) = &o.animation else {
                scene.objects.push(o.clone());
                frames.push(None);
                continue;
            };
            let (cloud, frame) = animation.cloud_at(&o.cloud, t).map_err(|e| format!("{}: {e}", o.name))?;
            let transform = animation.keyed(t) * o.transform;
            // The time and frame enter the hash: caches keyed by geometry tell frames apart.
            let what = [t.to_bits(), frame.unwrap_or(usize::MAX) as u64];
            let content_hash = what.iter().fold(o.content_hash, |h, v| fnv1a(h, &v.to_le_bytes()));
            scene.objects.push(SceneObject { cloud, transform, content_hash, animation: None, ..o.clone() });
            frames.push(frame);
        }
        let period = self.animation_period();
        Ok(SceneAtTime { scene, time: if period > 0.0 { t.rem_euclid(period) } else { t }, frames })
    }

    /// Whether some splat is drawn less than opaque.
    pub fn has_transparency(&self) -> bool {
        self.objects
            .iter()
            .any(|o| o.material.opacity < 1.0 || (o.material.opacity > 0.0 && o.cloud.has_transparency()))
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
        hash = fnv1a(hash, &cloud.colours.concat());
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
            colours: vec![colour],
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
        second.material = Material { colour: Some([9, 9, 9]), ..Material::with_opacity(0.5) };
        scene.objects.push(second);
        let flat = scene.flatten();
        let ranges: Vec<_> = flat.objects.iter().map(|(r, _)| r.clone()).collect();
        assert_eq!(ranges, vec![0..1, 1..2]);
        assert_eq!(flat.cloud.two_sided, vec![false, true], "the transparent object is two-sided");
        let c = &flat.cloud;
        assert!((c.positions[1] - Vec3::new(0.0, 2.0, 5.0)).length() < 1e-5);
        assert!((c.normals[1] - Vec3::Y).length() < 1e-5);
        assert!((c.radii[1] - 1.0).abs() < 1e-5);
        assert_eq!((c.colours[1], c.opacity[1]), ([9, 9, 9], 0.5));
        assert_eq!((c.colours[0], c.opacity[0]), ([1, 2, 3], 1.0));
        assert_ne!(scene.content_hash(), 7);
    }
}

#[cfg(test)]
mod placement_tests {
    use super::*;

    #[test]
    fn objects_keep_their_file_coordinates_relative_to_the_first() {
        let at = |origin: [f64; 3], scale_exponent: i32| PointCloud {
            positions: vec![Vec3::ZERO],
            normals: vec![Vec3::Z],
            radii: vec![1.0],
            colours: vec![[0; 3]],
            opacity: vec![1.0],
            origin,
            scale_exponent,
            ..Default::default()
        };
        let mut scene = Scene::single("a", at([1000.0, 0.0, 0.0], 0), 1);
        scene.objects.push(SceneObject {
            content_hash: 2,
            ..Scene::single("b", at([1003.0, 4.0, 0.0], 0), 2).objects.remove(0)
        });
        scene.objects.push(SceneObject {
            content_hash: 3,
            ..Scene::single("c", at([1000.0, 0.0, 20.0], 1), 3).objects.remove(0)
        });
        let flat = scene.flatten();
        assert_eq!(flat.cloud.positions[1], Vec3::new(3.0, 4.0, 0.0));
        assert_eq!(flat.cloud.positions[2], Vec3::new(0.0, 0.0, 20.0));
        assert_eq!(flat.cloud.radii[2], 10.0, "a radius in units of 10 becomes 10 units");
    }
}
