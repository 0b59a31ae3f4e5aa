//! Options and helpers shared by several subcommands.

use std::path::Path;

use anyhow::{Context, Result, bail};
use pointblend::cloud::{self, LoadOptions, LoadReport, PointCloud};
use pointblend::frame::{Camera, CameraRequest, NamedView, Projection, UpAxis};
use pointblend::output::ImageFormat;
use pointblend::render::{RenderMode, RenderSettings};
use pointblend::scene::Scene;

use super::parameter_flags::ParameterFlags;
use super::scene_args::SceneArgs;

/// The input as messages show it: a URL's user, password and query values masked.
pub fn shown_path(path: &Path) -> String {
    pointblend::copc::shown(&path.to_string_lossy())
}

/// Loads a cloud with progress bars and logs its warnings.
pub fn load(path: &Path) -> Result<(PointCloud, LoadReport)> {
    let options = LoadOptions { progress: true, ..Default::default() };
    let (cloud, report) = cloud::load_with(path, &options)?;
    for warning in &report.warnings {
        log::warn!("{}: {warning}", path.display());
    }
    Ok((cloud, report))
}

/// Opens a PLY file (a scene of one object) or a scene file, with progress
/// bars, and logs the objects' load warnings.
pub fn load_scene(path: &Path) -> Result<Scene> {
    let options = LoadOptions { progress: true, ..Default::default() };
    let (scene, warnings) = pointblend::scene::open(path, &options)?;
    for warning in &warnings {
        log::warn!("{warning}");
    }
    Ok(scene)
}

/// Whether `file` and `more` open as layers: several files, or a `.vpc`.
pub fn is_layered(file: &Path, more: &[std::path::PathBuf]) -> bool {
    !more.is_empty() || pointblend::scene::vpc::is_vpc(file)
}

/// Opens `file` and `more` as layers, each file an object with its own f64
/// origin. When a `.vpc` gives boxes, the camera is framed on them first
/// (the flags over the default view) and only the files it reaches are
/// opened; when that leaves some out, that camera, in the opened scene's
/// frame, comes back too.
pub fn load_layers(
    file: &Path,
    more: &[std::path::PathBuf],
    view: &ViewArgs,
    flags: &CameraArgs,
) -> Result<(Scene, Option<Camera>)> {
    use pointblend::scene::layers;
    let paths: Vec<std::path::PathBuf> = std::iter::once(file.to_path_buf()).chain(more.iter().cloned()).collect();
    let files = layers::layer_files(&paths)?;
    let framed = match layers::bounds_scene(&files) {
        Some(bounds) => {
            let camera = view.camera(flags, &bounds)?;
            let aspect = view.size.0 as f32 / view.size.1 as f32;
            let placement = bounds.frame_placement();
            Some((camera, placement, aspect))
        }
        None => None,
    };
    let reached: Vec<&Path> = files
        .iter()
        .filter(|f| match (&framed, f.bounds) {
            (Some((camera, placement, aspect)), Some(b)) => layers::reaches(camera, *aspect, *placement, b),
            _ => true,
        })
        .map(|f| f.path.as_path())
        .collect();
    if reached.is_empty() {
        bail!("{}: none of its {} files lies in the view", file.display(), files.len());
    }
    log::info!("opening {} of the layers' {} files (those the view reaches)", reached.len(), files.len());
    let options = LoadOptions { progress: true, ..Default::default() };
    let (scene, warnings) = layers::open_layers(&reached, &options)?;
    for warning in &warnings {
        log::warn!("{warning}");
    }
    // With every file open the view is the layers' own (framed on their points, as `A B C`
    // frames them); with some left out, the boxes' view that chose them.
    let camera = framed
        .filter(|_| reached.len() < files.len())
        .map(|(camera, from, _)| layers::camera_in_frame(&camera, from, scene.frame_placement()));
    Ok((scene, camera))
}

/// Several files as one virtual point cloud, for the commands that open
/// one path (`view A B`, `bench --together`): a `.vpc` listing them (absolute
/// paths; URLs as they are), named after them, in a temporary folder that
/// lives as long as this value.
pub struct LayersFile {
    _folder: tempfile::TempDir,
    pub path: std::path::PathBuf,
}

/// [`LayersFile`] of `files` (at least two).
pub fn layers_file(files: &[std::path::PathBuf]) -> Result<LayersFile> {
    let features = files
        .iter()
        .map(|file| {
            let href = if pointblend::copc::is_url(&file.to_string_lossy()) {
                file.to_string_lossy().into_owned()
            } else {
                let absolute = std::fs::canonicalize(file).with_context(|| format!("{}: cannot open", file.display()))?;
                absolute.to_string_lossy().into_owned()
            };
            Ok(serde_json::json!({"type": "Feature", "geometry": null, "properties": {}, "assets": {"data": {"href": href}}}))
        })
        .collect::<Result<Vec<_>>>()?;
    let first = files[0].file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let first = first.trim_end_matches(".copc");
    let folder = tempfile::Builder::new().prefix("pointblend-layers-").tempdir()?;
    let path = folder.path().join(format!("{first}+{}.vpc", files.len() - 1));
    let collection = serde_json::json!({"type": "FeatureCollection", "features": features});
    std::fs::write(&path, serde_json::to_string_pretty(&collection)?)?;
    Ok(LayersFile { _folder: folder, path })
}

