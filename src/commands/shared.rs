//! Options and helpers shared by several subcommands.

use std::path::Path;

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use pointblend::cloud::{self, LoadOptions, LoadReport, PointCloud};
use pointblend::frame::{Camera, Parameter, UpAxis};
use pointblend::grouping::GroupingSpec;
use pointblend::output::ImageFormat;
use pointblend::render::{Quality, RenderMode, RenderSettings};
use pointblend::scene::Scene;

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

/// `R,G,B`, each 0..255.
pub fn parse_rgb(text: &str) -> Result<[u8; 3], String> {
    let values: Vec<&str> = text.split(',').map(str::trim).collect();
    match values[..] {
        [r, g, b] => {
            let c = |v: &str| v.parse::<u8>().map_err(|_| format!("'{v}' is not a value in 0..255"));
            Ok([c(r)?, c(g)?, c(b)?])
        }
        _ => Err(format!("'{text}' is not R,G,B (three values in 0..255)")),
    }
}

/// `A` in 0..1.
pub fn parse_opacity(text: &str) -> Result<f32, String> {
    text.parse::<f32>()
        .ok()
        .filter(|a| (0.0..=1.0).contains(a))
        .ok_or_else(|| format!("'{text}' is not an opacity in 0..1"))
}

/// `WxH`, e.g. `512x512`.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(|| format!("'{text}' is not WxH, e.g. 512x512"))?;
    let w: u32 = w.trim().parse().map_err(|_| format!("'{w}' is not a width"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("'{h}' is not a height"))?;
    pointblend::frame::settings::check_image_size(w, h)?;
    Ok((w, h))
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum QualityArg {
    Filtered,
    Unfiltered,
}

impl QualityArg {
    pub fn quality(self) -> Quality {
        match self {
            QualityArg::Filtered => Quality::Filtered,
            QualityArg::Unfiltered => Quality::Unfiltered,
        }
    }
}

/// `--mode`: one of the registry's names, listed with their descriptions in `--help`.
fn mode_parser() -> impl clap::builder::TypedValueParser<Value = RenderMode> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    let values = RenderMode::ALL.map(|m| PossibleValue::new(m.name()).help(m.description()));
    PossibleValuesParser::new(values).try_map(|name| name.parse::<RenderMode>())
}

