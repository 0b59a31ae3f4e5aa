//! Several files as layers (`render A B ...`, `pick`, `measure`, a
//! `.vpc`): the files a `.vpc`'s boxes place in the view are opened, those
//! held whole as objects of one scene ([`layers::open_layers`]), the
//! streamed ones (COPC files, URLs) node by node under one shared point
//! budget ([`LayeredStreams`]); and a `.vpc` of files, for the commands
//! that open one path.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use pointblend::cloud::LoadOptions;
use pointblend::copc::is_streamed;
use pointblend::copc::layered::LayeredStreams;
use pointblend::frame::Camera;
use pointblend::lod::Choosing;
use pointblend::render::RenderMode;
use pointblend::scene::Scene;
use pointblend::scene::layers::{self, LayerFile, SharedCrs};

use super::shared::{CameraArgs, ViewArgs};

/// The layers opened: their scene, the camera they were chosen for (in the
/// scene's frame; `None`: the scene's own default view), and whether some
/// were chosen node by node (under the point budget already).
pub struct OpenedLayers {
    pub scene: Scene,
    pub camera: Option<Camera>,
    pub by_nodes: bool,
}

/// Whether `file` and `more` open as layers: several files, or a `.vpc`.
pub fn is_layered(file: &Path, more: &[PathBuf]) -> bool {
    !more.is_empty() || pointblend::scene::vpc::is_vpc(file)
}

/// Opens `file` and `more` as layers, each file an object with its own f64
/// origin. When a `.vpc` gives boxes, the camera is framed on them first
/// (the flags over the default view) and only the files it reaches are
/// opened. Streamed files draw the nodes that camera (else the flags' view
/// of every layer) selects, all of them under one `--point-budget`.
pub fn load_layers(
    (file, more): (&Path, &[PathBuf]),
    view: &ViewArgs,
    flags: &CameraArgs,
    mode: RenderMode,
) -> Result<OpenedLayers> {
    let paths: Vec<PathBuf> = std::iter::once(file.to_path_buf()).chain(more.iter().cloned()).collect();
    let files = layers::layer_files(&paths)?;
    let framed = match layers::bounds_scene(&files) {
        Some(bounds) => Some((view.camera(flags, &bounds)?, bounds.frame_placement())),
        None => None,
    };
    let aspect = view.size.0 as f32 / view.size.1 as f32;
    let reached: Vec<&LayerFile> = files
        .iter()
        .filter(|f| match (&framed, f.bounds) {
            (Some((camera, placement)), Some(b)) => layers::reaches(camera, aspect, *placement, b),
            _ => true,
        })
        .collect();
    if reached.is_empty() {
        bail!("{}: none of its {} files lies in the view", file.display(), files.len());
    }
    log::info!("opening {} of the layers' {} files (those the view reaches)", reached.len(), files.len());
    let (streamed, whole): (Vec<&Path>, Vec<&Path>) =
        reached.iter().map(|f| f.path.as_path()).partition(|p| is_streamed(p));
    let mut crs = SharedCrs::default();
    let whole = match whole.is_empty() {
        true => Scene::default(),
        false => {
            let options = LoadOptions { progress: true, ..Default::default() };
            let (scene, warnings) = layers::open_layers_sharing(&whole, &options, &mut crs)?;
            warnings.iter().for_each(|w| log::warn!("{w}"));
            scene
        }
    };
    // With some files left out, the boxes' view that chose them.
    let framed = framed.filter(|_| reached.len() < files.len());
    if streamed.is_empty() {
        let camera = framed.map(|(camera, from)| layers::camera_in_frame(&camera, from, whole.frame_placement()));
        return Ok(OpenedLayers { scene: whole, camera, by_nodes: false });
    }
    let load = LoadOptions { progress: true, ..Default::default() };
    let budget = (view.stream_budget()?, load);
    let layered = LayeredStreams::open(&streamed, view.stream.options(true), budget, &mut crs)?;
    streamed_layers(whole, layered, (view, flags, mode), framed)
}

/// `whole` and the nodes of `streams` that the camera selects under one
/// budget: the boxes' camera (`framed`, in the frame it was placed in),
/// else the flags' view of the layers (the streams' points the filters
/// keep, as [`super::stream_args::framing_scene`] frames one file).
fn streamed_layers(
    whole: Scene,
    mut layered: LayeredStreams,
    (view, flags, mode): (&ViewArgs, &CameraArgs, RenderMode),
    framed: Option<(Camera, (glam::DVec3, f64))>,
) -> Result<OpenedLayers> {
    let mut framing = whole.clone();
    for layer in &mut layered.layers {
        let scene = super::stream_args::framing_scene(&mut layer.stream, &view.scene);
        framing.objects.extend(scene.objects);
    }
    let (camera, from) = match framed {
        Some(framed) => framed,
        None => (view.camera(flags, &framing)?, framing.frame_placement()),
    };
    let choosing = Choosing::of(&view.base_settings(&framing, mode)?);
    let in_streams = layers::camera_in_frame(&camera, from, (layered.origin(), 1.0));
    let (streamed, drawn) = layered.scene(&in_streams, view.size, choosing)?;
    let mut scene = whole;
    scene.objects.extend(streamed.coloured_by_default().objects);
    if scene.objects.is_empty() {
        bail!("{}: no point of the layers is in view", shown_first(&layered));
    }
    let files = layered.layers.len();
    match budget_points(layered.budget) {
        Some(limit) if drawn > limit => log::warn!(
            "{drawn} points of {files} streamed files drawn, over the one budget of {limit}: every file's root in view is drawn whatever it holds (a larger --point-budget refines them)"
        ),
        Some(limit) => log::info!("{drawn} points of {files} streamed files drawn under one budget of {limit} points"),
        None => log::info!("{drawn} points of {files} streamed files drawn (every point)"),
    }
    let camera = layers::camera_in_frame(&camera, from, scene.frame_placement());
    Ok(OpenedLayers { scene, camera: Some(camera), by_nodes: true })
}

fn shown_first(layered: &LayeredStreams) -> String {
    layered.layers.first().map(|l| l.stream.name().to_string()).unwrap_or_default()
}

/// The points `budget` allows (`None`: every point).
fn budget_points(budget: pointblend::copc::StreamBudget) -> Option<usize> {
    use pointblend::copc::StreamBudget;
    match budget {
        StreamBudget::Default => Some(pointblend::copc::budget::DEFAULT_BUDGET),
        StreamBudget::Points(n) => Some(n),
        StreamBudget::All => None,
    }
}

/// Several files as one virtual point cloud, for the commands that open
/// one path (`view A B`, `bench --together`): a `.vpc` listing them (absolute
/// paths; URLs as they are), named after them, in a temporary folder that
/// lives as long as this value.
pub struct LayersFile {
    _folder: tempfile::TempDir,
    pub path: PathBuf,
}

/// [`LayersFile`] of `files` (at least two).
pub fn layers_file(files: &[PathBuf]) -> Result<LayersFile> {
    let hrefs = files
        .iter()
        .map(|file| pointblend::scene::vpc::href(file).with_context(|| format!("{}: cannot open", file.display())))
        .collect::<Result<Vec<_>>>()?;
    let first = files[0].file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let first = first.trim_end_matches(".copc");
    let folder = tempfile::Builder::new().prefix("pointblend-layers-").tempdir()?;
    let path = folder.path().join(format!("{first}+{}.vpc", files.len() - 1));
    pointblend::scene::vpc::write(&hrefs, &path)?;
    Ok(LayersFile { _folder: folder, path })
}