/// `WxH`, e.g. `512x512`.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(|| format!("'{text}' is not WxH, e.g. 512x512"))?;
    let w: u32 = w.trim().parse().map_err(|_| format!("'{w}' is not a width"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("'{h}' is not a height"))?;
    pointblend::frame::settings::check_image_size(w, h)?;
    Ok((w, h))
}

/// `--mode`: one of the registry's names, listed with their descriptions in `--help`.
pub fn mode_parser() -> impl clap::builder::TypedValueParser<Value = RenderMode> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    let values = RenderMode::ALL.map(|m| PossibleValue::new(m.name()).help(m.description()));
    PossibleValuesParser::new(values).try_map(|name| name.parse::<RenderMode>())
}

/// The camera flags of the commands that draw one view (`render`, `view`,
/// `pick`, `measure`): what they leave out, a scene file's `[camera]` and
/// then the model's default view fill.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct CameraArgs {
    /// Degrees around the up axis (default: front, or the scanner's side for a single-view scan).
    #[arg(long, allow_negative_numbers = true)]
    pub azimuth: Option<f32>,
    /// Degrees above the horizon, -90..90 (default 0; 40 for z-up lidar and E57 data).
    #[arg(long, allow_negative_numbers = true)]
    pub elevation: Option<f32>,
    /// Distance from the model's centre (default: every point fits the view).
    #[arg(long, allow_negative_numbers = true)]
    pub distance: Option<f32>,
    /// Vertical field of view in degrees, 0.5..170 [default: 35].
    #[arg(long, allow_negative_numbers = true)]
    pub fov: Option<f32>,
    /// Axis that points up: x, -x, y, -y, z or -z (default: y; z for LAS, LAZ,
    /// COPC and E57 files; -y for single-view scans, seen from their scanner).
    #[arg(long, allow_hyphen_values = true)]
    pub up: Option<UpAxis>,
    /// perspective or ortho (parallel rays: plan and elevation views; the
    /// window is as high as the field of view is at the distance) [default: perspective].
    #[arg(long)]
    pub projection: Option<Projection>,
    /// A named view about the up axis: top, bottom, front, back, left, right
    /// or iso (for z-up data front looks north, right looks west); --azimuth
    /// and --elevation given too win.
    #[arg(long)]
    pub view: Option<NamedView>,
}

impl CameraArgs {
    /// The camera these flags ask for.
    pub fn request(&self) -> CameraRequest {
        CameraRequest {
            azimuth: self.azimuth,
            elevation: self.elevation,
            distance: self.distance,
            fov: self.fov,
            up: self.up,
            projection: self.projection,
            view: self.view,
        }
    }
}

/// What every command that renders reads: the image size, the rendering
/// parameters, the scene flags (materials, styling, lights, clipping) and
/// the streaming flags.
#[derive(clap::Args, Debug, Clone)]
pub struct ViewArgs {
    /// Image size.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: (u32, u32),
    #[command(flatten)]
    pub parameters: ParameterFlags,
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub stream: super::stream_args::StreamArgs,
}

impl ViewArgs {
    /// The settings of `mode` for `scene`, saying which given options it does not read.
    pub fn settings(&self, scene: &Scene, mode: RenderMode) -> Result<RenderSettings> {
        let settings = self.base_settings(scene, mode)?;
        self.parameters.warn_ignored(mode);
        Ok(settings)
    }

    /// The settings, without checking them against `mode` (bench's base
    /// for every variant): the defaults, then the scene's background and
    /// lights, then the parameters given.
    pub fn base_settings(&self, scene: &Scene, mode: RenderMode) -> Result<RenderSettings> {
        let mut settings = RenderSettings { mode, ..Default::default() };
        if let Some(bg) = scene.background {
            settings.shading.background = bg;
        }
        // Lights are given in file coordinates, like the objects.
        let lights: Vec<_> = scene.lights.iter().chain(&self.scene.lights).map(|l| scene.light_in_frame(l)).collect();
        settings.lights = pointblend::frame::Lights::new(&lights).map_err(|e| anyhow::anyhow!("lights: {e}"))?;
        // The clip region too.
        settings.clip = scene.clip_in_frame(&self.scene.clip_region(scene).map_err(anyhow::Error::msg)?);
        // After the lights, so that `--lighting headlight` sets the scene's aside.
        self.parameters.apply(&mut settings).map_err(anyhow::Error::msg)?;
        // The checks a sidecar's settings get too.
        settings.check().map_err(anyhow::Error::msg)?;
        Ok(settings)
    }