/// Camera and render options.
#[derive(clap::Args, Debug, Clone)]
pub struct ViewArgs {
    /// Rendering mode [default: two-pass].
    #[arg(long, default_value_t = RenderMode::DEFAULT, value_parser = mode_parser())]
    pub mode: RenderMode,
    /// Quality level of two-pass: Gaussian-filtered blending, or unfiltered nearest splat [default: filtered].
    #[arg(long, value_enum)]
    pub quality: Option<QualityArg>,
    /// Image size.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Degrees around the up axis (default: front, or the scanner's side for a single-view scan).
    #[arg(long, allow_negative_numbers = true)]
    pub azimuth: Option<f32>,
    /// Degrees above the horizon, -90..90.
    #[arg(long, allow_negative_numbers = true)]
    pub elevation: Option<f32>,
    /// Distance from the model's centre (default: the bounding sphere fills the view).
    #[arg(long, allow_negative_numbers = true)]
    pub distance: Option<f32>,
    /// Vertical field of view in degrees, 0.5..170 [default: 35].
    #[arg(long, allow_negative_numbers = true)]
    pub fov: Option<f32>,
    /// Axis that points up: x, -x, y, -y, z or -z (default y; -y for single-view scans).
    #[arg(long, allow_hyphen_values = true)]
    pub up: Option<UpAxis>,
    /// ε of the depth test that decides which splats blend, in multiples of the mean splat radius (> 0).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub epsilon: f32,
    /// Eq. 10's low-precision depth step of deferred, alg1 and alg2, in multiples of ε (> 0) [default: 1.25].
    #[arg(long, allow_negative_numbers = true)]
    pub depth_step: Option<f32>,
    /// Keep back-facing splats.
    #[arg(long)]
    pub no_cull: bool,
    /// Grouping of the deferred mode: mgc-cC, wgc-kK, hash-kK or hash-kK-kept [default: mgc-c0.4].
    #[arg(long)]
    pub group: Option<GroupingSpec>,
    /// Turn off Voronoi rasterisation (Eq. 14) in the deferred mode's group images.
    #[arg(long)]
    pub no_voronoi: bool,
    /// No lighting: show the blended colours (no normal targets are used).
    #[arg(long)]
    pub unlit: bool,
    /// Back-to-front order of alg1, alg2 and alpha-blend: bucket (Gunjee's bucket sort), bsp (Zhang & Pajarola's BSP traversal) or sort (exact comparison sort) [default: bucket].
    #[arg(long)]
    pub order: Option<pointblend::spatial::order::OrderKind>,
    /// Transparent layers k of depth-peel (default 8) and approx-peel (default 3), 2..=64.
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=pointblend::frame::settings::MAX_PEEL_LAYERS as i64))]
    pub layers: Option<u32>,
    /// Opacity of every object, 0..1 (transparent objects are drawn two-sided;
    /// only transparent modes and the reference show it).
    #[arg(long, value_parser = parse_opacity)]
    pub opacity: Option<f32>,
    /// Colour R,G,B (0..255) that replaces every object's own.
    #[arg(long = "color", value_parser = parse_rgb)]
    pub colour: Option<[u8; 3]>,
    /// Background colour R,G,B (0..255) [default: the scene's, else 28,31,36].
    #[arg(long, value_parser = parse_rgb)]
    pub background: Option<[u8; 3]>,
    /// A white point light at X,Y,Z in the model's file coordinates (repeatable, at most 8 with the scene's);
    /// any light replaces the headlight, and casts translucent shadows.
    #[arg(long = "light", value_parser = parse_light, allow_hyphen_values = true)]
    pub lights: Vec<pointblend::frame::Light>,
    /// How lit splats find their light: tsm (Gunjee's translucent shadow map), exact (a shadow ray per splat) or off [default: tsm].
    #[arg(long, value_parser = parse_shadow_method)]
    pub shadows: Option<pointblend::frame::ShadowMethod>,
    /// Screen-space low-pass filter of the splat passes: ewa (Guennebaud's EWA approximation: splats
    /// smaller than a pixel are stretched to the filter's size, so far models do not alias) or none.
    #[arg(long, value_parser = parse_prefilter)]
    pub prefilter: Option<pointblend::frame::Prefilter>,
    /// Rays per pixel side of the reference, 1..=16: N×N rays per pixel, box-filtered (the exact
    /// answer to aliasing; in bench and --diff, the ruler) [default: 1].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=pointblend::frame::settings::MAX_SUPERSAMPLE as i64))]
    pub supersample: Option<u32>,
    /// Most splats a GPU frame draws (≥ 1; the octree's root, up to 1,728 splats, is always drawn): nodes of
    /// a multi-resolution octree (built once per model and cached) chosen by screen-space error; the
    /// reference always draws every splat [default: all].
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(1..))]
    pub point_budget: Option<u32>,
    /// Hybrid objects (`hybrid = "x.ply"` in a scene file): a leaf of the mesh is drawn as triangles
    /// where its largest splat would be wider than this radius in pixels, as splats elsewhere; 0 draws
    /// every leaf as triangles, inf none [default: 3].
    #[arg(long = "hybrid-px", value_name = "PX", value_parser = parse_hybrid_pixels)]
    pub hybrid_pixels: Option<f32>,
    /// TSM table size per light, POLxAZ cells (or N for NxN) [default: 512x512].
    #[arg(long, value_parser = pointblend::frame::lights::parse_cells)]
    pub shadow_cells: Option<[u32; 2]>,
}

/// `--hybrid-px PX`: 0 or more, or inf.
fn parse_hybrid_pixels(text: &str) -> Result<f32, String> {
    let mut settings = RenderSettings::default();
    Parameter::HybridPixels.apply(&mut settings, text).map(|()| settings.hybrid_pixels)
}

/// `--light X,Y,Z`.
pub fn parse_light(text: &str) -> Result<pointblend::frame::Light, String> {
    pointblend::frame::Light::parse_point(text).map_err(|e| e.to_string())
}

/// `--prefilter ewa|none`.
fn parse_prefilter(text: &str) -> Result<pointblend::frame::Prefilter, String> {
    text.parse()
}

/// `--shadows tsm|exact|off`.
fn parse_shadow_method(text: &str) -> Result<pointblend::frame::ShadowMethod, String> {
    text.parse()
}

impl ViewArgs {
    /// The settings of `--mode` for `scene`, saying which given options it does not read.
    pub fn settings(&self, scene: &Scene) -> Result<RenderSettings> {
        let settings = self.base_settings(scene)?;
        self.warn_ignored();
        Ok(settings)
    }

    /// Applies `--opacity` and `--color` to the scene's objects.
    pub fn apply_materials(&self, scene: &mut Scene) {
        if let Some(opacity) = self.opacity {
            scene.set_opacity(opacity);
        }
        if let Some(colour) = self.colour {
            scene.set_colour(colour);
        }
    }

