//! Several clouds as one scene: layers. `render A B ...` (and `pick`,
//! `measure`) open each file as an object of its own, which keeps its own
//! f64 origin: the scene's flattening ([`super::Scene::flatten`]) places
//! every object in the first one's frame in f64, so tiles far from the
//! origin meet exactly. A `.vpc` ([`super::vpc`]) is a layer of many files,
//! of which only those whose box the view reaches are opened
//! ([`reaches`]). Layers in different CRSs are refused, in one line that
//! names both.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};

use super::layer_seams::Layer;
use super::{OpenError, Scene, vpc};
use crate::cloud::{CloudError, LoadOptions, PointCloud};
use crate::frame::Camera;

/// One file of the layers, and its box (file coordinates) when a `.vpc` gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerFile {
    pub path: PathBuf,
    pub bounds: Option<(DVec3, DVec3)>,
}

/// The files `paths` name: each file itself, and each `.vpc`'s files.
pub fn layer_files(paths: &[PathBuf]) -> Result<Vec<LayerFile>, OpenError> {
    let mut files = Vec::new();
    for path in paths {
        if vpc::is_vpc(path) {
            let listed = vpc::read(path).map_err(|reason| CloudError::content(path, reason))?;
            files.extend(listed.into_iter().map(|f| LayerFile { path: f.path, bounds: f.bounds }));
        } else {
            files.push(LayerFile { path: path.clone(), bounds: None });
        }
    }
    Ok(files)
}

/// A scene of the corners of the boxes `files` give (`None` when none
/// does): what a camera is framed on before any file is opened.
pub fn bounds_scene(files: &[LayerFile]) -> Option<Scene> {
    let boxes: Vec<(DVec3, DVec3)> = files.iter().filter_map(|f| f.bounds).map(finite_heights).collect();
    let origin = boxes.iter().map(|(lo, hi)| (*lo + *hi) * 0.5).next()?;
    let corners: Vec<Vec3> = boxes.iter().flat_map(|b| corners(*b)).map(|c| (c - origin).as_vec3()).collect();
    let cloud = PointCloud { origin: origin.to_array(), z_up: true, ..PointCloud::facing_z(corners, 0.0, [0; 3]) };
    Some(Scene::single("bounds", cloud, 0))
}

/// A 2D box's heights, which span everything, as a thin slab at 0.
fn finite_heights((lo, hi): (DVec3, DVec3)) -> (DVec3, DVec3) {
    let z = |v: f64| if v.is_finite() { v } else { 0.0 };
    (DVec3::new(lo.x, lo.y, z(lo.z)), DVec3::new(hi.x, hi.y, z(hi.z)))
}

fn corners((lo, hi): (DVec3, DVec3)) -> impl Iterator<Item = DVec3> {
    (0..8).map(move |i| {
        let pick = |bit: usize, a: f64, b: f64| if i & bit != 0 { b } else { a };
        DVec3::new(pick(1, lo.x, hi.x), pick(2, lo.y, hi.y), pick(4, lo.z, hi.z))
    })
}

/// Whether `camera`, in a frame placed at `(origin, unit)` (file = frame ·
/// unit + origin), sees any of the box `bounds` (file coordinates) in an
/// image of `aspect`: its corners' clip-space box overlaps the view volume.
pub fn reaches(camera: &Camera, aspect: f32, (origin, unit): (DVec3, f64), bounds: (DVec3, DVec3)) -> bool {
    let view_projection = camera.projection(aspect) * camera.view_matrix();
    let (mut lo, mut hi) = (glam::Vec3::splat(f32::INFINITY), glam::Vec3::splat(f32::NEG_INFINITY));
    for corner in corners(finite_heights(bounds)) {
        let p = view_projection * ((corner - origin) / unit).as_vec3().extend(1.0);
        if p.w <= 1e-6 {
            // A corner behind the eye: the box may cross the view; keep it.
            return true;
        }
        let ndc = p.truncate() / p.w;
        (lo, hi) = (lo.min(ndc), hi.max(ndc));
    }
    lo.x <= 1.0 && hi.x >= -1.0 && lo.y <= 1.0 && hi.y >= -1.0 && hi.z >= 0.0 && lo.z <= 1.0
}

/// How a file's CRS is told apart from another's: its EPSG code, else its
/// WKT (without spaces); `None` when it declares none.
fn crs_key(epsg: Option<u32>, crs: Option<&str>) -> Option<String> {
    match (epsg, crs) {
        (Some(code), _) => Some(format!("EPSG:{code}")),
        (None, Some(text)) => Some(text.split_whitespace().collect()),
        (None, None) => None,
    }
}

/// A CRS's short name for a message: `EPSG:n`, else the WKT's first quoted name.
fn crs_name(key: &str) -> String {
    match key.split('"').nth(1) {
        Some(name) if !key.starts_with("EPSG:") => name.to_string(),
        _ => key.chars().take(60).collect(),
    }
}