    /// The points a streamed file draws: `--point-budget` as given (all, a
    /// number, or the streamed default when not given).
    pub fn stream_budget(&self) -> Result<pointblend::copc::StreamBudget> {
        let given = self.parameters.given(pointblend::frame::Parameter::PointBudget);
        pointblend::copc::StreamBudget::given(given).map_err(anyhow::Error::msg)
    }

    /// The camera: the flags' values, else the scene file's, else the default view framing every object.
    pub fn camera(&self, flags: &CameraArgs, scene: &Scene) -> Result<Camera> {
        let flat = scene.flatten();
        let aspect = self.size.0 as f32 / self.size.1 as f32;
        let request = flags.request().over(scene.camera.unwrap_or_default());
        request.camera(flat.cloud.as_ref(), aspect).map_err(|e| anyhow::anyhow!("--{e}"))
    }
}

/// `--env`'s help: the map's formats, and the modes that draw it (from the mode registry).
pub fn environment_help() -> String {
    let modes: Vec<&str> = RenderMode::ALL.iter().filter(|m| m.info().environment).map(|m| m.name()).collect();
    format!(
        "Environment map that transparent surfaces reflect and refract: an equirectangular OpenEXR, Radiance HDR, \
         PNG or JPEG (assets/venice.exr is bundled); drawn by {}",
        modes.join(", ")
    )
}

/// A time to draw a moving scene at: a number of seconds ≥ 0.
pub fn check_time(time: Option<f64>) -> Result<()> {
    match time {
        Some(t) if !(t.is_finite() && t >= 0.0) => bail!("--time must be a number of seconds ≥ 0, not {t}"),
        _ => Ok(()),
    }
}

/// Checks, before any work, that `path` can be written as an output file
/// (see [`pointblend::output::prepare`]); creates its folder.
pub fn prepare_output(path: &Path) -> Result<()> {
    pointblend::output::prepare(path).with_context(|| format!("{}: cannot write the output here", path.display()))?;
    Ok(())
}

/// Refuses an output `path` that names the file `other` (an input, or another
/// output), however the two are spelt: `..`, absolute or relative, links.
pub fn refuse_same_file(path: &Path, what: &str, other: &Path) -> Result<()> {
    if pointblend::output::same_file(path, other) {
        bail!("{}: this is {what} ({}); refusing to write over it", path.display(), other.display());
    }
    Ok(())
}

/// [`prepare_output`] for an image, whose extension must be one we encode.
pub fn prepare_image_output(path: &Path) -> Result<()> {
    prepare_output(path)?;
    ImageFormat::of(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(())
}

/// Writes `image` to `path` (PNG or JPEG by extension) through a temporary file and a rename.
pub fn write_image(image: &image::RgbaImage, path: &Path) -> Result<()> {
    pointblend::output::save_image(image, path).with_context(|| format!("{}: cannot write the image", path.display()))
}

/// One line per attribute: its range, its distinct values (classes by name), and its bytes per point.
/// `info`'s units line: the CRS's horizontal and vertical units and its
/// EPSG code, or that positions are in the units of the file.
pub fn print_units(units: &pointblend::cloud::crs_units::CrsUnits, declared: bool) {
    let Some(horizontal) = &units.horizontal else {
        let why = if declared { "the CRS names no unit known here" } else { "no CRS declared" };
        println!("units:       {} ({why})", pointblend::cloud::crs_units::UNITS_OF_THE_FILE);
        return;
    };
    let vertical = match &units.vertical {
        Some(v) => v.to_string(),
        None => units.vertical_name().to_string(),
    };
    let code = units.epsg.map(|c| format!(", EPSG:{c}")).unwrap_or_default();
    println!("units:       horizontal {horizontal}, vertical {vertical}{code}");
}

pub fn print_attributes(attributes: &pointblend::cloud::Attributes) {
    use pointblend::cloud::attributes::{names, summary};
    for channel in &attributes.channels {
        let (lo, hi, distinct) = summary(&channel.values);
        let mut line = format!("attribute:   {} in [{lo}, {hi}]", channel.name);
        if let Some(d) = distinct {
            line.push_str(&format!(", {d} distinct"));
        }
        line.push_str(&format!(" ({} bytes per point)", channel.values.bytes_per_value()));
        println!("{line}");
        if channel.name == names::CLASSIFICATION {
            for (class, count) in pointblend::style::classes::counts(&channel.values) {
                println!("  class {class:>3}: {count} points, {}", pointblend::style::classes::name(class));
            }
        }
    }
    if !attributes.is_empty() {
        println!("attributes:  {} bytes per point in all", attributes.bytes_per_point());
    }
}
