//! Scene files: a TOML file that lists objects, each a PLY file or a
//! generated sphere, with a transform and a material, and the scene's
//! background, environment map and camera.
//!
//! ```toml
//! background = [28, 31, 36]          # optional, 0..255
//! environment = "venice.exr"         # optional map to reflect and refract, relative to this file
//!
//! [camera]                           # optional; defaults frame every object
//! azimuth = 20                       # degrees
//! elevation = 10
//! fov = 35
//!
//! [[object]]
//! ply = "lion.ply"                   # relative to this file
//! opacity = 0.5                      # multiplies the splats' own, 0..1
//! color = [230, 200, 160]            # replaces the splats' own
//! two_sided = true                   # default: true when opacity < 1
//!
//! [[object]]
//! cloud = "tile.laz"                 # PLY, LAS, LAZ or E57 (`ply` is the same key)
//! color_by = "classification"        # or rgb, intensity, elevation, return, gps-time, an attribute's name
//! colormap = "viridis"               # magma, inferno, cividis, turbo, grey (scalars only)
//! range = [0, 255]                   # default: the 2nd to 98th percentile
//! classes = [2, 5, 6]                # only these classes are shown
//! class_opacity = { 5 = 0.3 }        # opacity per class; the object is then two-sided
//!
//! [[object]]
//! mesh = "cube.ply"                  # a PLY with faces, drawn as triangles
//!                                    # (or hybrid = "x.ply": triangles where its splats
//!                                    # would be large, splats elsewhere; crates/core/src/hybrid)
//!
//! [[object]]
//! sphere = { splats = 800, radius = 0.012, centre = [0.0, 0.03, 0.0] }
//! color = [200, 40, 40]
//! translate = [0.01, 0.0, 0.0]       # metres (the file's units)
//! rotate = [0, 30, 0]                # degrees about x, then y, then z
//! scale = 1.0
//!
//! [[object]]
//! plane = { splats = 40000, size = 0.4, centre = [0.0, -0.08, 0.0], normal = [0, 1, 0] }
//!
//! [[object]]                         # a moving object
//! ply = "lion.ply"                   # or sequence = "frames/*.ply" (a folder or a name pattern), fps = 30
//! interpolate = "smooth"             # between keyframes: "linear" (default) or "smooth"
//! deform = { kind = "wave", amount = 0.004, period = 2.0 }   # or "twist", "bend" (radians); wavelength = …
//! [[object.keyframe]]                # after the object's own transform; times in seconds, increasing
//! time = 0.0
//! translate = [0.0, 0.0, 0.0]
//! [[object.keyframe]]
//! time = 1.5
//! translate = [0.05, 0.0, 0.0]
//! rotate = [0, 90, 0]
//! scale = 1.0
//!
//! [[light]]                          # any lights replace the headlight; at most 8
//! position = [0.0, 0.3, 0.1]         # a point light, in file coordinates (or `direction`)
//! color = [255, 240, 220]            # optional, 0..255 (default white)
//! intensity = 1.0                    # optional (default 1)
//! falloff = "inverse-square"         # optional (default "none")
//!
//! [clip]                             # optional, in file coordinates; cut per pixel
//! box = { min = [-0.1, -0.1, -0.1], max = [0.1, 0.1, 0.0], hide = "outside" }  # or "inside"
//! planes = [[0.0, 0.0, 1.0, 0.02]]   # at most 6; each keeps n·x + d >= 0
//! ```
//!
//! Light positions are in file coordinates, like the objects' PLY files and
//! the generated objects' centres (what `--light` takes too). A `direction`
//! is the way a directional light's rays travel.
//!
//! TOML because people write these by hand (comments, no trailing-comma
//! traps). Unknown keys are refused, and every problem (a syntax error, a
//! missing PLY, an opacity outside 0..1) is reported on one line with the
//! file, line and column; values keep their place in the file through
//! `toml::Spanned`.

mod style_keys;
mod view_keys;

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Affine3A, EulerRot, Quat, Vec3};
use serde::Deserialize;
use toml::Spanned;

use super::animation::{Animation, Deform, DeformFrame, Interpolation, Keyframe, Sequence};
use super::primitives::{plane, sphere};
use super::{Material, Scene, SceneObject};
use crate::cloud::{self, LoadOptions};
use crate::frame::{Light, LightKind};
use crate::hash::{FNV_OFFSET, fnv1a};
use crate::hybrid::{Surface, SurfaceKind};