/// The one CRS layers share: the first file's that declares one, which
/// every later file that declares one must have too.
#[derive(Debug, Default)]
pub struct SharedCrs {
    first: Option<(String, String)>,
}

impl SharedCrs {
    /// Admits `file` (a path or URL as shown) of CRS `epsg`/`crs`, or says
    /// in one line, naming both files and both CRSs, why it cannot join.
    pub fn admit(&mut self, file: &str, epsg: Option<u32>, crs: Option<&str>) -> Result<(), String> {
        let Some(key) = crs_key(epsg, crs) else { return Ok(()) };
        match &self.first {
            Some((other, known)) if *known != key => Err(format!(
                "its CRS is {} but {other}'s is {}: layers must share one CRS (reproject one first)",
                crs_name(&key),
                crs_name(known)
            )),
            Some(_) => Ok(()),
            None => {
                self.first = Some((file.to_string(), key));
                Ok(())
            }
        }
    }
}

/// Opens `files` as one scene, each file an object (a scene file's objects
/// each), in order; refuses files in different CRSs; mends the seams where
/// survey layers meet ([`super::layer_seams`]). Returns the scene and the
/// load warnings, each naming its file.
pub fn open_layers(files: &[&Path], options: &LoadOptions) -> Result<(Scene, Vec<String>), OpenError> {
    open_layers_sharing(files, options, &mut SharedCrs::default())
}

/// [`open_layers`], the files' CRS checked against `crs` (which other layers may have set).
pub fn open_layers_sharing(
    files: &[&Path],
    options: &LoadOptions,
    crs: &mut SharedCrs,
) -> Result<(Scene, Vec<String>), OpenError> {
    let mut clouds: Vec<(&Path, Layer)> = Vec::new();
    let mut scenes: Vec<(usize, Scene)> = Vec::new();
    let mut warnings = Vec::new();
    for &path in files {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
            let (layer, more) = super::file::read(path, options)?;
            warnings.extend(more);
            scenes.push((clouds.len(), layer));
            continue;
        }
        let (cloud, report) = crate::cloud::load_with(path, options)?;
        warnings.extend(report.warnings.iter().map(|w| format!("{}: {w}", path.display())));
        let shown = path.display().to_string();
        crs.admit(&shown, cloud.units.epsg, report.crs.as_deref()).map_err(|why| CloudError::content(path, why))?;
        clouds.push((path, Layer { cloud, normals: report.normals, radii: report.radii }));
    }
    if clouds.len() > 1 {
        let mut layers: Vec<Layer> = clouds.drain(..).map(|(_, l)| l).collect();
        let estimate = crate::cloud::estimate::EstimateOptions { orient_up: true, ..options.estimate.clone() };
        let mended = super::layer_seams::mend(&mut layers, &estimate);
        log::info!("{mended} points where the layers meet estimated again with their neighbours across");
        clouds = files.iter().copied().filter(|p| !is_scene_file(p)).zip(layers).collect();
    }
    // In the order given: each scene file's objects where it stood among the clouds.
    let mut scene = Scene::default();
    let mut scenes = scenes.into_iter().peekable();
    for (k, (path, layer)) in clouds.into_iter().enumerate() {
        while let Some((_, s)) = scenes.next_if(|(at, _)| *at == k) {
            merge(&mut scene, s);
        }
        let hash = crate::hash::file_hash(path).map_err(|e| CloudError::io(path, e))?;
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "layer".into());
        merge(&mut scene, Scene::single(name, layer.cloud, hash).coloured_by_default());
    }
    for (_, s) in scenes {
        merge(&mut scene, s);
    }
    if scene.objects.is_empty() {
        return Err(CloudError::content(Path::new("."), "no file to open").into());
    }
    Ok((scene, warnings))
}

/// Adds `other`'s objects to `scene`; the first scene added gives the settings (a scene file's camera, lights, clip).
fn merge(scene: &mut Scene, other: Scene) {
    if scene.objects.is_empty() {
        *scene = other;
    } else {
        scene.objects.extend(other.objects);
    }
}

fn is_scene_file(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

/// `camera`, made for a frame placed at `from` (file = frame · unit +
/// origin), for a frame placed at `to`: the same view of the same place.
pub fn camera_in_frame(camera: &Camera, from: (DVec3, f64), to: (DVec3, f64)) -> Camera {
    let ratio = (from.1 / to.1) as f32;
    let target_in_file = camera.target.as_dvec3() * from.1 + from.0;
    Camera {
        target: ((target_in_file - to.0) / to.1).as_vec3(),
        distance: camera.distance * ratio,
        scene_radius: camera.scene_radius * ratio,
        ..*camera
    }
}