    /// The settings, without checking them against `--mode` (bench's base for every variant).
    pub fn base_settings(&self, scene: &Scene) -> Result<RenderSettings> {
        let mut settings = RenderSettings {
            mode: self.mode,
            depth_step: self.depth_step.unwrap_or(pointblend::frame::settings::DEFAULT_DEPTH_STEP),
            quality: self.quality.map_or(Quality::Filtered, QualityArg::quality),
            epsilon_scale: self.epsilon,
            backface_culling: !self.no_cull,
            grouping: self.group.unwrap_or_default(),
            voronoi: !self.no_voronoi,
            lighting: !self.unlit,
            peel_layers: self.layers.unwrap_or(0),
            order: self.order.unwrap_or(pointblend::spatial::order::OrderKind::Bucket),
            prefilter: self.prefilter.unwrap_or_default(),
            supersample: self.supersample.unwrap_or(1),
            point_budget: self.point_budget,
            hybrid_pixels: self.hybrid_pixels.unwrap_or(pointblend::frame::settings::DEFAULT_HYBRID_PIXELS),
            ..Default::default()
        };
        if let Some(bg) = self.background.map(|c| glam::Vec3::from_array(c.map(f32::from)) / 255.0).or(scene.background)
        {
            settings.shading.background = bg;
        }
        // Lights are given in file coordinates, like the objects.
        let lights: Vec<_> = scene.lights.iter().chain(&self.lights).map(|l| scene.light_in_frame(l)).collect();
        settings.lights = pointblend::frame::Lights::new(&lights).map_err(|e| anyhow::anyhow!("lights: {e}"))?;
        settings.shadows.method = self.shadows.unwrap_or_default();
        if let Some(cells) = self.shadow_cells {
            settings.shadows.cells = cells;
        }
        // The checks a sidecar's settings get too.
        settings.check().map_err(anyhow::Error::msg)?;
        Ok(settings)
    }

    /// Says which given options the chosen mode does not read.
    fn warn_ignored(&self) {
        let reads = self.mode.parameters();
        let given = [
            ("--quality", self.quality.is_some(), Parameter::Quality),
            ("--group", self.group.is_some(), Parameter::Grouping),
            ("--no-voronoi", self.no_voronoi, Parameter::Voronoi),
            ("--layers", self.layers.is_some(), Parameter::PeelLayers),
            ("--order", self.order.is_some(), Parameter::Order),
            ("--depth-step", self.depth_step.is_some(), Parameter::DepthStep),
            ("--prefilter", self.prefilter.is_some(), Parameter::Prefilter),
            ("--point-budget", self.point_budget.is_some(), Parameter::PointBudget),
            ("--hybrid-px", self.hybrid_pixels.is_some(), Parameter::HybridPixels),
        ];
        for (option, is_given, parameter) in given {
            if is_given && !reads.contains(&parameter) {
                log::warn!("{option} is ignored: mode {} does not use it", self.mode);
            }
        }
    }

    /// The camera: the options given, else the scene file's, else framing every object.
    pub fn camera(&self, scene: &Scene) -> Result<Camera> {
        let flat = scene.flatten();
        let cloud = flat.cloud.as_ref();
        let aspect = self.size.0 as f32 / self.size.1 as f32;
        let mut camera = Camera::default_for(cloud, aspect);
        let asked = scene.camera.unwrap_or_default();
        let given = ViewArgs {
            up: self.up.or(asked.up),
            fov: self.fov.or(asked.fov),
            azimuth: self.azimuth.or(asked.azimuth),
            elevation: self.elevation.or(asked.elevation),
            distance: self.distance.or(asked.distance),
            ..self.clone()
        };
        let this = &given;
        if let Some(up) = this.up {
            if up != camera.up {
                let dir = camera.direction();
                camera.up = up;
                camera.look_from_direction(dir);
            }
        }
        if let Some(fov) = this.fov {
            if !(0.5..=170.0).contains(&fov) {
                bail!("--fov must be between 0.5 and 170 degrees, not {fov}");
            }
            camera.fov_y_deg = fov;
        }
        if let Some(a) = this.azimuth {
            if !a.is_finite() {
                bail!("--azimuth must be a finite number of degrees, not {a}");
            }
            camera.azimuth_deg = a;
        }
        if let Some(e) = this.elevation {
            if !e.is_finite() {
                bail!("--elevation must be a finite number of degrees, not {e}");
            }
            camera.elevation_deg = e.clamp(-90.0, 90.0);
        }
        camera.distance = camera.fit_distance(&cloud.positions, aspect);
        if let Some(d) = this.distance {
            if !(d.is_finite() && d > 0.0) {
                bail!("--distance must be a positive number, not {d}");
            }
            camera.distance = d;
        }
        Ok(camera)
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