/// A problem with a scene file, with where it is.
#[derive(Debug, thiserror::Error)]
#[error("{path}{}: {message}", location.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default())]
pub struct SceneError {
    pub path: PathBuf,
    /// Line and column (from 1), when the problem has a place in the file.
    pub location: Option<(usize, usize)>,
    pub message: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    background: Option<Spanned<[f32; 3]>>,
    environment: Option<Spanned<String>>,
    camera: Option<view_keys::CameraEntry>,
    clip: Option<Spanned<crate::frame::ClipRegion>>,
    #[serde(rename = "object", default)]
    objects: Vec<Spanned<ObjectEntry>>,
    #[serde(rename = "light", default)]
    lights: Vec<Spanned<LightEntry>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightEntry {
    position: Option<[f32; 3]>,
    direction: Option<[f32; 3]>,
    color: Option<[f32; 3]>,
    intensity: Option<f32>,
    falloff: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlaneEntry {
    splats: usize,
    size: f32,
    centre: [f32; 3],
    normal: Option<[f32; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectEntry {
    /// A point cloud file: PLY, LAS, LAZ or E57 (`cloud` is the same key).
    #[serde(alias = "cloud")]
    ply: Option<Spanned<String>>,
    mesh: Option<Spanned<String>>,
    hybrid: Option<Spanned<String>>,
    sphere: Option<Spanned<SphereEntry>>,
    plane: Option<Spanned<PlaneEntry>>,
    name: Option<String>,
    opacity: Option<Spanned<f32>>,
    color: Option<Spanned<[f32; 3]>>,
    two_sided: Option<bool>,
    translate: Option<[f32; 3]>,
    rotate: Option<[f32; 3]>,
    scale: Option<Spanned<f32>>,
    sequence: Option<Spanned<String>>,
    fps: Option<Spanned<f32>>,
    #[serde(rename = "keyframe", default)]
    keyframes: Vec<Spanned<KeyframeEntry>>,
    interpolate: Option<Spanned<String>>,
    deform: Option<Spanned<DeformEntry>>,
    color_by: Option<Spanned<String>>,
    colormap: Option<Spanned<String>>,
    range: Option<Spanned<[f64; 2]>>,
    classes: Option<Spanned<Vec<u8>>>,
    class_opacity: Option<Spanned<std::collections::BTreeMap<String, f32>>>,
    opacity_by: Option<Spanned<String>>,
    /// Attribute filters, `["intensity=0..200", "classification=2,6"]` (all must hold).
    filter: Option<Spanned<Vec<String>>>,
    /// `first`, `last`, `only` or a return number.
    returns: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct KeyframeEntry {
    time: f64,
    translate: Option<[f32; 3]>,
    rotate: Option<[f32; 3]>,
    scale: Option<f32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DeformEntry {
    kind: String,
    amount: f32,
    period: f32,
    wavelength: Option<f32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereEntry {
    splats: usize,
    radius: f32,
    centre: [f32; 3],
}

/// The radii and sizes a generated sphere or plane may have: their splats'
/// radii, squared, must stay normal f32 numbers.
const SIZES: std::ops::RangeInclusive<f32> = 1e-9..=1e9;

/// The latest keyframe time, in seconds (about 32 years).
const MAX_KEY_TIME: f64 = 1e9;

/// Most splats a generated sphere may have.
const MAX_SPHERE_SPLATS: usize = 50_000_000;

/// Reads the scene file at `path`; PLY paths in it are relative to its folder.
/// Returns the scene and the load warnings of its objects.
pub fn read(path: &Path, options: &LoadOptions) -> Result<(Scene, Vec<String>), SceneError> {
    let text = crate::input::read_settings(path).map_err(|e| SceneError {
        path: path.to_path_buf(),
        location: None,
        message: e.to_string(),
    })?;
    let reader = Reader { path, text: &text, folder: path.parent().unwrap_or(Path::new(".")), options };
    let file: SceneFile = toml::from_str(&text).map_err(|e| reader.at(e.span(), cloud::one_line(e.message())))?;
    if file.objects.is_empty() {
        return Err(reader.at(None, "the scene has no [[object]]".into()));
    }
    let mut scene = Scene::default();
    if let Some(c) = &file.camera {
        scene.camera = Some(reader.camera(c)?);
    }
    let up = scene.camera.and_then(|c| c.up).unwrap_or_default().frame().0;
    let mut warnings = Vec::new();
    for entry in &file.objects {
        scene.objects.push(reader.object(entry, up, &mut warnings)?);
    }
    if let Some(bg) = &file.background {
        if !bg.get_ref().iter().all(|v| (0.0..=255.0).contains(v)) {
            return Err(reader.at(Some(bg.span()), "background must be three values in 0..255".into()));
        }
        scene.background = Some(Vec3::from_array(*bg.get_ref()) / 255.0);
    }
    if let Some(env) = &file.environment {
        let map_path = reader.folder.join(env.get_ref());
        let map = super::environment_map::EnvironmentMap::load(&map_path)
            .map_err(|e| reader.at(Some(env.span()), cloud::one_line(&e.to_string())))?;
        if map.cleaned > 0 {
            warnings.push(format!("{}: {} negative or non-finite values set to 0", map_path.display(), map.cleaned));
        }
        scene.environment = Some(Arc::new(map));
    }
    if file.lights.len() > crate::frame::lights::MAX_LIGHTS {
        let message = crate::frame::lights::LightError::TooMany(file.lights.len()).to_string();
        return Err(reader.at(Some(file.lights[crate::frame::lights::MAX_LIGHTS].span()), message));
    }
    for entry in &file.lights {
        scene.lights.push(reader.light(entry)?);
    }
    if let Some(clip) = &file.clip {
        scene.clip = reader.clip(clip)?;
    }
    Ok((scene, warnings))
}

/// The scene file being read: where it is, its text (for error locations),
/// the folder its paths are relative to, and how its PLY files are loaded.
struct Reader<'a> {
    path: &'a Path,
    text: &'a str,
    folder: &'a Path,
    options: &'a LoadOptions,
}

impl Reader<'_> {
    /// An error at `span` of the file (at no place when `None`).
    fn at(&self, span: Option<Range<usize>>, message: String) -> SceneError {
        SceneError { path: self.path.to_path_buf(), location: span.map(|s| line_column(self.text, s.start)), message }
    }

    /// One `[[object]]`: its splats, transform, material and animation (`up`: the scene's up axis).
    fn object(
        &self,
        entry: &Spanned<ObjectEntry>,
        up: Vec3,
        warnings: &mut Vec<String>,
    ) -> Result<SceneObject, SceneError> {
        let span = entry.span();
        let entry = entry.get_ref();
        let mut sequence = None;
        let mut surface = None;
        let sources = [entry.ply.is_some(), entry.mesh.is_some(), entry.hybrid.is_some()];
        let (name, cloud, hash) = match (&entry.ply, &entry.sphere, &entry.plane, &entry.sequence) {
            _ if sources.iter().filter(|&&s| s).count()
                + [entry.sphere.is_some(), entry.plane.is_some(), entry.sequence.is_some()]
                    .iter()
                    .filter(|&&s| s)
                    .count()
                != 1 =>
            {
                return Err(self.at(
                    Some(span),
                    "an object needs exactly one of `ply`, `mesh`, `hybrid`, `sphere`, `plane` or `sequence`".into(),
                ));
            }
            (Some(ply), ..) => self.ply(ply, warnings)?,
            (_, Some(s), ..) => self.sphere(s)?,
            (_, _, Some(p), _) => self.plane(p)?,
            (.., Some(pattern)) => {
                let (found, first) = self.sequence(pattern, entry.fps.as_ref())?;
                sequence = Some(found);
                first
            }
            _ => {
                let (file, kind) = match (&entry.mesh, &entry.hybrid) {
                    (Some(m), _) => (m, SurfaceKind::Mesh),
                    (_, Some(h)) => (h, SurfaceKind::Hybrid),
                    _ => unreachable!("one source is set (checked above)"),
                };
                let (name, cloud, hash, found) = self.mesh(file, kind, warnings)?;
                surface = Some(Arc::new(found));
                (name, cloud, hash)
            }
        };
        if let (Some(fps), None) = (&entry.fps, &entry.sequence) {
            return Err(self.at(Some(fps.span()), "`fps` belongs to an object with a `sequence`".into()));
        }
        let opacity = match &entry.opacity {
            Some(a) if !(0.0..=1.0).contains(a.get_ref()) => {
                return Err(self.at(Some(a.span()), format!("opacity must be in 0..1, not {}", a.get_ref())));
            }
            Some(a) => *a.get_ref(),
            None => 1.0,
        };
        let colour = match &entry.color {
            Some(c) if !c.get_ref().iter().all(|v| (0.0..=255.0).contains(v)) => {
                return Err(self.at(Some(c.span()), "color must be three values in 0..255".into()));
            }
            Some(c) => Some(c.get_ref().map(|v| v.round() as u8)),
            None => None,
        };
        let scale = match &entry.scale {
            Some(s) if !super::SCALES.contains(s.get_ref()) => {
                let (low, high) = (super::SCALES.start(), super::SCALES.end());
                return Err(
                    self.at(Some(s.span()), format!("scale must be within {low:e}..{high:e}, not {}", s.get_ref()))
                );
            }
            Some(s) => *s.get_ref(),
            None => 1.0,
        };
        let [rx, ry, rz] = entry.rotate.unwrap_or([0.0; 3]).map(f32::to_radians);
        let transform = Affine3A::from_scale_rotation_translation(
            Vec3::splat(scale),
            Quat::from_euler(EulerRot::ZYX, rz, ry, rx),
            Vec3::from_array(entry.translate.unwrap_or([0.0; 3])),
        );
        if !transform.is_finite() {
            return Err(self.at(Some(span), "the transform is not finite".into()));
        }
        let style = self.style(entry)?;
        let material = Material { colour, opacity, two_sided: entry.two_sided.unwrap_or(opacity < 1.0) };
        let mut animation = self.animation(entry, &cloud, up, sequence)?;
        let mut transform = transform;
        if let Some(still) = animation.take_if(|a| a.period() <= 0.0) {
            // Keys that never move (one key at 0 s) place the object once.
            transform = still.keyed(0.0) * transform;
        }
        if surface.is_some() && animation.is_some() {
            return Err(self.at(Some(span), "a mesh or hybrid object cannot move (keyframes or deform) yet".into()));
        }
        let mut object = SceneObject {
            name: entry.name.clone().unwrap_or(name),
            cloud: Arc::new(cloud),
            transform,
            material,
            content_hash: hash,
            animation,
            surface,
            styled: None,
            cut: None,
        };
        if !style.is_plain() {
            let two_sided = object.material.two_sided;
            object.restyle(&Arc::new(style)).map_err(|e| self.at(Some(span.clone()), e))?;
            if entry.two_sided.is_some() {
                object.material.two_sided = two_sided;
            }
        }
        Ok(object)
    }

    /// A `mesh` or `hybrid` object: its name, its vertices' cloud, its
    /// content hash and its triangles in leaves; load warnings go to `warnings`.
    fn mesh(
        &self,
        file: &Spanned<String>,
        kind: SurfaceKind,
        warnings: &mut Vec<String>,
    ) -> Result<(String, cloud::PointCloud, u64, Surface), SceneError> {
        let path = self.folder.join(file.get_ref());
        let (cloud, triangles, report) = cloud::load_mesh(&path, self.options)
            .map_err(|e| self.at(Some(file.span()), cloud::one_line(&e.to_string())))?;
        let hash = crate::hash::file_hash(&path)
            .map_err(|e| self.at(Some(file.span()), format!("{}: {e}", path.display())))?;
        warnings.extend(report.warnings.iter().map(|w| format!("{}: {w}", path.display())));
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let surface = Surface::build(kind, &cloud, triangles);
        Ok((format!("{name} ({})", kind.name()), cloud, crate::hash::fnv1a(hash, kind.name().as_bytes()), surface))
    }

    /// A `sequence` object's frames and its first frame (name, cloud, hash).
    fn sequence(
        &self,
        pattern: &Spanned<String>,
        fps: Option<&Spanned<f32>>,
    ) -> Result<(Sequence, (String, cloud::PointCloud, u64)), SceneError> {
        let fps_value = fps.map_or(30.0, |f| *f.get_ref());
        let at = |message: String| {
            let span = match fps {
                Some(f) if message.starts_with("fps") => f.span(),
                _ => pattern.span(),
            };
            self.at(Some(span), message)
        };
        let found = Sequence::find(&self.folder.join(pattern.get_ref()), fps_value, self.options).map_err(at)?;
        let (index, first) = found.frame(0).map_err(|e| self.at(Some(pattern.span()), e))?;
        let path = &found.frames[index];
        let hash = crate::hash::file_hash(path)
            .map_err(|e| self.at(Some(pattern.span()), format!("{}: {e}", path.display())))?;
        let name = format!("{} ({} frames)", pattern.get_ref(), found.frames.len());
        Ok((found, (name, first.as_ref().clone(), hash)))
    }

    /// The object's keyframes, deformation and sequence, checked; `None` when it has none.
    fn animation(
        &self,
        entry: &ObjectEntry,
        cloud: &cloud::PointCloud,
        up: Vec3,
        sequence: Option<Sequence>,
    ) -> Result<Option<Arc<Animation>>, SceneError> {
        for (k, key) in entry.keyframes.iter().enumerate() {
            // Read as f64, so that a time beyond f32 is reported as written, not as infinite.
            let time = key.get_ref().time;
            if time.is_finite() && time > MAX_KEY_TIME {
                let message =
                    format!("keyframe {} at {time:e} s: a keyframe's time must be within 0..{MAX_KEY_TIME:e} s", k + 1);
                return Err(self.at(Some(key.span()), message));
            }
        }
        let keyframes: Vec<Keyframe> = entry
            .keyframes
            .iter()
            .map(|k| {
                let k = k.get_ref();
                let [rx, ry, rz] = k.rotate.unwrap_or([0.0; 3]).map(f32::to_radians);
                Keyframe {
                    time: k.time as f32,
                    translate: Vec3::from_array(k.translate.unwrap_or([0.0; 3])),
                    rotate: Quat::from_euler(EulerRot::ZYX, rz, ry, rx),
                    scale: k.scale.unwrap_or(1.0),
                }
            })
            .collect();
        Animation::check_keyframes(&keyframes)
            .map_err(|(k, message)| self.at(Some(entry.keyframes[k].span()), message))?;
        let interpolate = match &entry.interpolate {
            None => Interpolation::Linear,
            Some(i) => match i.get_ref().as_str() {
                "linear" => Interpolation::Linear,
                "smooth" => Interpolation::Smooth,
                other => {
                    return Err(self
                        .at(Some(i.span()), format!("interpolate must be \"linear\" or \"smooth\", not \"{other}\"")));
                }
            },
        };
        let deform = match &entry.deform {
            None => None,
            Some(d) => {
                let e = d.get_ref();
                let kind = e.kind.parse().map_err(|m| self.at(Some(d.span()), m))?;
                let deform = Deform { kind, amount: e.amount, period: e.period, wavelength: e.wavelength };
                deform.validate().map_err(|m| self.at(Some(d.span()), m))?;
                Some((deform, DeformFrame::of(cloud, up)))
            }
        };
        if keyframes.is_empty() && deform.is_none() && sequence.is_none() {
            return Ok(None);
        }
        Ok(Some(Arc::new(Animation { keyframes, interpolate, deform, sequence })))
    }

    /// A `ply` object: its name, cloud and content hash; its load warnings go to `warnings`.
    fn ply(
        &self,
        ply: &Spanned<String>,
        warnings: &mut Vec<String>,
    ) -> Result<(String, cloud::PointCloud, u64), SceneError> {
        if crate::formats::is_url(ply.get_ref()) {
            return self.streamed(ply, warnings);
        }
        let file = self.folder.join(ply.get_ref());
        let (cloud, report) = cloud::load_with(&file, self.options)
            .map_err(|e| self.at(Some(ply.span()), cloud::one_line(&e.to_string())))?;
        let hash =
            crate::hash::file_hash(&file).map_err(|e| self.at(Some(ply.span()), format!("{}: {e}", file.display())))?;
        warnings.extend(report.warnings.iter().map(|w| format!("{}: {w}", file.display())));
        let name = file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        Ok((name, cloud, hash))
    }

    /// An object given as an http(s) URL, streamed as the command line
    /// streams one: a COPC file, every node of it (a scene's objects are
    /// loaded before any view is chosen), refused in one line when its points
    /// would not fit the node cache.
    fn streamed(
        &self,
        url: &Spanned<String>,
        warnings: &mut Vec<String>,
    ) -> Result<(String, cloud::PointCloud, u64), SceneError> {
        use crate::copc::{CopcStream, StreamBudget, StreamOptions, subset::StreamSubset};
        use crate::frame::subset::{Choosing, Subset};
        let at = |e: crate::copc::CopcError| self.at(Some(url.span()), e.to_string());
        let options = StreamOptions { progress: self.options.progress, ..Default::default() };
        let stream = CopcStream::open(url.get_ref(), options).map_err(at)?;
        let camera = crate::frame::Camera::default_for(&stream.bounds_cloud(), 1.0);
        let mut subset = StreamSubset::new(stream, StreamBudget::All, self.options.clone());
        let choice = subset.choose(&camera, (1, 1), Choosing::default()).map_err(at)?;
        let name = subset.stream.name();
        warnings.extend(subset.last.warnings.iter().map(|w| format!("{name}: {w}")));
        Ok((subset.stream.file_name().to_string(), choice.cloud.unwrap_or_default(), choice.key))
    }

    /// A `sphere` object: its name, generated cloud and a hash of its parameters.
    fn sphere(&self, s: &Spanned<SphereEntry>) -> Result<(String, cloud::PointCloud, u64), SceneError> {
        let spec = s.get_ref();
        if spec.splats == 0 || spec.splats > MAX_SPHERE_SPLATS || !SIZES.contains(&spec.radius) {
            let (low, high) = (SIZES.start(), SIZES.end());
            let message =
                format!("a sphere needs 1..={MAX_SPHERE_SPLATS} splats and a radius within {low:e}..{high:e}");
            return Err(self.at(Some(s.span()), message));
        }
        if !spec.centre.iter().all(|c| c.is_finite()) {
            return Err(self.at(Some(s.span()), "the sphere's centre is not finite".into()));
        }
        let centre = Vec3::from_array(spec.centre);
        let hash = [spec.splats as f32, spec.radius, centre.x, centre.y, centre.z]
            .iter()
            .fold(fnv1a(FNV_OFFSET, b"sphere"), |h, v| fnv1a(h, &v.to_le_bytes()));
        Ok((format!("sphere of {} splats", spec.splats), sphere(spec.splats, spec.radius, centre), hash))
    }

    /// A `plane` object: its name, generated cloud and a hash of its parameters.
    fn plane(&self, p: &Spanned<PlaneEntry>) -> Result<(String, cloud::PointCloud, u64), SceneError> {
        let spec = p.get_ref();
        if spec.splats == 0 || spec.splats > MAX_SPHERE_SPLATS || !SIZES.contains(&spec.size) {
            let (low, high) = (SIZES.start(), SIZES.end());
            let message = format!("a plane needs 1..={MAX_SPHERE_SPLATS} splats and a size within {low:e}..{high:e}");
            return Err(self.at(Some(p.span()), message));
        }
        let normal = Vec3::from_array(spec.normal.unwrap_or([0.0, 1.0, 0.0]));
        if !spec.centre.iter().all(|c| c.is_finite()) || !normal.is_finite() || normal.length_squared() < 1e-12 {
            return Err(
                self.at(Some(p.span()), "the plane's centre and normal must be finite, the normal not zero".into())
            );
        }
        let centre = Vec3::from_array(spec.centre);
        let hash = [spec.splats as f32, spec.size, centre.x, centre.y, centre.z, normal.x, normal.y, normal.z]
            .iter()
            .fold(fnv1a(FNV_OFFSET, b"plane"), |h, v| fnv1a(h, &v.to_le_bytes()));
        Ok((format!("plane of {} splats", spec.splats), plane(spec.splats, spec.size, centre, normal), hash))
    }

    /// One `[[light]]`, checked.
    fn light(&self, entry: &Spanned<LightEntry>) -> Result<Light, SceneError> {
        let span = Some(entry.span());
        let e = entry.get_ref();
        let kind = match (e.position, e.direction) {
            (Some(p), None) => LightKind::Point(Vec3::from_array(p)),
            (None, Some(d)) => LightKind::Directional(Vec3::from_array(d).normalize_or_zero()),
            _ => return Err(self.at(span, "a light needs exactly one of `position` or `direction`".into())),
        };
        let inverse_square = match e.falloff.as_deref() {
            None | Some("none") => false,
            Some("inverse-square") => true,
            Some(other) => {
                return Err(self.at(span, format!("falloff must be \"none\" or \"inverse-square\", not \"{other}\"")));
            }
        };
        let colour = e.color.map_or(Vec3::ONE, |c| Vec3::from_array(c) / 255.0);
        let light = Light { kind, colour, intensity: e.intensity.unwrap_or(1.0), inverse_square };
        light.validate().map_err(|err| self.at(span, err.to_string()))?;
        Ok(light)
    }
}

/// Line and column (from 1) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}
