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
