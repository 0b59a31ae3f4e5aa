//! Options and helpers shared by several subcommands.

use std::path::Path;

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use pointblend::cloud::{self, LoadOptions, LoadReport, PointCloud};
use pointblend::grouping::GroupingSpec;
use pointblend::render::{Quality, RenderMode, RenderSettings};
use pointblend::view::{Camera, UpAxis};

/// Loads a cloud with progress bars and logs its warnings.
pub fn load(path: &Path) -> Result<(PointCloud, LoadReport)> {
    let options = LoadOptions { progress: true, ..Default::default() };
    let (cloud, report) = cloud::load_with(path, &options)?;
    for warning in &report.warnings {
        log::warn!("{}: {warning}", path.display());
    }
    Ok((cloud, report))
}

/// `WxH`, e.g. `512x512`.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(|| format!("'{text}' is not WxH, e.g. 512x512"))?;
    let w: u32 = w.trim().parse().map_err(|_| format!("'{w}' is not a width"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("'{h}' is not a height"))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("{w}x{h}: each side must be 1..=16384"));
    }
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

/// Camera and render options.
#[derive(clap::Args, Debug, Clone)]
pub struct ViewArgs {
    /// Rendering mode.
    #[arg(long, default_value = "two-pass")]
    pub mode: RenderMode,
    /// Quality level: Gaussian-filtered blending, or unfiltered nearest splat.
    #[arg(long, value_enum, default_value = "filtered")]
    pub quality: QualityArg,
    /// Image size.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Degrees around the up axis (default: front, or the scanner's side for a single-view scan).
    #[arg(long, allow_negative_numbers = true)]
    pub azimuth: Option<f32>,
    /// Degrees above the horizon.
    #[arg(long, allow_negative_numbers = true)]
    pub elevation: Option<f32>,
    /// Distance from the model's centre (default: the bounding sphere fills the view).
    #[arg(long)]
    pub distance: Option<f32>,
    /// Vertical field of view in degrees.
    #[arg(long)]
    pub fov: Option<f32>,
    /// Axis that points up: x, -x, y, -y, z or -z (default y; -y for single-view scans).
    #[arg(long, allow_hyphen_values = true)]
    pub up: Option<UpAxis>,
    /// ε of the visibility pass, in multiples of the mean splat radius.
    #[arg(long, default_value_t = 1.0)]
    pub epsilon: f32,
    /// Keep back-facing splats.
    #[arg(long)]
    pub no_cull: bool,
    /// Grouping for the deferred mode: mgc-cC, wgc-kK or hash-kK.
    #[arg(long, default_value = "mgc-c0.4")]
    pub group: GroupingSpec,
    /// Voronoi rasterisation in the deferred mode (Eq. 14).
    #[arg(long)]
    pub voronoi: bool,
    /// No lighting: show the blended colours (no normal targets are used).
    #[arg(long)]
    pub unlit: bool,
}

impl ViewArgs {
    pub fn settings(&self) -> Result<RenderSettings> {
        if !(self.epsilon.is_finite() && self.epsilon >= 0.0) {
            bail!("--epsilon must be a finite number >= 0, not {}", self.epsilon);
        }
        Ok(RenderSettings {
            mode: self.mode,
            quality: self.quality.quality(),
            epsilon_scale: self.epsilon,
            backface_culling: !self.no_cull,
            voronoi: self.voronoi,
            lighting: !self.unlit,
            ..Default::default()
        })
    }

    pub fn camera(&self, cloud: &PointCloud) -> Result<Camera> {
        let aspect = self.size.0 as f32 / self.size.1 as f32;
        let mut camera = Camera::default_for(cloud, aspect);
        if let Some(up) = self.up {
            if up != camera.up {
                let dir = camera.direction();
                camera.up = up;
                camera.look_from_direction(dir);
            }
        }
        if let Some(fov) = self.fov {
            if !(fov > 0.5 && fov < 170.0) {
                bail!("--fov must be between 0.5 and 170 degrees, not {fov}");
            }
            camera.fov_y_deg = fov;
        }
        if let Some(a) = self.azimuth {
            camera.azimuth_deg = a;
        }
        if let Some(e) = self.elevation {
            camera.elevation_deg = e.clamp(-90.0, 90.0);
        }
        camera.distance = camera.fit_distance(&cloud.positions, aspect);
        if let Some(d) = self.distance {
            if !(d.is_finite() && d > 0.0) {
                bail!("--distance must be a positive number, not {d}");
            }
            camera.distance = d;
        }
        Ok(camera)
    }
}

/// Writes `image` as PNG to `path` through a temporary file and a rename.
pub fn write_png_atomically(image: &image::RgbaImage, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    }
    pointblend::output::save_png(image, path).with_context(|| format!("{}: cannot write the PNG", path.display()))
}
